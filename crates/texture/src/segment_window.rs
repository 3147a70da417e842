//! Segmentation of a window of a larger map, certified against the whole
//! map's ([`segment`](crate::segment())) basin by basin.
//!
//! A rank of a distributed rolling run holds only a window of columns of a
//! long texture (docs/distributed.md, "Memory per rank"). The flooding reads
//! the whole map (points by decreasing height, basins merged by prominence
//! against the highest basin they meet), so a window's segmentation can
//! differ from the whole map's near its cut edges, and what differs can
//! travel inwards. [`segment_window`] floods the window and tracks, for
//! every basin, whether it is **certified**: the same points, summit, size
//! and kept flag as in the whole map at every step, so its asperity (cells,
//! fit, cap) is the whole map's bit for bit.
//!
//! # Certification (sound, not exact)
//!
//! Both floods visit the window's points in the same relative order. A
//! point in a cut column (next to columns not read) has unknown neighbours:
//! every basin it touches is **uncertain** (tainted). At an interior point
//! `k` whose neighbours' basins include an uncertain one, the whole map's
//! basins there are the certain ones plus unknown ones. Let `c` be the
//! highest certain basin at `k`. Every other certain basin is not the
//! highest in either flood (c is above it), so it is tested (kept or
//! merged) the same way in both, and a kept one gains nothing. `c` stays
//! certain only if it cannot receive a merge in either flood: it is kept,
//! no certain unkept basin at `k` fails its test, and for every uncertain
//! neighbour `p` the highest point of `p`'s connected part of the
//! superlevel set in the window comes before `c`. The last condition holds
//! because the only unkept basin of a superlevel component is the one of
//! its highest point (lower summits are tested as they meet it), and the
//! whole map's component of `p` contains the window's: an unkept unknown
//! basin at `k` is then above `c`, so `c` is not the highest there. A basin
//! that merges an uncertain one becomes uncertain. A basin certain at the
//! end is the whole map's; the highest basin and the islands are then
//! decided as in the whole map, given the whole map's first point.
//!
//! A window **certifies** a range of columns when every point of the range
//! that started a basin (a summit candidate: no higher neighbour) ends in a
//! certain basin: every whole-map asperity with its summit point there is
//! then a certain basin of the window. When it does not, the caller reads a
//! wider window (the halo doubled); the whole map certifies everything.

use std::ops::Range;

use crate::error::TextureError;
use crate::heightmap::HeightMap;
use crate::segment::{SegmentOptions, Segmentation, flood};
use crate::segment_taint::Taint;

/// Where a window lies in the whole map, and the whole map's first point.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct WindowFrame {
    /// The whole map's column at the window's column 0.
    pub first_column: usize,
    /// Columns of the whole map.
    pub whole_nx: usize,
    /// The whole map's first point `(i, j)` in the flood's order (the
    /// highest valid point, ties by the lowest `j·nx + i`): its basin is
    /// always kept.
    pub whole_first: (usize, usize),
}

/// A segmented window and which of its asperities are certified.
#[derive(Clone, Debug)]
pub struct WindowSegmentation {
    /// The window's segmentation: positions in the whole map's frame,
    /// indices (cells, labels, `summit_cell`) in the window's.
    pub segmentation: Segmentation,
    certified: Vec<bool>,
    /// Whole-map columns of the summit candidates left uncertain, sorted.
    uncertain_columns: Vec<usize>,
    frame: WindowFrame,
}

impl WindowSegmentation {
    /// Whether asperity `index` of the segmentation is the whole map's.
    pub fn is_certified(&self, index: usize) -> bool {
        self.certified.get(index).copied().unwrap_or(false)
    }

    /// Whether every whole-map asperity whose summit point lies in the
    /// whole-map columns `columns` is a certified asperity of the window.
    pub fn certifies(&self, columns: Range<usize>) -> bool {
        let from = self
            .uncertain_columns
            .partition_point(|&c| c < columns.start);
        self.uncertain_columns
            .get(from)
            .is_none_or(|&c| c >= columns.end)
    }

    /// The whole-map column of the window's column 0.
    pub fn first_column(&self) -> usize {
        self.frame.first_column
    }

    /// The whole map's index `j·nx + i` of asperity `index`'s summit point:
    /// with its grid height, the key of the whole map's asperity order
    /// (higher first, ties by this index).
    pub fn whole_index(&self, index: usize) -> Option<usize> {
        let a = self.segmentation.asperities().get(index)?;
        let (i, j) = a.summit_cell;
        Some(j * self.frame.whole_nx + i + self.frame.first_column)
    }
}

/// Segments `map`, the whole map's columns `frame.first_column ..
/// frame.first_column + map.nx()`, as [`segment`](crate::segment()) would
/// segment the whole map, certifying each basin (module documentation).
///
/// # Errors
/// As [`segment`](crate::segment()), and [`TextureError::InvalidMap`] if the
/// window does not fit in `frame.whole_nx` columns.
pub fn segment_window(
    map: &HeightMap,
    frame: WindowFrame,
    opts: &SegmentOptions,
) -> Result<WindowSegmentation, TextureError> {
    let (nx, ny) = (map.nx(), map.ny());
    let end = frame.first_column + nx;
    if end > frame.whole_nx {
        return Err(TextureError::InvalidMap(format!(
            "a window of columns {}..{end} in a map of {} columns",
            frame.first_column, frame.whole_nx
        )));
    }
    let mut taint = Taint::new(nx, ny, frame.first_column > 0, end < frame.whole_nx);
    let (fi, fj) = frame.whole_first;
    let highest = (fi >= frame.first_column && fi < end && fj < ny)
        .then(|| fj * nx + fi - frame.first_column);
    let segmentation = flood(
        map,
        opts,
        frame.first_column,
        Some(highest),
        Some(&mut taint),
    )?;
    let certified = segmentation
        .asperities()
        .iter()
        .map(|a| !taint.tainted[a.summit_cell.1 * nx + a.summit_cell.0])
        .collect();
    let mut uncertain_columns: Vec<usize> = taint
        .uncertain_starts
        .iter()
        .map(|&p| p % nx + frame.first_column)
        .collect();
    uncertain_columns.sort_unstable();
    uncertain_columns.dedup();
    Ok(WindowSegmentation {
        segmentation,
        certified,
        uncertain_columns,
        frame,
    })
}
