//! Hard road kinds: the synthetic textures that break a naive segmentation
//! into rounded summits (grooves, flat tops, deep pores, large blocks).
//!
//! Each kind is a parameter struct with physical defaults (SI units) and a
//! function returning a [`HeightMap`], reproducible from its seed. They are
//! built from the blocks of [`crate::synth`]: the fine roughness of mortar or
//! stone is a [`SelfAffine`] surface, chippings come from [`aggregate`]; this
//! module adds grooves, clipping planes, pores, striations and blocks.
//!
//! A plain chip seal of rounded 6/10 mm chippings needs no kind of its own:
//! it is `Aggregate::new(nx, ny, dx, dy, Aggregate::grading_6_10(), seed)`
//! (ellipsoids, 30–50 % embedded, coverage 1.3); [`WornChipSeal`] is that
//! surface with its tops ground flat.
//!
//! Heights are in metres, `z = 0` being the mortar plane (tining, brushed
//! concrete, exposed aggregate), the chippings' base plane (porous asphalt,
//! chip seal) or the nominal top of the blocks (pavé).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;

use tyreroad_core::validate;

use crate::error::TextureError;
use crate::heightmap::{HeightMap, check_size};
use crate::synth::{Aggregate, ChipShape, SelfAffine, aggregate, self_affine_to_grid};

/// The grid of a synthetic road: `nx × ny` points at spacings `dx`, `dy`
/// (m), x being the driving direction.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RoadGrid {
    /// Points along x.
    pub nx: usize,
    /// Points along y.
    pub ny: usize,
    /// Spacing along x (m).
    pub dx: f64,
    /// Spacing along y (m).
    pub dy: f64,
}

impl RoadGrid {
    /// A square-celled grid of `nx × ny` points at spacing `spacing` (m).
    pub fn square(nx: usize, ny: usize, spacing: f64) -> Self {
        Self {
            nx,
            ny,
            dx: spacing,
            dy: spacing,
        }
    }

    /// Checks the sizes against the crate's allocation limit and the
    /// spacings; returns the number of points.
    fn check(&self) -> Result<usize, TextureError> {
        let n = check_size(self.nx, self.ny)?;
        validate::positive("dx", self.dx)?;
        validate::positive("dy", self.dy)?;
        Ok(n)
    }
}

/// Fine, isotropic roughness (mortar, stone surface) as a self-affine
/// surface; an `rms` of 0 means perfectly smooth.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Microtexture {
    /// Root mean square height `Sq` (m), ≥ 0.
    pub rms: f64,
    /// Hurst exponent, in (0, 1].
    pub hurst: f64,
    /// Long cut-off wavelength (m).
    pub lambda_long: f64,
    /// Short cut-off wavelength (m).
    pub lambda_short: f64,
}

impl Default for Microtexture {
    /// Sand-cement mortar: Sq 0.05 mm, H 0.8, wavelengths 0.5–5 mm.
    fn default() -> Self {
        Self {
            rms: 0.05e-3,
            hurst: 0.8,
            lambda_long: 5e-3,
            lambda_short: 0.5e-3,
        }
    }
}

impl Microtexture {
    /// The roughness heights on `grid` (row-major), all zero when `rms` is 0.
    fn heights(&self, grid: &RoadGrid, seed: u64) -> Result<Vec<f64>, TextureError> {
        let n = grid.check()?;
        validate::finite("microtexture rms", self.rms)?;
        if self.rms < 0.0 {
            return Err(TextureError::InvalidParameter {
                name: "microtexture rms",
                value: self.rms,
                requirement: "≥ 0",
            });
        }
        if self.rms == 0.0 {
            return Ok(vec![0.0; n]);
        }
        let map = self_affine_to_grid(&SelfAffine {
            nx: grid.nx,
            ny: grid.ny,
            dx: grid.dx,
            dy: grid.dy,
            rms: self.rms,
            hurst: self.hurst,
            lambda_long: self.lambda_long,
            lambda_short: self.lambda_short,
            seed,
        })?;
        Ok(map.heights().to_vec())
    }
}

/// An independent generator seed for component `k` of a road (SplitMix64),
/// so the grooves do not reuse the roughness's random stream.
fn sub_seed(seed: u64, k: u64) -> u64 {
    let mut z = seed
        .wrapping_add(k.wrapping_add(1).wrapping_mul(0x9E37_79B9_7F4A_7C15))
        .wrapping_add(0x9E37_79B9_7F4A_7C15);
    z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
    z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
    z ^ (z >> 31)
}

fn check_fraction(name: &'static str, value: f64, max: f64) -> Result<f64, TextureError> {
    validate::finite(name, value)?;
    if !(0.0..=max).contains(&value) {
        return Err(TextureError::InvalidParameter {
            name,
            value,
            requirement: "a fraction in [0, its upper bound]",
        });
    }
    Ok(value)
}

/// Lowers every height above the `1 − fraction` quantile to it: the top
/// `fraction` of the area becomes flat plateaus at one level (a wear or
/// rolling plane). Returns the plane's height.
fn grind_flat(h: &mut [f64], fraction: f64) -> f64 {
    let mut sorted = h.to_vec();
    sorted.sort_by(f64::total_cmp);
    let n = sorted.len();
    let k = (((1.0 - fraction) * n as f64).floor() as usize).min(n - 1);
    let level = sorted[k];
    for v in h.iter_mut() {
        *v = v.min(level);
    }
    level
}

/// Direction of the grooves of a tined concrete.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum TiningDirection {
    /// Grooves across the driving direction (lines along y, spaced along x).
    Transverse,
    /// Grooves along the driving direction (lines along x, spaced along y).
    Longitudinal,
}

/// Tined concrete: rectangular grooves cut into a mortar plane with fine
/// roughness.
///
/// The groove centres are spaced by pitches drawn uniformly in `pitch`
/// (equal bounds give a regular pitch; a range gives the random spacing
/// used against tonal tyre noise), the first one at a random offset within
/// the first pitch. A grid point lies in a groove when its coordinate across
/// the grooves is within half a `groove_width` of a centre; there the height
/// is the roughness minus `groove_depth`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Tining {
    /// The grid.
    pub grid: RoadGrid,
    /// Transverse or longitudinal grooves.
    pub direction: TiningDirection,
    /// Groove width (m), at least one grid spacing across the grooves and
    /// less than the smallest pitch. Default 3 mm.
    pub groove_width: f64,
    /// Groove depth (m). Default 4 mm.
    pub groove_depth: f64,
    /// Range of the centre-to-centre groove spacing (m). Default 12.5 mm
    /// regular; e.g. `(12.5e-3, 25e-3)` for random tining.
    pub pitch: (f64, f64),
    /// Mortar roughness on lands and groove bottoms.
    pub mortar: Microtexture,
    /// Seed of the ChaCha8 generators.
    pub seed: u64,
}

impl Tining {
    /// Transverse tining with the defaults: 3 mm wide, 4 mm deep grooves at
    /// a regular 12.5 mm pitch on the default mortar.
    pub fn transverse(grid: RoadGrid, seed: u64) -> Self {
        Self {
            grid,
            direction: TiningDirection::Transverse,
            groove_width: 3e-3,
            groove_depth: 4e-3,
            pitch: (12.5e-3, 12.5e-3),
            mortar: Microtexture::default(),
            seed,
        }
    }

    /// Longitudinal tining with the same defaults as [`Self::transverse`].
    pub fn longitudinal(grid: RoadGrid, seed: u64) -> Self {
        Self {
            direction: TiningDirection::Longitudinal,
            ..Self::transverse(grid, seed)
        }
    }
}

/// Synthesise a tined concrete (see [`Tining`]).
pub fn tining(p: &Tining) -> Result<HeightMap, TextureError> {
    let g = p.grid;
    g.check()?;
    validate::positive("groove_width", p.groove_width)?;
    validate::positive("groove_depth", p.groove_depth)?;
    validate::positive("pitch", p.pitch.0)?;
    validate::positive("pitch", p.pitch.1)?;
    if p.pitch.1 < p.pitch.0 {
        return Err(TextureError::InvalidParameter {
            name: "pitch",
            value: p.pitch.1,
            requirement: "an ordered range (max ≥ min)",
        });
    }
    let (spacing, n_across, length) = match p.direction {
        TiningDirection::Transverse => (g.dx, g.nx, g.nx as f64 * g.dx),
        TiningDirection::Longitudinal => (g.dy, g.ny, g.ny as f64 * g.dy),
    };
    if p.groove_width < spacing {
        return Err(TextureError::InvalidParameter {
            name: "groove_width",
            value: p.groove_width,
            requirement: "≥ the grid spacing across the grooves (else unresolved)",
        });
    }
    if p.groove_width >= p.pitch.0 {
        return Err(TextureError::InvalidParameter {
            name: "groove_width",
            value: p.groove_width,
            requirement: "< the smallest pitch (a land between grooves)",
        });
    }
    let mut h = p.mortar.heights(&g, sub_seed(p.seed, 0))?;
    let mut rng = ChaCha8Rng::seed_from_u64(sub_seed(p.seed, 1));
    let draw_pitch =
        |rng: &mut ChaCha8Rng| p.pitch.0 + (p.pitch.1 - p.pitch.0) * rng.random::<f64>();
    // Which points across the grooves are in one; the loop ends since each
    // pitch is at least one grid spacing (groove_width ≥ spacing).
    let mut grooved = vec![false; n_across];
    let mut centre = draw_pitch(&mut rng) * rng.random::<f64>();
    let half = 0.5 * p.groove_width;
    while centre - half < length {
        let first = ((centre - half) / spacing).ceil().max(0.0) as usize;
        let mut k = first;
        while k < n_across && (k as f64 * spacing) < centre + half {
            grooved[k] = true;
            k += 1;
        }
        centre += draw_pitch(&mut rng);
    }
    for j in 0..g.ny {
        for i in 0..g.nx {
            let across = match p.direction {
                TiningDirection::Transverse => i,
                TiningDirection::Longitudinal => j,
            };
            if grooved[across] {
                h[j * g.nx + i] -= p.groove_depth;
            }
        }
    }
    HeightMap::new(g.nx, g.ny, g.dx, g.dy, h)
}

/// Fine transverse striations of a brushed (or broomed) concrete on its
/// mortar: an anisotropic self-affine surface whose features are
/// `elongation` times longer along y (across the driving direction) than
/// along x.
///
/// Built as a [`SelfAffine`] surface on the grid with `dy / elongation` as
/// y spacing, so that a feature of wavelength λ in the generator spans
/// `λ·elongation` along y on the road, then added to the mortar.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BrushedConcrete {
    /// The grid.
    pub grid: RoadGrid,
    /// Root mean square height of the striations (m). Default 0.2 mm.
    pub striation_rms: f64,
    /// Shortest striation wavelength along x (m). Default 0.5 mm.
    pub striation_short: f64,
    /// Longest striation wavelength along x (m). Default 3 mm.
    pub striation_long: f64,
    /// Length-to-width ratio of the striations, in [1, 1000]. Default 20.
    pub elongation: f64,
    /// Mortar roughness beneath.
    pub mortar: Microtexture,
    /// Seed of the ChaCha8 generators.
    pub seed: u64,
}

impl BrushedConcrete {
    /// The defaults: striations of Sq 0.2 mm, 0.5–3 mm wide, 20 times
    /// longer than wide, on the default mortar.
    pub fn new(grid: RoadGrid, seed: u64) -> Self {
        Self {
            grid,
            striation_rms: 0.2e-3,
            striation_short: 0.5e-3,
            striation_long: 3e-3,
            elongation: 20.0,
            mortar: Microtexture::default(),
            seed,
        }
    }
}

/// Synthesise a brushed concrete (see [`BrushedConcrete`]).
pub fn brushed_concrete(p: &BrushedConcrete) -> Result<HeightMap, TextureError> {
    let g = p.grid;
    g.check()?;
    validate::finite("elongation", p.elongation)?;
    if !(1.0..=1000.0).contains(&p.elongation) {
        return Err(TextureError::InvalidParameter {
            name: "elongation",
            value: p.elongation,
            requirement: "in [1, 1000]",
        });
    }
    validate::positive("striation_rms", p.striation_rms)?;
    validate::positive("striation_short", p.striation_short)?;
    validate::positive("striation_long", p.striation_long)?;
    if p.striation_short >= p.striation_long {
        return Err(TextureError::InvalidParameter {
            name: "striation_short",
            value: p.striation_short,
            requirement: "< striation_long",
        });
    }
    let striations = self_affine_to_grid(&SelfAffine {
        nx: g.nx,
        ny: g.ny,
        dx: g.dx,
        dy: g.dy / p.elongation,
        rms: p.striation_rms,
        hurst: 0.8,
        lambda_long: p.striation_long,
        lambda_short: p.striation_short,
        seed: sub_seed(p.seed, 1),
    })?;
    let mut h = p.mortar.heights(&g, sub_seed(p.seed, 0))?;
    for (v, s) in h.iter_mut().zip(striations.heights()) {
        *v += s;
    }
    HeightMap::new(g.nx, g.ny, g.dx, g.dy, h)
}

/// Exposed-aggregate concrete: crushed chippings standing out of a flat
/// mortar plane (the surface mortar washed or brushed off before setting).
///
/// The chippings are an [`Aggregate`] of rounded polyhedra whose embedded
/// fraction is `1 − exposure`; off the chippings the surface is the mortar
/// (plane `z = 0` plus its roughness), on them the higher of chipping and
/// mortar.
#[derive(Clone, Debug, PartialEq)]
pub struct ExposedAggregate {
    /// The grid.
    pub grid: RoadGrid,
    /// Grading curve (see [`Aggregate::grading`]). Default 4/6.3 mm.
    pub grading: Vec<(f64, f64)>,
    /// Summed plan area of the chippings over the map area. Default 0.8.
    pub coverage: f64,
    /// Range of the fraction of a chipping's height standing out of the
    /// mortar, in (0, 1]. Default 0.25–0.4.
    pub exposure: (f64, f64),
    /// Mortar roughness.
    pub mortar: Microtexture,
    /// Seed of the ChaCha8 generators.
    pub seed: u64,
}

impl ExposedAggregate {
    /// The defaults: 4/6.3 mm polyhedral chippings, coverage 0.8, 25–40 %
    /// exposed, default mortar.
    pub fn new(grid: RoadGrid, seed: u64) -> Self {
        Self {
            grid,
            grading: Aggregate::grading_4_6(),
            coverage: 0.8,
            exposure: (0.25, 0.4),
            mortar: Microtexture::default(),
            seed,
        }
    }
}

/// Synthesise an exposed-aggregate concrete (see [`ExposedAggregate`]).
pub fn exposed_aggregate(p: &ExposedAggregate) -> Result<HeightMap, TextureError> {
    let g = p.grid;
    g.check()?;
    for v in [p.exposure.0, p.exposure.1] {
        validate::finite("exposure", v)?;
        if !(v > 0.0 && v <= 1.0) || p.exposure.0 > p.exposure.1 {
            return Err(TextureError::InvalidParameter {
                name: "exposure",
                value: v,
                requirement: "an ordered range within (0, 1]",
            });
        }
    }
    let mut chips = Aggregate::new(
        g.nx,
        g.ny,
        g.dx,
        g.dy,
        p.grading.clone(),
        sub_seed(p.seed, 1),
    );
    chips.coverage = p.coverage;
    chips.embedding = (1.0 - p.exposure.1, 1.0 - p.exposure.0);
    chips.shape = ChipShape::Polyhedron {
        cuts: 6,
        rounding: 0.1,
    };
    let chips = aggregate(&chips)?;
    let mut h = p.mortar.heights(&g, sub_seed(p.seed, 0))?;
    // `aggregate` puts its base plane at exactly 0: a positive height is a
    // chipping.
    for (v, &c) in h.iter_mut().zip(chips.heights()) {
        if c > 0.0 {
            *v = v.max(c);
        }
    }
    HeightMap::new(g.nx, g.ny, g.dx, g.dy, h)
}

/// Porous (open-graded) asphalt: a skeleton of crushed chippings with deep
/// voids between them, their tops flattened by the rollers.
///
/// The chippings are an [`Aggregate`] of rounded polyhedra; where none
/// covers the base plane the surface drops into a pore `pore_depth` below
/// it; then the top `plateau_fraction` of the area is cut flat at one level.
/// Heights therefore have a negative skew: flat tops, deep narrow voids.
#[derive(Clone, Debug, PartialEq)]
pub struct PorousAsphalt {
    /// The grid.
    pub grid: RoadGrid,
    /// Grading curve. Default 6/10 mm.
    pub grading: Vec<(f64, f64)>,
    /// Summed plan area of the chippings over the map area. Default 3 (the
    /// chippings are half embedded, so their footprints on the base plane are
    /// much smaller than their plan areas: voids on about a fifth of the
    /// area).
    pub coverage: f64,
    /// Depth of the voids below the chippings' base plane (m). Default 3 mm.
    pub pore_depth: f64,
    /// Fraction of the area flattened at the top, in [0, 0.9]. Default 0.2.
    pub plateau_fraction: f64,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl PorousAsphalt {
    /// The defaults: 6/10 mm polyhedra, coverage 3, voids 3 mm deep, 20 %
    /// plateaus.
    pub fn new(grid: RoadGrid, seed: u64) -> Self {
        Self {
            grid,
            grading: Aggregate::grading_6_10(),
            coverage: 3.0,
            pore_depth: 3e-3,
            plateau_fraction: 0.2,
            seed,
        }
    }
}

/// Synthesise a porous asphalt (see [`PorousAsphalt`]).
pub fn porous_asphalt(p: &PorousAsphalt) -> Result<HeightMap, TextureError> {
    let g = p.grid;
    g.check()?;
    validate::positive("pore_depth", p.pore_depth)?;
    check_fraction("plateau_fraction", p.plateau_fraction, 0.9)?;
    let mut chips = Aggregate::new(g.nx, g.ny, g.dx, g.dy, p.grading.clone(), p.seed);
    chips.coverage = p.coverage;
    chips.shape = ChipShape::Polyhedron {
        cuts: 6,
        rounding: 0.1,
    };
    let chips = aggregate(&chips)?;
    let mut h: Vec<f64> = chips
        .heights()
        .iter()
        .map(|&c| if c > 0.0 { c } else { -p.pore_depth })
        .collect();
    grind_flat(&mut h, p.plateau_fraction);
    HeightMap::new(g.nx, g.ny, g.dx, g.dy, h)
}

/// A worn chip seal: the rounded chippings of a surface dressing
/// (ellipsoids of a 6/10 mm grading, 30–50 % embedded, as
/// [`Aggregate::new`]) with the top `plateau_fraction` of the area ground
/// flat at one level by traffic.
#[derive(Clone, Debug, PartialEq)]
pub struct WornChipSeal {
    /// The grid.
    pub grid: RoadGrid,
    /// Grading curve. Default 6/10 mm.
    pub grading: Vec<(f64, f64)>,
    /// Fraction of the area worn flat, in [0, 0.9]. Default 0.1.
    pub plateau_fraction: f64,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl WornChipSeal {
    /// The defaults: 6/10 mm ellipsoids, 10 % of the area worn flat.
    pub fn new(grid: RoadGrid, seed: u64) -> Self {
        Self {
            grid,
            grading: Aggregate::grading_6_10(),
            plateau_fraction: 0.1,
            seed,
        }
    }
}

/// Synthesise a worn chip seal (see [`WornChipSeal`]).
pub fn worn_chip_seal(p: &WornChipSeal) -> Result<HeightMap, TextureError> {
    let g = p.grid;
    g.check()?;
    check_fraction("plateau_fraction", p.plateau_fraction, 0.9)?;
    let chips = aggregate(&Aggregate::new(
        g.nx,
        g.ny,
        g.dx,
        g.dy,
        p.grading.clone(),
        p.seed,
    ))?;
    let mut h = chips.heights().to_vec();
    grind_flat(&mut h, p.plateau_fraction);
    HeightMap::new(g.nx, g.ny, g.dx, g.dy, h)
}

/// Pavé (setts): rectangular blocks with rounded edges separated by joints.
///
/// Blocks of `block_length × block_width` (x × y) repeat at pitches
/// `block + joint_width`; with `stagger` every other row is shifted by half
/// a pitch along x (running bond). Each block's top sits at a random offset
/// uniform in `±height_spread/2` about `z = 0`; its edges and corners are
/// rounded by a quarter circle of radius `edge_radius` (the top drops by
/// `edge_radius` at the block's edge); the joints are filled to
/// `joint_depth` below `z = 0`. The stone's roughness is added everywhere.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Pave {
    /// The grid.
    pub grid: RoadGrid,
    /// Block length along x (m). Default 100 mm.
    pub block_length: f64,
    /// Block width along y (m). Default 100 mm.
    pub block_width: f64,
    /// Joint width (m), at least one grid spacing. Default 10 mm.
    pub joint_width: f64,
    /// Joint depth below the nominal block top (m). Default 4 mm.
    pub joint_depth: f64,
    /// Edge radius (m), at most half the smaller block side. Default 5 mm.
    pub edge_radius: f64,
    /// Range of the blocks' top heights (m), ≥ 0. Default 1 mm.
    pub height_spread: f64,
    /// Running bond (rows shifted by half a pitch). Default true.
    pub stagger: bool,
    /// Roughness of the stone.
    pub stone: Microtexture,
    /// Seed of the ChaCha8 generators.
    pub seed: u64,
}

impl Pave {
    /// The defaults: 100 × 100 mm blocks, 10 mm joints 4 mm deep, 5 mm edge
    /// radius, tops within 1 mm, running bond, stone Sq 0.1 mm at
    /// wavelengths 0.5–10 mm.
    pub fn new(grid: RoadGrid, seed: u64) -> Self {
        Self {
            grid,
            block_length: 100e-3,
            block_width: 100e-3,
            joint_width: 10e-3,
            joint_depth: 4e-3,
            edge_radius: 5e-3,
            height_spread: 1e-3,
            stagger: true,
            stone: Microtexture {
                rms: 0.1e-3,
                hurst: 0.8,
                lambda_long: 10e-3,
                lambda_short: 0.5e-3,
            },
            seed,
        }
    }
}

/// Synthesise a pavé (see [`Pave`]).
pub fn pave(p: &Pave) -> Result<HeightMap, TextureError> {
    let g = p.grid;
    g.check()?;
    validate::positive("block_length", p.block_length)?;
    validate::positive("block_width", p.block_width)?;
    validate::positive("joint_width", p.joint_width)?;
    validate::positive("joint_depth", p.joint_depth)?;
    validate::positive("edge_radius", p.edge_radius)?;
    validate::finite("height_spread", p.height_spread)?;
    if p.height_spread < 0.0 {
        return Err(TextureError::InvalidParameter {
            name: "height_spread",
            value: p.height_spread,
            requirement: "≥ 0",
        });
    }
    if p.joint_width < g.dx.max(g.dy) {
        return Err(TextureError::InvalidParameter {
            name: "joint_width",
            value: p.joint_width,
            requirement: "≥ the grid spacing (else unresolved)",
        });
    }
    if 2.0 * p.edge_radius > p.block_length.min(p.block_width) {
        return Err(TextureError::InvalidParameter {
            name: "edge_radius",
            value: p.edge_radius,
            requirement: "≤ half the smaller block side",
        });
    }
    let mut h = p.stone.heights(&g, sub_seed(p.seed, 0))?;
    let (px, py) = (
        p.block_length + p.joint_width,
        p.block_width + p.joint_width,
    );
    // Blocks' top offsets, drawn row by row over the blocks the map touches
    // (one more column for the staggered rows).
    let cols = ((g.nx as f64 * g.dx) / px).ceil() as usize + 2;
    let rows = ((g.ny as f64 * g.dy) / py).ceil() as usize + 1;
    let mut rng = ChaCha8Rng::seed_from_u64(sub_seed(p.seed, 1));
    let offsets: Vec<f64> = (0..cols * rows)
        .map(|_| p.height_spread * (rng.random::<f64>() - 0.5))
        .collect();
    let r = p.edge_radius;
    for j in 0..g.ny {
        let y = j as f64 * g.dy;
        let row = (y / py).floor() as usize;
        let v = y - row as f64 * py;
        let shift = if p.stagger && row % 2 == 1 {
            0.5 * px
        } else {
            0.0
        };
        for i in 0..g.nx {
            let xs = i as f64 * g.dx + shift;
            let col = (xs / px).floor() as usize;
            let u = xs - col as f64 * px;
            let top = if u < p.block_length && v < p.block_width {
                // Distance to the block's inner rectangle (shrunk by r): the
                // rounded edge is a quarter circle over the last r.
                let ex = (r - u).max(u - (p.block_length - r)).max(0.0);
                let ey = (r - v).max(v - (p.block_width - r)).max(0.0);
                let e = (ex * ex + ey * ey).sqrt().min(r);
                let offset = offsets[(row.min(rows - 1)) * cols + col.min(cols - 1)];
                offset - (r - (r * r - e * e).sqrt())
            } else {
                f64::NEG_INFINITY
            };
            h[j * g.nx + i] += top.max(-p.joint_depth);
        }
    }
    HeightMap::new(g.nx, g.ny, g.dx, g.dy, h)
}
