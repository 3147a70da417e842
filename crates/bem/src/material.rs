//! Elastic half-space material.

use crate::BemError;

/// Isotropic linear elastic material of the half-space.
///
/// Only the plane-strain modulus `E* = E / (1 − ν²)` enters the frictionless
/// contact of a rigid body against an elastic half-space.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Material {
    young: f64,
    poisson: f64,
}

impl Material {
    /// A material with Young's modulus `young` (Pa) and Poisson's ratio `poisson`.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] unless `young` is finite and > 0 and
    /// `−1 < poisson ≤ 0.5`.
    pub fn new(young: f64, poisson: f64) -> Result<Self, BemError> {
        if !(young.is_finite() && young > 0.0) {
            return Err(BemError::invalid(format!(
                "Young's modulus must be finite and > 0, got {young}"
            )));
        }
        if !(poisson.is_finite() && poisson > -1.0 && poisson <= 0.5) {
            return Err(BemError::invalid(format!(
                "Poisson's ratio must satisfy -1 < nu <= 0.5, got {poisson}"
            )));
        }
        Ok(Self { young, poisson })
    }

    /// Young's modulus E (Pa).
    pub fn young(&self) -> f64 {
        self.young
    }

    /// Poisson's ratio ν.
    pub fn poisson(&self) -> f64 {
        self.poisson
    }

    /// Plane-strain (contact) modulus E* = E / (1 − ν²) (Pa).
    pub fn e_star(&self) -> f64 {
        self.young / (1.0 - self.poisson * self.poisson)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation() {
        assert!(Material::new(1e6, 0.5).is_ok());
        assert!(Material::new(0.0, 0.3).is_err());
        assert!(Material::new(f64::NAN, 0.3).is_err());
        assert!(Material::new(1e6, -1.0).is_err());
        assert!(Material::new(1e6, 0.51).is_err());
        let m = Material::new(6.54e6, 0.5).expect("valid");
        assert!((m.e_star() - 8.72e6).abs() < 1e-6);
    }
}
