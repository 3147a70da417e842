//! Pressure-film analysis from an image array (docs/film.md).

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tyreroad::film::{
    AnalysisOptions, Calibration, FilmResponse, LlwCurve, Scan, Scanner, Threshold, analyse,
};

use crate::arrays::{rows_cols, slice, to_numpy1, to_numpy2, view2};
use crate::errors::{OrRaise, input_error};

/// Analyses a scanned pressure film: `grey` float64 (height, width)
/// normalised grey levels in [0, 1] (1 white, 0 black), `pixel_size` (m),
/// the Fujifilm Prescale LLW `curve` ("A"–"D"), an optional fixed
/// `threshold_grey` (else midway from background to the darkest print), and
/// `min_pixels` the smallest print kept.
///
/// Returns a dict: per print arrays `area` (m²), `radius` (apparent radius,
/// m), `centroid_x`, `centroid_y` (pixels), `mean_pressure` (Pa, mean of
/// the pixels' pressures), `force` (N, mean pressure × area); `labels`
/// uint32 (height, width); `threshold_grey`, `background_grey`. The grey
/// levels are converted once to float32 (the scan's own type).
#[pyfunction]
#[pyo3(signature = (grey, pixel_size, curve="B", threshold_grey=None, min_pixels=20))]
fn analyse_film<'py>(
    py: Python<'py>,
    grey: &Bound<'py, PyAny>,
    pixel_size: f64,
    curve: &str,
    threshold_grey: Option<f64>,
    min_pixels: usize,
) -> PyResult<Bound<'py, PyDict>> {
    let view = view2(grey, "grey")?;
    let (h, w) = rows_cols(&view);
    let values = slice(&view)?;
    if let Some(v) = values.iter().find(|g| !(0.0..=1.0).contains(*g)) {
        return Err(input_error(format!(
            "grey: value {v} outside [0, 1] (normalised grey levels)"
        )));
    }
    let scan = Scan::from_grey(
        w,
        h,
        values.iter().map(|&g| g as f32).collect(),
        Some(pixel_size),
        32,
    )
    .or_raise()?;
    let curve = match curve {
        "A" => LlwCurve::A,
        "B" => LlwCurve::B,
        "C" => LlwCurve::C,
        "D" => LlwCurve::D,
        other => {
            return Err(input_error(format!(
                "curve: {other:?}, expected one of \"A\", \"B\", \"C\", \"D\""
            )));
        }
    };
    let response = FilmResponse::new(Calibration::llw(curve).or_raise()?, Scanner::default());
    let mut options = AnalysisOptions {
        min_pixels,
        ..AnalysisOptions::default()
    };
    if let Some(t) = threshold_grey {
        options.threshold = Threshold::Grey(t);
    }
    let d = py
        .detach(|| analyse(&scan, &response, &options))
        .or_raise()?;
    let out = PyDict::new(py);
    let column =
        |f: &dyn Fn(&tyreroad::film::Print) -> f64| to_numpy1(py, d.prints.iter().map(f).collect());
    out.set_item("area", column(&|p| p.area))?;
    out.set_item("radius", column(&|p| p.apparent_radius))?;
    out.set_item("centroid_x", column(&|p| p.centroid_px.0))?;
    out.set_item("centroid_y", column(&|p| p.centroid_px.1))?;
    out.set_item("mean_pressure", column(&|p| p.mean_pixel_pressure))?;
    out.set_item("force", column(&|p| p.mean_pixel_pressure * p.area))?;
    let counts = |f: &dyn Fn(&tyreroad::film::Print) -> usize| -> Vec<usize> {
        d.prints.iter().map(f).collect()
    };
    out.set_item("saturated_pixels", counts(&|p| p.saturated_pixels))?;
    out.set_item("below_range_pixels", counts(&|p| p.below_range_pixels))?;
    out.set_item(
        "touches_border",
        d.prints
            .iter()
            .map(|p| p.touches_border)
            .collect::<Vec<_>>(),
    )?;
    // A saturated print's force counts its saturated pixels at the
    // calibration's top: a lower bound, which a user must be told of.
    for (k, p) in d.prints.iter().enumerate() {
        if p.saturated_pixels > 0 {
            crate::errors::warn(
                py,
                &format!(
                    "print {k}: {} pixels read above the calibration's top (saturated): its \
                     mean pressure and force are lower bounds",
                    p.saturated_pixels
                ),
            )?;
        }
    }
    out.set_item("threshold_grey", d.threshold_grey)?;
    out.set_item("background_grey", d.background_grey)?;
    out.set_item("labels", to_numpy2(py, d.labels, d.height, d.width)?)?;
    Ok(out)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(analyse_film, m)?)?;
    Ok(())
}
