//! The viscoelastic rolling BEM: [`roll_bem`](super::roll_bem) with a
//! Prony tread (docs/viscoelastic.md, "The viscoelastic rolling BEM").
//!
//! The tread does not slip on the road, so the memory of every rubber cell
//! in the footprint is fixed to the road ([`TreadMemory`]); the window
//! moves by `Δx/dx` cells a step and the memory is shifted back by as much.
//! A step that is not a whole number of road cells is refused rather than
//! interpolated: interpolating the memory would smear it by up to half a
//! cell every step, an error that accumulates along the footprint. Time is
//! `x/V`, so each step lasts `Δt = Δx/V`; it is one elastic BEM contact of
//! modulus `E_eff` on the effective surface raised by the displacement of
//! the memory pressures `h` (`K_eff h`), warm-started from the previous
//! step's pressure, exactly as [`ViscoBem`](crate::viscoelastic::ViscoBem)
//! does at rest. The result has the elastic run's shape
//! ([`BemRollingResult`]): per-step forces, approach, sensor forces, so its
//! spectra come from [`compare`](super::compare) and the scenario tools as
//! the elastic one's do.

use std::path::Path;

use crate::bem::{BemOptions, Solver};
use crate::rolling::RollingConfig;
use crate::scenario::Scenario;
use crate::shared::{Field, Par};
use crate::viscoelastic::{Prony, TreadMemory, ViscoError};

use super::run_scenario::{texture_field, texture_of};
use super::{
    BemRollingError, BemRollingOptions, BemRollingResult, Stretch, effective_surface, failed_step,
    locate, record_step, shift_pressure, solve_step, window_layout,
};

fn visco(e: ViscoError) -> BemRollingError {
    BemRollingError::InvalidInput(e.to_string())
}

/// Rolls the tread of `config` over `road` as [`roll_bem`](super::roll_bem)
/// does, with the viscoelastic `material` (its Poisson's ratio is the
/// half-space's). The run starts from fresh rubber at its first step.
///
/// # Errors
/// As [`roll_bem`](super::roll_bem); [`BemRollingError::InvalidInput`]
/// also when the step `Δx` is not a whole number of road cells (to 1e-6
/// cell), since the road-fixed memory is shifted cell by cell.
pub fn roll_visco_bem(
    road: &Field,
    material: &Prony,
    config: &RollingConfig,
    options: &BemRollingOptions,
) -> Result<BemRollingResult, BemRollingError> {
    config
        .validate()
        .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
    if road.valid_count() != road.grid().len() {
        return Err(BemRollingError::InvalidInput(format!(
            "the road height map has {} invalid cells: the BEM needs a complete map",
            road.grid().len() - road.valid_count()
        )));
    }
    let g = road.grid();
    let cells_per_step = config.step / g.dx();
    if config.steps() > 1 && (cells_per_step - cells_per_step.round()).abs() > 1e-6 {
        return Err(BemRollingError::InvalidInput(format!(
            "viscoelastic rolling BEM: the step {} m is {cells_per_step} road cells of {} m; \
             it must be a whole number of cells (the tread's road-fixed memory is shifted \
             cell by cell, not interpolated)",
            config.step,
            g.dx()
        )));
    }
    let dt = config.step / config.speed;
    let hx = config.tread.half_extents().0;
    let m = config.tread.effective_margin(config.margin);
    let (window_grid, (nx, j0, ny)) = window_layout(road, config)?;
    let mut memory = TreadMemory::new(material.clone(), nx, ny);
    // Δt is the same every step, so one E_eff and one solver serve the run.
    let effective = memory.history(dt).map_err(visco)?.effective_modulus;
    let elastic = material.elastic(effective).map_err(visco)?;
    let bem_options = BemOptions {
        tolerance: options.tolerance,
        max_iterations: options.max_iterations,
        periodic: false,
        par: options.par,
    };
    let mut solver = Solver::new(&window_grid, &elastic, &bem_options)
        .map_err(|source| BemRollingError::Bem { step: 0, source })?;
    let z_max = road.max();
    let windows = (0..config.steps())
        .map(|k| locate(g, k, config.position(k), hx + m, (nx, j0, ny)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut steps = Vec::with_capacity(windows.len());
    let mut previous: Option<(super::Window, Vec<f64>)> = None;
    let mut last_window = windows.first().copied();
    for (k, &window) in windows.iter().enumerate() {
        if let Some(w) = last_window {
            memory.shift(
                window.i0 as i64 - w.i0 as i64,
                window.j0 as i64 - w.j0 as i64,
            );
        }
        last_window = Some(window);
        let xc = config.position(k);
        let surface = effective_surface(road, config, xc, window)?;
        let history = memory.history(dt).map_err(visco)?;
        let raise = solver
            .displacement(&history.pressure)
            .map_err(|source| BemRollingError::Bem { step: k, source })?;
        let raised: Vec<f64> = surface
            .values()
            .iter()
            .zip(&raise)
            .map(|(h, r)| h + r)
            .collect();
        let raised = Field::new(surface.grid().clone(), raised)
            .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
        let guess = previous
            .as_ref()
            .map(|(w, p)| shift_pressure(p, *w, window));
        let solved = solve_step(
            &mut solver,
            &raised,
            config.control,
            z_max,
            guess.as_deref(),
            k,
        )?;
        let step = match solved {
            Some((solution, approach)) => {
                memory.commit(&history, &solution.pressure).map_err(visco)?;
                let record = record_step(config, k, &solution, approach, window, g);
                previous = Some((window, solution.pressure));
                record
            }
            None => {
                memory.hold(dt).map_err(visco)?;
                previous = None;
                failed_step(config, k)
            }
        };
        steps.push(step);
    }
    Ok(BemRollingResult {
        steps,
        sample_rate: config.sample_rate(),
        window: (nx, ny),
    })
}

/// Rolls the viscoelastic BEM over a scenario's `[rolling]` path on its
/// `[texture]` (the road frame of [`texture_field`]), cut to `stretch`, with
/// the tread `material`, at `speed` (m/s; default the scenario's). The
/// scenario's own elastic `[material]` is not used beyond its Poisson's
/// ratio, which must be the tread's. No multipoint run is made.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the scenario has no `[rolling]`
/// or `[texture]`, the stretch is empty or off the path, or the Poisson's
/// ratios differ; the errors of [`roll_visco_bem`].
pub fn roll_visco_bem_scenario(
    scenario: &Scenario,
    base_dir: &Path,
    stretch: Stretch,
    material: &Prony,
    speed: Option<f64>,
    par: Par,
    options: &BemRollingOptions,
) -> Result<BemRollingResult, BemRollingError> {
    let texture = texture_of(scenario, "the viscoelastic BEM rolling reference")?;
    let elastic = scenario.material()?;
    if (elastic.poisson_ratio() - material.poisson_ratio()).abs() > 1e-12 {
        return Err(BemRollingError::InvalidInput(format!(
            "the tread's Poisson's ratio {} differs from the scenario's [material] {}",
            material.poisson_ratio(),
            elastic.poisson_ratio()
        )));
    }
    let Some(spec) = scenario.rolling.as_ref() else {
        return Err(BemRollingError::InvalidInput(
            "the scenario has no [rolling] section".into(),
        ));
    };
    let mut config = spec.config()?;
    let start = stretch.start.unwrap_or(config.start);
    if !(start >= config.start && start <= config.end) {
        return Err(BemRollingError::InvalidInput(format!(
            "stretch start {start} m: must lie on the path, from {} m to {} m",
            config.start, config.end
        )));
    }
    if stretch.steps == Some(0) {
        return Err(BemRollingError::InvalidInput(
            "steps must be >= 1, got 0".into(),
        ));
    }
    config.end = stretch.steps.map_or(config.end, |n| {
        (start + (n - 1) as f64 * config.step).min(config.end)
    });
    config.start = start;
    if let Some(speed) = speed {
        config.speed = speed;
    }
    let map = texture.height_map(base_dir)?;
    let road = texture_field(&map)?;
    roll_visco_bem(
        &road,
        material,
        &config,
        &BemRollingOptions {
            par,
            ..options.clone()
        },
    )
}
