//! Newton–Raphson on the N nonlinear equations, globalised by a line search
//! and, when that is not enough, by load (or approach) stepping.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::lu::partial_pivoting as lu;
use faer::{Mat, MatMut, Par};
use tyreroad_contact_law::ContactLaw;

use crate::coarse::Clusters;
use crate::krylov::{self, ActiveOperator, Interaction, KrylovStats, Preconditioner};
use crate::{Boussinesq, FastBoussinesq, FastOptions, Problem, Solution, SolveError};

/// What is imposed on the tread.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Control {
    /// The total normal load `Σ P_i = W` (N); the approach `δ0` is unknown.
    Load(f64),
    /// The rigid approach `δ0` (m); the total load is an output.
    Approach(f64),
}

/// How each Newton step's linear system is solved.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum LinearSolver {
    /// Dense below [`SolverOptions::krylov_min_active`] active asperities when
    /// the matrix fits [`SolverOptions::dense_memory_limit_bytes`], Krylov
    /// otherwise.
    #[default]
    Auto,
    /// In-place dense Cholesky (LU when indefinite) of the active matrix. A
    /// solve whose matrix would exceed the memory limit fails with
    /// [`SolveError::InvalidInput`] rather than allocate it.
    Dense,
    /// Matrix-free preconditioned CG (GMRES when indefinite) with inexact
    /// Newton forcing terms.
    Krylov,
}

/// Tuning of the solver. The defaults converge from a cold start on every
/// layout in the test suite.
#[derive(Clone, Copy, Debug)]
pub struct SolverOptions {
    /// Convergence when every residual `|P_i − P_i^law(δ_i)|` and the load
    /// residual are below `tolerance × force scale` (the imposed load, or the
    /// uncoupled total force under approach control).
    pub tolerance: f64,
    /// Newton iterations allowed per load step.
    pub max_iterations: usize,
    /// Load (or approach) steps allowed when a direct solve fails.
    pub max_load_steps: usize,
    /// Parallelism of the interaction products and of the factorizations.
    pub par: Par,
    /// Dense or matrix-free linear algebra (see [`LinearSolver`]).
    pub linear_solver: LinearSolver,
    /// The most memory a dense active matrix (`8 n_A²` bytes plus its
    /// factorization scratch) may take; above it [`LinearSolver::Auto`] goes
    /// Krylov and [`LinearSolver::Dense`] refuses. Default 1 GiB.
    pub dense_memory_limit_bytes: usize,
    /// Under [`LinearSolver::Auto`], the active count from which Krylov is
    /// preferred to the dense factorization even when it would fit. Default
    /// 1200: the measured crossover on the project machine with the default
    /// [`Self::fast_operator_min_n`] (road-like field, 2 threads: dense 6 %
    /// faster at 1120 active, Krylov 1.8× faster at 1487 and 2.8× at 2178;
    /// `scaling/crossover` in benches/scaling.rs, docs/performance.md).
    pub krylov_min_active: usize,
    /// The number of asperities from which the Krylov path computes every
    /// interaction product `T·x` with the fast multipole operator
    /// ([`FastBoussinesq`]) instead of the exact `O(N · nnz)` sum: residuals
    /// at [`Self::fast_operator`] accuracy, Krylov products at a lower
    /// order. Never used by the dense path. Default 1500 (from there the
    /// fast products are 5–10× cheaper; forces stay within ~1e-8 of the
    /// exact kernel's). `usize::MAX` disables it.
    pub fast_operator_min_n: usize,
    /// Accuracy of the fast residual products (order 10: relative error
    /// ≈ 1e-10). Newton converges on the residual of that operator, so the
    /// forces differ from the exact-kernel solution by about this error
    /// times the problem's conditioning.
    pub fast_operator: FastOptions,
    /// The number of asperities from which a cold solve starts from nested
    /// coarse problems on clusters of neighbouring asperities (about N/10,
    /// N/100, … clusters, the coarsest of 256 to 1024) instead of the
    /// uncoupled state: on large patches the coupling's bowl-shaped
    /// displacement dwarfs the interpenetrations and the uncoupled start
    /// costs many Newton iterations with short steps (docs/performance.md:
    /// 21 → 9 at N = 10⁵). Only the start changes; Newton then converges to
    /// the same tolerance. `usize::MAX` disables it.
    pub coarse_start_min_n: usize,
}

/// The cluster hierarchy of the coarse start
/// ([`SolverOptions::coarse_start_min_n`]).
#[derive(Clone, Copy, Debug)]
pub(crate) struct CoarseLevels {
    /// Asperities per cluster between consecutive levels. One Jacobi step
    /// bridges a factor of 10 well; a single level of clusters of 100 at
    /// N = 10⁵ was too rough a start (docs/performance.md).
    pub(crate) ratio: usize,
    /// Fewest clusters of a level.
    pub(crate) min: usize,
    /// Most clusters of the coarsest level (solved from the uncoupled
    /// start): a dense solve of 10³ clusters costs tens of milliseconds.
    pub(crate) max: usize,
}

impl CoarseLevels {
    pub(crate) const DEFAULT: Self = Self {
        ratio: 10,
        min: 256,
        max: 1024,
    };

    /// Cluster counts of the levels, finest first: `n/r`, `n/r²`, … while at
    /// least `min`, stopping at the first count ≤ `max`.
    fn targets(&self, n: usize) -> Vec<usize> {
        let mut targets = Vec::new();
        let mut t = n / self.ratio.max(2);
        while t >= self.min.max(2) {
            targets.push(t);
            if t <= self.max {
                break;
            }
            t /= self.ratio.max(2);
        }
        targets
    }
}

impl Default for SolverOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-11,
            max_iterations: 60,
            max_load_steps: 200,
            par: Par::Seq,
            linear_solver: LinearSolver::Auto,
            dense_memory_limit_bytes: 1 << 30,
            krylov_min_active: 1200,
            fast_operator_min_n: 1500,
            fast_operator: FastOptions::default(),
            coarse_start_min_n: 4096,
        }
    }
}

/// Solves the multipoint contact `problem` under `control` from a cold start.
pub fn solve<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
) -> Result<Solution, SolveError> {
    solve_from(problem, control, options, None)
}

/// Solves from a previous solution of the same asperities (warm start, e.g.
/// the previous step of a rolling path), or cold when `initial` is `None`.
pub fn solve_from<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    initial: Option<&Solution>,
) -> Result<Solution, SolveError> {
    solve_with(problem, control, options, initial, &CoarseLevels::DEFAULT)
}

/// [`solve_from`] with the coarse start's hierarchy spelled out (tests use
/// small ones).
pub(crate) fn solve_with<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    initial: Option<&Solution>,
    levels: &CoarseLevels,
) -> Result<Solution, SolveError> {
    check_control(control)?;
    check_options(options)?;
    let n = problem.len();
    if let Some(s) = initial
        && s.forces.len() != n
    {
        return Err(SolveError::InvalidInput(format!(
            "warm start has {} forces for {n} asperities",
            s.forces.len()
        )));
    }
    let mut ws = Workspace::new(n);
    let exact = Boussinesq::new(problem.positions(), problem.material().boussinesq_factor());
    let may_krylov = options.linear_solver != LinearSolver::Dense;
    let use_fast = may_krylov && n >= options.fast_operator_min_n;
    let factor = problem.material().boussinesq_factor();
    let tree = may_krylov.then(|| {
        let fo = if use_fast {
            residual_options(&options.fast_operator)
        } else {
            FastOptions {
                order: 2,
                ..options.fast_operator
            }
        };
        FastBoussinesq::new(problem.positions(), factor, fo)
    });
    let tree_lo = (use_fast).then(|| {
        let fo = FastOptions {
            order: krylov_order(options.fast_operator.order),
            ..options.fast_operator
        };
        FastBoussinesq::new(problem.positions(), factor, fo)
    });
    let op = Ops {
        exact,
        residual: match (&tree, use_fast) {
            (Some(t), true) => Interaction::Fast(t),
            _ => Interaction::Exact(exact),
        },
        product: match &tree_lo {
            Some(t) => Interaction::Fast(t),
            None => Interaction::Exact(exact),
        },
        // The preconditioner's blocks are the leaves of the Krylov tree
        // (sized for its order), else of the only tree.
        tree: tree_lo.as_ref().or(tree.as_ref()),
        positions: problem.positions(),
        profile: std::env::var_os("TYREROAD_PROFILE").is_some(),
    };
    let par = options.par;
    let first_touch = problem.gaps().iter().copied().fold(f64::INFINITY, f64::min);

    let scale = match control {
        Control::Load(w) => w,
        Control::Approach(d0) => {
            let laws = problem.laws();
            let gaps = problem.gaps();
            (0..n).map(|i| laws[i].force(d0 - gaps[i])).sum::<f64>()
        }
    };
    if scale == 0.0 {
        // Nothing touches: no load, or an approach short of the highest summit.
        let approach = match control {
            Control::Load(_) => first_touch,
            Control::Approach(d0) => d0,
        };
        return Ok(Solution::assemble(
            problem,
            vec![0.0; n],
            approach,
            0,
            0,
            0.0,
            op.residual,
            par,
        ));
    }
    let tol = options.tolerance * scale;

    // Start: the warm state, or the uncoupled solution (T = 0).
    let (mut p, mut d0) = match initial {
        Some(s) => (s.forces.clone(), s.approach),
        None => {
            ws.u.iter_mut().for_each(|u| *u = 0.0);
            uncoupled_start(problem, control, &ws.u)
        }
    };
    // Newton iterates on the local interpenetrations δ_i (see `newton`): from
    // the warm state's, shifted to the imposed approach, or the uncoupled ones.
    let mut delta: Vec<f64> = match initial {
        Some(s) => {
            let shift = match control {
                Control::Approach(target) => target - s.approach,
                Control::Load(_) => 0.0,
            };
            s.depths.iter().map(|d| d + shift).collect()
        }
        None => {
            let start = match control {
                Control::Approach(target) => target,
                Control::Load(_) => d0,
            };
            problem.gaps().iter().map(|h| start - h).collect()
        }
    };
    if let Control::Approach(target) = control {
        d0 = target;
    }
    if initial.is_none()
        && n >= options.coarse_start_min_n
        && let Some((coarse_delta, coarse_d0)) = coarse_start(problem, control, options, levels)
    {
        delta = coarse_delta;
        d0 = coarse_d0;
    }
    let mut iterations = 0;
    let direct = newton(
        problem, &op, control, &mut p, &mut delta, &mut d0, tol, options, &mut ws,
    )?;
    iterations += direct.iterations;
    if direct.converged {
        return Ok(Solution::finish(
            problem,
            p,
            d0,
            iterations,
            1,
            direct.residual / scale,
            op.residual,
            par,
        ));
    }

    // Continuation from first contact: s ∈ (0, 1] scales the load (or the
    // approach beyond first touch); each step starts from the last converged
    // state scaled to the new target.
    let start_d0 = match control {
        Control::Load(_) => first_touch,
        Control::Approach(_) => first_touch,
    };
    let target_at = |s: f64| match control {
        Control::Load(w) => Control::Load(w * s),
        Control::Approach(d) => Control::Approach(start_d0 + s * (d - start_d0)),
    };
    let (mut s, mut step) = (0.0_f64, 1.0 / 16.0);
    let (mut p_ok, mut d0_ok) = (vec![0.0; n], start_d0);
    let mut delta_ok: Vec<f64> = problem.gaps().iter().map(|h| start_d0 - h).collect();
    let mut steps = 0;
    let mut last_residual = direct.residual;
    while s < 1.0 {
        if steps >= options.max_load_steps || step < 1e-9 {
            return Err(SolveError::NotConverged {
                iterations,
                load_steps: steps,
                residual: last_residual / scale,
            });
        }
        steps += 1;
        let s_next = (s + step).min(1.0);
        let sub = target_at(s_next);
        if s > 0.0 {
            delta.copy_from_slice(&delta_ok);
            d0 = d0_ok;
        } else {
            ws.u.iter_mut().for_each(|u| *u = 0.0);
            (p, d0) = uncoupled_start(problem, sub, &ws.u);
            for (d, h) in delta.iter_mut().zip(problem.gaps()) {
                *d = d0 - h;
            }
        }
        if let Control::Approach(target) = sub {
            delta.iter_mut().for_each(|d| *d += target - d0);
            d0 = target;
        }
        let sub_scale = match sub {
            Control::Load(w) => w,
            Control::Approach(_) => scale * s_next,
        };
        let run = newton(
            problem,
            &op,
            sub,
            &mut p,
            &mut delta,
            &mut d0,
            options.tolerance * sub_scale,
            options,
            &mut ws,
        )?;
        iterations += run.iterations;
        last_residual = run.residual;
        if run.converged {
            s = s_next;
            p_ok.copy_from_slice(&p);
            delta_ok.copy_from_slice(&delta);
            d0_ok = d0;
            step = (step * 2.0).min(1.0);
        } else {
            step *= 0.25;
        }
    }
    Ok(Solution::finish(
        problem,
        p_ok,
        d0_ok,
        iterations,
        steps + 1,
        last_residual / scale,
        op.residual,
        par,
    ))
}

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
                let warm = Solution {
                    forces,
                    depths: delta,
                    approach: d0,
                    iterations: 0,
                    load_steps: 0,
                    residual: f64::NAN,
                };
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
fn jacobi_start<L: ContactLaw + Sync>(
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
    let delta = problem
        .gaps()
        .iter()
        .zip(&u)
        .map(|(h, u)| d0 - h - u)
        .collect();
    (delta, d0)
}

fn check_control(control: Control) -> Result<(), SolveError> {
    match control {
        Control::Load(w) if !(w.is_finite() && w >= 0.0) => Err(SolveError::InvalidInput(format!(
            "imposed load must be finite and ≥ 0 N, got {w}"
        ))),
        Control::Approach(d) if !d.is_finite() => Err(SolveError::InvalidInput(format!(
            "imposed approach must be finite, got {d}"
        ))),
        _ => Ok(()),
    }
}

/// The residual operator's options: the user's order, and leaves grown by
/// `(order / Krylov order)²` over the user's leaf size (which sizes the
/// Krylov operator and the preconditioner's blocks). The far field costs
/// `O(n⁴ / s)` a summit for order `n` and `s` summits a leaf, the near field
/// `O(s)`, so the cheapest leaf grows like `n²`: at N = 10⁵, order 10, leaves
/// of ~100 summits instead of ~25 made the product about 2× faster
/// (docs/performance.md).
fn residual_options(fast: &FastOptions) -> FastOptions {
    let (hi, lo) = (fast.order as f64, krylov_order(fast.order) as f64);
    let grow = (hi / lo).powi(2).max(1.0);
    FastOptions {
        order: fast.order,
        leaf_size: (fast.leaf_size as f64 * grow).round() as usize,
    }
}

/// Chebyshev order of the Krylov products for residual order `order`: the
/// Jacobian only steers Newton, so about half the digits do.
fn krylov_order(order: usize) -> usize {
    (order / 2 + 1).clamp(4, order.max(4))
}

/// The interaction products of one solve.
struct Ops<'a> {
    exact: Boussinesq<'a>,
    /// Residuals (and the final depths).
    residual: Interaction<'a>,
    /// Krylov products.
    product: Interaction<'a>,
    /// The cluster tree of the Krylov preconditioner.
    tree: Option<&'a FastBoussinesq>,
    positions: &'a [[f64; 2]],
    /// Print per-iteration timings to stderr (`TYREROAD_PROFILE` set).
    profile: bool,
}

impl Ops<'_> {
    fn exact_positions(&self) -> &[[f64; 2]] {
        self.positions
    }

    /// Whether the Krylov operator is a cheaper (lower-order) fast operator
    /// than the residual's.
    fn product_is_cheaper(&self) -> bool {
        match (self.product, self.residual) {
            (Interaction::Fast(lo), Interaction::Fast(hi)) => lo.order() < hi.order(),
            _ => false,
        }
    }

    /// The residual level above which the cheap operator may evaluate
    /// residuals: 100 × the largest force residual its error causes,
    /// `max_i k_i |(T̃p)_i − (Tp)_i|` at the state `evaluate` left in `ws`
    /// (forces `p`, stiffnesses, cheap products in `ws.u`), with one
    /// accurate product. Below that level the cheap residual would mislead
    /// the iteration, so the accurate one takes over.
    fn coarse_until(&self, p: &[f64], ws: &mut Workspace, par: Par) -> f64 {
        self.residual.apply(p, &mut ws.coupled, par);
        let worst = ws
            .stiffness
            .iter()
            .zip(ws.u.iter().zip(&ws.coupled))
            .map(|(k, (lo, hi))| k * (lo - hi).abs())
            .fold(0.0_f64, f64::max);
        if worst.is_finite() {
            100.0 * worst
        } else {
            f64::INFINITY
        }
    }
}

fn check_options(options: &SolverOptions) -> Result<(), SolveError> {
    if !(options.tolerance.is_finite() && options.tolerance > 0.0) || options.max_iterations == 0 {
        return Err(SolveError::InvalidInput(format!(
            "solver options need tolerance > 0 and max_iterations ≥ 1, got {} and {}",
            options.tolerance, options.max_iterations
        )));
    }
    Ok(())
}

/// The state where every asperity carries its own law's force at fixed
/// interaction displacements `u`: under load control the approach solves
/// `Σ P_i^law(δ0 − H_i − u_i) = W` (monotone in δ0: bracketing and bisection).
fn uncoupled_start<L: ContactLaw>(
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
                if (f - w).abs() <= 1e-12 * w || hi - lo <= 1e-12 * hi.abs().max(width) {
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

struct Workspace {
    u: Vec<f64>,
    residual: Vec<f64>,
    stiffness: Vec<f64>,
    step: Vec<f64>,
    active: Vec<usize>,
    matrix: Mat<f64>,
    rhs: Mat<f64>,
    perm: Vec<usize>,
    perm_inv: Vec<usize>,
    stack: MemBuffer,
    /// Krylov: `1/Σ`-solve of the previous step (warm start), per asperity.
    ones_solution: Vec<f64>,
    /// Krylov: inexact Newton forcing term of the next step.
    forcing: f64,
    /// Krylov: products spent, for diagnostics.
    krylov: KrylovStats,
    /// Whether the last Newton direction came from a Krylov solve.
    last_was_krylov: bool,
    /// `F_i = δ_i + u_i − δ0 + H_i`: how far the iterate's δ is from the one
    /// its forces imply.
    mismatch: Vec<f64>,
    /// Weights of `F` in the line-search merit, fixed during one step.
    weight: Vec<f64>,
    /// The Newton change of δ.
    depth_step: Vec<f64>,
    /// `T · ΔP`, and the line search's trial δ.
    coupled: Vec<f64>,
    trial_depth: Vec<f64>,
}

impl Workspace {
    fn new(n: usize) -> Self {
        Self {
            u: vec![0.0; n],
            residual: vec![0.0; n],
            stiffness: vec![0.0; n],
            step: vec![0.0; n],
            active: Vec::with_capacity(n),
            matrix: Mat::zeros(0, 0),
            rhs: Mat::zeros(n, 2),
            perm: vec![0; n],
            perm_inv: vec![0; n],
            stack: MemBuffer::new(faer::dyn_stack::StackReq::EMPTY),
            ones_solution: vec![0.0; n],
            forcing: 0.1,
            krylov: KrylovStats::default(),
            last_was_krylov: false,
            mismatch: vec![0.0; n],
            weight: vec![1.0; n],
            depth_step: vec![0.0; n],
            coupled: vec![0.0; n],
            trial_depth: vec![0.0; n],
        }
    }
}

struct NewtonRun {
    converged: bool,
    iterations: usize,
    residual: f64,
}

/// State at `(δ, d0)`: forces `p = P^law(δ)` with their stiffnesses, the
/// interaction displacements `u = T p`, the mismatch `F = δ + u − δ0 + H`
/// (into `ws.mismatch`) and the true residuals `R_i = P_i − P_i^law(δ0 − H_i
/// − u_i)` (into `ws.residual`). Returns the max-norm of `R` and of the load
/// equation, the weighted merit `Σ (w_i F_i)² + R_W²`, and `R_W`.
#[allow(clippy::too_many_arguments)]
fn evaluate<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    interaction: &Interaction<'_>,
    control: Control,
    delta: &[f64],
    d0: f64,
    p: &mut [f64],
    ws: &mut Workspace,
    par: Par,
) -> (f64, f64, f64) {
    let (laws, gaps) = (problem.laws(), problem.gaps());
    for i in 0..p.len() {
        let law = laws[i].evaluate(delta[i]);
        p[i] = law.force;
        ws.stiffness[i] = law.stiffness;
    }
    interaction.apply(p, &mut ws.u, par);
    let (mut max, mut sq) = (0.0_f64, 0.0);
    for i in 0..p.len() {
        let f = delta[i] + ws.u[i] - d0 + gaps[i];
        ws.mismatch[i] = f;
        sq += (ws.weight[i] * f).powi(2);
        let r = p[i] - laws[i].force(d0 - gaps[i] - ws.u[i]);
        ws.residual[i] = r;
        max = max.max(r.abs());
    }
    let mut load_residual = 0.0;
    if let Control::Load(w) = control {
        load_residual = p.iter().sum::<f64>() - w;
        max = max.max(load_residual.abs());
        sq += load_residual * load_residual;
    }
    // A NaN anywhere must never pass for convergence.
    if max.is_nan() || sq.is_nan() {
        return (f64::INFINITY, f64::INFINITY, load_residual);
    }
    (max, sq, load_residual)
}

/// Newton–Raphson in the local interpenetrations: the iterate is `(δ, δ0)`
/// with `P = P^law(δ)`, and the equations `F_i = δ_i + (T P)_i − δ0 + H_i = 0`
/// (with `Σ P = W` under load control). Its Jacobian, scaled by `diag(k)`
/// on the active rows, is the same symmetric `diag(1/k) + T` as the force
/// form's, but a step moves along each law's curve instead of along its
/// tangent: a force can neither go negative nor overshoot, which is what
/// makes strongly coupled, dense layouts converge in a few iterations.
/// Convergence is judged on the force-form residuals all the same.
#[allow(clippy::too_many_arguments)]
fn newton<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    op: &Ops<'_>,
    control: Control,
    p: &mut [f64],
    delta: &mut [f64],
    d0: &mut f64,
    tol: f64,
    options: &SolverOptions,
    ws: &mut Workspace,
) -> Result<NewtonRun, SolveError> {
    let par = options.par;
    let n = p.len();
    // Early iterations evaluate their residuals with the cheaper Krylov
    // operator while they are far above what its error can reach
    // (`Ops::coarse_until`); the accurate operator takes over below that,
    // and always judges convergence.
    let mut cheap = op.product_is_cheaper();
    let mut eval_op = if cheap { op.product } else { op.residual };
    let (mut max, _, mut load_residual) =
        evaluate(problem, &eval_op, control, delta, *d0, p, ws, par);
    let coarse_until = if cheap {
        op.coarse_until(p, ws, par)
    } else {
        0.0
    };
    // Eisenstat–Walker (choice 2, γ = 0.9, α = 2) forcing terms for Krylov.
    ws.forcing = 0.1;
    let mut tight = false;
    let mut previous_norm = f64::NAN;
    for iteration in 0..options.max_iterations {
        if cheap && max <= coarse_until.max(tol) {
            cheap = false;
            eval_op = op.residual;
            (max, _, load_residual) = evaluate(problem, &eval_op, control, delta, *d0, p, ws, par);
            previous_norm = f64::NAN;
            if op.profile {
                eprintln!(
                    "switch to the accurate operator: coarse_until/tol {:.2e}, residual/tol {:.2e}",
                    coarse_until / tol,
                    max / tol
                );
            }
        }
        if max <= tol {
            return Ok(NewtonRun {
                converged: true,
                iterations: iteration,
                residual: max,
            });
        }
        // Merit weights for this step: k_i on contacts (F in force units),
        // their mean elsewhere.
        let (mut k_sum, mut k_count) = (0.0, 0usize);
        for &k in &ws.stiffness {
            if k > 0.0 {
                k_sum += k;
                k_count += 1;
            }
        }
        if k_count == 0 && matches!(control, Control::Load(_)) {
            // Nothing in contact: lower the tread until the deepest summit
            // just touches, and carry on.
            let deepest = delta.iter().copied().fold(f64::NEG_INFINITY, f64::max);
            let lift = deepest - deepest.abs() * 1e-3 - f64::MIN_POSITIVE;
            delta.iter_mut().for_each(|d| *d -= lift);
            *d0 -= lift;
            (max, _, load_residual) = evaluate(problem, &eval_op, control, delta, *d0, p, ws, par);
            if ws.stiffness.iter().all(|&k| k <= 0.0) {
                break;
            }
            continue;
        }
        let k_mean = if k_count > 0 {
            k_sum / k_count as f64
        } else {
            1.0
        };
        let mut merit = load_residual * load_residual;
        for i in 0..n {
            let k = ws.stiffness[i];
            ws.weight[i] = if k > 0.0 { k } else { k_mean };
            merit += (ws.weight[i] * ws.mismatch[i]).powi(2);
            // The linear solve reads −R_i/k_i on active rows and moves no
            // inactive force: feed it the δ-form right-hand side.
            ws.residual[i] = if k > 0.0 { k * ws.mismatch[i] } else { 0.0 };
        }
        let norm = merit.sqrt();
        if previous_norm.is_finite() && previous_norm > 0.0 {
            let ratio = norm / previous_norm;
            let mut eta = 0.9 * ratio * ratio;
            let guard = 0.9 * ws.forcing * ws.forcing;
            if guard > 0.1 {
                eta = eta.max(guard);
            }
            ws.forcing = eta.clamp(1e-10, 0.1);
        }
        // Safeguard against over-solving (Kelley, "Iterative methods for
        // linear and nonlinear equations", §6.3): a linear residual far below
        // what the convergence test needs buys nothing.
        ws.forcing = ws.forcing.max((0.1 * tol / max).min(0.1));
        if tight {
            ws.forcing = 1e-10;
        }
        previous_norm = norm;
        let t_iter = std::time::Instant::now();
        let products_before = ws.krylov.products;
        let Some(mut d0_step) = newton_step(op, control, p, ws, options)? else {
            break;
        };
        d0_step = secant_corrections(problem, op, control, p, delta, d0_step, ws, options)?;
        let t_step = t_iter.elapsed().as_secs_f64();
        // δ changes by ΔP/k on contacts and, elsewhere, by what the new
        // forces and approach imply: Δδ_i = −F_i − (T ΔP)_i + Δδ0.
        // The direction only steers Newton: the Krylov operator will do.
        op.product.apply(&ws.step, &mut ws.coupled, par);
        for i in 0..n {
            let k = ws.stiffness[i];
            ws.depth_step[i] = if k > 0.0 {
                ws.step[i] / k
            } else {
                -ws.mismatch[i] - ws.coupled[i] + d0_step
            };
        }
        // Backtracking line search on the weighted merit.
        let mut alpha = 1.0;
        let accepted = loop {
            for ((t, &d), &step) in ws
                .trial_depth
                .iter_mut()
                .zip(delta.iter())
                .zip(&ws.depth_step)
            {
                *t = d + alpha * step;
            }
            let trial_d0 = *d0 + alpha * d0_step;
            let trial = std::mem::take(&mut ws.trial_depth);
            let (m, sq, rw) = evaluate(problem, &eval_op, control, &trial, trial_d0, p, ws, par);
            ws.trial_depth = trial;
            if sq <= (1.0 - 1e-4 * alpha) * merit || m <= tol {
                delta.copy_from_slice(&ws.trial_depth);
                *d0 = trial_d0;
                (max, load_residual) = (m, rw);
                break true;
            }
            alpha *= 0.5;
            if alpha < 1e-6 {
                break false;
            }
        };
        if !accepted {
            // Restore the state of the current iterate.
            (max, _, load_residual) = evaluate(problem, &eval_op, control, delta, *d0, p, ws, par);
            if cheap {
                // Let the accurate operator judge before giving up.
                cheap = false;
                eval_op = op.residual;
                (max, _, load_residual) =
                    evaluate(problem, &eval_op, control, delta, *d0, p, ws, par);
                previous_norm = f64::NAN;
                continue;
            }
            if ws.last_was_krylov && !tight {
                // An inexact direction may be too rough: retry solved tightly.
                tight = true;
                continue;
            }
            return Ok(NewtonRun {
                converged: false,
                iterations: iteration + 1,
                residual: max,
            });
        }
        if op.profile {
            eprintln!(
                "newton it {iteration}: active {}, eta {:.1e}, products {}, step {:.3} s, \
                 alpha {alpha}, total {:.3} s, residual/tol {:.2e}",
                ws.active.len(),
                ws.forcing,
                ws.krylov.products - products_before,
                t_step,
                t_iter.elapsed().as_secs_f64(),
                max / tol
            );
        }
        if alpha == 1.0 {
            tight = false;
        }
    }
    Ok(NewtonRun {
        converged: max <= tol,
        iterations: options.max_iterations,
        residual: max,
    })
}

/// Re-solves of a Newton step with secant stiffnesses, at most.
const SECANT_PASSES: usize = 12;

/// A contact's step crosses a kink of its law when the law's force change
/// differs from the tangent's prediction by more than this fraction of the
/// prediction, beyond what smooth curvature explains (`2|Δδ|/δ`).
const SECANT_TRIGGER: f64 = 0.05;

/// Corrects a Newton step for contacts whose step crosses a kink of their
/// law; returns the (possibly re-solved) approach increment.
///
/// A law is only piecewise smooth (a tabulated cap's nodes, a ramp's
/// ends). When a contact sits at a kink, its tangent `k` predicts the force
/// change of its step wrongly, by orders of magnitude when `k` jumps there,
/// and no step length along that direction decreases the merit: the solve
/// stalls just above the tolerance, at any tolerance. Such contacts (the
/// force change off the tangent's by more than [`SECANT_TRIGGER`] plus the
/// smooth-curvature allowance `2|Δδ|/δ`) get the secant of their law over
/// the step as stiffness, and the step is solved again; a contact that
/// flips between the two sides' slopes moves, from the second pass on, to
/// their geometric mean, which converges to the slope landing its step on
/// the kink. Smooth laws never trigger it.
#[allow(clippy::too_many_arguments)]
fn secant_corrections<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    op: &Ops<'_>,
    control: Control,
    p: &[f64],
    delta: &[f64],
    mut d0_step: f64,
    ws: &mut Workspace,
    options: &SolverOptions,
) -> Result<f64, SolveError> {
    let laws = problem.laws();
    for pass in 0..SECANT_PASSES {
        let mut changed = false;
        for i in 0..p.len() {
            let k = ws.stiffness[i];
            if !(k > 0.0 && delta[i] > 0.0) || ws.step[i] == 0.0 {
                continue;
            }
            let d = ws.step[i] / k;
            let actual = laws[i].force(delta[i] + d) - p[i];
            let allowance = SECANT_TRIGGER + 2.0 * d.abs() / delta[i];
            if (actual - ws.step[i]).abs() <= allowance * ws.step[i].abs() {
                continue;
            }
            let secant = actual / d;
            if secant > 0.0 && secant.is_finite() {
                let k_new = if pass == 0 {
                    secant
                } else {
                    (k * secant).sqrt()
                };
                ws.stiffness[i] = k_new;
                ws.residual[i] = k_new * ws.mismatch[i];
                changed = true;
            }
        }
        if !changed {
            break;
        }
        match newton_step(op, control, p, ws, options)? {
            Some(step) => d0_step = step,
            None => break,
        }
    }
    Ok(d0_step)
}

/// Bytes of a dense active solve: the matrix and the factorization scratch.
fn dense_bytes(na: usize) -> usize {
    na.saturating_mul(na)
        .saturating_mul(8)
        .saturating_add(na.saturating_mul(64))
}

/// One Newton direction into `ws.step`; returns the approach increment, or
/// `None` under load control when no asperity is in contact.
///
/// Rows out of contact (`k_i = 0`) read `ΔP_i = −R_i`. Active rows, divided
/// by `k_i`, form the symmetric system `(diag(1/k) + T_AA) ΔP_A − Δδ0 = b`,
/// bordered under load control by `Σ ΔP = W − Σ P`; it is solved for two
/// right-hand sides (`b` and `1`): by one dense factorization, or by two
/// Krylov solves to the current forcing term.
fn newton_step(
    op: &Ops<'_>,
    control: Control,
    p: &[f64],
    ws: &mut Workspace,
    options: &SolverOptions,
) -> Result<Option<f64>, SolveError> {
    let par = options.par;
    let n = p.len();
    ws.active.clear();
    for i in 0..n {
        if ws.stiffness[i] > 0.0 {
            ws.active.push(i);
        } else {
            ws.step[i] = -ws.residual[i];
        }
    }
    let na = ws.active.len();
    let load = match control {
        Control::Load(w) => Some(w),
        Control::Approach(_) => None,
    };
    ws.last_was_krylov = false;
    if na == 0 {
        return Ok(match load {
            Some(_) => None,
            None => Some(0.0),
        });
    }
    let fits = dense_bytes(na) <= options.dense_memory_limit_bytes;
    let use_krylov = match options.linear_solver {
        LinearSolver::Dense if !fits => {
            return Err(SolveError::InvalidInput(format!(
                "a dense solve of {na} active asperities needs {} bytes, over the \
                 dense_memory_limit_bytes of {}: use LinearSolver::Auto or Krylov",
                dense_bytes(na),
                options.dense_memory_limit_bytes
            )));
        }
        LinearSolver::Dense => false,
        LinearSolver::Krylov => true,
        LinearSolver::Auto => !fits || na >= options.krylov_min_active,
    };
    let moving: Vec<usize> = (0..n)
        .filter(|&j| ws.stiffness[j] <= 0.0 && ws.step[j] != 0.0)
        .collect();
    if use_krylov && let Some(tree) = op.tree {
        return Ok(krylov_step(op, tree, load, p, &moving, ws, par));
    }
    // Right-hand sides: b_i = −R_i/k_i − Σ_{j inactive} T_ij ΔP_j, and 1.
    let ncols = if load.is_some() { 2 } else { 1 };
    ws.rhs.resize_with(na, ncols, |_, _| 0.0);
    for (a, &i) in ws.active.iter().enumerate() {
        let coupling: f64 = moving
            .iter()
            .map(|&j| op.exact.coefficient(i, j) * ws.step[j])
            .sum();
        ws.rhs[(a, 0)] = -ws.residual[i] / ws.stiffness[i] - coupling;
        if ncols == 2 {
            ws.rhs[(a, 1)] = 1.0;
        }
    }
    solve_active(&op.exact, ws, na, ncols, par);
    let d0_step = match load {
        Some(w) => {
            let sum_p: f64 = p.iter().sum();
            let inactive: f64 = moving.iter().map(|&j| ws.step[j]).sum();
            let c = w - sum_p - inactive;
            let (mut sx, mut sy) = (0.0, 0.0);
            for a in 0..na {
                sx += ws.rhs[(a, 0)];
                sy += ws.rhs[(a, 1)];
            }
            if sy.abs() < f64::MIN_POSITIVE || !sy.is_finite() {
                return Ok(None);
            }
            (c - sx) / sy
        }
        None => 0.0,
    };
    for (a, &i) in ws.active.iter().enumerate() {
        let y = if ncols == 2 { ws.rhs[(a, 1)] } else { 0.0 };
        ws.step[i] = ws.rhs[(a, 0)] + y * d0_step;
    }
    Ok(Some(d0_step))
}

/// The Krylov version of the active solve in [`newton_step`]: the coupling
/// of the moving inactive forces is one interaction product, and the two
/// right-hand sides are two preconditioned Krylov solves to relative
/// residual `ws.forcing` (the `1` solve warm-started from the last step's).
#[allow(clippy::too_many_arguments)]
fn krylov_step(
    op: &Ops<'_>,
    tree: &FastBoussinesq,
    load: Option<f64>,
    p: &[f64],
    moving: &[usize],
    ws: &mut Workspace,
    par: Par,
) -> Option<f64> {
    ws.last_was_krylov = true;
    let n = p.len();
    let na = ws.active.len();
    let mut coupling = vec![0.0; n];
    if !moving.is_empty() {
        let mut x = vec![0.0; n];
        for &j in moving {
            x[j] = ws.step[j];
        }
        op.product.apply(&x, &mut coupling, par);
    }
    let b: Vec<f64> = ws
        .active
        .iter()
        .map(|&i| -ws.residual[i] / ws.stiffness[i] - coupling[i])
        .collect();
    let mut slot = vec![usize::MAX; n];
    for (a, &i) in ws.active.iter().enumerate() {
        slot[i] = a;
    }
    let t_pre = std::time::Instant::now();
    // Coarse clusters: at most ~1024 of them.
    let coarse_level = tree.depth().saturating_sub(1).min(5);
    let (leaves, leaf_coarse) = tree.clusters(coarse_level);
    let mut pre = Preconditioner::new(
        &op.exact,
        op.exact_positions(),
        &leaves,
        &leaf_coarse,
        &ws.active,
        &ws.stiffness,
        &slot,
        par,
    );
    let m = ActiveOperator {
        op: op.product,
        active: &ws.active,
        stiffness: &ws.stiffness,
        n,
        par,
    };
    let budget = 20 * na.max(50);
    let t_pre = t_pre.elapsed().as_secs_f64();
    let mut x = vec![0.0; na];
    let s1 = krylov::solve(&m, &mut pre, &b, &mut x, ws.forcing, budget);
    ws.krylov.products += s1.products;
    ws.krylov.breakdowns += s1.breakdowns;
    let d0_step = match load {
        Some(w) => {
            let ones = vec![1.0; na];
            let mut y: Vec<f64> = ws.active.iter().map(|&i| ws.ones_solution[i]).collect();
            // The step is x + y Δδ0, so its residual is r_x + Δδ0 r_y: y
            // needs ‖r_y‖ ≤ η ‖b‖ / |Δδ0| only, not a fixed tight tolerance.
            // Solve it to η first, then tighten while Δδ0 says so (CG
            // restarts from the current y). The constant right-hand side is
            // the smoothest vector, the hardest for the preconditioner:
            // over-solving it cost most of the Krylov products at N = 10⁵.
            let sum_p: f64 = p.iter().sum();
            let inactive: f64 = moving.iter().map(|&j| ws.step[j]).sum();
            let c = w - sum_p - inactive;
            let sx: f64 = x.iter().sum();
            let b_norm = b.iter().map(|v| v * v).sum::<f64>().sqrt();
            let ones_norm = (na as f64).sqrt();
            let mut rtol = ws.forcing;
            let mut s2 = KrylovStats::default();
            let d = loop {
                let s = krylov::solve(&m, &mut pre, &ones, &mut y, rtol, budget);
                s2.products += s.products;
                s2.breakdowns += s.breakdowns;
                let sy: f64 = y.iter().sum();
                if sy.abs() < f64::MIN_POSITIVE || !sy.is_finite() {
                    return None;
                }
                let d = (c - sx) / sy;
                let needed = ws.forcing * b_norm / (d.abs() * ones_norm);
                if rtol <= needed || rtol <= 1e-10 || s2.products >= budget {
                    break d;
                }
                rtol = (0.5 * needed).max(1e-10);
            };
            if op.profile {
                eprintln!(
                    "  krylov: preconditioner {t_pre:.3} s, products {} + {}, ones rtol {rtol:.1e}",
                    s1.products, s2.products
                );
            }
            ws.krylov.products += s2.products;
            ws.krylov.breakdowns += s2.breakdowns;
            ws.ones_solution.iter_mut().for_each(|v| *v = 0.0);
            for (a, &i) in ws.active.iter().enumerate() {
                ws.ones_solution[i] = y[a];
            }
            for (a, &i) in ws.active.iter().enumerate() {
                ws.step[i] = x[a] + y[a] * d;
            }
            d
        }
        None => {
            for (a, &i) in ws.active.iter().enumerate() {
                ws.step[i] = x[a];
            }
            0.0
        }
    };
    Some(d0_step)
}

/// Solves `(diag(1/k_A) + T_AA) X = rhs` in place: Cholesky when the matrix is
/// positive definite (the usual case), partial-pivoting LU when it is not
/// (T has a zero diagonal, so very stiff close neighbours can make it
/// indefinite).
fn solve_active(op: &Boussinesq<'_>, ws: &mut Workspace, na: usize, ncols: usize, par: Par) {
    if ws.matrix.nrows() < na {
        ws.matrix = Mat::zeros(na, na);
        let llt_req = llt::factor::cholesky_in_place_scratch::<f64>(na, par, Default::default());
        let lu_req = lu::factor::lu_in_place_scratch::<usize, f64>(na, na, par, Default::default())
            .or(lu::solve::solve_in_place_scratch::<usize, f64>(na, 2, par));
        ws.stack = MemBuffer::new(llt_req.or(lu_req));
    }
    fill_matrix(op, &ws.active, &ws.stiffness, &mut ws.matrix);
    let stack = MemStack::new(&mut ws.stack);
    let factored = {
        let a = ws.matrix.as_mut().submatrix_mut(0, 0, na, na);
        llt::factor::cholesky_in_place(a, Default::default(), par, stack, Default::default())
            .is_ok()
    };
    let rhs = ws.rhs.as_mut().submatrix_mut(0, 0, na, ncols);
    if factored {
        let l = ws.matrix.as_ref().submatrix(0, 0, na, na);
        llt::solve::solve_in_place(l, rhs, par, stack);
        return;
    }
    fill_matrix(op, &ws.active, &ws.stiffness, &mut ws.matrix);
    let a: MatMut<'_, f64> = ws.matrix.as_mut().submatrix_mut(0, 0, na, na);
    let (_, perm) = lu::factor::lu_in_place(
        a,
        &mut ws.perm[..na],
        &mut ws.perm_inv[..na],
        par,
        stack,
        Default::default(),
    );
    let f = ws.matrix.as_ref().submatrix(0, 0, na, na);
    lu::solve::solve_in_place(
        f,
        f,
        perm,
        ws.rhs.as_mut().submatrix_mut(0, 0, na, ncols),
        par,
        stack,
    );
}

fn fill_matrix(op: &Boussinesq<'_>, active: &[usize], stiffness: &[f64], matrix: &mut Mat<f64>) {
    let na = active.len();
    let mut m = matrix.as_mut().submatrix_mut(0, 0, na, na);
    for (b, &j) in active.iter().enumerate() {
        for (a, &i) in active.iter().enumerate() {
            m[(a, b)] = if a == b {
                1.0 / stiffness[i]
            } else {
                op.coefficient(i, j)
            };
        }
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use tyreroad_asperity::Sphere;
    use tyreroad_contact_law::{Material, PotentialLaw};

    use super::*;

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
