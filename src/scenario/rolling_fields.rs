//! The whole `[model] fidelity = "calibrated_fields"` run of a `[rolling]`
//! scenario with the calibrated road it rolled, for `crate::bem_rolling`'s
//! recounts of its sensors.

use tyreroad_rolling as rolling;

use super::rolling::{Rolled, RollingRun, What, calibrated_road, roll_road_with};
use super::{RunOptions, Scenario, ScenarioError};
use crate::fidelity::CalibratedLaw;
use crate::fidelity::rolling_fields::{FieldRolling, FieldRollingStats};

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
    let material = scenario.material()?;
    let (road, summary) = calibrated_road(scenario, spec, options, texture, true)?;
    let coupling = FieldRolling::with_defaults(&material)?;
    match roll_road_with(
        scenario,
        (&road, Some(&coupling)),
        summary,
        material,
        spec,
        options,
        What::Whole,
    )? {
        Rolled::Run(run) => Ok((*run, road, coupling.stats())),
        _ => Err(ScenarioError::Invalid("a whole run gave a part".into())),
    }
}
