//! The Newton workspace and the step's linear algebra: the active set, the
//! right-hand sides, and the dense in-place Cholesky (LU when indefinite).

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::linalg::lu::partial_pivoting as lu;
use faer::{Mat, MatMut, Par};

use super::krylov_step::krylov_step;
use super::newton::Ops;
use super::options::{Control, LinearSolver, SolverOptions};
use crate::krylov::KrylovStats;
use crate::{Boussinesq, SolveError};

pub(super) struct Workspace {
    pub(super) u: Vec<f64>,
    pub(super) residual: Vec<f64>,
    pub(super) stiffness: Vec<f64>,
    pub(super) step: Vec<f64>,
    pub(super) active: Vec<usize>,
    pub(super) matrix: Mat<f64>,
    pub(super) rhs: Mat<f64>,
    pub(super) perm: Vec<usize>,
    pub(super) perm_inv: Vec<usize>,
    pub(super) stack: MemBuffer,
    /// Krylov: `1/Σ`-solve of the previous step (warm start), per asperity.
    pub(super) ones_solution: Vec<f64>,
    /// Krylov: inexact Newton forcing term of the next step.
    pub(super) forcing: f64,
    /// Krylov: products spent, for diagnostics.
    pub(super) krylov: KrylovStats,
    /// Whether the last Newton direction came from a Krylov solve.
    pub(super) last_was_krylov: bool,
    /// Whether any Newton direction of this solve came from a Krylov solve.
    pub(super) used_krylov: bool,
    /// Levenberg–Marquardt shift of the step's matrix, relative to the mean
    /// active compliance `1/k`; `None` for plain Newton.
    pub(super) damping: Option<f64>,
    /// The law stiffnesses while a damped step is solved with shifted ones.
    pub(super) law_stiffness: Vec<f64>,
    /// `F_i = δ_i + u_i − δ0 + H_i`: how far the iterate's δ is from the one
    /// its forces imply.
    pub(super) mismatch: Vec<f64>,
    /// Weights of `F` in the line-search merit, fixed during one step.
    pub(super) weight: Vec<f64>,
    /// The Newton change of δ.
    pub(super) depth_step: Vec<f64>,
    /// `T · ΔP`, and the line search's trial δ.
    pub(super) coupled: Vec<f64>,
    pub(super) trial_depth: Vec<f64>,
}

impl Workspace {
    pub(super) fn new(n: usize) -> Self {
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
            used_krylov: false,
            damping: None,
            law_stiffness: vec![0.0; n],
            mismatch: vec![0.0; n],
            weight: vec![1.0; n],
            depth_step: vec![0.0; n],
            coupled: vec![0.0; n],
            trial_depth: vec![0.0; n],
        }
    }
}

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

pub(super) fn fill_matrix(
    op: &Boussinesq<'_>,
    active: &[usize],
    stiffness: &[f64],
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
}
