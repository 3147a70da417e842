//! The error type of the geometry layer.

/// What can go wrong when building an asperity shape.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum GeometryError {
    /// A dimension (radius, angle, depth) is not a finite positive number.
    #[error("invalid {name}: {value:e} (must be finite and {requirement})")]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// A triangle mesh cannot describe a closed solid asperity.
    #[error("invalid mesh: {0}")]
    InvalidMesh(String),
    /// A table of cap measures is not usable for interpolation.
    #[error("invalid cap table: {0}")]
    InvalidTable(String),
}

pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<f64, GeometryError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(GeometryError::InvalidParameter {
            name,
            value,
            requirement: "> 0",
        })
    }
}
