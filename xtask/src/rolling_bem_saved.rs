//! `rolling-bem --bem-from DIR`: the BEM signals of an earlier
//! `rolling-bem` run of the same stretch, read back from its
//! `rolling_bem_steps.csv` and `rolling_bem_sensors.csv`, so that another
//! fidelity is compared without solving the BEM again (the BEM reference
//! does not depend on the model's laws).

use std::collections::HashMap;
use std::path::Path;

use anyhow::{Context, Result, bail};
use tyreroad::bem_rolling::{BemRollingResult, BemStep};
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

/// The BEM run saved in `dir` for `scenario`'s sensors and sampling.
pub fn read(dir: &Path, scenario: &Scenario) -> Result<BemRollingResult> {
    let config = scenario.rolling_config()?;
    let steps_path = dir.join("rolling_bem_steps.csv");
    let sensors_path = dir.join("rolling_bem_sensors.csv");
    let mut steps = Vec::new();
    for row in read_csv(&steps_path)? {
        let total_force = number(&row, "total_force_bem_n", &steps_path)?;
        steps.push(BemStep {
            index: number(&row, "step", &steps_path)? as usize,
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
    for row in read_csv(&sensors_path)? {
        let name = row.get("sensor").map(String::as_str).unwrap_or("");
        let Some(k) = config.sensors.iter().position(|s| s.name == name) else {
            bail!(
                "{}: sensor {name:?} is not the scenario's",
                sensors_path.display()
            );
        };
        let i = number(&row, "step", &sensors_path)? as usize;
        let Some(step) = i.checked_sub(first).and_then(|j| steps.get_mut(j)) else {
            bail!(
                "{}: step {i} is not in the steps file",
                sensors_path.display()
            );
        };
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
    for s in steps {
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
    }
    Ok(())
}
