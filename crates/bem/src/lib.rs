//! Reference full-grid boundary-element (BEM) solver for the frictionless
//! normal contact of a rigid rough surface against an elastic half-space.
//!
//! It is the reference against which the multipoint model of the workspace is
//! validated, and the local solver of the two-scale approach (the real shape
//! of one asperity carrying a given force). It depends only on
//! `tyreroad-core` (material, grid and field, parallelism).
//!
//! # Conventions
//!
//! SI units throughout (m, Pa, N).
//!
//! * The **rigid surface** (the road) is a [`HeightMap`]: heights `h_i` (m,
//!   positive upward) at the centres of the `nx × ny` cells of a regular
//!   [`Grid`] (cell `(i, j)` at `(x0 + i·dx, y0 + j·dy)`, stored row-major at
//!   index `j·nx + i`).
//! * The **elastic half-space** (the tyre), of modulus `E*` = E/(1 − ν²)
//!   ([`Material`]), comes down from above. Its undeformed surface is a plane;
//!   at zero approach it touches the highest point `z_top = max h` (reported
//!   as [`BemSolution::reference_height`]), so the initial gap is
//!   `g0_i = z_top − h_i ≥ 0`.
//! * The **approach** `δ` is the rigid downward displacement of the body from
//!   that position: its undeformed surface lies at `z = z_top − δ`.
//! * The **contact pressure** `p_i ≥ 0` (Pa) is uniform on each cell; the
//!   **elastic displacement** `u_i` of the body's surface at the cell
//!   centres is positive into the body (upward) and `u = K p`.
//! * The **gap** is `g_i = g0_i + u_i − δ`. The contact conditions (a linear
//!   complementarity problem) are
//!   `p_i ≥ 0,  g_i ≥ 0,  p_i · g_i = 0` for every cell,
//!   plus `Σ p_i · dx·dy = W` under load control ([`Control::Load`], δ unknown)
//!   or δ given under displacement control ([`Control::Approach`], W output).
//! * **Contact area**: number of cells with `p > 0` times `dx·dy`.
//!
//! # Influence coefficients (Love 1929)
//!
//! A uniform pressure `p` on the rectangle `|x| ≤ a, |y| ≤ b` (`a = dx/2`,
//! `b = dy/2`) displaces the surface of the half-space at `(x, y)` by
//!
//! ```text
//! u(x, y) = p/(π E*) · [F(x+a, y+b) − F(x+a, y−b) − F(x−a, y+b) + F(x−a, y−b)]
//! F(ξ, η) = ξ · asinh(η/|ξ|) + η · asinh(ξ/|η|)
//! ```
//!
//! (the antiderivative of `1/r`, i.e. Johnson 1985, eq. 3.25, written without
//! cancellation; see [`love_influence`]). At the centre of a square cell of
//! side `s` it is `4 ln(1+√2) s p / (π E*)`; far away it tends to the
//! Boussinesq point load `p dx dy / (π E* r)`. The influence matrix
//! `K_ij = u(x_i − x_j, y_i − y_j)` with unit pressure is a 2D Toeplitz
//! (convolution) operator, symmetric and positive definite.
//!
//! # Convolution by FFT
//!
//! *Non-periodic* (default, an isolated contact on an infinite half-space):
//! the coefficients of all offsets `−(n−1) … n−1` are laid out in
//! wrap-around order on an FFT grid of `M ≥ 2n − 1` points per axis (the
//! smallest even 2·3·5·7-smooth length, 1024 for n = 512) and the pressure is
//! zero padded to it; the circular convolution then equals the linear one on
//! the `nx × ny` block exactly (no wrap-around). The kernel spectrum is
//! computed once per [`Solver`]; each product `K p` costs one forward and one
//! inverse real 2D FFT (`realfft` rows, `rustfft` columns, rows and columns
//! spread over a rayon pool when [`BemOptions::par`] asks for one).
//!
//! *Periodic* ([`BemOptions::periodic`]): the height map is one period
//! `Lx × Ly = nx·dx × ny·dy`. The kernel is the Love kernel summed over all
//! periodic images, applied on the `nx × ny` FFT grid. Its spectrum at the
//! discrete wave vector `q` follows from Poisson summation:
//!
//! ```text
//! K̂(q) = Σ_G 2 S(kx dx/2) S(ky dy/2) / (E* |k|),  k = q + G,
//! G = (2πm/dx, 2πn/dy),  S(t) = sin t / t,   |m|, |n| ≤ 32,
//! ```
//!
//! i.e. the continuum half-space response `2/(E*|k|)` to the cell-wise
//! constant pressure, sampled at the cell centres (the aliases `G` converge
//! as an alternating series; with half weight on the last alias the
//! truncation is below 10⁻⁶ relative).
//! The `q = 0` term, the mean displacement of a half-space under a periodic
//! load of non-zero mean, is infinite: it is set to zero, so in periodic mode
//! **the elastic displacement has zero mean** and the approach is measured
//! from there: the mean gap (mean separation of the two surfaces) is
//! `mean(g) = mean(g0) − δ`. Under load control that is well posed (full
//! contact gives `δ = mean(g0)` for any load); under displacement control
//! `δ` must stay below `mean(g0)`, else no finite pressure exists and an
//! error is returned.
//!
//! # Constrained conjugate gradient (Polonsky & Keer 1999)
//!
//! The solver minimises the complementary energy `½ pᵀ K p + pᵀ(g0 − δ)` over
//! `p ≥ 0` (with `Σ p dx dy = W` under load control) by the conjugate gradient
//! restricted to the current contact set `Ic = {p > 0}`:
//!
//! 1. `u = K p`; `g = g0 + u`; under load control `δ = mean_{Ic} g`
//!    (this is the Lagrange multiplier of the load constraint, and the
//!    approach); `g ← g − δ`.
//! 2. `G = Σ_{Ic} g²`; search direction `t = g + β t_old` on `Ic`, 0 elsewhere,
//!    with `β = G/G_old`, or `β = 0` after an iteration that re-entered points.
//! 3. `r = K t`; under load control `r ← r − mean_{Ic} r`;
//!    step `τ = Σ_{Ic} g t / Σ_{Ic} r t`.
//! 4. `p ← max(p − τ t, 0)` on `Ic`.
//! 5. Polonsky–Keer projection: points out of contact that penetrate
//!    (`p = 0`, `g < 0`) re-enter with `p = −τ g > 0`; if any did, the
//!    conjugacy is reset (`β = 0` at the next iteration).
//! 6. Load control: `p ← p · W / (Σ p dx dy)` (the load constraint).
//!
//! Two FFT convolutions per iteration (`K p` and `K t`), or one: when an
//! iteration neither clamps nor re-enters a point, the update
//! `p ← s (p − τ t)` is linear and `u ← s (u − τ K t)` is carried over
//! (recomputed by FFT at least every 8 iterations and always before
//! returning). No allocation inside the loop (all buffers live in the
//! [`Solver`]). The load-controlled start is the uniform
//! pressure `W/(nx ny dx dy)` (as in the paper); the displacement-controlled
//! start is a pressure proportional to the rigid interference
//! `max(δ − g0, 0)`. [`Solver::solve_from`] warm-starts from a given field.
//!
//! ## Stopping criterion and invariants
//!
//! At the top of each iteration (with `u = K p` exact for the current `p`)
//! the relative complementarity residual
//!
//! ```text
//! residual = max( max_{p>0} |g|,  max_{p=0} max(−g, 0) ) / max(max |u|, |δ|)
//! ```
//!
//! is compared with [`BemOptions::tolerance`]; the returned solution is that
//! state, so on success
//!
//! * `p ≥ 0` exactly (projection),
//! * `g ≥ −tol · scale` everywhere and `|g| ≤ tol · scale` on the contact, so
//!   `|p g| ≤ tol · p_max · scale` (`scale = max(max |u|, |δ|)`),
//! * under load control `Σ p dx dy = W` to rounding (≈ 10⁻¹⁵ relative: the
//!   rescaling of step 6 is the last operation on `p`),
//! * `u` is exactly `K p` (to FFT rounding, ≈ 10⁻¹⁴ relative).
//!
//! Failure to reach the tolerance within [`BemOptions::max_iterations`] is
//! [`BemError::NotConverged`], with the iterations and the residual reached.
//!
//! # Accuracy (see `tests/validation.rs` and `docs/bem.md`)
//!
//! | case | grid | measured |
//! |---|---|---|
//! | Hertz paraboloid, `a` ≈ 42 cells, radius √(A/π) | 256² | +0.35 % |
//! | Hertz approach `δ = a²/R` | 256² | −2·10⁻⁵ |
//! | Hertz peak pressure | 256² | +3·10⁻⁵ |
//! | flat punch `W = 2 E* a δ`, `a` = 40 cells | 160² | −0.29 % |
//! | periodic sinusoid, full contact, 64 cells per wavelength | 64 × 8 | 4·10⁻⁴ of p* |
//!
//! # Example
//!
//! A sphere (R = 5 mm) pressed with 1 N into rubber, compared with Hertz:
//!
//! ```
//! use tyreroad_bem::{BemOptions, Control, Grid, Material, Solver, Sphere, spherical_caps};
//!
//! # fn main() -> Result<(), tyreroad_bem::BemError> {
//! let grid = Grid::centered(65, 65, 4e-5, 4e-5)?; // 2.6 mm square, summit on a cell centre
//! let ball = Sphere { centre: [0.0, 0.0], radius: 5e-3, summit: 0.0 };
//! let surface = spherical_caps(&grid, &[ball], -5e-3)?;
//! let material = Material::new(6.54e6, 0.5)?;
//! let mut solver = Solver::new(&grid, &material, &BemOptions::default())?;
//! let s = solver.solve(&surface, Control::Load(1.0))?;
//! assert!((s.force - 1.0).abs() < 1e-12);
//! let a_hertz = (3.0 * 1.0 * 5e-3 / (4.0 * material.reduced_modulus())).cbrt();
//! assert!((s.equivalent_radius() / a_hertz - 1.0).abs() < 0.05);
//! assert!((s.approach / (a_hertz * a_hertz / 5e-3) - 1.0).abs() < 0.02);
//! assert!(s.pressure.iter().all(|&p| p >= 0.0));
//! # Ok(())
//! # }
//! ```
//!
//! # References
//!
//! * A. E. H. Love (1929), The stress produced in a semi-infinite solid by
//!   pressure on part of the boundary, Phil. Trans. R. Soc. A 228, 377–420.
//! * K. L. Johnson (1985), Contact Mechanics, Cambridge University Press.
//! * I. A. Polonsky, L. M. Keer (1999), A numerical method for solving rough
//!   contact problems based on the multi-level multi-summation and conjugate
//!   gradient techniques, Wear 231, 206–219.
//! * H. M. Stanley, T. Kato (1997), An FFT-based method for rough surface
//!   contact, J. Tribol. 119, 481–485.

mod error;
mod grid;
mod influence;
mod solver;

pub use error::BemError;
pub use grid::{HeightMap, Sphere, nearest_labels, spherical_caps};
pub use influence::{cells_at_same_fft_cost, love_influence};
pub use solver::{BemOptions, BemSolution, Control, MAX_TOLERANCE, RegionContact, Solver, solve};
pub use tyreroad_core::{Field, Grid, Material, Par};
