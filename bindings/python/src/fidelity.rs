//! The fidelity ladder against the full BEM on a road of one's own
//! (docs/validation.md, "Your own road against the BEM"): what `cargo xtask
//! validate --textures --scenario` measures, on a height array.

use pyo3::prelude::*;
use pyo3::types::{PyDict, PyList};
use tyreroad::fidelity::compare::{CompareOptions, compare_texture as rust_compare};
use tyreroad::fidelity::{CalibrationOptions, Fidelity, RUNGS};
use tyreroad::multipoint::SolverOptions;
use tyreroad::texture_road::TextureRoadOptions;

use crate::arrays::view2;
use crate::errors::{OrRaise, input_error};
use crate::geometry::Material;
use crate::texture::height_map;

/// Compares each rung of the fidelity ladder with the full BEM on a rigid
/// road `heights` float64 (ny, nx) (m, NaN where not measured; filled for
/// the BEM) with cells `dx × dy` (m), pressed by a flat half-space of
/// `material` at each of `loads` (N, solved in increasing order, the BEM
/// warm-started from the last).
///
/// `rungs`: names of `wilke`, `calibrated`, `distributed`, `clustered`,
/// `calibrated_fields` (every rung when `None`). The road is segmented at
/// `min_prominence` (m) and `min_area` (m²); flat tops wider than
/// `max_cap_width` (m) are split into tiles.
///
/// Returns a dict: `asperities`, `bem_cells`, `bem` (per load: `load`,
/// `approach`, `contact_area`, `iterations`, `seconds`) and `rungs`, a dict
/// by rung name of `setup_seconds` and `loads`, per load either the metrics
/// (`load`, `approach_error`, `area_error`, `wrong_asperity`,
/// `wrong_block_10mm`, `wrong_block_5mm`, `field_block_10mm`,
/// `field_block_5mm`, fractions; `seconds`, `bem_seconds`; `warnings`:
/// summits inside each other's contact patch, where the answer is no
/// road's) or `error`, the message of that load's failure; `unavailable`:
/// why a rung did not run at all (`None` when it ran). `notes`: what the
/// reference cannot say (missing points filled, a contact covering most of
/// the map or only a few cells, a single asperity). Each warning and note
/// is also raised as a `UserWarning`. Loads listed twice are compared once.
/// Runs without the GIL; Ctrl-C is raised when the comparison ends.
#[pyfunction]
#[pyo3(signature = (heights, dx, dy, material, loads, *, rungs=None, min_prominence=0.2e-3, min_area=2e-6, max_cap_width=None))]
#[allow(clippy::too_many_arguments)]
fn compare_texture<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    dx: f64,
    dy: f64,
    material: &Material,
    loads: Vec<f64>,
    rungs: Option<Vec<String>>,
    min_prominence: f64,
    min_area: f64,
    max_cap_width: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    if loads.is_empty() {
        return Err(input_error("loads: give at least one load (N)"));
    }
    if let Some(bad) = loads.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
        return Err(input_error(format!(
            "loads: {bad} is no load (each must be a finite force > 0 N)"
        )));
    }
    let rungs: Vec<Fidelity> = match rungs {
        None => RUNGS.to_vec(),
        Some(names) => names
            .iter()
            .map(|n| {
                n.parse::<Fidelity>().map_err(|_| {
                    let known: Vec<&str> = RUNGS.iter().map(|r| r.name()).collect();
                    input_error(format!(
                        "rungs: unknown rung {n:?} (one of {})",
                        known.join(", ")
                    ))
                })
            })
            .collect::<PyResult<_>>()?,
    };
    for (name, v) in [("min_prominence", min_prominence), ("min_area", min_area)] {
        if !(v.is_finite() && v >= 0.0) {
            return Err(input_error(format!("{name}: {v} (must be finite and ≥ 0)")));
        }
    }
    if let Some(w) = max_cap_width
        && !(w.is_finite() && w > 0.0)
    {
        return Err(input_error(format!(
            "max_cap_width: {w} (must be a width > 0 in m)"
        )));
    }
    let map = height_map(&view2(heights, "heights")?, dx, dy)?;
    let mut road = TextureRoadOptions::new(min_prominence, min_area);
    road.max_cap_width = max_cap_width;
    let options = CompareOptions {
        loads,
        road,
        calibration: CalibrationOptions::default(),
        rungs,
        solver: SolverOptions::default(),
        neighbour_passes: 2,
    };
    let material = material.inner;
    let c =
        crate::interrupt::run(py, |_cancel| rust_compare(&map, material, &options))?.or_raise()?;
    let out = PyDict::new(py);
    out.set_item("asperities", c.asperities)?;
    out.set_item("bem_cells", c.bem_cells)?;
    let bem = PyList::empty(py);
    for b in &c.bem {
        let d = PyDict::new(py);
        d.set_item("load", b.load)?;
        d.set_item("approach", b.approach)?;
        d.set_item("contact_area", b.contact_area)?;
        d.set_item("iterations", b.iterations)?;
        d.set_item("seconds", b.seconds)?;
        bem.append(d)?;
    }
    out.set_item("bem", bem)?;
    let by_rung = PyDict::new(py);
    for r in &c.rungs {
        let d = PyDict::new(py);
        d.set_item("setup_seconds", r.setup_seconds)?;
        d.set_item("unavailable", r.unavailable.clone())?;
        let loads = PyList::empty(py);
        for l in &r.loads {
            let row = PyDict::new(py);
            match l {
                Ok(l) => {
                    row.set_item("load", l.load)?;
                    row.set_item("approach_error", l.approach_error)?;
                    row.set_item("area_error", l.area_error)?;
                    row.set_item("wrong_asperity", l.wrong_asperity)?;
                    row.set_item("wrong_block_10mm", l.wrong_block[0])?;
                    row.set_item("wrong_block_5mm", l.wrong_block[1])?;
                    row.set_item("field_block_10mm", l.field_block[0])?;
                    row.set_item("field_block_5mm", l.field_block[1])?;
                    row.set_item("seconds", l.seconds)?;
                    row.set_item("bem_seconds", l.bem_seconds)?;
                    row.set_item("warnings", l.warnings.clone())?;
                    for w in &l.warnings {
                        crate::errors::warn(py, &format!("{}: {w}", r.fidelity.name()))?;
                    }
                }
                Err(e) => row.set_item("error", e)?,
            }
            loads.append(row)?;
        }
        d.set_item("loads", loads)?;
        by_rung.set_item(r.fidelity.name(), d)?;
    }
    out.set_item("rungs", by_rung)?;
    for n in &c.notes {
        crate::errors::warn(py, n)?;
    }
    out.set_item("notes", c.notes)?;
    Ok(out)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(compare_texture, m)?)?;
    Ok(())
}
