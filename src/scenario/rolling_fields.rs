//! The calibrated texture road of a `[rolling]` run (`[model] fidelity =
//! "calibrated"` or `"calibrated_fields"`), and the whole
//! `calibrated_fields` run with the road it rolled, for
//! `crate::bem_rolling`'s recounts of its sensors.

use tyreroad_multipoint::Par;
use tyreroad_rolling as rolling;

use super::rolling::{RoadSummary, Rolled, RollingRun, What, roll_road_with};
use super::texture::calibrated_texture_road_set_with;
use super::{RollingSpec, RunOptions, Scenario, ScenarioError, TextureSpec};
use crate::fidelity::CalibratedLaw;
use crate::fidelity::rolling_fields::{FieldRolling, FieldRollingStats};

/// The scenario's texture road with each selectable cap's calibrated law,
/// with its fields when `fields`, and its summary.
pub(super) fn calibrated_road(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    texture: &TextureSpec,
    fields: bool,
) -> Result<(rolling::Road<CalibratedLaw>, RoadSummary), ScenarioError> {
    let material = scenario.material()?;
    let config = scenario.rolling_config()?;
    let par = options
        .par
        .unwrap_or_else(|| Par::rayon(spec.threads.unwrap_or(0)));
    // Tables are kept beside the checkpoints: a resumed or repeated run on
    // the same road does not calibrate it again.
    let cache = options
        .checkpoint_dir
        .as_deref()
        .filter(|_| spec.checkpoint)
        .map(|dir| dir.join("calibration"));
    let (set, summary, radii) = calibrated_texture_road_set_with(
        texture,
        &options.base_dir,
        material,
        &config,
        par,
        cache.as_deref(),
        fields,
    )?;
    let road = rolling::Road::new(set).with_summit_radii(radii)?;
    Ok((road, RoadSummary::Texture(summary)))
}

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
