//! Print analysis: threshold, connected components, per-print measures
//! (area, mean grey and pressure, force, best-fit ellipse, Hertz profile fit).

use crate::calibration::{Calibrated, FilmResponse};
use crate::error::{FilmError, Result, check_positive};
use crate::hertz_fit::hertz_fit;
use crate::scan::Scan;

/// Pixel connectivity of a print.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Connectivity {
    /// Edge neighbours only (up, down, left, right).
    Four,
    /// Edge and corner neighbours (the default: a print's diagonal pixels
    /// belong to it).
    #[default]
    Eight,
}

/// How reacted pixels are separated from the background. A pixel is reacted
/// when its grey level is strictly below the threshold grey (prints are
/// darker than the film's background).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub enum Threshold {
    /// Otsu's method on the grey histogram of the whole scan (maximum
    /// between-class variance). Beware: a calibrated print spans a wide
    /// range of greys, and Otsu's split often falls inside the prints
    /// (cutting their faint rim), not between prints and background.
    Otsu,
    /// A given normalised grey level.
    Grey(f64),
    /// A given optical density (through the scanner relation).
    Density(f64),
    /// Half-way (in grey) between the background (the histogram's mode among
    /// greys lighter than the calibration floor) and
    /// the grey of the calibration's lowest pressure: the faintest print the
    /// calibration can read is kept, unreacted film is not. The default.
    #[default]
    MidwayToFloor,
}

/// How a print's force and radius are estimated from its pixels.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Default)]
pub enum Estimator {
    /// The paper's way: the mean grey of the print is converted to a mean
    /// pressure through the calibration; force = that pressure × reacted
    /// area; radius = √(ab) of the best-fit ellipse of the reacted pixels.
    #[default]
    MeanGrey,
    /// Mean of the per-pixel calibrated pressures × reacted area (= the sum
    /// of per-pixel forces); radius as [`Estimator::MeanGrey`].
    PixelMean,
    /// Fit of a Hertzian (semi-ellipsoidal) profile `p² = p0²(1 − ρ²/s²)` to
    /// the calibrated pixels, `ρ` being the normalised radius in the reacted
    /// ellipse: recovers the part of the print below the film's threshold.
    /// Valid for smooth (paraboloidal) indenters only.
    HertzFit,
}

impl Estimator {
    /// The estimator's name on the command line (`mean-grey`, `pixel-mean`,
    /// `hertz-fit`).
    pub fn name(self) -> &'static str {
        match self {
            Self::MeanGrey => "mean-grey",
            Self::PixelMean => "pixel-mean",
            Self::HertzFit => "hertz-fit",
        }
    }
}

/// Options of [`analyse`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct AnalysisOptions {
    /// Threshold method.
    pub threshold: Threshold,
    /// Pixel connectivity of prints.
    pub connectivity: Connectivity,
    /// Components with fewer pixels are discarded as specks.
    pub min_pixels: usize,
    /// Pixels used by the Hertz fit: normalised radius `ρ ≤ fit_fraction`
    /// in the reacted ellipse (keeps away from the blurred, thresholded edge).
    pub fit_fraction: f64,
}

impl Default for AnalysisOptions {
    fn default() -> Self {
        Self {
            threshold: Threshold::MidwayToFloor,
            connectivity: Connectivity::Eight,
            min_pixels: 20,
            fit_fraction: 0.85,
        }
    }
}

/// Best-fit ellipse of a print from its second moments, in the film frame
/// (x to the right, y up), lengths in metres.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Ellipse {
    /// Semi-major axis `a`, m.
    pub semi_major: f64,
    /// Semi-minor axis `b ≤ a`, m.
    pub semi_minor: f64,
    /// Angle of the major axis from +x, counter-clockwise, radians in
    /// `(−π/2, π/2]`.
    pub orientation: f64,
}

impl Ellipse {
    /// From central second moments `μ20 = ⟨x²⟩, μ02 = ⟨y²⟩, μ11 = ⟨xy⟩` of a
    /// uniform region (any length unit): the ellipse with the same moments
    /// has semi-axes `2√λ1 ≥ 2√λ2` (eigenvalues of the moment matrix) and its
    /// major axis at `θ = ½·atan2(2μ11, μ20 − μ02)`.
    pub fn from_moments(mu20: f64, mu02: f64, mu11: f64) -> Self {
        let mean = 0.5 * (mu20 + mu02);
        let dev = (0.25 * (mu20 - mu02).powi(2) + mu11 * mu11).sqrt();
        let l1 = (mean + dev).max(0.0);
        let l2 = (mean - dev).max(0.0);
        let mut theta = 0.5 * (2.0 * mu11).atan2(mu20 - mu02);
        if theta <= -std::f64::consts::FRAC_PI_2 {
            theta += std::f64::consts::PI;
        }
        Self {
            semi_major: 2.0 * l1.sqrt(),
            semi_minor: 2.0 * l2.sqrt(),
            orientation: theta,
        }
    }

    /// Apparent radius `√(ab)`.
    pub fn apparent_radius(&self) -> f64 {
        (self.semi_major * self.semi_minor).sqrt()
    }
}

/// Result of the Hertzian profile fit of one print.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct HertzFit {
    /// Peak pressure `p0`, Pa.
    pub peak_pressure: f64,
    /// Ratio `s` of the contact ellipse to the reacted ellipse (≥ 1 when the
    /// film misses the low-pressure rim).
    pub scale: f64,
    /// Semi-axes of the contact ellipse, m.
    pub semi_axes: (f64, f64),
    /// Force `⅔ π a b p0`, N.
    pub force: f64,
    /// Contact radius `√(ab)`, m.
    pub radius: f64,
    /// Number of pixels used.
    pub pixels: usize,
}

/// The measures of one print (a connected component of reacted pixels).
#[derive(Debug, Clone, PartialEq)]
pub struct Print {
    /// Component label in [`Detection::labels`].
    pub label: u32,
    /// Reacted pixel count.
    pub pixel_count: usize,
    /// Reacted area = pixel count × pixel area, m².
    pub area: f64,
    /// Centroid in pixel coordinates `(col, row)`, continuous (the centre
    /// of pixel `(i, j)` is `(i + 0.5, j + 0.5)`).
    pub centroid_px: (f64, f64),
    /// Best-fit ellipse of the reacted pixels.
    pub ellipse: Ellipse,
    /// Apparent radius `√(ab)` of the ellipse, m.
    pub apparent_radius: f64,
    /// Mean normalised grey level over the reacted pixels.
    pub mean_grey: f64,
    /// Density of the mean grey level.
    pub mean_grey_density: f64,
    /// Pressure of the mean grey level (the paper's mean pressure).
    pub pressure_of_mean_grey: Calibrated,
    /// Mean of the per-pixel calibrated pressures, Pa (pixels below range
    /// count as the bottom of the range, saturated ones as the top).
    pub mean_pixel_pressure: f64,
    /// Pixels reacted but below the calibrated range.
    pub below_range_pixels: usize,
    /// Saturated pixels (the force is then a lower bound).
    pub saturated_pixels: usize,
    /// Whether the print touches the image border (possibly cut).
    pub touches_border: bool,
    /// Hertzian profile fit, when enough pixels are in range.
    pub hertz: Option<HertzFit>,
}

impl Print {
    /// Force (N) by `estimator`; `None` when it cannot be computed (mean grey
    /// out of the calibrated range, or no Hertz fit).
    pub fn force(&self, estimator: Estimator) -> Option<f64> {
        match estimator {
            Estimator::MeanGrey => self.pressure_of_mean_grey.in_range().map(|p| p * self.area),
            Estimator::PixelMean => Some(self.mean_pixel_pressure * self.area),
            Estimator::HertzFit => self.hertz.map(|h| h.force),
        }
    }

    /// Radius (m) by `estimator`.
    pub fn radius(&self, estimator: Estimator) -> Option<f64> {
        match estimator {
            Estimator::MeanGrey | Estimator::PixelMean => Some(self.apparent_radius),
            Estimator::HertzFit => self.hertz.map(|h| h.radius),
        }
    }
}

/// All prints found in a scan.
#[derive(Debug, Clone, PartialEq)]
pub struct Detection {
    /// Image width, px.
    pub width: usize,
    /// Image height, px.
    pub height: usize,
    /// Pixel size, m.
    pub pixel_size: f64,
    /// Grey threshold used (reacted: grey < threshold).
    pub threshold_grey: f64,
    /// Background grey: median grey of the unreacted pixels.
    pub background_grey: f64,
    /// The calibration's pressures `(lowest, highest)`, Pa: a pixel beyond
    /// them is below range or saturated.
    pub pressure_range: (f64, f64),
    /// Prints, in label order (top to bottom, then left to right, of their
    /// first pixel).
    pub prints: Vec<Print>,
    /// Per pixel, row-major: the label of its print, 0 for none (background
    /// and discarded specks).
    pub labels: Vec<u32>,
}

/// A print that reaches the scan's border and covers more than this
/// fraction of it is the background read as pressure: a press test's prints
/// are islands on unreacted film.
pub const BACKGROUND_PRINT_FRACTION: f64 = 0.5;

impl Detection {
    /// What a reader of this detection should be told: each print that
    /// reaches the scan's border and covers more than
    /// [`BACKGROUND_PRINT_FRACTION`] of it, the background read as pressure
    /// (a scan inverted, prints light on dark film, or a threshold above
    /// the unreacted film's grey). Empty for a scan of islands.
    pub fn warnings(&self) -> Vec<String> {
        let pixels = (self.width * self.height) as f64;
        self.prints
            .iter()
            .filter(|p| {
                p.touches_border && p.pixel_count as f64 > BACKGROUND_PRINT_FRACTION * pixels
            })
            .map(|p| {
                format!(
                    "print {} covers {:.0} % of the scan and reaches its border: the background \
                     reads as pressure; is the scan inverted (prints light on dark film), or the \
                     threshold (grey {:.4}) above the unreacted film's?",
                    p.label,
                    100.0 * p.pixel_count as f64 / pixels,
                    self.threshold_grey
                )
            })
            .collect()
    }
}

/// Grey histogram with `levels` bins over [0, 1] (bin `k` holds grey values
/// rounding to `k / (levels − 1)`).
pub fn histogram(grey: &[f32], levels: usize) -> Vec<u64> {
    let levels = levels.max(2);
    let mut h = vec![0u64; levels];
    let scale = (levels - 1) as f32;
    for &g in grey {
        let k = (g.clamp(0.0, 1.0) * scale).round() as usize;
        h[k.min(levels - 1)] += 1;
    }
    h
}

/// Otsu's threshold of a histogram over [0, 1]: the grey level between bins
/// `k*` and `k* + 1` maximising the between-class variance
/// `w0·w1·(μ0 − μ1)²`. Returns `None` for a histogram with one occupied bin.
pub fn otsu(hist: &[u64]) -> Option<f64> {
    let n = hist.len();
    if n < 2 {
        return None;
    }
    let total: f64 = hist.iter().map(|&c| c as f64).sum();
    let sum_all: f64 = hist
        .iter()
        .enumerate()
        .map(|(k, &c)| k as f64 * c as f64)
        .sum();
    let (mut w0, mut s0) = (0.0, 0.0);
    let mut best: Option<(f64, usize, usize)> = None; // (variance, first k, last k)
    for (k, &c) in hist.iter().enumerate().take(n - 1) {
        w0 += c as f64;
        s0 += k as f64 * c as f64;
        let w1 = total - w0;
        if w0 == 0.0 || w1 == 0.0 {
            continue;
        }
        let m0 = s0 / w0;
        let m1 = (sum_all - s0) / w1;
        let var = w0 * w1 * (m0 - m1) * (m0 - m1);
        match best {
            Some((v, _, _)) if var > v * (1.0 + 1e-12) => best = Some((var, k, k)),
            Some((v, first, _)) if var >= v * (1.0 - 1e-12) => best = Some((v, first, k)),
            None => best = Some((var, k, k)),
            _ => {}
        }
    }
    // A plateau of equal variance (empty bins between the classes): take its
    // middle.
    best.map(|(_, first, last)| (0.5 * (first + last) as f64 + 0.5) / (n - 1) as f64)
}

/// Connected components of `mask` (row-major `width × height`). Returns the
/// per-pixel labels (0 = not in mask, components numbered 1.. in raster
/// order of their first pixel) and the number of components.
///
/// Errors: a mask whose length is not `width × height`
/// ([`FilmError::MaskSize`]).
pub fn connected_components(
    mask: &[bool],
    width: usize,
    height: usize,
    connectivity: Connectivity,
) -> Result<(Vec<u32>, usize)> {
    if width.checked_mul(height) != Some(mask.len()) {
        return Err(FilmError::MaskSize {
            len: mask.len(),
            width,
            height,
        });
    }
    let mut labels = vec![0u32; mask.len()];
    let mut parent: Vec<u32> = vec![0];
    fn find(parent: &mut [u32], mut x: u32) -> u32 {
        while parent[x as usize] != x {
            let p = parent[x as usize];
            parent[x as usize] = parent[p as usize];
            x = p;
        }
        x
    }
    for r in 0..height {
        for c in 0..width {
            let i = r * width + c;
            if !mask[i] {
                continue;
            }
            let mut neigh = [0u32; 4];
            let mut nn = 0;
            if c > 0 && labels[i - 1] != 0 {
                neigh[nn] = labels[i - 1];
                nn += 1;
            }
            if r > 0 {
                let up = i - width;
                if labels[up] != 0 {
                    neigh[nn] = labels[up];
                    nn += 1;
                }
                if connectivity == Connectivity::Eight {
                    if c > 0 && labels[up - 1] != 0 {
                        neigh[nn] = labels[up - 1];
                        nn += 1;
                    }
                    if c + 1 < width && labels[up + 1] != 0 {
                        neigh[nn] = labels[up + 1];
                        nn += 1;
                    }
                }
            }
            if nn == 0 {
                let l = parent.len() as u32;
                parent.push(l);
                labels[i] = l;
            } else {
                let mut root = find(&mut parent, neigh[0]);
                for &l in &neigh[1..nn] {
                    let rl = find(&mut parent, l);
                    if rl != root {
                        let (lo, hi) = if rl < root { (rl, root) } else { (root, rl) };
                        parent[hi as usize] = lo;
                        root = lo;
                    }
                }
                labels[i] = root;
            }
        }
    }
    // Compact the roots to 1..n in order of first appearance.
    let mut compact = vec![0u32; parent.len()];
    let mut n = 0u32;
    for l in 1..parent.len() as u32 {
        let r = find(&mut parent, l);
        if r == l {
            n += 1;
            compact[l as usize] = n;
        }
    }
    for l in labels.iter_mut() {
        if *l != 0 {
            let r = find(&mut parent, *l);
            *l = compact[r as usize];
        }
    }
    Ok((labels, n as usize))
}

#[derive(Clone, Copy, Default)]
struct Acc {
    n: f64,
    sx: f64,
    sy: f64,
    sxx: f64,
    syy: f64,
    sxy: f64,
    sg: f64,
    border: bool,
    // second pass
    sp: f64,
    below: usize,
    sat: usize,
}

/// Per-level pressures of a quantised scan (8 or 16 bit), to avoid
/// inverting the calibration once per pixel.
struct PressureLut {
    levels: f32,
    table: Vec<Calibrated>,
}

impl PressureLut {
    fn new(response: &FilmResponse, bit_depth: u8) -> Option<Self> {
        let levels = match bit_depth {
            8 => 255usize,
            16 => 65535,
            _ => return None,
        };
        let table = (0..=levels)
            .map(|k| response.pressure_of_grey(k as f64 / levels as f64))
            .collect();
        Some(Self {
            levels: levels as f32,
            table,
        })
    }

    fn get(&self, g: f32, response: &FilmResponse) -> Calibrated {
        let x = g * self.levels;
        let k = x.round();
        if (x - k).abs() < 1e-3 && k >= 0.0 && (k as usize) < self.table.len() {
            self.table[k as usize]
        } else {
            response.pressure_of_grey(g as f64)
        }
    }
}

/// Finds and measures the prints of a scan.
///
/// Steps: threshold (see [`Threshold`]); connected components
/// ([`connected_components`]); components below `min_pixels` dropped; per
/// print, the measures of [`Print`]. Errors: no pixel size, an invalid
/// threshold (a grey outside `(0, 1]`, a negative or non-finite density),
/// Otsu's threshold on a uniform scan ([`FilmError::UniformScan`]), a scan
/// with no pixel lighter than the calibration's floor under
/// [`Threshold::MidwayToFloor`] (nothing to read as background), no print
/// at all.
pub fn analyse(
    scan: &Scan,
    response: &FilmResponse,
    options: &AnalysisOptions,
) -> Result<Detection> {
    let pixel_size = scan.pixel_size().ok_or(FilmError::PixelSizeUnknown)?;
    check_positive("fit fraction", options.fit_fraction)?;
    // The fields are public: a scanner written field by field skips
    // `Scanner::new`, and a bad reference would surface as a grey floor.
    response.scanner.check()?;
    let (w, h) = (scan.width(), scan.height());
    let grey = scan.grey();
    let levels = if scan.bit_depth() == 8 { 256 } else { 1024 };
    let hist = histogram(grey, levels);
    let threshold = match options.threshold {
        Threshold::Otsu => otsu(&hist).ok_or_else(|| FilmError::UniformScan {
            grey: grey.iter().map(|&g| g as f64).sum::<f64>() / grey.len() as f64,
            pixels: grey.len(),
        })?,
        Threshold::Grey(g) => g,
        Threshold::Density(d) => {
            // Checked as the density given: its grey (10 for a density of
            // −1) would name a value the user never typed.
            if !(d.is_finite() && d >= 0.0) {
                return Err(FilmError::InvalidParameter {
                    name: "density threshold",
                    value: d,
                    requirement: "finite and ≥ 0 (density 0 is the scanner's white)",
                });
            }
            response.scanner.grey(d)
        }
        Threshold::MidwayToFloor => {
            // Background: the histogram mode among greys lighter than the
            // floor (unreacted film is lighter than any calibrated print).
            let floor = response.floor_grey();
            let k0 = ((floor * (levels - 1) as f64).floor() as usize + 1).min(levels);
            let mode = hist[k0..]
                .iter()
                .enumerate()
                .filter(|&(_, &c)| c > 0)
                .max_by_key(|&(_, &c)| c)
                .map(|(k, _)| (k + k0) as f64 / (levels - 1) as f64);
            let Some(mode) = mode else {
                // The scan is at fault as often as the calibration (one
                // pixel, a scan all print): name the scan's lightest grey.
                return Err(FilmError::InvalidParameter {
                    name: "lightest grey of the scan",
                    value: crate::error::widen(grey.iter().fold(0.0f32, |a, &g| a.max(g))),
                    requirement: "above the grey of the calibration's lowest pressure: no pixel \
                        shows unreacted film to take as background (a scan all print, or a \
                        calibration whose faintest print is lighter than this film); give a grey \
                        or density threshold",
                });
            };
            0.5 * (mode + floor)
        }
    };
    if !(threshold.is_finite() && threshold > 0.0 && threshold <= 1.0) {
        return Err(FilmError::InvalidParameter {
            name: "grey threshold",
            value: threshold,
            requirement: "in (0, 1]",
        });
    }
    let t = threshold as f32;
    let mask: Vec<bool> = grey.iter().map(|&g| g < t).collect();
    let reacted = mask.iter().filter(|&&m| m).count();
    let (mut labels, n) = connected_components(&mask, w, h, options.connectivity)?;
    drop(mask);

    // Background: median grey of unreacted pixels, from the histogram.
    let background_grey = {
        let kt = (threshold * (levels - 1) as f64).ceil() as usize;
        let above: u64 = hist[kt.min(levels - 1)..].iter().sum();
        let mut acc = 0u64;
        let mut med = 1.0;
        for (k, &c) in hist.iter().enumerate().skip(kt.min(levels - 1)) {
            acc += c;
            if 2 * acc >= above {
                med = k as f64 / (levels - 1) as f64;
                break;
            }
        }
        med
    };

    // Pass 1: moments.
    let mut acc = vec![Acc::default(); n + 1];
    for r in 0..h {
        for c in 0..w {
            let l = labels[r * w + c] as usize;
            if l == 0 {
                continue;
            }
            let a = &mut acc[l];
            let x = c as f64 + 0.5;
            let y = r as f64 + 0.5;
            a.n += 1.0;
            a.sx += x;
            a.sy += y;
            a.sxx += x * x;
            a.syy += y * y;
            a.sxy += x * y;
            a.sg += grey[r * w + c] as f64;
            if r == 0 || c == 0 || r + 1 == h || c + 1 == w {
                a.border = true;
            }
        }
    }
    // Keep components with enough pixels; relabel 1..m.
    let mut keep = vec![0u32; n + 1];
    let mut m = 0u32;
    for l in 1..=n {
        if acc[l].n >= options.min_pixels.max(1) as f64 {
            m += 1;
            keep[l] = m;
        }
    }
    if m == 0 {
        return Err(FilmError::NoPrints { threshold, reacted });
    }
    for l in labels.iter_mut() {
        *l = keep[*l as usize];
    }
    let acc: Vec<Acc> = (1..=n).filter(|&l| keep[l] != 0).map(|l| acc[l]).collect();
    let mut acc = acc;

    // Ellipses (pixel units, image axes: x right, y down).
    struct Geo {
        cx: f64,
        cy: f64,
        e: Ellipse, // in pixels, film orientation (y up)
    }
    let geos: Vec<Geo> = acc
        .iter()
        .map(|a| {
            let cx = a.sx / a.n;
            let cy = a.sy / a.n;
            // +1/12: each pixel is a unit square, not a point.
            let mu20 = (a.sxx / a.n - cx * cx).max(0.0) + 1.0 / 12.0;
            let mu02 = (a.syy / a.n - cy * cy).max(0.0) + 1.0 / 12.0;
            // Film frame has y up: the cross moment changes sign.
            let mu11 = -(a.sxy / a.n - cx * cy);
            Geo {
                cx,
                cy,
                e: Ellipse::from_moments(mu20, mu02, mu11),
            }
        })
        .collect();

    // Pass 2: per-pixel pressures, pixel mean and Hertz fit sums.
    let (p_lo, p_hi) = response.calibration.pressure_range();
    let lut = PressureLut::new(response, scan.bit_depth());
    let f2 = options.fit_fraction * options.fit_fraction;
    let mut samples: Vec<Vec<(f32, f32)>> = vec![Vec::new(); acc.len()];
    let mut saturated: Vec<Vec<f32>> = vec![Vec::new(); acc.len()];
    for r in 0..h {
        for c in 0..w {
            let l = labels[r * w + c] as usize;
            if l == 0 {
                continue;
            }
            let g = grey[r * w + c];
            let cal = match &lut {
                Some(t) => t.get(g, response),
                None => response.pressure_of_grey(g as f64),
            };
            let a = &mut acc[l - 1];
            let geo = &geos[l - 1];
            let dx = c as f64 + 0.5 - geo.cx;
            let dy = -(r as f64 + 0.5 - geo.cy);
            let (sn, co) = geo.e.orientation.sin_cos();
            let u = dx * co + dy * sn;
            let v = -dx * sn + dy * co;
            let rho2 =
                (u / geo.e.semi_major.max(0.5)).powi(2) + (v / geo.e.semi_minor.max(0.5)).powi(2);
            match cal {
                Calibrated::InRange(p) => {
                    a.sp += p;
                    if rho2 <= f2 {
                        samples[l - 1].push((rho2 as f32, p as f32));
                    }
                }
                Calibrated::BelowRange => {
                    a.sp += p_lo;
                    a.below += 1;
                }
                Calibrated::Saturated => {
                    a.sp += p_hi;
                    a.sat += 1;
                    saturated[l - 1].push(rho2 as f32);
                }
            }
        }
    }

    let px_area = pixel_size * pixel_size;
    let prints = acc
        .iter()
        .zip(&geos)
        .zip(&samples)
        .zip(saturated.iter_mut())
        .enumerate()
        .map(|(k, (((a, geo), samples), sat))| {
            let e = Ellipse {
                semi_major: geo.e.semi_major * pixel_size,
                semi_minor: geo.e.semi_minor * pixel_size,
                orientation: geo.e.orientation,
            };
            let mean_grey = a.sg / a.n;
            let hertz = hertz_fit(samples, sat, options.fit_fraction, &e);
            Print {
                label: k as u32 + 1,
                pixel_count: a.n as usize,
                area: a.n * px_area,
                centroid_px: (geo.cx, geo.cy),
                ellipse: e,
                apparent_radius: e.apparent_radius(),
                mean_grey,
                mean_grey_density: response.density_of_grey(mean_grey),
                pressure_of_mean_grey: response.pressure_of_grey(mean_grey),
                mean_pixel_pressure: a.sp / a.n,
                below_range_pixels: a.below,
                saturated_pixels: a.sat,
                touches_border: a.border,
                hertz,
            }
        })
        .collect();
    Ok(Detection {
        width: w,
        height: h,
        pixel_size,
        threshold_grey: threshold,
        background_grey,
        pressure_range: (p_lo, p_hi),
        prints,
        labels,
    })
}
