//! What a solve is asked for and how it may go about it: the control, the
//! linear solver, the tuning options and the coarse start's hierarchy, with
//! their checks.

use faer::Par;

use crate::{FastOptions, SolveError};

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

/// How the forces of two asperities couple through the half-space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Interaction {
    /// The point kernel `T_ij = f / r_ij`, `f = (1 − ν²)/(π E)` (Cesbron et
    /// al. 2006). Close summits whose contact patches overlap can make
    /// `diag(1/k) + T_AA` indefinite and the load path fold
    /// (docs/theory.md §3).
    Point,
    /// Near pairs, `r_ij < near_factor · (a_i + a_j)` with `a` the radii of
    /// the laws' local contacts at the current state, couple through the
    /// mutual compliance of their Hertz pressure distributions,
    /// `f · g(r_ij; a_i, a_j)` ([`mutual_compliance`](crate::mutual_compliance)),
    /// blended smoothly into the point kernel between `near_factor` and
    /// `2 near_factor`; farther pairs keep the point kernel (and the fast
    /// operator). `g` is bounded at `r = 0` and within `(a_i² + a_j²)/(10 r²)`
    /// of `1/r` beyond the patches (docs/theory.md §3).
    Distributed {
        /// Where the blend into the point kernel starts, in units of
        /// `a_i + a_j`; ≥ 1 so that overlapping patches are always near.
        near_factor: f64,
    },
}

/// When asperities whose contact patches overlap are merged into one body
/// (a cluster) and solved as such (docs/theory.md §3, "Clusters").
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Clusters {
    /// Never: the point-force model as the paper has it. A folding load
    /// path ends in [`SolveError::NotConverged`].
    Off,
    /// Only when every other recovery has failed: a solve that converges
    /// without clusters returns the same bits as with [`Self::Off`]; one that
    /// does not is solved with its overlapping contacts merged and says so
    /// ([`Recovery::Clustered`](crate::Recovery)).
    #[default]
    OnFailure,
    /// Always: after a converged solve, overlapping contacts are merged and
    /// the problem solved again, until no two bodies' patches overlap (the
    /// `clustered` rung of the fidelity ladder). Without overlaps the
    /// solution is that of [`Self::Off`].
    Always,
}

impl Interaction {
    /// The distributed kernel with the default blend, from `2 (a_i + a_j)`
    /// to `4 (a_i + a_j)` (where `g` differs from `1/r` by ≤ 0.3 %).
    pub const DISTRIBUTED: Self = Self::Distributed { near_factor: 2.0 };
}

/// Tuning of the solver. The defaults converge from a cold start on every
/// layout in the test suite.
#[derive(Clone, Copy, Debug)]
pub struct SolverOptions {
    /// Convergence when every residual `|P_i − P_i^law(δ_i)|` and the load
    /// residual are below `tolerance × force scale` (the imposed load, or the
    /// uncoupled total force under approach control). A solve that stalls
    /// above it is still [`Convergence::Converged`](crate::Convergence) when
    /// the load equation meets it and every force residual is within it plus
    /// its own rounding floor `k_i · 8ε · (|δ0| + |H_i| + |u_i|)` (what double
    /// precision can resolve of `P^law(δ0 − H_i − u_i)`; docs/theory.md §3).
    /// At most [`MAX_TOLERANCE`].
    pub tolerance: f64,
    /// The largest relative force residual a solve that stagnates (its line
    /// search fails after every recovery) may return with, marked
    /// [`Convergence::Stagnated`](crate::Convergence); above it the solve
    /// fails with [`SolveError::NotConverged`]. The load equation must still
    /// meet [`Self::tolerance`]. Default 1e-8; a value below `tolerance`
    /// counts as `tolerance` (set it so to accept strict convergence only).
    /// At most [`MAX_TOLERANCE`].
    pub acceptable_tolerance: f64,
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
    /// ([`FastBoussinesq`](crate::FastBoussinesq)) instead of the exact
    /// `O(N · nnz)` sum: residuals at [`Self::fast_operator`] accuracy,
    /// Krylov products at a lower order. Never used by the dense path. Default 1500 (from there the
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
    /// The coupling kernel (see [`Interaction`]). The dense path, the
    /// Krylov products and the residuals all use it; the coarse start and
    /// the Krylov preconditioner keep the point kernel (they only steer).
    pub interaction: Interaction,
    /// When overlapping contacts are merged into clusters (see
    /// [`Clusters`]; default [`Clusters::OnFailure`]).
    pub clusters: Clusters,
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
    pub(super) fn targets(&self, n: usize) -> Vec<usize> {
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
            acceptable_tolerance: 1e-8,
            max_iterations: 60,
            max_load_steps: 200,
            par: Par::Seq,
            linear_solver: LinearSolver::Auto,
            dense_memory_limit_bytes: 1 << 30,
            krylov_min_active: 1200,
            fast_operator_min_n: 1500,
            fast_operator: FastOptions::default(),
            coarse_start_min_n: 4096,
            interaction: Interaction::Point,
            clusters: Clusters::OnFailure,
        }
    }
}

/// The loosest [`SolverOptions::tolerance`] and
/// [`SolverOptions::acceptable_tolerance`] a solve accepts. Both bound each
/// asperity's force residual by a fraction of the *total* load: past about
/// `1 / N` of it, a start far from the solution already passes for
/// converged (a 200-asperity road "converged" at 3e-2 with every force 0).
pub const MAX_TOLERANCE: f64 = 1e-3;

/// The smallest non-zero imposed load (N) a solve accepts: far below any
/// physical load, and above where the laws' arithmetic (`δ ~ W^(2/3)` near
/// 1e-100 m) underflows and Newton cannot converge.
pub const MIN_LOAD: f64 = 1e-100;

pub(super) fn check_control(control: Control) -> Result<(), SolveError> {
    match control {
        Control::Load(w) if !(w.is_finite() && w >= 0.0) => Err(SolveError::InvalidInput(format!(
            "imposed load must be finite and ≥ 0 N, got {w:e}"
        ))),
        Control::Load(w) if w > 0.0 && w < MIN_LOAD => Err(SolveError::InvalidInput(format!(
            "imposed load {w:e} N is below the {MIN_LOAD:e} N a solve resolves (0 for no load)"
        ))),
        Control::Approach(d) if !d.is_finite() => Err(SolveError::InvalidInput(format!(
            "imposed approach must be finite, got {d:e}"
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
pub(super) fn residual_options(fast: &FastOptions) -> FastOptions {
    let (hi, lo) = (fast.order as f64, krylov_order(fast.order) as f64);
    let grow = (hi / lo).powi(2).max(1.0);
    FastOptions {
        order: fast.order,
        leaf_size: (fast.leaf_size as f64 * grow).round() as usize,
    }
}

/// Chebyshev order of the Krylov products for residual order `order`: the
/// Jacobian only steers Newton, so about half the digits do.
pub(super) fn krylov_order(order: usize) -> usize {
    (order / 2 + 1).clamp(4, order.max(4))
}

pub(super) fn check_options(options: &SolverOptions) -> Result<(), SolveError> {
    let in_range = |t: f64| t > 0.0 && t <= MAX_TOLERANCE;
    if !in_range(options.tolerance) || options.max_iterations == 0 {
        return Err(SolveError::InvalidInput(format!(
            "solver options need tolerance in (0, {MAX_TOLERANCE:e}] and max_iterations ≥ 1, \
             got {:e} and {}",
            options.tolerance, options.max_iterations
        )));
    }
    if !in_range(options.acceptable_tolerance) {
        return Err(SolveError::InvalidInput(format!(
            "solver options need acceptable_tolerance in (0, {MAX_TOLERANCE:e}], got {:e}",
            options.acceptable_tolerance
        )));
    }
    if let Interaction::Distributed { near_factor } = options.interaction
        && !(near_factor.is_finite() && near_factor >= 1.0)
    {
        return Err(SolveError::InvalidInput(format!(
            "solver options need Interaction::Distributed's near_factor finite and ≥ 1, \
             got {near_factor}"
        )));
    }
    Ok(())
}
