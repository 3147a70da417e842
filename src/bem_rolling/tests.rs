//! The BEM rolling reference against independent references: the
//! multipoint model on widely spaced spheres (Hertz laws, where point
//! coupling is exact to about 1 %), a static BEM solve of one step built
//! independently, a cold start, load balance and sensor conservation.

use super::*;
use crate::bem::{Sphere, spherical_caps};
use crate::contact_law::HertzLaw;
use crate::multipoint::AsperitySet;
use crate::rolling::{Road, RunOptions, Tread, roll};

const E: f64 = 6.54e6;
const NU: f64 = 0.5;
const R: f64 = 5e-3;
/// Cell size: a Hertz contact of ~1.3 mm radius spans ~13 cells.
const DX: f64 = 1e-4;

fn material() -> Material {
    Material::new(E, NU).expect("valid material")
}

/// Summits of a row of spheres along x at 9 mm pitch, y = 0, heights
/// alternating 0 and −0.1 mm (so forces differ from sphere to sphere).
fn summits() -> Vec<([f64; 2], f64)> {
    (0..8)
        .map(|k| {
            (
                [4e-3 + 9e-3 * k as f64, 0.0],
                if k % 2 == 0 { 0.0 } else { -1e-4 },
            )
        })
        .collect()
}

/// The spheres' height map on a 76 × 8 mm road (cells on the summits).
fn road_map() -> Field {
    let grid = Grid::new(761, 81, DX, DX)
        .and_then(|g| g.with_origin([0.0, -4e-3]))
        .expect("valid grid");
    let spheres: Vec<Sphere> = summits()
        .iter()
        .map(|&(centre, summit)| Sphere {
            centre,
            radius: R,
            summit,
        })
        .collect();
    spherical_caps(&grid, &spheres, -R).expect("valid spheres")
}

/// A nearly flat tyre (1 m radii) over a 50 × 6 mm footprint: the profile
/// at the footprint's ends (0.31 mm) exceeds the approach, so the
/// multipoint selection is exact and both models see the same spheres. (A strongly curved tread, say 0.05 m, adds
/// its curvature to each sphere's and moves the patch off the summit
/// towards the footprint centre, which the multipoint law does not see: 3 %
/// on the approach at 0.05 m; 0.5 % at most here.)
fn config(steps: usize, control: RollingControl) -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 1.0,
        radius_y: 1.0,
        length: 50e-3,
        width: 6e-3,
    };
    let start = 30e-3;
    let mut c = RollingConfig::new(
        tyre,
        [start, start + (steps - 1) as f64 * 1e-3, 1e-3],
        10.0,
        control,
    );
    c.sensors = vec![
        Sensor {
            name: "one sphere".into(),
            x: [17.5e-3, 26.5e-3],
            y: [-3e-3, 3e-3],
        },
        Sensor {
            name: "half".into(),
            x: [0.0, 31e-3],
            y: [-4e-3, 0.0],
        },
    ];
    c
}

fn options() -> BemRollingOptions {
    BemRollingOptions {
        tolerance: 1e-9,
        par: Par::Seq,
        ..BemRollingOptions::default()
    }
}

#[test]
fn rolling_bem_matches_the_multipoint_model_on_widely_spaced_spheres() {
    let steps = 12;
    let config = config(steps, RollingControl::Load(3.0));
    let bem = roll_bem(&road_map(), material(), &config, &options()).expect("BEM run");
    let (positions, heights): (Vec<_>, Vec<_>) = summits().into_iter().unzip();
    let law = HertzLaw::new(R, material()).expect("Hertz law");
    let set = AsperitySet::new(positions.clone(), heights, vec![law; positions.len()])
        .expect("valid set");
    let model =
        roll(&Road::new(set), material(), &config, &RunOptions::default()).expect("multipoint run");
    assert_eq!(bem.failed(), 0);
    for (m, b) in model.steps.iter().zip(&bem.steps) {
        // Load control: both carry the load exactly.
        assert!(
            (b.total_force - 3.0).abs() < 1e-9 * 3.0,
            "{}",
            b.total_force
        );
        // Hertz on 11-cell contacts, true spheres against paraboloids, a
        // 1 m tread's curvature ignored by the laws: measured 0.13 %.
        let approach_error = (m.approach - b.approach).abs() / b.approach.abs();
        assert!(approach_error < 0.005, "step {}: {approach_error}", m.index);
        // A sensor around one sphere, and one cutting another in four:
        // measured within 0.22 % of the load.
        for k in 0..2 {
            let diff = (m.sensor_forces[k] - b.sensor_forces[k]).abs();
            assert!(diff < 0.005 * 3.0, "step {} sensor {k}: {diff} N", m.index);
        }
    }
    // The comparison says the same: per-step errors as measured above,
    // relative to the mean approach and to each sensor's peak.
    let c = compare(&model, &positions, &config.sensors, &bem, 1.0, Some(8)).expect("compare");
    assert_eq!(c.steps, steps);
    assert!(c.total.max_error < 1e-9 && c.total.bands.is_empty());
    assert!(c.approach.max_error < 0.005, "{}", c.approach.max_error);
    assert!(
        c.sensors.iter().all(|s| s.max_error < 0.01),
        "{:?}",
        c.sensors
    );
    // The sphere under the first sensor is unloaded as the tyre moves on.
    let s0 = bem.sensor(0);
    assert!(s0[0] > 2.0 * s0[steps - 1], "{s0:?}");
}

#[test]
fn one_step_equals_a_static_bem_solve_of_the_tread_on_the_road() {
    let config = config(1, RollingControl::Approach(4e-4));
    let road = road_map();
    let bem = roll_bem(&road, material(), &config, &options()).expect("BEM run");
    // The same contact built directly: the window of the footprint (50 × 6
    // mm around x = 30 mm: 501 × 61 cells), the road minus the tyre.
    let window = Grid::new(501, 61, DX, DX)
        .and_then(|g| g.with_origin([5e-3, -3e-3]))
        .expect("valid grid");
    let spheres: Vec<Sphere> = summits()
        .iter()
        .map(|&(centre, summit)| Sphere {
            centre,
            radius: R,
            summit,
        })
        .collect();
    let caps = spherical_caps(&window, &spheres, -R).expect("caps");
    let heights: Vec<f64> = (0..window.len())
        .map(|k| {
            let (i, j) = window.cell(k);
            let (x, y) = (window.x(i) - 30e-3, window.y(j));
            caps.values()[k] - (x * x + y * y) / (2.0 * 1.0)
        })
        .collect();
    let surface = Field::new(window.clone(), heights).expect("surface");
    let mut solver = Solver::new(
        &window,
        &material(),
        &BemOptions {
            tolerance: 1e-9,
            par: Par::Seq,
            ..BemOptions::default()
        },
    )
    .expect("solver");
    // δ0 is below the road's highest point (0); the BEM's approach is
    // measured from the window's highest effective point.
    let z_ref = surface.max();
    let direct = solver
        .solve(&surface, Control::Approach(4e-4 + z_ref))
        .expect("static solve");
    let step = &bem.steps[0];
    assert!(direct.force > 0.1);
    assert!((step.total_force - direct.force).abs() < 1e-6 * direct.force);
    assert!((step.approach - 4e-4).abs() < 1e-15);
    assert!((step.contact_area - direct.contact_area).abs() <= DX * DX);
}

#[test]
fn a_warm_started_step_equals_a_cold_started_one() {
    let road = road_map();
    let run = roll_bem(
        &road,
        material(),
        &config(8, RollingControl::Load(3.0)),
        &options(),
    )
    .expect("run");
    let mut single = config(1, RollingControl::Load(3.0));
    single.start = run.steps[7].position;
    single.end = single.start;
    let cold = roll_bem(&road, material(), &single, &options()).expect("cold");
    let (w, c) = (&run.steps[7], &cold.steps[0]);
    assert!((w.approach - c.approach).abs() < 1e-6 * c.approach.abs());
    for (a, b) in w.sensor_forces.iter().zip(&c.sensor_forces) {
        assert!((a - b).abs() < 1e-6 * 3.0, "{a} vs {b}");
    }
}

#[test]
fn sensors_tiling_the_footprint_sum_to_the_total_force() {
    let mut config = config(5, RollingControl::Load(3.0));
    // A 3 × 2 tiling of the whole road with edges that cut cells.
    let xs = [-1e-3, 31.05e-3, 40.333e-3, 80e-3];
    let ys = [-5e-3, 0.017e-3, 5e-3];
    config.sensors = (0..3)
        .flat_map(|i| {
            (0..2).map(move |j| Sensor {
                name: format!("{i}{j}"),
                x: [xs[i], xs[i + 1]],
                y: [ys[j], ys[j + 1]],
            })
        })
        .collect();
    let run = roll_bem(&road_map(), material(), &config, &options()).expect("run");
    for s in &run.steps {
        let sum: f64 = s.sensor_forces.iter().sum();
        assert!((sum - s.total_force).abs() < 1e-12 * s.total_force, "{sum}");
        // The cut sensors do share the load.
        assert!(s.sensor_forces.iter().filter(|&&f| f > 1e-3).count() >= 2);
    }
}

#[test]
fn the_pressure_moves_with_the_window() {
    let from = Window {
        i0: 10,
        j0: 5,
        nx: 3,
        ny: 2,
    };
    let to = Window { i0: 11, ..from };
    let p = [1.0, 2.0, 3.0, 4.0, 5.0, 6.0];
    assert_eq!(
        shift_pressure(&p, from, to),
        vec![2.0, 3.0, 0.0, 5.0, 6.0, 0.0]
    );
}

#[test]
fn a_footprint_leaving_the_map_is_a_named_error() {
    let mut config = config(3, RollingControl::Load(3.0));
    config.end = 0.2;
    let err = roll_bem(&road_map(), material(), &config, &options()).expect_err("off the map");
    assert!(
        matches!(err, BemRollingError::OffMap { axis: "x", .. }),
        "{err}"
    );
}

/// The tread's slope across the spheres: the path runs 50 mm to the side
/// of the row (a 110 mm wide, nearly flat tyre, 1 m radii), so each sphere
/// sees a slope `σ = 0.05` across. The first point of contact then lies
/// `η R/(R + Ry) = 0.25 mm` off the summit towards the path, where the gap
/// is smaller by `½ σ² R Ry/(R + Ry) = 6.2 µm` (`Tread::contact_gap`). The
/// BEM sees the real surface; the multipoint road with summit radii must
/// follow it, the road without (gaps at the summits) misses it.
#[test]
fn contact_point_gaps_follow_the_bem_under_a_sloping_tread() {
    let steps = 6;
    let mut config = config(steps, RollingControl::Load(3.0));
    config.tread = Tread::Tyre {
        radius_x: 1.0,
        radius_y: 1.0,
        length: 50e-3,
        width: 110e-3,
    };
    config.lateral = 50e-3;
    let bem = roll_bem(&road_map(), material(), &config, &options()).expect("BEM run");
    let (positions, heights): (Vec<_>, Vec<_>) = summits().into_iter().unzip();
    let law = HertzLaw::new(R, material()).expect("Hertz law");
    let set = AsperitySet::new(positions.clone(), heights, vec![law; positions.len()])
        .expect("valid set");
    let summit_road = Road::new(set);
    let radii = vec![R; summit_road.len()];
    let contact_road = summit_road.clone().with_summit_radii(radii).expect("radii");
    let run = |road: &Road<HertzLaw>| roll(road, material(), &config, &RunOptions::default());
    let (old, new) = (
        run(&summit_road).expect("old"),
        run(&contact_road).expect("new"),
    );
    assert_eq!(bem.failed(), 0);
    let mut worst = [[0.0f64; 2]; 2];
    for ((o, n), b) in old.steps.iter().zip(&new.steps).zip(&bem.steps) {
        for (w, m) in worst.iter_mut().zip([o, n]) {
            w[0] = w[0].max((m.approach - b.approach).abs());
            w[1] = w[1].max((m.sensor_forces[1] - b.sensor_forces[1]).abs() / 3.0);
        }
    }
    let [[old_gap, old_sensor], [new_gap, new_sensor]] = worst;
    // Measured: approach off by 5.9 µm at the summits (the predicted
    // 6.2 µm), 0.47 µm at the contact points; the half sensor (its edge
    // along the row, cutting each patch) off by 12.2 % and 0.22 % of the
    // load.
    assert!(old_gap > 4e-6, "summit gaps: {old_gap}");
    assert!(new_gap < 1e-6, "contact-point gaps: {new_gap}");
    assert!(old_sensor > 0.05, "summit gaps: {old_sensor}");
    assert!(new_sensor < 0.005, "contact-point gaps: {new_sensor}");
}
