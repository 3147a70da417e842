//! The error type of the crate.

/// What can go wrong in the core: an input quantity out of its valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CoreError {
    /// A scalar input is not finite or out of its range.
    #[error("invalid {name}: {value} (expected {expected})")]
    InvalidValue {
        /// Which quantity (e.g. "Young's modulus", "dx").
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it should be (e.g. "finite and > 0").
        expected: &'static str,
    },
    /// A size or a length of a buffer does not fit (the message names it).
    #[error("invalid {name}: {message}")]
    InvalidShape {
        /// Which quantity (e.g. "grid", "field values").
        name: &'static str,
        /// What is wrong.
        message: String,
    },
    /// The FFT library reported an error (a bug: buffer sizes are planned
    /// together with the transform).
    #[error("FFT failure: {0}")]
    Fft(String),
}

impl From<realfft::FftError> for CoreError {
    fn from(e: realfft::FftError) -> Self {
        Self::Fft(e.to_string())
    }
}
