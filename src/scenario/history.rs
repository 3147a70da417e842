//! `[static.history]`: a loading history (ramp, hold, unload) on a static
//! scenario's `[[asperity]]` list, run by the hereditary multipoint model
//! (the steps of [`tyreroad_viscoelastic::run_load_history`]) with a viscoelastic tread
//! (README.md, "Scenario files"; docs/viscoelastic.md, "Loading history in
//! scenario files").
//!
//! ```toml
//! [static.history]
//! steps = 10              # steps per segment (default 10)
//! receding = "ting"       # or "lee_radok" (default "ting")
//! bands_per_decade = 20   # Ting's depth bands (default 20, 1 to 1000)
//!
//! [[static.history.segment]]
//! duration = "2 ms"       # a ramp from 0 to 100 N
//! load = "100 N"
//!
//! [[static.history.segment]]
//! duration = "2 ms"       # a hold: the same load
//! load = "100 N"
//!
//! [[static.history.segment]]
//! duration = "2 ms"       # unloading to 60 N
//! load = "60 N"
//! steps = 20              # this segment's own step count
//! ```
//!
//! Each segment goes linearly, in time, from the previous segment's end
//! load (0 N at time 0) to its `load` over its `duration`. An elastic
//! material has no history, so a history with one is refused, naming
//! `[material]`.

use serde::Deserialize;
use tyreroad_viscoelastic::{
    DEFAULT_BANDS_PER_DECADE, Hereditary, MAX_BANDS_PER_DECADE, Prony, Receding, ViscoStep,
};

use super::output::{OutputSet, fmt};
use super::ranges::{LOAD_RANGE, in_range};
use super::units::{Force, Time};
use super::{Scenario, ScenarioError};

/// `[static.history]`: the segments and their default step count.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct HistorySpec {
    /// Steps per segment when a segment gives none (default 10).
    pub steps: Option<usize>,
    /// The segments, in time order.
    #[serde(rename = "segment", default)]
    pub segments: Vec<SegmentSpec>,
    /// How receding contacts are treated (default Ting's).
    pub receding: Option<RecedingSpec>,
    /// Ting's depth bands per decade of interpenetration (default
    /// [`DEFAULT_BANDS_PER_DECADE`]).
    pub bands_per_decade: Option<usize>,
}

/// `[static.history] receding`: the treatment of a contact that recedes
/// (docs/viscoelastic.md, "Receding contacts: Ting's treatment").
#[derive(Debug, Clone, Copy, PartialEq, Eq, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum RecedingSpec {
    /// Ting's treatment by depth bands ([`Receding::Ting`]).
    Ting,
    /// Lee–Radok's recursion on the whole force, also while receding
    /// ([`Receding::LeeRadok`]).
    LeeRadok,
}

/// `[[static.history.segment]]`: a linear change of the load.
#[derive(Debug, Clone, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SegmentSpec {
    /// How long the segment lasts.
    pub duration: Time,
    /// The total load at its end (the previous end load held is a hold).
    pub load: Force,
    /// Its steps (default `[static.history] steps`).
    pub steps: Option<usize>,
}

/// Default steps per segment.
pub const DEFAULT_SEGMENT_STEPS: usize = 10;

/// Most steps of a whole history (all segments): the bound of a rolling
/// path, [`tyreroad_rolling::MAX_STEPS`]. Each step is one elastic
/// multipoint solve and one row per asperity of `history.csv`.
pub const MAX_HISTORY_STEPS: usize = tyreroad_rolling::MAX_STEPS;

/// Range (s) of a segment's duration: a nanosecond to about 30 years.
pub const SEGMENT_DURATION_RANGE: [f64; 2] = [1e-9, 1e9];

impl HistorySpec {
    /// The treatment of receding contacts.
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming `[static.history] bands_per_decade`
    /// outside `1..=1000`, or given with `receding = "lee_radok"` (which has
    /// no bands, so the value would be dropped without a word).
    pub fn receding(&self) -> Result<Receding, ScenarioError> {
        let bands = |expected: &str| ScenarioError::Value {
            key: "[static.history] bands_per_decade".into(),
            value: self.bands_per_decade.unwrap_or(0).to_string(),
            expected: expected.into(),
        };
        match (self.receding, self.bands_per_decade) {
            (Some(RecedingSpec::LeeRadok), Some(_)) => Err(bands(
                "no value with receding = \"lee_radok\" (bands are Ting's)",
            )),
            (Some(RecedingSpec::LeeRadok), None) => Ok(Receding::LeeRadok),
            (_, per_decade) => {
                let per_decade = per_decade.unwrap_or(DEFAULT_BANDS_PER_DECADE);
                if (1..=MAX_BANDS_PER_DECADE).contains(&per_decade) {
                    Ok(Receding::Ting { per_decade })
                } else {
                    Err(bands(&format!("from 1 to {MAX_BANDS_PER_DECADE}")))
                }
            }
        }
    }

    /// The history as `(time (s), load (N))` samples after time 0.
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming the segment's key for no segment, a
    /// duration outside [`SEGMENT_DURATION_RANGE`], a load outside the
    /// range of a static load (`[0, 1e7]` N), zero steps, more than
    /// [`MAX_HISTORY_STEPS`] steps in all, or a step too short to advance
    /// the time after the segments before it (a nanosecond after 30 years).
    pub fn samples(&self) -> Result<Vec<(f64, f64)>, ScenarioError> {
        // The whole section is checked when the file is read, which calls
        // this: the receding keys too.
        self.receding()?;
        let value = |key: String, value: String, expected: &str| ScenarioError::Value {
            key,
            value,
            expected: expected.into(),
        };
        if self.segments.is_empty() {
            return Err(value(
                "[static.history] segment".into(),
                "none".into(),
                "at least one [[static.history.segment]] (duration, load)",
            ));
        }
        if self.steps == Some(0) {
            return Err(value(
                "[static.history] steps".into(),
                "0".into(),
                "at least 1",
            ));
        }
        // Counted before anything is allocated: a runaway step count is an
        // error, not an allocation.
        let mut total = 0usize;
        for (k, segment) in self.segments.iter().enumerate() {
            let steps = segment
                .steps
                .or(self.steps)
                .unwrap_or(DEFAULT_SEGMENT_STEPS);
            total = total.saturating_add(steps);
            if total > MAX_HISTORY_STEPS {
                let key = match (segment.steps, self.steps) {
                    (Some(_), _) => format!("[[static.history.segment]] {} steps", k + 1),
                    _ => "[static.history] steps".into(),
                };
                return Err(value(
                    key,
                    steps.to_string(),
                    &format!("at most {MAX_HISTORY_STEPS} steps over the whole history"),
                ));
            }
        }
        let (mut time, mut load) = (0.0, 0.0);
        let mut samples = Vec::with_capacity(total);
        for (k, segment) in self.segments.iter().enumerate() {
            let key = |name: &str| format!("[[static.history.segment]] {} {name}", k + 1);
            let duration = segment.duration.value();
            in_range(
                &key("duration"),
                duration,
                SEGMENT_DURATION_RANGE,
                false,
                "s",
            )?;
            in_range(&key("load"), segment.load.value(), LOAD_RANGE, false, "N")?;
            let end = segment.load.value();
            let steps = segment
                .steps
                .or(self.steps)
                .unwrap_or(DEFAULT_SEGMENT_STEPS);
            if steps == 0 {
                return Err(value(key("steps"), "0".into(), "at least 1"));
            }
            for j in 1..=steps {
                let s = j as f64 / steps as f64;
                let t = time + s * duration;
                // A step lost in the rounding of the time before it would be
                // a zero time step deep in the run.
                if samples.last().is_some_and(|&(before, _)| t <= before) {
                    return Err(value(
                        key("duration"),
                        format!("{duration:e} s in {steps} steps after {time:e} s"),
                        "steps long enough to advance the time (more than 1e-16 of the \
                         time before them)",
                    ));
                }
                samples.push((t, load + s * (end - load)));
            }
            time += duration;
            load = end;
        }
        Ok(samples)
    }
}

/// One step of a history run.
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryStep {
    /// Time at the step's end (s).
    pub time: f64,
    /// Imposed total load (N).
    pub load: f64,
    /// Rigid approach `δ0` (m).
    pub approach: f64,
    /// Asperity forces (N), in `[[asperity]]` order.
    pub forces: Vec<f64>,
    /// Asperities whose contact receded over the step.
    pub receding: usize,
}

/// A loading history's run: the steps solved, in time order, and the
/// failure that ended it early, if any (the later steps depend on it, so
/// none is solved after it).
#[derive(Clone, Debug, PartialEq)]
pub struct HistoryResult {
    /// The scenario's name.
    pub name: String,
    /// Asperity labels, in order.
    pub ids: Vec<u32>,
    /// The steps solved.
    pub steps: Vec<HistoryStep>,
    /// Why the run stopped before the history's end.
    pub failure: Option<String>,
    /// What the run should say of its input (a master curve whose storage
    /// modulus dips with frequency); [`run_load_history_scenario`] leaves
    /// it empty, the caller that fitted the tread fills it.
    pub warnings: Vec<String>,
}

/// Runs the scenario's `[static.history]` on its `[[asperity]]` list with
/// the viscoelastic tread `material` (its Poisson's ratio must be the
/// scenario's `[material]` one, whose modulus only serves as the laws'
/// reference and is divided out).
///
/// # Errors
/// [`ScenarioError::Value`] naming `[material]` when `material` is `None`
/// (an elastic tread has no loading history); [`ScenarioError::Invalid`]
/// without `[static.history]`, on a `[texture]` or `[rolling]` scenario, or
/// when no step could be solved; the errors of
/// [`HistorySpec::samples`] and of the problem's construction.
pub fn run_load_history_scenario(
    scenario: &Scenario,
    material: Option<&Prony>,
) -> Result<HistoryResult, ScenarioError> {
    let Some(history) = scenario
        .static_case
        .as_ref()
        .and_then(|s| s.history.as_ref())
    else {
        return Err(ScenarioError::Invalid(format!(
            "scenario {}: no [static.history] section",
            origin(scenario)
        )));
    };
    let Some(material) = material else {
        return Err(elastic_refusal(scenario));
    };
    if scenario.texture.is_some() || scenario.rolling.is_some() {
        return Err(ScenarioError::Invalid(format!(
            "scenario {}: [static.history] runs on an [[asperity]] list, not with a \
             [texture] or [rolling] section",
            origin(scenario)
        )));
    }
    let samples = history.samples()?;
    let problem = scenario.problem()?;
    let receding = history.receding()?;
    let mut solver = Hereditary::with_receding(
        &problem,
        material.clone(),
        scenario.solver_options(),
        receding,
    )
    .map_err(|e| ScenarioError::Value {
        key: "[material] poisson_ratio".into(),
        value: e.to_string(),
        expected: "the viscoelastic tread's Poisson's ratio".into(),
    })?;
    // Stepped here rather than by `run_load_history` so that a failing step
    // ends the run as a recorded failure and keeps the steps before it.
    let mut steps = Vec::with_capacity(samples.len());
    let mut failure = None;
    for &(time, load) in &samples {
        match solver.step_load(time - solver.time(), load) {
            Ok(step) => steps.push(history_step(step, load)),
            Err(error) => {
                failure = Some(error.to_string());
                break;
            }
        }
    }
    if steps.is_empty() {
        return Err(ScenarioError::Invalid(format!(
            "scenario {}: [static.history]: no step solved ({})",
            origin(scenario),
            failure.unwrap_or_default()
        )));
    }
    Ok(HistoryResult {
        name: scenario.name.clone(),
        ids: scenario.ids(),
        steps,
        failure,
        warnings: Vec::new(),
    })
}

/// Where the scenario came from (its file), to start an error as those of
/// `Scenario::parse` do; its name when it has no origin.
fn origin(scenario: &Scenario) -> &str {
    if scenario.origin.is_empty() {
        &scenario.name
    } else {
        &scenario.origin
    }
}

/// The error for a `[static.history]` with an elastic tread.
pub(crate) fn elastic_refusal(scenario: &Scenario) -> ScenarioError {
    ScenarioError::Value {
        key: format!("{}: [material]", origin(scenario)),
        value: "an elastic tread".into(),
        expected: "a viscoelastic tread (Prony series): [static.history] needs one, \
                   an elastic tread's force does not depend on the loading history"
            .into(),
    }
}

fn history_step(step: ViscoStep, load: f64) -> HistoryStep {
    HistoryStep {
        time: step.time,
        load,
        approach: step.approach,
        forces: step.forces,
        receding: step.receding,
    }
}

/// One row of `history.csv`.
#[derive(serde::Serialize)]
struct HistoryRow {
    #[serde(serialize_with = "fmt::sci9")]
    time_s: f64,
    #[serde(serialize_with = "fmt::sci9")]
    load_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    approach_m: f64,
    receding: usize,
    id: u32,
    #[serde(serialize_with = "fmt::sci9")]
    force_n: f64,
}

/// Writes `history.csv` into `set`: one row per step and asperity (time,
/// load, approach, receding count, asperity id, its force), time-major.
///
/// # Errors
/// As [`OutputSet::write_csv`].
pub fn write_history_csv(result: &HistoryResult, set: &mut OutputSet) -> Result<(), ScenarioError> {
    let rows: Vec<HistoryRow> = result
        .steps
        .iter()
        .flat_map(|s| {
            s.forces
                .iter()
                .zip(&result.ids)
                .map(|(force, id)| HistoryRow {
                    time_s: s.time,
                    load_n: s.load,
                    approach_m: s.approach,
                    receding: s.receding,
                    id: *id,
                    force_n: *force,
                })
        })
        .collect();
    set.write_csv("history.csv", &rows)
}

#[cfg(test)]
#[path = "history_tests.rs"]
mod tests;
