//! From a road texture to the multipoint model, and back to its real shapes.
//!
//! A measured or synthesised height map ([`crate::texture::HeightMap`]) is
//! split into asperity basins ([`crate::texture::segment()`]); each basin's
//! cap measures `Ω(δ)`, `Σ(δ)`, `Γ(δ)` are tabulated on the grid
//! ([`crate::texture::asperity_cap`], smooth at contact onset) and get the
//! interaction-potential law with the half-section local rule
//! ([`crate::contact_law::PotentialLaw`], `LocalRule::HalfSection`). The
//! result, an [`AsperitySet`], feeds [`crate::multipoint::Problem::from_set`] for a static
//! contact, or a rolling road.
//!
//! The way back, for the two-scale pressure map ([`crate::two_scale`]):
//! [`TextureRoad::local_shapes`] describes each asperity by the texture's own
//! surface restricted to its basin, so the local BEM solves see the real
//! (flat-topped, skewed, ridged) chipping, not the equivalent paraboloid.
//!
//! Like [`crate::two_scale`], this module is where the layers meet: the
//! texture crate knows nothing of laws, the laws nothing of textures.
//!
//! # Invariants
//! - Asperities keep the segmentation's order (highest summit first);
//!   [`TextureRoad::asperity_index`] maps each kept one back to the
//!   segmentation.
//! - An asperity without a depth range (a summit at the height of its
//!   basin's boundary, e.g. one point of a plateau) is dropped, never given a
//!   degenerate law.

use std::sync::Arc;

use crate::asperity::{CapGeometry, TabulatedCap};
use crate::contact_law::{C_SPHERE, LawError, LocalRule, Material, PotentialLaw};
use crate::multipoint::AsperitySet;
use crate::shared::{Par, map_at};
use crate::texture::{
    Asperity, CapOptions, HeightMap, SegmentOptions, Segmentation, TextureError, UNLABELLED,
    asperity_cap, segment, split_wide_tops,
};
use crate::two_scale::LocalShape;

mod past_caps;
pub mod window;

pub use past_caps::{PastCap, PastCapTally, PastShape, pressed_past_caps};

/// The contact law of one texture asperity.
pub type TextureLaw = PotentialLaw<Arc<TabulatedCap>>;

/// Errors of [`texture_road`].
#[derive(Debug, thiserror::Error)]
pub enum TextureRoadError {
    /// Segmentation or cap tabulation failed.
    #[error(transparent)]
    Texture(#[from] TextureError),
    /// A law could not be built from a cap.
    #[error("asperity {index}: {source}")]
    Law {
        /// Index in the segmentation.
        index: usize,
        /// The law's error.
        source: LawError,
    },
    /// No asperity has a depth range.
    #[error("the texture has no asperity with a depth range ({segmented} segmented)")]
    NoAsperity {
        /// Number of asperities the segmentation found.
        segmented: usize,
    },
    /// Invalid options or a map that does not match the segmentation.
    #[error("invalid input: {0}")]
    InvalidInput(String),
}

/// How deep each asperity's cap is tabulated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum CapDepth {
    /// Down to the lowest valid point of the basin (default). The cap is
    /// then the basin's own surface below its boundary, so an asperity cut
    /// by the map's edge (its summit on the edge, no closed boundary) still
    /// gets a depth range.
    BasinBottom,
    /// The grid cap's exact range: summit minus the highest boundary point.
    GridCapRange,
    /// A fixed depth (m) for every asperity.
    Fixed(f64),
}

/// How a texture is turned into asperities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRoadOptions {
    /// Smallest prominence (summit − key saddle) of an asperity (m).
    pub min_prominence: f64,
    /// Smallest basin area of an asperity (m²).
    pub min_area: f64,
    /// Shape constant `c` of the potential law (0.36 for smooth summits).
    pub constant: f64,
    /// Number of depths in each cap table.
    pub nodes: usize,
    /// Depth range of the tables.
    pub depth: CapDepth,
    /// Split every basin whose top is wider than this (m) into tiles no
    /// wider, one asperity each (`tyreroad_texture::split_wide_tops`: the
    /// ground-flat plateaus of a porous asphalt); `None` keeps the basins.
    pub max_cap_width: Option<f64>,
    /// Parallelism of the per-asperity cap tables and laws (each is its
    /// basin's own: the road does not depend on it).
    pub par: Par,
}

impl TextureRoadOptions {
    /// Options with the given thresholds, `c = 0.36`, 120 table nodes and
    /// caps down to the basin bottom.
    pub fn new(min_prominence: f64, min_area: f64) -> Self {
        Self {
            min_prominence,
            min_area,
            constant: C_SPHERE,
            nodes: CapOptions::default().nodes,
            depth: CapDepth::BasinBottom,
            max_cap_width: None,
            par: Par::Seq,
        }
    }
}

/// A texture ready for the multipoint model.
#[derive(Debug)]
pub struct TextureRoad {
    /// The kept asperities: summit positions `(x, y)` (m) in the map's frame
    /// (cell `(i, j)` at `(i·dx, j·dy)`), summit heights (m) and laws.
    pub set: AsperitySet<TextureLaw>,
    /// The segmentation of the height map.
    pub segmentation: Segmentation,
    /// For each kept asperity, its index in `segmentation.asperities()`.
    pub asperity_index: Vec<usize>,
    /// The map's highest valid point (m): the plane a rolling road on this
    /// texture measures its approach from
    /// ([`crate::rolling::Road::with_top`]), as the BEM does, whatever
    /// asperities a run keeps and however far a fitted summit vertex stands
    /// above its grid point.
    pub top: f64,
}

/// Segments `map` and builds one tabulated cap and law per asperity.
///
/// # Errors
/// [`TextureRoadError::Texture`] if the segmentation fails,
/// [`TextureRoadError::Law`] if a law cannot be built,
/// [`TextureRoadError::NoAsperity`] if no asperity has a depth range,
/// [`TextureRoadError::InvalidInput`] for a non-positive fixed depth or
/// fewer than 4 nodes.
pub fn texture_road(
    map: &HeightMap,
    material: Material,
    opts: &TextureRoadOptions,
) -> Result<TextureRoad, TextureRoadError> {
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
    let seg = segment(
        map,
        &SegmentOptions {
            min_prominence: opts.min_prominence,
            min_area: opts.min_area,
        },
    )?;
    let seg = match opts.max_cap_width {
        Some(width) => split_wide_tops(&seg, map, width)?,
        None => seg,
    };
    let n = seg.asperities().len();
    // Each basin's table and law (the ramp scan of a many-piece table is
    // the dear part), `None` for an asperity without a depth range: it is
    // dropped (module invariants).
    let law_of = |k: usize| -> Result<Option<TextureLaw>, TextureRoadError> {
        let max_depth = match opts.depth {
            CapDepth::BasinBottom => basin_depth(&seg.asperities()[k]),
            CapDepth::GridCapRange => None,
            CapDepth::Fixed(d) => Some(d),
        };
        let cap = CapOptions {
            nodes: opts.nodes,
            max_depth,
        };
        let Ok(table) = asperity_cap(map, &seg, k, &cap) else {
            return Ok(None);
        };
        PotentialLaw::new(
            Arc::new(table),
            material,
            opts.constant,
            LocalRule::HalfSection,
        )
        .map(Some)
        .map_err(|source| TextureRoadError::Law { index: k, source })
    };
    let built: Vec<Result<Option<TextureLaw>, TextureRoadError>> = map_at(opts.par, n, law_of);
    let mut positions = Vec::with_capacity(n);
    let mut heights = Vec::with_capacity(n);
    let mut laws = Vec::with_capacity(n);
    let mut asperity_index = Vec::with_capacity(n);
    for (k, (a, law)) in seg.asperities().iter().zip(built).enumerate() {
        let Some(law) = law? else {
            continue;
        };
        positions.push(a.summit);
        heights.push(a.summit_height);
        laws.push(law);
        asperity_index.push(k);
    }
    if laws.is_empty() {
        return Err(TextureRoadError::NoAsperity { segmented: n });
    }
    let set = AsperitySet::new(positions, heights, laws)
        .map_err(|e| TextureRoadError::InvalidInput(e.to_string()))?;
    // A map without a valid point has no asperity (refused above).
    let top = map.min_max().map_or(set.top(), |(_, hi)| hi);
    Ok(TextureRoad {
        set,
        segmentation: seg,
        asperity_index,
        top,
    })
}

/// Summit height minus the lowest valid point of the basin
/// ([`Asperity::floor`]: of the whole basin for a piece of a split top),
/// if positive.
pub(crate) fn basin_depth(a: &Asperity) -> Option<f64> {
    let d = a.summit_height - a.floor;
    (d.is_finite() && d > 0.0).then_some(d)
}

impl TextureRoad {
    /// Number of kept asperities.
    pub fn len(&self) -> usize {
        self.set.len()
    }

    /// Never true: [`texture_road`] refuses a texture without asperities.
    pub fn is_empty(&self) -> bool {
        self.set.is_empty()
    }

    /// The real shape of every kept asperity for [`crate::two_scale`]: the
    /// texture's surface, bilinearly interpolated, restricted to the
    /// asperity's basin, relative to its summit height (clamped to `≤ 0`).
    /// Outside the basin (and at invalid points) the shape drops to the
    /// basin's lowest point, so a local solve never touches a neighbour.
    /// The equivalent radius (which only sizes the local grid) is the larger
    /// of `√(r₁r₂)` of the summit paraboloid (when it fits) and the secant
    /// radius `Σ(δ)/(2πδ)` of the cap table at a quarter of its depth range.
    ///
    /// # Errors
    /// [`TextureRoadError::InvalidInput`] if `map` is not the map that was
    /// segmented (different size).
    pub fn local_shapes(&self, map: &Arc<HeightMap>) -> Result<Vec<LocalShape>, TextureRoadError> {
        if self.segmentation.size() != (map.nx(), map.ny()) {
            return Err(TextureRoadError::InvalidInput(format!(
                "map is {} × {}, the segmentation {:?}",
                map.nx(),
                map.ny(),
                self.segmentation.size()
            )));
        }
        let labels: Arc<[u32]> = self.segmentation.labels().into();
        let shapes = self
            .asperity_index
            .iter()
            .zip(self.set.laws())
            .map(|(&k, law)| {
                let a = &self.segmentation.asperities()[k];
                let floor = -basin_depth(a).unwrap_or(0.0);
                let basin = BasinSurface {
                    map: Arc::clone(map),
                    labels: Arc::clone(&labels),
                    label: k as u32,
                    summit: a.summit,
                    top: a.summit_height,
                    floor,
                };
                let equivalent_radius = equivalent_radius(a, law);
                LocalShape::Custom {
                    height: Arc::new(move |dx, dy| basin.height(dx, dy)),
                    equivalent_radius,
                }
            })
            .collect();
        Ok(shapes)
    }
}

/// Columns per id block of a rolling texture road
/// ([`TextureRoad::rolling_order`]).
pub const ID_BLOCK_COLUMNS: usize = 64;

impl TextureRoad {
    /// The order of a rolling road's asperities (ids): block-major, by the
    /// block of [`ID_BLOCK_COLUMNS`] columns holding the summit's grid
    /// point, then as the segmentation (higher grid summit first, ties by
    /// the point's index). An asperity's id is then the count of asperities
    /// in earlier blocks plus its rank within its block, which a window of
    /// whole blocks can compute from per-block counts alone
    /// ([`window::NpyTextureRoad`]). Returns the kept asperities' indices
    /// (into [`TextureRoad::set`]) in that order.
    pub fn rolling_order(&self) -> Vec<usize> {
        let block = |k: usize| {
            self.segmentation.asperities()[self.asperity_index[k]]
                .summit_cell
                .0
                / ID_BLOCK_COLUMNS
        };
        let mut order: Vec<usize> = (0..self.len()).collect();
        // Stable: within a block, the segmentation's order.
        order.sort_by_key(|&k| block(k));
        order
    }

    /// The kept asperities and their summit radii
    /// ([`TextureRoad::summit_radii`]) in the rolling order
    /// ([`TextureRoad::rolling_order`]), in the map's frame.
    ///
    /// # Errors
    /// [`TextureRoadError::InvalidInput`] never for a road
    /// [`texture_road`] built (a permutation of its valid set).
    pub fn rolling_set(&self) -> Result<(AsperitySet<TextureLaw>, Vec<f64>), TextureRoadError> {
        let order = self.rolling_order();
        let radii = self.summit_radii();
        let set = AsperitySet::new(
            order.iter().map(|&k| self.set.positions()[k]).collect(),
            order.iter().map(|&k| self.set.heights()[k]).collect(),
            order.iter().map(|&k| self.set.laws()[k].clone()).collect(),
        )
        .map_err(|e| TextureRoadError::InvalidInput(e.to_string()))?;
        Ok((set, order.iter().map(|&k| radii[k]).collect()))
    }
}

/// The rolling road on a texture's asperities `set` (its own laws or
/// calibrated ones, in any frame): the tread's gap at each cap's contact
/// point (summit `radii`, [`TextureRoad::summit_radii`]), the approach from
/// the map's highest point `top` ([`TextureRoad::top`]), as the BEM
/// measures it whatever asperities a run keeps.
///
/// # Errors
/// Those of [`crate::rolling::Road::with_summit_radii`] and
/// [`crate::rolling::Road::with_top`].
pub fn rolling_road<L>(
    set: AsperitySet<L>,
    radii: Vec<f64>,
    top: f64,
) -> Result<crate::rolling::Road<L>, crate::rolling::RollingError> {
    crate::rolling::Road::new(set)
        .with_summit_radii(radii)?
        .with_top(top)
}

impl TextureRoad {
    /// Each kept asperity's equivalent summit radius (m), as in
    /// [`TextureRoad::local_shapes`]: the rolling road measures the tread
    /// gap at the cap's contact point with it
    /// ([`crate::rolling::Road::with_summit_radii`]).
    pub fn summit_radii(&self) -> Vec<f64> {
        self.asperity_index
            .iter()
            .zip(self.set.laws())
            .map(|(&k, law)| equivalent_radius(&self.segmentation.asperities()[k], law))
            .collect()
    }

    /// The depth (m, set order) to which each kept asperity's cap is
    /// tabulated ([`CapGeometry::max_depth`]: its basin's floor by
    /// default). Pressed deeper, its whole basin is in contact and its law
    /// continues on vertical walls ([`pressed_past_caps`] names them).
    pub fn cap_depths(&self) -> Vec<f64> {
        self.set
            .laws()
            .iter()
            .map(|law| law.geometry().max_depth())
            .collect()
    }
}

/// The larger of the summit's curvature radius `√(r₁r₂)` and the secant
/// radius `Σ(δ)/(2πδ)` of the cap at a quarter of its depth range: a
/// flat-topped or blunt chipping has a sharp-looking summit fit but spreads
/// its contact like a far larger sphere.
///
/// A cap with no depth or no area at a quarter of it (a one-cell spike) has
/// no radius to speak of: it is a sharp summit, radius 0, touched at its tip
/// (its gap is the summit's), never a NaN that would refuse the whole road.
pub(crate) fn equivalent_radius(a: &Asperity, law: &TextureLaw) -> f64 {
    let d = 0.25 * law.geometry().max_depth();
    let secant = law.geometry().cap(d).base_area / (2.0 * std::f64::consts::PI * d);
    let secant = if secant.is_finite() { secant } else { 0.0 };
    let radius = match a.fit {
        Some(f) => (f.radii.0 * f.radii.1).sqrt().max(secant),
        None => secant,
    };
    if radius.is_finite() && radius > 0.0 {
        radius
    } else {
        0.0
    }
}

/// One basin of a texture seen from its summit.
struct BasinSurface {
    map: Arc<HeightMap>,
    labels: Arc<[u32]>,
    label: u32,
    summit: [f64; 2],
    top: f64,
    floor: f64,
}

impl BasinSurface {
    /// Height (m, in `[floor, 0]`) relative to the summit at offset `(dx, dy)`.
    fn height(&self, dx: f64, dy: f64) -> f64 {
        let (nx, ny) = (self.map.nx(), self.map.ny());
        let u = (self.summit[0] + dx) / self.map.dx();
        let v = (self.summit[1] + dy) / self.map.dy();
        if !(u > -0.5 && v > -0.5 && u < nx as f64 - 0.5 && v < ny as f64 - 0.5) {
            return self.floor;
        }
        // Corner values: the surface inside the basin, the floor outside.
        let z = |i: usize, j: usize| {
            let c = self.map.index(i, j);
            if self.labels[c] == self.label && self.labels[c] != UNLABELLED && self.map.valid()[c] {
                (self.map.heights()[c] - self.top).min(0.0)
            } else {
                self.floor
            }
        };
        let (i0, j0) = (
            (u.floor().max(0.0) as usize).min(nx - 1),
            (v.floor().max(0.0) as usize).min(ny - 1),
        );
        let (i1, j1) = ((i0 + 1).min(nx - 1), (j0 + 1).min(ny - 1));
        let (s, t) = (
            (u - i0 as f64).clamp(0.0, 1.0),
            (v - j0 as f64).clamp(0.0, 1.0),
        );
        let h = (1.0 - s) * (1.0 - t) * z(i0, j0)
            + s * (1.0 - t) * z(i1, j0)
            + (1.0 - s) * t * z(i0, j1)
            + s * t * z(i1, j1);
        h.clamp(self.floor, 0.0)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::multipoint::{Control, Problem, SolverOptions, solve};

    /// Four balls R = 5 mm at known places on a plane, summits 2.0, 1.9,
    /// 1.8, 1.7 mm above it, 0.1 mm grid.
    fn balls() -> (HeightMap, Vec<[f64; 3]>) {
        let r = 5e-3;
        let centres = vec![
            [6.03e-3, 6.01e-3, 2.0e-3],
            [18.02e-3, 6.04e-3, 1.9e-3],
            [6.01e-3, 18.03e-3, 1.8e-3],
            [18.04e-3, 18.02e-3, 1.7e-3],
        ];
        let c = centres.clone();
        let map = HeightMap::from_fn(240, 240, 1e-4, 1e-4, move |x, y| {
            c.iter()
                .map(|&[cx, cy, top]| {
                    let d2 = (x - cx).powi(2) + (y - cy).powi(2);
                    if d2 < r * r {
                        (r * r - d2).sqrt() - (r - top)
                    } else {
                        0.0
                    }
                })
                .fold(0.0, f64::max)
        })
        .unwrap();
        (map, centres)
    }

    #[test]
    fn balls_on_a_plane_give_four_asperities_and_a_balanced_solve() {
        let (map, centres) = balls();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let road = texture_road(&map, material, &TextureRoadOptions::new(0.2e-3, 1e-6)).unwrap();
        assert_eq!(road.len(), 4);
        // Highest first, each within one cell of its ball's summit.
        for (k, [cx, cy, top]) in centres.iter().enumerate() {
            let p = road.set.positions()[k];
            assert!((p[0] - cx).abs() < 1e-4, "{k}: {p:?}");
            assert!((p[1] - cy).abs() < 1e-4, "{k}: {p:?}");
            assert!((road.set.heights()[k] - top).abs() < 1e-5, "{k}");
        }
        let problem = Problem::from_set(road.set, material).unwrap();
        let load = 50.0;
        let s = solve(&problem, Control::Load(load), &SolverOptions::default()).unwrap();
        assert!((s.total_force() - load).abs() < 1e-6 * load);
        assert!(s.forces.iter().all(|&f| f >= 0.0));
        assert!(s.forces[0] >= s.forces[3], "{:?}", s.forces);
    }

    /// Each basin's table and law is its own: built on two threads, the
    /// road is the one built on one, law for law (tables and ramps), in
    /// the same order, with the same basin behind each.
    #[test]
    fn the_road_built_in_parallel_is_the_sequential_one() {
        let (balls, _) = balls();
        // The balls on a rough, tilted floor: hundreds of small basins,
        // enough to spread over both threads.
        let map = HeightMap::from_fn(240, 240, 1e-4, 1e-4, |x, y| {
            let floor = 2e-5 * ((x * 7e3).sin() * (y * 5e3).cos()) + 0.01 * x;
            let (i, j) = ((x / 1e-4).round() as usize, (y / 1e-4).round() as usize);
            balls.get(i, j).unwrap_or(0.0).max(floor)
        })
        .unwrap();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let seq = TextureRoadOptions::new(1e-5, 1e-8);
        let par = TextureRoadOptions {
            par: Par::rayon(2),
            ..seq
        };
        let a = texture_road(&map, material, &seq).unwrap();
        let b = texture_road(&map, material, &par).unwrap();
        assert!(a.len() > 4, "{} asperities", a.len());
        assert_eq!(a.asperity_index, b.asperity_index);
        assert_eq!(a.set.positions(), b.set.positions());
        assert_eq!(a.set.heights(), b.set.heights());
        for (k, (la, lb)) in a.set.laws().iter().zip(b.set.laws()).enumerate() {
            assert_eq!(format!("{la:?}"), format!("{lb:?}"), "law {k}");
        }
    }

    /// Balls at columns 60 and 180 of 0.1 mm cells: blocks 0 and 2 of 64
    /// columns. The rolling order takes block 0's balls (0 and 2, highest
    /// first) before block 2's (1 and 3), and the rolling set follows it.
    #[test]
    fn the_rolling_order_is_by_block_then_the_segmentations() {
        let (map, _) = balls();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let road = texture_road(&map, material, &TextureRoadOptions::new(0.2e-3, 1e-6)).unwrap();
        assert_eq!(road.rolling_order(), vec![0, 2, 1, 3]);
        let (set, radii) = road.rolling_set().unwrap();
        let whole_radii = road.summit_radii();
        for (id, k) in [0, 2, 1, 3].into_iter().enumerate() {
            assert_eq!(set.positions()[id], road.set.positions()[k]);
            assert_eq!(set.heights()[id], road.set.heights()[k]);
            assert_eq!(radii[id], whole_radii[k]);
        }
    }

    #[test]
    fn local_shape_of_a_ball_follows_the_sphere_inside_its_basin_and_drops_outside() {
        let (map, centres) = balls();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let road = texture_road(&map, material, &TextureRoadOptions::new(0.2e-3, 1e-6)).unwrap();
        let map = Arc::new(map);
        let shapes = road.local_shapes(&map).unwrap();
        let r: f64 = 5e-3;
        for (k, shape) in shapes.iter().enumerate() {
            // Summit paraboloid fits a sphere of radius R.
            let re = shape.equivalent_radius();
            assert!((re - r).abs() < 0.02 * r, "{k}: R = {re}");
            let [cx, cy, top] = centres[k];
            let [sx, sy] = road.set.positions()[k];
            // On the ball, 1–3 mm from its centre: the sphere to the
            // interpolation error of a 0.1 mm grid (≈ h²/8R ≈ 0.3 µm) and
            // the summit offset (< 1 cell).
            for (ox, oy) in [(1e-3, 0.0), (0.0, -2e-3), (2.1e-3, 2.1e-3)] {
                let (x, y) = (cx + ox, cy + oy);
                let exact = (r * r - ox * ox - oy * oy).sqrt() - r;
                let h = shape.height(x - sx, y - sy);
                assert!(
                    (h - (exact + top - road.set.heights()[k])).abs() < 2e-6,
                    "{k}: h = {h}, sphere {exact}"
                );
            }
            // 9 mm away the point lies in another basin or on the plane
            // outside this ball's basin: the floor, the basin bottom.
            let h = shape.height(9e-3, 9e-3);
            assert!((h + top).abs() < 1e-9 || h <= -top + 1e-9, "{k}: {h}");
            assert!(shape.height(0.0, 0.0) <= 0.0);
        }
        // A map of another size is refused.
        let other = Arc::new(HeightMap::from_fn(10, 10, 1e-4, 1e-4, |_, _| 0.0).unwrap());
        assert!(road.local_shapes(&other).is_err());
    }

    /// Every summit radius is finite and non-negative, one-cell spikes
    /// included, so the rolling road is built: a cap with no radius to speak
    /// of is a sharp summit (radius 0), never a NaN that loses the whole
    /// road to one asperity (seen once on a generated 2 m road at
    /// `min_area = 1 mm²`, not reproduced here; the guard is in
    /// `equivalent_radius`).
    #[test]
    fn a_one_cell_spike_is_a_sharp_summit_not_a_lost_road() {
        let (balls, _) = balls();
        let spikes = [
            (120usize, 120usize, 1.0e-3),
            (230, 120, 0.6e-3),
            (120, 230, 0.3e-3),
        ];
        let map = HeightMap::from_fn(240, 240, 1e-4, 1e-4, |x, y| {
            let (i, j) = ((x / 1e-4).round() as usize, (y / 1e-4).round() as usize);
            let spike = spikes
                .iter()
                .find(|&&(si, sj, _)| (si, sj) == (i, j))
                .map_or(0.0, |&(_, _, h)| h);
            balls.get(i, j).unwrap_or(0.0).max(spike)
        })
        .unwrap();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let road = texture_road(&map, material, &TextureRoadOptions::new(0.2e-3, 1e-12)).unwrap();
        assert!(
            road.len() >= 7,
            "four balls and three spikes: {}",
            road.len()
        );
        let radii = road.summit_radii();
        assert!(
            radii.iter().all(|r| r.is_finite() && *r >= 0.0),
            "{radii:?}"
        );
        // The balls keep their radius (about R = 5 mm); the spikes are far
        // sharper than any ball.
        let mut sorted = radii.clone();
        sorted.sort_by(f64::total_cmp);
        assert!(sorted[..3].iter().all(|r| *r < 1e-3), "{sorted:?}");
        tyreroad_rolling::Road::new(road.set.clone())
            .with_summit_radii(radii)
            .expect("the road is built with its sharp summits");
    }

    #[test]
    fn invalid_options_are_refused() {
        let (map, _) = balls();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let mut o = TextureRoadOptions::new(0.2e-3, 1e-6);
        o.depth = CapDepth::Fixed(f64::NAN);
        assert!(matches!(
            texture_road(&map, material, &o),
            Err(TextureRoadError::InvalidInput(_))
        ));
        let flat = HeightMap::from_fn(50, 50, 1e-4, 1e-4, |_, _| 0.0).unwrap();
        assert!(texture_road(&flat, material, &TextureRoadOptions::new(0.2e-3, 1e-6)).is_err());
    }
}
