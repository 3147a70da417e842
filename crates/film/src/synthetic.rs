//! Synthetic films: pressure maps (core fields), Hertzian prints, rendering
//! through the calibration to a scan, and the synthetic round trip of an
//! experiment.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_core::{Field, Grid};

use crate::analysis::{AnalysisOptions, Estimator, analyse};
use crate::calibration::{Calibration, FilmResponse, LlwCurve, Scanner};
use crate::compare::{Comparison, ModelRow, compare, layout_of, loads, measurements, rows_at_load};
use crate::error::{FilmError, Result, check_non_negative, check_positive};
use crate::layout::{Frame, match_layout, square_pixel_size};
use crate::scan::Scan;

/// The grid of a pressure map of `nx × ny` square pixels of side
/// `pixel_size` (m), centred on the film origin.
///
/// A film pressure map is a core [`Field`] (Pa) on such a grid: cell
/// `(i, j)` centred at film coordinates `(x0 + i·s, y0 + j·s)`, x right and
/// y up, row `j = 0` at the bottom. Scans run the other way (row 0 at the
/// top); [`render`] does the row flip and [`Frame::of_grid`] gives the scan's
/// frame.
pub fn pixel_grid(nx: usize, ny: usize, pixel_size: f64) -> Result<Grid> {
    check_positive("pixel size", pixel_size)?;
    Ok(Grid::centered(nx, ny, pixel_size, pixel_size)?)
}

/// The grid of a pressure map covering `[x_min, x_max] × [y_min, y_max]`
/// (m) with square pixels of side `pixel_size`: `⌈width / s⌉` pixels (at
/// least 1) each way, centred on that rectangle.
pub fn covering_grid(
    x_min: f64,
    x_max: f64,
    y_min: f64,
    y_max: f64,
    pixel_size: f64,
) -> Result<Grid> {
    let s = check_positive("pixel size", pixel_size)?;
    // Bad rectangles end in the grid's errors, not in a huge allocation: an
    // infinite or too wide span saturates the count past MAX_CELLS, a NaN
    // gives one cell at a NaN origin.
    let nx = ((x_max - x_min) / s).ceil().max(1.0) as usize;
    let ny = ((y_max - y_min) / s).ceil().max(1.0) as usize;
    let grid = Grid::new(nx, ny, s, s)?;
    let x0 = 0.5 * (x_min + x_max) - 0.5 * (nx as f64 - 1.0) * s;
    let y0 = 0.5 * (y_min + y_max) - 0.5 * (ny as f64 - 1.0) * s;
    Ok(grid.with_origin([x0, y0])?)
}

/// `map` with Hertzian prints added (pressures sum where prints overlap;
/// invalid cells of a masked map stay invalid).
pub fn add_hertz(map: Field, prints: &[HertzPrint]) -> Result<Field> {
    let grid = map.grid().clone();
    let mask = map.mask().map(<[bool]>::to_vec);
    let mut values = map.into_values();
    let (nx, ny) = (grid.nx(), grid.ny());
    let [x0, y0] = grid.origin();
    let (dx, dy) = (grid.dx(), grid.dy());
    // First and one-past-last cell whose centre can fall in [lo, hi].
    let span = |lo: f64, hi: f64, origin: f64, d: f64, n: usize| {
        let first = (((lo - origin) / d + 0.5).floor().max(0.0) as usize).min(n);
        let end = (((hi - origin) / d + 0.5).ceil().max(0.0) as usize).min(n);
        first..end
    };
    for h in prints {
        check_positive("Hertz contact radius", h.radius)?;
        check_non_negative("Hertz force", h.force)?;
        if !(h.x.is_finite() && h.y.is_finite()) {
            return Err(FilmError::InvalidParameter {
                name: "Hertz print position",
                value: if h.x.is_finite() { h.y } else { h.x },
                requirement: "finite",
            });
        }
        let p0 = h.peak_pressure();
        if !p0.is_finite() {
            return Err(FilmError::InvalidParameter {
                name: "Hertz peak pressure",
                value: p0,
                requirement: "finite (force / radius² too large)",
            });
        }
        let a2 = h.radius * h.radius;
        let columns = span(h.x - h.radius, h.x + h.radius, x0, dx, nx);
        for j in span(h.y - h.radius, h.y + h.radius, y0, dy, ny) {
            let y = grid.y(j);
            for i in columns.clone() {
                let r2 = (grid.x(i) - h.x).powi(2) + (y - h.y).powi(2);
                if r2 < a2 {
                    values[grid.index(i, j)] += p0 * (1.0 - r2 / a2).sqrt();
                }
            }
        }
    }
    Ok(match mask {
        Some(mask) => Field::with_mask(grid, values, mask)?,
        None => Field::new(grid, values)?,
    })
}

/// A Hertzian print: centre (m), force `P` (N) and contact radius `a` (m);
/// pressure `p(r) = 3P/(2πa²)·√(1 − r²/a²)` for `r < a`.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzPrint {
    /// Centre x, m.
    pub x: f64,
    /// Centre y, m.
    pub y: f64,
    /// Force, N.
    pub force: f64,
    /// Contact radius, m.
    pub radius: f64,
}

impl HertzPrint {
    /// Peak pressure `p0 = 3P/(2πa²)`, Pa.
    pub fn peak_pressure(&self) -> f64 {
        3.0 * self.force / (2.0 * std::f64::consts::PI * self.radius * self.radius)
    }
}

/// The pressure map (Pa) of Hertzian prints on `nx × ny` pixels of side
/// `pixel_size` centred on the film origin (see [`pixel_grid`],
/// [`add_hertz`]).
pub fn hertz_pressure_map(
    prints: &[HertzPrint],
    nx: usize,
    ny: usize,
    pixel_size: f64,
) -> Result<Field> {
    add_hertz(Field::zeros(pixel_grid(nx, ny, pixel_size)?), prints)
}

/// How a film is rendered to a scan.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RenderOptions {
    /// Scanner relation between density and grey.
    pub scanner: Scanner,
    /// Density of unreacted film (pressure below the calibrated range);
    /// must be below the calibration's lowest density for prints to show.
    pub background_density: f64,
    /// Standard deviation of the film grain, in density units, independent
    /// per pixel (added before the blur).
    pub grain_sigma: f64,
    /// Gaussian blur of the scanner optics, standard deviation in pixels
    /// (applied to grey levels, i.e. to reflected light). 0 for none.
    pub blur_sigma_px: f64,
    /// Quantisation: 8 or 16 bit.
    pub bit_depth: u8,
    /// Seed of the grain noise (the render is reproducible).
    pub seed: u64,
}

impl Default for RenderOptions {
    fn default() -> Self {
        Self {
            scanner: Scanner::default(),
            background_density: 0.08,
            grain_sigma: 0.0,
            blur_sigma_px: 0.0,
            bit_depth: 16,
            seed: 1,
        }
    }
}

/// Renders a pressure map to a scanned film.
///
/// Per pixel: below the calibrated range the film does not react (background
/// density); inside it the calibration's response; above it the film
/// saturates at the top response. The density gets grain noise, is turned
/// into grey by the scanner relation, blurred, clamped to `[0, 1]` and
/// quantised. Invalid cells of a masked map render as unreacted film. The
/// scan carries the map's pixel size (the map's pixels must be square); its
/// row 0 is the map's top row `ny − 1` (see [`Frame::of_grid`]).
pub fn render(map: &Field, response: &FilmResponse, options: &RenderOptions) -> Result<Scan> {
    let grid = map.grid();
    let pixel_size = square_pixel_size(grid)?;
    let (nx, ny) = (grid.nx(), grid.ny());
    check_non_negative("grain sigma", options.grain_sigma)?;
    check_non_negative("blur sigma", options.blur_sigma_px)?;
    options.scanner.check()?;
    response.scanner.check()?;
    if !options.background_density.is_finite() {
        return Err(FilmError::InvalidParameter {
            name: "background density",
            value: options.background_density,
            requirement: "finite",
        });
    }
    let levels = match options.bit_depth {
        8 => 255.0,
        16 => 65535.0,
        b => {
            return Err(FilmError::InvalidParameter {
                name: "bit depth",
                value: b as f64,
                requirement: "8 or 16",
            });
        }
    };
    let cal = &response.calibration;
    let scanner = &options.scanner;
    let mut rng = ChaCha8Rng::seed_from_u64(options.seed);
    let mut grey: Vec<f64> = Vec::with_capacity(grid.len());
    // Image rows run downward, the map's rows upward.
    let image_order = (0..ny).rev().flat_map(|j| map.row(j).iter().copied());
    for p in image_order {
        let mut d = match cal.response_clamped(p) {
            Some(r) => match cal.response() {
                crate::calibration::Response::Density => r,
                crate::calibration::Response::Grey => response.scanner.density(r),
            },
            None => options.background_density,
        };
        if options.grain_sigma > 0.0 {
            d += options.grain_sigma * gaussian(&mut rng);
        }
        grey.push(scanner.grey(d));
    }
    if options.blur_sigma_px > 0.0 {
        gaussian_blur(&mut grey, nx, ny, options.blur_sigma_px);
    }
    let data: Vec<f32> = grey
        .iter()
        .map(|&g| ((g.clamp(0.0, 1.0) * levels).round() / levels) as f32)
        .collect();
    Scan::from_grey(nx, ny, data, Some(pixel_size), options.bit_depth)
}

/// A standard normal deviate (Box–Muller).
fn gaussian(rng: &mut ChaCha8Rng) -> f64 {
    let u1: f64 = 1.0 - rng.random::<f64>(); // (0, 1]
    let u2: f64 = rng.random::<f64>();
    (-2.0 * u1.ln()).sqrt() * (2.0 * std::f64::consts::PI * u2).cos()
}

/// Separable Gaussian blur, edges clamped.
fn gaussian_blur(img: &mut [f64], w: usize, h: usize, sigma: f64) {
    let r = (3.0 * sigma).ceil() as isize;
    let mut k: Vec<f64> = (-r..=r)
        .map(|i| (-(i * i) as f64 / (2.0 * sigma * sigma)).exp())
        .collect();
    let sum: f64 = k.iter().sum();
    k.iter_mut().for_each(|v| *v /= sum);
    let mut tmp = vec![0.0; img.len()];
    for y in 0..h {
        let row = &img[y * w..(y + 1) * w];
        for x in 0..w {
            let mut acc = 0.0;
            for (t, kv) in k.iter().enumerate() {
                let xx = (x as isize + t as isize - r).clamp(0, w as isize - 1) as usize;
                acc += kv * row[xx];
            }
            tmp[y * w + x] = acc;
        }
    }
    for y in 0..h {
        for x in 0..w {
            let mut acc = 0.0;
            for (t, kv) in k.iter().enumerate() {
                let yy = (y as isize + t as isize - r).clamp(0, h as isize - 1) as usize;
                acc += kv * tmp[yy * w + x];
            }
            img[y * w + x] = acc;
        }
    }
}

/// Options of the synthetic round trip ([`synthetic_round_trip`]).
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticOptions {
    /// The film (calibration and scanner) used both to render and analyse.
    pub response: FilmResponse,
    /// Pixel size of the synthetic scan, m.
    pub pixel_size: f64,
    /// Margin around the prints, m.
    pub margin: f64,
    /// Rendering (noise, blur, bit depth, seed).
    pub render: RenderOptions,
    /// Analysis options.
    pub analysis: AnalysisOptions,
}

impl SyntheticOptions {
    /// LLW curve B, 25 µm pixels (about 1000 dpi), 5 mm margin, 16-bit scan,
    /// grain 0.01 density, blur 1 px, threshold half-way to the calibration
    /// floor.
    pub fn llw_default() -> Result<Self> {
        Ok(Self {
            response: FilmResponse::new(Calibration::llw(LlwCurve::B)?, Scanner::default()),
            pixel_size: 25e-6,
            margin: 5e-3,
            render: RenderOptions {
                grain_sigma: 0.01,
                blur_sigma_px: 1.0,
                ..RenderOptions::default()
            },
            analysis: AnalysisOptions {
                threshold: crate::analysis::Threshold::MidwayToFloor,
                ..AnalysisOptions::default()
            },
        })
    }
}

/// The synthetic round trip at one load, by each estimator.
#[derive(Debug, Clone, PartialEq)]
pub struct SyntheticLoad {
    /// Total load, N.
    pub load_n: f64,
    /// The paper's estimator ([`Estimator::MeanGrey`]).
    pub mean_grey: Comparison,
    /// Mean of per-pixel pressures ([`Estimator::PixelMean`]).
    pub pixel_mean: Comparison,
    /// Hertzian profile fit ([`Estimator::HertzFit`]).
    pub hertz_fit: Comparison,
}

impl SyntheticLoad {
    /// The comparison of one estimator.
    pub fn by(&self, estimator: Estimator) -> &Comparison {
        match estimator {
            Estimator::MeanGrey => &self.mean_grey,
            Estimator::PixelMean => &self.pixel_mean,
            Estimator::HertzFit => &self.hertz_fit,
        }
    }
}

/// Synthetic round trip of an experiment given by model rows
/// (`load, indenter, x, y, force, radius`, e.g. the paper's 25 balls): for
/// each load, Hertzian prints of the model forces and radii are rendered to
/// a film scan, analysed, matched to the model layout and compared with the
/// model. The Table 1 statistics then measure the post-processing alone
/// (calibration known exactly).
pub fn synthetic_round_trip(
    rows: &[ModelRow],
    options: &SyntheticOptions,
) -> Result<Vec<SyntheticLoad>> {
    check_positive("pixel size", options.pixel_size)?;
    check_non_negative("margin", options.margin)?;
    let mut out = Vec::new();
    for load in loads(rows) {
        let model = rows_at_load(rows, load);
        let layout = layout_of(&model)?;
        let prints: Vec<HertzPrint> = model
            .iter()
            .map(|r| HertzPrint {
                x: r.x_m,
                y: r.y_m,
                force: r.force_n,
                radius: r.radius_m,
            })
            .collect();
        let (mut x0, mut x1, mut y0, mut y1) = (f64::MAX, f64::MIN, f64::MAX, f64::MIN);
        for p in &prints {
            x0 = x0.min(p.x - p.radius);
            x1 = x1.max(p.x + p.radius);
            y0 = y0.min(p.y - p.radius);
            y1 = y1.max(p.y + p.radius);
        }
        let m = options.margin;
        let grid = covering_grid(x0 - m, x1 + m, y0 - m, y1 + m, options.pixel_size)?;
        let frame = Frame::of_grid(&grid)?;
        let map = add_hertz(Field::zeros(grid), &prints)?;
        let scan = render(&map, &options.response, &options.render)?;
        let det = analyse(&scan, &options.response, &options.analysis)?;
        let matching = match_layout(&det, &layout, frame.origin(), None)?;
        let cmp = |e: Estimator| -> Result<Comparison> {
            compare(load, &measurements(&det, &matching, e)?, &model)
        };
        out.push(SyntheticLoad {
            load_n: load,
            mean_grey: cmp(Estimator::MeanGrey)?,
            pixel_mean: cmp(Estimator::PixelMean)?,
            hertz_fit: cmp(Estimator::HertzFit)?,
        });
    }
    Ok(out)
}

/// Model rows of the paper's experiment from Hertz alone (no interaction):
/// 25 balls of radius `ball_radius` on the [`crate::Layout::paper_grid`]
/// at 10 mm pitch, each carrying `load / 25`, contact radius
/// `a = (3 P R / (4 E*))^(1/3)` with `E* = E / (1 − ν²)`. A stand-in for the
/// static model runner's CSV when only this crate is at hand.
pub fn paper_hertz_rows(loads_n: &[f64], e_eq: f64, nu: f64, ball_radius: f64) -> Vec<ModelRow> {
    let e_star = e_eq / (1.0 - nu * nu);
    let layout = crate::layout::Layout::paper_grid(10e-3);
    let mut rows = Vec::new();
    for &load in loads_n {
        let p = load / 25.0;
        let a = (3.0 * p * ball_radius / (4.0 * e_star)).cbrt();
        for i in layout.indenters() {
            rows.push(ModelRow {
                load_n: load,
                indenter: i.number,
                x_m: i.x,
                y_m: i.y,
                force_n: p,
                radius_m: a,
            });
        }
    }
    rows
}
