//! Tiles of one plateau calibrated as one body (issue 15).
//!
//! A wide flat top split into tiles (`[texture] max_cap_width`,
//! [`crate::texture::split_wide_tops`]) puts one force on each tile, so a
//! plateau's load sits where the plateau is pressed, not at one summit.
//! Calibrated alone, each tile is a flat punch of its own shape, and the
//! multipoint model couples the tiles of one plateau as separate punches
//! through the point kernel: their patches merge under a block, which that
//! coupling does not give (docs/validation.md, "The static texture tables
//! with wide flat tops split": area −5 %, approach +3 % against the BEM).
//!
//! Here the tiles of one plateau are calibrated together: one BEM sweep of
//! the whole plateau's cap ([`super::calibrate_joint`]), each tile's table
//! the force, area and field on its own cells, in its own depth. At a
//! common depth their sum is the whole plateau's table, and their mutual
//! coupling through the half-space is in the tables, so the multipoint
//! solve cancels the point kernel between tiles of one body
//! ([`body_correction`], `C_ij = −1/(π E* r_ij)`) and keeps it to every
//! other asperity. Pressed unevenly, each tile follows its share of the
//! level plateau's law at its own depth: exact for a uniform depth, but
//! blind to its neighbours' depths, so rolling runs (a tyre's crown across
//! the plateau) keep the tiles alone (docs/theory.md §3, "Tiles of one
//! body").
//!
//! Invariants: a road without split tops is calibrated exactly as before
//! (same tables, no correction); every tile of a body gets a table from
//! the same sweep; a body whose sweep fails is the set's error where a
//! failed cap is ([`super::calibrated_set`]), and where a cap keeps its
//! Wilke law instead ([`super::calibrated_set_or_wilke`], a user's run) its
//! tiles are calibrated alone, each with its own fallback.

use std::sync::Arc;

use super::texture::OnCapFailure;
use super::{CalibratedLaw, Calibrator, FidelityError, JointTile, cap_patch};
use crate::multipoint::{
    Clusters, Control, Interaction, PairCorrection, Problem, Solution, SolverOptions,
    solve_corrected, solve_from,
};
use crate::texture::{Asperity, HeightMap};
use crate::texture_road::TextureRoad;

/// The correction that cancels the point kernel between every two laws of
/// one body (`C_ij = −f / r_ij`, `f = 1/(π E*)`); empty when no two laws
/// share a body.
///
/// # Errors
/// None for a valid problem (the pairs are distinct and finite); the
/// `Result` is [`PairCorrection::new`]'s.
pub fn body_correction(problem: &Problem<CalibratedLaw>) -> Result<PairCorrection, FidelityError> {
    let factor = problem.material().boussinesq_factor();
    let positions = problem.positions();
    // Only laws of one body are paired: the cost is the sum of the
    // bodies' squared sizes, not the problem's.
    let mut members: Vec<(usize, usize)> = problem
        .laws()
        .iter()
        .enumerate()
        .filter_map(|(i, law)| law.body().map(|b| (b, i)))
        .collect();
    members.sort_unstable();
    let mut pairs = Vec::new();
    for body in members.chunk_by(|a, b| a.0 == b.0) {
        for (n, &(_, i)) in body.iter().enumerate() {
            for &(_, j) in &body[n + 1..] {
                let r =
                    (positions[i][0] - positions[j][0]).hypot(positions[i][1] - positions[j][1]);
                if r > 0.0 {
                    pairs.push((i, j, -factor / r));
                }
            }
        }
    }
    PairCorrection::new(problem.len(), pairs).map_err(FidelityError::Solve)
}

/// Solves a calibrated problem: as [`solve_from`] when no two laws share a
/// body, else with the point kernel cancelled within each body
/// ([`body_correction`]).
///
/// # Errors
/// [`FidelityError::Solve`] for a failed solve;
/// [`FidelityError::InvalidInput`] when tiles share a body and the options
/// ask for what a corrected solve does not do (an interaction other than
/// the point kernel, clusters always formed).
pub fn solve_calibrated(
    problem: &Problem<CalibratedLaw>,
    control: Control,
    solver: &SolverOptions,
    initial: Option<&Solution>,
) -> Result<Solution, FidelityError> {
    let correction = body_correction(problem)?;
    if correction.is_empty() {
        return Ok(solve_from(problem, control, solver, initial)?);
    }
    if solver.interaction != Interaction::Point || solver.clusters == Clusters::Always {
        return Err(FidelityError::invalid(
            "solver options",
            format!(
                "{:?} interaction, clusters {:?}",
                solver.interaction, solver.clusters
            ),
            "the point interaction without forced clusters on a road whose \
             plateaus are split into tiles (the calibrated or calibrated_fields rung)",
        ));
    }
    Ok(solve_corrected(
        problem,
        control,
        solver,
        initial,
        &correction,
    )?)
}

/// One body's tile laws, or why its sweep failed.
type BodyLaws = Result<Vec<CalibratedLaw>, FidelityError>;

/// The laws of the tiles among the road's asperities `indices`, calibrated
/// body by body (module docs): one entry per index, `None` for an asperity
/// that is no tile (or the only tile of its plateau among `indices`) and,
/// with [`OnCapFailure::WilkeLaw`], for the tiles of a body whose sweep
/// failed (to be calibrated alone, each with its own fallback). Bodies are
/// solved in parallel on rayon's current pool.
///
/// # Errors
/// With [`OnCapFailure::Abort`], the first body's failure; a disk cache
/// that cannot be written, always.
pub(super) fn body_laws(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
    indices: &[usize],
    on_failure: OnCapFailure,
) -> Result<Vec<Option<CalibratedLaw>>, FidelityError> {
    use rayon::prelude::*;
    let segmented = road.segmentation.asperities();
    let asperity = |i: usize| &segmented[road.asperity_index[i]];
    // Positions in `indices` grouped by plateau, in first-seen order.
    let mut bodies: Vec<(usize, Vec<usize>)> = Vec::new();
    for (n, &i) in indices.iter().enumerate() {
        if let Some(p) = asperity(i).plateau {
            match bodies.iter_mut().find(|(q, _)| *q == p) {
                Some((_, members)) => members.push(n),
                None => bodies.push((p, vec![n])),
            }
        }
    }
    bodies.retain(|(_, members)| members.len() > 1);
    let top = road.set.top();
    let solved: Vec<(Vec<usize>, BodyLaws)> = bodies
        .into_par_iter()
        .map(|(plateau, members)| {
            let tiles: Vec<usize> = members.iter().map(|&n| indices[n]).collect();
            let laws = one_body(road, map, max_approach, calibrator, &tiles, top)
                .map(|laws| laws.into_iter().map(|l| l.in_body(plateau)).collect());
            (members, laws)
        })
        .collect();
    let mut out = vec![None; indices.len()];
    for (members, laws) in solved {
        match laws {
            Ok(laws) => {
                for (n, law) in members.into_iter().zip(laws) {
                    out[n] = Some(law);
                }
            }
            Err(e @ FidelityError::Cache { .. }) => return Err(e),
            Err(e) if on_failure == OnCapFailure::Abort => return Err(e),
            // Its tiles are calibrated alone, each failing on its own.
            Err(_) => {}
        }
    }
    Ok(out)
}

/// The tiles `tiles` (road indices) of one plateau, calibrated by one sweep
/// of their union.
fn one_body(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
    tiles: &[usize],
    top: f64,
) -> Result<Vec<CalibratedLaw>, FidelityError> {
    let segmented = road.segmentation.asperities();
    let members: Vec<&Asperity> = tiles
        .iter()
        .map(|&i| &segmented[road.asperity_index[i]])
        .collect();
    let highest = members
        .iter()
        .copied()
        .max_by(|a, b| a.summit_height.total_cmp(&b.summit_height))
        .ok_or_else(|| FidelityError::invalid("body", 0, "at least one tile"))?;
    let mut body = highest.clone();
    body.cells = members
        .iter()
        .flat_map(|a| a.cells.iter().copied())
        .collect();
    body.cells.sort_unstable();
    // Deep enough for every tile's own range from its own summit.
    let depth = tiles
        .iter()
        .zip(&members)
        .map(|(&i, a)| {
            super::texture::table_depth(map, a, road.set.heights()[i], top, max_approach)
                + (body.summit_height - a.summit_height)
        })
        .fold(0.0, f64::max);
    let patch = cap_patch(map, &body, depth)?;
    let depth = depth.max(2.0 * patch.summit_offset());
    // The patch's cell (0, 0) on the map.
    let i0 = ((patch.origin[0] + body.summit[0]) / map.dx()).round() as i64;
    let j0 = ((patch.origin[1] + body.summit[1]) / map.dy()).round() as i64;
    let joint: Vec<JointTile> = members
        .iter()
        .map(|a| {
            let mut cells = vec![false; patch.nx * patch.ny];
            for &c in &a.cells {
                let (pi, pj) = ((c % map.nx()) as i64 - i0, (c / map.nx()) as i64 - j0);
                if pi >= 0 && pj >= 0 && (pi as usize) < patch.nx && (pj as usize) < patch.ny {
                    cells[pj as usize * patch.nx + pi as usize] = true;
                }
            }
            JointTile {
                cells,
                below: (body.summit_height - a.summit_height).max(0.0),
            }
        })
        .collect();
    let tables = calibrator.joint_tables(&patch, depth, &joint)?;
    Ok(tables
        .into_iter()
        .zip(&members)
        .map(|(table, a)| {
            // The patch's cell (0, 0) seen from the tile's summit.
            let origin = [
                patch.origin[0] + body.summit[0] - a.summit[0],
                patch.origin[1] + body.summit[1] - a.summit[1],
            ];
            CalibratedLaw::with_origin(Arc::new(table), origin)
        })
        .collect())
}
