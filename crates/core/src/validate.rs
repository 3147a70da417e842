//! Small named checks on scalar inputs: each returns the value when it is
//! acceptable, or a [`CoreError::InvalidValue`] naming the quantity.
//!
//! The comparisons are written so that NaN fails every check.

use crate::CoreError;

fn invalid(name: &'static str, value: f64, expected: &'static str) -> CoreError {
    CoreError::InvalidValue {
        name,
        value,
        expected,
    }
}

/// `value` if it is finite.
pub fn finite(name: &'static str, value: f64) -> Result<f64, CoreError> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(invalid(name, value, "finite"))
    }
}

/// `value` if it is finite and `> 0`.
pub fn positive(name: &'static str, value: f64) -> Result<f64, CoreError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(invalid(name, value, "finite and > 0"))
    }
}

/// `value` if it is finite and `≥ 0`.
pub fn non_negative(name: &'static str, value: f64) -> Result<f64, CoreError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(invalid(name, value, "finite and >= 0"))
    }
}

/// `value` if it is finite and `lo ≤ value ≤ hi`; `expected` describes the
/// range in the error (e.g. `"in [0, 1]"`).
pub fn in_range(
    name: &'static str,
    value: f64,
    lo: f64,
    hi: f64,
    expected: &'static str,
) -> Result<f64, CoreError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(value)
    } else {
        Err(invalid(name, value, expected))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn checks_name_the_quantity_and_reject_nan() {
        assert_eq!(positive("dx", 2.5), Ok(2.5));
        assert!(positive("dx", 0.0).is_err());
        assert!(positive("dx", f64::NAN).is_err());
        assert_eq!(non_negative("load", 0.0), Ok(0.0));
        assert!(non_negative("load", -1e-300).is_err());
        assert!(finite("x0", f64::INFINITY).is_err());
        assert_eq!(in_range("ratio", 1.0, 0.0, 1.0, "in [0, 1]"), Ok(1.0));
        let e = in_range("ratio", f64::NAN, 0.0, 1.0, "in [0, 1]").expect_err("NaN");
        assert_eq!(e.to_string(), "invalid ratio: NaN (expected in [0, 1])");
    }
}
