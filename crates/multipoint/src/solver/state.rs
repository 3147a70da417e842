//! The state a solve carries between its parts: the interaction products
//! (`Ops`) and the scratch vectors and matrices (`Workspace`), shared by the
//! Newton loop, the dense and Krylov steps and the secant corrections so
//! that none of them imports another's internals.

use faer::dyn_stack::MemBuffer;
use faer::{Mat, Par};

use super::near::NearField;
use crate::krylov::{KrylovStats, Operator};
use crate::{Boussinesq, FastBoussinesq};

/// The interaction products of one solve.
pub(super) struct Ops<'a> {
    pub(super) exact: Boussinesq<'a>,
    /// Residuals (and the final depths).
    pub(super) residual: Operator<'a>,
    /// Krylov products.
    pub(super) product: Operator<'a>,
    /// The cluster tree of the Krylov preconditioner.
    pub(super) tree: Option<&'a FastBoussinesq>,
    pub(super) positions: &'a [[f64; 2]],
    /// Print per-iteration timings to stderr (`TYREROAD_PROFILE` set).
    pub(super) profile: bool,
}

impl Ops<'_> {
    pub(super) fn exact_positions(&self) -> &[[f64; 2]] {
        self.positions
    }

    /// Whether the Krylov operator is a cheaper (lower-order) fast operator
    /// than the residual's.
    pub(super) fn product_is_cheaper(&self) -> bool {
        match (self.product, self.residual) {
            (Operator::Fast(lo), Operator::Fast(hi)) => lo.order() < hi.order(),
            _ => false,
        }
    }

    /// The residual level above which the cheap operator may evaluate
    /// residuals: 100 × the largest force residual its error causes,
    /// `max_i k_i |(T̃p)_i − (Tp)_i|` at the state `evaluate` left in `ws`
    /// (forces `p`, stiffnesses, cheap products in `ws.u`), with one
    /// accurate product. Below that level the cheap residual would mislead
    /// the iteration, so the accurate one takes over.
    pub(super) fn coarse_until(&self, p: &[f64], ws: &mut Workspace, par: Par) -> f64 {
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
    /// The near-pair correction of the distributed interaction, at the
    /// radii of the last evaluated state; `None` for the point kernel.
    pub(super) near: Option<NearField>,
    /// Active-set slot of each asperity (`usize::MAX` if inactive), for
    /// adding the near pairs to the dense matrix.
    pub(super) slot: Vec<usize>,
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
            near: None,
            slot: vec![usize::MAX; n],
        }
    }
}
