//! The error type of the crate.

/// Everything that can go wrong in this crate.
///
/// User input never panics: a bad grid, height map, material, option or
/// control value is reported as [`BemError::InvalidInput`] with a message
/// naming the offending quantity; a solve that does not reach the requested
/// tolerance is reported as [`BemError::NotConverged`], and one that ends on
/// numbers no contact has as [`BemError::NotPhysical`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum BemError {
    /// An input value is out of its valid range (the message names it).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The constrained conjugate-gradient iteration stopped before reaching
    /// the tolerance.
    #[error(
        "BEM contact solve did not converge: residual {residual:e} > tolerance {tolerance:e} after {iterations} iterations"
    )]
    NotConverged {
        /// Iterations performed.
        iterations: usize,
        /// Relative complementarity residual reached (see [`crate::BemSolution::residual`]).
        residual: f64,
        /// Tolerance that was asked for.
        tolerance: f64,
    },
    /// The solve ended on a result that is no contact: a force, approach
    /// or pressure that is not finite, a negative pressure, or a force
    /// other than the load imposed (inputs past what floating point holds:
    /// a load of 1e300 N, cells of 1e-300 m).
    #[error(
        "the BEM solve ended on numbers no contact has ({0}): are the inputs past what \
         floating point holds (loads, approaches or cells many decades from the physical)?"
    )]
    NotPhysical(String),
    /// The FFT library reported an error (a bug: buffer sizes are fixed at
    /// construction).
    #[error("FFT failure: {0}")]
    Fft(String),
}

impl BemError {
    pub(crate) fn invalid(msg: impl Into<String>) -> Self {
        Self::InvalidInput(msg.into())
    }
}

impl From<tyreroad_core::CoreError> for BemError {
    fn from(e: tyreroad_core::CoreError) -> Self {
        Self::InvalidInput(e.to_string())
    }
}

impl From<realfft::FftError> for BemError {
    fn from(e: realfft::FftError) -> Self {
        Self::Fft(e.to_string())
    }
}
