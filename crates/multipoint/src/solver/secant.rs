//! Secant corrections of a Newton step at the kinks of piecewise-smooth laws.

use tyreroad_contact_law::ContactLaw;

use super::dense::newton_step;
use super::options::{Control, SolverOptions};
use super::state::{Ops, Workspace};
use crate::{Problem, SolveError};

/// Re-solves of a Newton step with secant stiffnesses, at most.
pub(super) const SECANT_PASSES: usize = 12;

/// A contact's step crosses a kink of its law when the law's force change
/// differs from the tangent's prediction by more than this fraction of the
/// prediction, beyond what smooth curvature explains (`2|Δδ|/δ`).
pub(super) const SECANT_TRIGGER: f64 = 0.05;

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
pub(super) fn secant_corrections<L: ContactLaw + Sync>(
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
