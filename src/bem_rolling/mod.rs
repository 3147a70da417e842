//! Full-BEM rolling reference: the tread rolled over the road's height map
//! and solved at every step by the full-grid BEM (`tyreroad-bem`), to judge
//! the multipoint rolling run (`tyreroad-rolling`) on the same stretch
//! (docs/validation.md, "Rolling against the BEM").
//!
//! # The contact at one step
//!
//! The road is a height map `h(x, y)` on a regular grid (a core
//! [`Field`] whose grid origin places it in the road
//! frame of the multipoint run: x along the path, y across). At footprint
//! centre `(x_c, y_c)` the tread's undeformed surface lies `s(ξ, η)` above
//! its lowest point ([`Tread::profile`](crate::rolling::Tread::profile),
//! `ξ = x − x_c`, `η = y − y_c`), so the contact is that of a flat
//! half-space against the rigid *effective* surface
//!
//! ```text
//! h_eff(x, y) = h(x, y) − s(x − x_c, y − y_c)
//! ```
//!
//! over the window of cells whose centres lie in the multipoint run's
//! selection window (`|ξ| ≤ L/2 + m`, `|η| ≤ W/2 + m`). The window has the
//! same number of cells at every step, so one [`Solver`]
//! (one kernel spectrum) serves the whole run.
//!
//! Approach: as in the rolling crate, `δ0` is the approach of the tread's
//! lowest point below the road's highest point `z_max` (here the map's
//! maximum). The BEM's approach is measured from the window's highest
//! effective point `z_ref = max h_eff`, so `δ0 = δ_BEM + z_max − z_ref`;
//! under displacement control `δ_BEM = δ0 − z_max + z_ref` is imposed
//! (no contact when it is ≤ 0).
//!
//! # Warm start
//!
//! Each step starts from the previous step's pressure shifted by the
//! window's move (a whole number of cells: `Δx` need not be a multiple of
//! `dx`, the window start is rounded to the grid), cells entering the window
//! at zero; under load control the guess is rescaled to the load by the
//! BEM. A step that does not converge is recorded as failed (NaN values) and
//! the next step cold-starts, as in the rolling crate.
//!
//! # Signals
//!
//! Per step ([`BemStep`]): total force `Σ p_k dx dy`, approach `δ0`, contact
//! area (cells with `p > 0`), and the force on each sensor: the BEM pressure,
//! uniform on each cell, integrated over the sensor's road-fixed rectangle
//! (each cell counted with the fraction of its area inside it), so sensors
//! tiling the road sum to the total force. Spectra are the core's
//! one-third-octave bands ([`compare`]), under the same policy as the
//! scenario's rolling runs (failed samples bridged, the scenario's Welch
//! segment).
//!
//! # Invariants
//!
//! - `total_force` equals the imposed load under load control (to the BEM's
//!   rounding, ≈ 1e-15 relative);
//! - the sensor forces of sensors tiling the window sum to the total force;
//! - a step's result depends on its warm start only within the BEM
//!   tolerance ([`BemRollingOptions::tolerance`]).

mod compare;
mod reference;
mod refine;
mod run_scenario;
mod split;
mod visco;
mod visco_compare;

pub use compare::{
    BandComparison, ERROR_DB_FOR_1DB, RollingComparison, SignalComparison, SpectrumKind, compare,
    compare_references, summit_sensor_forces, third_octave_policy, transient_policy,
};
pub use reference::BemReference;
pub use refine::{
    GridConvergence, Refinement, grid_convergence, refine_bilinear, refined_texture_fields,
    run_grid_convergence,
};
pub use run_scenario::{
    BemRollingRun, FieldRungAccountings, Stretch, run_scenario_comparison,
    run_scenario_comparison_against, scenario_bem_reference, texture_field,
};
pub use split::{AsperityShare, StepSplit, asperity_split};
pub use visco::{roll_visco_bem, roll_visco_bem_scenario};
pub use visco_compare::{ViscoBemRollingRun, run_visco_scenario_comparison};

use crate::bem::{BemError, BemOptions, BemSolution, Control, Solver};
use crate::rolling::{RollingConfig, RollingControl, Sensor, StepStatus};
use crate::shared::{Field, Grid, Material, Par};

/// What can go wrong in a BEM rolling run.
#[derive(Debug, thiserror::Error)]
pub enum BemRollingError {
    /// The road, configuration or options are malformed (the message names
    /// the value and what it must be).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The footprint window leaves the road's height map at some step.
    #[error(
        "step {step} (x = {position} m): the footprint window leaves the height map \
         (cells {first}..{end} of {available} along {axis})"
    )]
    OffMap {
        /// Step index.
        step: usize,
        /// Footprint centre (m).
        position: f64,
        /// "x" or "y".
        axis: &'static str,
        /// First window cell (may be negative).
        first: i64,
        /// One past the last window cell.
        end: i64,
        /// Cells of the map along that axis.
        available: usize,
    },
    /// The scenario could not be read or its multipoint run failed.
    #[error(transparent)]
    Scenario(#[from] crate::scenario::ScenarioError),
    /// The BEM failed for a reason other than non-convergence.
    #[error("step {step}: {source}")]
    Bem {
        /// Step index.
        step: usize,
        /// The BEM's error.
        source: BemError,
    },
}

/// How the BEM reference is solved (nothing here changes what is solved,
/// only how precisely and on how many threads).
#[derive(Clone, Debug, PartialEq)]
pub struct BemRollingOptions {
    /// Relative complementarity residual of each step's BEM solve.
    pub tolerance: f64,
    /// Iterations allowed per step.
    pub max_iterations: usize,
    /// Parallelism of the FFTs.
    pub par: Par,
}

impl BemRollingOptions {
    /// The options of one cap's own solve
    /// ([`crate::fidelity::cap_sensors`]): this tolerance and iteration
    /// limit, the rest the BEM's defaults.
    pub fn cap_solve(&self) -> crate::bem::BemOptions {
        crate::bem::BemOptions {
            tolerance: self.tolerance,
            max_iterations: self.max_iterations,
            ..crate::bem::BemOptions::default()
        }
    }
}

impl Default for BemRollingOptions {
    /// Tolerance `1e-7` (forces converge to ~1e-6 of the load, far below
    /// the 2 % targets), 5000 iterations, every thread of the current pool.
    fn default() -> Self {
        Self {
            tolerance: 1e-7,
            max_iterations: 5000,
            par: Par::rayon(0),
        }
    }
}

/// One step of the BEM reference.
#[derive(Clone, Debug, PartialEq)]
pub struct BemStep {
    /// Step index `k`.
    pub index: usize,
    /// Footprint centre `x_c` (m).
    pub position: f64,
    /// Time `x_c / V` (s).
    pub time: f64,
    /// Total force (N).
    pub total_force: f64,
    /// Approach `δ0` below the map's highest point (m).
    pub approach: f64,
    /// Contact area (m²): cells with `p > 0`.
    pub contact_area: f64,
    /// Conjugate-gradient iterations.
    pub iterations: usize,
    /// Converged, or failed (NaN values).
    pub status: StepStatus,
    /// Force on each sensor (N), in the configuration's order.
    pub sensor_forces: Vec<f64>,
}

/// A BEM rolling run: one record per step.
#[derive(Clone, Debug, PartialEq)]
pub struct BemRollingResult {
    /// One record per step, in path order.
    pub steps: Vec<BemStep>,
    /// Sampling rate `V/Δx` (Hz).
    pub sample_rate: f64,
    /// Cells of the footprint window `(nx, ny)`.
    pub window: (usize, usize),
}

impl BemRollingResult {
    /// Total force signal (N).
    pub fn total_force(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.total_force).collect()
    }
    /// Approach signal (m).
    pub fn approach(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.approach).collect()
    }
    /// Force signal of sensor `k` (N).
    pub fn sensor(&self, k: usize) -> Vec<f64> {
        self.steps
            .iter()
            .map(|s| s.sensor_forces.get(k).copied().unwrap_or(f64::NAN))
            .collect()
    }
    /// Steps that failed.
    pub fn failed(&self) -> usize {
        self.steps
            .iter()
            .filter(|s| s.status == StepStatus::Failed)
            .count()
    }
    /// Conjugate-gradient iterations over the run.
    pub fn iterations(&self) -> usize {
        self.steps.iter().map(|s| s.iterations).sum()
    }
}

/// The window of cells under the footprint: first cell and count per axis.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Window {
    i0: usize,
    j0: usize,
    nx: usize,
    ny: usize,
}

/// Cells per axis of a window of half-width `half` (m) on spacing `d`.
fn window_cells(half: f64, d: f64) -> usize {
    (2.0 * half / d + 1e-9).floor() as usize + 1
}

/// First cell of a window starting at `lo` (m) on an axis of origin `o`,
/// spacing `d`: the first cell centre `≥ lo` (to 1e-9 cell).
fn first_cell(lo: f64, o: f64, d: f64) -> i64 {
    ((lo - o) / d - 1e-9).ceil() as i64
}

/// Rolls the tread of `config` over the height map `road` (in the road
/// frame: its grid origin is the centre of cell `(0, 0)`) and solves every
/// step by the BEM, under the same control and with the same sensors.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for an invalid configuration, a map
/// with invalid cells or options out of range; [`BemRollingError::OffMap`]
/// when the footprint leaves the map; [`BemRollingError::Bem`] when a BEM
/// solve fails for another reason than non-convergence (which is that
/// step's failure, recorded).
pub fn roll_bem(
    road: &Field,
    material: Material,
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
    let (hx, _) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    let (window_grid, (nx, j0, ny)) = window_layout(road, config)?;
    let bem_options = BemOptions {
        tolerance: options.tolerance,
        max_iterations: options.max_iterations,
        periodic: false,
        par: options.par,
    };
    let mut solver = Solver::new(&window_grid, &material, &bem_options)
        .map_err(|source| BemRollingError::Bem { step: 0, source })?;
    let z_max = road.max();
    // Every window is on the map before anything is solved.
    let windows = (0..config.steps())
        .map(|k| locate(g, k, config.position(k), hx + m, (nx, j0, ny)))
        .collect::<Result<Vec<_>, _>>()?;
    let mut steps = Vec::with_capacity(windows.len());
    // The previous step's pressure and window, for the warm start.
    let mut previous: Option<(Window, Vec<f64>)> = None;
    for (k, &window) in windows.iter().enumerate() {
        let xc = config.position(k);
        let surface = effective_surface(road, config, xc, window)?;
        let guess = previous
            .as_ref()
            .map(|(w, p)| shift_pressure(p, *w, window));
        let solved = solve_step(
            &mut solver,
            &surface,
            config.control,
            z_max,
            guess.as_deref(),
            k,
        )?;
        let step = match solved {
            Some((solution, approach)) => {
                let record = record_step(config, k, &solution, approach, window, g);
                previous = Some((window, solution.pressure));
                record
            }
            None => {
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

/// The footprint window's grid and its cells `(nx, j0, ny)`: `nx` along
/// the path, rows `j0 .. j0 + ny` across (clipped to the map: no road
/// there, as the multipoint road has no asperity there).
fn window_layout(
    road: &Field,
    config: &RollingConfig,
) -> Result<(Grid, (usize, usize, usize)), BemRollingError> {
    let g = road.grid();
    let (hx, hy) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    let nx = window_cells(hx + m, g.dx());
    let j_first = first_cell(config.lateral - hy - m, g.origin()[1], g.dy());
    let j_end = j_first + window_cells(hy + m, g.dy()) as i64;
    let (j0, j1) = (j_first.max(0), j_end.min(g.ny() as i64));
    if j1 <= j0 {
        return Err(BemRollingError::OffMap {
            step: 0,
            position: config.start,
            axis: "y",
            first: j_first,
            end: j_end,
            available: g.ny(),
        });
    }
    let (j0, ny) = (j0 as usize, (j1 - j0) as usize);
    let grid = Grid::new(nx, ny, g.dx(), g.dy())
        .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
    Ok((grid, (nx, j0, ny)))
}

/// The window of step `k` (rows `j0 .. j0 + ny`), checked to lie on the
/// map along x.
fn locate(
    g: &Grid,
    k: usize,
    xc: f64,
    half_x: f64,
    (nx, j0, ny): (usize, usize, usize),
) -> Result<Window, BemRollingError> {
    let i0 = first_cell(xc - half_x, g.origin()[0], g.dx());
    let end = i0 + nx as i64;
    if i0 < 0 || end > g.nx() as i64 {
        return Err(BemRollingError::OffMap {
            step: k,
            position: xc,
            axis: "x",
            first: i0,
            end,
            available: g.nx(),
        });
    }
    Ok(Window {
        i0: i0 as usize,
        j0,
        nx,
        ny,
    })
}

/// `h_eff = h − s(ξ, η)` on the window (a block has `s = 0` on it; a cell
/// the tread does not cover is set far below the road).
fn effective_surface(
    road: &Field,
    config: &RollingConfig,
    xc: f64,
    w: Window,
) -> Result<Field, BemRollingError> {
    let g = road.grid();
    let (lo, hi) = road.min_max().unwrap_or((0.0, 0.0));
    let below = lo - 10.0 * (hi - lo).max(g.dx());
    let mut values = Vec::with_capacity(w.nx * w.ny);
    for j in 0..w.ny {
        let y = g.y(w.j0 + j);
        for i in 0..w.nx {
            let x = g.x(w.i0 + i);
            let h = road.at(w.i0 + i, w.j0 + j);
            values.push(match config.tread.profile(x - xc, y - config.lateral) {
                Some(s) => h - s,
                None => below,
            });
        }
    }
    let grid = Grid::new(w.nx, w.ny, g.dx(), g.dy())
        .and_then(|grid| grid.with_origin([g.x(w.i0), g.y(w.j0)]))
        .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
    Field::new(grid, values).map_err(|e| BemRollingError::InvalidInput(e.to_string()))
}

/// The previous pressure moved onto the new window (cells entering at 0).
fn shift_pressure(p: &[f64], from: Window, to: Window) -> Vec<f64> {
    let (di, dj) = (to.i0 as i64 - from.i0 as i64, to.j0 as i64 - from.j0 as i64);
    let mut out = vec![0.0; to.nx * to.ny];
    for j in 0..to.ny {
        let sj = j as i64 + dj;
        if sj < 0 || sj >= from.ny as i64 {
            continue;
        }
        for i in 0..to.nx {
            let si = i as i64 + di;
            if si >= 0 && si < from.nx as i64 {
                out[j * to.nx + i] = p[sj as usize * from.nx + si as usize];
            }
        }
    }
    out
}

/// Solves one step; `None` when the BEM did not converge (the step's
/// failure). Returns the solution and the approach `δ0` below `z_max`.
fn solve_step(
    solver: &mut Solver,
    surface: &Field,
    control: RollingControl,
    z_max: f64,
    guess: Option<&[f64]>,
    k: usize,
) -> Result<Option<(BemSolution, f64)>, BemRollingError> {
    let z_ref = surface.max();
    let bem_control = match control {
        RollingControl::Load(w) => Control::Load(w),
        RollingControl::Approach(d) => Control::Approach(d - (z_max - z_ref)),
        RollingControl::TreadHeight(h) => Control::Approach(z_max - h - (z_max - z_ref)),
    };
    // Displacement control above the window's highest point: no contact.
    if let Control::Approach(d) = bem_control
        && d <= 0.0
    {
        let n = surface.grid().len();
        let solution = BemSolution {
            grid: surface.grid().clone(),
            pressure: vec![0.0; n],
            displacement: vec![0.0; n],
            gap: vec![f64::NAN; n],
            reference_height: z_ref,
            approach: d,
            force: 0.0,
            contact_area: 0.0,
            contact_cells: 0,
            iterations: 0,
            residual: 0.0,
        };
        return Ok(Some((solution, d + z_max - z_ref)));
    }
    let usable = guess.filter(|p| p.iter().any(|&v| v > 0.0));
    let result = match usable {
        Some(p) => solver.solve_from(surface, bem_control, p),
        None => solver.solve(surface, bem_control),
    };
    match result {
        Ok(s) => {
            let approach = s.approach + z_max - s.reference_height;
            Ok(Some((s, approach)))
        }
        Err(BemError::NotConverged { .. }) => Ok(None),
        Err(source) => Err(BemRollingError::Bem { step: k, source }),
    }
}

fn record_step(
    config: &RollingConfig,
    k: usize,
    s: &BemSolution,
    approach: f64,
    w: Window,
    road: &Grid,
) -> BemStep {
    let xc = config.position(k);
    BemStep {
        index: k,
        position: xc,
        time: xc / config.speed,
        total_force: s.force,
        approach,
        contact_area: s.contact_area,
        iterations: s.iterations,
        status: StepStatus::Converged,
        sensor_forces: config
            .sensors
            .iter()
            .map(|sensor| sensor_force(sensor, &s.pressure, w, road))
            .collect(),
    }
}

fn failed_step(config: &RollingConfig, k: usize) -> BemStep {
    let xc = config.position(k);
    BemStep {
        index: k,
        position: xc,
        time: xc / config.speed,
        total_force: f64::NAN,
        approach: f64::NAN,
        contact_area: f64::NAN,
        iterations: 0,
        status: StepStatus::Failed,
        sensor_forces: vec![f64::NAN; config.sensors.len()],
    }
}

/// Length of `[a0, a1] ∩ [b0, b1]` (0 when disjoint).
fn overlap(a0: f64, a1: f64, b0: f64, b1: f64) -> f64 {
    (a1.min(b1) - a0.max(b0)).max(0.0)
}

/// The pressure `p` (uniform on each window cell) integrated over the
/// sensor's rectangle: each cell's force times the fraction of the cell
/// inside it.
fn sensor_force(sensor: &Sensor, p: &[f64], w: Window, road: &Grid) -> f64 {
    let (dx, dy) = (road.dx(), road.dy());
    let mut force = 0.0;
    for j in 0..w.ny {
        let y = road.y(w.j0 + j);
        let fy = overlap(y - 0.5 * dy, y + 0.5 * dy, sensor.y[0], sensor.y[1]);
        if fy == 0.0 {
            continue;
        }
        for i in 0..w.nx {
            let x = road.x(w.i0 + i);
            let fx = overlap(x - 0.5 * dx, x + 0.5 * dx, sensor.x[0], sensor.x[1]);
            force += p[j * w.nx + i] * fx * fy;
        }
    }
    force
}

#[cfg(test)]
mod caps_tests;
#[cfg(test)]
mod compare_tests;
#[cfg(test)]
mod refine_tests;
#[cfg(test)]
mod slope_tests;
#[cfg(test)]
mod split_tests;
#[cfg(test)]
mod tests;
#[cfg(test)]
mod visco_compare_tests;
#[cfg(test)]
mod visco_tests;
