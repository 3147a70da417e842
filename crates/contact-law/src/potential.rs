//! The Wilke–Sameur interaction-potential law (paper eq. 1).

use std::f64::consts::PI;

use tyreroad_asperity::{CapGeometry, Cone, EllipticParaboloid, Sphere};

use crate::{ContactLaw, LawError, LawPoint, LocalContact, Material, PressureProfile};

/// `c` given by the paper for a sphere (Sameur 2004).
pub const C_SPHERE: f64 = 0.36;
/// `c` given by the paper for a cone (Sameur 2004).
pub const C_CONE: f64 = 0.45;
/// `c = 2 / π^(3/2)`: the value for which the sphere law is exactly Hertz as
/// `δ/R → 0`.
pub const C_HERTZ_EXACT: f64 = 0.359_174_244_250_333_1;
/// `c = 45 / (4 √2 π^(5/2))`: the value for which the cone law is exactly
/// Sneddon's.
pub const C_SNEDDON_EXACT: f64 = 0.454_739_670_621_523_9;

/// How the local contact (radius and pressure) is rebuilt from the force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LocalRule {
    /// Hertz with radius of curvature `R`: `a = (3 P R / (4 E*))^(1/3)`
    /// (independent of `δ`, how the paper computed its model radii).
    Hertz {
        /// Summit radius of curvature (m).
        radius: f64,
    },
    /// Sneddon's cone of half-angle `α`: `a = √(2 P tan α / (π E*))`
    /// (from `P = π/2 · E* a² cot α`), logarithmic pressure.
    Sneddon {
        /// Half-angle (rad).
        half_angle: f64,
    },
    /// Any shape: the contact area is half the cap's base area,
    /// `π a² = Σ(δ) / 2`, with a Hertzian pressure profile. Exact for every
    /// paraboloid in Hertz's limit (`π R δ = Σ/2`); for a cone it
    /// overestimates Sneddon's radius by 11 %. The two-scale BEM rebuild is the
    /// accurate alternative for real shapes.
    HalfSection,
}

/// The interaction-potential law of Wilke and Sameur (DESIGN §2.1):
///
/// ```text
/// U(δ) = c · 8 π^(3/4) / 15 · E/(1 − ν²) · Ω² Γ^(1/2) / Σ^(7/4),   P = dU/dδ
/// ```
///
/// `P` and `k = dP/dδ` are computed analytically from the cap measures and
/// their derivatives through the logarithmic derivative
/// `g = U'/U = 2Σ/Ω + Γ'/(2Γ) − 7Σ'/(4Σ)` (using `Ω' = Σ`): `P = U g`,
/// `k = U (g² + g')`.
#[derive(Clone, Debug, PartialEq)]
pub struct PotentialLaw<G> {
    geometry: G,
    material: Material,
    constant: f64,
    rule: LocalRule,
}

impl<G: CapGeometry> PotentialLaw<G> {
    /// The law of `geometry` with shape constant `constant` (`c`) and the
    /// local rule `rule`.
    pub fn new(
        geometry: G,
        material: Material,
        constant: f64,
        rule: LocalRule,
    ) -> Result<Self, LawError> {
        if !(constant.is_finite() && constant > 0.0) {
            return Err(LawError::InvalidConstant(constant));
        }
        Ok(Self {
            geometry,
            material,
            constant,
            rule,
        })
    }

    /// The shape.
    pub fn geometry(&self) -> &G {
        &self.geometry
    }

    /// The half-space's material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The shape constant `c`.
    pub fn constant(&self) -> f64 {
        self.constant
    }

    /// The local-contact rule.
    pub fn rule(&self) -> LocalRule {
        self.rule
    }

    /// The same law with another shape constant `c`.
    pub fn with_constant(mut self, constant: f64) -> Result<Self, LawError> {
        if !(constant.is_finite() && constant > 0.0) {
            return Err(LawError::InvalidConstant(constant));
        }
        self.constant = constant;
        Ok(self)
    }

    /// The potential `U(δ)` (J).
    pub fn potential(&self, depth: f64) -> f64 {
        let cap = self.geometry.cap(depth);
        if !(cap.volume > 0.0 && cap.base_area > 0.0 && cap.perimeter > 0.0) {
            return 0.0;
        }
        self.log_potential(cap.volume, cap.base_area, cap.perimeter)
            .exp()
    }

    fn prefactor(&self) -> f64 {
        self.constant * 8.0 * PI.powf(0.75) / 15.0 * self.material.reduced_modulus()
    }

    // In logarithms: the powers of tiny caps under- and overflow separately.
    fn log_potential(&self, volume: f64, area: f64, perimeter: f64) -> f64 {
        self.prefactor().ln() + 2.0 * volume.ln() + 0.5 * perimeter.ln() - 1.75 * area.ln()
    }
}

impl PotentialLaw<Sphere> {
    /// The paper's sphere law: `c = 0.36`, Hertz local contacts.
    pub fn sphere(sphere: Sphere, material: Material) -> Self {
        let rule = LocalRule::Hertz {
            radius: sphere.radius(),
        };
        Self {
            geometry: sphere,
            material,
            constant: C_SPHERE,
            rule,
        }
    }
}

impl PotentialLaw<Cone> {
    /// The paper's cone law: `c = 0.45`, Sneddon local contacts.
    pub fn cone(cone: Cone, material: Material) -> Self {
        let rule = LocalRule::Sneddon {
            half_angle: cone.half_angle(),
        };
        Self {
            geometry: cone,
            material,
            constant: C_CONE,
            rule,
        }
    }
}

impl PotentialLaw<EllipticParaboloid> {
    /// An elliptic paraboloid with the sphere's constant `c = 0.36` and Hertz
    /// local contacts of the mean radius `√(Rx Ry)`.
    pub fn paraboloid(paraboloid: EllipticParaboloid, material: Material) -> Self {
        let (rx, ry) = paraboloid.radii();
        Self {
            geometry: paraboloid,
            material,
            constant: C_SPHERE,
            rule: LocalRule::Hertz {
                radius: (rx * ry).sqrt(),
            },
        }
    }
}

impl<G: CapGeometry> ContactLaw for PotentialLaw<G> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        let cap = self.geometry.cap(depth);
        let (om, sg, gm) = (cap.volume, cap.base_area, cap.perimeter);
        if !(om > 0.0 && sg > 0.0 && gm > 0.0) {
            return LawPoint::default();
        }
        let u = self.log_potential(om, sg, gm).exp();
        let (ds, dg) = (cap.d_base_area, cap.d_perimeter);
        let g = 2.0 * sg / om + 0.5 * dg / gm - 1.75 * ds / sg;
        let dg_log = 2.0 * (ds / om - (sg / om).powi(2))
            + 0.5 * (cap.d2_perimeter / gm - (dg / gm).powi(2))
            - 1.75 * (cap.d2_base_area / sg - (ds / sg).powi(2));
        LawPoint {
            force: u * g,
            stiffness: u * (g * g + dg_log),
        }
    }

    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if !(force > 0.0) {
            return LocalContact::NONE;
        }
        let e_star = self.material.reduced_modulus();
        let (radius, profile) = match self.rule {
            LocalRule::Hertz { radius } => (
                (0.75 * force * radius / e_star).cbrt(),
                PressureProfile::Hertz,
            ),
            LocalRule::Sneddon { half_angle } => (
                (2.0 * force * half_angle.tan() / (PI * e_star)).sqrt(),
                PressureProfile::Cone,
            ),
            LocalRule::HalfSection => (
                (self.geometry.cap(depth).base_area / (2.0 * PI)).sqrt(),
                PressureProfile::Hertz,
            ),
        };
        LocalContact {
            force,
            radius,
            profile,
        }
    }
}
