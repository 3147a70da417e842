//! Threshold, components, ellipse fit, statistics.

use tyreroad_film::*;

#[test]
fn otsu_splits_a_bimodal_histogram_between_its_modes() {
    // Two Gaussian modes at 0.3 (30 %) and 0.7 (70 %), σ = 0.05, on 256
    // levels: the threshold must fall within 0.02 of 0.5 (the exact Otsu
    // split for unequal weights moves slightly towards the smaller mode).
    let mut hist = vec![0u64; 256];
    for (k, h) in hist.iter_mut().enumerate() {
        let g = k as f64 / 255.0;
        let f = |m: f64, w: f64| w * (-(g - m).powi(2) / (2.0 * 0.05f64.powi(2))).exp();
        *h = (1e5 * (f(0.3, 0.3) + f(0.7, 0.7))).round() as u64;
    }
    let t = otsu(&hist).unwrap_or(f64::NAN);
    assert!((t - 0.5).abs() < 0.02, "threshold {t}");
    // Two spikes with empty bins between: the middle of the gap.
    let mut h2 = vec![0u64; 256];
    h2[50] = 1000;
    h2[200] = 9000;
    let t2 = otsu(&h2).unwrap_or(f64::NAN);
    assert!((t2 * 255.0 - 125.0).abs() <= 1.0, "threshold {t2}");
    assert_eq!(otsu(&[0, 10, 0]), None);
}

#[test]
fn connected_components_counts() -> Result<()> {
    // 0 = background. Two diagonal-touching pixels, an L, a ring, a lone
    // pixel at the far corner.
    let pic = [
        "#.........",
        ".#..###...",
        "....#.....",
        "..........",
        "..###.....",
        "..#.#.....",
        "..###....#",
    ];
    let w = pic[0].len();
    let h = pic.len();
    let mask: Vec<bool> = pic
        .iter()
        .flat_map(|r| r.bytes().map(|b| b == b'#'))
        .collect();
    let (l8, n8) = connected_components(&mask, w, h, Connectivity::Eight)?;
    let (l4, n4) = connected_components(&mask, w, h, Connectivity::Four)?;
    assert_eq!(n8, 4); // diagonal pair joined
    assert_eq!(n4, 5);
    // Labels are 1..n in raster order of first pixel.
    assert_eq!(l8[0], 1);
    assert_eq!(l8[w + 1], 1);
    assert_eq!(l4[w + 1], 2);
    assert_eq!(l8[6 * w + 9], 4);
    // A U-shape whose arms meet only at the bottom: one component
    // (exercises label merging).
    let u = ["#.#", "#.#", "###"];
    let m: Vec<bool> = u
        .iter()
        .flat_map(|r| r.bytes().map(|b| b == b'#'))
        .collect();
    assert_eq!(connected_components(&m, 3, 3, Connectivity::Four)?.1, 1);
    Ok(())
}

#[test]
fn ellipse_of_a_rasterised_ellipse() -> Result<()> {
    // a = 40 px, b = 20 px, major axis at 30° (film frame, y up); pixel
    // size 10 µm. Tolerances: axes within 0.5 px, orientation within 0.5°.
    let (a, b, th) = (40.0, 20.0, 30f64.to_radians());
    let (w, h) = (120usize, 100usize);
    let (cx, cy) = (60.3, 49.6);
    let s = 10e-6;
    let mut grey = vec![0.9f32; w * h];
    for r in 0..h {
        for c in 0..w {
            let x = c as f64 + 0.5 - cx;
            let y = -(r as f64 + 0.5 - cy);
            let u = x * th.cos() + y * th.sin();
            let v = -x * th.sin() + y * th.cos();
            if (u / a).powi(2) + (v / b).powi(2) <= 1.0 {
                grey[r * w + c] = 0.3;
            }
        }
    }
    let scan = Scan::from_grey(w, h, grey, Some(s), 32)?;
    let film = FilmResponse::new(Calibration::llw(LlwCurve::B)?, Scanner::default());
    let opts = AnalysisOptions {
        threshold: Threshold::Grey(0.6),
        ..AnalysisOptions::default()
    };
    let det = analyse(&scan, &film, &opts)?;
    assert_eq!(det.prints.len(), 1);
    let p = &det.prints[0];
    assert!(
        (p.ellipse.semi_major / s - a).abs() < 0.5,
        "{:?}",
        p.ellipse
    );
    assert!(
        (p.ellipse.semi_minor / s - b).abs() < 0.5,
        "{:?}",
        p.ellipse
    );
    assert!((p.ellipse.orientation - th).abs() < 0.5f64.to_radians());
    assert!(
        (p.centroid_px.0 - cx).abs() < 0.1 && (p.centroid_px.1 - cy).abs() < 0.1,
        "{:?}",
        p.centroid_px
    );
    assert!((p.apparent_radius / s - (a * b).sqrt()).abs() < 0.5);
    // Area within 0.5 % of π a b.
    assert!((p.area / (std::f64::consts::PI * a * b * s * s) - 1.0).abs() < 0.005);
    // Moments of a known ellipse, exactly.
    let e = Ellipse::from_moments(100.0, 25.0, 0.0);
    assert_eq!(
        (e.semi_major, e.semi_minor, e.orientation),
        (20.0, 10.0, 0.0)
    );
    let e = Ellipse::from_moments(25.0, 100.0, 0.0);
    assert!((e.orientation - std::f64::consts::FRAC_PI_2).abs() < 1e-15);
    Ok(())
}

#[test]
fn table1_statistics_against_a_hand_computation() -> Result<()> {
    // ε = 0.1, −0.2, 0.05: mean |ε| = 0.35/3 = 0.1166667;
    // deviations −0.0166667, 0.0833333, −0.0666667; squares sum 0.0116667;
    // sample variance 0.0058333; sd 0.0763763.
    let s =
        AbsErrorStats::of(&[0.1, -0.2, 0.05]).ok_or(FilmError::LayoutMismatch("empty".into()))?;
    assert!((s.mean_abs - 0.116_666_7).abs() < 1e-7);
    assert!((s.std_abs - 0.076_376_3).abs() < 1e-7);
    assert_eq!(AbsErrorStats::of(&[]), None);
    let model = [
        ModelRow {
            load_n: 300.0,
            indenter: 1,
            x_m: 0.0,
            y_m: 0.0,
            force_n: 10.0,
            radius_m: 2e-3,
        },
        ModelRow {
            load_n: 300.0,
            indenter: 2,
            x_m: 0.01,
            y_m: 0.0,
            force_n: 20.0,
            radius_m: 2.5e-3,
        },
    ];
    // Measured 11 N (ε 0.1) and 16 N (ε −0.2); radii 1.9 mm (−0.05), 2.5 mm (0).
    let c = compare(300.0, &[(2, 16.0, 2.5e-3), (1, 11.0, 1.9e-3)], &model)?;
    assert!((c.indenters[0].eps_force - 0.1).abs() < 1e-12);
    assert!((c.indenters[1].eps_force + 0.2).abs() < 1e-12);
    assert!((c.table1.force.mean_abs - 0.15).abs() < 1e-12);
    assert!((c.table1.force.std_abs - 0.1 / 2f64.sqrt()).abs() < 1e-12);
    assert!((c.table1.radius.mean_abs - 0.025).abs() < 1e-12);
    // A model indenter without measurement is an error.
    assert!(compare(300.0, &[(1, 11.0, 1.9e-3)], &model).is_err());
    Ok(())
}

#[test]
fn model_csv_reading() -> Result<()> {
    let text = "# static run\nload_n,indenter,x_m,y_m,force_n,radius_m\n289,1,0.02,-0.02,11.5,1.7e-3\n289,2,0.01,-0.02,11.6,1.71e-3\n355,1,0.02,-0.02,14.2,1.8e-3\n";
    let rows = parse_model_csv(text, std::path::Path::new("m.csv"))?;
    assert_eq!(rows.len(), 3);
    // A spreadsheet's byte-order mark is not part of the first line
    // (regression: it made the header "\u{feff}load_n,…" unknown).
    let with_bom = format!("\u{feff}{}", text.trim_start_matches("# static run\n"));
    assert_eq!(
        parse_model_csv(&with_bom, std::path::Path::new("m.csv"))?,
        rows
    );
    // One row per load and indenter (regression: a repeated indenter was
    // counted twice in the statistics).
    let twice = format!("{text}289,2,0.01,-0.02,11.6,1.71e-3\n");
    let e = parse_model_csv(&twice, std::path::Path::new("m.csv"))
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(e.contains("line 6: indenter 2 at 289 N given twice"), "{e}");
    assert_eq!(loads(&rows), vec![289.0, 355.0]);
    assert_eq!(rows_at_load(&rows, 289.0).len(), 2);
    let bad = "load,indenter,x_m,y_m,force_n,radius_m\n";
    let e = parse_model_csv(bad, std::path::Path::new("m.csv"))
        .err()
        .map(|e| e.to_string());
    assert!(
        e.unwrap_or_default()
            .contains("m.csv, line 1: expected header")
    );
    let bad = "load_n,indenter,x_m,y_m,force_n,radius_m\n289,1,0.02,-0.02,x,1e-3\n";
    let e = parse_model_csv(bad, std::path::Path::new("m.csv"))
        .err()
        .map(|e| e.to_string());
    assert!(
        e.unwrap_or_default()
            .contains("line 2: not a finite number: \"x\"")
    );
    Ok(())
}
