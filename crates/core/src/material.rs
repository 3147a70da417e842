//! The elastic half-space's material.

use crate::CoreError;
use crate::validate::positive;

/// Linear elastic, isotropic material of the half-space (the tread).
///
/// Invariant: `E` is finite and positive, `−1 < ν ≤ 0.5` (0.5 is rubber's
/// incompressible limit), and `E*` and `1/(π E*)` are finite and positive. Only the plane-strain modulus `E* = E / (1 − ν²)`
/// enters the frictionless contact of a rigid body on the half-space.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Material {
    youngs_modulus: f64,
    poisson_ratio: f64,
}

impl Material {
    /// A material with Young's modulus `youngs_modulus` (Pa) and Poisson's
    /// ratio `poisson_ratio`.
    ///
    /// # Errors
    /// [`CoreError::InvalidValue`] unless `youngs_modulus` is finite and > 0
    /// and `−1 < poisson_ratio ≤ 0.5`, or when the moduli derived from them,
    /// `E* = E/(1 − ν²)` and Boussinesq's `1/(π E*)`, are not finite and > 0
    /// (`E` near `f64::MAX` or below about 1e-308 Pa).
    pub fn new(youngs_modulus: f64, poisson_ratio: f64) -> Result<Self, CoreError> {
        positive("Young's modulus (Pa)", youngs_modulus)?;
        if !(poisson_ratio.is_finite() && poisson_ratio > -1.0 && poisson_ratio <= 0.5) {
            return Err(CoreError::InvalidValue {
                name: "Poisson's ratio",
                value: poisson_ratio,
                expected: "in (-1, 0.5]",
            });
        }
        let material = Self {
            youngs_modulus,
            poisson_ratio,
        };
        // Every coupling and law divides by or multiplies with these: an
        // overflow here would turn into inf/NaN forces far from the cause.
        let reduced = material.reduced_modulus();
        let compliance = material.boussinesq_factor();
        if !(reduced.is_finite() && reduced > 0.0 && compliance.is_finite() && compliance > 0.0) {
            return Err(CoreError::InvalidValue {
                name: "Young's modulus (Pa)",
                value: youngs_modulus,
                expected: "such that E* = E/(1 − ν²) and Boussinesq's 1/(π E*) are finite \
                           and > 0 (E between about 1e-308 and 1e307 Pa)",
            });
        }
        Ok(material)
    }

    /// Young's modulus `E` (Pa).
    pub fn youngs_modulus(&self) -> f64 {
        self.youngs_modulus
    }

    /// Poisson's ratio `ν`.
    pub fn poisson_ratio(&self) -> f64 {
        self.poisson_ratio
    }

    /// Plane-strain (reduced) modulus `E* = E / (1 − ν²)` (Pa) of a half-space
    /// pressed by a rigid body.
    pub fn reduced_modulus(&self) -> f64 {
        self.youngs_modulus / (1.0 - self.poisson_ratio * self.poisson_ratio)
    }

    /// Boussinesq's surface compliance factor `(1 − ν²) / (π E)` (1/Pa): a point
    /// force `F` displaces the surface at distance `r` by `F · factor / r`.
    pub fn boussinesq_factor(&self) -> f64 {
        1.0 / (std::f64::consts::PI * self.reduced_modulus())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn validation_and_moduli() {
        assert!(Material::new(1e6, 0.5).is_ok());
        assert!(Material::new(0.0, 0.3).is_err());
        assert!(Material::new(f64::NAN, 0.3).is_err());
        assert!(Material::new(1e6, -1.0).is_err());
        assert!(Material::new(1e6, 0.51).is_err());
        let m = Material::new(6.54e6, 0.5).expect("valid");
        assert!((m.reduced_modulus() - 8.72e6).abs() < 1e-6);
        assert!((m.boussinesq_factor() - 1.0 / (std::f64::consts::PI * 8.72e6)).abs() < 1e-22);
    }

    #[test]
    fn a_modulus_whose_e_star_or_compliance_overflows_is_refused() {
        // 1/(π E*) overflows for a subnormal E; E/(1 − ν²) overflows at f64::MAX.
        for (e, nu) in [(1e-320, 0.3), (5e-324, 0.0), (f64::MAX, 0.5)] {
            let err = Material::new(e, nu).expect_err("non-finite derived modulus");
            let text = err.to_string();
            assert!(
                matches!(
                    err,
                    CoreError::InvalidValue {
                        name: "Young's modulus (Pa)",
                        ..
                    }
                ) && text.contains("E* = E/(1 − ν²)")
                    && !text.contains("000000000"),
                "{text}"
            );
        }
        // The extremes that still fit are kept.
        let stiff = Material::new(1e307, 0.5).expect("π E* = 4.2e307 is finite");
        assert!(stiff.reduced_modulus().is_finite() && stiff.boussinesq_factor() > 0.0);
    }
}
