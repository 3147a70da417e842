//! The multipoint model measured against the full-grid BEM reference on a
//! scenario of balls (docs/validation.md): the same balls as true spherical
//! caps on a 0.1 mm grid, per-ball forces and radii from the Voronoi regions
//! of the summits; the two-scale radii (each ball's real shape solved alone
//! under its multipoint force) and pressure maps.

use std::time::Instant;

use tyreroad_bem::{BemOptions, Control, Grid, Solver, Sphere, nearest_labels, spherical_caps};
use tyreroad_multipoint::solve;

use super::statics::StaticResult;
use super::{Scenario, ScenarioError, ShapeSpec};
use crate::two_scale::{LocalShape, TwoScale, TwoScaleOptions, two_scale};

/// BEM cell size (m): per-ball forces change by < 0.05 % from 0.1 to
/// 0.05 mm on the paper's case (docs/bem.md, grid convergence).
pub const BEM_CELL: f64 = 1e-4;

/// Largest relative per-ball force difference, model vs BEM, that passes.
pub const MAX_FORCE_DIFFERENCE: f64 = 0.05;

/// Cell of the two-scale pressure map (m).
pub const MAP_CELL: f64 = 8e-5;

/// The load whose pressure map is shown (N), or the largest if absent.
pub const IMAGE_LOAD: f64 = 500.0;

/// One ball of the scenario, as the BEM sees it.
struct Ball {
    position: [f64; 2],
    summit: f64,
    radius: f64,
}

fn balls(scenario: &Scenario) -> Result<Vec<Ball>, ScenarioError> {
    (0..scenario.asperities.len())
        .map(|k| {
            let a = &scenario.asperities[k];
            let ShapeSpec::Sphere { radius, .. } = scenario.shape_of(k)? else {
                return Err(ScenarioError::Invalid(format!(
                    "asperity #{}: the BEM comparison handles spheres only",
                    k + 1
                )));
            };
            Ok(Ball {
                position: [a.x.value(), a.y.value()],
                summit: a.height.map_or(0.0, |h| h.value()),
                radius: radius.value(),
            })
        })
        .collect()
}

/// The BEM grid: square cells of `cell`, an odd count per axis centred on
/// the middle of the summits (so that summits on a pitch multiple of `cell`
/// are cell centres), covering every ball's footprint.
fn bem_grid(balls: &[Ball], cell: f64) -> Result<Grid, tyreroad_bem::BemError> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in balls {
        for a in 0..2 {
            lo[a] = lo[a].min(b.position[a] - b.radius);
            hi[a] = hi[a].max(b.position[a] + b.radius);
        }
    }
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let n = |a: usize| 2 * ((0.5 * (hi[a] - lo[a]) / cell).ceil() as usize) + 1;
    let (nx, ny) = (n(0), n(1));
    Ok(Grid::new(nx, ny, cell, cell)?.with_origin([
        centre[0] - (nx / 2) as f64 * cell,
        centre[1] - (ny / 2) as f64 * cell,
    ])?)
}

/// One load of the BEM reference.
#[derive(Clone, Debug, PartialEq)]
pub struct BemLoad {
    /// Imposed load (N).
    pub load: f64,
    /// Force of each ball's Voronoi region (N), scenario order.
    pub forces: Vec<f64>,
    /// Equivalent contact radius of each region (m).
    pub radii: Vec<f64>,
    /// Approach (m).
    pub approach: f64,
    /// Solver iterations.
    pub iterations: usize,
    /// Wall time (s).
    pub seconds: f64,
}

/// One load of the comparison.
#[derive(Clone, Debug)]
pub struct ComparedLoad {
    /// Imposed load (N).
    pub load: f64,
    /// The BEM reference.
    pub bem: BemLoad,
    /// The two-scale rebuild of the multipoint forces.
    pub two_scale: TwoScale,
    /// The multipoint approach (m), NaN if its solve failed.
    pub model_approach: f64,
}

/// The model against the BEM reference.
#[derive(Clone, Debug)]
pub struct BemComparison {
    /// The BEM grid.
    pub grid: Grid,
    /// Grid and surface set-up time (s).
    pub setup_seconds: f64,
    /// Time of all two-scale rebuilds (s).
    pub two_scale_seconds: f64,
    /// One entry per load, in the order of the static result.
    pub loads: Vec<ComparedLoad>,
}

impl BemComparison {
    /// The load whose pressure map is shown: [`IMAGE_LOAD`] if solved,
    /// else the largest.
    pub fn shown_load(&self) -> Option<&ComparedLoad> {
        self.loads
            .iter()
            .find(|l| l.load == IMAGE_LOAD)
            .or_else(|| self.loads.iter().max_by(|a, b| a.load.total_cmp(&b.load)))
    }
}

/// Solves the scenario by the BEM at every load of `statics` (the
/// multipoint results, in scenario order per load, loads in increasing
/// order warm-started) and rebuilds the two-scale radii.
///
/// # Errors
/// A shape other than a sphere, rows that do not match the scenario, a
/// failed BEM or two-scale solve.
pub fn bem_comparison(
    scenario: &Scenario,
    statics: &StaticResult,
) -> Result<BemComparison, ScenarioError> {
    let balls = balls(scenario)?;
    let material = scenario.material()?;
    let bem_error = |context: &str| {
        let context = context.to_string();
        move |source| ScenarioError::Bem { context, source }
    };
    let positions: Vec<[f64; 2]> = balls.iter().map(|b| b.position).collect();
    let load_list = statics.loads();
    let n = balls.len();
    for &load in &load_list {
        let rows = statics.at_load(load).len();
        if rows != n {
            return Err(ScenarioError::Invalid(format!(
                "{load} N: {rows} rows for {n} asperities"
            )));
        }
    }

    let start = Instant::now();
    let grid = bem_grid(&balls, BEM_CELL).map_err(bem_error("BEM grid"))?;
    let base = balls
        .iter()
        .map(|b| b.summit - b.radius)
        .fold(f64::INFINITY, f64::min);
    let spheres: Vec<Sphere> = balls
        .iter()
        .map(|b| Sphere {
            centre: b.position,
            radius: b.radius,
            summit: b.summit,
        })
        .collect();
    let surface = spherical_caps(&grid, &spheres, base).map_err(bem_error("BEM surface"))?;
    let labels = nearest_labels(&grid, &positions);
    let mut solver =
        Solver::new(&grid, &material, &BemOptions::default()).map_err(bem_error("BEM solver"))?;
    let setup_seconds = start.elapsed().as_secs_f64();
    let mut order = load_list.clone();
    order.sort_by(f64::total_cmp);
    let mut previous: Option<Vec<f64>> = None;
    let mut bem = Vec::new();
    for &load in &order {
        let t = Instant::now();
        let context = format!("BEM solve at {load} N");
        let sol = match &previous {
            Some(p) => solver.solve_from(&surface, Control::Load(load), p),
            None => solver.solve(&surface, Control::Load(load)),
        }
        .map_err(bem_error(&context))?;
        let regions = sol.regions(&labels).map_err(bem_error(&context))?;
        bem.push(BemLoad {
            load,
            forces: regions.iter().map(|r| r.force).collect(),
            radii: regions.iter().map(|r| r.equivalent_radius).collect(),
            approach: sol.approach,
            iterations: sol.iterations,
            seconds: t.elapsed().as_secs_f64(),
        });
        previous = Some(sol.pressure);
    }

    let shapes: Vec<LocalShape> = balls
        .iter()
        .map(|b| LocalShape::Sphere { radius: b.radius })
        .collect();
    let options = TwoScaleOptions {
        map_cell: Some(MAP_CELL),
        ..TwoScaleOptions::default()
    };
    let t = Instant::now();
    let mut two = Vec::new();
    for &load in &load_list {
        let forces: Vec<f64> = statics.at_load(load).iter().map(|r| r.force).collect();
        let ts =
            two_scale(&positions, &forces, &shapes, &material, &options).map_err(|source| {
                ScenarioError::TwoScale {
                    context: format!("two-scale at {load} N"),
                    source,
                }
            })?;
        two.push(ts);
    }
    let two_scale_seconds = t.elapsed().as_secs_f64();

    // The multipoint approaches, for the comparison (a solve is milliseconds).
    let problem = scenario.problem()?;
    let solver_options = scenario.solver_options();
    let mut loads = Vec::with_capacity(load_list.len());
    for (load, ts) in load_list.into_iter().zip(two) {
        let b = bem
            .iter()
            .position(|b| b.load == load)
            .map(|k| bem[k].clone())
            .ok_or_else(|| ScenarioError::Invalid(format!("missing BEM load {load} N")))?;
        let model_approach = solve(
            &problem,
            tyreroad_multipoint::Control::Load(load),
            &solver_options,
        )
        .map_or(f64::NAN, |s| s.approach);
        loads.push(ComparedLoad {
            load,
            bem: b,
            two_scale: ts,
            model_approach,
        });
    }
    Ok(BemComparison {
        grid,
        setup_seconds,
        two_scale_seconds,
        loads,
    })
}

/// Max and mean of `|a − b| / b` over the entries with `b > 0`, and the
/// index of the max.
pub fn differences(a: &[f64], b: &[f64]) -> (f64, f64, usize) {
    let (mut max, mut sum, mut count, mut arg) = (0.0f64, 0.0, 0usize, 0);
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        if *y > 0.0 {
            let d = (x - y).abs() / y;
            if d > max {
                max = d;
                arg = k;
            }
            sum += d;
            count += 1;
        }
    }
    (max, sum / count.max(1) as f64, arg)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_are_relative_to_the_reference() {
        let (max, mean, arg) = differences(&[1.1, 2.0, 5.0], &[1.0, 2.0, 0.0]);
        assert!((max - 0.1).abs() < 1e-12);
        assert!((mean - 0.05).abs() < 1e-12);
        assert_eq!(arg, 0);
    }
}
