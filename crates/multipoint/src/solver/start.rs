//! Where Newton starts: the uncoupled state, one Jacobi step from coarser
//! forces, and the coarse-to-fine start of large cold solves.

use tyreroad_contact_law::ContactLaw;

use super::options::{CoarseLevels, Control, SolverOptions, krylov_order};
use super::{solve, solve_from};
use crate::coarse::Clusters;
use crate::{Boussinesq, FastBoussinesq, FastOptions, Problem, Solution};

/// The start of a large cold solve (see `crate::coarse`): nested coarse
/// problems on the cluster counts of `levels`, the coarsest solved from its
/// uncoupled start, each finer one from the level below it through one
/// Jacobi step (`jacobi_start`), and a last Jacobi step to the asperities.
/// Returns the start `(δ, δ0)`; `None` (use the uncoupled start) when the
/// layout is too small to cluster or every coarse solve fails.
pub(crate) fn coarse_start<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    levels: &CoarseLevels,
) -> Option<(Vec<f64>, f64)> {
    let n = problem.len();
    let targets = levels.targets(n);
    let opts = SolverOptions {
        // A start needs a few digits only.
        tolerance: 1e-7,
        coarse_start_min_n: usize::MAX,
        ..*options
    };
    let laws = problem.laws();
    // Interpenetration of every asperity implied by the last level solved,
    // and that level's approach.
    let mut state: Option<(Vec<f64>, f64)> = None;
    for &target in targets.iter().rev() {
        let clusters = Clusters::new(problem, target);
        if clusters.members.len() < 2 {
            continue;
        }
        let cluster_laws = clusters.laws(laws, problem.gaps());
        // Boxed: a generic coarse law type would make `solve` instantiate
        // itself for ever deeper cluster-of-cluster types.
        let boxed: Vec<Box<dyn ContactLaw + Sync + '_>> = cluster_laws
            .iter()
            .map(|l| Box::new(l) as Box<dyn ContactLaw + Sync>)
            .collect();
        let Ok(coarse) = Problem::new(
            clusters.centroids.clone(),
            clusters.gaps.clone(),
            boxed,
            *problem.material(),
        ) else {
            continue;
        };
        let solved = match &state {
            None => solve(&coarse, control, &opts),
            Some((depths, _)) => {
                let forces: Vec<f64> = cluster_laws
                    .iter()
                    .map(|c| c.members().iter().map(|&i| laws[i].force(depths[i])).sum())
                    .collect();
                let (delta, d0) = jacobi_start(&coarse, control, &forces, options);
                let warm = Solution::warm_start(forces, delta, d0);
                solve_from(&coarse, control, &opts, Some(&warm))
            }
        };
        let Ok(solution) = solved else {
            continue;
        };
        let mut depths = vec![0.0; n];
        for (c, law) in cluster_laws.iter().enumerate() {
            let inner = law.inner_depth(solution.depths[c]);
            for (&i, &h) in law.members().iter().zip(law.offsets()) {
                depths[i] = inner - h;
            }
        }
        state = Some((depths, solution.approach));
    }
    let (depths, _) = state?;
    let forces: Vec<f64> = (0..n).map(|i| laws[i].force(depths[i])).collect();
    Some(jacobi_start(problem, control, &forces, options))
}

/// One Jacobi step from forces `p` that are right at a coarser scale: the
/// displacements they cause, `u = T p` (the fast operator at the Krylov
/// order from [`SolverOptions::fast_operator_min_n`] summits), then the
/// approach that balances the load at those displacements and
/// `δ_i = δ0 − H_i − u_i`. The bowl of `u` comes from the coarse solution;
/// the step adds the local variation of `u` that the clusters smeared out.
pub(super) fn jacobi_start<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    p: &[f64],
    options: &SolverOptions,
) -> (Vec<f64>, f64) {
    let n = problem.len();
    let factor = problem.material().boussinesq_factor();
    let mut u = vec![0.0; n];
    if n >= options.fast_operator_min_n {
        let fo = FastOptions {
            order: krylov_order(options.fast_operator.order),
            ..options.fast_operator
        };
        FastBoussinesq::new(problem.positions(), factor, fo).apply(p, &mut u, options.par);
    } else {
        Boussinesq::new(problem.positions(), factor).apply(p, &mut u, options.par);
    }
    let (_, d0) = uncoupled_start(problem, control, &u);
    (crate::solution::interpenetrations(problem, d0, &u), d0)
}

/// The state where every asperity carries its own law's force at fixed
/// interaction displacements `u`: under load control the approach solves
/// `Σ P_i^law(δ0 − H_i − u_i) = W` (monotone in δ0: bracketing and bisection).
pub(super) fn uncoupled_start<L: ContactLaw>(
    problem: &Problem<L>,
    control: Control,
    u: &[f64],
) -> (Vec<f64>, f64) {
    let (laws, gaps) = (problem.laws(), problem.gaps());
    // Σ P_i^law and Σ k_i at approach d0.
    let total = |d0: f64| -> (f64, f64) {
        laws.iter()
            .zip(gaps.iter().zip(u))
            .map(|(law, (h, u))| law.evaluate(d0 - h - u))
            .fold((0.0, 0.0), |(p, k), l| (p + l.force, k + l.stiffness))
    };
    let d0 = match control {
        Control::Approach(d0) => d0,
        Control::Load(w) => {
            let lo0 = gaps
                .iter()
                .zip(u)
                .map(|(h, u)| h + u)
                .fold(f64::INFINITY, f64::min);
            let spread = gaps
                .iter()
                .zip(u)
                .map(|(h, u)| h + u - lo0)
                .fold(0.0, f64::max);
            let mut width = (spread * 1e-3).max(lo0.abs() * 1e-9).max(1e-12);
            while total(lo0 + width).0 < w && width < 1e3 {
                width *= 2.0;
            }
            // Newton safeguarded by the bracket [lo, hi]; a start point only
            // needs a few digits, the coupled Newton refines it.
            let (mut lo, mut hi) = (lo0, lo0 + width);
            let mut x = hi;
            for _ in 0..100 {
                let (f, k) = total(x);
                if f < w {
                    lo = x;
                } else {
                    hi = x;
                }
                if (f - w).abs() <= 1e-12 * w || hi - lo <= 1e-12 * hi.abs().max(hi - lo0) {
                    break;
                }
                let newton = x - (f - w) / k;
                x = if k > 0.0 && newton > lo && newton < hi {
                    newton
                } else {
                    0.5 * (lo + hi)
                };
            }
            x
        }
    };
    let p = laws
        .iter()
        .zip(gaps.iter().zip(u))
        .map(|(law, (h, u))| law.force(d0 - h - u))
        .collect();
    (p, d0)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use tyreroad_asperity::Sphere;
    use tyreroad_contact_law::{Material, PotentialLaw};

    use super::*;
    use crate::solver::{LinearSolver, solve_with};

    fn lcg(seed: &mut u64) -> f64 {
        *seed = seed
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The road-like field of the integration tests.
    fn field(n: usize, seed: u64) -> Problem<PotentialLaw<Sphere>> {
        let rubber = Material::new(6.54e6, 0.5).unwrap();
        let mut s = seed;
        crate::layouts::road_like_field(n, rubber, || lcg(&mut s)).unwrap()
    }

    fn max_rel_diff(a: &[f64], b: &[f64]) -> f64 {
        let scale = b.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
        a.iter()
            .zip(b)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max)
            / scale
    }

    /// A small hierarchy (N/4, N/16, … clusters) so that a test-sized
    /// problem exercises two coarse levels and both Jacobi transfers.
    const SMALL: CoarseLevels = CoarseLevels {
        ratio: 4,
        min: 16,
        max: 64,
    };

    #[test]
    fn small_hierarchy_has_two_levels() {
        assert_eq!(SMALL.targets(900), vec![225, 56]);
        assert_eq!(CoarseLevels::DEFAULT.targets(100_000), vec![10_000, 1000]);
        assert_eq!(CoarseLevels::DEFAULT.targets(10_000), vec![1000]);
        assert!(CoarseLevels::DEFAULT.targets(2000).is_empty());
    }

    /// The coarse start changes the start only: the converged forces equal
    /// the dense solution from the uncoupled start (both to 1e-11), under
    /// load and approach control, on the dense and on the Krylov path with
    /// the fast operator (which also exercises the cheap-residual phase).
    #[test]
    fn coarse_start_reaches_the_dense_solution() {
        let n = 900;
        let problem = field(n, 11);
        let load = 0.2e6 * 9e-6 * n as f64;
        let reference_opts = SolverOptions {
            linear_solver: LinearSolver::Dense,
            coarse_start_min_n: usize::MAX,
            ..SolverOptions::default()
        };
        let reference = solve(&problem, Control::Load(load), &reference_opts).unwrap();
        let start = coarse_start(&problem, Control::Load(load), &reference_opts, &SMALL).unwrap();
        let uncoupled_start_d0 = uncoupled_start(&problem, Control::Load(load), &vec![0.0; n]).1;
        // The coupled bowl lowers the tread: the coarse approach is within
        // 10 % of the converged one, the uncoupled one far from it.
        let d0 = reference.approach;
        assert!((start.1 - d0).abs() < 0.1 * d0, "{} vs {d0}", start.1);
        assert!((uncoupled_start_d0 - d0).abs() > 0.3 * d0);
        for (name, opts) in [
            (
                "dense",
                SolverOptions {
                    coarse_start_min_n: 0,
                    ..reference_opts
                },
            ),
            (
                "krylov+fast",
                SolverOptions {
                    linear_solver: LinearSolver::Krylov,
                    fast_operator_min_n: 0,
                    coarse_start_min_n: 0,
                    ..SolverOptions::default()
                },
            ),
        ] {
            let s = solve_with(&problem, Control::Load(load), &opts, None, &SMALL).unwrap();
            let diff = max_rel_diff(&s.forces, &reference.forces);
            eprintln!(
                "{name}: {} iterations (uncoupled start: {}), max |ΔP|/max P = {diff:.2e}",
                s.iterations, reference.iterations
            );
            assert!(s.residual <= 1e-11);
            assert!(diff < 1e-6, "{name}: {diff:e}");
            let a = solve_with(&problem, Control::Approach(d0), &opts, None, &SMALL).unwrap();
            let diff_a = max_rel_diff(&a.forces, &reference.forces);
            assert!(diff_a < 1e-6, "{name}, approach control: {diff_a:e}");
        }
    }
}
