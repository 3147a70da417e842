//! A `.npy` texture road read and segmented by windows, for the ranks of a
//! distributed rolling run (docs/distributed.md, "Road windows").
//!
//! The rolling road's ids are block-major
//! ([`super::TextureRoad::rolling_order`]): by the block of
//! [`ID_BLOCK_COLUMNS`] columns holding the summit's grid point, then
//! higher grid summit first, ties by the point's whole-map index. So an
//! asperity's id is `start[b] + r`, `start[b]` the count of asperities in
//! the blocks before its block `b` and `r` its rank within `b`: what a
//! window of whole blocks computes from the per-block counts alone.
//!
//! [`NpyTextureRoad::open`] makes two streaming passes over the file, one
//! tile of columns (whole blocks) at a time: the first finds the map's
//! first point (its highest, ties by index: the segmentation always keeps
//! its basin) and the valid heights' mean; the second segments each tile
//! with a halo ([`crate::texture::segment_window()`]), doubling the halo
//! until every summit candidate of the tile is certified, and builds the
//! law of each asperity whose summit lies in the tile, exactly as
//! [`super::texture_road`] does on the whole map. A tile's asperities,
//! sorted by id, are folded into the road's digest
//! ([`rolling::RoadDigest`], radii in their own stream) and counted per
//! block, then dropped; the tile's valid heights also give the
//! reference plane `z_max` (the map's highest point, as
//! [`super::TextureRoad::top`]). What stays is 8 B per block
//! (about 125 B per metre at 1 mm spacing): no per-asperity state.
//!
//! [`NpyTextureRoad::window`] then builds the road window of an x-range:
//! the whole blocks its summits can lie in, certified the same way, their
//! laws, and their ids from the block counts. Every asperity of a window,
//! its position, height, law and summit radius, and the window's `z_max`
//! and digest, are the whole build's bit for bit (tested against
//! [`super::texture_road`] in [`super::TextureRoad::rolling_order`]).
//! [`NpyTextureRoad::summits`] streams the whole road's summits in id
//! order, a tile at a time, for a run's outputs.

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{
    CapDepth, ID_BLOCK_COLUMNS, TextureLaw, TextureRoadError, TextureRoadOptions, basin_depth,
    equivalent_radius,
};
use crate::contact_law::{LocalRule, Material, PotentialLaw};
use crate::multipoint::AsperitySet;
use crate::rolling;
use crate::texture::io::npy::sidecar_spacing;
use crate::texture::io::window::{NpyLayout, npy_layout, read_npy_window};
use crate::texture::{
    CapOptions, SegmentOptions, TextureError, WindowFrame, WindowSegmentation, asperity_cap,
    segment_window,
};

/// Columns per tile of the streaming passes (1 m at 1 mm spacing; whole
/// id blocks).
pub const TILE_COLUMNS: usize = 1024;

/// First halo (columns each side) of a window; doubled until certified.
const FIRST_HALO: usize = 32;

/// A texture road in a `.npy` file, known by what its windows need.
#[derive(Debug)]
pub struct NpyTextureRoad {
    path: PathBuf,
    spacing: (f64, f64),
    layout: NpyLayout,
    material: Material,
    opts: TextureRoadOptions,
    tile: usize,
    whole_first: (usize, usize),
    /// `block_start[b]`: asperities in the blocks before block `b` (the id
    /// of block `b`'s first); one more entry than blocks, the last the
    /// road's count.
    block_start: Vec<usize>,
    top: f64,
    digest: u64,
    /// Asperities the segmentation found (with or without a depth range).
    segmented: usize,
    /// Sq of the valid heights (m).
    rms: f64,
    /// Valid (finite) heights of the whole map.
    valid: usize,
}

/// An asperity's place in the rolling order (module documentation).
#[derive(Clone, Copy, Debug, PartialEq)]
struct Key {
    block: usize,
    /// Grid summit height (m).
    grid: f64,
    /// Whole-map index `j·nx + i` of the summit point.
    index: usize,
}

/// An asperity of a window with its law.
struct Built {
    key: Key,
    position: [f64; 2],
    height: f64,
    law: TextureLaw,
    radius: f64,
}

/// An asperity of a tile as the streaming passes keep it: what the digest
/// reads, its law probed (128 B), never the law itself.
struct Probed {
    key: Key,
    position: [f64; 2],
    height: f64,
    radius: f64,
    probed: [(f64, f64); 5],
}

/// The rolling order: by block, then higher grid summit, ties by index.
fn order(a: &Key, b: &Key) -> std::cmp::Ordering {
    a.block
        .cmp(&b.block)
        .then(b.grid.total_cmp(&a.grid))
        .then(a.index.cmp(&b.index))
}

/// The segmentation's order of points: higher first, ties by index.
fn point_order(a: &(f64, usize), b: &(f64, usize)) -> std::cmp::Ordering {
    b.0.total_cmp(&a.0).then(a.1.cmp(&b.1))
}

impl NpyTextureRoad {
    /// Opens the `.npy` road at `path` (spacing from its sidecar file,
    /// [`crate::texture::io::npy::sidecar_spacing`]) and makes the two
    /// streaming passes (module documentation).
    ///
    /// # Errors
    /// [`TextureRoadError::Texture`] for an unreadable file or a map
    /// without valid points, [`TextureRoadError::Law`] as
    /// [`super::texture_road`], [`TextureRoadError::NoAsperity`] if no
    /// asperity has a depth range, [`TextureRoadError::InvalidInput`] for
    /// the options [`super::texture_road`] refuses.
    pub fn open(
        path: &Path,
        material: Material,
        opts: &TextureRoadOptions,
    ) -> Result<Self, TextureRoadError> {
        Self::open_tiled(path, material, opts, TILE_COLUMNS)
    }

    /// [`NpyTextureRoad::open`] with passes over tiles of `tile` columns
    /// (rounded up to whole id blocks of [`ID_BLOCK_COLUMNS`]; the road
    /// does not depend on it, the memory of a pass does: `tile + 2·halo`
    /// columns).
    ///
    /// # Errors
    /// As [`NpyTextureRoad::open`].
    pub fn open_tiled(
        path: &Path,
        material: Material,
        opts: &TextureRoadOptions,
        tile: usize,
    ) -> Result<Self, TextureRoadError> {
        check_options(opts)?;
        let tile = tile.max(1).div_ceil(ID_BLOCK_COLUMNS) * ID_BLOCK_COLUMNS;
        let spacing = sidecar_spacing(path)?;
        let layout = npy_layout(path)?;
        let blocks = layout.nx.div_ceil(ID_BLOCK_COLUMNS);
        let mut road = Self {
            path: path.to_path_buf(),
            spacing,
            layout,
            material,
            opts: *opts,
            tile,
            whole_first: (0, 0),
            block_start: vec![0; blocks + 1],
            top: f64::NEG_INFINITY,
            digest: 0,
            segmented: 0,
            rms: f64::NAN,
            valid: 0,
        };
        let mean;
        (road.whole_first, mean) = road.first_point()?;
        let mut digest = rolling::RoadDigest::streamed();
        let mut counts = vec![0usize; blocks];
        let mut squares = (0.0, 0usize);
        let mut segmented = 0;
        let y_shift = -road.y_mid();
        let mut top = f64::NEG_INFINITY;
        road.for_each_tile(|win, map, own, built| {
            segmented += (0..win.segmentation.asperities().len())
                .filter(|&k| win.is_certified(k) && in_columns(win, k, own))
                .count();
            let skip = own.start - win.first_column();
            for j in 0..map.ny() {
                for i in skip..skip + own.len() {
                    if let Some(z) = map.get(i, j) {
                        squares.0 += (z - mean) * (z - mean);
                        squares.1 += 1;
                        top = top.max(z);
                    }
                }
            }
            // A tile holds whole blocks, in id order once sorted.
            for b in built {
                counts[b.key.block] += 1;
                let position = [b.position[0] + 0.0, b.position[1] + y_shift];
                digest.push_probed(position, b.height, &b.probed);
                digest.push_summit_radius(b.radius);
            }
        })?;
        road.top = top;
        if counts.iter().all(|&c| c == 0) {
            return Err(TextureRoadError::NoAsperity { segmented });
        }
        for (b, c) in counts.iter().enumerate() {
            road.block_start[b + 1] = road.block_start[b] + c;
        }
        road.digest = digest.finish();
        road.segmented = segmented;
        road.rms = (squares.0 / squares.1 as f64).sqrt();
        road.valid = squares.1;
        Ok(road)
    }
    /// Asperities of the whole road.
    pub fn len(&self) -> usize {
        self.block_start.last().copied().unwrap_or(0)
    }

    /// Never true: [`NpyTextureRoad::open`] refuses a road without
    /// asperities.
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// Asperities the whole map's segmentation finds (some without a depth
    /// range, so not on the road).
    pub fn segmented(&self) -> usize {
        self.segmented
    }

    /// The whole map's highest valid point `z_max` (m): the plane the
    /// approach is measured from, as [`super::TextureRoad::top`].
    pub fn top(&self) -> f64 {
        self.top
    }

    /// The whole road's checkpoint digest ([`rolling::Road::digest`]).
    pub fn digest(&self) -> u64 {
        self.digest
    }

    /// The map's points along x and y.
    pub fn size(&self) -> (usize, usize) {
        (self.layout.nx, self.layout.ny)
    }

    /// The map's grid spacing along x and y (m).
    pub fn spacing(&self) -> (f64, f64) {
        self.spacing
    }

    /// The map's points and how many of them hold a height (the others
    /// are missing: NaN in the file), counted over the tiles.
    pub fn valid_points(&self) -> (usize, usize) {
        (self.valid, self.layout.nx * self.layout.ny)
    }

    /// Sq of the map's valid heights (m): their root mean square about
    /// their mean, summed tile by tile (equal to
    /// [`crate::texture::HeightMap::rms`] of the whole map to rounding).
    pub fn rms(&self) -> f64 {
        self.rms
    }

    /// Ids of the asperities of each id block: `block_start()[b]..
    /// block_start()[b + 1]` are block `b`'s (module documentation).
    pub fn block_start(&self) -> &[usize] {
        &self.block_start
    }

    /// The window of the road holding every asperity whose summit `x` lies
    /// in `[x0, x1]` (m), by the whole road's ids, with its summit radii,
    /// `z_max` and digest: rolled on steps whose footprints lie in the
    /// range, it gives the whole road's records. It holds the whole id
    /// blocks those summits can lie in, so a few more.
    ///
    /// # Errors
    /// [`TextureRoadError::InvalidInput`] for a range off the map or
    /// holding no asperity; as [`NpyTextureRoad::open`] for the file.
    pub fn window(
        &self,
        [x0, x1]: [f64; 2],
    ) -> Result<rolling::Road<TextureLaw>, TextureRoadError> {
        let dx = self.spacing.0;
        let nx = self.layout.nx;
        // A summit lies within 1.5 cells of its grid point (the fit's
        // vertex, crate::texture::SummitFit).
        let from = ((x0 / dx).floor() - 2.0).max(0.0);
        let to = ((x1 / dx).ceil() + 3.0).min(nx as f64);
        if !(from < to) {
            return Err(TextureRoadError::InvalidInput(format!(
                "road window x ∈ [{x0}, {x1}] m is off the map's {nx} columns at {dx} m"
            )));
        }
        let (from, to) = (from as usize, to as usize);
        let own = (from / ID_BLOCK_COLUMNS * ID_BLOCK_COLUMNS)
            ..(to.div_ceil(ID_BLOCK_COLUMNS) * ID_BLOCK_COLUMNS).min(nx);
        let (win, map) = self.certified(&own)?;
        let mut built = Vec::new();
        self.build(&win, &map, &own, |b| built.push(b))?;
        built.sort_by(|a, b| order(&a.key, &b.key));
        if built.is_empty() {
            return Err(TextureRoadError::InvalidInput(format!(
                "road window x ∈ [{x0}, {x1}] m holds no asperity"
            )));
        }
        let ids = self.ids(built.iter().map(|b| b.key.block))?;
        let mut positions = Vec::with_capacity(built.len());
        let mut heights = Vec::with_capacity(built.len());
        let mut laws = Vec::with_capacity(built.len());
        let mut radii = Vec::with_capacity(built.len());
        for b in built {
            positions.push(b.position);
            heights.push(b.height);
            laws.push(b.law);
            radii.push(b.radius);
        }
        let invalid =
            |e: &dyn std::fmt::Display| TextureRoadError::InvalidInput(format!("road window: {e}"));
        let set = AsperitySet::new(positions, heights, laws)
            .and_then(|s| s.translated([0.0, -self.y_mid()]))
            .map_err(|e| invalid(&e))?;
        rolling::Road::window_of(set, ids, self.len(), self.top, self.digest)
            .and_then(|r| r.window_with_summit_radii(radii))
            .map_err(|e| invalid(&e))
    }

    /// Every summit of the whole road in id order: `sink(id, position,
    /// height)` (m, in the road's frame, as [`rolling::Road::positions`]
    /// and [`rolling::Road::heights`] of the whole road), streamed a tile
    /// at a time (each tile's laws are built to know which asperities the
    /// road keeps, then dropped: the time of the open pass, the memory of
    /// a tile). Callable any number of times.
    ///
    /// # Errors
    /// As [`NpyTextureRoad::open`] for the file;
    /// [`TextureRoadError::InvalidInput`] if the file changed since it was
    /// opened (a block's count differs).
    pub fn summits(
        &self,
        mut sink: impl FnMut(usize, [f64; 2], f64),
    ) -> Result<(), TextureRoadError> {
        let y_shift = -self.y_mid();
        let mut failed = None;
        self.for_each_tile(|_, _, _, built| {
            if failed.is_some() {
                return;
            }
            match self.ids(built.iter().map(|b| b.key.block)) {
                Ok(ids) => {
                    for (id, b) in ids.into_iter().zip(built) {
                        sink(id, [b.position[0] + 0.0, b.position[1] + y_shift], b.height);
                    }
                }
                Err(e) => failed = Some(e),
            }
        })?;
        failed.map_or(Ok(()), Err)
    }

    /// The ids of asperities of whole blocks sorted in id order, given
    /// their blocks: `block_start[b]` plus the rank within the block.
    fn ids(&self, blocks: impl Iterator<Item = usize>) -> Result<Vec<usize>, TextureRoadError> {
        let mut ids = Vec::new();
        let mut current: Option<(usize, usize)> = None;
        let close = |block: usize, rank: usize| -> Result<(), TextureRoadError> {
            let expected = self.block_start[block + 1] - self.block_start[block];
            if rank == expected {
                Ok(())
            } else {
                Err(TextureRoadError::InvalidInput(format!(
                    "{}: id block {block} holds {rank} asperities, {expected} when it was \
                     opened (the file changed?)",
                    self.path.display()
                )))
            }
        };
        for block in blocks {
            let rank = match current {
                Some((b, r)) if b == block => r,
                Some((b, r)) => {
                    close(b, r)?;
                    0
                }
                None => 0,
            };
            if block + 1 >= self.block_start.len() {
                return Err(TextureRoadError::InvalidInput(format!(
                    "{}: id block {block} is off the map (the file changed?)",
                    self.path.display()
                )));
            }
            ids.push(self.block_start[block] + rank);
            current = Some((block, rank + 1));
        }
        if let Some((b, r)) = current {
            close(b, r)?;
        }
        Ok(ids)
    }

    /// Each tile of the map in turn (whole id blocks): `f(window, map,
    /// own columns, the asperities whose summit lies in them, in id
    /// order)`. Each law is probed and dropped as it is built: a tile's
    /// laws are never held at once.
    fn for_each_tile(
        &self,
        mut f: impl FnMut(&WindowSegmentation, &crate::texture::HeightMap, &Range<usize>, Vec<Probed>),
    ) -> Result<(), TextureRoadError> {
        let nx = self.layout.nx;
        for t0 in (0..nx).step_by(self.tile) {
            let own = t0..(t0 + self.tile).min(nx);
            let (win, map) = self.certified(&own)?;
            let mut built = Vec::new();
            self.build(&win, &map, &own, |b| {
                built.push(Probed {
                    key: b.key,
                    position: b.position,
                    height: b.height,
                    radius: b.radius,
                    probed: rolling::RoadDigest::probe(&b.law),
                });
            })?;
            built.sort_by(|a, b| order(&a.key, &b.key));
            f(&win, &map, &own, built);
        }
        Ok(())
    }

    /// The map's mid-width (m): the road's y is centred on it.
    fn y_mid(&self) -> f64 {
        0.5 * (self.layout.ny - 1) as f64 * self.spacing.1
    }

    fn read(&self, columns: Range<usize>) -> Result<crate::texture::HeightMap, TextureError> {
        let (dx, dy) = self.spacing;
        Ok(read_npy_window(&self.path, dx, dy, columns)?.map)
    }

    /// The map's first point in the segmentation's order (highest valid
    /// point, ties by the lowest `j·nx + i`) and the valid heights' mean
    /// (m), tile by tile.
    fn first_point(&self) -> Result<((usize, usize), f64), TextureRoadError> {
        let nx = self.layout.nx;
        let mut best: Option<(f64, usize)> = None;
        let (mut sum, mut count) = (0.0, 0usize);
        for t0 in (0..nx).step_by(self.tile) {
            let map = self.read(t0..(t0 + self.tile).min(nx))?;
            for j in 0..map.ny() {
                for i in 0..map.nx() {
                    let Some(z) = map.get(i, j) else { continue };
                    sum += z;
                    count += 1;
                    let key = (z, j * nx + i + t0);
                    if best.is_none_or(|b| point_order(&key, &b).is_lt()) {
                        best = Some(key);
                    }
                }
            }
        }
        let (_, k) = best.ok_or_else(|| {
            TextureError::NotEnoughData(format!(
                "{}: the map has no valid point",
                self.path.display()
            ))
        })?;
        Ok(((k % nx, k / nx), sum / count as f64))
    }

    /// A window certifying the columns `own`: read with a halo, doubled
    /// until every summit candidate in `own` is certified (at worst the
    /// whole map, which certifies itself).
    fn certified(
        &self,
        own: &Range<usize>,
    ) -> Result<(WindowSegmentation, crate::texture::HeightMap), TextureRoadError> {
        let nx = self.layout.nx;
        let seg_opts = SegmentOptions {
            min_prominence: self.opts.min_prominence,
            min_area: self.opts.min_area,
        };
        let mut halo = FIRST_HALO;
        loop {
            let cols = own.start.saturating_sub(halo)..(own.end + halo).min(nx);
            let map = self.read(cols.clone())?;
            let frame = WindowFrame {
                first_column: cols.start,
                whole_nx: nx,
                whole_first: self.whole_first,
            };
            let win = segment_window(&map, frame, &seg_opts)?;
            if win.certifies(own.clone()) || cols.len() == nx {
                return Ok((win, map));
            }
            halo *= 2;
        }
    }

    /// The laws of the certified asperities of `win` whose summit point
    /// lies in the columns `own`, as [`super::texture_road`] builds them,
    /// each given to `sink` as it is built.
    fn build(
        &self,
        win: &WindowSegmentation,
        map: &crate::texture::HeightMap,
        own: &Range<usize>,
        mut sink: impl FnMut(Built),
    ) -> Result<(), TextureRoadError> {
        let seg = &win.segmentation;
        for (k, a) in seg.asperities().iter().enumerate() {
            if !(win.is_certified(k) && in_columns(win, k, own)) {
                continue;
            }
            let max_depth = match self.opts.depth {
                CapDepth::BasinBottom => basin_depth(a),
                CapDepth::GridCapRange => None,
                CapDepth::Fixed(d) => Some(d),
            };
            let cap = CapOptions {
                nodes: self.opts.nodes,
                max_depth,
            };
            // Dropped as by the whole build (super's module invariants).
            let Ok(table) = asperity_cap(map, seg, k, &cap) else {
                continue;
            };
            let index = win.whole_index(k).unwrap_or(usize::MAX);
            let law = PotentialLaw::new(
                Arc::new(table),
                self.material,
                self.opts.constant,
                LocalRule::HalfSection,
            )
            .map_err(|source| TextureRoadError::Law { index, source })?;
            let (i, j) = a.summit_cell;
            let grid = map.get(i, j).unwrap_or(f64::NAN);
            let radius = equivalent_radius(a, &law);
            sink(Built {
                key: Key {
                    block: (i + win.first_column()) / ID_BLOCK_COLUMNS,
                    grid,
                    index,
                },
                position: a.summit,
                height: a.summit_height,
                law,
                radius,
            });
        }
        Ok(())
    }
}

/// Whether asperity `k`'s summit point lies in the whole-map columns `own`.
fn in_columns(win: &WindowSegmentation, k: usize, own: &Range<usize>) -> bool {
    win.segmentation
        .asperities()
        .get(k)
        .is_some_and(|a| own.contains(&(a.summit_cell.0 + win.first_column())))
}

/// What [`super::texture_road`] refuses.
fn check_options(opts: &TextureRoadOptions) -> Result<(), TextureRoadError> {
    if let CapDepth::Fixed(d) = opts.depth
        && !(d.is_finite() && d > 0.0)
    {
        return Err(TextureRoadError::InvalidInput(format!(
            "fixed cap depth must be finite and > 0, got {d} m"
        )));
    }
    if opts.nodes < 4 {
        return Err(TextureRoadError::InvalidInput(format!(
            "cap tables need at least 4 nodes, got {}",
            opts.nodes
        )));
    }
    // A window's basins are certified against the whole map's; their
    // pieces would need the same certificate, which is not built yet.
    if let Some(width) = opts.max_cap_width {
        return Err(TextureRoadError::InvalidInput(format!(
            "max_cap_width ({:.3} mm) splits wide tops on a whole map only, \
             not on a road read in windows",
            width * 1e3
        )));
    }
    Ok(())
}
