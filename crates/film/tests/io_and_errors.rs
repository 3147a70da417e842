//! Reading scans (PNG/TIFF, 8/16 bit, grey/RGB, resolution) and bad input.

use std::io::Cursor;
use std::path::Path;

use image::{ImageBuffer, ImageFormat, Luma, Rgb};
use tyreroad_core::Field;
use tyreroad_film::*;

/// A scratch folder removed when the test ends (passed or failed), so the
/// machine's temporary folder does not collect one per test run.
fn scratch() -> tempfile::TempDir {
    tempfile::Builder::new()
        .prefix("tyreroad-film-tests-")
        .tempdir()
        .expect("a scratch folder in the temporary directory")
}

const W: u32 = 7;
const H: u32 = 5;

/// Pixel (x, y) of the test pattern: green carries `x·y`-dependent values,
/// red and blue carry something else, so the channel choice shows.
fn g_of(x: u32, y: u32) -> f64 {
    (x + W * y) as f64 / (W * H) as f64
}

#[test]
fn reads_8_and_16_bit_grey_and_rgb_png_and_tiff() -> Result<()> {
    let dir = scratch();
    let tmp = |name: &str| dir.path().join(name);
    for fmt in [ImageFormat::Png, ImageFormat::Tiff] {
        let ext = if fmt == ImageFormat::Png {
            "png"
        } else {
            "tif"
        };
        // 8-bit grey.
        let p = tmp(&format!("g8.{ext}"));
        ImageBuffer::from_fn(W, H, |x, y| Luma([(g_of(x, y) * 255.0).round() as u8]))
            .save_with_format(&p, fmt)
            .map_err(|e| FilmError::Image {
                path: p.clone(),
                message: e.to_string(),
            })?;
        let s = Scan::open(&p, Channel::Auto)?;
        assert_eq!((s.width(), s.height(), s.bit_depth()), (7, 5, 8));
        assert!((s.get(3, 2).unwrap_or(-1.0) as f64 - g_of(3, 2)).abs() <= 0.5 / 255.0);
        // 16-bit grey.
        let p = tmp(&format!("g16.{ext}"));
        ImageBuffer::from_fn(W, H, |x, y| Luma([(g_of(x, y) * 65535.0).round() as u16]))
            .save_with_format(&p, fmt)
            .map_err(|e| FilmError::Image {
                path: p.clone(),
                message: e.to_string(),
            })?;
        let s = Scan::open(&p, Channel::Auto)?;
        assert_eq!(s.bit_depth(), 16);
        assert!((s.get(6, 4).unwrap_or(-1.0) as f64 - g_of(6, 4)).abs() <= 0.5 / 65535.0);
        // 8-bit RGB: green analysed by default; red on request.
        let p = tmp(&format!("rgb8.{ext}"));
        ImageBuffer::from_fn(W, H, |x, y| {
            Rgb([200u8, (g_of(x, y) * 255.0).round() as u8, 10])
        })
        .save_with_format(&p, fmt)
        .map_err(|e| FilmError::Image {
            path: p.clone(),
            message: e.to_string(),
        })?;
        let s = Scan::open(&p, Channel::Auto)?;
        assert!((s.get(2, 3).unwrap_or(-1.0) as f64 - g_of(2, 3)).abs() <= 0.5 / 255.0);
        let r = Scan::open(&p, Channel::Red)?;
        assert!((r.get(2, 3).unwrap_or(-1.0) - 200.0 / 255.0).abs() < 1e-6);
        // 16-bit RGB.
        let p = tmp(&format!("rgb16.{ext}"));
        ImageBuffer::from_fn(W, H, |x, y| {
            Rgb([60000u16, (g_of(x, y) * 65535.0).round() as u16, 100])
        })
        .save_with_format(&p, fmt)
        .map_err(|e| FilmError::Image {
            path: p.clone(),
            message: e.to_string(),
        })?;
        let s = Scan::open(&p, Channel::Green)?;
        assert_eq!(s.bit_depth(), 16);
        assert!((s.get(5, 1).unwrap_or(-1.0) as f64 - g_of(5, 1)).abs() <= 0.5 / 65535.0);
        let l = Scan::open(&p, Channel::Luma)?;
        let want =
            (0.2126 * 60000.0 + 0.7152 * (g_of(5, 1) * 65535.0).round() + 0.0722 * 100.0) / 65535.0;
        assert!((l.get(5, 1).unwrap_or(-1.0) as f64 - want).abs() < 1e-5);
        // The image crate writes no usable resolution: pixel size unknown.
        assert_eq!(s.pixel_size(), None);
        assert!((s.with_dpi(1200.0)?.pixel_size().unwrap_or(0.0) - 0.0254 / 1200.0).abs() < 1e-15);
    }
    Ok(())
}

#[test]
fn pixel_size_from_png_phys_and_tiff_resolution() -> Result<()> {
    // PNG: pHYs in pixels per metre (40 000 /m = 25 µm).
    let mut buf = Vec::new();
    {
        let mut enc = png::Encoder::new(&mut buf, W, H);
        enc.set_color(png::ColorType::Grayscale);
        enc.set_depth(png::BitDepth::Eight);
        enc.set_pixel_dims(Some(png::PixelDimensions {
            xppu: 40_000,
            yppu: 40_000,
            unit: png::Unit::Meter,
        }));
        let mut w = enc.write_header().map_err(|e| FilmError::Image {
            path: "png".into(),
            message: e.to_string(),
        })?;
        w.write_image_data(&vec![128u8; (W * H) as usize])
            .map_err(|e| FilmError::Image {
                path: "png".into(),
                message: e.to_string(),
            })?;
    }
    let s = Scan::decode(&buf, Channel::Auto, Path::new("phys.png"))?;
    assert!((s.pixel_size().unwrap_or(0.0) - 25e-6).abs() < 1e-15);
    // TIFF: 600 dpi.
    let mut cur = Cursor::new(Vec::new());
    {
        let mut enc = tiff::encoder::TiffEncoder::new(&mut cur).map_err(|e| FilmError::Image {
            path: "tif".into(),
            message: e.to_string(),
        })?;
        let mut img = enc
            .new_image::<tiff::encoder::colortype::Gray16>(W, H)
            .map_err(|e| FilmError::Image {
                path: "tif".into(),
                message: e.to_string(),
            })?;
        img.resolution(
            tiff::tags::ResolutionUnit::Inch,
            tiff::encoder::Rational { n: 600, d: 1 },
        );
        img.write_data(&vec![30000u16; (W * H) as usize])
            .map_err(|e| FilmError::Image {
                path: "tif".into(),
                message: e.to_string(),
            })?;
    }
    let s = Scan::decode(cur.get_ref(), Channel::Auto, Path::new("res.tif"))?;
    assert!((s.pixel_size().unwrap_or(0.0) - 0.0254 / 600.0).abs() < 1e-15);
    assert!((s.get(0, 0).unwrap_or(0.0) as f64 - 30000.0 / 65535.0).abs() < 1e-6);
    Ok(())
}

#[test]
fn unreadable_images_are_errors_that_name_the_file() {
    let e = Scan::open(Path::new("/nonexistent/scan.png"), Channel::Auto).err();
    assert!(matches!(e, Some(FilmError::Io { .. })));
    let e = Scan::decode(
        b"this is not an image",
        Channel::Auto,
        Path::new("junk.png"),
    )
    .err();
    let msg = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(msg.starts_with("unreadable image junk.png"), "{msg}");
    // A PNG cut short.
    let mut buf = Vec::new();
    ImageBuffer::from_fn(W, H, |x, _| Luma([x as u8]))
        .write_to(&mut Cursor::new(&mut buf), ImageFormat::Png)
        .ok();
    buf.truncate(buf.len() / 2);
    assert!(matches!(
        Scan::decode(&buf, Channel::Auto, Path::new("cut.png")),
        Err(FilmError::Image { .. })
    ));
    assert!(Scan::from_grey(3, 3, vec![0.5; 8], None, 8).is_err());
}

/// Regression (second adversarial run): a TIFF cut short said only
/// "failed to fill whole buffer".
#[test]
fn a_truncated_tiff_is_said_to_be_cut_short() {
    let mut buf = Vec::new();
    ImageBuffer::from_fn(W, H, |x, _| Luma([x as u8]))
        .write_to(&mut Cursor::new(&mut buf), ImageFormat::Tiff)
        .ok();
    assert!(Scan::decode(&buf, Channel::Auto, Path::new("whole.tif")).is_ok());
    buf.truncate(buf.len() / 2);
    let msg = Scan::decode(&buf, Channel::Auto, Path::new("cut.tif"))
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(msg.starts_with("unreadable image cut.tif"), "{msg}");
    assert!(msg.contains("truncated"), "{msg}");
}

fn synthetic_25() -> Result<(Detection, FilmResponse)> {
    let rows = paper_hertz_rows(&[289.0], 6.54e6, 0.5, 5e-3);
    let film = FilmResponse::new(Calibration::llw(LlwCurve::B)?, Scanner::default());
    let prints: Vec<HertzPrint> = rows
        .iter()
        .map(|r| HertzPrint {
            x: r.x_m,
            y: r.y_m,
            force: r.force_n,
            radius: r.radius_m,
        })
        .collect();
    let grid = covering_grid(-0.025, 0.025, -0.025, 0.025, 60e-6)?;
    let map = add_hertz(Field::zeros(grid), &prints)?;
    let scan = render(&map, &film, &RenderOptions::default())?;
    Ok((analyse(&scan, &film, &AnalysisOptions::default())?, film))
}

#[test]
fn layout_problems_are_errors() -> Result<()> {
    let (det, film) = synthetic_25()?;
    // An indenter moved to a blank place: print not found, named.
    let mut ind = Layout::paper_grid(10e-3).indenters().to_vec();
    ind[12].x = 0.005;
    ind[12].y = 0.005;
    let layout = Layout::new(ind)?;
    let origin = Origin::Pixel {
        col: 0.025 / 60e-6,
        row: 0.025 / 60e-6,
    };
    let e = match_layout(&det, &layout, origin, None)
        .err()
        .map(|e| e.to_string());
    assert!(
        e.unwrap_or_default()
            .starts_with("print not found for indenter 13")
    );
    // More indenters than prints.
    let mut ind = Layout::paper_grid(10e-3).indenters().to_vec();
    ind.push(Indenter {
        number: 26,
        x: 0.03,
        y: 0.0,
    });
    let e = match_layout(&det, &Layout::new(ind)?, origin, None).err();
    assert!(matches!(e, Some(FilmError::LayoutMismatch(_))));
    // Wrong pitch: prints fall between expected places.
    let e = match_layout(&det, &Layout::paper_grid(7e-3), origin, None).err();
    assert!(matches!(e, Some(FilmError::PrintNotFound { .. })));
    // The message points at the scale: prints 10 mm apart, indenters 7 mm.
    let msg = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(
        msg.contains("the pixel size (dpi) is likely wrong, by a factor 0.700"),
        "{msg}"
    );
    // A print missing at the right scale names no scale problem.
    let mut ind = Layout::paper_grid(10e-3).indenters().to_vec();
    ind[12].x = 0.005;
    ind[12].y = 0.005;
    let e = match_layout(&det, &Layout::new(ind)?, origin, None).err();
    let msg = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(
        msg.starts_with("print not found") && !msg.contains("dpi"),
        "{msg}"
    );
    // Two indenters on one print (large tolerance).
    let two = Layout::new(vec![
        Indenter {
            number: 1,
            x: 0.0,
            y: 0.0,
        },
        Indenter {
            number: 2,
            x: 0.001,
            y: 0.0,
        },
    ])?;
    let e = match_layout(&det, &two, origin, Some(0.004))
        .err()
        .map(|e| e.to_string());
    assert!(
        e.unwrap_or_default()
            .contains("indenters 1 and 2 both match")
    );
    // Duplicate numbers; bad CSV header.
    assert!(
        Layout::new(vec![
            Indenter {
                number: 1,
                x: 0.0,
                y: 0.0
            },
            Indenter {
                number: 1,
                x: 1.0,
                y: 0.0
            }
        ])
        .is_err()
    );
    assert!(matches!(
        Layout::parse_csv("n,x,y\n1,0,0\n", Path::new("l.csv")),
        Err(FilmError::Csv { line: 1, .. })
    ));
    let ok = Layout::parse_csv(
        "# balls\nindenter,x_m,y_m\n1,0.02,-0.02\n2,0.01,-0.02\n",
        Path::new("l.csv"),
    )?;
    assert_eq!(ok.indenters().len(), 2);
    // No pixel size; nothing to find.
    let blank = Scan::from_grey(50, 50, vec![0.8; 2500], None, 16)?;
    assert!(matches!(
        analyse(&blank, &film, &AnalysisOptions::default()),
        Err(FilmError::PixelSizeUnknown)
    ));
    let blank = blank.with_pixel_size(1e-4)?;
    assert!(matches!(
        analyse(&blank, &film, &AnalysisOptions::default()),
        Err(FilmError::NoPrints { .. })
    ));
    let grey = Scan::from_grey(50, 50, vec![0.5; 2500], Some(1e-4), 16)?;
    assert!(matches!(
        analyse(&grey, &film, &AnalysisOptions::default()),
        Err(FilmError::InvalidParameter { .. })
    ));
    Ok(())
}

/// Regression (adversarial run, 2026-11-29): a one-indenter layout on a
/// scan of several equal prints, the origin estimated from the prints, was
/// matched to whichever print lay nearest their centroid, without a word.
#[test]
fn a_one_indenter_layout_on_several_prints_is_refused_as_ambiguous() -> Result<()> {
    let (det, film) = synthetic_25()?;
    let one = Layout::new(vec![Indenter {
        number: 13,
        x: 0.0,
        y: 0.0,
    }])?;
    let e = match_layout(&det, &one, Origin::Centroid, None).err();
    let msg = e.as_ref().map(|e| e.to_string()).unwrap_or_default();
    assert!(
        msg.contains("single indenter 13 matches any of the 25 prints") && msg.contains("--origin"),
        "{msg}"
    );
    // Given the origin, the indenter is placed: the centre print.
    let origin = Origin::Pixel {
        col: 0.025 / 60e-6,
        row: 0.025 / 60e-6,
    };
    let m = match_layout(&det, &one, origin, None)?;
    assert!(m.matches[0].distance < 60e-6, "{:?}", m.matches);
    assert_eq!(m.unmatched_prints.len(), 24);
    // One print for one indenter needs no origin.
    let ball = HertzPrint {
        x: 0.0,
        y: 0.0,
        force: 16.0,
        radius: 1.9e-3,
    };
    let scan = render(
        &hertz_pressure_map(&[ball], 200, 200, 25e-6)?,
        &film,
        &RenderOptions::default(),
    )?;
    let single = analyse(&scan, &film, &AnalysisOptions::default())?;
    assert_eq!(
        match_layout(&single, &one, Origin::Centroid, None)?
            .matches
            .len(),
        1
    );
    Ok(())
}

/// A `width` × `height` scan of 25 µm pixels: unreacted film (grey 0.83,
/// density 0.08) with a disc of radius 20 px and grey `disc` at its centre.
fn disc_scan(disc: f32) -> Result<Scan> {
    let (w, h) = (100usize, 100usize);
    let grey = (0..w * h)
        .map(|k| {
            let (c, r) = ((k % w) as f64 + 0.5, (k / w) as f64 + 0.5);
            if (c - 50.0).hypot(r - 50.0) < 20.0 {
                disc
            } else {
                0.83
            }
        })
        .collect();
    Scan::from_grey(w, h, grey, Some(25e-6), 16)
}

/// Regression (adversarial run, 2026-11-29): a print darker than the
/// calibration's top (a film pressed beyond its range) was refused as a
/// "layout mismatch", which sends the user to the layout file.
#[test]
fn a_saturated_print_is_reported_as_saturated_not_as_a_layout_mismatch() -> Result<()> {
    let film = FilmResponse::new(Calibration::llw(LlwCurve::B)?, Scanner::default());
    let one = Layout::new(vec![Indenter {
        number: 1,
        x: 0.0,
        y: 0.0,
    }])?;
    // Grey 0.05 is density 1.30, beyond curve B's top (1.22 at 2.458 MPa).
    let det = analyse(&disc_scan(0.05)?, &film, &AnalysisOptions::default())?;
    let n = det.prints[0].pixel_count;
    assert_eq!(det.prints[0].saturated_pixels, n);
    let m = match_layout(&det, &one, Origin::Centroid, None)?;
    for estimator in [Estimator::MeanGrey, Estimator::HertzFit] {
        let e = measurements(&det, &m, estimator).err();
        let msg = e.as_ref().map(|e| e.to_string()).unwrap_or_default();
        assert!(
            matches!(e, Some(FilmError::SaturatedPrint { indenter: 1, .. })),
            "{msg}"
        );
        assert!(
            msg.contains(&format!("{n} of its {n} pixels (100.0 %)"))
                && msg.contains("above the calibration's top, 2.458e6 Pa")
                && !msg.contains("layout"),
            "{msg}"
        );
    }
    // The pixel mean still reads it, as a lower bound.
    assert!(measurements(&det, &m, Estimator::PixelMean).is_ok());
    // A print too faint for the calibration (grey 0.70: density 0.155,
    // below curve B's floor 0.179) is said to be below its range.
    let det = analyse(&disc_scan(0.70)?, &film, &AnalysisOptions::default())?;
    assert_eq!(det.prints[0].below_range_pixels, det.prints[0].pixel_count);
    let m = match_layout(&det, &one, Origin::Centroid, None)?;
    for estimator in [Estimator::MeanGrey, Estimator::HertzFit] {
        let e = measurements(&det, &m, estimator).err();
        let msg = e.as_ref().map(|e| e.to_string()).unwrap_or_default();
        assert!(
            matches!(e, Some(FilmError::PrintNotMeasured { indenter: 1, .. })),
            "{msg}"
        );
        assert!(
            msg.contains("below the calibration's bottom, 4.859e5 Pa") && !msg.contains("layout"),
            "{msg}"
        );
    }
    Ok(())
}

#[test]
fn annotated_image_marks_prints() -> Result<()> {
    let (det, _) = synthetic_25()?;
    let m = match_layout(&det, &Layout::paper_grid(10e-3), Origin::Centroid, None)?;
    let scan = {
        // A plain background scan of the same size is enough for drawing.
        Scan::from_grey(
            det.width,
            det.height,
            vec![0.8; det.width * det.height],
            Some(det.pixel_size),
            16,
        )?
    };
    let img = annotate(&scan, &det, Some(&m));
    let red = img.pixels().filter(|p| p.0 == [230, 30, 30]).count();
    let blue = img.pixels().filter(|p| p.0 == [30, 90, 240]).count();
    let green = img.pixels().filter(|p| p.0 == [0, 150, 0]).count();
    // Outlines and ellipses (≈ 170 px of perimeter per print at 60 µm), and
    // 1- or 2-digit numbers.
    assert!(
        red > 25 * 20 && red + blue > 25 * 150 && green > 25 * 10,
        "{red} {blue} {green}"
    );
    Ok(())
}

/// A grey PNG of W × H with the given pHYs (pixels per metre along x, y).
fn png_with_phys(xppu: u32, yppu: u32) -> Vec<u8> {
    let mut buf = Vec::new();
    let mut enc = png::Encoder::new(&mut buf, W, H);
    enc.set_color(png::ColorType::Grayscale);
    enc.set_depth(png::BitDepth::Eight);
    enc.set_pixel_dims(Some(png::PixelDimensions {
        xppu,
        yppu,
        unit: png::Unit::Meter,
    }));
    let mut w = enc.write_header().expect("png header");
    w.write_image_data(&vec![128u8; (W * H) as usize])
        .expect("png data");
    drop(w);
    buf
}

#[test]
fn scans_with_non_square_pixels_are_refused_not_read_as_square() {
    // 600 × 300 dpi = 23 622 × 11 811 pixels per metre.
    let bytes = png_with_phys(23_622, 11_811);
    let e = Scan::decode(&bytes, Channel::Auto, Path::new("wide.png")).err();
    let msg = e.as_ref().map(ToString::to_string).unwrap_or_default();
    assert!(
        matches!(e, Some(FilmError::Image { .. }))
            && msg.contains("wide.png")
            && msg.contains("non-square pixels")
            && msg.contains("600 × 300 dpi"),
        "{msg}"
    );
    // The same scan at 600 × 600 dpi reads, with its pixel size.
    let s = Scan::decode(
        &png_with_phys(23_622, 23_622),
        Channel::Auto,
        Path::new("sq.png"),
    );
    let size = s.ok().and_then(|s| s.pixel_size()).unwrap_or(0.0);
    assert!((size - 1.0 / 23_622.0).abs() < 1e-15, "{size}");

    let mut cur = Cursor::new(Vec::new());
    {
        let mut enc = tiff::encoder::TiffEncoder::new(&mut cur).expect("tiff encoder");
        let mut img = enc
            .new_image::<tiff::encoder::colortype::Gray16>(W, H)
            .expect("tiff image");
        img.resolution_unit(tiff::tags::ResolutionUnit::Inch);
        img.x_resolution(tiff::encoder::Rational { n: 600, d: 1 });
        img.y_resolution(tiff::encoder::Rational { n: 300, d: 1 });
        img.write_data(&vec![30000u16; (W * H) as usize])
            .expect("tiff data");
    }
    let e = Scan::decode(cur.get_ref(), Channel::Auto, Path::new("wide.tif")).err();
    let msg = e.map(|e| e.to_string()).unwrap_or_default();
    assert!(
        msg.contains("wide.tif") && msg.contains("600 × 300 dpi"),
        "{msg}"
    );
}
