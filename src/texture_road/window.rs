//! A `.npy` texture road read and segmented by windows, for the ranks of a
//! distributed rolling run (docs/distributed.md, "Memory per rank").
//!
//! [`NpyTextureRoad::open`] makes two streaming passes over the file, one
//! tile of columns at a time: the first finds the map's first point (its
//! highest, ties by index: the segmentation always keeps its basin); the
//! second segments each tile with a halo
//! ([`crate::texture::segment_window()`]), doubling the halo until every
//! summit candidate of the tile is certified, and builds the law of each
//! asperity whose summit lies in the tile, exactly as [`super::texture_road`]
//! does on the whole map. Of each asperity it keeps its order key (grid
//! summit height, whole-map index: the whole build's ids are this order),
//! and, until the pass ends, what the road's digest reads (position,
//! height, radius, the law's probes: 128 B); sorted by key, these give the
//! whole road's ids, highest summit `z_max` and [`rolling::RoadDigest`].
//! What stays is 16 B per asperity of the whole road.
//!
//! [`NpyTextureRoad::window`] then builds the road window of an x-range:
//! the columns its summits can lie in, certified the same way, their laws,
//! and their ids found among the keys by binary search. Every asperity of
//! a window, its position, height, law and summit radius, and the window's
//! `z_max` and digest, are the whole build's bit for bit (tested against
//! [`super::texture_road`]).

use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use super::{
    CapDepth, TextureLaw, TextureRoadError, TextureRoadOptions, basin_depth, equivalent_radius,
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

/// Columns per tile of the streaming passes (1 m at 1 mm spacing).
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
    whole_first: (usize, usize),
    /// The whole road's asperities in id order: (grid summit height,
    /// whole-map index of the summit point).
    keys: Vec<(f64, usize)>,
    top: f64,
    digest: u64,
    /// Asperities the segmentation found (with or without a depth range).
    segmented: usize,
}

/// One asperity as the digest reads it, with its order key.
struct Digested {
    key: (f64, usize),
    position: [f64; 2],
    height: f64,
    radius: f64,
    probed: [(f64, f64); 5],
}

/// An asperity of a window with its law.
struct Built {
    key: (f64, usize),
    position: [f64; 2],
    height: f64,
    law: TextureLaw,
    radius: f64,
}

/// The whole build's order: higher grid summit first, ties by index.
fn order(a: &(f64, usize), b: &(f64, usize)) -> std::cmp::Ordering {
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
    /// (at least 1; the road does not depend on it, the memory of a pass
    /// does: `tile + 2·halo` columns).
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
        let tile = tile.max(1);
        let spacing = sidecar_spacing(path)?;
        let layout = npy_layout(path)?;
        let mut road = Self {
            path: path.to_path_buf(),
            spacing,
            layout,
            material,
            opts: *opts,
            whole_first: (0, 0),
            keys: Vec::new(),
            top: f64::NEG_INFINITY,
            digest: 0,
            segmented: 0,
        };
        road.whole_first = road.first_point(tile)?;
        let y_shift = -road.y_mid();
        let mut all: Vec<Digested> = Vec::new();
        let mut segmented = 0;
        for t0 in (0..layout.nx).step_by(tile) {
            let own = t0..(t0 + tile).min(layout.nx);
            let (win, map) = road.certified(&own)?;
            segmented += (0..win.segmentation.asperities().len())
                .filter(|&k| win.is_certified(k) && in_columns(&win, k, &own))
                .count();
            // Each law is probed and dropped as it is built: a tile's laws
            // are never held at once.
            road.build(&win, &map, &own, |b| {
                all.push(Digested {
                    key: b.key,
                    position: [b.position[0] + 0.0, b.position[1] + y_shift],
                    height: b.height,
                    radius: b.radius,
                    probed: rolling::RoadDigest::probe(&b.law),
                });
            })?;
        }
        if all.is_empty() {
            return Err(TextureRoadError::NoAsperity { segmented });
        }
        all.sort_by(|a, b| order(&a.key, &b.key));
        let mut digest = rolling::RoadDigest::new(all.len());
        let mut top = f64::NEG_INFINITY;
        for a in &all {
            digest.push_probed(a.position, a.height, &a.probed);
            top = top.max(a.height);
        }
        let radii: Vec<f64> = all.iter().map(|a| a.radius).collect();
        digest.summit_radii(&radii);
        road.keys = all.iter().map(|a| a.key).collect();
        road.top = top;
        road.digest = digest.finish();
        road.segmented = segmented;
        Ok(road)
    }

    /// Asperities of the whole road.
    pub fn len(&self) -> usize {
        self.keys.len()
    }

    /// Never true: [`NpyTextureRoad::open`] refuses a road without
    /// asperities.
    pub fn is_empty(&self) -> bool {
        self.keys.is_empty()
    }

    /// Asperities the whole map's segmentation finds (some without a depth
    /// range, so not on the road).
    pub fn segmented(&self) -> usize {
        self.segmented
    }

    /// The whole road's highest summit `z_max` (m).
    pub fn top(&self) -> f64 {
        self.top
    }

    /// The whole road's checkpoint digest ([`rolling::Road::digest`]).
    pub fn digest(&self) -> u64 {
        self.digest
    }

    /// The window of the road holding every asperity whose summit `x` lies
    /// in `[x0, x1]` (m), by the whole road's ids, with its summit radii,
    /// `z_max` and digest: rolled on steps whose footprints lie in the
    /// range, it gives the whole road's records.
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
        let own = from as usize..to as usize;
        let (win, map) = self.certified(&own)?;
        let mut built = Vec::new();
        self.build(&win, &map, &own, |b| built.push(b))?;
        built.sort_by(|a, b| order(&a.key, &b.key));
        if built.is_empty() {
            return Err(TextureRoadError::InvalidInput(format!(
                "road window x ∈ [{x0}, {x1}] m holds no asperity"
            )));
        }
        let mut ids = Vec::with_capacity(built.len());
        for b in &built {
            let id = self
                .keys
                .binary_search_by(|k| order(k, &b.key))
                .map_err(|_| {
                    TextureRoadError::InvalidInput(format!(
                        "asperity at map point {} is not on the whole road",
                        b.key.1
                    ))
                })?;
            ids.push(id);
        }
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
        rolling::Road::window_of(set, ids, self.keys.len(), self.top, self.digest)
            .and_then(|r| r.window_with_summit_radii(radii))
            .map_err(|e| invalid(&e))
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
    /// point, ties by the lowest `j·nx + i`), tile by tile.
    fn first_point(&self, tile: usize) -> Result<(usize, usize), TextureRoadError> {
        let nx = self.layout.nx;
        let mut best: Option<(f64, usize)> = None;
        for t0 in (0..nx).step_by(tile) {
            let map = self.read(t0..(t0 + tile).min(nx))?;
            for j in 0..map.ny() {
                for i in 0..map.nx() {
                    let Some(z) = map.get(i, j) else { continue };
                    let key = (z, j * nx + i + t0);
                    if best.is_none_or(|b| order(&key, &b).is_lt()) {
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
        Ok((k % nx, k / nx))
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
                CapDepth::BasinBottom => basin_depth(map, a),
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
                key: (grid, index),
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
    Ok(())
}
