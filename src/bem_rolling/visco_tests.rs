//! The viscoelastic rolling BEM against the elastic rolling BEM: its two
//! limits (slow: `E∞`; fast: `E∞ + Σ E_k`), and the sign of its hysteresis
//! (the pressure centroid moves ahead of the elastic one).

use super::*;
use crate::bem::{Sphere, spherical_caps};
use crate::rolling::Tread;
use crate::viscoelastic::{Branch, Prony};

const DX: f64 = 2e-4;
const NU: f64 = 0.5;
const E_INF: f64 = 2e6;
const E_GLASSY: f64 = 10e6;

/// The test tread of docs/viscoelastic.md: 2 MPa, 3 MPa at 1 ms, 5 MPa at
/// 20 µs.
fn tread() -> Prony {
    Prony::new(
        E_INF,
        vec![
            Branch {
                modulus: 3e6,
                relaxation_time: 1e-3,
            },
            Branch {
                modulus: 5e6,
                relaxation_time: 2e-5,
            },
        ],
        NU,
    )
    .expect("valid tread")
}

fn elastic(e: f64) -> Material {
    Material::new(e, NU).expect("valid material")
}

fn options() -> BemRollingOptions {
    BemRollingOptions {
        tolerance: 1e-9,
        par: Par::Seq,
        ..BemRollingOptions::default()
    }
}

/// Spheres (R = 5 mm) along x at 6 mm pitch, summits alternating 0 and
/// −30 µm, on a 34 × 4.8 mm road.
fn sphere_road() -> Field {
    let grid = Grid::new(171, 25, DX, DX)
        .and_then(|g| g.with_origin([0.0, -2.4e-3]))
        .expect("valid grid");
    let spheres: Vec<Sphere> = (0..6)
        .map(|k| Sphere {
            centre: [3e-3 + 6e-3 * k as f64, 0.0],
            radius: 5e-3,
            summit: if k % 2 == 0 { 0.0 } else { -3e-5 },
        })
        .collect();
    spherical_caps(&grid, &spheres, -5e-3).expect("valid spheres")
}

/// A nearly flat tyre, 20 × 4 mm, 8 steps of two cells under approach
/// control, and a sensor around the sphere at 15 mm.
fn sphere_config(speed: f64) -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 1.0,
        radius_y: 1.0,
        length: 20e-3,
        width: 4e-3,
    };
    let mut c = RollingConfig::new(
        tyre,
        [15e-3, 15e-3 + 7.0 * 2.0 * DX, 2.0 * DX],
        speed,
        RollingControl::Approach(8e-5),
    );
    c.sensors = vec![Sensor {
        name: "sphere at 15 mm".into(),
        x: [12e-3, 18e-3],
        y: [-2.4e-3, 2.4e-3],
    }];
    c
}

/// Per step, total force and sensor force within `tolerance` of the
/// elastic run's force.
fn assert_matches(visco: &BemRollingResult, elastic: &BemRollingResult, tolerance: f64) {
    assert_eq!(visco.failed(), 0);
    assert_eq!(visco.steps.len(), elastic.steps.len());
    for (v, e) in visco.steps.iter().zip(&elastic.steps) {
        assert!(e.total_force > 0.1, "step {}: no contact", e.index);
        let error = (v.total_force - e.total_force).abs() / e.total_force;
        assert!(error < tolerance, "step {}: force {error}", e.index);
        let error = (v.sensor_forces[0] - e.sensor_forces[0]).abs() / e.total_force;
        assert!(error < tolerance, "step {}: sensor {error}", e.index);
    }
}

#[test]
fn slow_rolling_is_the_elastic_run_with_the_long_term_modulus() {
    // Δt = 40 s against τ ≤ 1 ms: every branch has relaxed.
    let config = sphere_config(1e-5);
    let visco = roll_visco_bem(&sphere_road(), &tread(), &config, &options()).expect("visco");
    let soft = roll_bem(&sphere_road(), elastic(E_INF), &config, &options()).expect("E∞");
    let stiff = roll_bem(&sphere_road(), elastic(E_GLASSY), &config, &options()).expect("E0");
    // The limits are far apart, so the 0.5 % check can fail.
    assert!(stiff.steps[0].total_force > 2.0 * soft.steps[0].total_force);
    assert_matches(&visco, &soft, 0.005);
}

#[test]
fn fast_rolling_is_the_elastic_run_with_the_instantaneous_modulus() {
    // Δt = 4 ns against τ ≥ 20 µs: nothing relaxes.
    let config = sphere_config(1e5);
    let visco = roll_visco_bem(&sphere_road(), &tread(), &config, &options()).expect("visco");
    let stiff = roll_bem(&sphere_road(), elastic(E_GLASSY), &config, &options()).expect("E0");
    assert_matches(&visco, &stiff, 0.005);
}

/// A curved tyre (50 mm radii) rolled under 5 N over a flat road, with one
/// sensor per road column so the pressure centroid is exact.
fn flat_config(speed: f64) -> (Field, RollingConfig) {
    let (nx, ny) = (181, 61);
    let grid = Grid::new(nx, ny, DX, DX)
        .and_then(|g| g.with_origin([0.0, -6e-3]))
        .expect("valid grid");
    let road = Field::new(grid.clone(), vec![0.0; nx * ny]).expect("flat road");
    let tyre = Tread::Tyre {
        radius_x: 0.05,
        radius_y: 0.05,
        length: 16e-3,
        width: 12e-3,
    };
    let mut c = RollingConfig::new(
        tyre,
        [10e-3, 10e-3 + 39.0 * 2.0 * DX, 2.0 * DX],
        speed,
        RollingControl::Load(5.0),
    );
    c.sensors = (0..nx)
        .map(|i| Sensor {
            name: format!("column {i}"),
            x: [grid.x(i) - 0.5 * DX, grid.x(i) + 0.5 * DX],
            y: [-6e-3, 6e-3],
        })
        .collect();
    (road, c)
}

/// Mean offset (m) of the pressure centroid ahead of the footprint centre
/// over the last 10 steps.
pub(super) fn centroid_offset(result: &BemRollingResult, road: &Grid) -> f64 {
    let last = &result.steps[result.steps.len() - 10..];
    last.iter()
        .map(|s| {
            let moment: f64 = (0..road.nx()).map(|i| s.sensor_forces[i] * road.x(i)).sum();
            moment / s.total_force - s.position
        })
        .sum::<f64>()
        / last.len() as f64
}

#[test]
fn rolling_at_an_intermediate_speed_moves_the_pressure_ahead() {
    // V τ_1 = 3 mm, the contact's half-length: the most hysteresis.
    let (road, config) = flat_config(3.0);
    let visco = roll_visco_bem(&road, &tread(), &config, &options()).expect("visco");
    let soft = roll_bem(&road, elastic(E_INF), &config, &options()).expect("E∞");
    assert_eq!(visco.failed(), 0);
    let (v, e) = (
        centroid_offset(&visco, road.grid()),
        centroid_offset(&soft, road.grid()),
    );
    // The elastic centroid is on the footprint centre by symmetry.
    assert!(e.abs() < 1e-6, "elastic offset {e}");
    // Measured: 0.74 mm ahead, a fifth of the contact radius (3.3 mm),
    // steady from about step 30 (docs/viscoelastic.md).
    assert!(v > 0.5e-3, "viscoelastic offset {v}");
    // Stiffer than the relaxed rubber, softer than the glassy one.
    let stiff = roll_bem(&road, elastic(E_GLASSY), &config, &options()).expect("E0");
    let k = visco.steps.len() - 1;
    let (a, soft_a, stiff_a) = (
        visco.steps[k].approach,
        soft.steps[k].approach,
        stiff.steps[k].approach,
    );
    assert!(a < soft_a && a > stiff_a, "{stiff_a} < {a} < {soft_a}");
}

#[test]
fn a_step_that_is_not_a_whole_number_of_cells_is_refused() {
    let mut config = sphere_config(1.0);
    config.step = 1.5 * DX;
    let error = roll_visco_bem(&sphere_road(), &tread(), &config, &options())
        .expect_err("1.5 cells refused");
    assert!(
        error.to_string().contains("whole number of cells"),
        "{error}"
    );
}
