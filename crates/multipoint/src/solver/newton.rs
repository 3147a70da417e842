//! The Newton loop: residual evaluation, the step, the backtracking line
//! search on the weighted merit, and the switch from the cheap to the
//! accurate interaction operator.

use faer::Par;
use tyreroad_contact_law::ContactLaw;

use super::dense::newton_step;
use super::options::{Control, SolverOptions};
use super::secant::secant_corrections;
use super::state::{Ops, Workspace};
use crate::krylov::Operator;
use crate::{Problem, SolveError};

/// Bounds of the Levenberg–Marquardt shift, relative to the mean active
/// compliance: below the smallest it changes no digit of a well-conditioned
/// step; above the largest the step is a vanishing multiple of `−F`.
const MIN_DAMPING: f64 = 1e-8;
const MAX_DAMPING: f64 = 1e4;

/// Re-solves the step with `diag(1/k) + T_AA + μ I`, `μ = λ · mean(1/k_A)`:
/// the shift bounds the step along the (nearly) singular directions that
/// overlapping contacts give `diag(1/k) + T` (docs/theory.md §3), where the
/// plain step alternates in sign and grows. The shifted system is solved by
/// giving the active rows the stiffnesses `k/(1 + μk)` (compliance `1/k +
/// μ`) with the same δ-mismatch right-hand side; the laws' own stiffnesses
/// come back afterwards, so the step still moves δ by `ΔP/k`.
fn damped_step(
    op: &Ops<'_>,
    control: Control,
    p: &[f64],
    lambda: f64,
    ws: &mut Workspace,
    options: &SolverOptions,
) -> Result<Option<f64>, SolveError> {
    let (mut compliance, mut count) = (0.0, 0usize);
    for &k in &ws.stiffness {
        if k > 0.0 {
            compliance += 1.0 / k;
            count += 1;
        }
    }
    if count == 0 {
        return Ok(Some(0.0));
    }
    let mu = lambda * compliance / count as f64;
    ws.law_stiffness.copy_from_slice(&ws.stiffness);
    for i in 0..p.len() {
        let k = ws.law_stiffness[i];
        if k > 0.0 {
            ws.stiffness[i] = k / (1.0 + mu * k);
            ws.residual[i] = ws.stiffness[i] * ws.mismatch[i];
        }
    }
    let step = newton_step(op, control, p, ws, options);
    std::mem::swap(&mut ws.stiffness, &mut ws.law_stiffness);
    step
}

pub(super) struct NewtonRun {
    pub(super) converged: bool,
    pub(super) iterations: usize,
    pub(super) residual: f64,
}

/// State at `(δ, d0)`: forces `p = P^law(δ)` with their stiffnesses, the
/// interaction displacements `u = T p`, the mismatch `F = δ + u − δ0 + H`
/// (into `ws.mismatch`) and the true residuals `R_i = P_i − P_i^law(δ0 − H_i
/// − u_i)` (into `ws.residual`). Returns the max-norm of `R` and of the load
/// equation, the weighted merit `Σ (w_i F_i)² + R_W²`, and `R_W`.
#[allow(clippy::too_many_arguments)]
pub(super) fn evaluate<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    interaction: &Operator<'_>,
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
    if let Some(near) = &mut ws.near {
        near.update(laws, problem.positions(), p, delta);
        near.add(p, &mut ws.u);
    }
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
pub(super) fn newton<L: ContactLaw + Sync>(
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
        if let Some(lambda) = ws.damping {
            match damped_step(op, control, p, lambda, ws, options)? {
                Some(step) => d0_step = step,
                None => break,
            }
        }
        let t_step = t_iter.elapsed().as_secs_f64();
        // δ changes by ΔP/k on contacts and, elsewhere, by what the new
        // forces and approach imply: Δδ_i = −F_i − (T ΔP)_i + Δδ0.
        // The direction only steers Newton: the Krylov operator will do.
        op.product.apply(&ws.step, &mut ws.coupled, par);
        if let Some(near) = &ws.near {
            near.add(&ws.step, &mut ws.coupled);
        }
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
            if let Some(lambda) = ws.damping
                && lambda < MAX_DAMPING
            {
                ws.damping = Some(lambda * 10.0);
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
            if let Some(lambda) = ws.damping {
                ws.damping = Some((lambda * 0.1).max(MIN_DAMPING));
            }
        }
    }
    Ok(NewtonRun {
        converged: max <= tol,
        iterations: options.max_iterations,
        residual: max,
    })
}
