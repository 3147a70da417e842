//! Regressions of the sixth adversarial run: bad input to the public API
//! gives a typed error naming what was given, never a panic, a silent
//! infinity, or a message about a value the user never typed.

use std::path::Path;

use tyreroad_film::*;

fn film() -> FilmResponse {
    let cal = Calibration::from_pairs(Response::Density, &[(0.1, 0.5e6), (0.5, 1e6), (1.0, 2e6)])
        .expect("a valid calibration");
    FilmResponse::new(cal, Scanner::default())
}

/// A 64 × 64 scan of 100 µm pixels: a disk of `ink` on a `bg` background.
fn disk(bg: f32, ink: f32) -> Vec<f32> {
    (0..64 * 64)
        .map(|k| {
            let (i, j) = ((k % 64) as f64 - 32.0, (k / 64) as f64 - 32.0);
            if i * i + j * j < 100.0 { ink } else { bg }
        })
        .collect()
}

fn message<T>(r: Result<T>) -> String {
    r.err().map(|e| e.to_string()).unwrap_or_default()
}

/// P6: a 2-value mask for a 4 × 4 image indexed out of bounds.
#[test]
fn a_mask_of_the_wrong_length_is_refused_not_a_panic() {
    assert!(matches!(
        connected_components(&[true, false], 4, 4, Connectivity::Eight),
        Err(FilmError::MaskSize {
            len: 2,
            width: 4,
            height: 4
        })
    ));
    // width × height overflowing usize is no match either.
    assert!(matches!(
        connected_components(&[true, true], usize::MAX, 2, Connectivity::Four),
        Err(FilmError::MaskSize { .. })
    ));
    let e = message(connected_components(&[true; 5], 2, 2, Connectivity::Four));
    assert!(e.contains("mask of 5 values for a 2 × 2 image"), "{e}");
    assert!(matches!(
        connected_components(&[true, false, false, true], 2, 2, Connectivity::Four),
        Ok((_, 2))
    ));
}

/// S15: a NaN grey read as a saturated print through the scanner, while a
/// NaN response reads below range.
#[test]
fn a_nan_grey_level_is_read_below_range_like_a_nan_response_not_as_saturated() {
    let film = film();
    assert_eq!(film.pressure_of_grey(f64::NAN), Calibrated::BelowRange);
    assert_eq!(
        film.pressure_of_grey(f64::NAN),
        film.calibration.pressure(f64::NAN)
    );
    assert!(film.density_of_grey(f64::NAN).is_nan());
    // The black end still saturates.
    assert_eq!(film.pressure_of_grey(0.0), Calibrated::Saturated);
    assert_eq!(film.density_of_grey(0.0), f64::INFINITY);
}

/// S15: a NaN scan found no print; a scan of greys 2 and −1 gave a
/// saturated 6.1 N print; bit depth 0 was taken.
#[test]
fn scans_with_nan_or_out_of_range_greys_or_no_bit_depth_are_refused() {
    let scan = |grey, bits| Scan::from_grey(64, 64, grey, Some(1e-4), bits);
    let e = message(scan(disk(0.95, f32::NAN), 8));
    assert!(
        e.contains("grey level NaN at pixel (col ") && e.contains("[0, 1]"),
        "{e}"
    );
    let e = message(scan(disk(2.0, -1.0), 8));
    assert!(e.contains("grey level 2 at pixel (col 0, row 0)"), "{e}");
    let e = message(scan(disk(0.95, -1.0), 8));
    assert!(e.contains("grey level -1 at pixel (col 28, row 23)"), "{e}");
    let e = message(scan(disk(0.95, 1.2), 8));
    assert!(e.contains("grey level 1.2 at"), "{e}");
    assert!(matches!(
        scan(disk(0.95, 0.3), 0),
        Err(FilmError::InvalidParameter {
            name: "bit depth",
            ..
        })
    ));
    assert!(scan(disk(1.0, 0.0), 8).is_ok() && scan(disk(0.95, 0.3), 32).is_ok());
}

/// The new range check on greys keeps decoded scans: white read as Luma
/// (weights summing to 1 in f32) is full scale, not above it.
#[test]
fn a_white_rgb_scan_read_as_luma_is_accepted() -> Result<()> {
    let img = image::RgbImage::from_pixel(5, 3, image::Rgb([255, 255, 255]));
    let mut bytes = Vec::new();
    img.write_to(
        &mut std::io::Cursor::new(&mut bytes),
        image::ImageFormat::Png,
    )
    .map_err(|e| FilmError::InvalidCalibration(e.to_string()))?;
    let scan = Scan::decode(&bytes, Channel::Luma, Path::new("white.png"))?;
    assert!(scan.grey().iter().all(|&g| g == 1.0));
    Ok(())
}

/// S16: a pixel of 1e300 m (or 1e-300 dpi) gave an infinite area and
/// force, Ok.
#[test]
fn pixel_sizes_and_dpi_of_no_finite_pixel_area_are_refused_by_name() -> Result<()> {
    let scan = Scan::from_grey(64, 64, disk(0.95, 0.3), None, 8)?;
    let e = message(scan.clone().with_pixel_size(1e300));
    assert!(
        e.contains("invalid pixel size: 1e300 (must be between") && e.contains("metres"),
        "{e}"
    );
    let e = message(scan.clone().with_pixel_size(1e-300));
    assert!(e.contains("pixel size: 1e-300 "), "{e}");
    // 25 µm given in µm.
    assert!(scan.clone().with_pixel_size(25.0).is_err());
    let e = message(scan.clone().with_dpi(1e-300));
    assert!(e.contains("invalid dpi: 1e-300 "), "{e}");
    assert!(message(scan.clone().with_dpi(1e300)).contains("invalid dpi: 1e300 "));
    assert!(Scan::from_grey(64, 64, disk(0.95, 0.3), Some(1e300), 8).is_err());
    let scan = scan.with_dpi(254.0)?;
    let det = analyse(&scan, &film(), &AnalysisOptions::default())?;
    let area = det.prints[0].area;
    assert!((area / (305.0 * 1e-8) - 1.0).abs() < 1e-9, "{area}");
    Ok(())
}

/// A file resolution of 1 pixel per metre (software writing "unknown")
/// reads as no resolution, so the user can give one, not as a refusal.
#[test]
fn an_absurd_file_resolution_reads_as_unknown() -> Result<()> {
    let mut buf = Vec::new();
    let mut enc = png::Encoder::new(&mut buf, 4, 3);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_pixel_dims(Some(png::PixelDimensions {
        xppu: 1,
        yppu: 1,
        unit: png::Unit::Meter,
    }));
    let mut w = enc
        .write_header()
        .map_err(|e| FilmError::InvalidCalibration(e.to_string()))?;
    w.write_image_data(&[200u8; 12])
        .map_err(|e| FilmError::InvalidCalibration(e.to_string()))?;
    drop(w);
    let scan = Scan::decode(&buf, Channel::Auto, Path::new("one-ppm.png"))?;
    assert_eq!(scan.pixel_size(), None);
    assert!(scan.with_dpi(600.0)?.pixel_size().is_some());
    Ok(())
}

/// S17: pressures in MPa typed as Pa made a calibration of 0.5 to 2 Pa.
#[test]
fn a_calibration_in_mpa_typed_as_pa_is_refused_with_a_unit_hint() {
    let e = message(Calibration::from_pairs(
        Response::Density,
        &[(0.1, 0.5), (0.5, 1.0), (1.0, 2.0)],
    ));
    assert!(
        e.contains("highest pressure 2e0 Pa") && e.contains("MPa given as Pa"),
        "{e}"
    );
    assert!(Calibration::from_pairs(Response::Density, &[(0.1, 1e-300), (0.2, 2e-300)]).is_err());
    // The most sensitive film (Prescale 5LW, from 6 kPa) still calibrates.
    assert!(Calibration::from_pairs(Response::Density, &[(0.1, 6e3), (0.9, 5e4)]).is_ok());
    let csv = "density,pressure_pa\n0.1,0.5\n0.9,2\n";
    assert!(message(Calibration::parse_csv(csv, Path::new("c.csv"))).contains("MPa"));
}

/// U7: a one-pixel or all-black scan was said to have an invalid
/// calibration floor; the scan has no background.
#[test]
fn a_scan_without_background_is_named_not_the_calibration() -> Result<()> {
    let film = film();
    let opts = AnalysisOptions::default();
    let one = Scan::from_grey(1, 1, vec![0.4], Some(1e-4), 8)?;
    let e = message(analyse(&one, &film, &opts));
    assert!(
        e.contains("invalid lightest grey of the scan: 0.4 ") && e.contains("background"),
        "{e}"
    );
    assert!(!e.contains("grey floor of the calibration"), "{e}");
    let black = Scan::from_grey(64, 64, vec![0.0; 4096], Some(1e-4), 8)?;
    let e = message(analyse(&black, &film, &opts));
    assert!(e.contains("lightest grey of the scan: 0 "), "{e}");
    Ok(())
}

/// Found by the seventh adversarial run (2026-12-01): an inverted scan
/// (the print light on dark film) gave "1 print in the scan", the
/// background measured as one print, without a word.
#[test]
fn an_inverted_scan_is_warned_of_as_background_read_as_pressure() -> Result<()> {
    let film = film();
    let opts = AnalysisOptions::default();
    let upright = Scan::from_grey(64, 64, disk(0.9, 0.2), Some(1e-4), 8)?;
    let det = analyse(&upright, &film, &opts)?;
    assert_eq!(det.prints.len(), 1);
    assert!(det.warnings().is_empty(), "{:?}", det.warnings());
    let inverted = Scan::from_grey(64, 64, disk(0.2, 0.9), Some(1e-4), 8)?;
    let w = analyse(&inverted, &film, &opts)?.warnings();
    // The "print" is every pixel outside the disk.
    let outside = disk(0.0, 1.0).iter().filter(|&&g| g == 0.0).count();
    let percent = format!("{:.0}", 100.0 * outside as f64 / 4096.0);
    assert_eq!(percent, "93");
    assert!(
        w.len() == 1
            && w[0].starts_with(&format!(
                "print 1 covers {percent} % of the scan and reaches its border"
            )),
        "{w:?}"
    );
    Ok(())
}

/// U7: Otsu's threshold on a uniform scan reported "threshold grey NaN".
#[test]
fn otsu_on_a_uniform_scan_names_its_one_grey_not_a_nan_threshold() -> Result<()> {
    let opts = AnalysisOptions {
        threshold: Threshold::Otsu,
        min_pixels: 0,
        ..AnalysisOptions::default()
    };
    let uniform = Scan::from_grey(64, 64, vec![0.25; 4096], Some(1e-4), 8)?;
    let r = analyse(&uniform, &film(), &opts);
    assert!(
        matches!(r, Err(FilmError::UniformScan { pixels: 4096, grey }) if grey == 0.25),
        "{r:?}"
    );
    let e = message(r);
    assert!(
        e.contains("4096 pixels have grey 0.2500") && !e.contains("NaN"),
        "{e}"
    );
    Ok(())
}

/// U7: `Threshold::Density(-1)` was refused as "grey threshold: 10".
#[test]
fn a_bad_density_threshold_is_refused_as_the_density_given() -> Result<()> {
    let scan = Scan::from_grey(64, 64, disk(0.95, 0.3), Some(1e-4), 8)?;
    let with = |d| AnalysisOptions {
        threshold: Threshold::Density(d),
        ..AnalysisOptions::default()
    };
    let e = message(analyse(&scan, &film(), &with(-1.0)));
    assert!(e.contains("invalid density threshold: -1 "), "{e}");
    assert!(!e.contains("10"), "{e}");
    let e = message(analyse(&scan, &film(), &with(f64::NAN)));
    assert!(e.contains("density threshold: NaN"), "{e}");
    assert_eq!(analyse(&scan, &film(), &with(0.2))?.prints.len(), 1);
    Ok(())
}
