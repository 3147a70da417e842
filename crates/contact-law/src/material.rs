//! The elastic half-space's material.

use crate::LawError;

/// Linear elastic, isotropic material of the half-space (the tread).
///
/// Invariant: `E` is finite and positive, `−1 < ν ≤ 0.5` (0.5 is rubber's
/// incompressible limit).
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize)]
pub struct Material {
    youngs_modulus: f64,
    poisson_ratio: f64,
}

impl Material {
    /// A material with Young's modulus `youngs_modulus` (Pa) and Poisson's
    /// ratio `poisson_ratio`.
    pub fn new(youngs_modulus: f64, poisson_ratio: f64) -> Result<Self, LawError> {
        if !(youngs_modulus.is_finite() && youngs_modulus > 0.0) {
            return Err(LawError::InvalidMaterial(format!(
                "Young's modulus must be finite and > 0 Pa, got {youngs_modulus}"
            )));
        }
        if !(poisson_ratio.is_finite() && poisson_ratio > -1.0 && poisson_ratio <= 0.5) {
            return Err(LawError::InvalidMaterial(format!(
                "Poisson's ratio must lie in (-1, 0.5], got {poisson_ratio}"
            )));
        }
        Ok(Self {
            youngs_modulus,
            poisson_ratio,
        })
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

impl<'de> serde::Deserialize<'de> for Material {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        #[derive(serde::Deserialize)]
        #[serde(deny_unknown_fields)]
        struct Raw {
            youngs_modulus: f64,
            poisson_ratio: f64,
        }
        let raw = Raw::deserialize(deserializer)?;
        Material::new(raw.youngs_modulus, raw.poisson_ratio).map_err(serde::de::Error::custom)
    }
}
