//! Newton–Raphson on the N nonlinear equations, globalised by a line search
//! and, when that is not enough, by load (or approach) stepping.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::lu::partial_pivoting as lu;
use faer::{Mat, MatMut, Par};
use tyreroad_contact_law::ContactLaw;

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
    /// preferred to the dense factorization even when it would fit (the
    /// measured crossover on the project machine, docs/performance.md).
    pub krylov_min_active: usize,
    /// The number of asperities from which the Krylov path computes every
    /// interaction product `T·x` with the fast multipole operator
    /// ([`FastBoussinesq`]) instead of the exact `O(N²)` sum: residuals at
    /// [`Self::fast_operator`] accuracy, Krylov products at a lower order.
    /// Never used by the dense path. `usize::MAX` disables it.
    pub fast_operator_min_n: usize,
    /// Accuracy of the fast residual products (order 10: relative error
    /// ≈ 1e-10). Newton converges on the residual of that operator, so the
    /// forces differ from the exact-kernel solution by about this error
    /// times the problem's conditioning.
    pub fast_operator: FastOptions,
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
            krylov_min_active: 2000,
            fast_operator_min_n: 8192,
            fast_operator: FastOptions::default(),
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
        let fo = FastOptions {
            order: if use_fast {
                options.fast_operator.order
            } else {
                2
            },
            ..options.fast_operator
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
        tree: tree.as_ref(),
        positions: problem.positions(),
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
}

impl Ops<'_> {
    fn exact_positions(&self) -> &[[f64; 2]] {
        self.positions
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
    op: &Ops<'_>,
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
    op.residual.apply(p, &mut ws.u, par);
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
    let (mut max, _, mut load_residual) = evaluate(problem, op, control, delta, *d0, p, ws, par);
    // Eisenstat–Walker (choice 2, γ = 0.9, α = 2) forcing terms for Krylov.
    ws.forcing = 0.1;
    let mut tight = false;
    let mut previous_norm = f64::NAN;
    for iteration in 0..options.max_iterations {
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
            (max, _, load_residual) = evaluate(problem, op, control, delta, *d0, p, ws, par);
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
        if tight {
            ws.forcing = 1e-10;
        }
        previous_norm = norm;
        let Some(d0_step) = newton_step(op, control, p, ws, options)? else {
            break;
        };
        // δ changes by ΔP/k on contacts and, elsewhere, by what the new
        // forces and approach imply: Δδ_i = −F_i − (T ΔP)_i + Δδ0.
        op.residual.apply(&ws.step, &mut ws.coupled, par);
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
            let (m, sq, rw) = evaluate(problem, op, control, &trial, trial_d0, p, ws, par);
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
            (max, _, load_residual) = evaluate(problem, op, control, delta, *d0, p, ws, par);
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
    let mut x = vec![0.0; na];
    let s1 = krylov::solve(&m, &mut pre, &b, &mut x, ws.forcing, budget);
    ws.krylov.products += s1.products;
    ws.krylov.breakdowns += s1.breakdowns;
    let d0_step = match load {
        Some(w) => {
            let ones = vec![1.0; na];
            let mut y: Vec<f64> = ws.active.iter().map(|&i| ws.ones_solution[i]).collect();
            let s2 = krylov::solve(&m, &mut pre, &ones, &mut y, ws.forcing.min(1e-3), budget);
            ws.krylov.products += s2.products;
            ws.krylov.breakdowns += s2.breakdowns;
            ws.ones_solution.iter_mut().for_each(|v| *v = 0.0);
            for (a, &i) in ws.active.iter().enumerate() {
                ws.ones_solution[i] = y[a];
            }
            let sum_p: f64 = p.iter().sum();
            let inactive: f64 = moving.iter().map(|&j| ws.step[j]).sum();
            let c = w - sum_p - inactive;
            let sx: f64 = x.iter().sum();
            let sy: f64 = y.iter().sum();
            if sy.abs() < f64::MIN_POSITIVE || !sy.is_finite() {
                return None;
            }
            let d = (c - sx) / sy;
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
