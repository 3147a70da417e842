//! The error type of the film layer.

use std::path::PathBuf;

use crate::analysis::Estimator;

/// What can go wrong in film post-processing. Every variant names the problem;
/// user input never panics.
#[derive(Debug, thiserror::Error)]
pub enum FilmError {
    /// A calibration curve whose response does not vary strictly monotonically
    /// with pressure (it cannot be inverted).
    #[error(
        "non-monotone calibration: {response} {r0} at {p0} Pa then {r1} at {p1} Pa \
         (points {i} and {j} after sorting by pressure; the response must vary strictly \
         one way with pressure)"
    )]
    NonMonotoneCalibration {
        /// Name of the response ("density" or "grey").
        response: &'static str,
        /// Index of the first offending point (sorted by pressure).
        i: usize,
        /// Index of the second offending point.
        j: usize,
        /// Pressure of the first point, Pa.
        p0: f64,
        /// Response at the first point.
        r0: f64,
        /// Pressure of the second point, Pa.
        p1: f64,
        /// Response at the second point.
        r1: f64,
    },
    /// A calibration (or other table) is unusable for another reason.
    #[error("invalid calibration: {0}")]
    InvalidCalibration(String),
    /// A parameter is out of its domain.
    #[error("invalid {name}: {} (must be {requirement})", readable(*.value))]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// A pressure map's grid or values do not fit (sizes, spacings, a
    /// non-finite pressure, pixels that are not square).
    #[error("invalid pressure map: {0}")]
    InvalidPressureMap(String),
    /// A mask whose length is not `width × height`.
    #[error(
        "mask of {len} values for a {width} × {height} image (a row-major mask holds \
         width × height values)"
    )]
    MaskSize {
        /// Values in the mask.
        len: usize,
        /// Image width, px.
        width: usize,
        /// Image height, px.
        height: usize,
    },
    /// Otsu's threshold asked of a scan whose greys all fall in one
    /// histogram bin: there is nothing to split.
    #[error(
        "Otsu's threshold is undefined on this scan: all its {pixels} pixels have grey \
         {grey:.4} (to the histogram's resolution), so nothing separates prints from \
         background; give a grey or density threshold"
    )]
    UniformScan {
        /// The scan's one grey level (the mean of its pixels).
        grey: f64,
        /// Pixels of the scan.
        pixels: usize,
    },
    /// A file could not be read or written.
    #[error("cannot access {path}: {reason}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        reason: std::io::Error,
    },
    /// An image could not be decoded or encoded.
    #[error("unreadable image {path}: {message}")]
    Image {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// What the decoder said.
        message: String,
    },
    /// A CSV file is malformed.
    #[error("{path}, line {line}: {message}")]
    Csv {
        /// The file (or `<memory>`).
        path: PathBuf,
        /// 1-based line number.
        line: usize,
        /// What is wrong.
        message: String,
    },
    /// No pixel size: neither given nor readable from the file's resolution.
    #[error("pixel size unknown: the image carries no resolution; give the DPI or the pixel size")]
    PixelSizeUnknown,
    /// The scan holds no print at all.
    #[error("no print found in the scan (threshold grey {threshold:.4}, {reacted} reacted pixels)")]
    NoPrints {
        /// The grey threshold used.
        threshold: f64,
        /// Number of pixels darker than the threshold.
        reacted: usize,
    },
    /// An indenter of the layout has no print near its expected position.
    #[error(
        "print not found for indenter {indenter}: nothing within {tolerance_m:.3e} m of \
         ({x_m:.4e}, {y_m:.4e}) m{scale_hint}"
    )]
    PrintNotFound {
        /// Indenter number.
        indenter: u32,
        /// Expected position, m (film frame).
        x_m: f64,
        /// Expected position, m (film frame).
        y_m: f64,
        /// Search radius, m.
        tolerance_m: f64,
        /// Empty, or (starting with "; ") why the scale is likely wrong:
        /// the prints lie much closer or farther apart, at the scan's pixel
        /// size, than the layout's indenters.
        scale_hint: String,
    },
    /// A one-indenter layout, the film origin estimated from the prints, on
    /// a scan of several prints: nothing tells which print is the
    /// indenter's.
    #[error(
        "the layout's single indenter {indenter} matches any of the {prints} prints of the \
         scan equally (with the film origin estimated from the prints, one indenter cannot \
         tell which is its print): give the film origin (--origin COL,ROW) or a layout with \
         more indenters"
    )]
    AmbiguousMatch {
        /// The layout's indenter.
        indenter: u32,
        /// Number of prints in the scan.
        prints: usize,
    },
    /// A matched print read above the calibration's top where the estimator
    /// needs a pressure: its mean grey (mean-grey), or so much of it that
    /// the Hertz fit finds too little in range around the saturated core.
    #[error(
        "print of indenter {indenter} is saturated: {saturated} of its {pixels} pixels \
         ({:.1} %) read above the calibration's top, {top_pa:.3e} Pa; {}",
        percent(*.saturated, *.pixels),
        saturated_hint(*.estimator)
    )]
    SaturatedPrint {
        /// Indenter number.
        indenter: u32,
        /// The estimator that cannot measure it.
        estimator: Estimator,
        /// Saturated pixels of the print.
        saturated: usize,
        /// Pixels of the print.
        pixels: usize,
        /// The calibration's highest pressure, Pa.
        top_pa: f64,
    },
    /// A matched print the estimator cannot measure for another reason than
    /// saturation: too faint for the calibration, or no Hertz fit.
    #[error("print of indenter {indenter} cannot be measured with {}: {reason}", .estimator.name())]
    PrintNotMeasured {
        /// Indenter number.
        indenter: u32,
        /// The estimator that cannot measure it.
        estimator: Estimator,
        /// Why.
        reason: String,
    },
    /// The layout does not fit the prints (or the model rows).
    #[error("layout mismatch: {0}")]
    LayoutMismatch(String),
}

pub(crate) use tyreroad_core::readable;

/// A stored `f32` grey as the `f64` its shortest decimal names: `0.4f32`
/// reports as 0.4, not 0.4000000059604645.
pub(crate) fn widen(g: f32) -> f64 {
    format!("{g}").parse().unwrap_or(g as f64)
}

/// `100 · part / whole`, 0 for an empty whole.
pub(crate) fn percent(part: usize, whole: usize) -> f64 {
    if whole == 0 {
        0.0
    } else {
        100.0 * part as f64 / whole as f64
    }
}

/// What else a saturated print allows: the user's next step depends on
/// the estimator that gave up.
fn saturated_hint(estimator: Estimator) -> &'static str {
    match estimator {
        Estimator::MeanGrey => {
            "its mean grey reads beyond that top, so mean-grey finds no pressure: hertz-fit \
             reads through a saturated centre with a rim in range, pixel-mean gives a lower \
             bound, or use a film of a higher range"
        }
        Estimator::HertzFit => {
            "around the saturated core too little of it is in range for hertz-fit (or it is no \
             Hertz profile): pixel-mean gives a lower bound, or use a film of a higher range"
        }
        Estimator::PixelMean => "pixel-mean reads it as a lower bound",
    }
}

/// Shorthand for results of this crate.
pub type Result<T> = std::result::Result<T, FilmError>;

/// A core error in this crate's terms: an invalid scalar keeps its name,
/// value and requirement; a grid or field that does not fit is named as a
/// pressure map.
impl From<tyreroad_core::CoreError> for FilmError {
    fn from(e: tyreroad_core::CoreError) -> Self {
        match e {
            tyreroad_core::CoreError::InvalidValue {
                name,
                value,
                expected,
            } => Self::InvalidParameter {
                name,
                value,
                requirement: expected,
            },
            other => Self::InvalidPressureMap(other.to_string()),
        }
    }
}

pub(crate) fn check_positive(name: &'static str, value: f64) -> Result<f64> {
    Ok(tyreroad_core::validate::positive(name, value)?)
}

pub(crate) fn check_non_negative(name: &'static str, value: f64) -> Result<f64> {
    Ok(tyreroad_core::validate::non_negative(name, value)?)
}
