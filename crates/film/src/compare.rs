//! Comparison of measured prints with a model run: relative errors per
//! indenter and the paper's Table 1 statistics per load.

use std::path::Path;

use crate::analysis::{Detection, Estimator, Print};
use crate::calibration::Calibrated;
use crate::error::{FilmError, Result, percent};
use crate::layout::{Indenter, Layout, Matching};

/// The exact header of a model CSV.
pub const MODEL_CSV_HEADER: &str = "load_n,indenter,x_m,y_m,force_n,radius_m";

/// One row of a model run: one indenter at one total load (SI units).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ModelRow {
    /// Total load, N.
    pub load_n: f64,
    /// Indenter number.
    pub indenter: u32,
    /// Position x, m.
    pub x_m: f64,
    /// Position y, m.
    pub y_m: f64,
    /// Model force on this indenter, N.
    pub force_n: f64,
    /// Model contact radius, m.
    pub radius_m: f64,
}

/// Parses a model CSV: `#` comments allowed, header exactly
/// [`MODEL_CSV_HEADER`], one row per load and indenter.
pub fn parse_model_csv(text: &str, source: &Path) -> Result<Vec<ModelRow>> {
    let csv_err = |line: usize, message: String| FilmError::Csv {
        path: source.to_path_buf(),
        line,
        message,
    };
    let mut header = false;
    let mut rows = Vec::new();
    for (n, line) in crate::data_lines(text) {
        if !header {
            if line != MODEL_CSV_HEADER {
                return Err(csv_err(
                    n + 1,
                    format!("expected header {MODEL_CSV_HEADER:?}"),
                ));
            }
            header = true;
            continue;
        }
        let cols: Vec<&str> = line.split(',').map(str::trim).collect();
        if cols.len() != 6 {
            return Err(csv_err(
                n + 1,
                format!("expected 6 columns, got {}", cols.len()),
            ));
        }
        let num = |s: &str| -> Result<f64> {
            s.parse::<f64>()
                .ok()
                .filter(|v| v.is_finite())
                .ok_or_else(|| csv_err(n + 1, format!("not a finite number: {s:?}")))
        };
        let indenter: u32 = cols[1]
            .parse()
            .map_err(|_| csv_err(n + 1, format!("bad indenter number {:?}", cols[1])))?;
        let load_n = num(cols[0])?;
        // One row per load and indenter: a repeated one would be counted
        // twice in the statistics.
        if rows
            .iter()
            .any(|r: &ModelRow| r.load_n == load_n && r.indenter == indenter)
        {
            return Err(csv_err(
                n + 1,
                format!("indenter {indenter} at {load_n} N given twice"),
            ));
        }
        rows.push(ModelRow {
            load_n,
            indenter,
            x_m: num(cols[2])?,
            y_m: num(cols[3])?,
            force_n: num(cols[4])?,
            radius_m: num(cols[5])?,
        });
    }
    if !header {
        return Err(csv_err(
            0,
            format!("no header (expected {MODEL_CSV_HEADER:?})"),
        ));
    }
    Ok(rows)
}

/// Reads a model CSV file ([`parse_model_csv`]).
pub fn read_model_csv(path: &Path) -> Result<Vec<ModelRow>> {
    let text = tyreroad_core::read_input_text(path).map_err(|reason| FilmError::Io {
        path: path.to_path_buf(),
        reason,
    })?;
    parse_model_csv(&text, path)
}

/// The distinct loads of model rows, in order of first appearance.
pub fn loads(rows: &[ModelRow]) -> Vec<f64> {
    let mut v: Vec<f64> = Vec::new();
    for r in rows {
        if !v.contains(&r.load_n) {
            v.push(r.load_n);
        }
    }
    v
}

/// The rows of one load.
pub fn rows_at_load(rows: &[ModelRow], load_n: f64) -> Vec<ModelRow> {
    rows.iter()
        .filter(|r| r.load_n == load_n)
        .copied()
        .collect()
}

/// The layout of the model rows of one load.
pub fn layout_of(rows: &[ModelRow]) -> Result<Layout> {
    Layout::new(
        rows.iter()
            .map(|r| Indenter {
                number: r.indenter,
                x: r.x_m,
                y: r.y_m,
            })
            .collect(),
    )
}

/// Measured against model for one indenter.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct IndenterComparison {
    /// Indenter number.
    pub indenter: u32,
    /// Measured force, N.
    pub force_meas: f64,
    /// Model force, N.
    pub force_model: f64,
    /// Measured radius, m.
    pub radius_meas: f64,
    /// Model radius, m.
    pub radius_model: f64,
    /// `ε_P = (P_meas − P_model) / P_model`.
    pub eps_force: f64,
    /// `ε_a = (a_meas − a_model) / a_model`.
    pub eps_radius: f64,
}

/// Mean of `|ε|` and its sample standard deviation.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AbsErrorStats {
    /// `mean |ε|`.
    pub mean_abs: f64,
    /// Sample standard deviation of `|ε|` (divisor `n − 1`; 0 for `n = 1`).
    pub std_abs: f64,
}

impl AbsErrorStats {
    /// Statistics of the absolute values of `eps`; `None` when empty or any
    /// value is not finite.
    pub fn of(eps: &[f64]) -> Option<Self> {
        if eps.is_empty() || eps.iter().any(|e| !e.is_finite()) {
            return None;
        }
        let n = eps.len() as f64;
        let mean = eps.iter().map(|e| e.abs()).sum::<f64>() / n;
        let var = if eps.len() > 1 {
            eps.iter().map(|e| (e.abs() - mean).powi(2)).sum::<f64>() / (n - 1.0)
        } else {
            0.0
        };
        Some(Self {
            mean_abs: mean,
            std_abs: var.sqrt(),
        })
    }
}

/// One row of the paper's Table 1: a load and the error statistics over its
/// indenters.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Table1Row {
    /// Total load, N.
    pub load_n: f64,
    /// Number of indenters compared.
    pub indenters: usize,
    /// Forces: mean |ε_P| and its standard deviation.
    pub force: AbsErrorStats,
    /// Radii: mean |ε_a| and its standard deviation.
    pub radius: AbsErrorStats,
}

/// A comparison at one load.
#[derive(Debug, Clone, PartialEq)]
pub struct Comparison {
    /// Per indenter, in model-row order.
    pub indenters: Vec<IndenterComparison>,
    /// The Table 1 statistics.
    pub table1: Table1Row,
}

/// Compares measured `(indenter, force N, radius m)` with the model rows of
/// one load. Every model indenter must be measured, else
/// [`FilmError::PrintNotFound`]-like [`FilmError::LayoutMismatch`].
pub fn compare(
    load_n: f64,
    measured: &[(u32, f64, f64)],
    model: &[ModelRow],
) -> Result<Comparison> {
    let mut v = Vec::with_capacity(model.len());
    for m in model {
        let Some(&(_, f, a)) = measured.iter().find(|x| x.0 == m.indenter) else {
            return Err(FilmError::LayoutMismatch(format!(
                "model indenter {} at load {load_n} N has no measurement",
                m.indenter
            )));
        };
        if !(m.force_n > 0.0 && m.radius_m > 0.0) {
            return Err(FilmError::LayoutMismatch(format!(
                "model indenter {} at load {load_n} N has force {} N and radius {} m: \
                 relative errors need both > 0",
                m.indenter, m.force_n, m.radius_m
            )));
        }
        v.push(IndenterComparison {
            indenter: m.indenter,
            force_meas: f,
            force_model: m.force_n,
            radius_meas: a,
            radius_model: m.radius_m,
            eps_force: (f - m.force_n) / m.force_n,
            eps_radius: (a - m.radius_m) / m.radius_m,
        });
    }
    let ef: Vec<f64> = v.iter().map(|c| c.eps_force).collect();
    let ea: Vec<f64> = v.iter().map(|c| c.eps_radius).collect();
    let none = || FilmError::LayoutMismatch(format!("no finite errors at load {load_n} N"));
    let table1 = Table1Row {
        load_n,
        indenters: v.len(),
        force: AbsErrorStats::of(&ef).ok_or_else(none)?,
        radius: AbsErrorStats::of(&ea).ok_or_else(none)?,
    };
    Ok(Comparison {
        indenters: v,
        table1,
    })
}

/// The measured `(indenter, force, radius)` of matched prints by
/// `estimator`. A print it cannot measure is
/// [`FilmError::SaturatedPrint`] when saturation is why (its mean grey
/// beyond the calibration's top, or no Hertz fit around a saturated core),
/// else [`FilmError::PrintNotMeasured`] (too faint, no Hertz fit).
pub fn measurements(
    detection: &Detection,
    matching: &Matching,
    estimator: Estimator,
) -> Result<Vec<(u32, f64, f64)>> {
    matching
        .matches
        .iter()
        .map(|m| {
            let p = &detection.prints[m.print];
            match (p.force(estimator), p.radius(estimator)) {
                (Some(f), Some(a)) => Ok((m.indenter.number, f, a)),
                _ => Err(unmeasured(detection, p, m.indenter.number, estimator)),
            }
        })
        .collect()
}

/// Why `estimator` cannot measure print `p`: saturation first, since a
/// saturated print is a film pressed beyond its range, not a bad layout or
/// a bad profile.
fn unmeasured(detection: &Detection, p: &Print, indenter: u32, estimator: Estimator) -> FilmError {
    let (bottom, top) = detection.pressure_range;
    let saturated = match estimator {
        Estimator::MeanGrey => p.pressure_of_mean_grey == Calibrated::Saturated,
        Estimator::HertzFit | Estimator::PixelMean => p.saturated_pixels > 0,
    };
    if saturated {
        return FilmError::SaturatedPrint {
            indenter,
            estimator,
            saturated: p.saturated_pixels,
            pixels: p.pixel_count,
            top_pa: top,
        };
    }
    let below = format!(
        "{} of its {} pixels ({:.1} %)",
        p.below_range_pixels,
        p.pixel_count,
        percent(p.below_range_pixels, p.pixel_count)
    );
    // A mean-grey failure that is no saturation is a mean grey below range.
    let reason = match estimator {
        Estimator::MeanGrey => format!(
            "its mean grey {:.4} reads below the calibration's bottom, {bottom:.3e} Pa, as do \
             {below}: too faint a print to read",
            p.mean_grey
        ),
        _ if p.below_range_pixels == p.pixel_count => format!(
            "all {} of its pixels read below the calibration's bottom, {bottom:.3e} Pa: too \
             faint a print to read",
            p.pixel_count
        ),
        _ if p.below_range_pixels > 0 => format!(
            "{below} read below the calibration's bottom, {bottom:.3e} Pa, and the others are \
             too few for a Hertz fit or follow no Hertz profile (flat-topped or conical?)"
        ),
        _ => "its calibrated pixels are too few for a Hertz fit or follow no Hertz profile \
              (flat-topped or conical?)"
            .into(),
    };
    FilmError::PrintNotMeasured {
        indenter,
        estimator,
        reason,
    }
}
