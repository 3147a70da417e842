//! What the solver returns when Newton cannot meet the tolerance: the
//! rounding floor, the stagnated status and the recoveries.
#![allow(clippy::unwrap_used)]

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::*;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// 400 balls at 1.5 mm pitch, heights over 0.3 mm, radii 0.5–2.5 mm (the
/// dense layout of tests/solver.rs).
fn dense_layout() -> Problem<PotentialLaw<Sphere>> {
    let mut seed = 42;
    layouts::dense_sphere_grid(rubber(), || lcg(&mut seed)).unwrap()
}

#[test]
fn a_tolerance_below_double_precision_is_met_up_to_the_rounding_floor() {
    // 1e-17 of the load is below what the residuals can be computed to
    // (each R_i = P_i − P^law(δ0 − H_i − u_i) carries k_i ε (|δ0| + |H_i| +
    // |u_i|)): Newton stalls there, and used to fail with NotConverged.
    let problem = dense_layout();
    let load = 400.0;
    let options = SolverOptions {
        tolerance: 1e-17,
        ..SolverOptions::default()
    };
    let s = solve(&problem, Control::Load(load), &options).unwrap();
    assert_eq!(s.convergence, Convergence::Converged);
    assert_ne!(s.recovery, Recovery::None);
    assert!(
        (s.total_force() - load).abs() <= 1e-12 * load,
        "{}",
        s.total_force()
    );
    assert!(
        s.residual.is_finite() && s.residual <= 1e-14,
        "{}",
        s.residual
    );
}

/// The layout whose load path folds before 100 N
/// (`layouts::folding_field`, drawn from seed 1).
fn folding_layout() -> Problem<PotentialLaw<Sphere>> {
    let mut seed = 1;
    layouts::folding_field(rubber(), || lcg(&mut seed)).unwrap()
}

#[test]
fn a_folding_load_path_without_clusters_still_fails_with_its_residual() {
    let problem = folding_layout();
    let point_only = SolverOptions {
        clusters: Clusters::Off,
        ..SolverOptions::default()
    };
    match solve(&problem, Control::Load(100.0), &point_only) {
        Err(SolveError::NotConverged { residual, .. }) => {
            assert!(residual.is_finite() && residual > 1e-8, "{residual}");
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
    // Short of the fold the same layout converges.
    let s = solve(&problem, Control::Load(50.0), &SolverOptions::default()).unwrap();
    assert_eq!(s.convergence, Convergence::Converged);
    assert!((s.total_force() - 50.0).abs() <= 1e-11 * 50.0);
}

#[test]
fn a_bad_acceptable_tolerance_is_refused() {
    let problem = folding_layout();
    for bad in [0.0, -1.0, f64::NAN, f64::INFINITY] {
        let options = SolverOptions {
            acceptable_tolerance: bad,
            ..SolverOptions::default()
        };
        assert!(matches!(
            solve(&problem, Control::Load(1.0), &options),
            Err(SolveError::InvalidInput(_))
        ));
    }
}
