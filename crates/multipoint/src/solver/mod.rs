//! Newton–Raphson on the N nonlinear equations, globalised by a line search
//! and, when that is not enough, by load (or approach) stepping.
//!
//! The pieces: `options` (what is asked), `start` (where Newton starts),
//! `newton` (the loop and its globalisation), `secant` (steps across law
//! kinks), `dense` (the workspace and the dense step) and `krylov_step`
//! (the matrix-free step).

mod dense;
mod krylov_step;
mod newton;
mod options;
mod secant;
mod start;

use tyreroad_contact_law::ContactLaw;

use crate::krylov::Interaction;
use crate::{Boussinesq, FastBoussinesq, FastOptions, Problem, Solution, SolveError};
use dense::Workspace;
use newton::{Ops, newton};
pub(crate) use options::CoarseLevels;
pub use options::{Control, LinearSolver, SolverOptions};
use options::{check_control, check_options, krylov_order, residual_options};
use start::{coarse_start, uncoupled_start};

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
