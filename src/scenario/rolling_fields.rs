//! The whole `[model] fidelity = "calibrated_fields"` run of a `[rolling]`
//! scenario with the calibrated road it rolled, for `crate::bem_rolling`'s
//! recounts of its sensors.

use tyreroad_rolling as rolling;

use super::rolling::{Rolled, RollingRun, What};
use super::rolling_calibrated::roll_with_fields;
use super::{RunOptions, Scenario, ScenarioError};
use crate::fidelity::CalibratedLaw;
use crate::fidelity::rolling_fields::FieldRollingStats;

/// A whole `[model] fidelity = "calibrated_fields"` run of the scenario's
/// `[rolling]` on its `[texture]`, as [`Scenario::run`] makes it, with the
/// calibrated road it rolled and the coupling's rounds and pairs (for
/// `crate::bem_rolling`, which recounts the run's sensors on that road).
pub(crate) fn run_calibrated_fields(
    scenario: &Scenario,
    options: &RunOptions<'_>,
) -> Result<(RollingRun, rolling::Road<CalibratedLaw>, FieldRollingStats), ScenarioError> {
    let spec = scenario
        .rolling
        .as_ref()
        .ok_or_else(|| ScenarioError::Invalid("the scenario has no [rolling] section".into()))?;
    let texture = scenario
        .texture
        .as_ref()
        .ok_or_else(|| ScenarioError::Invalid("the scenario has no [texture] section".into()))?;
    match roll_with_fields(scenario, spec, options, texture, What::Whole)? {
        (Rolled::Run(run), road, stats) => Ok((*run, road, stats)),
        _ => Err(ScenarioError::Invalid("a whole run gave a part".into())),
    }
}
