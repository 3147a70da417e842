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

/// A tolerance measures each force residual against the total load: on a
/// road of 200 asperities, 3e-2 let the uncoupled start (every force nil
/// at the final state) pass for converged, 0 N for a 500 N load. It is
/// refused past `MAX_TOLERANCE`, and at that bound the load is carried.
#[test]
fn a_tolerance_loose_enough_to_pass_a_nil_start_is_refused() {
    let mut seed = 7;
    let problem = layouts::road_like_field(200, rubber(), || lcg(&mut seed)).unwrap();
    for tolerance in [3e-2, 0.5, 1e10] {
        let options = SolverOptions {
            tolerance,
            acceptable_tolerance: tolerance,
            ..SolverOptions::default()
        };
        match solve(&problem, Control::Load(500.0), &options) {
            Err(SolveError::InvalidInput(m)) => {
                assert!(m.contains("tolerance in (0, 1e-3]"), "{m}")
            }
            other => panic!("tolerance {tolerance}: expected InvalidInput, got {other:?}"),
        }
    }
    let options = SolverOptions {
        tolerance: MAX_TOLERANCE,
        acceptable_tolerance: MAX_TOLERANCE,
        ..SolverOptions::default()
    };
    let s = solve(&problem, Control::Load(500.0), &options).unwrap();
    assert!(
        (s.total_force() - 500.0).abs() <= 1e-3 * 500.0,
        "{}",
        s.total_force()
    );
    assert!(s.contact_count() > 100, "{}", s.contact_count());
}

#[test]
fn a_warm_start_without_its_depths_is_refused_not_indexed() {
    let problem = folding_layout();
    let n = problem.len();
    let warm = Solution::warm_start(vec![1.0; n], vec![], 1e-4);
    match solve_from(
        &problem,
        Control::Load(1.0),
        &SolverOptions::default(),
        Some(&warm),
    ) {
        Err(SolveError::InvalidInput(m)) => assert!(m.contains("0 depths"), "{m}"),
        other => panic!("expected InvalidInput, got {other:?}"),
    }
}

/// Three balls of 5 mm in a row, 10 mm apart, the middle one 50 µm lower.
fn three_balls() -> Problem<PotentialLaw<Sphere>> {
    let m = rubber();
    let ball = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), m);
    Problem::new(
        vec![[-0.01, 0.0], [0.0, 0.0], [0.01, 0.0]],
        vec![0.0, 5e-5, 0.0],
        vec![ball.clone(), ball.clone(), ball],
        m,
    )
    .unwrap()
}

/// Below 1e-100 N the laws' arithmetic underflows and Newton ended with
/// "relative residual 1e185": such a load is refused by name instead.
/// (Loads above it converge: `a_load_whose_depth_is_below_the_gaps_rounding_converges`.)
#[test]
fn a_load_below_what_the_solver_resolves_is_refused_by_name() {
    let problem = three_balls();
    for w in [1e-150, 1e-300, 5e-324] {
        match solve(&problem, Control::Load(w), &SolverOptions::default()) {
            Err(SolveError::InvalidInput(m)) => assert!(m.contains("below the 1e-100 N"), "{m}"),
            other => panic!("load {w:e}: expected InvalidInput, got {other:?}"),
        }
    }
    let s = solve(&problem, Control::Load(MIN_LOAD), &SolverOptions::default()).unwrap();
    assert!((s.total_force() - MIN_LOAD).abs() <= 1e-9 * MIN_LOAD);
    let s = solve(&problem, Control::Load(0.0), &SolverOptions::default()).unwrap();
    assert_eq!(s.total_force(), 0.0);
}

/// 25 balls at 10 mm pitch, heights spread over 1 mm: from about 1e-30 N
/// the highest ball's Hertz depth (1e-24 m) lay under the start's bracket
/// floor (1e-24 m, an absolute 1e-12 of a 1e-12 m width), and every load
/// down to `MIN_LOAD` ended `NotConverged` ("relative residual 9.4" at
/// 1e-30 N, 1e70 at 1e-99 N). The bracket now stops relative to the depth
/// it brackets: one ball in contact, at Hertz's depth.
#[test]
fn a_load_whose_depth_is_below_the_gaps_rounding_converges() {
    let m = rubber();
    let ball = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), m);
    let centres = (0..25)
        .map(|k| [(k % 5) as f64 * 0.01, (k / 5) as f64 * 0.01])
        .collect();
    // A permutation of 0, 0.04, ..., 0.96 mm: ball 0 is the only one at 0.
    let gaps = (0..25).map(|k| ((k * 7) % 25) as f64 * 4e-5).collect();
    let problem = Problem::new(centres, gaps, vec![ball; 25], m).unwrap();
    let e_star = m.reduced_modulus();
    let hertz = |w: f64| (3.0 * w / (4.0 * e_star * 5e-3f64.sqrt())).powf(2.0 / 3.0);
    // The law's own depth at a load its arithmetic resolves easily; a
    // sphere's law goes as δ^(3/2) at small depths, so δ ∝ w^(2/3).
    let (w_ref, reference) = (1e-10, {
        let s = solve(&problem, Control::Load(1e-10), &SolverOptions::default()).unwrap();
        s.approach
    });
    // The Cesbron law of a sphere is Hertz's to 0.15 % at small depths.
    assert!(
        (reference / hertz(w_ref) - 1.0).abs() < 5e-3,
        "{reference:e}"
    );
    for w in [1e-20, 1e-30, 1e-40, 1e-60, 1e-80, MIN_LOAD] {
        let s = solve(&problem, Control::Load(w), &SolverOptions::default())
            .unwrap_or_else(|e| panic!("load {w:e}: {e}"));
        assert!((s.total_force() - w).abs() <= 1e-9 * w, "load {w:e}");
        assert_eq!(
            s.forces.iter().filter(|&&p| p > 0.0).count(),
            1,
            "load {w:e}"
        );
        assert!(s.forces[0] > 0.0, "load {w:e}: {:?}", s.forces);
        let scaled = reference * (w / w_ref).powf(2.0 / 3.0);
        assert!(
            (s.approach - scaled).abs() <= 1e-6 * scaled,
            "load {w:e}: approach {:e} against {scaled:e}",
            s.approach
        );
    }
}

/// Three balls 10 mm apart (contact radii ≈ 1 mm) given one Newton
/// iteration: every reduced solve failed, the merging reach widened until
/// the three were one body, and the answer was "converged" 6 % off the
/// point solution. Patches further apart than about twice their radii
/// stay separate contacts.
#[test]
fn contacts_far_apart_are_not_merged_into_one_body_when_newton_is_starved() {
    let problem = three_balls();
    let reference = solve(&problem, Control::Load(30.0), &SolverOptions::default()).unwrap();
    assert_eq!(reference.recovery, Recovery::None);
    let starved = SolverOptions {
        max_iterations: 1,
        ..SolverOptions::default()
    };
    match solve(&problem, Control::Load(30.0), &starved) {
        Err(SolveError::NotConverged { .. }) => {}
        Ok(s) => {
            assert!(s.clusters.is_empty(), "{:?}", s.clusters);
            for (p, q) in s.forces.iter().zip(&reference.forces) {
                assert!((p - q).abs() <= 1e-6 * q, "{p} vs {q}");
            }
        }
        Err(e) => panic!("expected a point solution or NotConverged, got {e}"),
    }
}
