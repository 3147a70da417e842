//! The error type of the crate.

/// What can go wrong with a viscoelastic material, its fit or a hereditary
/// solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ViscoError {
    /// A scalar input is not finite or out of its range.
    #[error("invalid {name}: {} (expected {expected})", significant(*value))]
    InvalidValue {
        /// Which quantity.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it should be.
        expected: &'static str,
    },
    /// Two lists that must have the same length do not.
    #[error("{name}: {found} entries, expected {expected}")]
    LengthMismatch {
        /// Which list.
        name: &'static str,
        /// Its length.
        found: usize,
        /// The length it should have.
        expected: usize,
    },
    /// A line of a master-curve CSV cannot be read.
    #[error("master curve line {line}, column {column} ({field}): {message}")]
    Csv {
        /// 1-based line number.
        line: usize,
        /// 1-based column number.
        column: usize,
        /// Which field of the row (frequency, storage or loss modulus).
        field: &'static str,
        /// What is wrong, with the text found.
        message: String,
    },
    /// A master curve has too few points to fit.
    #[error("master curve has {found} points, at least {needed} are needed")]
    TooFewPoints {
        /// Points read.
        found: usize,
        /// Points needed.
        needed: usize,
    },
    /// A master curve measured at fewer distinct frequencies than a fit
    /// needs (repeated frequencies count once).
    #[error("master curve has {found} distinct frequencies, at least {needed} are needed")]
    TooFewFrequencies {
        /// Distinct frequencies read.
        found: usize,
        /// Distinct frequencies needed.
        needed: usize,
    },
    /// Two rows of a master-curve CSV give the same frequency with
    /// different moduli.
    #[error(
        "master curve lines {first_line} and {line}: the frequency {} Hz is given twice with different moduli",
        significant(*frequency)
    )]
    ConflictingFrequency {
        /// 1-based line of the first row.
        first_line: usize,
        /// 1-based line of the second row.
        line: usize,
        /// The repeated frequency (Hz).
        frequency: f64,
    },
    /// A master curve's storage modulus falls with frequency by more than
    /// [`crate::MAX_STORAGE_FALL`]: no passive material does (its `E'` is
    /// non-decreasing), and no Prony series can follow it.
    #[error(
        "{fall}: a passive tread's E' does not decrease with frequency, and falls \
         over {}% are not measurement noise (check the columns: frequency, E', E'')",
        significant(100.0 * *max)
    )]
    StorageModulusFalls {
        /// Where it falls most.
        fall: crate::StorageFall,
        /// The largest fall accepted, as a fraction.
        max: f64,
    },
    /// A fit would need more relaxation times than [`crate::MAX_RELAXATION_TIMES`]:
    /// `per_decade` times the decades the curve spans (plus one at each end).
    #[error(
        "per_decade = {per_decade} over the {} decades of relaxation time the master curve spans \
         ({} to {} Hz, half a decade added at each end) asks for {} relaxation times: at most {max} \
         (lower per_decade or narrow the curve)",
        significant(*decades),
        significant(*lowest),
        significant(*highest),
        significant(*count)
    )]
    TooManyRelaxationTimes {
        /// Relaxation times per decade asked.
        per_decade: usize,
        /// Decades of relaxation time spanned.
        decades: f64,
        /// Lowest frequency of the curve (Hz).
        lowest: f64,
        /// Highest frequency of the curve (Hz).
        highest: f64,
        /// Relaxation times the grid would hold (a float: it may exceed any
        /// integer).
        count: f64,
        /// The cap.
        max: usize,
    },
    /// A temperature shift cannot be evaluated at a temperature: at or below
    /// the WLF pole, or with a factor `a_T` outside floating point (the
    /// message names the exponent and the inputs that make it, and suspects
    /// °C for a temperature below 150 K).
    #[error("invalid temperature for the shift factor a_T: {message}")]
    TemperatureShift {
        /// The temperature asked (K).
        temperature: f64,
        /// What is wrong.
        message: String,
    },
    /// The non-negative least-squares fit did not terminate.
    #[error("non-negative least squares did not converge in {iterations} iterations")]
    FitNotConverged {
        /// Iterations spent.
        iterations: usize,
    },
    /// Under load control with [`crate::Receding::LeeRadok`], the relaxing
    /// history alone carries more than the load: the tread would separate, a
    /// receding contact that recursion cannot carry ([`crate::Receding::Ting`]
    /// can; docs/viscoelastic.md).
    #[error(
        "hereditary step {step} (t = {} s): the load {} N is below the relaxing history's {} N (Lee–Radok's recursion cannot recede that far: use Ting's treatment)",
        significant(*time),
        significant(*load),
        significant(*history)
    )]
    Separation {
        /// 0-based step index.
        step: usize,
        /// Time of the step (s).
        time: f64,
        /// The load asked (N).
        load: f64,
        /// The force the history alone carries (N).
        history: f64,
    },
    /// The elastic BEM inside a viscoelastic BEM step failed.
    #[error("viscoelastic BEM at t = {} s: {source}", significant(*time))]
    Bem {
        /// Time of the step (s).
        time: f64,
        /// The BEM's error.
        source: tyreroad_bem::BemError,
    },
    /// An elastic multipoint solve inside a hereditary step failed.
    #[error("hereditary step {step} (t = {} s): {source}", significant(*time))]
    Solve {
        /// 0-based step index.
        step: usize,
        /// Time of the step (s).
        time: f64,
        /// The multipoint solver's error.
        source: tyreroad_multipoint::SolveError,
    },
    /// A viscoelastic rolling run's configuration, road or progress callback
    /// stopped it (the rolling crate's error).
    #[error("viscoelastic rolling: {source}")]
    Rolling {
        /// The rolling crate's error.
        source: tyreroad_rolling::RollingError,
    },
}

/// `x` with six significant digits and no float noise (`183.15`, not
/// `183.14999999999998`), in scientific notation outside `[1e-3, 1e6)`.
pub fn significant(x: f64) -> String {
    if !x.is_finite() || x == 0.0 {
        return format!("{x}");
    }
    let magnitude = x.abs();
    if (1e-3..1e6).contains(&magnitude) {
        let decimals = (5 - magnitude.log10().floor() as i32).max(0) as usize;
        let text = format!("{x:.decimals$}");
        if text.contains('.') {
            text.trim_end_matches('0').trim_end_matches('.').to_string()
        } else {
            text
        }
    } else {
        let text = format!("{x:.5e}");
        match text.split_once('e') {
            Some((mantissa, exponent)) if mantissa.contains('.') => format!(
                "{}e{exponent}",
                mantissa.trim_end_matches('0').trim_end_matches('.')
            ),
            _ => text,
        }
    }
}

pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64, ViscoError> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(ViscoError::InvalidValue {
            name,
            value,
            expected: "finite and > 0",
        })
    }
}

pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64, ViscoError> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(ViscoError::InvalidValue {
            name,
            value,
            expected: "finite and >= 0",
        })
    }
}

#[cfg(test)]
mod tests {
    use super::significant;

    #[test]
    fn messages_print_six_significant_digits_without_float_noise() {
        assert_eq!(significant(183.14999999999998), "183.15");
        assert_eq!(significant(293.15), "293.15");
        assert_eq!(significant(4e6), "4e6");
        assert_eq!(significant(-1.5e-7), "-1.5e-7");
        assert_eq!(significant(0.0), "0");
        assert_eq!(significant(f64::NAN), "NaN");
        assert_eq!(significant(1e300), "1e300");
        assert_eq!(significant(12.0), "12");
        assert_eq!(significant(0.0123456789), "0.0123457");
    }

    /// Regression (adversarial run, U1): times and loads printed with `{}`
    /// came out as hundreds of digits.
    #[test]
    fn step_errors_print_extreme_times_and_loads_in_scientific_notation() {
        let e = super::ViscoError::Separation {
            step: 3,
            time: 1e300,
            load: 1e-300,
            history: 2.5,
        };
        assert_eq!(
            e.to_string(),
            "hereditary step 3 (t = 1e300 s): the load 1e-300 N is below the relaxing history's \
             2.5 N (Lee–Radok's recursion cannot recede that far: use Ting's treatment)"
        );
    }
}
