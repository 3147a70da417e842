//! The matrix-free path: fast operator accuracy, Krylov against dense, and
//! the automatic dense/Krylov choice under a memory limit.
#![allow(clippy::unwrap_used)]

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::*;

type SphereLaw = PotentialLaw<Sphere>;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// The road-like field (`layouts::road_like_field`) drawn from [`lcg`].
fn field(n: usize, seed: u64) -> Problem<SphereLaw> {
    let mut s = seed;
    layouts::road_like_field(n, rubber(), || lcg(&mut s)).unwrap()
}

fn max_rel_diff(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
        / scale
}

#[test]
fn fast_operator_accuracy() {
    let f = rubber().boussinesq_factor();
    for (n, clustered) in [(2000usize, false), (2000, true)] {
        let mut s = 7 + n as u64;
        let positions: Vec<[f64; 2]> = (0..n)
            .map(|k| {
                if clustered {
                    // Five tight clusters in a large square.
                    let c = (k % 5) as f64;
                    [c * 0.07 + 0.01 * lcg(&mut s), c * 0.03 + 0.01 * lcg(&mut s)]
                } else {
                    [lcg(&mut s), lcg(&mut s)]
                }
            })
            .collect();
        let x: Vec<f64> = (0..n).map(|_| lcg(&mut s)).collect();
        let mut exact = vec![0.0; n];
        Boussinesq::new(&positions, f).apply(&x, &mut exact, Par::Seq);
        let norm = exact.iter().map(|v| v * v).sum::<f64>().sqrt();
        for order in [4, 6, 8, 10] {
            let op = FastBoussinesq::new(
                &positions,
                f,
                FastOptions {
                    order,
                    leaf_size: 24,
                },
            );
            assert!(op.depth() >= 2, "the test must exercise the far field");
            let mut fast = vec![0.0; n];
            op.apply(&x, &mut fast, Par::Seq);
            let err = exact
                .iter()
                .zip(&fast)
                .map(|(a, b)| (a - b) * (a - b))
                .sum::<f64>()
                .sqrt()
                / norm;
            eprintln!("N = {n}, clustered {clustered}, order {order}: relative error {err:.2e}");
            assert!(err <= op.error_bound(), "order {order}: {err:e}");
            if order >= 6 {
                assert!(err <= 1e-6);
            }
            // Threads change nothing but the summation order.
            let mut par = vec![0.0; n];
            op.apply(&x, &mut par, Par::rayon(2));
            assert!(max_rel_diff(&par, &fast) < 1e-12);
        }
    }
}

#[test]
fn krylov_matches_dense_under_load_and_approach_control() {
    for (n, seed) in [(300usize, 1u64), (1200, 2)] {
        let problem = field(n, seed);
        let load = 0.2e6 * 9e-6 * n as f64;
        let dense_opts = SolverOptions {
            linear_solver: LinearSolver::Dense,
            ..SolverOptions::default()
        };
        let krylov_opts = SolverOptions {
            linear_solver: LinearSolver::Krylov,
            par: Par::rayon(2),
            ..SolverOptions::default()
        };
        let dense = solve(&problem, Control::Load(load), &dense_opts).unwrap();
        let krylov = solve(&problem, Control::Load(load), &krylov_opts).unwrap();
        let diff = max_rel_diff(&krylov.forces, &dense.forces);
        eprintln!(
            "N = {n} load control: {} in contact, dense {} it, Krylov {} it, max |ΔP|/max P = {diff:.2e}",
            dense.contact_count(),
            dense.iterations,
            krylov.iterations
        );
        assert!(diff < 1e-6, "load control N = {n}: {diff:e}");
        assert!(krylov.residual <= 1e-11);
        assert!((krylov.total_force() - load).abs() < 1e-9 * load);
        // Displacement control at the dense solution's approach.
        let d0 = dense.approach;
        let dense_a = solve(&problem, Control::Approach(d0), &dense_opts).unwrap();
        let krylov_a = solve(&problem, Control::Approach(d0), &krylov_opts).unwrap();
        let diff_a = max_rel_diff(&krylov_a.forces, &dense_a.forces);
        eprintln!("N = {n} approach control: max |ΔP|/max P = {diff_a:.2e}");
        assert!(diff_a < 1e-6, "approach control N = {n}: {diff_a:e}");
    }
}

#[test]
fn krylov_with_the_fast_operator_matches_dense() {
    let n = 1600;
    let problem = field(n, 3);
    let load = 0.2e6 * 9e-6 * n as f64;
    let dense = solve(
        &problem,
        Control::Load(load),
        &SolverOptions {
            linear_solver: LinearSolver::Dense,
            par: Par::rayon(2),
            ..SolverOptions::default()
        },
    )
    .unwrap();
    let fast = solve(
        &problem,
        Control::Load(load),
        &SolverOptions {
            linear_solver: LinearSolver::Krylov,
            fast_operator_min_n: 0,
            par: Par::rayon(2),
            ..SolverOptions::default()
        },
    )
    .unwrap();
    let diff = max_rel_diff(&fast.forces, &dense.forces);
    eprintln!("N = {n} fast operator: max |ΔP|/max P = {diff:.2e}");
    assert!(diff < 1e-6, "{diff:e}");
}

#[test]
fn a_tiny_memory_limit_forces_krylov_and_dense_refuses() {
    let problem = field(400, 4);
    let load = 0.2e6 * 9e-6 * 400.0;
    let tiny = SolverOptions {
        dense_memory_limit_bytes: 1000,
        ..SolverOptions::default()
    };
    let auto = solve(&problem, Control::Load(load), &tiny).unwrap();
    let dense = solve(&problem, Control::Load(load), &SolverOptions::default()).unwrap();
    assert!(max_rel_diff(&auto.forces, &dense.forces) < 1e-6);
    let refused = solve(
        &problem,
        Control::Load(load),
        &SolverOptions {
            linear_solver: LinearSolver::Dense,
            ..tiny
        },
    );
    assert!(matches!(refused, Err(SolveError::InvalidInput(_))));
}
