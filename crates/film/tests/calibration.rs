//! Calibration: PCHIP fit and inverse, flags, LLW chart, scanner relation.

use std::path::Path;

use tyreroad_film::*;

#[test]
fn llw_chart_loads_four_curves_over_the_film_range() -> Result<()> {
    let chart = LlwChart::standard()?;
    assert_eq!(chart.pressure_pa.len(), 86);
    for d in &chart.density {
        assert_eq!(d.len(), 86);
    }
    // The shipped data file is the one the crate embeds.
    let on_disk = std::fs::read_to_string(
        Path::new(env!("CARGO_MANIFEST_DIR")).join("data/fuji-llw-density-curves.csv"),
    )
    .map_err(|reason| FilmError::Io {
        path: "fixture".into(),
        reason,
    })?;
    assert_eq!(on_disk, LLW_CHART_CSV);
    assert!(LLW_CHART_CSV.starts_with("# Fuji Prescale LLW"));
    for c in [LlwCurve::A, LlwCurve::B, LlwCurve::C, LlwCurve::D] {
        let cal = Calibration::llw(c)?;
        let (p0, p1) = cal.pressure_range();
        assert!((p0 - 0.48586e6).abs() < 1.0 && (p1 - 2.45837e6).abs() < 1.0);
        assert_eq!(cal.response(), Response::Density);
    }
    let b = Calibration::llw(LlwCurve::B)?;
    assert!((b.response_range().0 - 0.17906).abs() < 1e-12);
    assert!((b.response_range().1 - 1.22483).abs() < 1e-12);
    Ok(())
}

#[test]
fn inverse_round_trip_to_round_off() -> Result<()> {
    // Tolerance: 1e-9 relative in pressure (bisection to machine precision).
    for c in [LlwCurve::A, LlwCurve::B, LlwCurve::C, LlwCurve::D] {
        let cal = Calibration::llw(c)?;
        let (p0, p1) = cal.pressure_range();
        for k in 0..=500 {
            let p = p0 + (p1 - p0) * k as f64 / 500.0;
            let d = cal
                .response_at(p)
                .ok_or(FilmError::InvalidCalibration("range".into()))?;
            match cal.pressure(d) {
                Calibrated::InRange(q) => assert!((q / p - 1.0).abs() < 1e-9, "{c:?} {p} {q}"),
                other => panic!("{c:?}: {p} Pa read back as {other:?}"),
            }
        }
    }
    Ok(())
}

#[test]
fn pchip_interpolates_knots_and_stays_monotone() -> Result<()> {
    let cal = Calibration::llw(LlwCurve::A)?;
    let curve = cal.curve();
    for (x, y) in curve.xs().iter().zip(curve.ys()) {
        let v = curve
            .eval(*x)
            .ok_or(FilmError::InvalidCalibration("knot".into()))?;
        assert!((v - y).abs() < 1e-12);
    }
    // Dense sampling: strictly increasing.
    let (a, b) = curve.domain();
    let mut prev = f64::NEG_INFINITY;
    for k in 0..=20000 {
        let v = curve
            .eval(a + (b - a) * k as f64 / 20000.0)
            .unwrap_or(f64::NAN);
        assert!(v >= prev, "not monotone at sample {k}");
        prev = v;
    }
    // A step-like data set would make an ordinary cubic spline overshoot;
    // PCHIP stays within the data.
    let step = MonotoneCubic::new(vec![0.0, 1.0, 2.0, 3.0], vec![0.0, 0.01, 0.99, 1.0])?;
    for k in 0..=300 {
        let v = step.eval(3.0 * k as f64 / 300.0).unwrap_or(f64::NAN);
        assert!((0.0..=1.0).contains(&v));
    }
    Ok(())
}

#[test]
fn values_outside_the_range_are_flagged() -> Result<()> {
    let cal = Calibration::llw(LlwCurve::B)?;
    assert_eq!(cal.pressure(0.10), Calibrated::BelowRange);
    assert_eq!(cal.pressure(1.5), Calibrated::Saturated);
    assert_eq!(cal.pressure(f64::NAN), Calibrated::BelowRange);
    assert_eq!(cal.pressure(f64::INFINITY), Calibrated::Saturated);
    assert!(matches!(cal.pressure(0.17906), Calibrated::InRange(_)));
    assert_eq!(cal.response_at(3e6), None);
    assert_eq!(cal.response_at(0.4e6), None);
    assert_eq!(cal.response_clamped(3e6), Some(cal.response_range().1));
    // Grey calibrations fall with pressure: dark beyond the range is
    // saturation, light is below range.
    let grey =
        Calibration::from_pairs(Response::Grey, &[(0.8, 0.5e6), (0.5, 1.0e6), (0.2, 2.0e6)])?;
    assert_eq!(grey.pressure(0.9), Calibrated::BelowRange);
    assert_eq!(grey.pressure(0.1), Calibrated::Saturated);
    assert!((grey.pressure(0.5).in_range().unwrap_or(0.0) - 1.0e6).abs() < 1e-6);
    // Through the scanner: a white pixel is below range, a black one saturated.
    let film = FilmResponse::new(cal, Scanner::default());
    assert_eq!(film.pressure_of_grey(1.0), Calibrated::BelowRange);
    assert_eq!(film.pressure_of_grey(0.0), Calibrated::Saturated);
    Ok(())
}

#[test]
fn non_monotone_calibration_is_an_error() {
    let r = Calibration::from_pairs(
        Response::Density,
        &[(0.2, 0.5e6), (0.5, 1.0e6), (0.45, 1.5e6), (0.9, 2.0e6)],
    );
    let e = r.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("non-monotone calibration: density 0.5"), "{e}");
    // Flat segments cannot be inverted either.
    assert!(matches!(
        Calibration::from_pairs(Response::Density, &[(0.2, 0.5e6), (0.2, 1.0e6)]),
        Err(FilmError::NonMonotoneCalibration { .. })
    ));
    // Two points at the same pressure.
    assert!(matches!(
        Calibration::from_pairs(Response::Density, &[(0.2, 0.5e6), (0.3, 0.5e6)]),
        Err(FilmError::InvalidCalibration(_))
    ));
    let csv = "# my film\ndensity,pressure_mpa\n0.2,0.5\n0.6,1.0\n0.4,1.5\n";
    assert!(matches!(
        Calibration::parse_csv(csv, Path::new("cal.csv")),
        Err(FilmError::NonMonotoneCalibration { .. })
    ));
}

#[test]
fn calibration_csv_units_are_converted() -> Result<()> {
    let csv = "# grey levels of an 8-bit scan\ngrey8,pressure_mpa\n200,0.5\n120,1.0\n40,2.0\n";
    let cal = Calibration::parse_csv(csv, Path::new("cal.csv"))?;
    assert_eq!(cal.response(), Response::Grey);
    assert_eq!(cal.pressure_range(), (0.5e6, 2.0e6));
    let p = cal.pressure(120.0 / 255.0).in_range().unwrap_or(0.0);
    assert!((p - 1.0e6).abs() < 1e-3);
    let bad = "grey8,pressure_bar\n200,5\n";
    let e = Calibration::parse_csv(bad, Path::new("cal.csv"))
        .err()
        .map(|e| e.to_string());
    assert!(
        e.unwrap_or_default()
            .contains("cal.csv, line 1: unknown pressure column")
    );
    Ok(())
}

#[test]
fn scanner_density_relation() -> Result<()> {
    let s = Scanner::new(0.9, 0.05)?;
    // R = (g − 0.05)/0.85; D = −log10 R.
    assert!((s.density(0.9)).abs() < 1e-15);
    assert!((s.density(0.05 + 0.085) - 1.0).abs() < 1e-12);
    for d in [0.0, 0.2, 0.7, 1.3, 2.5] {
        assert!((s.density(s.grey(d)) - d).abs() < 1e-12);
    }
    assert_eq!(s.density(0.05), f64::INFINITY);
    assert!(Scanner::new(0.1, 0.2).is_err());
    Ok(())
}

/// Regression (adversarial run, 2026-11-29): `--white 2` was taken, and
/// the analysis then failed on a "grey floor of the calibration" of 1.32,
/// a grey no scan holds, without naming the white reference.
#[test]
fn a_white_level_above_one_is_refused_by_name() -> Result<()> {
    let refused = |white, black| {
        Scanner::new(white, black)
            .err()
            .map(|e| e.to_string())
            .unwrap_or_default()
    };
    let e = refused(2.0, 0.0);
    assert!(
        e.contains("scanner white reference: 2 ") && e.contains("(0, 1]"),
        "{e}"
    );
    let e = refused(0.0, 0.0);
    assert!(e.contains("scanner white reference: 0 "), "{e}");
    let e = refused(0.9, -0.1);
    assert!(
        e.contains("scanner black reference: -0.1 ") && e.contains("[0, 1)"),
        "{e}"
    );
    let e = refused(0.5, 0.6);
    assert!(
        e.contains("scanner white reference: 0.5 ") && e.contains("above the black reference"),
        "{e}"
    );
    let e = refused(f64::NAN, 0.0);
    assert!(e.contains("scanner white reference: NaN"), "{e}");
    assert!(Scanner::new(1.0, 0.0).is_ok() && Scanner::new(0.9, 0.05).is_ok());
    // A scanner written field by field reaches the analysis unchecked: it
    // is refused there by the same name, not as a grey floor.
    let film = FilmResponse::new(
        Calibration::llw(LlwCurve::B)?,
        Scanner {
            white: 2.0,
            black: 0.0,
        },
    );
    let scan = Scan::from_grey(50, 50, vec![0.8; 2500], Some(1e-4), 16)?;
    let e = analyse(&scan, &film, &AnalysisOptions::default())
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("scanner white reference: 2 "), "{e}");
    Ok(())
}
