//! Road textures as height maps: input/output, synthesis, texture
//! indicators and segmentation into asperities for the multipoint model.
//!
//! # Height maps
//!
//! A [`HeightMap`] is a regular grid: `nx` points along x (the driving
//! direction) at spacing `dx`, `ny` profiles along y at spacing `dy`,
//! heights in metres stored row-major (`j·nx + i`), and a validity mask
//! (missing points store NaN): a `tyreroad_core::Field` at the origin whose
//! mask is always present ([`HeightMap::field`]). Invariants: sizes ≥ 1 and consistent,
//! spacings finite and > 0, valid heights finite. Constructors return a
//! [`TextureError`]; nothing panics on user input.
//!
//! # Formats ([`io`])
//!
//! - **X3P** (ISO 25178-72 / ISO 5436-2): a zip with `main.xml` and
//!   `bindata/data.bin`; z types `I` (i16), `L` (i32), `F` (f32), `D` (f64),
//!   `z = offset + increment · raw`; invalid points as NaN and/or the
//!   `bindata/valid.bin` bit array; MD5 of the data, of the validity buffer
//!   and of `main.xml` (`md5_checksum.hex`) verified; written with correct
//!   checksums ([`io::x3p`]).
//! - **ASCII grid**: a `key value` header (`nx`, `ny`, `dx`, `dy`, optional
//!   `z_scale`, `xy_scale`), a `data` line, then `ny` rows of `nx` heights
//!   (`NaN` or `*` = missing) ([`io::text::ascii_grid_from_str`]).
//! - **xyz**: `x y z` lines on a regular grid, recovered from the points
//!   ([`io::text::xyz_from_str`]).
//! - **Digital Surf `.sur`**: classic uncompressed files, 16/32-bit integer
//!   points, read from the 512-byte header ([`io::sur::sur_from_bytes`]).
//!
//! Every reader turns malformed or truncated bytes into an error (property
//! tests feed them arbitrary, truncated and mutated bytes); writers write a
//! temporary file and rename it, so an output is whole or absent.
//!
//! A "no data" marker written as a height (−9999, 1e30) is found by
//! [`find_sentinels`]: a value repeated exactly and lying more than
//! [`sentinel::SENTINEL_SPANS`] times the others' 1st–99th percentile span
//! beyond them; [`HeightMap::without_values`] marks its points missing.
//!
//! # Synthesis ([`synth`])
//!
//! Self-affine Gaussian surfaces ([`synth::SelfAffine`]): white noise
//! filtered by `√C(q)` with
//!
//! ```text
//! C(q) = 1 (0 < q < q_L),  (q/q_L)^(−2(1+H)) (q_L ≤ q ≤ q_s),  0 (q > q_s),
//! q_L = 2π/λ_long,  q_s = 2π/λ_short,
//! ```
//!
//! then rescaled to the exact rms. Aggregate surfaces
//! ([`synth::Aggregate`]): chippings of a grading curve (ellipsoids or
//! rounded polyhedra, random orientation and embedding) on a base plane,
//! the height being the maximum of the shapes. Both are reproducible from a
//! seed (ChaCha8).
//!
//! # Hard road kinds ([`roads`])
//!
//! Tined, brushed and exposed-aggregate concrete, porous asphalt, worn chip
//! seal and pavé, built from the same blocks plus grooves, wear planes,
//! pores and blocks (docs/texture.md has the table of kinds).
//!
//! # Indicators ([`indicators`])
//!
//! - Mean profile depth (ISO 13473-1), along x: per segment of
//!   `N = round(100 mm / dx)` samples, remove the least-squares line, split
//!   into halves, `MSD = (peak₁ + peak₂)/2` (the detrended mean is 0); MPD =
//!   mean of the MSDs over segments and profiles. Profiles shorter than
//!   100 mm use their whole length as the baseline (reported).
//! - One-third-octave texture spectrum (ISO/TS 13473-4), along x: per
//!   detrended profile, the one-sided periodogram `P_k = 2|X_k|²/N²`
//!   (`tyreroad_core::spectrum::periodogram`) summed
//!   over the bins whose wavelength `N·dx/k` lies in each band
//!   (`λ_c = 10^(m/10)` mm, edges `λ_c·10^(±1/20)`), averaged over profiles;
//!   `L = 20 log10(a_rms / 1 µm)` with `a_rms² =` band power.
//!
//! # Segmentation ([`segment`](mod@segment))
//!
//! Flooding from the top (a watershed of the inverted surface): points by
//! decreasing height, union–find over basins, 8-connectivity; where basins
//! meet, a basin whose prominence (summit − saddle) is below
//! `min_prominence`, or whose area above the saddle is below `min_area`, is
//! merged into the basin of the higher summit. Each [`Asperity`] has its
//! summit (refined by a least-squares paraboloid on the 5 × 5 points around
//! it), its prominence, its cells and label.
//!
//! Caps ([`GridCap`]): the basin's piecewise-linear surface (four triangles
//! per cell about its centre) cut by the plane `top − δ`:
//!
//! ```text
//! Σ = area above the plane,  Ω = ∫ max(0, h − plane) dA,  Γ = iso-contour length
//! ```
//!
//! exact for that surface while the plane stays above the basin's boundary
//! (`max_depth`). [`asperity_cap`] tabulates it into a
//! [`tyreroad_asperity::TabulatedCap`], using the summit paraboloid near
//! contact onset (blended into the grid cap between `2δ₁` and `10δ₁`, `δ₁` the depth
//! of the lowest of the 8 points around the summit), so the
//! contact law starts as Hertz does on a smooth summit instead of as a
//! pyramid.
//!
//! Windows ([`segment_window()`]): a window of columns of a larger map
//! segmented on its own, each basin flagged **certified** when it is
//! provably the whole map's (same cells, summit, size and kept flag at every
//! step of the flood; uncertainty starts at the cut columns and spreads only
//! where a merge could differ). A certified asperity's cells, fit and cap
//! are the whole map's bit for bit; positions are in the whole map's frame.
//!
//! # Example
//!
//! ```
//! use tyreroad_asperity::{CapGeometry, Sphere};
//! use tyreroad_texture::{CapOptions, HeightMap, SegmentOptions, asperity_cap, segment};
//!
//! // Two balls of radius 5 mm standing 2 mm above a plane, 0.1 mm grid.
//! let r = 5e-3;
//! let ball = |x: f64, y: f64, cx: f64, cy: f64| {
//!     let d2 = (x - cx).powi(2) + (y - cy).powi(2);
//!     if d2 < r * r { (r * r - d2).sqrt() - (r - 2e-3) } else { 0.0 }
//! };
//! let map = HeightMap::from_fn(160, 80, 1e-4, 1e-4, |x, y| {
//!     ball(x, y, 4e-3, 4e-3).max(ball(x, y, 12e-3, 4e-3)).max(0.0)
//! })?;
//! let seg = segment(&map, &SegmentOptions { min_prominence: 0.1e-3, min_area: 1e-6 })?;
//! assert_eq!(seg.asperities().len(), 2);
//! let cap = asperity_cap(&map, &seg, 0, &CapOptions::default())?;
//! let (grid, exact) = (cap.cap(0.5e-3), Sphere::new(r)?.cap(0.5e-3));
//! assert!((grid.base_area / exact.base_area - 1.0).abs() < 0.02);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

pub mod cap;
mod error;
mod heightmap;
pub mod indicators;
pub mod io;
pub mod roads;
pub mod segment;
pub mod segment_split;
mod segment_taint;
pub mod segment_window;
pub mod sentinel;
pub mod synth;

pub use cap::{CapOptions, GridCap, asperity_cap};
pub use error::TextureError;
pub use heightmap::{HeightMap, MAX_POINTS};
pub use indicators::{Mpd, ThirdOctaveBand, mean_profile_depth, third_octave_spectrum};
pub use io::read_any;
pub use roads::{
    BrushedConcrete, ExposedAggregate, Microtexture, Pave, PorousAsphalt, RoadGrid, Tining,
    TiningDirection, WornChipSeal, brushed_concrete, exposed_aggregate, pave, porous_asphalt,
    tining, worn_chip_seal,
};
pub use segment::{Asperity, SegmentOptions, Segmentation, SummitFit, UNLABELLED, segment};
pub use segment_split::split_wide_tops;
pub use segment_window::{WindowFrame, WindowSegmentation, segment_window};
pub use sentinel::{Sentinel, find_sentinels};
pub use synth::{
    Aggregate, ChipShape, MAX_CHIPS, MIN_CHIP_CELLS, SelfAffine, aggregate, self_affine,
};
