//! Parameter sweeps: a sweep file names a base scenario and the values of
//! its parameters; every run is the base scenario with one value of each,
//! run on one machine (rayon, [`run_local`]) or over MPI ranks
//! (`crate::mpi::run_sweep`), giving one table row per run.
//!
//! ```toml
//! scenario = "rolling_small.toml"   # relative to the sweep file
//! combine = "grid"                  # every combination; "list": i-th of each
//! [parameters]
//! load = ["20 N", "30 N", "40 N"]
//! speed = ["30 km/h", "50 km/h"]
//! "rolling.synthetic_road.seed" = [1, 2]   # any scenario key, dotted
//! ```
//!
//! Named parameters: `load` (`rolling.control.load`), `speed`
//! (`rolling.speed`), `tyre` (`rolling.tread`, a table), `material`
//! (`material`, a table), `road` (`texture.file`, relative to the base
//! scenario's directory); any other name is a dotted key of the scenario.
//! Parameters are taken in the order of their names (TOML tables are
//! sorted); grid runs are numbered with the last one varying fastest.

use std::path::{Path, PathBuf};

use rayon::prelude::*;
use toml::{Table, Value};
use tyreroad::scenario::{RollingRun, Scenario};

use crate::DistributedError;
use crate::wire::{Reader, Writer};

/// Most runs a sweep may expand to (a typo in a grid should not queue a
/// billion runs).
pub const MAX_RUNS: usize = 100_000;

/// One run of a sweep: its number, its parameter values, its scenario.
#[derive(Clone, Debug)]
pub struct SweepRun {
    /// Run number (0-based, the table's order).
    pub index: usize,
    /// `(parameter name, value as written in the table)`.
    pub params: Vec<(String, String)>,
    /// The base scenario with this run's values set.
    pub scenario: Table,
}

impl SweepRun {
    /// The run's scenario, parsed and checked.
    ///
    /// # Errors
    /// The scenario with these values is invalid: the scenario's own error,
    /// its origin said as "the base scenario with this run's values" (the
    /// run's number is its row's, which the caller prints beside it).
    pub fn parse(&self) -> Result<Scenario, DistributedError> {
        let text = toml::to_string(&self.scenario)
            .map_err(|e| DistributedError::Sweep(format!("run {}: {e}", self.index)))?;
        Ok(Scenario::parse(
            &text,
            "the base scenario with this run's values",
        )?)
    }
}

/// A parsed sweep file.
#[derive(Clone, Debug)]
pub struct Sweep {
    /// The base scenario's directory (relative paths of runs resolve there).
    pub base_dir: PathBuf,
    /// Every run, in order.
    pub runs: Vec<SweepRun>,
}

fn sweep_err(origin: &str, m: impl std::fmt::Display) -> DistributedError {
    DistributedError::Sweep(format!("{origin}: {m}"))
}

/// The scenario key of a parameter name.
pub fn parameter_key(name: &str) -> &str {
    match name {
        "load" => "rolling.control.load",
        "speed" => "rolling.speed",
        "tyre" => "rolling.tread",
        "material" => "material",
        "road" => "texture.file",
        other => other,
    }
}

impl Sweep {
    /// Reads a sweep file and its base scenario.
    ///
    /// # Errors
    /// [`DistributedError::Sweep`] naming the file and the key for an
    /// unreadable file, unknown keys, an empty or mismatched parameter
    /// list, or too many runs.
    pub fn from_path(path: &Path) -> Result<Self, DistributedError> {
        let text =
            std::fs::read_to_string(path).map_err(|e| sweep_err(&path.display().to_string(), e))?;
        let dir = path.parent().unwrap_or(Path::new("."));
        Self::parse(&text, &path.display().to_string(), dir)
    }

    /// Parses a sweep file's text; `dir` is the directory its `scenario`
    /// path is relative to.
    ///
    /// # Errors
    /// As [`Sweep::from_path`].
    pub fn parse(text: &str, origin: &str, dir: &Path) -> Result<Self, DistributedError> {
        let table: Table = toml::from_str(text).map_err(|e| sweep_err(origin, e))?;
        for key in table.keys() {
            if !["scenario", "combine", "parameters"].contains(&key.as_str()) {
                return Err(sweep_err(
                    origin,
                    format!("unknown key `{key}` (expected scenario, combine, parameters)"),
                ));
            }
        }
        let scenario = table
            .get("scenario")
            .and_then(Value::as_str)
            .ok_or_else(|| sweep_err(origin, "`scenario` (a path) is missing"))?;
        let scenario_path = dir.join(scenario);
        let base_text = std::fs::read_to_string(&scenario_path)
            .map_err(|e| sweep_err(origin, format!("scenario {}: {e}", scenario_path.display())))?;
        let base: Table = toml::from_str(&base_text)
            .map_err(|e| sweep_err(&scenario_path.display().to_string(), e))?;
        let grid = match table.get("combine") {
            None => true,
            Some(v) if v.as_str() == Some("grid") => true,
            Some(v) if v.as_str() == Some("list") => false,
            // The value as the file wrote it (`"product"`, `3`), not Rust's
            // `Some("product")`.
            Some(other) => {
                return Err(sweep_err(
                    origin,
                    format!("combine = {other}: expected \"grid\" or \"list\""),
                ));
            }
        };
        let params = table
            .get("parameters")
            .and_then(Value::as_table)
            .ok_or_else(|| sweep_err(origin, "[parameters] is missing"))?;
        let mut axes: Vec<(String, &Vec<Value>)> = Vec::new();
        for (name, values) in params {
            let values = values.as_array().filter(|v| !v.is_empty()).ok_or_else(|| {
                sweep_err(
                    origin,
                    format!("parameters.{name}: expected a non-empty list"),
                )
            })?;
            axes.push((name.clone(), values));
        }
        if axes.is_empty() {
            return Err(sweep_err(origin, "[parameters] names no parameter"));
        }
        // Two parameters that set the same key (`load` and
        // `rolling.control.load`), or one key inside the other's table
        // (`material` and `material.youngs_modulus`), would leave the run
        // with whichever was set last while the table shows both.
        for (i, (a, _)) in axes.iter().enumerate() {
            for (b, _) in &axes[i + 1..] {
                let (ka, kb) = (parameter_key(a), parameter_key(b));
                let inside = |outer: &str, inner: &str| {
                    inner.len() > outer.len()
                        && inner.starts_with(outer)
                        && inner.as_bytes()[outer.len()] == b'.'
                };
                if ka == kb || inside(ka, kb) || inside(kb, ka) {
                    return Err(sweep_err(
                        origin,
                        format!(
                            "parameters.{a} (`{ka}`) and parameters.{b} (`{kb}`) set the same \
                             part of the scenario: keep one"
                        ),
                    ));
                }
            }
        }
        let combos = combinations(&axes, grid).map_err(|m| sweep_err(origin, m))?;
        let mut runs = Vec::with_capacity(combos.len());
        for (index, combo) in combos.into_iter().enumerate() {
            let mut scenario = base.clone();
            let mut shown = Vec::with_capacity(axes.len());
            for ((name, values), &pick) in axes.iter().zip(&combo) {
                set_dotted(&mut scenario, parameter_key(name), values[pick].clone())
                    .map_err(|m| sweep_err(origin, format!("parameters.{name}: {m}")))?;
                shown.push((name.clone(), show(&values[pick])));
            }
            runs.push(SweepRun {
                index,
                params: shown,
                scenario,
            });
        }
        Ok(Self {
            base_dir: scenario_path
                .parent()
                .unwrap_or(Path::new("."))
                .to_path_buf(),
            runs,
        })
    }
}

/// The value picks of every run: a grid (last axis fastest) or a list
/// (every axis the same length, the i-th value of each).
fn combinations(axes: &[(String, &Vec<Value>)], grid: bool) -> Result<Vec<Vec<usize>>, String> {
    if !grid {
        let n = axes[0].1.len();
        if let Some((name, v)) = axes.iter().find(|(_, v)| v.len() != n) {
            return Err(format!(
                "combine = \"list\" needs lists of one length: {} has {n}, {name} has {}",
                axes[0].0,
                v.len()
            ));
        }
        return Ok((0..n).map(|i| vec![i; axes.len()]).collect());
    }
    let total = axes
        .iter()
        .try_fold(1usize, |acc, (_, v)| acc.checked_mul(v.len()))
        .filter(|&n| n <= MAX_RUNS)
        .ok_or_else(|| format!("the grid has more than {MAX_RUNS} runs"))?;
    Ok((0..total)
        .map(|mut k| {
            let mut pick = vec![0; axes.len()];
            for (a, (_, v)) in axes.iter().enumerate().rev() {
                pick[a] = k % v.len();
                k /= v.len();
            }
            pick
        })
        .collect())
}

fn set_dotted(table: &mut Table, key: &str, value: Value) -> Result<(), String> {
    let mut parts: Vec<&str> = key.split('.').collect();
    let last = parts.pop().filter(|s| !s.is_empty()).ok_or("empty key")?;
    let mut at = table;
    for p in parts {
        at = at
            .entry(p)
            .or_insert_with(|| Value::Table(Table::new()))
            .as_table_mut()
            .ok_or_else(|| format!("`{p}` of `{key}` is not a table in the scenario"))?;
    }
    at.insert(last.to_string(), value);
    Ok(())
}

/// A value as the table shows it: strings bare, anything else as TOML.
fn show(v: &Value) -> String {
    match v {
        Value::String(s) => s.clone(),
        other => other.to_string(),
    }
}

/// One row of the result table.
#[derive(Clone, Debug, PartialEq)]
pub struct SweepRow {
    /// Run number.
    pub index: usize,
    /// Parameter values, as in [`SweepRun::params`].
    pub params: Vec<(String, String)>,
    /// What the run gave, or why it failed (that run's failure only).
    pub outcome: Result<RunSummary, String>,
}

/// The numbers of one run.
#[derive(Clone, Debug, PartialEq)]
pub struct RunSummary {
    /// Steps on the path.
    pub steps: usize,
    /// Steps whose solve failed (NaN values).
    pub failed_steps: usize,
    /// Mean total force over the steps with values (N).
    pub mean_force: f64,
    /// The signal the levels are of: `approach` (load control, dB re 1 µm)
    /// or `force` (displacement control, dB re the reference force).
    pub level_of: String,
    /// Overall level `10 log10 Σ 10^(L_b/10)` over the bands (dB).
    pub overall_db: f64,
    /// `(nominal band centre Hz, level dB)` of each one-third-octave band.
    pub bands: Vec<(f64, f64)>,
}

impl RunSummary {
    /// The numbers of a finished run (the spectra of its primary signal, as
    /// `third_octave.csv` holds them).
    pub fn of(run: &RollingRun) -> Self {
        let forces: Vec<f64> = run
            .result
            .total_force()
            .into_iter()
            .filter(|f| f.is_finite())
            .collect();
        let mean_force = if forces.is_empty() {
            f64::NAN
        } else {
            forces.iter().sum::<f64>() / forces.len() as f64
        };
        let bands: Vec<(f64, f64)> = run
            .spectra
            .primary
            .iter()
            .map(|b| (b.band.nominal, b.level_db))
            .collect();
        let power: f64 = bands.iter().map(|(_, l)| 10f64.powf(l / 10.0)).sum();
        Self {
            steps: run.result.steps.len(),
            failed_steps: run.status_counts()[2],
            mean_force,
            level_of: if run.spectra.load_control {
                "approach"
            } else {
                "force"
            }
            .into(),
            overall_db: 10.0 * power.log10(),
            bands,
        }
    }
}

impl SweepRow {
    pub(crate) fn write(&self, w: &mut Writer) {
        w.u(self.index);
        w.u(self.params.len());
        for (k, v) in &self.params {
            w.s(k);
            w.s(v);
        }
        match &self.outcome {
            Err(e) => {
                w.u(0);
                w.s(e);
            }
            Ok(s) => {
                w.u(1);
                w.u(s.steps);
                w.u(s.failed_steps);
                w.f(s.mean_force);
                w.s(&s.level_of);
                w.f(s.overall_db);
                w.u(s.bands.len());
                for &(c, l) in &s.bands {
                    w.f(c);
                    w.f(l);
                }
            }
        }
    }

    pub(crate) fn read(r: &mut Reader<'_>) -> Result<Self, DistributedError> {
        let index = r.u()?;
        let n = r.count(16)?;
        let params = (0..n)
            .map(|_| Ok((r.s()?, r.s()?)))
            .collect::<Result<_, DistributedError>>()?;
        let outcome = if r.u()? == 0 {
            Err(r.s()?)
        } else {
            let (steps, failed_steps, mean_force) = (r.u()?, r.u()?, r.f()?);
            let (level_of, overall_db) = (r.s()?, r.f()?);
            let m = r.count(16)?;
            let bands = (0..m)
                .map(|_| Ok((r.f()?, r.f()?)))
                .collect::<Result<_, DistributedError>>()?;
            Ok(RunSummary {
                steps,
                failed_steps,
                mean_force,
                level_of,
                overall_db,
                bands,
            })
        };
        Ok(Self {
            index,
            params,
            outcome,
        })
    }
}

fn csv_cell(s: &str) -> String {
    if s.contains([',', '"', '\n']) {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

/// The result table (CSV): `run`, one column per parameter, `steps`,
/// `failed_steps`, `mean_force_n`, `level_of`, `overall_db`, then one
/// `L_<centre>hz_db` column per band any run has (empty where a run lacks
/// it, e.g. a slower run's highest bands), then `error`. Rows in run order.
pub fn table_csv(rows: &[SweepRow]) -> String {
    let mut rows: Vec<&SweepRow> = rows.iter().collect();
    rows.sort_by_key(|r| r.index);
    let mut centres: Vec<f64> = rows
        .iter()
        .filter_map(|r| r.outcome.as_ref().ok())
        .flat_map(|s| s.bands.iter().map(|b| b.0))
        .collect();
    centres.sort_by(f64::total_cmp);
    centres.dedup();
    let names: Vec<&str> = rows
        .first()
        .map(|r| r.params.iter().map(|p| p.0.as_str()).collect())
        .unwrap_or_default();
    let mut head = vec!["run".to_string()];
    head.extend(names.iter().map(|n| csv_cell(n)));
    head.extend(
        [
            "steps",
            "failed_steps",
            "mean_force_n",
            "level_of",
            "overall_db",
        ]
        .map(String::from),
    );
    head.extend(centres.iter().map(|c| format!("L_{c}hz_db")));
    head.push("error".into());
    let mut out = head.join(",") + "\n";
    for r in rows {
        let mut cells = vec![r.index.to_string()];
        cells.extend(r.params.iter().map(|p| csv_cell(&p.1)));
        match &r.outcome {
            Ok(s) => {
                cells.push(s.steps.to_string());
                cells.push(s.failed_steps.to_string());
                cells.push(format!("{:.9e}", s.mean_force));
                cells.push(s.level_of.clone());
                cells.push(format!("{:.3}", s.overall_db));
                for c in &centres {
                    let level = s.bands.iter().find(|b| b.0 == *c);
                    cells.push(level.map(|b| format!("{:.3}", b.1)).unwrap_or_default());
                }
                cells.push(String::new());
            }
            Err(e) => {
                cells.extend(std::iter::repeat_n(String::new(), 5 + centres.len()));
                cells.push(csv_cell(e));
            }
        }
        out += &(cells.join(",") + "\n");
    }
    out
}

/// Runs every run on this machine, `threads` at a time (0: every core),
/// `run_one` giving each run's row (it records a failure in the row rather
/// than failing the sweep). Rows in run order.
///
/// # Errors
/// The thread pool cannot be built.
pub fn run_local<F>(
    runs: &[SweepRun],
    threads: usize,
    run_one: F,
) -> Result<Vec<SweepRow>, DistributedError>
where
    F: Fn(&SweepRun) -> SweepRow + Sync,
{
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .map_err(|e| DistributedError::Sweep(format!("thread pool: {e}")))?;
    Ok(pool.install(|| runs.par_iter().map(&run_one).collect()))
}

/// A sweep row, as a worker sends it to rank 0.
pub fn encode_row(row: &SweepRow) -> Vec<u8> {
    let mut w = Writer::default();
    row.write(&mut w);
    w.0
}

/// The inverse of [`encode_row`].
///
/// # Errors
/// [`DistributedError::Wire`] for a truncated or damaged message.
pub fn decode_row(bytes: &[u8]) -> Result<SweepRow, DistributedError> {
    let mut r = Reader::new(bytes);
    let row = SweepRow::read(&mut r)?;
    r.finished()?;
    Ok(row)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn fixtures() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures")
    }

    #[test]
    fn a_grid_expands_every_combination_last_parameter_fastest() {
        let text = r#"
            scenario = "rolling_small.toml"
            [parameters]
            load = ["20 N", "30 N"]
            speed = ["30 km/h", "50 km/h", "70 km/h"]
        "#;
        let sweep = Sweep::parse(text, "t", &fixtures()).unwrap();
        assert_eq!(sweep.runs.len(), 6);
        let r = &sweep.runs[4];
        assert_eq!(
            r.params,
            [
                ("load".into(), "30 N".into()),
                ("speed".into(), "50 km/h".into())
            ]
        );
        let s = r.parse().unwrap();
        let rolling = s.rolling.as_ref().unwrap();
        assert_eq!(rolling.speed.value(), 50.0 / 3.6);
        assert_eq!(rolling.control.load.map(|l| l.value()), Some(30.0));
    }

    #[test]
    fn lists_take_the_ith_value_and_bad_files_are_named_errors() {
        let list = r#"
            scenario = "rolling_small.toml"
            combine = "list"
            [parameters]
            load = ["20 N", "30 N"]
            "rolling.synthetic_road.seed" = [1, 2]
        "#;
        let sweep = Sweep::parse(list, "t", &fixtures()).unwrap();
        assert_eq!(sweep.runs.len(), 2);
        assert_eq!(sweep.runs[1].params[1].1, "2");
        for (bad, says) in [
            (list.replace("[1, 2]", "[1]"), "one length"),
            (
                list.replace("combine = \"list\"", "combine = \"all\""),
                "combine = \"all\": expected",
            ),
            (list.replace("[1, 2]", "[]"), "non-empty"),
            (list.replace("scenario =", "scenari ="), "unknown key"),
            (list.replace("rolling_small", "missing"), "missing.toml"),
        ] {
            let err = Sweep::parse(&bad, "sweep.toml", &fixtures())
                .unwrap_err()
                .to_string();
            assert!(err.contains(says) && err.contains("sweep.toml"), "{err}");
        }
        let wrong = list.replace("\"20 N\", \"30 N\"", "\"20 m\", \"30 N\"");
        let sweep = Sweep::parse(&wrong, "t", &fixtures()).unwrap();
        assert!(sweep.runs[0].parse().is_err());
        assert!(sweep.runs[1].parse().is_ok());
    }

    /// Regression (stops 44–45 noted it): a run's bad value read "sweep
    /// `sweep run 0: [rolling.control] load` = …", after the row's own
    /// "run 0:". The run's error is the scenario's, said once, its origin
    /// the base scenario with the run's values.
    #[test]
    fn a_run_s_bad_value_is_said_once_without_repeating_the_sweep() {
        let text = r#"
            scenario = "rolling_small.toml"
            [parameters]
            load = ["1e30 N"]
        "#;
        let sweep = Sweep::parse(text, "t", &fixtures()).unwrap();
        let err = sweep.runs[0].parse().unwrap_err().to_string();
        assert!(
            err.contains("the base scenario with this run's values: [rolling.control] load")
                && err.contains("1e30 N")
                && !err.contains("sweep"),
            "{err}"
        );
    }

    /// Rows survive the wire bit for bit, and the table has one line per
    /// run in run order, failures included, whatever the arrival order.
    #[test]
    fn rows_round_trip_and_tabulate_in_run_order() {
        let ok = SweepRow {
            index: 1,
            params: vec![("load".into(), "30 N".into())],
            outcome: Ok(RunSummary {
                steps: 40,
                failed_steps: 0,
                mean_force: 30.000000001,
                level_of: "approach".into(),
                overall_db: 12.3456,
                bands: vec![(100.0, 10.0), (125.0, 8.0)],
            }),
        };
        let bad = SweepRow {
            index: 0,
            params: vec![("load".into(), "-1 N".into())],
            outcome: Err("load: must be > 0, \"x\"".into()),
        };
        for row in [&ok, &bad] {
            assert_eq!(&decode_row(&encode_row(row)).unwrap(), row);
        }
        let bytes = encode_row(&ok);
        assert!(decode_row(&bytes[..bytes.len() - 3]).is_err());
        let table = table_csv(&[ok, bad]);
        let lines: Vec<&str> = table.lines().collect();
        assert_eq!(
            lines[0],
            "run,load,steps,failed_steps,mean_force_n,level_of,overall_db,L_100hz_db,L_125hz_db,error"
        );
        assert!(lines[1].starts_with("0,-1 N,,,,,,,,\"load"));
        assert_eq!(
            lines[2],
            "1,30 N,40,0,3.000000000e1,approach,12.346,10.000,8.000,"
        );
    }

    /// A parameter named by its alias and by its key, or a table and a key
    /// inside it, is refused: the run would keep one and the table show
    /// both (a run labelled 20 N once rolled at 30 N).
    #[test]
    fn two_parameters_on_the_same_key_are_refused() {
        let dir = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures");
        for params in [
            "load = [\"20 N\"]\n\"rolling.control.load\" = [\"30 N\"]",
            "material = [\"a.toml\"]\n\"material.youngs_modulus\" = [\"5 MPa\"]",
        ] {
            let text = format!("scenario = \"rolling_small.toml\"\n[parameters]\n{params}\n");
            let err = Sweep::parse(&text, "s.toml", &dir).unwrap_err().to_string();
            assert!(err.contains("set the same part of the scenario"), "{err}");
        }
        let text = "scenario = \"rolling_small.toml\"\n[parameters]\nload = [\"20 N\"]\nspeed = [\"50 km/h\"]\n";
        assert!(Sweep::parse(text, "s.toml", &dir).is_ok());
    }
}
