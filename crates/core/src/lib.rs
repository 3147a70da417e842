//! The shared core of the tyreroad layers: what every layer may use and
//! none should define twice. It depends on no other tyreroad crate.
//!
//! SI units throughout (m, Pa, N, Hz). Nothing panics on user input: every
//! check returns a [`CoreError`] naming the invalid quantity (the indexing
//! accessors [`Field::at`] and [`Field::row`] panic on an index outside the
//! grid, as slice indexing does; [`Field::get`] does not).
//!
//! # Material ([`Material`])
//!
//! The linear elastic, isotropic half-space: Young's modulus `E > 0`,
//! Poisson's ratio `−1 < ν ≤ 0.5`, both finite, and the derived `E*` and
//! `1/(π E*)` finite and positive. Plane-strain (reduced)
//! modulus `E* = E / (1 − ν²)`; Boussinesq's surface compliance
//! `(1 − ν²)/(π E) = 1/(π E*)`: a point force `F` displaces the surface at
//! distance `r` by `F / (π E* r)`.
//!
//! # Grid and field ([`Grid`], [`Field`])
//!
//! `nx × ny` cells of `dx × dy`, cell `(i, j)` centred at
//! `origin + (i·dx, j·dy)` (y up), values stored row-major at `j·nx + i`.
//! Invariants: sizes ≥ 1, at most [`MAX_CELLS`] cells, spacings finite and
//! positive with a finite extent and a finite, positive cell area, origin
//! and farthest cell centre finite; a field has one value per cell, finite where
//! valid, NaN where its optional mask says invalid.
//!
//! # Spectra ([`spectrum`])
//!
//! Base-10 one-third-octave bands (IEC 61260-1): band `k` about a reference
//! `r` has the centre `r·10^(k/10)` and edges `centre·10^(∓1/20)`.
//! Welch's averaged periodogram with a periodic Hann window,
//! `S(f_m) = c_m |X_m|² / (fs Σ w²)` (`c_m = 1` at DC and Nyquist, 2
//! between), so that `Σ S df` is the window-weighted mean square; band
//! levels `L = 10 log10(P_band / ref²)`. The plain one-sided periodogram
//! `P_k = c_k |X_k|²/N²` sums to the mean square (Parseval).
//!
//! # PCHIP ([`pchip`])
//!
//! Knot slopes of a monotone piecewise-cubic Hermite interpolant: the
//! Fritsch–Butland harmonic mean with shape-preserving ends, or
//! Fritsch–Carlson with a prescribed first slope; both keep the cubic
//! monotone wherever the data are.
//!
//! # Validators ([`validate`])
//!
//! `finite`, `positive` (> 0), `non_negative` (≥ 0), `in_range`: each returns
//! the value or a [`CoreError::InvalidValue`] naming the quantity; NaN fails
//! them all.
//!
//! # Parallelism ([`Par`])
//!
//! The one parallelism type (faer's), passed by the caller: [`Par::Seq`] or
//! `Par::rayon(n)`; [`run_at`] runs a closure in a rayon pool of that size,
//! reusing the current pool when it has that size.
//!
//! # Example
//!
//! ```
//! use tyreroad_core::{Field, Grid, Material, validate};
//!
//! let rubber = Material::new(6.54e6, 0.5)?;
//! assert!((rubber.reduced_modulus() - 8.72e6).abs() < 1e-6);
//!
//! // A 3 × 3 grid of 1 mm cells centred on the origin, a pyramid on it.
//! let grid = Grid::centered(3, 3, 1e-3, 1e-3)?;
//! assert_eq!(grid.x(1), 0.0);
//! let field = Field::from_fn(grid, |x, y| 1e-3 - x.abs().max(y.abs()))?;
//! assert_eq!(field.max(), 1e-3);
//! assert!((field.integral() - 1e-9).abs() < 1e-20); // 1 mm³ above zero
//!
//! let e = validate::positive("load (N)", -1.0).unwrap_err();
//! assert_eq!(e.to_string(), "invalid load (N): -1 (expected finite and > 0)");
//! # Ok::<(), tyreroad_core::CoreError>(())
//! ```

mod error;
mod grid;
mod input_file;
mod material;
mod par;
pub mod pchip;
pub mod spectrum;
mod union_find;
pub mod validate;

pub use error::{CoreError, readable, readable3};
pub use grid::{Field, Grid, MAX_CELLS};
pub use input_file::{MAX_INPUT_BYTES, check_input_file, read_input_file, read_input_text};
pub use material::Material;
pub use par::{Par, is_parallel, map_at, run_at, thread_count};
pub use pchip::{PchipRule, pchip_slopes};
pub use union_find::UnionFind;
