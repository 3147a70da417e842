//! Synthetic road textures, reproducible from a seed.

// Numerical kernels index several arrays in step.
#![allow(clippy::needless_range_loop)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use rustfft::{FftPlanner, num_complex::Complex};

use tyreroad_core::validate;

use crate::error::TextureError;
use crate::heightmap::{HeightMap, check_size};

/// A self-affine (fractal) Gaussian surface described by its power spectrum.
///
/// The isotropic 2-D spectrum, with `q = |q|` the wavenumber (rad/m),
/// `q_L = 2π/λ_long` and `q_s = 2π/λ_short`:
///
/// ```text
/// C(q) = 1                       0 < q < q_L      (roll-off plateau)
/// C(q) = (q/q_L)^(−2(1+H))       q_L ≤ q ≤ q_s    (self-affine range)
/// C(q) = 0                       q > q_s or q = 0
/// ```
///
/// White Gaussian noise on the `nx × ny` grid is filtered by `√C` in the
/// Fourier domain (2-D FFT, periodic), transformed back, its mean removed,
/// and the result rescaled to the exact requested rms (`Sq`).
#[derive(Clone, Debug, PartialEq)]
pub struct SelfAffine {
    /// Points along x.
    pub nx: usize,
    /// Points along y.
    pub ny: usize,
    /// Spacing along x (m).
    pub dx: f64,
    /// Spacing along y (m).
    pub dy: f64,
    /// Root mean square height `Sq` (m).
    pub rms: f64,
    /// Hurst exponent `H`, in (0, 1].
    pub hurst: f64,
    /// Long cut-off (roll-off) wavelength `λ_long` (m).
    pub lambda_long: f64,
    /// Short cut-off wavelength `λ_short` (m), `< λ_long`.
    pub lambda_short: f64,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

/// One standard normal deviate (Box–Muller).
fn gauss(rng: &mut impl Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (std::f64::consts::TAU * u2).cos()
}

/// In-place 2-D FFT of a row-major `nx × ny` array.
pub(crate) fn fft2(data: &mut [Complex<f64>], nx: usize, ny: usize, inverse: bool) {
    let mut planner = FftPlanner::new();
    let (fx, fy) = if inverse {
        (planner.plan_fft_inverse(nx), planner.plan_fft_inverse(ny))
    } else {
        (planner.plan_fft_forward(nx), planner.plan_fft_forward(ny))
    };
    fx.process(data);
    let mut col = vec![Complex::new(0.0, 0.0); ny];
    for i in 0..nx {
        for j in 0..ny {
            col[j] = data[j * nx + i];
        }
        fy.process(&mut col);
        for j in 0..ny {
            data[j * nx + i] = col[j];
        }
    }
}

/// Signed FFT frequency index of bin `k` of `n`.
fn freq(k: usize, n: usize) -> f64 {
    if k <= n / 2 {
        k as f64
    } else {
        k as f64 - n as f64
    }
}

/// The largest Sq [`self_affine`] synthesises (m).
pub const MAX_SYNTH_RMS: f64 = 1.0;

/// Synthesise a self-affine surface (see [`SelfAffine`]).
///
/// # Errors
/// [`TextureError::InvalidParameter`] naming a spacing, `rms` (in
/// `(0, 1 m]`), `hurst` (in `(0, 1]`) or a wavelength out of its range
/// (`λ_short < λ_long`, both at least `2 max(dx, dy)`, the shortest
/// wavelength the grid holds in every direction);
/// [`TextureError::NotEnoughData`] when no wavenumber of the grid falls in
/// the band.
pub fn self_affine(p: &SelfAffine) -> Result<HeightMap, TextureError> {
    let n = check_self_affine(p)?;
    // A cut-off finer than the grid cuts nothing the grid holds: the
    // surface would stop at the grid's wavelengths, not at the one asked
    // for (0.01 mm on a 0.25 mm grid was accepted and meant nothing).
    if p.lambda_short < 2.0 * p.dx.max(p.dy) {
        return Err(TextureError::InvalidParameter {
            name: "lambda_short",
            value: p.lambda_short,
            requirement: "at least two grid spacings (the coarser), the shortest wavelength \
                          the grid holds in every direction",
        });
    }
    draw_self_affine(p, n)
}

/// A self-affine roughness down to `λ_short` or to the grid's shortest
/// wavelength, whichever is longer: the road kinds' fine roughness
/// ([`crate::roads::Microtexture`], the brushed striations), whose
/// wavelengths are the material's and not chosen for the grid. Otherwise
/// checked as [`self_affine`].
pub(crate) fn self_affine_to_grid(p: &SelfAffine) -> Result<HeightMap, TextureError> {
    let n = check_self_affine(p)?;
    draw_self_affine(p, n)
}

/// Every check of [`self_affine`] but `λ_short` against the grid; returns
/// the number of points.
fn check_self_affine(p: &SelfAffine) -> Result<usize, TextureError> {
    let n = check_size(p.nx, p.ny)?;
    validate::positive("dx", p.dx)?;
    validate::positive("dy", p.dy)?;
    validate::positive("rms", p.rms)?;
    validate::positive("lambda_short", p.lambda_short)?;
    validate::positive("lambda_long", p.lambda_long)?;
    if !(p.hurst > 0.0 && p.hurst <= 1.0) {
        return Err(TextureError::InvalidParameter {
            name: "hurst",
            value: p.hurst,
            requirement: "in (0, 1]",
        });
    }
    if p.lambda_short >= p.lambda_long {
        return Err(TextureError::InvalidParameter {
            name: "lambda_short",
            value: p.lambda_short,
            requirement: "< lambda_long",
        });
    }
    // A 1e300 m Sq overflowed nothing here but every solve after it: no
    // surface texture is a metre rough.
    if p.rms > MAX_SYNTH_RMS {
        return Err(TextureError::InvalidParameter {
            name: "rms",
            value: p.rms,
            requirement: "at most 1 m: the Sq of a surface texture",
        });
    }
    // With the roll-off below the grid's shortest wavelength every
    // wavenumber lies on the plateau: white noise, not the self-affine
    // spectrum that was asked for.
    if p.lambda_long < 2.0 * p.dx.max(p.dy) {
        return Err(TextureError::InvalidParameter {
            name: "lambda_long",
            value: p.lambda_long,
            requirement: "at least two grid spacings, the shortest wavelength the grid holds",
        });
    }
    Ok(n)
}

/// Draws the checked surface `p` of `n` points.
fn draw_self_affine(p: &SelfAffine, n: usize) -> Result<HeightMap, TextureError> {
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let mut data: Vec<Complex<f64>> = (0..n).map(|_| Complex::new(gauss(&mut rng), 0.0)).collect();
    fft2(&mut data, p.nx, p.ny, false);
    let tau = std::f64::consts::TAU;
    let (ql, qs) = (tau / p.lambda_long, tau / p.lambda_short);
    let (lx, ly) = (p.nx as f64 * p.dx, p.ny as f64 * p.dy);
    let expo = -(1.0 + p.hurst); // sqrt of C
    for j in 0..p.ny {
        let qy = tau * freq(j, p.ny) / ly;
        for i in 0..p.nx {
            let qx = tau * freq(i, p.nx) / lx;
            let q = (qx * qx + qy * qy).sqrt();
            let a = if q == 0.0 || q > qs {
                0.0
            } else if q < ql {
                1.0
            } else {
                (q / ql).powf(expo)
            };
            data[j * p.nx + i] *= a;
        }
    }
    fft2(&mut data, p.nx, p.ny, true);
    let mut h: Vec<f64> = data.iter().map(|c| c.re).collect();
    let mean = h.iter().sum::<f64>() / n as f64;
    let ms = h.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / n as f64;
    if !(ms > 0.0 && ms.is_finite()) {
        return Err(TextureError::NotEnoughData(
            "no wavenumber of the grid falls in the requested band (check dx, λ_short, λ_long)"
                .into(),
        ));
    }
    let s = p.rms / ms.sqrt();
    for v in &mut h {
        *v = (*v - mean) * s;
    }
    HeightMap::new(p.nx, p.ny, p.dx, p.dy, h)
}

/// The shape of a chipping.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum ChipShape {
    /// An ellipsoid with semi-axes `a ≥ b` (horizontal) and `c` (vertical
    /// before tilting).
    Ellipsoid,
    /// A rounded polyhedron: the box `|u|, |v|, |w| ≤ 1` (in units of the
    /// semi-axes) cut by `cuts` random planes at distance 0.7–0.95 from the
    /// centre (crushed-stone facets), its edges rounded by a soft minimum of
    /// the face distances over a length `rounding` (relative to the
    /// semi-axes, e.g. 0.1).
    Polyhedron {
        /// Number of random cutting planes.
        cuts: usize,
        /// Edge rounding length relative to the semi-axes (> 0).
        rounding: f64,
    },
}

/// An aggregate surface: rigid chippings on a base plane, like a dense
/// asphalt or a surface dressing.
///
/// Each chipping gets:
///
/// - a size `s` drawn from the grading curve: `u` uniform between the first
///   and last cumulative percentages, `s` by linear interpolation of the
///   curve (the grading is used as a number distribution);
/// - semi-axes `a = s/2 · e` (long, `e` uniform in `elongation`), `b = s/2`,
///   `c = s/2 · f` (`f` uniform in `flatness`);
/// - an orientation: azimuth uniform in [0, 2π), then a tilt uniform in
///   [0, `max_tilt`] about a random horizontal axis;
/// - a position uniform over the map widened by the largest half-size (so the
///   edges are covered as densely as the middle);
/// - an embedding: a fraction `ε` (uniform in `embedding`) of its vertical
///   extent lies below the base plane `z = 0`.
///
/// Chippings are added until their summed plan areas `π a b` reach
/// `coverage` times the map area. The height map is the maximum of the base
/// plane and of the chippings' upper surfaces at each grid point.
#[derive(Clone, Debug, PartialEq)]
pub struct Aggregate {
    /// Points along x.
    pub nx: usize,
    /// Points along y.
    pub ny: usize,
    /// Spacing along x (m).
    pub dx: f64,
    /// Spacing along y (m).
    pub dy: f64,
    /// Grading curve: `(sieve size in m, cumulative % passing)`, sizes
    /// increasing, percentages non-decreasing in [0, 100], last > first.
    pub grading: Vec<(f64, f64)>,
    /// Summed plan area of the chippings over the map area (e.g. 1.2).
    pub coverage: f64,
    /// Range of the elongation `a/b` (≥ 1).
    pub elongation: (f64, f64),
    /// Range of the flatness `c/b` (> 0).
    pub flatness: (f64, f64),
    /// Range of the embedded fraction of the vertical extent, in [0, 1).
    pub embedding: (f64, f64),
    /// Largest tilt of a chipping's short axis from the vertical (rad).
    pub max_tilt: f64,
    /// Shape of the chippings.
    pub shape: ChipShape,
    /// Seed of the ChaCha8 generator.
    pub seed: u64,
}

impl Aggregate {
    /// A surface-dressing-like default for the given grid and grading:
    /// coverage 1.3, elongation 1–1.5, flatness 0.5–0.8, embedding 30–50 %,
    /// tilt up to 0.3 rad, ellipsoids.
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        grading: Vec<(f64, f64)>,
        seed: u64,
    ) -> Self {
        Self {
            nx,
            ny,
            dx,
            dy,
            grading,
            coverage: 1.3,
            elongation: (1.0, 1.5),
            flatness: (0.5, 0.8),
            embedding: (0.3, 0.5),
            max_tilt: 0.3,
            shape: ChipShape::Ellipsoid,
            seed,
        }
    }

    /// Grading of a 4/6.3 mm chipping (10 % passing 4 mm, 90 % passing 6.3 mm,
    /// 0 and 100 % at 2.8 and 8 mm).
    pub fn grading_4_6() -> Vec<(f64, f64)> {
        vec![(2.8e-3, 0.0), (4e-3, 10.0), (6.3e-3, 90.0), (8e-3, 100.0)]
    }

    /// Grading of a 6/10 mm chipping (0, 10, 90, 100 % passing 4, 6.3, 10,
    /// 12.5 mm).
    pub fn grading_6_10() -> Vec<(f64, f64)> {
        vec![(4e-3, 0.0), (6.3e-3, 10.0), (10e-3, 90.0), (12.5e-3, 100.0)]
    }
}

fn check_range(name: &'static str, r: (f64, f64), lo: f64, hi: f64) -> Result<(), TextureError> {
    validate::finite(name, r.0)?;
    validate::finite(name, r.1)?;
    if r.0 < lo || r.1 > hi || r.0 > r.1 {
        return Err(TextureError::InvalidParameter {
            name,
            value: if r.0 < lo || r.0 > r.1 { r.0 } else { r.1 },
            requirement: "an ordered range within its bounds",
        });
    }
    Ok(())
}

fn uniform(rng: &mut impl Rng, r: (f64, f64)) -> f64 {
    r.0 + (r.1 - r.0) * rng.random::<f64>()
}

/// A chipping in its own frame: columns of `rot` are its axes in the world.
struct Chip {
    centre: [f64; 2],
    axes: [f64; 3],
    rot: [[f64; 3]; 3],
    /// Cutting planes (unit normal in normalised coordinates, distance).
    planes: Vec<([f64; 3], f64)>,
    rounding: f64,
}

impl Chip {
    /// Top and bottom of the chip along the vertical through `(x, y)`,
    /// relative to its centre height; `None` outside.
    fn span(&self, x: f64, y: f64) -> Option<(f64, f64)> {
        let (dx, dy) = (x - self.centre[0], y - self.centre[1]);
        // Normalised coordinates u = D⁻¹ Rᵀ p: line u0 + t w with p = (dx, dy, t).
        let r = &self.rot;
        let mut u0 = [0.0; 3];
        let mut w = [0.0; 3];
        for k in 0..3 {
            u0[k] = (r[0][k] * dx + r[1][k] * dy) / self.axes[k];
            w[k] = r[2][k] / self.axes[k];
        }
        if self.planes.is_empty() {
            // Ellipsoid |u0 + t w|² = 1.
            let a = w.iter().map(|v| v * v).sum::<f64>();
            let b = u0.iter().zip(&w).map(|(p, q)| p * q).sum::<f64>();
            let c = u0.iter().map(|v| v * v).sum::<f64>() - 1.0;
            let disc = b * b - a * c;
            if disc <= 0.0 {
                return None;
            }
            let s = disc.sqrt();
            return Some(((-b + s) / a, (-b - s) / a));
        }
        // Polyhedron: t ≤ (d − n·u0)/(n·w) for n·w > 0, ≥ for n·w < 0,
        // soft minimum / maximum over the faces for rounded edges.
        let rr = self.rounding;
        let (mut top_min, mut bot_max) = (f64::INFINITY, f64::NEG_INFINITY);
        let mut ts = Vec::with_capacity(self.planes.len());
        for (n, d) in &self.planes {
            let nw = n[0] * w[0] + n[1] * w[1] + n[2] * w[2];
            let nu = n[0] * u0[0] + n[1] * u0[1] + n[2] * u0[2];
            if nw.abs() < 1e-12 {
                if nu > *d {
                    return None;
                }
                continue;
            }
            // Scale the distance to t units by |w| so that rounding is
            // expressed in normalised length.
            let t = (d - nu) / nw;
            ts.push((t, nw));
            if nw > 0.0 {
                top_min = top_min.min(t);
            } else {
                bot_max = bot_max.max(t);
            }
        }
        if top_min <= bot_max {
            return None;
        }
        let wn = w.iter().map(|v| v * v).sum::<f64>().sqrt();
        let scale = rr / wn;
        let (mut st, mut sb) = (0.0, 0.0);
        for (t, nw) in ts {
            if nw > 0.0 {
                st += (-(t - top_min) / scale).exp();
            } else {
                sb += ((t - bot_max) / scale).exp();
            }
        }
        let top = top_min - scale * st.ln();
        let bot = bot_max + scale * sb.ln();
        (top > bot).then_some((top, bot))
    }
}

fn rotation(azimuth: f64, tilt: f64, tilt_axis: f64) -> [[f64; 3]; 3] {
    // R = Rz(tilt_axis) · Rx(tilt) · Rz(azimuth − tilt_axis)
    let rz = |a: f64| {
        let (s, c) = a.sin_cos();
        [[c, -s, 0.0], [s, c, 0.0], [0.0, 0.0, 1.0]]
    };
    let (s, c) = tilt.sin_cos();
    let rx = [[1.0, 0.0, 0.0], [0.0, c, -s], [0.0, s, c]];
    let mul = |a: [[f64; 3]; 3], b: [[f64; 3]; 3]| {
        let mut m = [[0.0; 3]; 3];
        for i in 0..3 {
            for j in 0..3 {
                m[i][j] = (0..3).map(|k| a[i][k] * b[k][j]).sum();
            }
        }
        m
    };
    mul(mul(rz(tilt_axis), rx), rz(azimuth - tilt_axis))
}

/// The fewest grid spacings (the coarser of `dx`, `dy`) the smallest
/// chipping of an [`Aggregate`] must span: a disc four cells across holds
/// about a dozen grid points, enough to draw a rounded top, and bounds the
/// number of chippings to at most `coverage / (4π)` per cell.
pub const MIN_CHIP_CELLS: f64 = 4.0;

/// The most chippings one aggregate map draws ([`aggregate`] refuses a map
/// whose coverage needs more: `coverage × area / mean chipping area`).
pub const MAX_CHIPS: usize = 10_000_000;

/// The error of a map needing `count` chippings, more than [`MAX_CHIPS`].
fn too_many_chips(count: f64) -> TextureError {
    TextureError::InvalidParameter {
        name: "chippings to draw (coverage × map area / mean chipping area)",
        value: count,
        requirement: "at most 10 million: synthesise a smaller map (or tile it) or lower the coverage",
    }
}

/// The chipping size at cumulative percentage `u` of the grading `g`
/// (sizes interpolated linearly between its points).
fn grading_size(g: &[(f64, f64)], u: f64) -> f64 {
    let k = g
        .iter()
        .position(|&(_, c)| c >= u)
        .unwrap_or(g.len() - 1)
        .max(1);
    let ((s0, p0), (s1, p1)) = (g[k - 1], g[k]);
    if p1 > p0 {
        s0 + (s1 - s0) * (u - p0) / (p1 - p0)
    } else {
        s1
    }
}

/// The mean plan area `π a b` of a chipping drawn from grading `g` between
/// percentages `c0` and `c1` (`b` half its size, `a = b e`, `e` uniform in
/// `elongation`): the midpoint rule on 256 percentages.
fn mean_chip_area(g: &[(f64, f64)], (c0, c1): (f64, f64), elongation: (f64, f64)) -> f64 {
    const N: usize = 256;
    let mean_square = (0..N)
        .map(|k| grading_size(g, c0 + (c1 - c0) * (k as f64 + 0.5) / N as f64).powi(2))
        .sum::<f64>()
        / N as f64;
    0.25 * std::f64::consts::PI * mean_square * 0.5 * (elongation.0 + elongation.1)
}

/// Synthesise an aggregate surface (see [`Aggregate`]).
///
/// # Errors
/// [`TextureError::InvalidParameter`] naming a spacing, the coverage (in
/// `(0, 20]`), a range or the grading out of its bounds;
/// [`TextureError::Unresolved`] when the grading's smallest chipping spans
/// fewer than [`MIN_CHIP_CELLS`] grid spacings.
pub fn aggregate(p: &Aggregate) -> Result<HeightMap, TextureError> {
    let n = check_size(p.nx, p.ny)?;
    validate::positive("dx", p.dx)?;
    validate::positive("dy", p.dy)?;
    validate::positive("coverage", p.coverage)?;
    if p.coverage > 20.0 {
        return Err(TextureError::InvalidParameter {
            name: "coverage",
            value: p.coverage,
            requirement: "≤ 20",
        });
    }
    check_range("elongation", p.elongation, 1.0, 10.0)?;
    check_range("flatness", p.flatness, 1e-3, 10.0)?;
    check_range("embedding", p.embedding, 0.0, 0.99)?;
    check_range(
        "max_tilt",
        (0.0, p.max_tilt),
        0.0,
        std::f64::consts::FRAC_PI_2,
    )?;
    let g = &p.grading;
    if g.len() < 2 {
        return Err(TextureError::InvalidParameter {
            name: "grading points",
            value: g.len() as f64,
            requirement: "≥ 2",
        });
    }
    for (k, &(s, c)) in g.iter().enumerate() {
        validate::positive("grading size", s)?;
        check_range("grading percentage", (c, c), 0.0, 100.0)?;
        if k > 0 && (s <= g[k - 1].0 || c < g[k - 1].1) {
            return Err(TextureError::InvalidParameter {
                name: "grading",
                value: s,
                requirement: "sizes increasing and percentages non-decreasing",
            });
        }
    }
    let (c0, c1) = (g[0].1, g[g.len() - 1].1);
    if c1 <= c0 {
        return Err(TextureError::InvalidParameter {
            name: "grading percentage",
            value: c1,
            requirement: "last > first",
        });
    }
    // The smallest chipping the grading draws: the last size at the first
    // percentage (sizes are interpolated above it). Narrower than a few
    // cells, a chipping is not drawn but sampled at a point or missed, and
    // the chippings needed to reach the coverage outnumber the cells (a
    // 20 × 20 grid at 1 m asked for ten million 4 mm chippings: a hang).
    let smallest = g
        .iter()
        .take_while(|&&(_, c)| c <= c0)
        .last()
        .map_or(g[0].0, |&(s, _)| s);
    let spacing = p.dx.max(p.dy);
    if smallest < MIN_CHIP_CELLS * spacing {
        return Err(TextureError::Unresolved {
            what: "smallest chipping",
            size: smallest,
            spacing,
            min_cells: MIN_CHIP_CELLS,
        });
    }
    let (rounding, cuts) = match p.shape {
        ChipShape::Ellipsoid => (0.0, 0),
        ChipShape::Polyhedron { cuts, rounding } => {
            validate::positive("rounding", rounding)?;
            if cuts > 64 {
                return Err(TextureError::InvalidParameter {
                    name: "cuts",
                    value: cuts as f64,
                    requirement: "≤ 64",
                });
            }
            (rounding, cuts)
        }
    };
    let smax = g[g.len() - 1].0 * p.elongation.1;
    let (lx, ly) = (p.nx as f64 * p.dx, p.ny as f64 * p.dy);
    let margin = 0.5 * smax;
    let area = lx * ly;
    // Refused before anything is drawn: a map needing more chippings than
    // the generator draws would stop short of its coverage without a word.
    let expected = p.coverage * area / mean_chip_area(g, (c0, c1), p.elongation);
    if expected > MAX_CHIPS as f64 {
        return Err(too_many_chips(expected));
    }
    let mut rng = ChaCha8Rng::seed_from_u64(p.seed);
    let mut h = vec![0.0f64; n];
    let mut placed = 0.0;
    let mut count = 0usize;
    while placed < p.coverage * area {
        if count == MAX_CHIPS {
            // The draw outran its expectation (a few per cent at most).
            return Err(too_many_chips(count as f64));
        }
        count += 1;
        let s = grading_size(g, c0 + (c1 - c0) * rng.random::<f64>());
        let b = 0.5 * s;
        let axes = [
            b * uniform(&mut rng, p.elongation),
            b,
            b * uniform(&mut rng, p.flatness),
        ];
        let az = std::f64::consts::TAU * rng.random::<f64>();
        let tilt = p.max_tilt * rng.random::<f64>();
        let tilt_axis = std::f64::consts::TAU * rng.random::<f64>();
        let rot = rotation(az, tilt, tilt_axis);
        let centre = [
            -margin + (lx + 2.0 * margin) * rng.random::<f64>(),
            -margin + (ly + 2.0 * margin) * rng.random::<f64>(),
        ];
        let mut planes = Vec::new();
        if cuts > 0 || rounding > 0.0 {
            for k in 0..3 {
                let mut e = [0.0; 3];
                e[k] = 1.0;
                planes.push((e, 1.0));
                e[k] = -1.0;
                planes.push((e, 1.0));
            }
            for _ in 0..cuts {
                let v = [gauss(&mut rng), gauss(&mut rng), gauss(&mut rng)];
                let norm = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt().max(1e-12);
                let d = uniform(&mut rng, (0.7, 0.95));
                planes.push(([v[0] / norm, v[1] / norm, v[2] / norm], d));
            }
        }
        let emb = uniform(&mut rng, p.embedding);
        let chip = Chip {
            centre,
            axes,
            rot,
            planes,
            rounding,
        };
        placed += std::f64::consts::PI * axes[0] * axes[1];
        // Horizontal half-extent of the bounding box (covers the box corners).
        let ext = |row: usize| (0..3).map(|k| (rot[row][k] * axes[k]).abs()).sum::<f64>();
        let (ex, ey) = (ext(0), ext(1));
        let i0 = ((centre[0] - ex) / p.dx).floor().max(0.0) as usize;
        let i1 = (((centre[0] + ex) / p.dx).ceil().max(-1.0) + 1.0).min(p.nx as f64) as usize;
        let j0 = ((centre[1] - ey) / p.dy).floor().max(0.0) as usize;
        let j1 = (((centre[1] + ey) / p.dy).ceil().max(-1.0) + 1.0).min(p.ny as f64) as usize;
        if i0 >= i1 || j0 >= j1 {
            continue;
        }
        // Vertical extent of the chip (on a fine sampling of its footprint,
        // independent of the map's clipping).
        let (mut top, mut bot) = (f64::NEG_INFINITY, f64::INFINITY);
        let m = 24;
        for a in 0..=m {
            for c in 0..=m {
                let x = centre[0] - ex + 2.0 * ex * a as f64 / m as f64;
                let y = centre[1] - ey + 2.0 * ey * c as f64 / m as f64;
                if let Some((t, b)) = chip.span(x, y) {
                    top = top.max(t);
                    bot = bot.min(b);
                }
            }
        }
        if !(top > bot) {
            continue;
        }
        // Fraction `emb` of [bot, top] below z = 0.
        let zc = -bot - emb * (top - bot);
        for j in j0..j1 {
            for i in i0..i1 {
                if let Some((t, _)) = chip.span(i as f64 * p.dx, j as f64 * p.dy) {
                    let z = zc + t;
                    let cell = &mut h[j * p.nx + i];
                    if z > *cell {
                        *cell = z;
                    }
                }
            }
        }
    }
    HeightMap::new(p.nx, p.ny, p.dx, p.dy, h)
}
