//! Wide tops split into tiles: one asperity per piece of a plateau.
//!
//! The multipoint model puts one force at one point on each asperity. That
//! is right for a rounded chipping, whose contact grows from its summit, and
//! wrong for a flat top tens of millimetres wide (a ground-flat plateau of a
//! porous asphalt joins several chippings into one basin, 20–40 mm across):
//! a tyre whose profile drops by millimetres across it touches part of it,
//! and a sensor edge through it takes part of its load. [`split_wide_tops`]
//! cuts such a basin into pieces no wider than `max_width`, each a basin of
//! its own (its cells, its highest point, its cap), so the model sees the
//! plateau as a patch of neighbouring punches coupled through the
//! half-space.
//!
//! **Which basins.** A basin's *top* is its cells within `max_width / 64`
//! of its highest point; a top wider than `max_width` along x or y is split.
//! A sphere's top is that wide from a radius of `8 max_width` up: flat tops
//! are split, rounded chippings (radii of a few millimetres to a few
//! centimetres) are not. Cutting a dome is worse than keeping it whole: its
//! pieces' summits all lie on the cuts beside its apex, point forces a cell
//! apart (a chip seal split at 5 mm with a `/16` top, radii from 10 mm:
//! approach 0.8 → 6.7 %, sensors 5 → 72 % against the BEM).
//!
//! **The pieces.** The top's bounding box is cut into `⌈extent / max_width⌉`
//! equal tiles along each axis; every cell of the basin goes to its tile
//! (cells beyond the top's box to the nearest border tile), each tile's
//! cells are split into 8-connected pieces, and a piece smaller than a
//! quarter of a tile or without a cell of the top (flank or ground cut off
//! within its tile by another basin) joins its neighbouring piece with the
//! highest point.
//! A piece's summit is its highest cell; on exact ties (a ground-flat top)
//! the tied cells' centroid, so a flat tile's force acts at its middle, not
//! at its first cell in index order. The summit paraboloid is fitted as for
//! any basin ([`crate::SummitFit`]; a flat tile has none).
//!
//! **Invariants.** Every cell keeps belonging to exactly one asperity (the
//! pieces partition the basin); a basin that is not split is returned
//! unchanged (its cells, summit, fit and prominence); the pieces depend on
//! the basin's cells and heights only, not on where the map's window lies;
//! asperities stay ordered highest summit first; every piece of a split
//! basin names it ([`Asperity::plateau`], its index in the input), a basin
//! kept whole names none.

use std::collections::VecDeque;

use tyreroad_core::validate;

use crate::error::TextureError;
use crate::heightmap::HeightMap;
use crate::segment::{Asperity, Segmentation, UNLABELLED, fit_summit};

/// The depth below a basin's highest point (as a fraction of `max_width`)
/// within which its cells form its top.
const TOP_DEPTH_PER_WIDTH: f64 = 1.0 / 64.0;

/// The narrowest tile, in cells of the map.
const SMALLEST_WIDTH_IN_CELLS: f64 = 4.0;

/// A piece smaller than this fraction of a tile joins a neighbour.
const SMALLEST_PIECE: f64 = 0.25;

/// Split every basin of `seg` whose top is wider than `max_width` (m)
/// along x or y into tiles (module doc).
///
/// # Errors
/// `max_width` not finite and positive or below four cells of `map`, or a
/// segmentation that is not of `map` (another size).
pub fn split_wide_tops(
    seg: &Segmentation,
    map: &HeightMap,
    max_width: f64,
) -> Result<Segmentation, TextureError> {
    validate::positive("max_cap_width", max_width)?;
    let (nx, ny) = (map.nx(), map.ny());
    if seg.size() != (nx, ny) {
        return Err(TextureError::InvalidMap(format!(
            "a segmentation of {} x {} points split on a map of {nx} x {ny}",
            seg.size().0,
            seg.size().1
        )));
    }
    // A top is the cells within max_width/64 of a basin's highest point:
    // below a few cells that is the highest cell alone on any rounded top
    // (nothing split), and a flat one falls into tiles of a cell or two,
    // caps with no shape to tabulate.
    if max_width < SMALLEST_WIDTH_IN_CELLS * map.dx().max(map.dy()) {
        return Err(TextureError::InvalidParameter {
            name: "max_cap_width",
            value: max_width,
            requirement: "at least four cells of the map: narrower tiles are a cell or two wide, \
                          and a rounded top is never split",
        });
    }
    // Each asperity, and whether it is a new piece (to be fitted).
    let mut pieces: Vec<(Asperity, bool)> = Vec::with_capacity(seg.asperities().len());
    for (k, a) in seg.asperities().iter().enumerate() {
        match tiles_of(map, a, max_width) {
            Some(cells) if cells.len() > 1 => {
                pieces.extend(cells.into_iter().map(|c| {
                    let mut tile = piece(map, seg.origin, a.floor, c);
                    tile.plateau = Some(k);
                    (tile, true)
                }));
            }
            _ => pieces.push((a.clone(), false)),
        }
    }
    if pieces.iter().all(|(_, new)| !new) {
        return Ok(seg.clone());
    }
    // Highest summit point first, ties by index: the segmentation's order.
    let h = map.heights();
    pieces.sort_by(|(a, _), (b, _)| {
        let (ka, kb) = (cell_of(a, nx), cell_of(b, nx));
        h[kb].total_cmp(&h[ka]).then(ka.cmp(&kb))
    });
    let mut labels = vec![UNLABELLED; nx * ny];
    for (id, (a, _)) in pieces.iter().enumerate() {
        for &c in &a.cells {
            labels[c] = id as u32;
        }
    }
    let mut asperities = Vec::with_capacity(pieces.len());
    for (id, (mut a, new)) in pieces.into_iter().enumerate() {
        if new {
            a.fit = fit_summit(map, &labels, id as u32, a.summit_cell, seg.origin);
            if let Some(f) = a.fit {
                a.summit = [f.x, f.y];
                a.summit_height = f.z.max(a.summit_height);
            }
        }
        asperities.push(a);
    }
    Ok(Segmentation::from_parts(
        nx, ny, seg.origin, labels, asperities,
    ))
}

fn cell_of(a: &Asperity, nx: usize) -> usize {
    a.summit_cell.1 * nx + a.summit_cell.0
}

/// The cells of each piece of basin `a`, or `None` when its top is not
/// wider than `max_width`.
fn tiles_of(map: &HeightMap, a: &Asperity, max_width: f64) -> Option<Vec<Vec<usize>>> {
    let (nx, ny) = (map.nx(), map.ny());
    let (h, valid) = (map.heights(), map.valid());
    let (dx, dy) = (map.dx(), map.dy());
    let high = a
        .cells
        .iter()
        .filter(|&&c| valid[c])
        .map(|&c| h[c])
        .fold(f64::NEG_INFINITY, f64::max);
    let floor = high - TOP_DEPTH_PER_WIDTH * max_width;
    let (mut i0, mut i1, mut j0, mut j1) = (usize::MAX, 0, usize::MAX, 0);
    for &c in a.cells.iter().filter(|&&c| valid[c] && h[c] >= floor) {
        let (i, j) = (c % nx, c / nx);
        (i0, i1, j0, j1) = (i0.min(i), i1.max(i), j0.min(j), j1.max(j));
    }
    if i0 > i1 {
        return None;
    }
    let (ext_x, ext_y) = ((i1 - i0 + 1) as f64 * dx, (j1 - j0 + 1) as f64 * dy);
    if ext_x <= max_width && ext_y <= max_width {
        return None;
    }
    let (tx, ty) = (
        (ext_x / max_width).ceil() as usize,
        (ext_y / max_width).ceil() as usize,
    );
    let (wx, wy) = (ext_x / tx as f64, ext_y / ty as f64);
    let tile = |c: usize| {
        let (i, j) = (c % nx, c / nx);
        let u = ((i as f64 - i0 as f64 + 0.5) * dx / wx).floor();
        let v = ((j as f64 - j0 as f64 + 0.5) * dy / wy).floor();
        let u = u.clamp(0.0, (tx - 1) as f64) as usize;
        let v = v.clamp(0.0, (ty - 1) as f64) as usize;
        v * tx + u
    };
    // 8-connected pieces of each tile, within the basin.
    let mut piece_of = vec![usize::MAX; a.cells.len()];
    let index = |c: usize| a.cells.binary_search(&c).ok();
    let mut pieces: Vec<Vec<usize>> = Vec::new();
    let mut queue = VecDeque::new();
    for (start, &c0) in a.cells.iter().enumerate() {
        if piece_of[start] != usize::MAX {
            continue;
        }
        let p = pieces.len();
        let t = tile(c0);
        piece_of[start] = p;
        let mut cells = vec![c0];
        queue.push_back(c0);
        while let Some(c) = queue.pop_front() {
            for n in neighbours(c, nx, ny) {
                if tile(n) != t {
                    continue;
                }
                let Some(k) = index(n) else { continue };
                if piece_of[k] == usize::MAX {
                    piece_of[k] = p;
                    cells.push(n);
                    queue.push_back(n);
                }
            }
        }
        pieces.push(cells);
    }
    // Small pieces, and pieces without a cell of the top, join the
    // neighbouring piece with the highest point, smallest first, until
    // none is left or one piece remains.
    // Each piece's highest point, kept up to date through the merges.
    let mut peak: Vec<f64> = pieces
        .iter()
        .map(|cells| {
            cells
                .iter()
                .filter(|&&c| valid[c])
                .map(|&c| h[c])
                .fold(f64::NEG_INFINITY, f64::max)
        })
        .collect();
    let smallest = SMALLEST_PIECE * wx * wy / (dx * dy);
    let mut alive: Vec<bool> = vec![true; pieces.len()];
    loop {
        // A piece below the top (a stretch of flank or ground cut off by
        // another basin within its tile) is no piece of the top either.
        let candidate = (0..pieces.len())
            .filter(|&p| alive[p] && ((pieces[p].len() as f64) < smallest || peak[p] < floor))
            .min_by_key(|&p| (pieces[p].len(), p));
        let Some(p) = candidate else { break };
        if alive.iter().filter(|&&x| x).count() == 1 {
            break;
        }
        let mut best: Option<(f64, usize)> = None;
        for &c in &pieces[p] {
            for n in neighbours(c, nx, ny) {
                let Some(k) = index(n) else { continue };
                let q = piece_of[k];
                if q == p {
                    continue;
                }
                let hq = peak[q];
                if best.is_none_or(|(hb, b)| hq > hb || (hq == hb && q < b)) {
                    best = Some((hq, q));
                }
            }
        }
        // A piece with no neighbour in its basin (a basin made of
        // disconnected parts) stays a piece of its own.
        let Some((_, q)) = best else {
            alive[p] = false;
            continue;
        };
        let moved = std::mem::take(&mut pieces[p]);
        for &c in &moved {
            if let Some(k) = index(c) {
                piece_of[k] = q;
            }
        }
        pieces[q].extend(moved);
        peak[q] = peak[q].max(peak[p]);
        alive[p] = false;
    }
    let mut out: Vec<Vec<usize>> = pieces.into_iter().filter(|p| !p.is_empty()).collect();
    for cells in &mut out {
        cells.sort_unstable();
    }
    Some(out)
}

/// The 8 neighbours of cell `c` on the grid.
fn neighbours(c: usize, nx: usize, ny: usize) -> impl Iterator<Item = usize> {
    let (i, j) = ((c % nx) as i64, (c / nx) as i64);
    (-1i64..=1)
        .flat_map(move |dj| (-1i64..=1).map(move |di| (i + di, j + dj)))
        .filter(move |&(ii, jj)| {
            (ii, jj) != (i, j) && ii >= 0 && jj >= 0 && ii < nx as i64 && jj < ny as i64
        })
        .map(move |(ii, jj)| jj as usize * nx + ii as usize)
}

/// A piece's record: its highest cell (the tied cells' centroid on a flat
/// top), its relief as prominence, the split basin's `floor`, no fit yet.
fn piece(map: &HeightMap, origin: usize, floor: f64, cells: Vec<usize>) -> Asperity {
    let (nx, h, valid) = (map.nx(), map.heights(), map.valid());
    let (dx, dy) = (map.dx(), map.dy());
    let measured = || cells.iter().copied().filter(|&c| valid[c]);
    let high = measured().map(|c| h[c]).fold(f64::NEG_INFINITY, f64::max);
    let low = measured().map(|c| h[c]).fold(f64::INFINITY, f64::min);
    let tied: Vec<usize> = measured().filter(|&c| h[c] == high).collect();
    let n = tied.len().max(1) as f64;
    let (ci, cj) = tied.iter().fold((0.0, 0.0), |(u, v), &c| {
        (u + (c % nx) as f64 / n, v + (c / nx) as f64 / n)
    });
    let summit = tied
        .iter()
        .copied()
        .min_by(|&a, &b| {
            let d = |c: usize| ((c % nx) as f64 - ci).powi(2) + ((c / nx) as f64 - cj).powi(2);
            d(a).total_cmp(&d(b)).then(a.cmp(&b))
        })
        .unwrap_or(cells[0]);
    let (si, sj) = (summit % nx, summit / nx);
    let position = if tied.len() > 1 {
        [(ci + origin as f64) * dx, cj * dy]
    } else {
        [(si + origin) as f64 * dx, sj as f64 * dy]
    };
    Asperity {
        summit_cell: (si, sj),
        summit: position,
        summit_height: high,
        prominence: high - low,
        area: cells.len() as f64 * dx * dy,
        cells,
        floor,
        fit: None,
        plateau: None,
    }
}
