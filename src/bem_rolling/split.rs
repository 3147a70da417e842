//! Where a sensor's load goes: one footprint position solved by the BEM
//! and by the multipoint model, the BEM's force split by segmentation basin
//! and set against each asperity's model force (docs/validation.md, "Where
//! the shoulder's load goes").
//!
//! At footprint centre `x_c` the BEM's pressure on the window
//! ([`super::roll_bem`]'s surface `h − s`) is summed per basin of the
//! texture's segmentation, over the whole basin and over the sensor's
//! rectangle (cells counted with the fraction of their area inside, as the
//! BEM sensors are). The model's step problem ([`crate::rolling::step_problem`])
//! is solved twice: under the scenario's control (its own run) and under
//! approach control at the BEM's approach (so the two differ in nothing but
//! the model). For each asperity three gaps are compared:
//!
//! - `H_model = z_top − z_i + s*` (the contact-point gap of
//!   [`crate::rolling::Tread::contact_gap`]);
//! - `H_exact = min over the basin's cells of (z_top − h + s)`: where the
//!   cap's own surface first meets the tilted tread;
//!
//! and the asperity's own surface under the tilted tread is solved alone by
//! the BEM at the depth the model gives it, `δ_exact = δ0 − H_exact − u_i`
//! (`u_i = δ0 − H_model − δ_i`, the model's interaction displacement):
//! what a law measured on the tilted cap would give for the same
//! interaction, against the model's `P_i(δ_i)`.

use std::collections::HashMap;
use std::path::Path;

use crate::bem::{BemOptions, Control as BemControl, Solver};
use crate::fidelity::{
    CalibrationOptions, Calibrator, Fidelity,
    rolling::{calibrate_rolling_road_under, calibrated_rolling_road},
    table_depth::TablePlan,
};
use crate::multipoint::Control;
use crate::rolling::{ContactLaw, Road, RollingConfig, RollingControl, settled_step};
use crate::scenario::Scenario;
use crate::shared::{Field, Grid, Material, Par};
use crate::texture::{HeightMap, UNLABELLED};
use crate::texture_road::{rolling_road, texture_road};

use super::run_scenario::{Stretch, cut_to_stretch, texture_field};
use super::{
    BemRollingError, BemRollingOptions, Window, effective_surface, locate, overlap, solve_step,
    window_layout,
};

/// Cells of margin around a basin in its single-asperity solve.
const MARGIN_CELLS: usize = 3;

/// One asperity at one footprint position: the BEM's basin against the
/// model's asperity.
#[derive(Clone, Debug, PartialEq)]
pub struct AsperityShare {
    /// Index in the segmentation (its basin's label).
    pub basin: usize,
    /// The rolling road's id, when the model holds the asperity.
    pub road_id: Option<usize>,
    /// Summit `(x, y)` (m), rolling frame.
    pub summit: [f64; 2],
    /// The summit radius the contact-point gap uses (m).
    pub radius: f64,
    /// BEM force on the whole basin (N).
    pub bem_force: f64,
    /// BEM force on the basin's cells inside the sensor (N).
    pub bem_sensor: f64,
    /// Model force under the scenario's control (N).
    pub model_force: f64,
    /// Its share on the sensor (N).
    pub model_sensor: f64,
    /// Model force under approach control at the BEM's approach (N).
    pub model_force_at_bem_approach: f64,
    /// Its share on the sensor (N).
    pub model_sensor_at_bem_approach: f64,
    /// Model interpenetration `δ_i` under the scenario's control (m).
    pub model_depth: f64,
    /// `H_model` (m, from the road's reference plane, the map's highest
    /// point).
    pub gap_model: f64,
    /// `H_exact` (m, same reference): the basin's cells under the tread.
    pub gap_exact: f64,
    /// The basin alone under the tilted tread, solved by the BEM at
    /// `δ_exact = δ0 − H_exact − u_i` (N; 0 when `δ_exact ≤ 0`).
    pub tilted_force: f64,
    /// The model's force placed by the BEM on the basin alone under the
    /// tilted tread (load control at the model's force): its share on the
    /// sensor (N), the sensor force the model's own force would give if
    /// its pressure were the cap's.
    pub local_sensor: f64,
}

/// One footprint position.
#[derive(Clone, Debug, PartialEq)]
pub struct StepSplit {
    /// Footprint centre `x_c` (m).
    pub position: f64,
    /// BEM approach below the road's reference plane (m).
    pub bem_approach: f64,
    /// Model approach under the scenario's control (m).
    pub model_approach: f64,
    /// BEM sensor force (N).
    pub bem_sensor: f64,
    /// BEM sensor force on cells of no basin (N).
    pub bem_sensor_unlabelled: f64,
    /// Model sensor force under the scenario's control (N).
    pub model_sensor: f64,
    /// Model sensor force at the BEM's approach (N).
    pub model_sensor_at_bem_approach: f64,
    /// Model total force at the BEM's approach (N).
    pub model_total_at_bem_approach: f64,
    /// Every asperity with a force on the sensor in either run, largest BEM
    /// sensor force first.
    pub asperities: Vec<AsperityShare>,
}

/// Splits sensor `sensor` of `scenario` (a `[rolling]` run on a
/// `[texture]`) at each footprint centre of `positions` (m, on the path),
/// on the scenario's rung (`wilke` or `calibrated`; calibrated over the
/// stretch from the first to the last position).
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for a scenario without `[rolling]` or
/// `[texture]`, an empty position list or an unknown sensor; the errors of
/// the calibration, the model's and the BEM's solves.
pub fn asperity_split(
    mut scenario: Scenario,
    base_dir: &Path,
    positions: &[f64],
    sensor: usize,
    par: Par,
    options: &BemRollingOptions,
) -> Result<Vec<StepSplit>, BemRollingError> {
    let invalid = |m: String| BemRollingError::InvalidInput(m);
    let (lo, hi) = positions
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| {
            (a.min(x), b.max(x))
        });
    if !(lo.is_finite() && hi.is_finite()) {
        return Err(invalid("asperity split: no footprint position".into()));
    }
    let step = scenario
        .rolling
        .as_ref()
        .map(|r| r.step.value())
        .unwrap_or(1.0);
    let steps = ((hi - lo) / step).round() as usize + 1;
    // The calibrated laws are those of a run of the whole path (its
    // approach bound and bulk sag), not of the stretch cut below.
    let path_config = scenario.rolling_config()?;
    cut_to_stretch(
        &mut scenario,
        Stretch {
            start: Some(lo),
            steps: Some(steps),
            segment: None,
        },
    )?;
    let texture = scenario
        .texture
        .as_ref()
        .ok_or_else(|| invalid("asperity split: the scenario has no [texture]".into()))?;
    let map = texture.height_map(base_dir)?;
    let material = scenario.material()?;
    let config = scenario.rolling_config()?;
    if sensor >= config.sensors.len() {
        return Err(invalid(format!(
            "asperity split: sensor {sensor}, the scenario has {}",
            config.sensors.len()
        )));
    }
    let troad = texture_road(&map, material, &texture.road_options())
        .map_err(|e| invalid(format!("texture road: {e}")))?;
    let radii = troad.summit_radii();
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let set = troad
        .set
        .clone()
        .translated([0.0, -y_mid])
        .map_err(|e| invalid(format!("texture road: {e}")))?;
    let wilke = rolling_road(set, radii.clone(), troad.top).map_err(|e| invalid(e.to_string()))?;
    let field = texture_field(&map)?;
    let ctx = Context {
        map: &map,
        field: &field,
        labels: troad.segmentation.labels(),
        config: &config,
        material,
        sensor,
        par,
        options,
    };
    // A rung the split cannot solve is refused by name: it used to fall
    // back to the Wilke laws without a word.
    let fidelity = scenario.fidelity()?;
    if !matches!(fidelity, Fidelity::Wilke | Fidelity::Calibrated) {
        return Err(invalid(format!(
            "asperity split: [model] fidelity {fidelity:?} is not supported (wilke or calibrated; \
             the coupled rungs' steps are not a single solve)"
        )));
    }
    if fidelity == Fidelity::Calibrated {
        let calibrator = Calibrator::new(material, CalibrationOptions::default());
        let under = scenario.model.calibrate_under()?;
        // The split re-solves single steps; laws placed along the path
        // have no single step problem to hand out.
        if under == crate::fidelity::under_tread::CalibrateUnder::TreadSlope {
            return Err(invalid(
                "asperity split: [model] calibrate_under \"tread_slope\" is not supported \
                 (\"flat\" or \"tread\")"
                    .into(),
            ));
        }
        let cal = calibrate_rolling_road_under(
            &troad,
            &wilke,
            &map,
            &path_config,
            &calibrator,
            par,
            // The tables of the run's first round (a run that pressed caps
            // past them and repeated itself has deeper ones for those caps).
            &TablePlan::new(under),
        )
        .map_err(|e| invalid(format!("calibration: {e}")))?;
        let radii = cal.kept.iter().map(|&i| radii[i]).collect();
        let road = calibrated_rolling_road(cal.set, radii, troad.top)
            .map_err(|e| invalid(e.to_string()))?;
        let basins: Vec<usize> = cal.kept.iter().map(|&i| troad.asperity_index[i]).collect();
        split_road(&road, &basins, &ctx, positions)
    } else {
        split_road(&wilke, &troad.asperity_index, &ctx, positions)
    }
}

struct Context<'a> {
    map: &'a HeightMap,
    field: &'a Field,
    labels: &'a [u32],
    config: &'a RollingConfig,
    material: Material,
    sensor: usize,
    par: Par,
    options: &'a BemRollingOptions,
}

/// Per basin label: BEM force, BEM force on the sensor, highest `h − s`.
#[derive(Clone, Copy)]
struct Basin {
    force: f64,
    sensor: f64,
    top: f64,
}

fn split_road<L: ContactLaw + Sync>(
    road: &Road<L>,
    basins: &[usize],
    ctx: &Context<'_>,
    positions: &[f64],
) -> Result<Vec<StepSplit>, BemRollingError> {
    let config = ctx.config;
    let (window_grid, (nx, j0, ny)) = window_layout(ctx.field, config)?;
    let bem_options = BemOptions {
        tolerance: ctx.options.tolerance,
        max_iterations: ctx.options.max_iterations,
        periodic: false,
        par: ctx.par,
    };
    let mut solver = Solver::new(&window_grid, &ctx.material, &bem_options)
        .map_err(|source| BemRollingError::Bem { step: 0, source })?;
    let g = ctx.field.grid();
    let (dx, dy) = (g.dx(), g.dy());
    let (hx, _) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    let z_max = ctx.field.max();
    let top = road.top();
    let sensor = &config.sensors[ctx.sensor];
    let road_of: HashMap<usize, usize> =
        basins.iter().enumerate().map(|(id, &b)| (b, id)).collect();
    let mut out = Vec::with_capacity(positions.len());
    for (k, &xc) in positions.iter().enumerate() {
        let w = locate(g, k, xc, hx + m, (nx, j0, ny))?;
        let surface = effective_surface(ctx.field, config, xc, w)?;
        let Some((bem, bem_approach)) =
            solve_step(&mut solver, &surface, config.control, z_max, None, k)?
        else {
            return Err(BemRollingError::InvalidInput(format!(
                "asperity split: the BEM did not converge at x = {xc} m"
            )));
        };
        let mut per: HashMap<u32, Basin> = HashMap::new();
        let mut unlabelled = 0.0;
        for j in 0..w.ny {
            let y = g.y(w.j0 + j);
            let fy = overlap(y - 0.5 * dy, y + 0.5 * dy, sensor.y[0], sensor.y[1]);
            for i in 0..w.nx {
                let x = g.x(w.i0 + i);
                let fx = overlap(x - 0.5 * dx, x + 0.5 * dx, sensor.x[0], sensor.x[1]);
                let label = ctx.labels[ctx.map.index(w.i0 + i, w.j0 + j)];
                let p = bem.pressure[j * w.nx + i];
                let h = surface.values()[j * w.nx + i];
                if label == UNLABELLED {
                    unlabelled += p * fx * fy;
                    continue;
                }
                let b = per.entry(label).or_insert(Basin {
                    force: 0.0,
                    sensor: 0.0,
                    top: f64::NEG_INFINITY,
                });
                b.force += p * dx * dy;
                b.sensor += p * fx * fy;
                b.top = b.top.max(h);
            }
        }
        let control = match config.control {
            RollingControl::Load(load) => Control::Load(load),
            RollingControl::Approach(d) => Control::Approach(d),
            RollingControl::TreadHeight(h) => Control::Approach(top - h),
        };
        // Each solve as the run's step solves it (the deformed tread's
        // contact points settled with its forces).
        let solve_at = |control| {
            settled_step(road, ctx.material, config, xc, control)
                .map_err(|e| {
                    BemRollingError::InvalidInput(format!("asperity split at x = {xc} m: {e}"))
                })?
                .ok_or_else(|| {
                    BemRollingError::InvalidInput(format!(
                        "asperity split: no asperity at x = {xc} m"
                    ))
                })
        };
        let own = solve_at(control)?;
        let at_bem = solve_at(Control::Approach(bem_approach - (z_max - top)))?;
        let ids = own.ids.clone();
        let shares = |s: &crate::rolling::SettledStep<'_, _>| -> Vec<f64> {
            s.solution
                .local_contacts(&s.problem)
                .iter()
                .zip(&s.contact_points)
                .map(|(c, &centre)| {
                    if c.force > 0.0 {
                        sensor.share(centre, c)
                    } else {
                        0.0
                    }
                })
                .collect()
        };
        let (own_shares, bem_shares) = (shares(&own), shares(&at_bem));
        let mut asperities = Vec::new();
        let mut seen = Vec::new();
        for (a, &id) in ids.iter().enumerate() {
            let basin = basins[id];
            seen.push(basin);
            let b = per.get(&(basin as u32)).copied();
            let bem_sensor = b.map_or(0.0, |b| b.sensor);
            if bem_sensor <= REPORTED && own_shares[a] <= REPORTED && bem_shares[a] <= REPORTED {
                continue;
            }
            let gap_model = own.problem.gaps()[a];
            let gap_exact = b.map_or(f64::INFINITY, |b| top - b.top);
            let interaction = own.solution.approach - gap_model - own.solution.depths[a];
            let depth_exact = own.solution.approach - gap_exact - interaction;
            let tilted_force = if depth_exact > 0.0 {
                alone(
                    ctx,
                    &surface,
                    w,
                    basin as u32,
                    BemControl::Approach(depth_exact),
                )?
                .0
            } else {
                0.0
            };
            let local_sensor = if own.solution.forces[a] > 0.0 {
                alone(
                    ctx,
                    &surface,
                    w,
                    basin as u32,
                    BemControl::Load(own.solution.forces[a]),
                )?
                .1
            } else {
                0.0
            };
            asperities.push(AsperityShare {
                basin,
                road_id: Some(id),
                summit: road.positions()[id],
                radius: road.summit_radius(id),
                bem_force: b.map_or(0.0, |b| b.force),
                bem_sensor,
                model_force: own.solution.forces[a],
                model_sensor: own_shares[a],
                model_force_at_bem_approach: at_bem.solution.forces[a],
                model_sensor_at_bem_approach: bem_shares[a],
                model_depth: own.solution.depths[a],
                gap_model,
                gap_exact,
                tilted_force,
                local_sensor,
            });
        }
        // Basins loaded by the BEM that the model's step does not hold.
        for (&label, b) in &per {
            if b.sensor > REPORTED && !seen.contains(&(label as usize)) {
                asperities.push(AsperityShare {
                    basin: label as usize,
                    road_id: road_of.get(&(label as usize)).copied(),
                    summit: [f64::NAN, f64::NAN],
                    radius: f64::NAN,
                    bem_force: b.force,
                    bem_sensor: b.sensor,
                    model_force: 0.0,
                    model_sensor: 0.0,
                    model_force_at_bem_approach: 0.0,
                    model_sensor_at_bem_approach: 0.0,
                    model_depth: f64::NAN,
                    gap_model: f64::NAN,
                    gap_exact: top - b.top,
                    tilted_force: f64::NAN,
                    local_sensor: 0.0,
                });
            }
        }
        asperities.sort_by(|a, b| b.bem_sensor.total_cmp(&a.bem_sensor));
        out.push(StepSplit {
            position: xc,
            bem_approach,
            model_approach: own.solution.approach + (z_max - top),
            bem_sensor: per.values().map(|b| b.sensor).sum::<f64>() + unlabelled,
            bem_sensor_unlabelled: unlabelled,
            model_sensor: own_shares.iter().sum(),
            model_sensor_at_bem_approach: bem_shares.iter().sum(),
            model_total_at_bem_approach: at_bem.solution.total_force(),
            asperities,
        });
    }
    Ok(out)
}

/// Force below which an asperity's sensor share is not reported (N).
const REPORTED: f64 = 1e-3;

/// Basin `label` alone (its cells of the step's surface `h − s`, a floor
/// elsewhere) solved by the BEM under `control` (approach below its highest
/// point, or load): its force and the force on `sensor` (N).
fn alone(
    ctx: &Context<'_>,
    surface: &Field,
    w: Window,
    label: u32,
    control: BemControl,
) -> Result<(f64, f64), BemRollingError> {
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    let mut low = f64::INFINITY;
    let mut high = f64::NEG_INFINITY;
    for j in 0..w.ny {
        for i in 0..w.nx {
            if ctx.labels[ctx.map.index(w.i0 + i, w.j0 + j)] == label {
                (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
                let h = surface.values()[j * w.nx + i];
                low = low.min(h);
                high = high.max(h);
            }
        }
    }
    let (i0, j0) = (
        i0.saturating_sub(MARGIN_CELLS),
        j0.saturating_sub(MARGIN_CELLS),
    );
    let (i1, j1) = (
        (i1 + MARGIN_CELLS).min(w.nx - 1),
        (j1 + MARGIN_CELLS).min(w.ny - 1),
    );
    let (pnx, pny) = (i1 - i0 + 1, j1 - j0 + 1);
    // Below anything the solve can reach: the basin's own depth plus 1 mm.
    let floor = low - (high - low) - 1e-3;
    let values = (0..pnx * pny)
        .map(|c| {
            let (i, j) = (i0 + c % pnx, j0 + c / pnx);
            if ctx.labels[ctx.map.index(w.i0 + i, w.j0 + j)] == label {
                surface.values()[j * w.nx + i]
            } else {
                floor
            }
        })
        .collect();
    let invalid = |e: crate::shared::CoreError| BemRollingError::InvalidInput(e.to_string());
    let (dx, dy) = (surface.grid().dx(), surface.grid().dy());
    let grid = Grid::new(pnx, pny, dx, dy).map_err(invalid)?;
    let patch = Field::new(grid, values).map_err(invalid)?;
    let options = BemOptions {
        tolerance: ctx.options.tolerance,
        max_iterations: ctx.options.max_iterations,
        periodic: false,
        par: Par::Seq,
    };
    let s = crate::bem::solve(&patch, &ctx.material, control, &options)
        .map_err(|source| BemRollingError::Bem { step: 0, source })?;
    let g = ctx.field.grid();
    let sensor = &ctx.config.sensors[ctx.sensor];
    let mut on_sensor = 0.0;
    for j in 0..pny {
        let y = g.y(w.j0 + j0 + j);
        let fy = overlap(y - 0.5 * dy, y + 0.5 * dy, sensor.y[0], sensor.y[1]);
        for i in 0..pnx {
            let x = g.x(w.i0 + i0 + i);
            let fx = overlap(x - 0.5 * dx, x + 0.5 * dx, sensor.x[0], sensor.x[1]);
            on_sensor += s.pressure[j * pnx + i] * fx * fy;
        }
    }
    Ok((s.force, on_sensor))
}
