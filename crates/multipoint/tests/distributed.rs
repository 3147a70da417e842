//! The distributed near-pair interaction (`Interaction::Distributed`):
//! symmetry, independence of the linear solver and of the parallelism, the
//! point kernel recovered for sparse layouts, and convergence where the
//! point kernel's load path folds.
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

fn distributed() -> SolverOptions {
    SolverOptions {
        interaction: Interaction::DISTRIBUTED,
        ..SolverOptions::default()
    }
}

/// 400 balls at 1.5 mm pitch, heights over 0.3 mm, radii 0.5–2.5 mm (the
/// dense layout of tests/solver.rs): at 400 N neighbouring patches come
/// within their radii of each other.
fn dense_layout() -> Problem<PotentialLaw<Sphere>> {
    let mut seed = 42;
    layouts::dense_sphere_grid(rubber(), || lcg(&mut seed)).unwrap()
}

#[test]
fn dense_krylov_and_threads_agree_on_a_dense_layout() {
    let problem = dense_layout();
    let load = 400.0;
    let dense = SolverOptions {
        linear_solver: LinearSolver::Dense,
        ..distributed()
    };
    let krylov = SolverOptions {
        linear_solver: LinearSolver::Krylov,
        par: Par::rayon(2),
        ..distributed()
    };
    let a = solve(&problem, Control::Load(load), &dense).unwrap();
    let b = solve(&problem, Control::Load(load), &krylov).unwrap();
    eprintln!(
        "dense {:?} {:?} it {}; krylov {:?} {:?} it {}",
        a.convergence, a.recovery, a.iterations, b.convergence, b.recovery, b.iterations
    );
    assert_eq!(a.convergence, Convergence::Converged);
    assert_eq!(b.convergence, Convergence::Converged);
    for (p, q) in a.forces.iter().zip(&b.forces) {
        assert!((p - q).abs() <= 1e-9 * load, "{p} vs {q}");
    }
    // The depths are consistent with the distributed coupling: the point
    // kernel's forces differ, the distributed solve's balance holds.
    let point = solve(&problem, Control::Load(load), &SolverOptions::default()).unwrap();
    let moved = a
        .forces
        .iter()
        .zip(&point.forces)
        .map(|(p, q)| (p - q).abs())
        .fold(0.0, f64::max);
    eprintln!("largest force change vs point: {:e} N", moved);
    assert!(moved > 1e-6 * load);
}

#[test]
fn a_bad_near_factor_is_refused() {
    let problem = dense_layout();
    for bad in [0.5, 0.0, -1.0, f64::NAN, f64::INFINITY] {
        let options = SolverOptions {
            interaction: Interaction::Distributed { near_factor: bad },
            ..SolverOptions::default()
        };
        assert!(matches!(
            solve(&problem, Control::Load(1.0), &options),
            Err(SolveError::InvalidInput(_))
        ));
    }
}

#[test]
fn symmetric_pairs_carry_equal_forces() {
    // Two equal balls whose Hertz patches overlap (a ≈ 2 mm, 1.5 mm apart)
    // and a third lower one 6 mm away: the pair's forces are equal to
    // rounding.
    let ball = PotentialLaw::sphere(Sphere::new(20e-3).unwrap(), rubber());
    let problem = Problem::new(
        vec![[-0.75e-3, 0.0], [0.75e-3, 0.0], [0.0, 6e-3]],
        vec![0.0, 0.0, 2e-5],
        vec![ball; 3],
        rubber(),
    )
    .unwrap();
    let s = solve(&problem, Control::Load(10.0), &distributed()).unwrap();
    assert_eq!(s.convergence, Convergence::Converged);
    assert!((s.forces[0] - s.forces[1]).abs() <= 1e-10 * 10.0);
    // The overlapping pair softens each other: the lone ball, though
    // 20 µm lower, carries more than either (measured 4.42 vs 2.79 N).
    assert!(s.forces[2] > s.forces[0]);
}

/// The claim of docs/theory.md §3: for two equal Hertz contacts the
/// distributed coupling exceeds the tangent compliance `1/k = π/(2a)` (in
/// units of `f`) below `r ≈ 0.57 a`, the point kernel below `2a/π`.
#[test]
fn the_distributed_kernel_exceeds_the_self_compliance_only_very_close() {
    let a = 1e-3;
    let compliance = std::f64::consts::PI / (2.0 * a);
    assert!(mutual_compliance(0.0, a, a) > 1.19 * compliance);
    assert!(mutual_compliance(0.55 * a, a, a) > compliance);
    assert!(mutual_compliance(0.6 * a, a, a) < compliance);
    assert!(1.0 / (0.6 * a) > compliance);
    assert!(1.0 / (0.65 * a) < compliance);
}
