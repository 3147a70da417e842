//! A rolling run's sensor forces with each contact's force spread as its
//! own cap's pressure: `[rolling] sensor_accounting = "caps"` in a
//! scenario, and the "(caps)" rows of the BEM rolling comparison
//! (docs/rolling.md, "Sensors counted on the caps"; docs/validation.md,
//! "Where the shoulder's load goes").
//!
//! The rolling run's sensors spread each contact's force as a Hertz or cone
//! pressure over a disc around its contact point (`Sensor::share`), or as
//! its calibrated field under a level punch. A road chipping is no
//! paraboloid: its highest point (the summit) may lie at one end of a long,
//! flat top, so its real patch reaches millimetres beyond that disc (on the
//! dense asphalt a chipping whose summit lies 1.9 mm outside the shoulder
//! sensor puts 23–40 % of its load inside it by the BEM, 2–3 % by the
//! disc). Here the force `P_i` of each contact that a sensor's edge could
//! cut is placed by the BEM on its cap alone: the cells of its segmentation
//! basin, under the tread's profile at that step (`h − s(x − x_c, y −
//! y_c)`, a floor elsewhere), pressed under load control to `P_i`; the
//! sensor takes that pressure over its rectangle (cells counted with the
//! fraction of their area inside). A contact whose basin lies wholly inside
//! a sensor gives it `P_i`, wholly outside 0, without a solve.
//!
//! Invariants: each contact's shares over sensors tiling the road sum to
//! `P_i` (the local solve carries exactly `P_i`); the forces are the run's,
//! only where they are counted changes; a failed step's sensors are NaN.

use crate::bem::{BemError, BemOptions, Control, Solver};
use crate::rolling::{RollingConfig, RollingResult};
use crate::shared::{Field, Grid, Material, Par, map_at};
use crate::texture::HeightMap;
use crate::texture_road::TextureRoad;

use super::FidelityError;

/// The texture `map` in a rolling run's road frame: x from the map's first
/// column, y from its mid-width (the frame of `crate::texture_road`'s
/// rolling sets).
///
/// # Errors
/// [`FidelityError::InvalidInput`] for a map with unmeasured points (a cap
/// solve needs every cell).
pub fn road_frame_field(map: &HeightMap) -> Result<Field, FidelityError> {
    let field = map.field();
    let missing = field.grid().len() - field.valid_count();
    if missing != 0 {
        return Err(FidelityError::invalid(
            "texture",
            format!("{missing} unmeasured points"),
            "a complete map (every cell measured)",
        ));
    }
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let grid = field
        .grid()
        .clone()
        .with_origin([0.0, -y_mid])
        .map_err(|e| FidelityError::invalid("road frame", e, "a valid grid"))?;
    Field::new(grid, field.values().to_vec())
        .map_err(|e| FidelityError::invalid("road frame", e, "a valid field"))
}

/// Cells of margin around a basin in its local solve.
const MARGIN_CELLS: usize = 3;

/// One basin's cells (indices into the road field) and the road-frame
/// rectangle they cover.
struct BasinCells<'a> {
    cells: &'a [usize],
    x: [f64; 2],
    y: [f64; 2],
}

/// The sensor forces of `run` (one row per sensor, one value per step; NaN
/// at a failed step) with each contact's force spread as its cap's
/// pressure, each cap solved with `bem` (its tolerance and iterations;
/// never periodic, each solve on one thread), the steps spread over `par`.
///
/// `road_positions` are the summits of the run's road by id (the
/// `RollingRun`'s); `field` is the texture in the road frame
/// ([`road_frame_field`]) and `texture` its segmentation into the road
/// (each run asperity is found in it by its summit position, to 1 nm).
///
/// # Errors
/// [`FidelityError::InvalidInput`] when a contact's summit is not a
/// segmented asperity of `texture`; [`FidelityError::CapSensors`] when a
/// local solve fails (the first step's, [`cap_sensor_forces_by_step`]
/// keeps the other steps).
pub fn cap_sensor_forces(
    run: &RollingResult,
    road_positions: &[[f64; 2]],
    config: &RollingConfig,
    (field, texture, material): (&Field, &TextureRoad, &Material),
    (bem, par): (&BemOptions, Par),
) -> Result<Vec<Vec<f64>>, FidelityError> {
    let by_step = cap_sensor_forces_by_step(
        run,
        road_positions,
        config,
        (field, texture, material),
        (bem, par),
    )?
    .into_iter()
    .collect::<Result<Vec<_>, _>>()?;
    // One row per sensor.
    Ok((0..config.sensors.len())
        .map(|s| by_step.iter().map(|row| row[s]).collect())
        .collect())
}

/// [`cap_sensor_forces`] step by step: each step's sensor forces (one per
/// sensor; NaN at a failed step), or [`FidelityError::CapSensors`] for a
/// step where a cap's solve failed, which is that step's failure only.
///
/// # Errors
/// What is wrong with the whole run: a road field that is not the
/// segmentation's, a contact whose summit is no segmented asperity of
/// `texture`.
pub fn cap_sensor_forces_by_step(
    run: &RollingResult,
    road_positions: &[[f64; 2]],
    config: &RollingConfig,
    (field, texture, material): (&Field, &TextureRoad, &Material),
    (bem, par): (&BemOptions, Par),
) -> Result<Vec<Result<Vec<f64>, FidelityError>>, FidelityError> {
    let g = field.grid();
    let (nx, ny) = (g.nx(), g.ny());
    if texture.segmentation.size() != (nx, ny) {
        return Err(FidelityError::invalid(
            "road field",
            format!("{nx} × {ny}"),
            format!("the segmentation's size {:?}", texture.segmentation.size()),
        ));
    }
    // Summit positions of the texture road in the road frame (the field's
    // origin carries the frame's shift across the path).
    let shift = g.origin();
    let asperities = texture.segmentation.asperities();
    let key = |p: [f64; 2]| ((p[0] * 1e9).round() as i64, (p[1] * 1e9).round() as i64);
    let by_summit: std::collections::HashMap<(i64, i64), usize> = texture
        .asperity_index
        .iter()
        .map(|&k| {
            let s = asperities[k].summit;
            (key([s[0] + shift[0], s[1] + shift[1]]), k)
        })
        .collect();
    let (dx, dy) = (g.dx(), g.dy());
    let bem_options = BemOptions {
        periodic: false,
        par: Par::Seq,
        ..*bem
    };
    let basin_cells = |basin: usize| {
        let cells = &asperities[basin].cells[..];
        let (mut x, mut y) = (
            [f64::INFINITY, f64::NEG_INFINITY],
            [f64::INFINITY, f64::NEG_INFINITY],
        );
        for &c in cells {
            let (cx, cy) = (g.x(c % nx), g.y(c / nx));
            x = [x[0].min(cx - 0.5 * dx), x[1].max(cx + 0.5 * dx)];
            y = [y[0].min(cy - 0.5 * dy), y[1].max(cy + 0.5 * dy)];
        }
        BasinCells { cells, x, y }
    };
    // One step's sensor forces (a row per sensor); the inner error is a
    // cap solve's, the step's own.
    type StepForces = Result<Vec<f64>, FidelityError>;
    let step_forces = |k: usize| -> Result<StepForces, FidelityError> {
        let step = &run.steps[k];
        let mut out = vec![0.0; config.sensors.len()];
        // A failed step's forces are unknown, not zero.
        if step.status == crate::rolling::StepStatus::Failed {
            out.fill(f64::NAN);
            return Ok(Ok(out));
        }
        for (&id, &force) in step.contact_ids.iter().zip(&step.contact_forces) {
            let basin = road_positions
                .get(id)
                .and_then(|&summit| by_summit.get(&key(summit)));
            let Some(&basin) = basin else {
                let summit = road_positions.get(id);
                return Err(FidelityError::invalid(
                    "contact",
                    format!("asperity {id} (summit {summit:?} m, step {k})"),
                    "an asperity of the texture's segmentation",
                ));
            };
            let b = basin_cells(basin);
            let mut local: Option<Vec<f64>> = None;
            for (s, sensor) in config.sensors.iter().enumerate() {
                let inside = b.x[0] >= sensor.x[0]
                    && b.x[1] <= sensor.x[1]
                    && b.y[0] >= sensor.y[0]
                    && b.y[1] <= sensor.y[1];
                let outside = b.x[1] <= sensor.x[0]
                    || b.x[0] >= sensor.x[1]
                    || b.y[1] <= sensor.y[0]
                    || b.y[0] >= sensor.y[1];
                if inside {
                    out[s] += force;
                    continue;
                }
                if outside {
                    continue;
                }
                if local.is_none() {
                    let on = cap_pressure(
                        field,
                        &b,
                        config,
                        step.position,
                        force,
                        material,
                        &bem_options,
                    );
                    let on = match on {
                        Ok(on) => on,
                        Err(source) => {
                            return Ok(Err(FidelityError::CapSensors { step: k, source }));
                        }
                    };
                    local = Some(
                        config
                            .sensors
                            .iter()
                            .map(|sensor| {
                                on.iter()
                                    .map(|&(x, y, f)| {
                                        f * overlap(
                                            x - 0.5 * dx,
                                            x + 0.5 * dx,
                                            sensor.x[0],
                                            sensor.x[1],
                                        ) * overlap(
                                            y - 0.5 * dy,
                                            y + 0.5 * dy,
                                            sensor.y[0],
                                            sensor.y[1],
                                        ) / (dx * dy)
                                    })
                                    .sum()
                            })
                            .collect(),
                    );
                }
                out[s] += local.as_ref().map_or(0.0, |l| l[s]);
            }
        }
        Ok(Ok(out))
    };
    map_at(par, run.steps.len(), step_forces)
}

/// The BEM pressure of basin `b` alone under the tread at `xc`, carrying
/// `force`: `(x, y, force on the cell)` for each loaded cell.
fn cap_pressure(
    field: &Field,
    b: &BasinCells<'_>,
    config: &RollingConfig,
    xc: f64,
    force: f64,
    material: &Material,
    options: &BemOptions,
) -> Result<Vec<(f64, f64, f64)>, BemError> {
    let g = field.grid();
    let nx = g.nx();
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    let mut low = f64::INFINITY;
    let mut high = f64::NEG_INFINITY;
    // A contact at a block's edge may have no cell under the block: its
    // cap is then pressed as the bare road (the tread's profile left out),
    // rather than not at all.
    let under_tread = b.cells.iter().any(|&c| {
        config
            .tread
            .profile(g.x(c % nx) - xc, g.y(c / nx) - config.lateral)
            .is_some()
    });
    let surface = |c: usize| {
        let (i, j) = (c % nx, c / nx);
        let s = if under_tread {
            config
                .tread
                .profile(g.x(i) - xc, g.y(j) - config.lateral)
                .unwrap_or(f64::INFINITY)
        } else {
            0.0
        };
        field.values()[c] - s
    };
    for &c in b.cells {
        let (i, j) = (c % nx, c / nx);
        (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        let h = surface(c);
        if h.is_finite() {
            low = low.min(h);
            high = high.max(h);
        }
    }
    let (i0, j0) = (
        i0.saturating_sub(MARGIN_CELLS),
        j0.saturating_sub(MARGIN_CELLS),
    );
    let (i1, j1) = (
        (i1 + MARGIN_CELLS).min(nx - 1),
        (j1 + MARGIN_CELLS).min(g.ny() - 1),
    );
    let (pnx, pny) = (i1 - i0 + 1, j1 - j0 + 1);
    // Below anything the solve can reach: the cap's whole depth again, and
    // a millimetre.
    let floor = low - (high - low) - 1e-3;
    let mut values = vec![floor; pnx * pny];
    for &c in b.cells {
        let h = surface(c);
        if h.is_finite() {
            let (i, j) = (c % nx - i0, c / nx - j0);
            values[j * pnx + i] = h;
        }
    }
    let grid = Grid::new(pnx, pny, g.dx(), g.dy())?;
    let patch = Field::new(grid, values)?;
    let s = Solver::new(patch.grid(), material, options)?.solve(&patch, Control::Load(force))?;
    let cell = g.dx() * g.dy();
    Ok((0..pnx * pny)
        .filter(|&c| s.pressure[c] > 0.0)
        .map(|c| (g.x(i0 + c % pnx), g.y(j0 + c / pnx), s.pressure[c] * cell))
        .collect())
}

/// Length of the overlap of `[a0, a1]` and `[b0, b1]` (0 when apart).
fn overlap(a0: f64, a1: f64, b0: f64, b1: f64) -> f64 {
    (a1.min(b1) - a0.max(b0)).max(0.0)
}
