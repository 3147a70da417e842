//! The error type of the crate.

/// What can go wrong with a viscoelastic material, its fit or a hereditary
/// solve.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum ViscoError {
    /// A scalar input is not finite or out of its range.
    #[error("invalid {name}: {value} (expected {expected})")]
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
    /// The non-negative least-squares fit did not terminate.
    #[error("non-negative least squares did not converge in {iterations} iterations")]
    FitNotConverged {
        /// Iterations spent.
        iterations: usize,
    },
    /// Under load control, the relaxing history alone carries more than the
    /// load: the tread would separate, a receding contact this crate does not
    /// model (Ting's treatment, docs/viscoelastic.md).
    #[error(
        "hereditary step {step} (t = {time} s): the load {load} N is below the relaxing history's {history} N (receding contact not modelled)"
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
    #[error("viscoelastic BEM at t = {time} s: {source}")]
    Bem {
        /// Time of the step (s).
        time: f64,
        /// The BEM's error.
        source: tyreroad_bem::BemError,
    },
    /// An elastic multipoint solve inside a hereditary step failed.
    #[error("hereditary step {step} (t = {time} s): {source}")]
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
