//! Newton–Raphson on the N nonlinear equations, globalised by a line search
//! and, when that is not enough, by load (or approach) stepping; when both
//! fail, by the recoveries of docs/theory.md §3 (cold restart, dense
//! fallback, Levenberg–Marquardt, a continuation accepting stagnated steps)
//! and the acceptance of a stagnated state.
//!
//! The pieces: `options` (what is asked), `start` (where Newton starts),
//! `newton` (the loop and its globalisation), `secant` (steps across law
//! kinks), `dense` (the workspace and the dense step) and `krylov_step`
//! (the matrix-free step).

mod cluster;
mod correction;
mod dense;
mod krylov_step;
mod near;
mod newton;
mod options;
mod secant;
mod start;
mod state;

use tyreroad_contact_law::ContactLaw;

use crate::krylov::Operator;
use faer::Par;

use crate::{
    Boussinesq, Convergence, FastBoussinesq, FastOptions, Problem, Recovery, Solution, SolveError,
};
pub use correction::{PairCorrection, solve_corrected};
use near::NearField;
use newton::{evaluate, newton};
pub(crate) use options::CoarseLevels;
pub use options::{
    Clusters, Control, Interaction, LinearSolver, MAX_TOLERANCE, MIN_LOAD, SolverOptions,
};
use options::{check_control, check_options, krylov_order, residual_options};
use start::{coarse_start, uncoupled_start};
use state::{Ops, Workspace};

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
    let result = solve_attempts(problem, control, options, initial, levels, &[]);
    let result = cluster::refine(problem, control, options, initial, levels, result)
        .and_then(|s| checked(s, control, options));
    if std::env::var_os("TYREROAD_PROFILE").is_some() {
        match &result {
            Ok(s) => eprintln!(
                "solve: {:?} via {:?}, {} iterations, {} load steps, residual {:.3e}",
                s.convergence, s.recovery, s.iterations, s.load_steps, s.residual
            ),
            Err(e) => eprintln!("solve: failed: {e}"),
        }
    }
    result
}

/// `s` if it is finite ([`finite`]) and, under load control, its forces
/// carry the load to [`LOAD_MISMATCH_FLOOR`] or the acceptable tolerance,
/// whichever is looser, once the asperities its final state leaves out of
/// contact are zeroed: a state that met a loose tolerance only because
/// each force residual is measured against the total load (a start with
/// every force nil, on a road of many asperities) must not pass for a
/// solution. Else [`SolveError::NotConverged`] with the load's relative
/// mismatch.
/// The relative load mismatch [`checked`] always lets through: the forces
/// the final state zeroes (out of contact, each within the force tolerance
/// of its law) may add up to more than a tight tolerance over a road of
/// thousands of asperities, and a millionth of the load is no wrong answer.
const LOAD_MISMATCH_FLOOR: f64 = 1e-6;

fn checked(s: Solution, control: Control, options: &SolverOptions) -> Result<Solution, SolveError> {
    let s = finite(s)?;
    if let Control::Load(w) = control
        && w > 0.0
    {
        let accept = options.acceptable_tolerance.max(options.tolerance);
        let mismatch = (s.total_force() - w).abs() / w;
        if mismatch > accept.max(LOAD_MISMATCH_FLOOR) {
            return Err(SolveError::NotConverged {
                iterations: s.iterations,
                load_steps: s.load_steps,
                residual: mismatch,
            });
        }
    }
    Ok(s)
}

/// `s`, or [`SolveError::NotFinite`] naming its first number that is not
/// finite (a residual of NaN included).
fn finite(s: Solution) -> Result<Solution, SolveError> {
    let first = |name: &str, values: &[f64]| {
        values
            .iter()
            .position(|v| !v.is_finite())
            .map(|i| format!("{name} {i} = {}", values[i]))
    };
    let what = first("force", &s.forces)
        .or_else(|| first("depth", &s.depths))
        .or_else(|| (!s.approach.is_finite()).then(|| format!("approach = {}", s.approach)))
        .or_else(|| s.residual.is_nan().then(|| "residual = NaN".to_string()));
    match what {
        Some(what) => Err(SolveError::NotFinite(what)),
        None => Ok(s),
    }
}

/// [`solve_with`] without the profile's summary line and the clusters, the
/// coupling corrected by the `fixed` pairs `(i, j, C_ij)` (each unordered
/// pair once; empty for the plain kernel).
fn solve_attempts<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    initial: Option<&Solution>,
    levels: &CoarseLevels,
    fixed: &[(usize, usize, f64)],
) -> Result<Solution, SolveError> {
    check_control(control)?;
    check_options(options)?;
    let n = problem.len();
    if let Some(s) = initial
        && (s.forces.len() != n || s.depths.len() != n)
    {
        return Err(SolveError::InvalidInput(format!(
            "warm start has {} forces and {} depths for {n} asperities",
            s.forces.len(),
            s.depths.len()
        )));
    }
    let mut ws = Workspace::new(n);
    ws.near = NearField::new(
        options.interaction,
        problem.positions(),
        problem.material().boussinesq_factor(),
        fixed,
    );
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
            (Some(t), true) => Operator::Fast(t),
            _ => Operator::Exact(exact),
        },
        product: match &tree_lo {
            Some(t) => Operator::Fast(t),
            None => Operator::Exact(exact),
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
            vec![0.0; n],
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
    let cold_start = |ws: &mut Workspace| -> (Vec<f64>, Vec<f64>, f64) {
        ws.u.iter_mut().for_each(|u| *u = 0.0);
        let (p, mut d0) = uncoupled_start(problem, control, &ws.u);
        if let Control::Approach(target) = control {
            d0 = target;
        }
        let mut delta: Vec<f64> = problem.gaps().iter().map(|h| d0 - h).collect();
        if n >= options.coarse_start_min_n
            && let Some((coarse_delta, coarse_d0)) = coarse_start(problem, control, options, levels)
        {
            delta = coarse_delta;
            d0 = coarse_d0;
        }
        (p, delta, d0)
    };
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
    let finish =
        |ws: &mut Workspace, p: Vec<f64>, d0: f64, iterations, steps, residual: f64, recovery| {
            let u = displacements(problem, &op, ws.near.as_mut(), &p, d0, par);
            let mut s = Solution::finish(problem, p, d0, iterations, steps, residual, u);
            s.recovery = recovery;
            s
        };
    if direct.converged {
        return Ok(finish(
            &mut ws,
            p,
            d0,
            iterations,
            1,
            direct.residual / scale,
            Recovery::None,
        ));
    }
    // The best full-target state of the failed runs, for the recoveries.
    let mut best = Attempt::new(&p, &delta, d0, direct.residual);

    match continuation(
        problem,
        &op,
        control,
        scale,
        first_touch,
        options,
        None,
        &mut ws,
        &mut iterations,
    )? {
        Continued::Converged {
            forces,
            approach,
            steps,
            residual,
            ..
        } => Ok(finish(
            &mut ws,
            forces,
            approach,
            iterations,
            steps + 1,
            residual / scale,
            Recovery::Continuation,
        )),
        Continued::Failed { steps } => {
            let report = NotConverged {
                iterations,
                load_steps: steps,
            };
            let mut recoveries = Recoveries {
                problem,
                op: &op,
                control,
                scale,
                tol,
                options,
                ws: &mut ws,
                iterations,
                best: &mut best,
            };
            // A warm start far from this step's solution can lead Newton
            // into a region it cannot leave; the cold start may not.
            if initial.is_some() {
                let (p, delta, d0) = cold_start(recoveries.ws);
                if let Some(s) = recoveries.run(p, delta, d0, None, Recovery::ColdRestart)? {
                    return Ok(s);
                }
            }
            // Inexact Krylov directions may be what stalls.
            if recoveries.ws.used_krylov {
                let (p, delta, d0) = recoveries.best.state();
                if let Some(s) = recoveries.run(p, delta, d0, None, Recovery::DenseFallback)? {
                    return Ok(s);
                }
            }
            let (p, delta, d0) = recoveries.best.state();
            if let Some(s) =
                recoveries.run(p, delta, d0, Some(INITIAL_DAMPING), Recovery::Regularized)?
            {
                return Ok(s);
            }
            // The stall is usually the same at every load from some fraction
            // of the target on: continue through it, taking load steps that
            // stagnate below the acceptable tolerance, to a full-target state
            // that the acceptance below judges.
            let accept = options.acceptable_tolerance.max(options.tolerance);
            let lenient = continuation(
                problem,
                &op,
                control,
                scale,
                first_touch,
                options,
                Some(accept),
                recoveries.ws,
                &mut recoveries.iterations,
            )?;
            if let Continued::Converged {
                forces,
                delta,
                approach,
                residual,
                ..
            } = lenient
                && residual < recoveries.best.residual
            {
                *recoveries.best = Attempt {
                    p: forces,
                    delta,
                    d0: approach,
                    residual,
                    recovery: Recovery::Continuation,
                };
            }
            recoveries.accept_stagnated(report)
        }
    }
}

/// The interaction displacements `u` of the final forces `p` (at approach
/// `d0`): the residual operator's, plus the near pairs' correction with
/// the radii at the depths `δ0 − H − u` (two passes, for the laws whose
/// radius reads the depth).
fn displacements<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    op: &Ops<'_>,
    near: Option<&mut NearField>,
    p: &[f64],
    d0: f64,
    par: Par,
) -> Vec<f64> {
    let mut u = vec![0.0; p.len()];
    op.residual.apply(p, &mut u, par);
    if let Some(near) = near {
        let point = u.clone();
        let mut depth = vec![0.0; p.len()];
        for _ in 0..2 {
            for ((d, h), u) in depth.iter_mut().zip(problem.gaps()).zip(&u) {
                *d = d0 - h - u;
            }
            near.update(problem.laws(), problem.positions(), p, &depth);
            u.copy_from_slice(&point);
            near.add(p, &mut u);
        }
    }
    u
}

/// The Levenberg–Marquardt shift a regularised run starts with, relative to
/// the mean active compliance.
const INITIAL_DAMPING: f64 = 1e-3;

/// What the failed attempts report when no recovery succeeds.
struct NotConverged {
    iterations: usize,
    load_steps: usize,
}

/// A full-target state (forces, interpenetrations, approach) and its
/// max-norm residual in force units.
struct Attempt {
    p: Vec<f64>,
    delta: Vec<f64>,
    d0: f64,
    residual: f64,
    recovery: Recovery,
}

impl Attempt {
    fn new(p: &[f64], delta: &[f64], d0: f64, residual: f64) -> Self {
        Self {
            p: p.to_vec(),
            delta: delta.to_vec(),
            d0,
            residual,
            recovery: Recovery::None,
        }
    }

    fn state(&self) -> (Vec<f64>, Vec<f64>, f64) {
        (self.p.clone(), self.delta.clone(), self.d0)
    }
}

/// The recoveries tried after the first run and the continuation failed,
/// each keeping the best state reached.
struct Recoveries<'a, 'o, L> {
    problem: &'a Problem<L>,
    op: &'a Ops<'o>,
    control: Control,
    scale: f64,
    tol: f64,
    options: &'a SolverOptions,
    ws: &'a mut Workspace,
    iterations: usize,
    best: &'a mut Attempt,
}

impl<L: ContactLaw + Sync> Recoveries<'_, '_, L> {
    /// One Newton run from `(p, δ, δ0)`, plain or damped; the solution if it
    /// converged, else `None` (the best state updated).
    fn run(
        &mut self,
        mut p: Vec<f64>,
        mut delta: Vec<f64>,
        mut d0: f64,
        damping: Option<f64>,
        recovery: Recovery,
    ) -> Result<Option<Solution>, SolveError> {
        let dense;
        let options = if recovery == Recovery::DenseFallback {
            dense = SolverOptions {
                linear_solver: LinearSolver::Auto,
                krylov_min_active: usize::MAX,
                ..*self.options
            };
            &dense
        } else {
            self.options
        };
        self.ws.damping = damping;
        let run = newton(
            self.problem,
            self.op,
            self.control,
            &mut p,
            &mut delta,
            &mut d0,
            self.tol,
            options,
            self.ws,
        );
        self.ws.damping = None;
        let run = run?;
        self.iterations += run.iterations;
        if run.converged {
            let u = displacements(
                self.problem,
                self.op,
                self.ws.near.as_mut(),
                &p,
                d0,
                self.options.par,
            );
            let mut s = Solution::finish(
                self.problem,
                p,
                d0,
                self.iterations,
                1,
                run.residual / self.scale,
                u,
            );
            s.recovery = recovery;
            return Ok(Some(s));
        }
        if run.residual < self.best.residual {
            *self.best = Attempt {
                p,
                delta,
                d0,
                residual: run.residual,
                recovery,
            };
        }
        Ok(None)
    }

    /// The best state reached, balanced in load, as a solution when it meets
    /// the tolerance up to rounding ([`Convergence::Converged`]) or the
    /// acceptable tolerance ([`Convergence::Stagnated`]); else the failure.
    fn accept_stagnated(self, report: NotConverged) -> Result<Solution, SolveError> {
        let Self {
            problem,
            op,
            control,
            scale,
            tol,
            options,
            ws,
            iterations,
            best,
        } = self;
        let par = options.par;
        let mut p = std::mem::take(&mut best.p);
        let mut delta = std::mem::take(&mut best.delta);
        let mut d0 = best.d0;
        let (max, load_residual, within_rounding) = balance_load(
            problem, op, control, tol, &mut p, &mut delta, &mut d0, ws, par,
        );
        let acceptable = options.acceptable_tolerance.max(options.tolerance) * scale;
        let load_ok = load_residual.abs() <= tol;
        let convergence = if load_ok && within_rounding {
            Convergence::Converged
        } else if load_ok && max <= acceptable {
            Convergence::Stagnated {
                residual: max / scale,
            }
        } else {
            return Err(SolveError::NotConverged {
                iterations,
                load_steps: report.load_steps,
                // The full target's residual: the continuation's last one
                // was at a fraction of the load.
                residual: best.residual.min(max) / scale,
            });
        };
        let u = displacements(problem, op, ws.near.as_mut(), &p, d0, par);
        let mut s = Solution::finish(
            problem,
            p,
            d0,
            iterations.max(report.iterations),
            1,
            max / scale,
            u,
        );
        s.convergence = convergence;
        s.recovery = best.recovery;
        Ok(s)
    }
}

/// Under load control, shifts δ and δ0 of the active contacts together
/// (which leaves the mismatch `F` alone but for the coupling's change) until
/// `Σ P = W` within `tol`, a few scalar Newton steps at most; then reports the
/// max-norm force residual, the load residual, and whether every force
/// residual is within `tol` plus its rounding floor. A stagnated iterate's
/// load equation is off by the line search's last unfinished step; the force
/// balance is the one equation the user reads directly.
#[allow(clippy::too_many_arguments)]
fn balance_load<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    op: &Ops<'_>,
    control: Control,
    tol: f64,
    p: &mut [f64],
    delta: &mut [f64],
    d0: &mut f64,
    ws: &mut Workspace,
    par: Par,
) -> (f64, f64, bool) {
    let (mut max, _, mut load_residual) =
        evaluate(problem, &op.residual, control, delta, *d0, p, ws, par);
    if let Control::Load(_) = control {
        for _ in 0..8 {
            if load_residual.abs() <= 0.5 * tol {
                break;
            }
            let k_sum: f64 = ws.stiffness.iter().filter(|&&k| k > 0.0).sum();
            if !(k_sum > 0.0) {
                break;
            }
            let shift = -load_residual / k_sum;
            for (d, &k) in delta.iter_mut().zip(&ws.stiffness) {
                if k > 0.0 {
                    *d += shift;
                }
            }
            *d0 += shift;
            (max, _, load_residual) =
                evaluate(problem, &op.residual, control, delta, *d0, p, ws, par);
        }
    }
    let eps = 8.0 * f64::EPSILON;
    let gaps = problem.gaps();
    let within_rounding = (0..p.len()).all(|i| {
        let floor =
            ws.stiffness[i] * eps * (d0.abs() + gaps[i].abs() + ws.u[i].abs()) + eps * p[i].abs();
        ws.residual[i].abs() <= tol + floor
    });
    (max, load_residual, within_rounding)
}

/// The outcome of the load (approach) continuation.
enum Continued {
    Converged {
        forces: Vec<f64>,
        delta: Vec<f64>,
        approach: f64,
        steps: usize,
        residual: f64,
    },
    Failed {
        steps: usize,
    },
}

/// Continuation from first contact: s ∈ (0, 1] scales the load (or the
/// approach beyond first touch); each step starts from the last converged
/// state scaled to the new target. With `accept`, a step whose Newton run
/// stops above the tolerance but within `accept` (relative) counts as done.
#[allow(clippy::too_many_arguments)]
fn continuation<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    op: &Ops<'_>,
    control: Control,
    scale: f64,
    first_touch: f64,
    options: &SolverOptions,
    accept: Option<f64>,
    ws: &mut Workspace,
    iterations: &mut usize,
) -> Result<Continued, SolveError> {
    let n = problem.len();
    let start_d0 = first_touch;
    let target_at = |s: f64| match control {
        Control::Load(w) => Control::Load(w * s),
        Control::Approach(d) => Control::Approach(start_d0 + s * (d - start_d0)),
    };
    let (mut s, mut step) = (0.0_f64, 1.0 / 16.0);
    let (mut p_ok, mut d0_ok) = (vec![0.0; n], start_d0);
    let mut delta_ok: Vec<f64> = problem.gaps().iter().map(|h| start_d0 - h).collect();
    let mut p = vec![0.0; n];
    let mut delta = delta_ok.clone();
    let mut d0;
    let mut steps = 0;
    let mut last_residual = f64::INFINITY;
    while s < 1.0 {
        if steps >= options.max_load_steps || step < 1e-9 {
            return Ok(Continued::Failed { steps });
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
            op,
            sub,
            &mut p,
            &mut delta,
            &mut d0,
            options.tolerance * sub_scale,
            options,
            ws,
        )?;
        *iterations += run.iterations;
        last_residual = run.residual;
        let accepted = accept.is_some_and(|a| run.residual <= a * sub_scale);
        if run.converged || accepted {
            s = s_next;
            p_ok.copy_from_slice(&p);
            delta_ok.copy_from_slice(&delta);
            d0_ok = d0;
            step = (step * 2.0).min(1.0);
        } else {
            step *= 0.25;
        }
    }
    Ok(Continued::Converged {
        forces: p_ok,
        delta: delta_ok,
        approach: d0_ok,
        steps,
        residual: last_residual,
    })
}
