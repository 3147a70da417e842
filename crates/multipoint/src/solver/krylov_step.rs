//! The glue between a Newton step and the matrix-free solvers of
//! `crate::krylov`: the active operator, the preconditioner, and the two
//! inexact solves of a load-controlled step.

use faer::Par;

use super::state::Ops;
use super::state::Workspace;
use crate::FastBoussinesq;
use crate::krylov::{self, ActiveOperator, KrylovStats, Preconditioner};

/// The Krylov version of the active solve in [`newton_step`](super::dense::newton_step): the coupling
/// of the moving inactive forces is one interaction product, and the two
/// right-hand sides are two preconditioned Krylov solves to relative
/// residual `ws.forcing` (the `1` solve warm-started from the last step's).
#[allow(clippy::too_many_arguments)]
pub(super) fn krylov_step(
    op: &Ops<'_>,
    tree: &FastBoussinesq,
    load: Option<f64>,
    p: &[f64],
    moving: &[usize],
    ws: &mut Workspace,
    par: Par,
) -> Option<f64> {
    ws.last_was_krylov = true;
    ws.used_krylov = true;
    let n = p.len();
    let na = ws.active.len();
    let mut coupling = vec![0.0; n];
    if !moving.is_empty() {
        let mut x = vec![0.0; n];
        for &j in moving {
            x[j] = ws.step[j];
        }
        op.product.apply(&x, &mut coupling, par);
        if let Some(near) = &ws.near {
            near.add(&x, &mut coupling);
        }
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
        near_pairs: ws.near.as_ref().map_or(&[], |near| &near.pairs),
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
