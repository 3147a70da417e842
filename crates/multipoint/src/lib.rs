//! Multipoint contact of N rigid asperities with an elastic half-space.
//!
//! # Equations (Cesbron et al. 2006, eq. 2; docs/theory.md §3)
//!
//! Summit `i` at horizontal position `(x_i, y_i)` has an initial gap `H_i ≥ 0`
//! to the undeformed tread. With `δ0` the rigid approach of the tread,
//!
//! ```text
//! P_i = P_i^law(δ_i),   δ_i = δ0 − H_i − u_i,   u_i = Σ_{j≠i} T_ij P_j,
//! T_ij = (1 − ν²) / (π E r_ij)            (Boussinesq)
//! ```
//!
//! and either `δ0` is imposed ([`Control::Approach`]) or the total load
//! `Σ P_i = W` ([`Control::Load`], `δ0` unknown). An asperity with `δ_i ≤ 0`
//! carries no force.
//!
//! [`solve_corrected`] adds a caller's fixed sparse symmetric correction
//! ([`PairCorrection`], entries `C_ij`, `i ≠ j`) to the kernel, `T + C`,
//! in every residual, dense matrix and Krylov product: numbers the caller
//! computed (e.g. from each asperity's own pressure field), which the solver
//! does not interpret; clusters are off in such a solve.
//!
//! With [`Interaction::Distributed`] ([`SolverOptions::interaction`]), pairs
//! closer than `2c (a_i + a_j)` (`a` the radii of the laws' local contacts
//! at the current state) couple instead through the mutual compliance of
//! their Hertz pressure distributions, blended into the point kernel
//! between `c` and `2c`:
//!
//! ```text
//! T_ij = f [ b g(r_ij; a_i, a_j) + (1 − b) / r_ij ],   f = (1 − ν²)/(π E),
//! g = ∫∫ q_i q_j / |x − y|   (symmetric, bounded, → 1/r as r/a grows)
//! ```
//!
//! ([`mutual_compliance`]); the radii are re-evaluated at every residual and
//! the Jacobian omits their derivative (docs/theory.md §3). It bounds the
//! coupling of very close pairs but does not make `diag(1/k) + T_AA`
//! definite where patches overlap by more than about 0.6 of their radius.
//!
//! # Method
//!
//! Newton–Raphson whose iterate is the set of local interpenetrations `δ_i`
//! (with `P_i = P_i^law(δ_i)`) and `δ0`, on the equations
//! `F_i = δ_i + u_i − δ0 + H_i = 0` (and `Σ P_i = W`). On the asperities in
//! contact, scaled by `k_i = dP/dδ`, the Jacobian is the symmetric
//! `(diag(1/k) + T_AA)`, bordered by the load equation under load control and
//! solved for two right-hand sides (`−F_A` and `1`; the border then gives
//! `Δδ0` in closed form); the others follow explicitly. Moving along each
//! law's curve rather than its tangent, forces can neither go negative nor
//! overshoot, so coupled layouts converge in a few iterations. Only
//! asperities in contact enter the linear algebra. A backtracking line search
//! on `Σ (k_i F_i)² + R_W²` globalises each step; if that fails, the load (or
//! approach) is applied in adaptive steps from first contact. Convergence is
//! declared on the force-form residuals `R_i = P_i − P_i^law(δ0 − H_i − u_i)`
//! and the load equation, max-norm, relative to the force scale
//! ([`SolverOptions::tolerance`]). When Newton and the continuation stall,
//! recoveries follow (a cold restart, dense steps, a Levenberg–Marquardt
//! shift, a continuation through stagnated steps); a state within the
//! tolerance up to each residual's rounding floor is
//! [`Convergence::Converged`], one within
//! [`SolverOptions::acceptable_tolerance`] with the load balanced is
//! returned as [`Convergence::Stagnated`], [`Solution::recovery`] says which
//! attempt produced it (docs/theory.md §3); a solve that does not get there
//! says so with its iterations and residual ([`SolveError::NotConverged`]).
//!
//! Two ways to solve the active system ([`LinearSolver`]):
//!
//! - **dense**: one in-place Cholesky factorization (LU when the matrix is
//!   indefinite — `T` has a zero diagonal, so very stiff close neighbours can
//!   make it so), `O(n_A³)` time and `8 n_A²` bytes;
//! - **Krylov** (matrix-free Newton–Krylov): preconditioned conjugate
//!   gradients on `M = diag(1/k_A) + T_AA`, switching to restarted GMRES on
//!   non-positive curvature `pᵀMp ≤ 0`. The preconditioner is two-level
//!   additive Schwarz: Cholesky of `M`'s diagonal blocks on the quadtree's
//!   leaves (spatial clusters of ~48 summits) plus a coarse Galerkin
//!   correction on piecewise-constant functions of ≤ 1024 larger clusters.
//!   The linear solves are inexact (Eisenstat–Walker forcing terms, choice 2,
//!   `η ≤ 0.1`, safeguarded against over-solving the last step), so early
//!   iterations are cheap; the load border's second solve (`M y = 1`) is
//!   solved only as tightly as the approach increment needs. The Newton
//!   loop still stops only when the nonlinear residual meets the same
//!   tolerance as the dense path, and a step whose line search fails is
//!   recomputed with `η = 1e-10`.
//!
//! [`LinearSolver::Auto`] (the default) goes dense for fewer than
//! [`SolverOptions::krylov_min_active`] (1200, the measured crossover)
//! active asperities when the matrix fits
//! [`SolverOptions::dense_memory_limit_bytes`] (1 GiB), Krylov otherwise. No
//! `n_A × n_A` matrix is ever allocated above that limit: an explicit
//! [`LinearSolver::Dense`] request over it fails with
//! [`SolveError::InvalidInput`].
//!
//! The interaction products `T·x` are exact `O(N · nnz(x))` sums
//! ([`Boussinesq`]) on the dense path and for small problems. From
//! [`SolverOptions::fast_operator_min_n`] summits the Krylov path uses the fast
//! multipole operator [`FastBoussinesq`] (Chebyshev-interpolated far field,
//! exact near field, `O(N)`): residuals at [`SolverOptions::fast_operator`]
//! accuracy (order 10, relative error ≈ 1e-10) and Krylov products at about
//! half the digits (order 6). While the residual is still far above the
//! error of the order-6 operator (100 × its effect on the residual, measured
//! once per solve), Newton evaluates its residuals and line searches with
//! that cheaper operator too; the accurate one takes over below and judges
//! convergence. Newton thus solves the system of the order-10 operator to
//! the tolerance; its forces differ from the exact-kernel ones by about the
//! operator's error (measured: 5e-9 relative at N = 900–2500).
//!
//! # Large patches: the coarse start
//!
//! From [`SolverOptions::coarse_start_min_n`] asperities (4096), a cold solve
//! starts from nested coarse problems on clusters of neighbouring asperities
//! (about N/10, N/100, … clusters, each cluster's law the sum of its members'
//! laws with the self-compliance of its own load), the coarsest solved from
//! the uncoupled state, each finer level and finally the asperities reached
//! by one Jacobi step. On a large patch the coupling's bowl-shaped
//! displacement (tens of millimetres at N = 10⁵) dwarfs the
//! interpenetrations (a tenth of a millimetre), and the uncoupled start cost
//! Newton 21 iterations with short, backtracked steps there; from the coarse
//! start it takes 9 (6 at N = 10⁴). See docs/performance.md.
//!
//! Setting the environment variable `TYREROAD_PROFILE` prints one line of
//! timings and Krylov products per Newton iteration to stderr.
//!
//! # Example
//!
//! ```
//! use tyreroad_asperity::Sphere;
//! use tyreroad_contact_law::{Material, PotentialLaw};
//! use tyreroad_multipoint::{solve, Control, Problem, SolverOptions};
//!
//! let rubber = Material::new(6.54e6, 0.5)?;
//! let ball = PotentialLaw::sphere(Sphere::new(5e-3)?, rubber);
//! // Three balls in a row, 10 mm apart, the middle one 0.05 mm lower.
//! let problem = Problem::new(
//!     vec![[-0.01, 0.0], [0.0, 0.0], [0.01, 0.0]],
//!     vec![0.0, 5e-5, 0.0],
//!     vec![ball.clone(), ball.clone(), ball],
//!     rubber,
//! )?;
//! let solution = solve(&problem, Control::Load(30.0), &SolverOptions::default())?;
//! assert!((solution.total_force() - 30.0).abs() < 1e-9);
//! assert!((solution.forces[0] - solution.forces[2]).abs() < 1e-9);
//! assert!(solution.forces[1] < solution.forces[0]);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod asperity_set;
mod coarse;
mod fast;
mod interaction;
mod krylov;
pub mod layouts;
mod problem;
mod solution;
mod solver;

pub use asperity_set::AsperitySet;
pub use fast::{FastBoussinesq, FastOptions};
pub use interaction::{Boussinesq, hertz_potential, mutual_compliance};
pub use problem::Problem;
pub use solution::{Convergence, Recovery, Solution, overlapping_contacts, pressure_map};
pub use solver::{
    Clusters, Control, Interaction, LinearSolver, MAX_TOLERANCE, MIN_LOAD, PairCorrection,
    SolverOptions, solve, solve_corrected, solve_from,
};
pub use tyreroad_contact_law::ContactLaw;
pub use tyreroad_core::Par;
pub use tyreroad_core::{Field, Grid};

/// What can go wrong in a multipoint solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum SolveError {
    /// The problem or the request is malformed.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// Two summits share a horizontal position (`1/r` is infinite).
    #[error("summits {first} and {second} coincide: the Boussinesq coupling 1/r is infinite")]
    CoincidentSummits {
        /// The first summit's index.
        first: usize,
        /// The second summit's index.
        second: usize,
    },
    /// Newton did not reach the tolerance, nor, after every recovery, the
    /// acceptable tolerance.
    #[error(
        "Newton-Raphson did not converge: {iterations} iterations over {load_steps} load steps, \
         relative residual {residual:.3e}"
    )]
    NotConverged {
        /// Iterations spent, all load steps included.
        iterations: usize,
        /// Load steps tried.
        load_steps: usize,
        /// Best max-norm residual reached at the full load (or approach),
        /// relative to the force scale.
        residual: f64,
    },
    /// The solve ended on numbers that are not finite: a load or approach
    /// past what the laws' powers hold in floating point (an approach of
    /// 1e160 m gives an infinite force), never returned as converged.
    #[error(
        "the solution is not finite ({0}): the load or approach is past what the laws hold in \
         floating point"
    )]
    NotFinite(String),
}
