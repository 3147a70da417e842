//! Calibrated laws for the asperities of a segmented texture.

use rayon::prelude::*;

use super::under_tread::CapShape;
use super::{CalibratedLaw, Calibrator, CapPatch, FidelityError};
use crate::multipoint::AsperitySet;
use crate::texture::{Asperity, HeightMap};
use crate::texture_road::TextureRoad;

/// Cells kept around the cells that can touch: the contact never reaches
/// the window's border inside the depth range, so the patch holds it whole.
const MARGIN_CELLS: usize = 3;

/// The patch of asperity `a` for depths up to `max_depth` (m, from its
/// summit): the bounding box of the basin's cells within `max_depth` of the
/// summit, widened by a margin; the basin's own heights where they are
/// within `max_depth` of the summit, a floor below any reachable depth
/// elsewhere (deeper cells, neighbouring basins, invalid points), so the
/// solve sees this cap alone.
///
/// # Errors
/// [`FidelityError::InvalidInput`] if `max_depth` is not finite and > 0 or
/// the asperity has no valid cell within it.
pub fn cap_patch(map: &HeightMap, a: &Asperity, max_depth: f64) -> Result<CapPatch, FidelityError> {
    if !(max_depth.is_finite() && max_depth > 0.0) {
        return Err(FidelityError::invalid(
            "calibration depth",
            max_depth,
            "finite and > 0 m",
        ));
    }
    let (nx, ny) = (map.nx(), map.ny());
    let reach = a.summit_height - max_depth;
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    for &c in &a.cells {
        if map.valid()[c] && map.heights()[c] >= reach {
            let (i, j) = (c % nx, c / nx);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        }
    }
    if i0 == usize::MAX {
        return Err(FidelityError::invalid(
            "asperity",
            format!("summit at {:?}", a.summit),
            "a valid cell within the calibration depth",
        ));
    }
    let (i0, j0) = (
        i0.saturating_sub(MARGIN_CELLS),
        j0.saturating_sub(MARGIN_CELLS),
    );
    let (i1, j1) = (
        (i1 + MARGIN_CELLS).min(nx - 1),
        (j1 + MARGIN_CELLS).min(ny - 1),
    );
    let (pnx, pny) = ((i1 - i0 + 1).max(3), (j1 - j0 + 1).max(3));
    let floor = -(1.5 * max_depth + map.dx().max(map.dy()));
    let mut inside = vec![false; nx * ny];
    for &c in &a.cells {
        inside[c] = map.valid()[c];
    }
    let heights = (0..pnx * pny)
        .map(|k| {
            let (i, j) = (i0 + k % pnx, j0 + k / pnx);
            if i >= nx || j >= ny {
                return floor;
            }
            let c = map.index(i, j);
            let z = map.heights()[c] - a.summit_height;
            // A cell deeper than the range can never touch within it: the
            // floor there changes no solve, and keeps equal caps equal
            // whatever the segmentation did with the ground around them.
            if inside[c] && z >= -max_depth {
                z.min(0.0)
            } else {
                floor
            }
        })
        .collect();
    Ok(CapPatch {
        nx: pnx,
        ny: pny,
        dx: map.dx(),
        dy: map.dy(),
        heights,
        origin: [
            i0 as f64 * map.dx() - a.summit[0],
            j0 as f64 * map.dy() - a.summit[1],
        ],
    })
}

/// The road's asperities with calibrated laws (same positions, heights and
/// order as `road.set`), for approaches up to `max_approach` (m, from the
/// highest summit): asperity `i` is tabulated to
/// `max(max_approach − (top − z_i), max_approach / 10)`, the depth it
/// reaches at that approach (with a floor so that low asperities still get
/// a range), and at least twice the height of its fitted summit above its
/// highest cell (so that the range holds a cell). Caps are calibrated in
/// parallel on rayon's current pool.
///
/// # Errors
/// [`FidelityError::InvalidInput`] if `map` is not the segmented map or
/// `max_approach` is not finite and > 0; the first calibration error.
pub fn calibrated_set(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
) -> Result<AsperitySet<CalibratedLaw>, FidelityError> {
    let all: Vec<usize> = (0..road.len()).collect();
    let laws = calibrated_laws(
        road,
        map,
        max_approach,
        calibrator,
        &all,
        &[],
        &CapShape::Flat,
    )?
    .into_iter()
    .map(|(law, _)| law)
    .collect();
    AsperitySet::new(
        road.set.positions().to_vec(),
        road.set.heights().to_vec(),
        laws,
    )
    .map_err(FidelityError::Solve)
}

/// How far (m) `a`'s summit stands above its highest valid cell (0 for a
/// summit on a cell, or when no cell is valid: `cap_patch` says so).
fn top_cell_offset(map: &HeightMap, a: &Asperity) -> f64 {
    let highest = a
        .cells
        .iter()
        .filter(|&&c| map.valid()[c])
        .map(|&c| map.heights()[c])
        .fold(f64::NEG_INFINITY, f64::max);
    if highest.is_finite() {
        (a.summit_height - highest).max(0.0)
    } else {
        0.0
    }
}

/// The calibrated laws of the road's asperities `indices` (indices into
/// `road.set`), tabulated as in [`calibrated_set`], in parallel on rayon's
/// current pool, each cap under `shape` (with how far its asperity is
/// lifted, [`super::under_tread`]). `lifts` (m, one per index, or empty for
/// none) is how far the tread's profile at least keeps each asperity from
/// the approach (a rolling path: [`super::rolling::profile_lifts`];
/// missing entries are no lift); a
/// lifted asperity can only be pressed `max_approach − (top − z_i) −
/// lift_i` deep, so its table stops there (with the same floor) instead of
/// paying for depths the run cannot reach.
///
/// # Errors
/// As [`calibrated_set`]; [`FidelityError::InvalidInput`] for an index out
/// of the road.
pub(crate) fn calibrated_laws(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
    indices: &[usize],
    lifts: &[f64],
    shape: &CapShape,
) -> Result<Vec<(CalibratedLaw, f64)>, FidelityError> {
    if road.segmentation.size() != (map.nx(), map.ny()) {
        return Err(FidelityError::invalid(
            "height map",
            format!("{} × {}", map.nx(), map.ny()),
            format!("the segmented size {:?}", road.segmentation.size()),
        ));
    }
    if !(max_approach.is_finite() && max_approach > 0.0) {
        return Err(FidelityError::invalid(
            "largest approach",
            max_approach,
            "finite and > 0 m",
        ));
    }
    let top = road.set.top();
    indices
        .par_iter()
        .enumerate()
        .map(|(n, &i)| {
            let (Some(&k), Some(&z)) = (road.asperity_index.get(i), road.set.heights().get(i))
            else {
                return Err(FidelityError::invalid(
                    "asperity index",
                    i,
                    format!("below the road's {} asperities", road.len()),
                ));
            };
            let a = &road.segmentation.asperities()[k];
            // A missing or non-positive lift is no lift: a deeper table,
            // never a shorter one.
            let lift = lifts.get(n).copied().filter(|l| *l > 0.0).unwrap_or(0.0);
            // A fitted summit may stand above every cell of a flat or
            // faceted top: the range must reach the highest cell (and as
            // far past it as the summit stands above it), or the cap has
            // no cell to calibrate.
            let depth = (max_approach - (top - z) - lift)
                .max(0.1 * max_approach)
                .max(2.0 * top_cell_offset(map, a));
            let shaped = shape.patch(map, a, i, depth)?;
            let patch = shaped.patch;
            // A cap raised to touch where its shape says is pressed deeper
            // by as much; the top cell may lie below a refined summit, and
            // the table must reach past it.
            let depth = (depth + shaped.lift).max(2.0 * patch.summit_offset());
            Ok((calibrator.law(&patch, depth)?, shaped.lift))
        })
        .collect()
}
