//! MPD and third-octave spectrum of known profiles; synthesis statistics.
#![allow(clippy::unwrap_used)]

use tyreroad_texture::{
    Aggregate, ChipShape, HeightMap, SelfAffine, aggregate, mean_profile_depth, self_affine,
    third_octave_spectrum,
};

#[test]
fn mpd_of_a_cosine_is_exact() {
    // h_i = A cos(2π (i + ½) dx / λ): symmetric about each segment's centre
    // (λ divides 50 mm), so the regression line is flat and at zero, and the
    // sampled peaks are A cos(π dx/λ): MPD = A cos(π dx / λ) exactly.
    let (a, lambda, dx) = (0.7e-3, 12.5e-3, 0.5e-3);
    let map = HeightMap::from_fn(1000, 3, dx, 1e-3, |x, _| {
        a * (std::f64::consts::TAU * (x + 0.5 * dx) / lambda).cos()
    })
    .unwrap();
    let m = mean_profile_depth(&map, None).unwrap();
    let expected = a * (std::f64::consts::PI * dx / lambda).cos();
    assert_eq!((m.samples, m.segments), (200, 15));
    assert!((m.mpd - expected).abs() < 1e-15, "{} vs {expected}", m.mpd);
    assert!((m.baseline - 0.1).abs() < 1e-12);
    // A slope (a tilted road) does not change it.
    let tilted = HeightMap::from_fn(1000, 3, dx, 1e-3, |x, _| {
        a * (std::f64::consts::TAU * (x + 0.5 * dx) / lambda).cos() + 0.03 * x
    })
    .unwrap();
    let mt = mean_profile_depth(&tilted, None).unwrap();
    assert!(
        (mt.mpd - expected).abs() < 1e-12,
        "{} vs {expected}",
        mt.mpd
    );
}

#[test]
fn mpd_on_a_short_map_uses_its_length() {
    let (a, lambda, dx) = (1e-3, 5e-3, 0.25e-3);
    let map = HeightMap::from_fn(160, 2, dx, dx, |x, _| {
        a * (std::f64::consts::TAU * (x + 0.5 * dx) / lambda).cos()
    })
    .unwrap();
    let m = mean_profile_depth(&map, None).unwrap();
    assert_eq!((m.samples, m.segments), (160, 2));
    assert!((m.baseline - 0.04).abs() < 1e-12);
    let expected = a * (std::f64::consts::PI * dx / lambda).cos();
    assert!((m.mpd - expected).abs() < 1e-15);
}

#[test]
fn third_octave_level_of_a_sine_at_a_band_centre() {
    // λ = 10 mm (band m = 10) and 31.62 mm (m = 15, profile of 8 periods).
    for (lambda, m, nx, dx) in [
        (10e-3, 10, 400, 0.5e-3),
        (
            10f64.powf(1.5) * 1e-3,
            15,
            512,
            10f64.powf(1.5) * 1e-3 / 64.0,
        ),
    ] {
        let a = 0.5e-3;
        let map = HeightMap::from_fn(nx, 4, dx, 1e-3, |x, _| {
            a * (std::f64::consts::TAU * (x + 0.5 * dx) / lambda).cos()
        })
        .unwrap();
        let bands = third_octave_spectrum(&map).unwrap();
        let b = bands.iter().find(|b| b.index == m).unwrap();
        let expected = 20.0 * (a / 2f64.sqrt() / 1e-6).log10(); // 50.97 dB
        assert!((b.centre / lambda - 1.0).abs() < 1e-12);
        assert!(
            (b.level_db - expected).abs() < 1e-9,
            "{} vs {expected}",
            b.level_db
        );
        // Nothing leaks into the other bands.
        let others = bands
            .iter()
            .filter(|o| o.index != m)
            .map(|o| o.rms)
            .fold(0.0, f64::max);
        assert!(others < 1e-12 * a, "leak {others:e}");
    }
}

/// Regression (adversarial run, 2026-11-29): `texture synth --rms 1e300`
/// and a roll-off wavelength below the grid (white noise under a
/// self-affine name) were accepted. Both are refused by name; the limits
/// themselves pass.
#[test]
fn a_self_affine_surface_no_grid_or_road_can_hold_is_refused_by_name() {
    let p = SelfAffine {
        nx: 64,
        ny: 64,
        dx: 0.25e-3,
        dy: 0.5e-3,
        rms: 0.8e-3,
        hurst: 0.8,
        lambda_long: 8e-3,
        lambda_short: 1e-3,
        seed: 7,
    };
    let refused = |q: SelfAffine| self_affine(&q).unwrap_err().to_string();
    let e = refused(SelfAffine {
        rms: 1e300,
        ..p.clone()
    });
    assert!(
        e.contains("invalid rms: 1e300") && e.contains("at most 1 m"),
        "{e}"
    );
    let e = refused(SelfAffine {
        lambda_long: 0.9e-3,
        lambda_short: 0.1e-3,
        ..p.clone()
    });
    assert!(
        e.contains("invalid lambda_long: 0.0009") && e.contains("two grid spacings"),
        "{e}"
    );
    assert!(
        self_affine(&SelfAffine {
            rms: 1.0,
            ..p.clone()
        })
        .is_ok()
    );
    // The band's limits pass: λ_short at two spacings of the coarser axis
    // (λ_long, above it, is then above its own limit too).
    assert!(
        self_affine(&SelfAffine {
            lambda_long: 1.5e-3,
            lambda_short: 1e-3,
            ..p
        })
        .is_ok()
    );
}

/// Regression (adversarial run): `lambda_short = "0.01 mm"` on a 0.25 mm
/// grid was accepted though the grid holds no wavelength below 0.5 mm: the
/// cut-off meant nothing. A cut-off below two spacings of the coarser axis
/// is refused by name; at the limit it passes. The road kinds' roughness
/// keeps its material wavelengths on any grid (drawn down to the grid).
#[test]
fn a_short_cutoff_finer_than_the_grid_is_refused() {
    let p = SelfAffine {
        nx: 128,
        ny: 128,
        dx: 0.25e-3,
        dy: 0.25e-3,
        rms: 0.5e-3,
        hurst: 0.8,
        lambda_long: 20e-3,
        lambda_short: 0.01e-3,
        seed: 1,
    };
    let e = self_affine(&p).unwrap_err().to_string();
    assert_eq!(
        e,
        "invalid lambda_short: 1e-5 (must be at least two grid spacings (the coarser), the \
         shortest wavelength the grid holds in every direction)"
    );
    // Just under 2·dx and under 2·dy of an anisotropic grid: refused.
    for q in [
        SelfAffine {
            lambda_short: 0.499e-3,
            ..p.clone()
        },
        SelfAffine {
            dy: 0.3e-3,
            lambda_short: 0.59e-3,
            ..p.clone()
        },
    ] {
        assert!(matches!(
            self_affine(&q),
            Err(tyreroad_texture::TextureError::InvalidParameter {
                name: "lambda_short",
                ..
            })
        ));
    }
    let at_limit = self_affine(&SelfAffine {
        lambda_short: 0.5e-3,
        ..p
    })
    .unwrap();
    assert!((at_limit.rms().unwrap() / 0.5e-3 - 1.0).abs() < 1e-12);
    // The mortar of a pavé on a 1 mm grid keeps its 0.5 mm cut-off.
    let pave = tyreroad_texture::pave(&tyreroad_texture::Pave::new(
        tyreroad_texture::RoadGrid::square(120, 120, 1e-3),
        3,
    ));
    assert!(pave.is_ok());
}

#[test]
fn self_affine_rms_slope_and_reproducibility() {
    let p = SelfAffine {
        nx: 256,
        ny: 256,
        dx: 0.25e-3,
        dy: 0.25e-3,
        rms: 0.8e-3,
        hurst: 0.8,
        lambda_long: 32e-3,
        lambda_short: 1e-3,
        seed: 7,
    };
    let map = self_affine(&p).unwrap();
    assert!((map.rms().unwrap() / p.rms - 1.0).abs() < 1e-12);
    assert_eq!(map, self_affine(&p).unwrap());
    assert_ne!(
        map,
        self_affine(&SelfAffine {
            seed: 8,
            ..p.clone()
        })
        .unwrap()
    );
    // Radially averaged 2-D power spectrum: slope −2(1 + H) in log-log
    // between q_L and q_s (fit over bins 1.5 q_L .. 0.7 q_s).
    let n = p.nx;
    let mut data: Vec<rustfft::num_complex::Complex<f64>> = map
        .heights()
        .iter()
        .map(|&h| rustfft::num_complex::Complex::new(h, 0.0))
        .collect();
    let mut planner = rustfft::FftPlanner::new();
    let f = planner.plan_fft_forward(n);
    f.process(&mut data);
    let mut col = vec![rustfft::num_complex::Complex::new(0.0, 0.0); n];
    for i in 0..n {
        for j in 0..n {
            col[j] = data[j * n + i];
        }
        f.process(&mut col);
        for j in 0..n {
            data[j * n + i] = col[j];
        }
    }
    let tau = std::f64::consts::TAU;
    let l = n as f64 * p.dx;
    let (ql, qs) = (tau / p.lambda_long, tau / p.lambda_short);
    let nb = 24;
    let (lo, hi) = ((1.5 * ql).ln(), (0.7 * qs).ln());
    let mut acc = vec![(0.0, 0usize); nb];
    for j in 0..n {
        for i in 0..n {
            let fi = if i <= n / 2 {
                i as f64
            } else {
                i as f64 - n as f64
            };
            let fj = if j <= n / 2 {
                j as f64
            } else {
                j as f64 - n as f64
            };
            let q = tau * (fi * fi + fj * fj).sqrt() / l;
            if q <= 0.0 {
                continue;
            }
            let b = ((q.ln() - lo) / (hi - lo) * nb as f64).floor();
            if b >= 0.0 && (b as usize) < nb {
                acc[b as usize].0 += data[j * n + i].norm_sqr();
                acc[b as usize].1 += 1;
            }
        }
    }
    let pts: Vec<(f64, f64)> = acc
        .iter()
        .enumerate()
        .filter(|(_, a)| a.1 > 0)
        .map(|(k, a)| {
            (
                lo + (k as f64 + 0.5) * (hi - lo) / nb as f64,
                (a.0 / a.1 as f64).ln(),
            )
        })
        .collect();
    let m = pts.len() as f64;
    let (xm, ym) = (
        pts.iter().map(|p| p.0).sum::<f64>() / m,
        pts.iter().map(|p| p.1).sum::<f64>() / m,
    );
    let slope = pts.iter().map(|p| (p.0 - xm) * (p.1 - ym)).sum::<f64>()
        / pts.iter().map(|p| (p.0 - xm).powi(2)).sum::<f64>();
    let expected = -2.0 * (1.0 + p.hurst);
    eprintln!("spectrum slope {slope:.4} (expected {expected})");
    assert!(
        (slope - expected).abs() < 0.1,
        "slope {slope} vs {expected}"
    );
}

#[test]
fn aggregate_surfaces_are_reproducible_and_plausible() {
    for shape in [
        ChipShape::Ellipsoid,
        ChipShape::Polyhedron {
            cuts: 6,
            rounding: 0.1,
        },
    ] {
        let mut p = Aggregate::new(400, 200, 0.25e-3, 0.25e-3, Aggregate::grading_6_10(), 3);
        p.shape = shape;
        let map = aggregate(&p).unwrap();
        assert_eq!(map, aggregate(&p).unwrap());
        let (lo, hi) = map.min_max().unwrap();
        assert!(lo >= 0.0 && hi < 12.5e-3 * 1.5 * 0.5 * 2.0);
        let mpd = mean_profile_depth(&map, None).unwrap();
        let sq = map.rms().unwrap();
        eprintln!(
            "{shape:?}: Sq = {:.3} mm, MPD = {:.3} mm, max = {:.3} mm",
            sq * 1e3,
            mpd.mpd * 1e3,
            hi * 1e3
        );
        // A 6/10 surface dressing: MPD of order 1–3 mm.
        assert!(mpd.mpd > 0.5e-3 && mpd.mpd < 4e-3, "MPD {}", mpd.mpd);
    }
    let mut bad = Aggregate::new(10, 10, 1e-3, 1e-3, vec![(5e-3, 50.0), (4e-3, 100.0)], 0);
    assert!(aggregate(&bad).is_err());
    bad.grading = Aggregate::grading_4_6();
    bad.embedding = (0.5, 0.2);
    assert!(aggregate(&bad).is_err());
}

#[test]
fn invalid_maps_are_refused() {
    assert!(HeightMap::new(0, 3, 1.0, 1.0, vec![]).is_err());
    assert!(HeightMap::new(2, 2, 1.0, 1.0, vec![0.0; 3]).is_err());
    assert!(HeightMap::new(2, 2, -1.0, 1.0, vec![0.0; 4]).is_err());
    assert!(HeightMap::new(2, 2, 1.0, f64::NAN, vec![0.0; 4]).is_err());
    assert!(HeightMap::new(2, 2, 1.0, 1.0, vec![0.0, f64::NAN, 0.0, 0.0]).is_err());
    assert!(HeightMap::new(usize::MAX, 2, 1.0, 1.0, vec![]).is_err());
    let m = HeightMap::from_nan_heights(2, 2, 1.0, 1.0, vec![0.0, f64::NAN, 2.0, 0.0]).unwrap();
    assert_eq!(m.valid_count(), 3);
    let f = m.filled().unwrap();
    assert_eq!(f.get(1, 0), Some(0.0));
}
