//! `[rolling] sensor_accounting = "caps"` (docs/rolling.md, "Sensors
//! counted on the caps"): a whole run's sensor forces recounted with each
//! contact's force on its own cap ([`crate::fidelity::cap_sensors`]) and
//! its spectra computed again from them. The forces, approach and areas
//! stay the run's.
//!
//! The texture is read and checked before the run ([`CapRecount::prepare`]:
//! a map with unmeasured points is refused before any step is solved), and
//! the recount is done once, on the finished run (after any calibrated
//! round that repeated itself).

use tyreroad_multipoint::Par;

use super::rolling::{RollingRun, spectra};
use super::{RoadSummary, RollingSpec, RunOptions, Scenario, ScenarioError};
use crate::fidelity::cap_sensors::{cap_sensor_forces_by_step, road_frame_field};
use crate::shared::{Field, Material};
use crate::texture_road::TextureRoad;

/// Relative tolerance of each cap's solve (the BEM rolling reference's
/// default): each cap's force is imposed, only where it lies is solved
/// for.
const CAP_TOLERANCE: f64 = 1e-7;

/// What a recount on the caps needs: the texture in the road frame and its
/// segmentation into the road.
pub(super) struct CapRecount {
    field: Field,
    road: TextureRoad,
    material: Material,
    par: Par,
}

impl CapRecount {
    /// `Some` when the scenario asks for sensors on the caps and has sensors:
    /// its texture read, segmented and checked.
    ///
    /// # Errors
    /// No `[texture]`, a texture that cannot be read or segmented, or a map
    /// with unmeasured points (a cap solve needs every cell).
    pub(super) fn prepare(
        scenario: &Scenario,
        spec: &RollingSpec,
        options: &RunOptions<'_>,
    ) -> Result<Option<Self>, ScenarioError> {
        if !spec.sensors_on_caps() || spec.sensors.is_empty() {
            return Ok(None);
        }
        let refused = |why: String| {
            ScenarioError::Invalid(format!(
                "[rolling] sensor_accounting = \"caps\": {why}; use \"run\""
            ))
        };
        let texture = scenario
            .texture
            .as_ref()
            .ok_or_else(|| refused("needs a [texture]".into()))?;
        let material = scenario.material()?;
        let map = texture.height_map(&options.base_dir)?;
        let field = road_frame_field(&map).map_err(|e| refused(e.to_string()))?;
        let par = options.rolling_par(spec);
        let road = super::texture::scenario_road(&map, material, texture, par)?;
        Ok(Some(Self {
            field,
            road,
            material,
            par,
        }))
    }

    /// `run`'s sensor forces counted on the caps, and its spectra again.
    ///
    /// A step where a cap's solve fails keeps the run's own sensor forces,
    /// said among the texture summary's `warnings`.
    ///
    /// # Errors
    /// A record whose sensors are not the configuration's, a contact that
    /// is no asperity of the texture, or a spectrum that cannot be
    /// computed.
    pub(super) fn recount(
        self,
        spec: &RollingSpec,
        run: &mut RollingRun,
    ) -> Result<(), ScenarioError> {
        let n = run.config.sensors.len();
        if let Some(step) = run.result.steps.iter().find(|s| s.sensor_forces.len() != n) {
            return Err(ScenarioError::Invalid(format!(
                "step {}: {} sensor forces, the configuration has {n} sensors",
                step.index,
                step.sensor_forces.len()
            )));
        }
        let bem = crate::bem::BemOptions {
            tolerance: CAP_TOLERANCE,
            ..crate::bem::BemOptions::default()
        };
        let by_step = cap_sensor_forces_by_step(
            &run.result,
            &run.road_positions,
            &run.config,
            (&self.field, &self.road, &self.material),
            (&bem, self.par),
        )?;
        // A step whose cap solve failed keeps the run's own accounting:
        // that step's failure, said among the texture's warnings.
        let mut kept: Vec<String> = Vec::new();
        for (step, counted) in run.result.steps.iter_mut().zip(by_step) {
            match counted {
                Ok(forces) => step.sensor_forces = forces,
                Err(e) => kept.push(e.to_string()),
            }
        }
        if let (Some(first), RoadSummary::Texture(t)) = (kept.first(), &mut run.road) {
            t.warnings.push(format!(
                "sensor_accounting = \"caps\": {} step(s) keep the run's own sensor \
                 accounting, their cap solves failed (first: {first})",
                kept.len()
            ));
        }
        run.spectra = spectra(&run.config, spec, &run.result)?;
        Ok(())
    }
}
