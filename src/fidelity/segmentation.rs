//! Segmentation invariance (issue 15, item 5): the same texture split into
//! asperities two ways (for example `min_prominence` doubled) and solved by
//! one rung; how far the outputs move.
//!
//! Per load `W`, with `a` the first segmentation and `b` the second:
//! approach `(δ_b − δ_a)/δ_a` (both from the map's highest grid point),
//! total contact area `(A_b − A_a)/A_a` (the rung's own area: the two-scale
//! rebuild for Wilke laws, the tables' for calibrated ones) and the load
//! moved between blocks `½ Σ |F_b − F_a| / W` of the forces as fields
//! ([`super::compare::field_blocks`]). A segmentation-free model would give
//! zeros; docs/validation.md holds the measured table and the 1 % target.

use crate::contact_law::{ContactLaw, Material};
use crate::multipoint::{Control, Problem, Solution, SolverOptions, solve};
use crate::texture::HeightMap;
use crate::texture_road::{TextureRoad, TextureRoadOptions, texture_road};
use crate::two_scale::{TwoScaleOptions, two_scale_solution};

use super::compare::{APPROACH_MARGIN, BLOCKS, field_blocks, wrong_load};
use super::coupling::{FieldCouplingOptions, solve_field_coupled};
use super::{Calibrator, Coupling, Fidelity, FidelityError, LawSource, calibrated_set};

/// One load solved on both segmentations.
#[derive(Clone, Debug, PartialEq)]
pub struct SegmentationRow {
    /// Load (N).
    pub load: f64,
    /// Asperities kept by each segmentation.
    pub asperities: [usize; 2],
    /// Approach from the highest grid point (m), per segmentation.
    pub approach: [f64; 2],
    /// Total contact area (m²), per segmentation.
    pub area: [f64; 2],
    /// Load on a different block of each size of [`BLOCKS`] between the
    /// two (fraction of W).
    pub block_moved: [f64; 2],
}

impl SegmentationRow {
    /// `(δ_b − δ_a)/δ_a`.
    pub fn approach_change(&self) -> f64 {
        (self.approach[1] - self.approach[0]) / self.approach[0]
    }

    /// `(A_b − A_a)/A_a`.
    pub fn area_change(&self) -> f64 {
        (self.area[1] - self.area[0]) / self.area[0]
    }
}

/// One segmentation's outputs at each load: approach, area, field blocks.
type Outputs = Vec<(f64, f64, [Vec<f64>; 2])>;

/// Solves `fidelity` on `map` under both segmentations at each of `loads`
/// and compares the outputs (module docs). Calibrated laws cover
/// [`APPROACH_MARGIN`] times the Wilke model's largest approach, as a
/// scenario run does.
///
/// # Errors
/// A texture that cannot be segmented, a failed calibration, solve or
/// two-scale rebuild, or a non-positive load.
#[allow(clippy::too_many_arguments)]
pub fn segmentation_spread(
    map: &HeightMap,
    material: Material,
    loads: &[f64],
    segmentations: [&TextureRoadOptions; 2],
    fidelity: Fidelity,
    solver: &SolverOptions,
    rebuild: &TwoScaleOptions,
    calibrator: &Calibrator,
) -> Result<Vec<SegmentationRow>, FidelityError> {
    if let Some(&w) = loads.iter().find(|w| !(w.is_finite() && **w > 0.0)) {
        return Err(FidelityError::invalid("load", w, "finite and > 0 N"));
    }
    let grid_top = map
        .filled()
        .map_err(crate::texture_road::TextureRoadError::from)?
        .heights()
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let rung = fidelity.rung(solver)?;
    let mut outputs = Vec::new();
    let mut counts = [0; 2];
    for (k, options) in segmentations.into_iter().enumerate() {
        let road = texture_road(map, material, options)?;
        counts[k] = road.len();
        let wilke = Problem::from_set(road.set.clone(), material)?;
        let out = match rung.laws {
            LawSource::Potential => {
                let solve_one = |w| Ok(solve(&wilke, Control::Load(w), &rung.solver)?);
                outputs_of(
                    &wilke, &road, map, grid_top, loads, &solve_one, rebuild, true,
                )?
            }
            LawSource::Calibrated => {
                let top_load = loads.iter().copied().fold(0.0, f64::max);
                let deepest = solve(&wilke, Control::Load(top_load), &rung.solver)?.approach;
                let set = calibrated_set(&road, map, APPROACH_MARGIN * deepest, calibrator)?;
                let problem = Problem::from_set(set, material)?;
                let solve_one = |w| match rung.coupling {
                    Coupling::Solver => Ok(super::solve_calibrated(
                        &problem,
                        Control::Load(w),
                        &rung.solver,
                        None,
                    )?),
                    Coupling::Fields => Ok(solve_field_coupled(
                        &problem,
                        Control::Load(w),
                        &rung.solver,
                        &FieldCouplingOptions::default(),
                        None,
                    )?
                    .solution),
                };
                outputs_of(
                    &problem, &road, map, grid_top, loads, &solve_one, rebuild, false,
                )?
            }
        };
        outputs.push(out);
    }
    Ok(loads
        .iter()
        .zip(outputs[0].iter().zip(&outputs[1]))
        .map(|(&load, (a, b))| SegmentationRow {
            load,
            asperities: counts,
            approach: [a.0, b.0],
            area: [a.1, b.1],
            block_moved: [0, 1].map(|k| wrong_load(&b.2[k], &a.2[k], load)),
        })
        .collect())
}

/// Approach from the grid top, area (two-scale when `two_scale_area`, else
/// the laws' local contacts) and field blocks of `problem` at each load.
#[allow(clippy::too_many_arguments)]
fn outputs_of<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    road: &TextureRoad,
    map: &HeightMap,
    grid_top: f64,
    loads: &[f64],
    solve_one: &dyn Fn(f64) -> Result<Solution, FidelityError>,
    rebuild: &TwoScaleOptions,
    two_scale_area: bool,
) -> Result<Outputs, FidelityError> {
    let shapes = road.local_shapes(&std::sync::Arc::new(map.clone()))?;
    let summit_above_grid = road.set.top() - grid_top;
    loads
        .iter()
        .map(|&w| {
            let s = solve_one(w)?;
            let two = two_scale_solution(problem, &s, &shapes, rebuild)
                .map_err(|e| FidelityError::invalid("two-scale rebuild", e, "a rebuild"))?;
            let area = if two_scale_area {
                two.local.iter().map(|f| f.contact_area).sum()
            } else {
                s.local_contacts(problem).iter().map(|c| c.area()).sum()
            };
            let blocks = [0, 1].map(|k| field_blocks(&two, map, BLOCKS[k]));
            Ok((s.approach - summit_above_grid, area, blocks))
        })
        .collect()
}
