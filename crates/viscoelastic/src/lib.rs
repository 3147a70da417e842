//! A viscoelastic tread for the multipoint model (docs/viscoelastic.md).
//!
//! # Material
//!
//! A generalized Maxwell model with constant Poisson's ratio ([`Prony`]):
//!
//! ```text
//! E(t)  = E∞ + Σ_k E_k e^{−t/τ_k}
//! E'(ω) = E∞ + Σ_k E_k ω²τ_k² / (1 + ω²τ_k²),   E''(ω) = Σ_k E_k ωτ_k / (1 + ω²τ_k²)
//! ```
//!
//! given directly or fitted to a measured master curve ([`MasterCurve`],
//! [`fit_prony`]: non-negative least squares on log-spaced `τ`), and moved
//! in temperature by a WLF or Arrhenius shift factor `a_T` that multiplies
//! every `τ_k` ([`TemperatureShift`], [`Prony::shifted`]).
//!
//! # Hereditary contact
//!
//! While contacts grow, Lee & Radok's replacement of the modulus by the
//! hereditary operator holds for the whole frictionless half-space problem:
//! `P_i(t) = ∫_0^t E(t − s) df_i/ds ds` with `f_i` the unit-modulus elastic
//! force of asperity `i`. [`Hereditary`] steps it with one internal variable
//! per asperity and branch, exact for `f` linear over a step, so each step
//! costs one elastic multipoint solve (derivation in docs/viscoelastic.md).
//! Its invariants, tested: very slow loading gives the elastic solution with
//! `E∞`, very fast loading the one with `E∞ + Σ E_k`; a sphere pressed at
//! constant rate follows the closed form [`lee_radok_ramp_force`].
//! Receding contacts (Ting 1966, [`Receding`]): by default each asperity's
//! law is cut into depth bands of independent springs, each with its own
//! memory (the method of dimensionality reduction, exact for axisymmetric
//! contact): a band leaves contact when its force would turn negative and
//! recovers on its own, and while every band touches the step is Lee–Radok's
//! recursion term by term. Tested against Ting's closed form for a sphere
//! pressed and withdrawn, and against the viscoelastic BEM through unloading
//! to 1 % of the peak. [`Receding::LeeRadok`] keeps the recursion on the
//! whole force, which over-relaxes near separation.
//!
//! # The reference
//!
//! [`ViscoBem`] time-steps the project's BEM with the same Prony recursion
//! per grid cell on the elastic-equivalent pressure `w` (`u = K̃ w`): each
//! step is an elastic BEM contact of modulus `E_eff` on the road raised by
//! the history's displacement, with the full complementarity conditions, so
//! it needs no assumption on growing contacts and judges unloading too.
//! [`compare_on_spheres`] runs both on a field of spheres. In rolling,
//! [`TreadMemory`] carries the same per-cell variables with the road (the
//! tread does not slip on it) as the footprint window moves.
//!
//! # Example
//!
//! ```
//! use tyreroad_viscoelastic::{Branch, Prony, TemperatureShift};
//!
//! let tread = Prony::new(2e6, vec![Branch { modulus: 6e6, relaxation_time: 1e-4 }], 0.5)?;
//! let shift = TemperatureShift::Wlf { c1: 8.86, c2: 101.6, reference: 293.15 };
//! let warm = tread.shifted(shift.factor(313.15)?)?;
//! // Warmer is softer at a given frequency.
//! let omega = 2.0 * std::f64::consts::PI * 1000.0;
//! assert!(warm.complex_modulus(omega).0 < tread.complex_modulus(omega).0);
//! # Ok::<(), tyreroad_viscoelastic::ViscoError>(())
//! ```

mod bem;
mod bem_rolling;
mod compare;
mod error;
mod fit;
mod history;
mod prony;
mod rolling;
mod rolling_law;
mod sphere;
mod ting;

pub use bem::{ViscoBem, ViscoBemStep};
pub use bem_rolling::{StepHistory, TreadMemory};
pub use compare::{Comparison, SphereField, compare_on_spheres, compare_on_spheres_with};
pub use error::{ViscoError, significant};
pub use fit::{
    MAX_PER_DECADE, MAX_RELAXATION_TIMES, MAX_STORAGE_FALL, MasterCurve, STORAGE_NOISE,
    StorageFall, fit_prony, fit_prony_with_times,
};
pub use history::{
    Hereditary, ViscoStep, ramp_hold_unload, run_load_history, run_load_history_with,
};
pub use prony::{Branch, GAS_CONSTANT, Prony, TemperatureShift};
pub use rolling::{
    DEFAULT_FADE, TrailingMemory, ViscoRollOptions, ViscoRolling, ViscoStart, roll_viscoelastic,
    roll_viscoelastic_coupled,
};
pub use sphere::{dawson, lee_radok_ramp_force};
pub use ting::{
    BAND_FLOOR, DEFAULT_BANDS_PER_DECADE, MAX_BANDS_PER_DECADE, Receding, base_band_depth,
    keeps_bands,
};
