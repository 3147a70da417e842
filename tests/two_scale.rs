//! Two-scale local pressures (src/two_scale.rs): Hertz for one ball, force
//! balance of the assembled map, symmetry, agreement with the multipoint
//! solution it starts from, bad input.

use std::sync::Arc;

use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Control, Par, Problem, SolverOptions, solve};
use tyreroad::two_scale::{
    LocalShape, TwoScaleError, TwoScaleOptions, two_scale, two_scale_solution,
};

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn rubber() -> Result<Material, Box<dyn std::error::Error>> {
    Ok(Material::new(6.54e6, 0.5)?)
}

fn hertz_radius(p: f64, r: f64, m: &Material) -> f64 {
    (3.0 * p * r / (4.0 * m.reduced_modulus())).cbrt()
}

#[test]
fn one_paraboloid_gives_hertz_radius_and_balanced_map() -> TestResult {
    let m = rubber()?;
    let (p, r) = (20.0, 5e-3);
    let shape = LocalShape::Paraboloid {
        radius_x: r,
        radius_y: r,
    };
    let ts = two_scale(
        &[[0.003, -0.002]],
        &[p],
        &[shape],
        &m,
        &TwoScaleOptions::default(),
    )?;
    let l = &ts.local[0];
    let a = hertz_radius(p, r, &m);
    let p0 = 3.0 * p / (2.0 * std::f64::consts::PI * a * a);
    let map = ts.map.as_ref().ok_or("no map")?;
    println!(
        "paraboloid R = 5 mm, P = 20 N: a = {:.5} mm vs Hertz {:.5} mm ({:+.3} %), semi-axes {:+.3} % / {:+.3} %, \
         p_max {:+.3} %, approach {:+.4} % vs a²/R, map Σ = {:.12} N ({} × {} cells), {} iterations",
        l.radius * 1e3,
        a * 1e3,
        (l.radius / a - 1.0) * 100.0,
        (l.semi_axes[0] / a - 1.0) * 100.0,
        (l.semi_axes[1] / a - 1.0) * 100.0,
        (l.max_pressure / p0 - 1.0) * 100.0,
        (l.approach / (a * a / r) - 1.0) * 100.0,
        map.integral(),
        map.grid().nx(),
        map.grid().ny(),
        l.iterations
    );
    assert!((l.radius / a - 1.0).abs() < 0.01);
    assert!((l.semi_axes[0] / a - 1.0).abs() < 0.01);
    assert!((l.max_pressure / p0 - 1.0).abs() < 0.01);
    assert!((l.approach / (a * a / r) - 1.0).abs() < 0.002);
    assert!((l.force - p).abs() < 1e-9 * p);
    assert!((map.integral() - p).abs() < 0.005 * p);
    assert!((map.integral() - p).abs() < 1e-9 * p, "conservative remap");
    // The local field is centred on the summit.
    let field = l.field.as_ref().ok_or("no field")?;
    let g = field.grid();
    assert!((g.x(g.nx() / 2) - 0.003).abs() < 1e-12);
    assert!((g.y(g.ny() / 2) + 0.002).abs() < 1e-12);
    Ok(())
}

#[test]
fn one_true_sphere_at_small_load_gives_hertz_radius() -> TestResult {
    let m = rubber()?;
    let r = 5e-3;
    for p in [0.2, 1.0] {
        let ts = two_scale(
            &[[0.0, 0.0]],
            &[p],
            &[LocalShape::Sphere { radius: r }],
            &m,
            &TwoScaleOptions::default(),
        )?;
        let a = hertz_radius(p, r, &m);
        let l = &ts.local[0];
        println!(
            "true sphere R = 5 mm, P = {p} N (a/R = {:.3}): a = {:.5} mm vs Hertz {:.5} mm ({:+.3} %)",
            a / r,
            l.radius * 1e3,
            a * 1e3,
            (l.radius / a - 1.0) * 100.0
        );
        assert!((l.radius / a - 1.0).abs() < 0.01);
        let map = ts.map.as_ref().ok_or("no map")?;
        assert!((map.integral() - p).abs() < 0.005 * p);
    }
    Ok(())
}

#[test]
fn symmetric_layout_gives_symmetric_radii_and_balanced_map() -> TestResult {
    let m = rubber()?;
    let ball = PotentialLaw::sphere(Sphere::new(5e-3)?, m);
    let mut positions = Vec::new();
    for j in -1..=1 {
        for i in -1..=1 {
            positions.push([f64::from(i) * 0.01, f64::from(j) * 0.01]);
        }
    }
    let problem = Problem::new(positions.clone(), vec![0.0; 9], vec![ball; 9], m)?;
    let solution = solve(&problem, Control::Load(150.0), &SolverOptions::default())?;
    let shapes = [LocalShape::Sphere { radius: 5e-3 }];
    let ts = two_scale_solution(&problem, &solution, &shapes, &TwoScaleOptions::default())?;
    let radius_at = |x: f64, y: f64| {
        positions
            .iter()
            .position(|p| (p[0] - x).abs() < 1e-12 && (p[1] - y).abs() < 1e-12)
            .map(|k| ts.local[k].radius)
    };
    let mut worst = 0.0f64;
    for (k, p) in positions.iter().enumerate() {
        let a = ts.local[k].radius;
        for (x, y) in [(-p[0], p[1]), (p[0], -p[1]), (p[1], p[0]), (-p[1], -p[0])] {
            let b = radius_at(x, y).ok_or("mirror not found")?;
            worst = worst.max((a - b).abs() / a);
        }
    }
    let map = ts.map.as_ref().ok_or("no map")?;
    println!(
        "3 × 3 balls at 150 N: radii corner/edge/centre {:.4}/{:.4}/{:.4} mm, max mirror asymmetry {worst:.1e}, \
         map Σ − W = {:.1e} N",
        ts.local[0].radius * 1e3,
        ts.local[1].radius * 1e3,
        ts.local[4].radius * 1e3,
        map.integral() - 150.0
    );
    assert!(worst < 1e-9, "asymmetry {worst}");
    assert!((map.integral() - 150.0).abs() < 0.005 * 150.0);
    assert!((map.integral() - 150.0).abs() < 1e-9 * 150.0);
    // Corner balls carry the most (elastic coupling), hence the largest radii.
    assert!(ts.local[0].radius > ts.local[1].radius);
    assert!(ts.local[1].radius > ts.local[4].radius);
    Ok(())
}

#[test]
fn serial_and_parallel_agree_and_custom_shape_matches_sphere() -> TestResult {
    let m = rubber()?;
    let positions = [[0.0, 0.0], [0.012, 0.0], [0.0, 0.015]];
    let forces = [10.0, 0.0, 25.0];
    let shapes = [LocalShape::Sphere { radius: 5e-3 }];
    let par = two_scale(
        &positions,
        &forces,
        &shapes,
        &m,
        &TwoScaleOptions::default(),
    )?;
    let serial_options = TwoScaleOptions {
        par: Par::Seq,
        ..TwoScaleOptions::default()
    };
    let ser = two_scale(&positions, &forces, &shapes, &m, &serial_options)?;
    assert_eq!(par, ser);
    // A pool of another size than the current one gives the same fields.
    let two_threads = TwoScaleOptions {
        par: Par::rayon(2),
        ..TwoScaleOptions::default()
    };
    let pool = two_scale(&positions, &forces, &shapes, &m, &two_threads)?;
    assert_eq!(par, pool);
    // Out of contact: no field, zero radius.
    assert!(par.local[1].field.is_none());
    assert_eq!(par.local[1].radius, 0.0);
    let custom = [LocalShape::Custom {
        height: Arc::new(|x: f64, y: f64| {
            let (r2, rr) = (x * x + y * y, 25e-6);
            if r2 < rr {
                (rr - r2).sqrt() - 5e-3
            } else {
                -5e-3
            }
        }),
        equivalent_radius: 5e-3,
    }];
    let cus = two_scale(
        &positions,
        &forces,
        &custom,
        &m,
        &TwoScaleOptions::default(),
    )?;
    for (a, b) in par.local.iter().zip(&cus.local) {
        assert!((a.radius - b.radius).abs() <= 1e-12 * a.radius.max(1e-3));
    }
    Ok(())
}

#[test]
fn bad_input_is_refused() -> TestResult {
    let m = rubber()?;
    let s = [LocalShape::Sphere { radius: 5e-3 }];
    let o = TwoScaleOptions::default();
    let invalid = |r: Result<_, TwoScaleError>| matches!(r, Err(TwoScaleError::InvalidInput(_)));
    assert!(invalid(two_scale(&[[0.0, 0.0]], &[1.0, 2.0], &s, &m, &o)));
    assert!(invalid(two_scale(&[[0.0, 0.0]], &[-1.0], &s, &m, &o)));
    assert!(invalid(two_scale(&[[f64::NAN, 0.0]], &[1.0], &s, &m, &o)));
    assert!(invalid(two_scale(
        &[[0.0, 0.0]],
        &[1.0],
        &[LocalShape::Sphere { radius: 0.0 }],
        &m,
        &o
    )));
    let tiny_map = TwoScaleOptions {
        map_cell: Some(1e-9),
        ..TwoScaleOptions::default()
    };
    assert!(matches!(
        two_scale(&[[0.0, 0.0]], &[1.0], &s, &m, &tiny_map),
        Err(TwoScaleError::MapTooLarge { .. })
    ));
    // No force anywhere: no map.
    let none = two_scale(&[[0.0, 0.0]], &[0.0], &s, &m, &o)?;
    assert!(none.map.is_none());
    Ok(())
}

#[test]
fn a_blunt_asperity_is_clipped_and_recorded_not_fatal() -> TestResult {
    use tyreroad::two_scale::LocalStatus;
    let m = rubber()?;
    // A near-flat cone (1 nm drop per metre) whose summit curvature claims
    // R = 0.1 mm: the contact spreads wider than any local grid.
    let flat = LocalShape::Custom {
        height: Arc::new(|dx: f64, dy: f64| -1e-9 * dx.hypot(dy)),
        equivalent_radius: 1e-4,
    };
    let ball = LocalShape::Paraboloid {
        radius_x: 5e-3,
        radius_y: 5e-3,
    };
    // 16 cells across the expected contact instead of 64: the widenings
    // are the same, each local grid 16 times smaller (this test took 20 s
    // of CI's time at the default).
    let options = TwoScaleOptions {
        cells_across: 16,
        ..TwoScaleOptions::default()
    };
    let ts = two_scale(
        &[[0.0, 0.0], [0.05, 0.0]],
        &[30.0, 10.0],
        &[flat, ball],
        &m,
        &options,
    )?;
    assert!(
        matches!(ts.local[0].status, LocalStatus::ClippedAtEdge { half_width } if half_width > 70.0),
        "{:?}",
        ts.local[0].status
    );
    assert_eq!(ts.local[1].status, LocalStatus::Complete);
    assert_eq!(ts.fallbacks().count(), 1);
    // The clipped field still carries its force exactly; the map balances.
    assert!((ts.local[0].force - 30.0).abs() < 1e-9 * 30.0);
    let map = ts.map.as_ref().ok_or("no map")?;
    assert!((map.integral() - 40.0).abs() < 1e-9 * 40.0);
    Ok(())
}

#[test]
fn a_failed_local_solve_falls_back_to_hertz_with_its_reason() -> TestResult {
    use tyreroad::two_scale::LocalStatus;
    let m = rubber()?;
    let mut options = TwoScaleOptions::default();
    // One conjugate-gradient iteration cannot converge: every local BEM
    // solve fails, and each asperity gets Hertz's field instead.
    options.bem.max_iterations = 1;
    let (p, r) = (20.0, 5e-3);
    let ts = two_scale(
        &[[0.0, 0.0]],
        &[p],
        &[LocalShape::Paraboloid {
            radius_x: r,
            radius_y: r,
        }],
        &m,
        &options,
    )?;
    let local = &ts.local[0];
    let LocalStatus::HertzFallback { reason } = &local.status else {
        panic!("expected a fallback, got {:?}", local.status);
    };
    assert!(!reason.is_empty());
    let a = hertz_radius(p, r, &m);
    assert!((local.force - p).abs() < 1e-12 * p);
    assert!((local.radius - a).abs() < 1e-12 * a);
    // The discrete Hertz field's area is πa² to the grid's resolution.
    let area = std::f64::consts::PI * a * a;
    assert!(
        (local.contact_area - area).abs() < 0.05 * area,
        "{} vs {area}",
        local.contact_area
    );
    Ok(())
}

#[test]
fn a_spike_pressed_to_the_floor_stops_widening_at_its_first_grid() -> TestResult {
    use tyreroad::two_scale::LocalStatus;
    let m = rubber()?;
    // A sharp cone 0.3 mm high on 0.25 mm, on a flat floor: at 5 N the
    // tread sinks onto the floor (the cone alone carries ~0.1 N at full
    // depth) and the contact on the floor reaches every grid's edge.
    // Widening used to run all nine grids (minutes); the floor stops it.
    let (height, base) = (3e-4, 2.5e-4);
    let spike = LocalShape::Custom {
        height: Arc::new(move |dx: f64, dy: f64| -(height * dx.hypot(dy) / base).min(height)),
        equivalent_radius: 1e-4,
    };
    let p = 5.0;
    let options = TwoScaleOptions::default();
    let ts = two_scale(&[[0.0, 0.0]], &[p], &[spike], &m, &options)?;
    let local = &ts.local[0];
    let LocalStatus::PressedToFloor { depth } = local.status else {
        panic!("expected the floor, got {:?}", local.status);
    };
    assert!((depth - height).abs() < 1e-9 * height, "{depth}");
    // The first grid: 2·⌈half_width · cells_across / 2⌉ + 1 cells.
    let field = local.field.as_ref().ok_or("no field")?;
    let first = 2 * (options.half_width * options.cells_across as f64 / 2.0).ceil() as usize + 1;
    assert_eq!(field.grid().nx(), first);
    assert!((local.force - p).abs() < 1e-9 * p);
    // The tread is on the floor: approach past the spike's height.
    assert!(local.approach > height, "{}", local.approach);
    assert_eq!(ts.fallbacks().count(), 1);
    Ok(())
}
