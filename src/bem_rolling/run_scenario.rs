//! A rolling scenario on a texture run twice over the same stretch: by the
//! multipoint model (the scenario's own run) and by the BEM reference.

use std::path::Path;
use std::time::{Duration, Instant};

use crate::fidelity::rolling_fields::{
    FieldRolling, FieldRollingStats, SensorAccounting, sensor_forces,
};
use crate::fidelity::{Fidelity, FidelityError};
use crate::rolling::{self, RollingConfig, RollingResult};
use crate::scenario::units::Length;
use crate::scenario::{
    RollingRun, RunOptions, Scenario, ScenarioResult, TextureSpec, run_calibrated_fields,
};
use crate::shared::spectrum::MIN_SPECTRUM_SAMPLES;
use crate::shared::{Field, Par};
use crate::texture::HeightMap;
use crate::texture_road::texture_road;

use super::{
    BemReference, BemRollingError, BemRollingOptions, BemRollingResult, RollingComparison, compare,
    roll_bem,
};

/// Both runs of one stretch and their comparison.
#[derive(Debug)]
pub struct BemRollingRun {
    /// The multipoint run (the scenario's, cut to the stretch).
    pub multipoint: RollingRun,
    /// The BEM reference on the same path.
    pub bem: BemRollingResult,
    /// Step-by-step and band-by-band comparison.
    pub comparison: RollingComparison,
    /// Wall time of the multipoint run (segmentation and laws included).
    pub multipoint_time: Duration,
    /// Wall time of the BEM run.
    pub bem_time: Duration,
    /// Texture cells `(nx, ny)` and spacing (m) of the road.
    pub road_grid: (usize, usize, f64),
    /// The same multipoint run with the tread gaps measured at the summits
    /// (the model before the contact-point gaps,
    /// [`crate::rolling::Tread::contact_gap`]) and its comparison with the
    /// same BEM run: what the contact-point gaps change. `None` on
    /// calibrated laws (`[model] fidelity = "calibrated"`: a second run
    /// would calibrate the road again).
    pub summit_gaps: Option<(RollingResult, RollingComparison)>,
    /// The same multipoint run with each contact's force spread on the
    /// sensors as its own cap's BEM pressure ([`crate::fidelity::cap_sensors`]):
    /// its sensor forces (one row per sensor) and its comparison with the
    /// BEM (its `sensors`; the other signals are the run's).
    pub caps: (Vec<Vec<f64>>, RollingComparison),
    /// On `[model] fidelity = "calibrated_fields"`: the run's sensors
    /// recounted on its calibrated road each way, and the coupling's
    /// rounds; `None` on the other rungs.
    pub field_rung: Option<FieldRungAccountings>,
    /// What the BEM run was solved for: written beside its saved signals,
    /// and checked when they are read back.
    pub bem_reference: BemReference,
}

/// A `calibrated_fields` run's sensors counted each way
/// ([`crate::fidelity::rolling_fields::sensor_forces`]), each with its
/// comparison with the BEM (its `sensors`; the other signals are the
/// run's), and the fixed point's rounds.
#[derive(Debug)]
pub struct FieldRungAccountings {
    /// Each contact's force spread as its calibrated field.
    pub fields: (Vec<Vec<f64>>, RollingComparison),
    /// Each contact's force spread as its law's disc.
    pub discs: (Vec<Vec<f64>>, RollingComparison),
    /// Rounds and pairs of the fixed point over the run.
    pub stats: FieldRollingStats,
    /// How the run's own sensors counted.
    pub in_run: SensorAccounting,
}

/// The texture's height map in the road frame of a scenario's rolling run:
/// cell `(i, j)` at `(i dx, j dy − y_mid)`, as the scenario centres the
/// texture's y on the path (`y_mid` the map's middle row).
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for a map with unmeasured points (the
/// BEM needs a complete surface).
pub fn texture_field(map: &HeightMap) -> Result<Field, BemRollingError> {
    crate::fidelity::cap_sensors::road_frame_field(map)
        .map_err(|e| BemRollingError::InvalidInput(format!("the BEM reference: {e}")))
}

/// The stretch of a scenario's path to compare: from `start` (m; default
/// the path's start) for `steps` steps (default: to the path's end; never
/// beyond it).
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct Stretch {
    /// First footprint centre (m).
    pub start: Option<f64>,
    /// Steps.
    pub steps: Option<usize>,
    /// Welch segment (samples) of the spectra of both runs, instead of the
    /// scenario's `[rolling] segment` (or the core's default, half the
    /// signal).
    pub segment: Option<usize>,
}

/// Runs `scenario` (a `[rolling]` run on a `[texture]`) over `stretch` by
/// the multipoint model and by the BEM reference, and compares them. `base_dir` resolves a texture file; `par`
/// is the parallelism of both runs. No checkpoint is read or written.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the scenario has no `[rolling]`
/// or no `[texture]`, or the stretch is empty or off the path; [`BemRollingError::Scenario`] when
/// the multipoint run fails; the errors of [`roll_bem`] and [`compare`].
pub fn run_scenario_comparison(
    scenario: Scenario,
    base_dir: &Path,
    stretch: Stretch,
    par: Par,
    options: &BemRollingOptions,
) -> Result<BemRollingRun, BemRollingError> {
    run_scenario_comparison_against(scenario, base_dir, stretch, par, options, None)
}

/// [`run_scenario_comparison`] against `saved`, a BEM run of the same
/// stretch saved earlier (the BEM reference does not depend on the model's
/// laws: one BEM run serves every fidelity), or against a new BEM run when
/// `None`; `bem_time` is then zero.
///
/// # Errors
/// As [`run_scenario_comparison`]; [`BemRollingError::InvalidInput`] when
/// `saved` has other steps (count or footprint positions, to 1 nm) or
/// sensors than the stretch.
pub fn run_scenario_comparison_against(
    mut scenario: Scenario,
    base_dir: &Path,
    stretch: Stretch,
    par: Par,
    options: &BemRollingOptions,
    saved: Option<BemRollingResult>,
) -> Result<BemRollingRun, BemRollingError> {
    let texture = texture_of(&scenario, "the BEM rolling reference")?;
    let map = texture.height_map(base_dir)?;
    let (segment, reference_force) = cut_to_stretch(&mut scenario, stretch)?;
    check_spectral_stretch(&scenario, segment)?;
    let run_options = RunOptions {
        par: Some(par),
        ..RunOptions::new(base_dir)
    };
    let clock = Instant::now();
    let (multipoint, field_road) = if scenario.fidelity()? == Fidelity::CalibratedFields {
        let (run, road, stats) = run_calibrated_fields(&scenario, &run_options)?;
        (Box::new(run), Some((road, stats)))
    } else {
        let ScenarioResult::Rolling(multipoint) = scenario.run(&run_options)? else {
            return Err(BemRollingError::InvalidInput(
                "the scenario did not run as a rolling run".into(),
            ));
        };
        (multipoint, None)
    };
    let multipoint_time = clock.elapsed();
    let config: &RollingConfig = &multipoint.config;
    let road = texture_field(&map)?;
    let clock = Instant::now();
    let bem = match saved {
        Some(saved) => same_stretch(saved, config, &multipoint.result)?,
        None => roll_bem(
            &road,
            scenario.material()?,
            config,
            &BemRollingOptions {
                par,
                ..options.clone()
            },
        )?,
    };
    let bem_time = clock.elapsed();
    let bem_reference = BemReference::of(&map, &scenario.material()?, config, options);
    let comparison = compare(
        &multipoint.result,
        &multipoint.road_positions,
        &config.sensors,
        &bem,
        reference_force,
        segment,
    )?;
    let caps = cap_run(
        &scenario,
        &map,
        &road,
        &multipoint,
        options,
        reference_force,
        segment,
        &bem,
    )?;
    let field_rung = match field_road {
        Some((road, stats)) => {
            let recount = |accounting| -> Result<_, BemRollingError> {
                let forces = sensor_forces(
                    &multipoint.result,
                    &road,
                    scenario.material()?,
                    config,
                    accounting,
                )
                .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
                let comparison = recounted(&multipoint, &forces, &bem, reference_force, segment)?;
                Ok((forces, comparison))
            };
            Some(FieldRungAccountings {
                fields: recount(SensorAccounting::Fields)?,
                discs: recount(SensorAccounting::Discs)?,
                stats,
                in_run: FieldRolling::with_defaults(&scenario.material()?)
                    .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?
                    .sensors(),
            })
        }
        None => None,
    };
    let summit_gaps = if scenario.fidelity()? == Fidelity::Wilke {
        let summit_result = summit_gap_run(&scenario, &map, config, par)?;
        let summit_comparison = compare(
            &summit_result,
            &multipoint.road_positions,
            &config.sensors,
            &bem,
            reference_force,
            segment,
        )?;
        Some((summit_result, summit_comparison))
    } else {
        None
    };
    Ok(BemRollingRun {
        multipoint: *multipoint,
        bem,
        comparison,
        multipoint_time,
        bem_time,
        road_grid: (map.nx(), map.ny(), map.dx()),
        summit_gaps,
        caps,
        field_rung,
        bem_reference,
    })
}

/// `scenario`'s `[texture]`, or the error that `what` needs one.
pub(super) fn texture_of<'s>(
    scenario: &'s Scenario,
    what: &str,
) -> Result<&'s TextureSpec, BemRollingError> {
    scenario.texture.as_ref().ok_or_else(|| {
        BemRollingError::InvalidInput(format!("{what} needs a scenario with a [texture]"))
    })
}

/// [`BemReference::of`] a scenario's BEM rolling run, read before any
/// solve (the texture's height map, the material, the rolling
/// configuration): what `cargo xtask rolling-bem --bem-from` checks saved
/// signals against before it runs the model.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the scenario has no `[texture]`;
/// [`BemRollingError::Scenario`] when its map, material or `[rolling]`
/// cannot be read.
pub fn scenario_bem_reference(
    scenario: &Scenario,
    base_dir: &Path,
    options: &BemRollingOptions,
) -> Result<BemReference, BemRollingError> {
    let texture = texture_of(scenario, "the BEM rolling reference")?;
    let map = texture.height_map(base_dir)?;
    Ok(BemReference::of(
        &map,
        &scenario.material()?,
        &scenario.rolling_config()?,
        options,
    ))
}

/// The multipoint run's sensors counted with each contact's force spread
/// as its cap's pressure, and that run's comparison with the BEM.
#[allow(clippy::too_many_arguments)]
fn cap_run(
    scenario: &Scenario,
    map: &HeightMap,
    road: &Field,
    multipoint: &RollingRun,
    options: &BemRollingOptions,
    reference_force: f64,
    segment: Option<usize>,
    bem: &BemRollingResult,
) -> Result<(Vec<Vec<f64>>, RollingComparison), BemRollingError> {
    let texture = texture_of(scenario, "the BEM rolling reference")?;
    let material = scenario.material()?;
    let troad = texture_road(map, material, &texture.road_options())
        .map_err(|e| BemRollingError::InvalidInput(format!("texture road: {e}")))?;
    let config = &multipoint.config;
    let bem_options = options.cap_solve();
    let forces = crate::fidelity::cap_sensors::cap_sensor_forces(
        &multipoint.result,
        &multipoint.road_positions,
        config,
        (road, &troad, &material),
        (&bem_options, options.par),
    )
    .map_err(|e| match e {
        FidelityError::CapSensors { step, source } => BemRollingError::Bem { step, source },
        e => BemRollingError::InvalidInput(format!("cap sensor forces: {e}")),
    })?;
    let comparison = recounted(multipoint, &forces, bem, reference_force, segment)?;
    Ok((forces, comparison))
}

/// The comparison with the BEM of `multipoint` with its sensor forces
/// replaced by `forces` (one row per sensor, one value per step).
fn recounted(
    multipoint: &RollingRun,
    forces: &[Vec<f64>],
    bem: &BemRollingResult,
    reference_force: f64,
    segment: Option<usize>,
) -> Result<RollingComparison, BemRollingError> {
    let mut result = multipoint.result.clone();
    for (k, step) in result.steps.iter_mut().enumerate() {
        for (s, f) in step.sensor_forces.iter_mut().enumerate() {
            *f = forces[s][k];
        }
    }
    compare(
        &result,
        &multipoint.road_positions,
        &multipoint.config.sensors,
        bem,
        reference_force,
        segment,
    )
}

/// The scenario's multipoint run rebuilt with the tread gaps at the
/// summits: the same texture road (segmentation, laws, frame) without its
/// summit radii, rolled with the same configuration.
fn summit_gap_run(
    scenario: &Scenario,
    map: &HeightMap,
    config: &RollingConfig,
    par: Par,
) -> Result<RollingResult, BemRollingError> {
    let texture = texture_of(scenario, "the BEM rolling reference")?;
    let material = scenario.material()?;
    let road = texture_road(map, material, &texture.road_options())
        .map_err(|e| BemRollingError::InvalidInput(format!("texture road: {e}")))?;
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    // The scenario run's ids (the rolling order): the comparison reads
    // both runs' contacts against its road positions.
    let (set, _) = road
        .rolling_set()
        .map_err(|e| BemRollingError::InvalidInput(format!("texture road: {e}")))?;
    let set = set
        .translated([0.0, -y_mid])
        .map_err(|e| BemRollingError::InvalidInput(format!("texture road: {e}")))?;
    // The scenario run's chunking: each chunk cold-starts its first step.
    let options = rolling::RunOptions {
        chunks: scenario.rolling.as_ref().and_then(|r| r.chunks),
        par,
        ..rolling::RunOptions::default()
    };
    // The approach from the map's highest point, as the scenario's run.
    rolling::Road::new(set)
        .with_top(road.top)
        .and_then(|road| rolling::roll(&road, material, config, &options))
        .map_err(|e| BemRollingError::InvalidInput(format!("summit-gap run: {e}")))
}

/// Cuts the scenario's `[rolling]` path to `stretch` (no checkpoint; the
/// stretch's Welch segment, if any, replaces the scenario's) and returns the
/// spectra's segment and reference force (N; default 1).
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the scenario has no `[rolling]`,
/// or the stretch is empty or off the path.
pub(super) fn cut_to_stretch(
    scenario: &mut Scenario,
    stretch: Stretch,
) -> Result<(Option<usize>, f64), BemRollingError> {
    let Some(spec) = scenario.rolling.as_mut() else {
        return Err(BemRollingError::InvalidInput(
            "the scenario has no [rolling] section".into(),
        ));
    };
    let (path_start, path_end, step) = (spec.start.value(), spec.end.value(), spec.step.value());
    let start = stretch.start.unwrap_or(path_start);
    if !(start >= path_start && start <= path_end) {
        return Err(BemRollingError::InvalidInput(format!(
            "stretch start {start} m: must lie on the path, from {path_start} m to {path_end} m"
        )));
    }
    if stretch.steps == Some(0) {
        return Err(BemRollingError::InvalidInput(
            "steps must be >= 1, got 0".into(),
        ));
    }
    let end = stretch
        .steps
        .map_or(path_end, |n| (start + (n - 1) as f64 * step).min(path_end));
    spec.start = Length::si(start);
    spec.end = Length::si(end);
    spec.checkpoint = false;
    // The comparison counts the model's sensors every way itself (its
    // "(caps)" rows among them): the run keeps its own accounting.
    spec.sensor_accounting = None;
    if stretch.segment.is_some() {
        spec.segment = stretch.segment;
    }
    Ok((
        spec.segment,
        spec.reference_force.map_or(1.0, |f| f.value()),
    ))
}

/// Refuses a cut scenario whose stretch or Welch segment is too short for
/// the comparison's spectra, before anything is calibrated or solved: the
/// spectra come last, after minutes of BEM steps, and a run that can only
/// fail there must fail at once.
pub(super) fn check_spectral_stretch(
    scenario: &Scenario,
    segment: Option<usize>,
) -> Result<(), BemRollingError> {
    let config = scenario.rolling_config()?;
    let (steps, min) = (config.steps(), MIN_SPECTRUM_SAMPLES);
    if steps < min {
        return Err(BemRollingError::InvalidInput(format!(
            "the stretch has {steps} step(s): the comparison's spectra need at least {min}"
        )));
    }
    match segment {
        Some(s) if s < min => Err(BemRollingError::InvalidInput(format!(
            "Welch segment of {s} sample(s): the comparison's spectra need at least {min}"
        ))),
        _ => Ok(()),
    }
}

/// `saved` if it holds the steps of `run` (count and footprint positions,
/// to 1 nm) and a force for each of `config`'s sensors.
fn same_stretch(
    saved: BemRollingResult,
    config: &RollingConfig,
    run: &RollingResult,
) -> Result<BemRollingResult, BemRollingError> {
    let (n, m) = (saved.steps.len(), run.steps.len());
    if n != m {
        return Err(BemRollingError::InvalidInput(format!(
            "the saved BEM run has {n} steps, the stretch {m}"
        )));
    }
    for (b, s) in saved.steps.iter().zip(&run.steps) {
        if (b.position - s.position).abs() > 1e-9 || b.sensor_forces.len() != config.sensors.len() {
            return Err(BemRollingError::InvalidInput(format!(
                "saved BEM step {} (x = {} m, {} sensors): the stretch's is at x = {} m with {} sensors",
                b.index,
                b.position,
                b.sensor_forces.len(),
                s.position,
                config.sensors.len()
            )));
        }
    }
    Ok(saved)
}
