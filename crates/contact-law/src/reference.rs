//! Closed-form reference laws: Hertz (sphere) and Sneddon (cone).

use std::f64::consts::PI;

use crate::{ContactLaw, LawError, LawPoint, LocalContact, Material, PressureProfile};

/// Hertz's law for a rigid sphere of radius `R` on the half-space:
/// `P = 4/3 · E* √R δ^(3/2)`, `a = √(R δ)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct HertzLaw {
    radius: f64,
    material: Material,
}

impl HertzLaw {
    /// Hertz's law for radius `radius` (m).
    pub fn new(radius: f64, material: Material) -> Result<Self, LawError> {
        if !(radius.is_finite() && radius > 0.0) {
            return Err(LawError::InvalidParameter {
                name: "Hertz radius",
                value: radius,
            });
        }
        Ok(Self { radius, material })
    }
}

impl ContactLaw for HertzLaw {
    fn evaluate(&self, depth: f64) -> LawPoint {
        if !(depth > 0.0) {
            return LawPoint::default();
        }
        let s = 4.0 / 3.0 * self.material.reduced_modulus() * self.radius.sqrt();
        LawPoint {
            force: s * depth.powf(1.5),
            stiffness: 1.5 * s * depth.sqrt(),
        }
    }

    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if !(force > 0.0 && depth > 0.0) {
            return LocalContact::NONE;
        }
        LocalContact {
            force,
            radius: (self.radius * depth).sqrt(),
            profile: PressureProfile::Hertz,
        }
    }
}

/// Sneddon's law for a rigid cone of half-angle `α` on the half-space:
/// `P = 2/π · E* tan α · δ²`, `a = 2/π · tan α · δ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SneddonLaw {
    half_angle: f64,
    material: Material,
}

impl SneddonLaw {
    /// Sneddon's law for half-angle `half_angle` (rad, in (0, π/2)).
    pub fn new(half_angle: f64, material: Material) -> Result<Self, LawError> {
        if !(half_angle.is_finite() && half_angle > 0.0 && half_angle < PI / 2.0) {
            return Err(LawError::InvalidParameter {
                name: "Sneddon half-angle",
                value: half_angle,
            });
        }
        Ok(Self {
            half_angle,
            material,
        })
    }
}

impl ContactLaw for SneddonLaw {
    fn evaluate(&self, depth: f64) -> LawPoint {
        if !(depth > 0.0) {
            return LawPoint::default();
        }
        let s = 2.0 / PI * self.material.reduced_modulus() * self.half_angle.tan();
        LawPoint {
            force: s * depth * depth,
            stiffness: 2.0 * s * depth,
        }
    }

    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if !(force > 0.0 && depth > 0.0) {
            return LocalContact::NONE;
        }
        LocalContact {
            force,
            radius: 2.0 / PI * self.half_angle.tan() * depth,
            profile: PressureProfile::Cone,
        }
    }
}
