//! The viscoelastic multipoint rolling run against the viscoelastic rolling
//! BEM over the same stretch (docs/viscoelastic.md, "Rolling against the
//! viscoelastic BEM").
//!
//! Both runs take the tread of the scenario's `[material.viscoelastic]` at
//! its temperature, start from fresh rubber at the stretch's first step and
//! step in time by `Δt = Δx / V`: the multipoint one keeps a hereditary
//! memory per asperity (`Scenario::roll_viscoelastic`), the BEM one per
//! rubber cell ([`roll_visco_bem`]). Their difference is compared as the
//! elastic runs' is ([`compare`]), so the viscoelastic error can be set
//! beside the elastic model's own on the same stretch.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::scenario::{RollingRun, RunOptions, Scenario, ViscoCase};
use crate::shared::Par;
use crate::viscoelastic::Prony;

use super::run_scenario::{check_spectral_stretch, cut_to_stretch, texture_field, texture_of};
use super::{
    BemRollingError, BemRollingOptions, BemRollingResult, RollingComparison, Stretch, compare,
    roll_visco_bem,
};

/// Both viscoelastic runs of one stretch and their comparison.
#[derive(Debug)]
pub struct ViscoBemRollingRun {
    /// The tread both runs rolled (the scenario's series at its
    /// temperature).
    pub tread: Prony,
    /// The multipoint run (`roll_viscoelastic`, cut to the stretch).
    pub multipoint: RollingRun,
    /// The viscoelastic BEM on the same path, at the same speed.
    pub bem: BemRollingResult,
    /// Step-by-step and band-by-band comparison (every step: both runs
    /// start fresh at the same place, so the transient is compared too).
    pub comparison: RollingComparison,
    /// Wall time of the multipoint run (segmentation and laws included).
    pub multipoint_time: Duration,
    /// Wall time of the BEM run.
    pub bem_time: Duration,
    /// Texture cells `(nx, ny)` and spacing (m) of the road.
    pub road_grid: (usize, usize, f64),
}

/// Runs `scenario` (a `[rolling]` run on a `[texture]` with a
/// `[material.viscoelastic]` tread) over `stretch` at `speed` (m/s; default
/// `[rolling] speed`) by the viscoelastic multipoint model and by the
/// viscoelastic rolling BEM, and compares them. `base_dir` resolves the
/// scenario's files; `par` is the BEM's parallelism (the multipoint run is
/// sequential along its path).
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the scenario has no `[rolling]`,
/// `[texture]` or `[material.viscoelastic]`, the stretch is empty or off
/// the path, or the step is not a whole number of texture cells;
/// [`BemRollingError::Scenario`] when the multipoint run fails; the errors
/// of [`roll_visco_bem`] and [`compare`].
pub fn run_visco_scenario_comparison(
    mut scenario: Scenario,
    base_dir: &Path,
    stretch: Stretch,
    speed: Option<f64>,
    par: Par,
    options: &BemRollingOptions,
) -> Result<ViscoBemRollingRun, BemRollingError> {
    let texture = texture_of(&scenario, "the viscoelastic BEM rolling comparison")?;
    let map = texture.height_map(base_dir)?;
    let Some(tread) = scenario.viscoelastic_material(base_dir)? else {
        return Err(BemRollingError::InvalidInput(
            "the viscoelastic BEM rolling comparison needs [material.viscoelastic]".into(),
        ));
    };
    let (segment, reference_force) = cut_to_stretch(&mut scenario, stretch)?;
    check_spectral_stretch(&scenario, segment)?;
    let run_options = RunOptions {
        par: Some(par),
        ..RunOptions::new(base_dir)
    };
    let case = ViscoCase {
        speed,
        temperature: None,
    };
    let clock = Instant::now();
    let multipoint = scenario
        .roll_viscoelastic(&run_options, &[case])?
        .pop()
        .ok_or_else(|| BemRollingError::InvalidInput("no viscoelastic run was made".into()))??;
    let multipoint_time = clock.elapsed();
    let road = texture_field(&map)?;
    let config = &multipoint.config;
    let clock = Instant::now();
    let bem = roll_visco_bem(
        &road,
        &tread,
        config,
        &BemRollingOptions {
            par,
            ..options.clone()
        },
    )?;
    let bem_time = clock.elapsed();
    let comparison = compare(
        &multipoint.result,
        &multipoint.road_positions,
        &config.sensors,
        &bem,
        reference_force,
        segment,
    )?;
    Ok(ViscoBemRollingRun {
        tread,
        multipoint,
        bem,
        comparison,
        multipoint_time,
        bem_time,
        road_grid: (map.nx(), map.ny(), map.dx()),
    })
}
