//! `rolling-bem --bem-from DIR`: the BEM signals of an earlier
//! `rolling-bem` run of the same stretch, read back from its
//! `rolling_bem_steps.csv` and `rolling_bem_sensors.csv`, so that another
//! fidelity is compared without solving the BEM again (the BEM reference
//! does not depend on the model's laws). The saved run's
//! `rolling_bem_reference.txt` ([`BemReference`]) must name the same
//! contact as this scenario's.

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Context, Result, bail};
use tyreroad::bem_rolling::{BemReference, BemRollingResult, BemStep};
use tyreroad::rolling::StepStatus;
use tyreroad::scenario::Scenario;

/// A CSV file as rows of named columns.
fn read_csv(path: &Path) -> Result<Vec<HashMap<String, String>>> {
    let text =
        std::fs::read_to_string(path).with_context(|| format!("reading {}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<String> = lines
        .next()
        .with_context(|| format!("{}: empty", path.display()))?
        .split(',')
        .map(str::to_string)
        .collect();
    Ok(lines
        .filter(|l| !l.is_empty())
        .map(|l| {
            header
                .iter()
                .cloned()
                .zip(l.split(',').map(str::to_string))
                .collect()
        })
        .collect())
}

fn number(row: &HashMap<String, String>, key: &str, path: &Path) -> Result<f64> {
    let v = row
        .get(key)
        .with_context(|| format!("{}: no column {key}", path.display()))?;
    v.parse()
        .with_context(|| format!("{}: {key} = {v:?} is not a number", path.display()))
}

/// The step id in `row`'s `step` column: a whole number (a step id read
/// as a float and cast would turn `2.5` into 2 and `1e30` into the
/// largest id).
fn step_id(row: &HashMap<String, String>, path: &Path) -> Result<usize> {
    let v = row
        .get("step")
        .with_context(|| format!("{}: no column step", path.display()))?;
    v.parse()
        .with_context(|| format!("{}: step = {v:?} is not a step id", path.display()))
}

/// The file beside the saved signals that names what the BEM was solved
/// for ([`BemReference::to_text`]).
pub const REFERENCE_FILE: &str = "rolling_bem_reference.txt";

/// How a saved BEM run must match this scenario's.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SavedAs {
    /// The same BEM run (`--bem-from`): every input of [`BemReference`].
    SameRun,
    /// A convergence check of it (`--bem-check`): the same contact on
    /// another grid, margin or tolerance
    /// ([`BemReference::without_discretisation`]).
    Check,
}

/// Refuses a saved run whose [`REFERENCE_FILE`] names another contact than
/// `reference` (this scenario's), listing each input that differs. A
/// folder saved before the file was written is read with a warning.
fn check_reference(dir: &Path, reference: &BemReference, saved_as: SavedAs) -> Result<()> {
    let path = dir.join(REFERENCE_FILE);
    let text = match std::fs::read_to_string(&path) {
        Ok(text) => text,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => {
            say!(
                "warning: {} has no {REFERENCE_FILE} (saved by an older version): \
                 nothing checks that its BEM was solved for this scenario's road, load and tread",
                dir.display()
            );
            return Ok(());
        }
        Err(e) => return Err(e).with_context(|| format!("reading {}", path.display())),
    };
    let saved = BemReference::parse(&text).with_context(|| path.display().to_string())?;
    let differences = match saved_as {
        SavedAs::SameRun => reference.differences(&saved),
        SavedAs::Check => reference
            .without_discretisation()
            .differences(&saved.without_discretisation()),
    };
    if !differences.is_empty() {
        bail!(
            "{}: the saved BEM run was solved for another contact than this scenario's:\n  {}\n\
             (solve the BEM again without --bem-from/--bem-check, or point them at a run of this scenario)",
            dir.display(),
            differences.join("\n  ")
        );
    }
    Ok(())
}

/// The BEM run saved in `dir` for `scenario`'s sensors and sampling, once
/// its [`REFERENCE_FILE`] is found to name `reference`'s contact as
/// `saved_as` asks.
pub fn read(
    dir: &Path,
    scenario: &Scenario,
    (reference, saved_as): (&BemReference, SavedAs),
) -> Result<BemRollingResult> {
    check_reference(dir, reference, saved_as)?;
    let config = scenario.rolling_config()?;
    let steps_path = dir.join("rolling_bem_steps.csv");
    let sensors_path = dir.join("rolling_bem_sensors.csv");
    let mut steps = Vec::new();
    for row in read_csv(&steps_path)? {
        let total_force = number(&row, "total_force_bem_n", &steps_path)?;
        steps.push(BemStep {
            index: step_id(&row, &steps_path)?,
            position: number(&row, "position_m", &steps_path)?,
            time: number(&row, "time_s", &steps_path)?,
            total_force,
            approach: number(&row, "approach_bem_m", &steps_path)?,
            contact_area: number(&row, "contact_area_bem_m2", &steps_path)?,
            iterations: 0,
            status: if total_force.is_finite() {
                StepStatus::Converged
            } else {
                StepStatus::Failed
            },
            sensor_forces: vec![f64::NAN; config.sensors.len()],
        });
    }
    let first = steps.first().map_or(0, |s| s.index);
    let mut seen = std::collections::HashSet::new();
    for row in read_csv(&sensors_path)? {
        let name = row.get("sensor").map(String::as_str).unwrap_or("");
        let Some(k) = config.sensors.iter().position(|s| s.name == name) else {
            bail!(
                "{}: sensor {name:?} is not the scenario's",
                sensors_path.display()
            );
        };
        let i = step_id(&row, &sensors_path)?;
        let Some(step) = i.checked_sub(first).and_then(|j| steps.get_mut(j)) else {
            bail!(
                "{}: step {i} is not in the steps file",
                sensors_path.display()
            );
        };
        if !seen.insert((i, k)) {
            bail!(
                "{}: step {i}, sensor {name:?} is given twice",
                sensors_path.display()
            );
        }
        step.sensor_forces[k] = number(&row, "bem_n", &sensors_path)?;
    }
    check_complete(&steps, scenario, &steps_path, &sensors_path)?;
    Ok(BemRollingResult {
        steps,
        sample_rate: config.speed / config.step,
        window: (0, 0),
    })
}

/// A saved run is whole: every step's position, time and (for a converged
/// step) force, approach and area are finite, and every converged step has
/// every sensor's force. A truncated or edited file would otherwise turn
/// into NaN samples that the comparison's maxima and band levels skip.
fn check_complete(
    steps: &[BemStep],
    scenario: &Scenario,
    steps_path: &Path,
    sensors_path: &Path,
) -> Result<()> {
    let config = scenario.rolling_config()?;
    if steps.is_empty() {
        bail!("{}: no steps", steps_path.display());
    }
    for (j, s) in steps.iter().enumerate() {
        // Rows one per step, in order: a repeated or missing step id would
        // put every later sample at another step than the BEM solved.
        let expected = steps[0].index.checked_add(j);
        if Some(s.index) != expected {
            bail!(
                "{}: row {} is step {}, expected step {} (the steps are consecutive)",
                steps_path.display(),
                j + 1,
                s.index,
                expected.map_or("past the largest id".into(), |e| e.to_string())
            );
        }
        if !(s.position.is_finite() && s.time.is_finite()) {
            bail!(
                "{}: step {} has no finite position or time",
                steps_path.display(),
                s.index
            );
        }
        if s.status != StepStatus::Converged {
            continue;
        }
        if !(s.approach.is_finite() && s.contact_area.is_finite()) {
            bail!(
                "{}: step {} has a force but no finite approach or contact area",
                steps_path.display(),
                s.index
            );
        }
        if let Some(k) = s.sensor_forces.iter().position(|f| !f.is_finite()) {
            bail!(
                "{}: step {} has no finite force for sensor {:?} (a truncated or edited file?)",
                sensors_path.display(),
                s.index,
                config.sensors[k].name
            );
        }
        // The BEM's pressures are compressive: no force or area below zero,
        // and no sensor beyond the step's whole force (to the rounding of
        // the saved digits). The approach may be negative: a tread held
        // above the road under an imposed height touches nothing.
        if !(s.total_force >= 0.0 && s.contact_area >= 0.0) {
            bail!(
                "{}: step {} has a negative force ({} N) or contact area ({} m²)",
                steps_path.display(),
                s.index,
                s.total_force,
                s.contact_area
            );
        }
        let slack = 1e-6 * s.total_force;
        if let Some((k, f)) = s
            .sensor_forces
            .iter()
            .enumerate()
            .find(|&(_, &f)| !(-slack..=s.total_force + slack).contains(&f))
        {
            bail!(
                "{}: step {}: sensor {:?} carries {f} N, outside 0 … {} N (the step's whole force)",
                sensors_path.display(),
                s.index,
                config.sensors[k].name,
                s.total_force
            );
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use tyreroad::bem_rolling::{BemRollingOptions, scenario_bem_reference};

    fn scenario(load: &str) -> Scenario {
        on_grid(load, "nx = 96\nny = 48\nspacing = \"0.25 mm\"")
    }

    fn on_grid(load: &str, grid: &str) -> Scenario {
        on_grid_with(load, grid, "")
    }

    /// [`on_grid`] with `sensors` (`[[rolling.sensor]]` tables).
    fn on_grid_with(load: &str, grid: &str, sensors: &str) -> Scenario {
        let text = format!(
            "name = \"saved\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [rolling]\nstart = \"10 mm\"\nend = \"14 mm\"\nstep = \"1 mm\"\nspeed = \"10 m/s\"\n\
             [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.1 m\"\nradius_y = \"0.1 m\"\n\
             length = \"6 mm\"\nwidth = \"6 mm\"\n{sensors}[rolling.control]\nload = \"{load}\"\n\
             [texture]\nmin_prominence = \"0.1 mm\"\nmin_area = \"1 mm2\"\n\
             [texture.synth]\nkind = \"exposed_aggregate\"\n{grid}\nseed = 7\n"
        );
        Scenario::parse(&text, "saved").expect("the scenario parses")
    }

    /// Regression (adversarial run, 2026-11-30): `rolling-bem --bem-from`
    /// compared a model run with a BEM run saved for another load (or
    /// road, or tread) whenever the footprint positions agreed.
    #[test]
    fn saved_bem_signals_of_another_contact_are_refused_before_any_solve() {
        let dir = std::env::temp_dir().join(format!("tyreroad-bem-from-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let options = BemRollingOptions::default();
        let here = Path::new(".");
        let saved = scenario_bem_reference(&scenario("30 N"), here, &options).expect("reference");
        std::fs::write(dir.join(REFERENCE_FILE), saved.to_text()).expect("write");

        let this = scenario("40 N");
        let reference = scenario_bem_reference(&this, here, &options).expect("reference");
        let message = format!(
            "{:#}",
            read(&dir, &this, (&reference, SavedAs::SameRun)).expect_err("another load")
        );
        assert!(
            message.contains("another contact") && message.contains("control: saved Load(30.0)"),
            "{message}"
        );

        // The same contact passes the check and goes on to the signals
        // (none here).
        let same = scenario("30 N");
        let message = format!(
            "{:#}",
            read(&dir, &same, (&saved, SavedAs::SameRun)).expect_err("no signals")
        );
        assert!(message.contains("rolling_bem_steps.csv"), "{message}");

        // A convergence check on a coarser grid is the same contact; as
        // the same run it is refused, naming the grid.
        let coarse = on_grid("30 N", "nx = 48\nny = 24\nspacing = \"0.5 mm\"");
        let coarse = scenario_bem_reference(&coarse, here, &options).expect("reference");
        std::fs::write(dir.join(REFERENCE_FILE), coarse.to_text()).expect("write");
        let message = format!(
            "{:#}",
            read(&dir, &same, (&saved, SavedAs::Check)).expect_err("no signals")
        );
        assert!(message.contains("rolling_bem_steps.csv"), "{message}");
        let message = format!(
            "{:#}",
            read(&dir, &same, (&saved, SavedAs::SameRun)).expect_err("grid")
        );
        assert!(message.contains("grid: saved 48 x 24 cells"), "{message}");
        std::fs::remove_dir_all(&dir).expect("clean up");
    }

    /// Regression (adversarial run, 2026-11-30): saved signals that are
    /// finite but impossible were compared as the BEM's: a sensor carrying
    /// 2.4e30 N or −2.4 N under a 30 N load, a step id repeated (every later
    /// sample shifted a step). Each is refused, naming the file and step;
    /// the same files unedited are read.
    #[test]
    fn saved_bem_signals_no_contact_can_give_are_refused() {
        let dir = std::env::temp_dir().join(format!("tyreroad-bem-odd-{}", std::process::id()));
        std::fs::create_dir_all(&dir).expect("temp dir");
        let this = on_grid_with(
            "30 N",
            "nx = 96\nny = 48\nspacing = \"0.25 mm\"",
            "[[rolling.sensor]]\nname = \"s\"\nx0 = \"8 mm\"\nx1 = \"12 mm\"\n\
             y0 = \"-2 mm\"\ny1 = \"2 mm\"\n",
        );
        let options = BemRollingOptions::default();
        let reference = scenario_bem_reference(&this, Path::new("."), &options).expect("reference");
        std::fs::write(dir.join(REFERENCE_FILE), reference.to_text()).expect("write");
        let write = |ids: [&str; 5], sensor: &str, approach: &str| {
            let mut steps = String::from(
                "step,position_m,time_s,total_force_bem_n,approach_bem_m,contact_area_bem_m2\n",
            );
            let mut sensors = String::from("step,sensor,bem_n\n");
            for (k, id) in ids.into_iter().enumerate() {
                let x = 0.010 + 1e-3 * k as f64;
                steps.push_str(&format!("{id},{x},{},30,{approach},2e-6\n", x / 10.0));
                let f = if k == 2 { sensor } else { "12.5" };
                sensors.push_str(&format!("{k},s,{f}\n"));
            }
            std::fs::write(dir.join("rolling_bem_steps.csv"), steps).expect("write");
            std::fs::write(dir.join("rolling_bem_sensors.csv"), sensors).expect("write");
        };
        let read_back = || read(&dir, &this, (&reference, SavedAs::SameRun));
        let ids = ["0", "1", "2", "3", "4"];
        write(ids, "30", "1e-4");
        let saved = read_back().expect("a whole run");
        assert_eq!(saved.steps[2].sensor_forces, [30.0]);
        // A negative approach is a run's right (a tread held above the road).
        write(ids, "30", "-1e-4");
        assert!(read_back().is_ok());
        for (sensor, ids, expected) in [
            (
                "2.4e30",
                ids,
                "step 2: sensor \"s\" carries 2400000000000000000000000000000 N, outside 0 … 30 N",
            ),
            ("-2.4", ids, "step 2: sensor \"s\" carries -2.4 N"),
            (
                "12.5",
                ["0", "0", "2", "3", "4"],
                "row 2 is step 0, expected step 1",
            ),
            // Read as a float and cast, 1e30 was the largest id and the
            // next row's expected id overflowed.
            (
                "12.5",
                ["0", "1e30", "2", "3", "4"],
                "step = \"1e30\" is not a step id",
            ),
        ] {
            write(ids, sensor, "1e-4");
            let message = format!("{:#}", read_back().expect_err(sensor));
            assert!(message.contains(expected), "{message}");
        }
        std::fs::remove_dir_all(&dir).expect("clean up");
    }
}
