//! The error type of the crate.

/// What can go wrong in the core: an input quantity out of its valid range.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum CoreError {
    /// A scalar input is not finite or out of its range.
    #[error("invalid {name}: {} (expected {expected})", readable(*value))]
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

/// `x` as `{}` prints it where that is short (`-1`, `0.5`, `6540000`, as
/// the messages always read), in scientific notation outside
/// `[1e-4, 1e16)`, where `{}` would print up to hundreds of digits
/// (`1e-320`, `1.7976931348623157e308`).
pub fn readable(x: f64) -> String {
    let magnitude = x.abs();
    if !x.is_finite() || x == 0.0 || (1e-4..1e16).contains(&magnitude) {
        format!("{x}")
    } else {
        format!("{x:e}")
    }
}

/// `x` with three decimals (`0.300`, `12.500`) where that is short
/// (`|x| < 1e6`), with three in scientific notation beyond (`1.000e150`),
/// where fixed notation would print hundreds of digits.
pub fn readable3(x: f64) -> String {
    if x.is_finite() && x.abs() >= 1e6 {
        format!("{x:.3e}")
    } else {
        format!("{x:.3}")
    }
}

impl From<realfft::FftError> for CoreError {
    fn from(e: realfft::FftError) -> Self {
        Self::Fft(e.to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn three_decimals_stay_short_for_huge_values() {
        assert_eq!(readable3(0.3), "0.300");
        assert_eq!(readable3(-12.5), "-12.500");
        assert_eq!(readable3(999_999.0), "999999.000");
        assert_eq!(readable3(1e150), "1.000e150");
        assert_eq!(readable3(f64::INFINITY), "inf");
    }

    #[test]
    fn extreme_values_print_in_scientific_notation_not_hundreds_of_digits() {
        let e = CoreError::InvalidValue {
            name: "dx",
            value: 5e-324,
            expected: "finite and > 0",
        };
        assert_eq!(
            e.to_string(),
            "invalid dx: 5e-324 (expected finite and > 0)"
        );
        assert_eq!(readable(f64::MAX), "1.7976931348623157e308");
        assert_eq!(readable(-1.0), "-1");
        assert_eq!(readable(6.54e6), "6540000");
        assert_eq!(readable(f64::NAN), "NaN");
        assert_eq!(readable(f64::NEG_INFINITY), "-inf");
    }
}
