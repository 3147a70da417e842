//! Scenario runs from Python: a TOML path, TOML text or a dict with the
//! file's structure; static, texture and rolling results as arrays.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::Mutex;
use std::sync::atomic::{AtomicBool, Ordering};

use pyo3::prelude::*;
use pyo3::types::{PyBool, PyDict, PyFloat, PyInt, PyList, PyString, PyTuple};
use tyreroad::scenario::{
    HistoryResult, Progress, RoadSummary, RollingRun, RunOptions, Scenario, ScenarioResult,
    StaticResult, TextureResult, TextureSummary, approach_past_window_warning,
};

use crate::arrays::{to_numpy1, to_numpy2};
use crate::errors::{OrRaise, input_error};

/// How deep a scenario dict may nest: a scenario file is four levels deep
/// at most; a dict that holds itself (or nests thousands deep) would
/// otherwise recurse until the stack overflows.
const MAX_SCENARIO_DEPTH: usize = 32;

/// A Python value (dict, list, str, int, float, bool) as TOML, `depth`
/// levels inside the scenario.
fn to_toml(obj: &Bound<'_, PyAny>, key: &str, depth: usize) -> PyResult<toml::Value> {
    if depth > MAX_SCENARIO_DEPTH {
        return Err(input_error(format!(
            "scenario {key}: nested more than {MAX_SCENARIO_DEPTH} levels deep (a dict or \
             list that contains itself?)"
        )));
    }
    if obj.is_instance_of::<PyBool>() {
        return Ok(toml::Value::Boolean(obj.extract()?));
    }
    if obj.is_instance_of::<PyInt>() {
        return obj.extract().map(toml::Value::Integer).map_err(|_| {
            input_error(format!(
                "scenario {key}: {obj} does not fit a TOML integer (64-bit signed)"
            ))
        });
    }
    if obj.is_instance_of::<PyFloat>() {
        return Ok(toml::Value::Float(obj.extract()?));
    }
    if obj.is_instance_of::<PyString>() {
        return Ok(toml::Value::String(obj.extract()?));
    }
    if let Ok(dict) = obj.cast::<PyDict>() {
        let mut table = toml::Table::new();
        for (k, v) in dict.iter() {
            let k: String = k
                .extract()
                .map_err(|_| input_error(format!("scenario {key}: keys must be strings")))?;
            let value = to_toml(&v, &format!("{key}.{k}"), depth + 1)?;
            table.insert(k, value);
        }
        return Ok(toml::Value::Table(table));
    }
    if obj.is_instance_of::<PyList>() || obj.is_instance_of::<PyTuple>() {
        let items: Vec<Bound<'_, PyAny>> = obj.extract()?;
        return items
            .iter()
            .enumerate()
            .map(|(i, v)| to_toml(v, &format!("{key}[{i}]"), depth + 1))
            .collect::<PyResult<Vec<_>>>()
            .map(toml::Value::Array);
    }
    Err(input_error(format!(
        "scenario {key}: {} is not a TOML value (dict, list, str, int, float, bool)",
        obj.get_type()
    )))
}

/// The scenario and the directory its relative paths resolve against.
fn load(scenario: &Bound<'_, PyAny>, base_dir: Option<PathBuf>) -> PyResult<(Scenario, PathBuf)> {
    if let Ok(dict) = scenario.cast::<PyDict>() {
        let text = toml::to_string(&to_toml(dict.as_any(), "", 0)?)
            .map_err(|e| input_error(format!("scenario: {e}")))?;
        let s = Scenario::parse(&text, "<dict>").or_raise()?;
        return Ok((s, base_dir.unwrap_or_else(|| PathBuf::from("."))));
    }
    // TOML text: several lines, or one `key = value` line that names no
    // file (a one-line scenario is TOML, not a path).
    if let Ok(text) = scenario.extract::<String>()
        && (text.contains('\n') || (text.contains('=') && !std::path::Path::new(&text).exists()))
    {
        let s = Scenario::parse(&text, "<text>").or_raise()?;
        return Ok((s, base_dir.unwrap_or_else(|| PathBuf::from("."))));
    }
    let path: PathBuf = scenario.extract().map_err(|_| {
        input_error("scenario: expected a dict, TOML text or a path to a .toml file")
    })?;
    let s = Scenario::from_path(&path).or_raise()?;
    let dir = path.parent().map(PathBuf::from).unwrap_or_default();
    Ok((s, base_dir.unwrap_or(dir)))
}

/// A `[static.history]` run: per step time, load, approach, receding
/// count, and the forces as a (steps, asperities) array.
fn history_dict<'py>(py: Python<'py>, r: &HistoryResult) -> PyResult<Bound<'py, PyDict>> {
    let out = PyDict::new(py);
    out.set_item("kind", "history")?;
    out.set_item("name", &r.name)?;
    out.set_item("ids", r.ids.clone())?;
    let steps = |f: fn(&tyreroad::scenario::HistoryStep) -> f64| {
        to_numpy1(py, r.steps.iter().map(f).collect())
    };
    out.set_item("time", steps(|s| s.time))?;
    out.set_item("load", steps(|s| s.load))?;
    out.set_item("approach", steps(|s| s.approach))?;
    out.set_item("receding", steps(|s| s.receding as f64))?;
    let forces: Vec<f64> = r
        .steps
        .iter()
        .flat_map(|s| s.forces.iter().copied())
        .collect();
    out.set_item("forces", to_numpy2(py, forces, r.steps.len(), r.ids.len())?)?;
    out.set_item("failure", r.failure.clone())?;
    Ok(out)
}

fn static_dict<'py>(py: Python<'py>, r: &StaticResult) -> PyResult<Bound<'py, PyDict>> {
    let loads: Vec<f64> = r.runs.iter().map(|l| l.load).collect();
    let (nl, n) = (loads.len(), r.rows.len() / loads.len().max(1));
    let out = PyDict::new(py);
    out.set_item("kind", "static")?;
    out.set_item("name", &r.name)?;
    out.set_item(
        "ids",
        r.rows.iter().take(n).map(|row| row.id).collect::<Vec<_>>(),
    )?;
    out.set_item(
        "x",
        to_numpy1(py, r.rows.iter().take(n).map(|row| row.x).collect()),
    )?;
    out.set_item(
        "y",
        to_numpy1(py, r.rows.iter().take(n).map(|row| row.y).collect()),
    )?;
    let grid = |f: fn(&tyreroad::scenario::StaticRow) -> f64| {
        to_numpy2(py, r.rows.iter().map(f).collect::<Vec<f64>>(), nl, n)
    };
    out.set_item("forces", grid(|row| row.force)?)?;
    out.set_item("radii", grid(|row| row.radius)?)?;
    let runs =
        |f: fn(&tyreroad::scenario::LoadRun) -> f64| to_numpy1(py, r.runs.iter().map(f).collect());
    out.set_item("loads", to_numpy1(py, loads))?;
    out.set_item("total_force", runs(|l| l.total))?;
    out.set_item("approach", runs(|l| l.approach))?;
    out.set_item("iterations", runs(|l| l.iterations as f64))?;
    out.set_item("residual", runs(|l| l.residual))?;
    // Wall time of each load's solve, measured on the Rust side.
    out.set_item("solve_seconds", runs(|l| l.seconds))?;
    out.set_item("failed_loads", r.failed_loads.clone())?;
    Ok(out)
}

fn texture_dict<'py>(py: Python<'py>, r: TextureResult) -> PyResult<Bound<'py, PyDict>> {
    let out = static_dict(py, &r.statics)?;
    out.set_item("kind", "texture")?;
    let (nx, ny) = r.texture.size;
    out.set_item("size", (nx, ny))?;
    out.set_item("spacing", r.texture.spacing)?;
    out.set_item("segmented", r.texture.segmented)?;
    let maps = PyList::empty(py);
    for l in r.loads {
        let map = match l.two_scale.map {
            Some(field) => {
                let g = field.grid().clone();
                let d = PyDict::new(py);
                d.set_item(
                    "pressure",
                    to_numpy2(py, field.into_values(), g.ny(), g.nx())?,
                )?;
                d.set_item("origin", (g.origin()[0], g.origin()[1]))?;
                d.set_item("spacing", (g.dx(), g.dy()))?;
                d.into_any()
            }
            None => py.None().into_bound(py),
        };
        maps.append(map)?;
    }
    out.set_item("pressure_maps", maps)?;
    out.set_item("calibration_fallbacks", calibration_fallbacks(&r.texture))?;
    Ok(out)
}

/// Each cap of a calibrated road that kept its Wilke law, with why (empty
/// on the Wilke rung or when every cap calibrated).
fn calibration_fallbacks(t: &TextureSummary) -> Vec<String> {
    t.calibration
        .iter()
        .flat_map(|c| c.fallbacks.iter().map(ToString::to_string))
        .collect()
}

fn rolling_dict<'py>(py: Python<'py>, r: &RollingRun) -> PyResult<Bound<'py, PyDict>> {
    let res = &r.result;
    let out = PyDict::new(py);
    out.set_item("kind", "rolling")?;
    out.set_item("sample_rate", res.sample_rate)?;
    out.set_item("time", to_numpy1(py, res.times()))?;
    out.set_item("total_force", to_numpy1(py, res.total_force()))?;
    out.set_item("approach", to_numpy1(py, res.approach()))?;
    out.set_item("contact_area", to_numpy1(py, res.contact_area()))?;
    let names: Vec<&str> = r.config.sensors.iter().map(|s| s.name.as_str()).collect();
    let (ns, nt) = (names.len(), res.steps.len());
    let sensors: Vec<f64> = (0..ns).flat_map(|k| res.sensor(k)).collect();
    out.set_item("sensor_names", names)?;
    out.set_item("sensor_forces", to_numpy2(py, sensors, ns, nt)?)?;
    let fallbacks = match &r.road {
        RoadSummary::Texture(t) => calibration_fallbacks(t),
        _ => Vec::new(),
    };
    out.set_item("calibration_fallbacks", fallbacks)?;
    out.set_item(
        "status",
        res.steps
            .iter()
            .map(|s| format!("{:?}", s.status))
            .collect::<Vec<_>>(),
    )?;
    let sp = &r.spectra;
    out.set_item(
        "band_centre",
        to_numpy1(py, sp.primary.iter().map(|b| b.band.centre).collect()),
    )?;
    out.set_item(
        "band_level_db",
        to_numpy1(py, sp.primary.iter().map(|b| b.level_db).collect()),
    )?;
    let nb = sp.primary.len();
    let sensor_levels: Vec<f64> = sp
        .sensors
        .iter()
        .flat_map(|bands| bands.iter().map(|b| b.level_db))
        .collect();
    if sensor_levels.len() == sp.sensors.len() * nb {
        out.set_item(
            "sensor_level_db",
            to_numpy2(py, sensor_levels, sp.sensors.len(), nb)?,
        )?;
    }
    Ok(out)
}

/// Runs a scenario: `scenario` is a path to a .toml file, TOML text, or a
/// dict with the file's structure (values with units as strings, "5 mm").
/// Relative paths in it resolve against `base_dir` (default: the file's
/// directory, or the working directory).
///
/// A rolling scenario with `[rolling] checkpoint = true` checkpoints its
/// steps into `checkpoint_dir` and resumes from it (the scenario's
/// checkpoint is not written without it).
///
/// `progress(done, total)` is called after each rolling step (from a
/// worker thread, holding the GIL); returning `False` (or any false value
/// but `None`: `np.False_`, 0) stops the run, which
/// raises `ScenarioError` ("interrupted after k of n steps"). Ctrl-C stops a rolling run between steps
/// (`KeyboardInterrupt`); a static run finishes first.
///
/// Returns a dict whose `kind` is `"static"` (per-load arrays `forces`,
/// `radii` of shape (loads, N), …), `"texture"` (the same plus the
/// two-scale `pressure_maps`) or `"rolling"` (`time`, `total_force`,
/// `sensor_forces` (sensors, steps), one-third-octave `band_centre` (Hz) and
/// `band_level_db`, …). Every kind carries `warnings`: what `cargo xtask
/// run` prints as `warning:` lines (contacts pressed past their shapes or
/// tables, a footprint off the map, an approach past the tread's window),
/// each also raised as a `UserWarning`.
#[pyfunction]
#[pyo3(signature = (scenario, base_dir=None, progress=None, checkpoint_dir=None))]
fn run_scenario<'py>(
    py: Python<'py>,
    scenario: &Bound<'py, PyAny>,
    base_dir: Option<PathBuf>,
    progress: Option<Py<PyAny>>,
    checkpoint_dir: Option<PathBuf>,
) -> PyResult<Bound<'py, PyDict>> {
    let (scenario, base_dir) = load(scenario, base_dir)?;
    // Said before the steps, as the CLI does: pressed this deep, a step
    // can take minutes.
    let early: Vec<String> = scenario
        .rolling
        .as_ref()
        .and_then(|_| scenario.rolling_config().ok())
        .and_then(|config| approach_past_window_warning(&config))
        .into_iter()
        .collect();
    for w in &early {
        crate::errors::warn(py, w)?;
    }
    let callback_error: Mutex<Option<PyErr>> = Mutex::new(None);
    let result = crate::interrupt::run(py, |cancel: &AtomicBool| {
        let on_step = |p: Progress| {
            if cancel.load(Ordering::Relaxed) {
                return ControlFlow::Break(());
            }
            let Some(cb) = &progress else {
                return ControlFlow::Continue(());
            };
            // `None` (no return statement) goes on; any other false value
            // (`False`, NumPy's `np.False_`, 0) stops the run.
            Python::attach(|py| {
                let verdict = cb
                    .call1(py, (p.done, p.total))
                    .and_then(|v| Ok(v.is_none(py) || v.bind(py).is_truthy()?));
                match verdict {
                    Ok(true) => ControlFlow::Continue(()),
                    Ok(false) => ControlFlow::Break(()),
                    Err(e) => {
                        if let Ok(mut slot) = callback_error.lock() {
                            slot.get_or_insert(e);
                        }
                        ControlFlow::Break(())
                    }
                }
            })
        };
        let options = RunOptions {
            base_dir,
            progress: Some(&on_step),
            checkpoint_dir: checkpoint_dir.clone(),
            ..RunOptions::default()
        };
        scenario.run(&options)
    })?;
    if let Some(e) = callback_error.lock().ok().and_then(|mut s| s.take()) {
        return Err(e);
    }
    let result = result.or_raise()?;
    let after = result.warnings();
    let out = match result {
        ScenarioResult::Static(r) => static_dict(py, &r),
        ScenarioResult::Texture(r) => texture_dict(py, *r),
        ScenarioResult::Rolling(r) => rolling_dict(py, &r),
        ScenarioResult::History(r) => history_dict(py, &r),
    }?;
    for w in &after {
        crate::errors::warn(py, w)?;
    }
    out.set_item(
        "warnings",
        early.into_iter().chain(after).collect::<Vec<_>>(),
    )?;
    Ok(out)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(run_scenario, m)?)?;
    Ok(())
}
