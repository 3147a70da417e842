//! Contact laws of single rigid asperities on an elastic half-space.
//!
//! A contact law gives the force `P` an asperity carries when the half-space
//! interpenetrates it by `δ` at its summit, and its stiffness `k = dP/dδ`.
//!
//! # The Wilke–Sameur potential law (Cesbron et al. 2006, eq. 1)
//!
//! ```text
//! U(δ) = c · 8 π^(3/4) / 15 · E / (1 − ν²) · Ω(δ)² Γ(δ)^(1/2) / Σ(δ)^(7/4)
//! P(δ) = dU/dδ,   P = 0 for δ ≤ 0
//! ```
//!
//! with `Ω`, `Σ`, `Γ` the volume, base area and base perimeter of the
//! interpenetrated cap (`tyreroad-asperity`). The constant `c` depends weakly
//! on the shape: 0.36 for a sphere, 0.45 for a cone (the paper's values,
//! [`C_SPHERE`], [`C_CONE`]). For a sphere at small `δ`
//! (`Ω ≈ πRδ²`, `Σ ≈ 2πRδ`, `Γ ≈ 2π√(2Rδ)`) the law is exactly Hertz's
//! `P = 4/3 E* √R δ^(3/2)` when `c = 2/π^(3/2)` ([`C_HERTZ_EXACT`]); for a cone
//! it is exactly Sneddon's `P = 2/π E* tan α δ²` when
//! `c = 45 / (4√2 π^(5/2))` ([`C_SNEDDON_EXACT`]). `docs/theory.md` derives
//! both.
//!
//! # Invariants
//!
//! - [`Material`] holds `E > 0` and `−1 < ν ≤ 0.5`, both finite;
//! - every [`ContactLaw`] gives `P = k = 0` for `δ ≤ 0` (and NaN), `P` continuous
//!   and non-decreasing, and `k = dP/dδ` (tested against finite differences);
//!   a [`PotentialLaw`] on a tabulated cap keeps it, with `k ≥ 0.1 P/δ`, by
//!   ramps where the raw potential law would flatten or dip;
//! - a law knows nothing of other asperities or of any solver: the coupling
//!   lives in `tyreroad-multipoint`.
//!
//! # Example
//!
//! ```
//! use tyreroad_asperity::Sphere;
//! use tyreroad_contact_law::{ContactLaw, HertzLaw, Material, PotentialLaw, C_HERTZ_EXACT};
//!
//! let rubber = Material::new(6.54e6, 0.5)?;
//! let ball = Sphere::new(5e-3)?;
//! let law = PotentialLaw::sphere(ball, rubber).with_constant(C_HERTZ_EXACT)?;
//! let hertz = HertzLaw::new(5e-3, rubber)?;
//! let delta = 1e-9; // δ/R = 2e-7: Hertz's limit
//! let (p, ph) = (law.force(delta), hertz.force(delta));
//! assert!(((p - ph) / ph).abs() < 1e-6);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod law;
mod potential;
mod reference;

pub use law::{ContactLaw, LawPoint, LocalContact, PressureProfile};
pub use potential::{
    C_CONE, C_HERTZ_EXACT, C_SNEDDON_EXACT, C_SPHERE, LocalRule, MIN_STIFFNESS_RATIO, PotentialLaw,
    Ramp,
};
pub use reference::{HertzLaw, SneddonLaw};
/// The half-space's material, shared with the other layers.
pub use tyreroad_core::Material;

/// What can go wrong when building a contact law.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum LawError {
    /// The half-space's material is not physical.
    #[error("invalid material: {0}")]
    InvalidMaterial(#[from] tyreroad_core::CoreError),
    /// The shape constant `c` is not finite and positive.
    #[error("invalid shape constant c = {0:e} (must be finite and > 0)")]
    InvalidConstant(f64),
    /// A parameter of a reference law is out of range.
    #[error("invalid {name}: {value:e}")]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
    },
    /// The asperity's geometry is invalid.
    #[error(transparent)]
    Geometry(#[from] tyreroad_asperity::GeometryError),
}
