//! The Newton workspace and the step's linear algebra: the active set, the
//! right-hand sides, and the dense in-place Cholesky (LU when indefinite).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::lu::partial_pivoting as lu;
use faer::{Mat, MatMut, Par};

use super::krylov_step::krylov_step;
use super::near::NearField;
use super::options::{Control, LinearSolver, SolverOptions};
use super::state::{Ops, Workspace};
use crate::{Boussinesq, SolveError};

/// Bytes of a dense active solve: the matrix and the factorization scratch.
pub(super) fn dense_bytes(na: usize) -> usize {
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
pub(super) fn newton_step(
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
    if let Some(near) = &ws.near {
        for (a, &i) in ws.active.iter().enumerate() {
            ws.slot[i] = a;
        }
        let moving_step = |j: usize| {
            if ws.stiffness[j] <= 0.0 {
                ws.step[j]
            } else {
                0.0
            }
        };
        for &(i, j, c) in &near.pairs {
            if ws.slot[i] != usize::MAX {
                ws.rhs[(ws.slot[i], 0)] -= c * moving_step(j);
            }
            if ws.slot[j] != usize::MAX {
                ws.rhs[(ws.slot[j], 0)] -= c * moving_step(i);
            }
        }
        for &i in &ws.active {
            ws.slot[i] = usize::MAX;
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

/// Solves `(diag(1/k_A) + T_AA) X = rhs` in place: Cholesky when the matrix is
/// positive definite (the usual case), partial-pivoting LU when it is not
/// (T has a zero diagonal, so very stiff close neighbours can make it
/// indefinite).
pub(super) fn solve_active(
    op: &Boussinesq<'_>,
    ws: &mut Workspace,
    na: usize,
    ncols: usize,
    par: Par,
) {
    if ws.matrix.nrows() < na {
        ws.matrix = Mat::zeros(na, na);
        let llt_req = llt::factor::cholesky_in_place_scratch::<f64>(na, par, Default::default());
        let lu_req = lu::factor::lu_in_place_scratch::<usize, f64>(na, na, par, Default::default())
            .or(lu::solve::solve_in_place_scratch::<usize, f64>(na, 2, par));
        ws.stack = MemBuffer::new(llt_req.or(lu_req));
    }
    fill_matrix(
        op,
        &ws.active,
        &ws.stiffness,
        ws.near.as_ref(),
        &mut ws.slot,
        &mut ws.matrix,
    );
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
    fill_matrix(
        op,
        &ws.active,
        &ws.stiffness,
        ws.near.as_ref(),
        &mut ws.slot,
        &mut ws.matrix,
    );
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

/// The active matrix `diag(1/k_A) + T_AA` (plus the near pairs' `C_AA`
/// under the distributed interaction) into `ws.matrix`.
pub(super) fn fill_matrix(
    op: &Boussinesq<'_>,
    active: &[usize],
    stiffness: &[f64],
    near: Option<&NearField>,
    slot: &mut [usize],
    matrix: &mut Mat<f64>,
) {
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
    if let Some(near) = near {
        for (a, &i) in active.iter().enumerate() {
            slot[i] = a;
        }
        for &(i, j, c) in &near.pairs {
            let (a, b) = (slot[i], slot[j]);
            if a != usize::MAX && b != usize::MAX {
                m[(a, b)] += c;
                m[(b, a)] += c;
            }
        }
        for &i in active {
            slot[i] = usize::MAX;
        }
    }
}
