//! Calibration curves: monotone piecewise-cubic Hermite (PCHIP) fits of film
//! response against pressure, their exact inverse, range flags, the
//! manufacturer's LLW chart, and the scanner relation between grey level and
//! optical density.

use std::path::Path;

use tyreroad_core::{PchipRule, pchip_slopes};

use crate::error::{FilmError, Result};

/// The manufacturer's LLW standard chart, shipped as
/// `crates/film/data/fuji-llw-density-curves.csv` (inside the crate, so it
/// packages with it; pressure in MPa, density of
/// curves A–D).
pub const LLW_CHART_CSV: &str = include_str!("../data/fuji-llw-density-curves.csv");

/// A monotone piecewise-cubic Hermite interpolant (Fritsch–Carlson / PCHIP,
/// as in SciPy's `PchipInterpolator`) through points `(x_k, y_k)` with `x`
/// strictly increasing and `y` strictly monotone (either direction).
///
/// Between knots it never overshoots the data, so it stays strictly monotone
/// and can be inverted exactly ([`MonotoneCubic::inverse`]); outside
/// `[x_0, x_n]` it is not defined (no extrapolation).
#[derive(Debug, Clone, PartialEq)]
pub struct MonotoneCubic {
    x: Vec<f64>,
    y: Vec<f64>,
    d: Vec<f64>,
    increasing: bool,
}

impl MonotoneCubic {
    /// Fits the interpolant. `x` must be strictly increasing and `y` strictly
    /// monotone, both finite, at least two points; otherwise an error
    /// ([`FilmError::NonMonotoneCalibration`] for a non-monotone `y`).
    pub fn new(x: Vec<f64>, y: Vec<f64>) -> Result<Self> {
        if x.len() != y.len() || x.len() < 2 {
            return Err(FilmError::InvalidCalibration(format!(
                "need at least two points with matching lengths (got {} and {})",
                x.len(),
                y.len()
            )));
        }
        if let Some(k) = x.iter().chain(&y).position(|v| !v.is_finite()) {
            return Err(FilmError::InvalidCalibration(format!(
                "non-finite value at position {k}"
            )));
        }
        for k in 1..x.len() {
            if x[k] <= x[k - 1] {
                return Err(FilmError::InvalidCalibration(format!(
                    "pressures not strictly increasing at point {k}: {} then {}",
                    x[k - 1],
                    x[k]
                )));
            }
        }
        let increasing = y[1] > y[0];
        for k in 1..y.len() {
            let ok = if increasing {
                y[k] > y[k - 1]
            } else {
                y[k] < y[k - 1]
            };
            if !ok {
                return Err(FilmError::NonMonotoneCalibration {
                    response: "response",
                    i: k - 1,
                    j: k,
                    p0: x[k - 1],
                    r0: y[k - 1],
                    p1: x[k],
                    r1: y[k],
                });
            }
        }
        let d = pchip_slopes(&x, &y, PchipRule::HarmonicMean);
        Ok(Self {
            x,
            y,
            d,
            increasing,
        })
    }

    /// The knots' abscissae.
    pub fn xs(&self) -> &[f64] {
        &self.x
    }

    /// The knots' ordinates.
    pub fn ys(&self) -> &[f64] {
        &self.y
    }

    /// Whether `y` increases with `x`.
    pub fn is_increasing(&self) -> bool {
        self.increasing
    }

    /// The domain `[x_0, x_n]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.x[0], self.x[self.x.len() - 1])
    }

    /// `y(x)` for `x` in the domain; `None` outside it (or NaN).
    pub fn eval(&self, x: f64) -> Option<f64> {
        let (x0, x1) = self.domain();
        if !(x >= x0 && x <= x1) {
            return None;
        }
        let k = match self.x.partition_point(|&v| v <= x) {
            0 => 0,
            n => (n - 1).min(self.x.len() - 2),
        };
        Some(self.eval_segment(k, x))
    }

    fn eval_segment(&self, k: usize, x: f64) -> f64 {
        let h = self.x[k + 1] - self.x[k];
        let t = (x - self.x[k]) / h;
        let t2 = t * t;
        let t3 = t2 * t;
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        h00 * self.y[k] + h10 * h * self.d[k] + h01 * self.y[k + 1] + h11 * h * self.d[k + 1]
    }

    /// The `x` at which the interpolant takes the value `y`: the exact
    /// inverse (bisection on the monotone cubic segment to machine
    /// precision). `None` when `y` is outside the range of the data.
    pub fn inverse(&self, y: f64) -> Option<f64> {
        let n = self.y.len();
        let (lo, hi) = if self.increasing {
            (self.y[0], self.y[n - 1])
        } else {
            (self.y[n - 1], self.y[0])
        };
        if !(y >= lo && y <= hi) {
            return None;
        }
        // Segment k with y between y_k and y_{k+1}.
        let k = if self.increasing {
            self.y.partition_point(|&v| v <= y)
        } else {
            self.y.partition_point(|&v| v >= y)
        };
        let k = k.saturating_sub(1).min(n - 2);
        let (mut a, mut b) = (self.x[k], self.x[k + 1]);
        let sign = if self.increasing { 1.0 } else { -1.0 };
        for _ in 0..200 {
            let m = 0.5 * (a + b);
            if m <= a || m >= b {
                break;
            }
            if sign * (self.eval_segment(k, m) - y) < 0.0 {
                a = m;
            } else {
                b = m;
            }
        }
        Some(0.5 * (a + b))
    }
}

/// A pressure read through a calibration, with its range flag. A value
/// outside the calibrated range is flagged, never extrapolated.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Calibrated {
    /// Inside the calibrated range: the pressure, Pa.
    InRange(f64),
    /// Less response than the lowest calibrated pressure gives (film below
    /// its threshold, or background); also NaN input.
    BelowRange,
    /// More response than the highest calibrated pressure gives: the film is
    /// saturated and the pressure is only known to be at least the top of the
    /// range.
    Saturated,
}

impl Calibrated {
    /// The pressure if in range.
    pub fn in_range(self) -> Option<f64> {
        match self {
            Calibrated::InRange(p) => Some(p),
            _ => None,
        }
    }
}

/// What a calibration curve's response variable is.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Response {
    /// Optical density `D = −log10(reflectance)` (grows with pressure).
    Density,
    /// Normalised grey level in `[0, 1]` of the analysed channel (falls with
    /// pressure for a reflective scan).
    Grey,
}

impl Response {
    fn name(self) -> &'static str {
        match self {
            Response::Density => "density",
            Response::Grey => "grey",
        }
    }
}

/// Highest calibration pressure a film can have recorded (Pa).
pub const MAX_FILM_PRESSURE: f64 = 1e9;

/// Lowest value the highest pressure of a calibration may take (Pa): the
/// most sensitive films (Prescale 5LW) start near 6 kPa, so a calibration
/// topping out below 1 kPa has its pressures in the wrong unit (MPa typed
/// as Pa).
pub const MIN_FILM_TOP_PRESSURE: f64 = 1e3;

/// Highest optical density of a calibration (a film's darkest print is near 3).
pub const MAX_DENSITY: f64 = 6.0;

/// A calibration curve: film response (density or grey) against pressure,
/// fitted by a monotone cubic ([`MonotoneCubic`]) in pressure, with its exact
/// inverse. Its range of validity is the range of the calibration pressures.
#[derive(Debug, Clone, PartialEq)]
pub struct Calibration {
    response: Response,
    curve: MonotoneCubic,
}

impl Calibration {
    /// Builds a calibration from `(response, pressure_pa)` pairs in any
    /// order. The pairs are sorted by pressure; the response must then vary
    /// strictly monotonically (either direction), else
    /// [`FilmError::NonMonotoneCalibration`].
    ///
    /// Refused as [`FilmError::InvalidCalibration`]: a non-finite value, a
    /// negative pressure, one above 1e9 Pa, a highest pressure below 1e3 Pa
    /// (MPa typed as Pa: no film reacts below about 6 kPa), a grey outside
    /// `[0, 1]` or a density outside `[0, 6]`.
    pub fn from_pairs(response: Response, pairs: &[(f64, f64)]) -> Result<Self> {
        let mut v: Vec<(f64, f64)> = pairs.iter().map(|&(r, p)| (p, r)).collect();
        if v.iter().any(|(p, r)| !p.is_finite() || !r.is_finite()) {
            return Err(FilmError::InvalidCalibration(
                "non-finite value in calibration pairs".into(),
            ));
        }
        // A film records contact pressure, which pushes: a negative one is
        // a typo or a wrong unit, and would calibrate prints to suction.
        if let Some(&(p, r)) = v.iter().find(|(p, _)| *p < 0.0) {
            return Err(FilmError::InvalidCalibration(format!(
                "negative pressure {p} Pa (at {} {r}): contact pressures are ≥ 0",
                response.name()
            )));
        }
        // No film records a gigapascal (the densest grades stop near
        // 300 MPa); a grey lies in [0, 1] and an optical density in
        // [0, MAX_DENSITY]. Beyond, a unit or a column is wrong.
        if let Some(&(p, r)) = v.iter().find(|(p, _)| *p > MAX_FILM_PRESSURE) {
            return Err(FilmError::InvalidCalibration(format!(
                "pressure {p:e} Pa (at {} {r}): no pressure film records more than \
                 {MAX_FILM_PRESSURE:e} Pa (pressure_pa or pressure_mpa?)",
                response.name()
            )));
        }
        // Symmetric to the bound above: even the most sensitive film needs
        // kilopascals, so a curve whose every point is below 1 kPa is in MPa.
        let top = v.iter().map(|&(p, _)| p).fold(0.0, f64::max);
        if !v.is_empty() && top < MIN_FILM_TOP_PRESSURE {
            return Err(FilmError::InvalidCalibration(format!(
                "highest pressure {top:e} Pa: no pressure film reacts below about 6e3 Pa, so a \
                 calibration must reach at least {MIN_FILM_TOP_PRESSURE:e} Pa; these values look \
                 like MPa given as Pa (pressure_pa or pressure_mpa?)"
            )));
        }
        let response_range = match response {
            Response::Grey => (0.0, 1.0),
            Response::Density => (0.0, MAX_DENSITY),
        };
        if let Some(&(p, r)) = v
            .iter()
            .find(|(_, r)| !(response_range.0..=response_range.1).contains(r))
        {
            return Err(FilmError::InvalidCalibration(format!(
                "{} {r} (at {p:e} Pa): expected {} to {} (grey8 is 0–255, grey16 0–65535)",
                response.name(),
                response_range.0,
                response_range.1
            )));
        }
        v.sort_by(|a, b| a.0.total_cmp(&b.0));
        let (x, y): (Vec<f64>, Vec<f64>) = v.into_iter().unzip();
        match MonotoneCubic::new(x, y) {
            Ok(curve) => Ok(Self { response, curve }),
            Err(FilmError::NonMonotoneCalibration {
                i,
                j,
                p0,
                r0,
                p1,
                r1,
                ..
            }) => Err(FilmError::NonMonotoneCalibration {
                response: response.name(),
                i,
                j,
                p0,
                r0,
                p1,
                r1,
            }),
            Err(e) => Err(e),
        }
    }

    /// Parses a calibration CSV. Lines starting with `#` and blank lines are
    /// skipped; the first other line is a header of two columns: the response,
    /// one of `density`, `grey` (normalised 0–1), `grey8` (0–255) or `grey16`
    /// (0–65535), then the pressure, `pressure_pa` or `pressure_mpa`
    /// (converted to Pa on reading).
    pub fn parse_csv(text: &str, source: &Path) -> Result<Self> {
        let csv_err = |line: usize, message: String| FilmError::Csv {
            path: source.to_path_buf(),
            line,
            message,
        };
        let mut header: Option<(Response, f64, f64)> = None;
        let mut pairs = Vec::new();
        for (n, line) in crate::data_lines(text) {
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            if cols.len() != 2 {
                return Err(csv_err(
                    n + 1,
                    format!("expected 2 columns, got {}", cols.len()),
                ));
            }
            match header {
                None => {
                    let (resp, rscale) = match cols[0] {
                        "density" => (Response::Density, 1.0),
                        "grey" | "gray" => (Response::Grey, 1.0),
                        "grey8" | "gray8" => (Response::Grey, 1.0 / 255.0),
                        "grey16" | "gray16" => (Response::Grey, 1.0 / 65535.0),
                        other => {
                            return Err(csv_err(
                                n + 1,
                                format!(
                                    "unknown response column {other:?} (density, grey, grey8, grey16)"
                                ),
                            ));
                        }
                    };
                    let pscale = match cols[1] {
                        "pressure_pa" => 1.0,
                        "pressure_mpa" => 1e6,
                        other => {
                            return Err(csv_err(
                                n + 1,
                                format!(
                                    "unknown pressure column {other:?} (pressure_pa, pressure_mpa)"
                                ),
                            ));
                        }
                    };
                    header = Some((resp, rscale, pscale));
                }
                Some((_, rscale, pscale)) => {
                    let r: f64 = cols[0]
                        .parse()
                        .map_err(|_| csv_err(n + 1, format!("not a number: {:?}", cols[0])))?;
                    let p: f64 = cols[1]
                        .parse()
                        .map_err(|_| csv_err(n + 1, format!("not a number: {:?}", cols[1])))?;
                    pairs.push((r * rscale, p * pscale));
                }
            }
        }
        let Some((resp, _, _)) = header else {
            return Err(csv_err(0, "no header line".into()));
        };
        Self::from_pairs(resp, &pairs)
    }

    /// Reads a calibration CSV file (format of [`Calibration::parse_csv`]).
    pub fn read_csv(path: &Path) -> Result<Self> {
        let text = tyreroad_core::read_input_text(path).map_err(|reason| FilmError::Io {
            path: path.to_path_buf(),
            reason,
        })?;
        Self::parse_csv(&text, path)
    }

    /// One curve of the shipped LLW standard chart (density against pressure).
    pub fn llw(curve: LlwCurve) -> Result<Self> {
        LlwChart::standard()?.calibration(curve)
    }

    /// The response variable.
    pub fn response(&self) -> Response {
        self.response
    }

    /// The fitted curve (x = pressure in Pa, y = response).
    pub fn curve(&self) -> &MonotoneCubic {
        &self.curve
    }

    /// Range of validity: lowest and highest calibrated pressure, Pa.
    pub fn pressure_range(&self) -> (f64, f64) {
        self.curve.domain()
    }

    /// The response at the lowest and at the highest calibrated pressure.
    pub fn response_range(&self) -> (f64, f64) {
        let ys = self.curve.ys();
        (ys[0], ys[ys.len() - 1])
    }

    /// The response at pressure `p` (Pa); `None` outside the calibrated
    /// range (see [`Calibration::response_clamped`] for a film that
    /// saturates).
    pub fn response_at(&self, p: f64) -> Option<f64> {
        self.curve.eval(p)
    }

    /// The response at `p` with the film's saturation: the top-of-range
    /// response above the range, `None` below it (the film does not react).
    pub fn response_clamped(&self, p: f64) -> Option<f64> {
        let (p0, p1) = self.pressure_range();
        if p > p1 {
            Some(self.response_range().1)
        } else if p >= p0 {
            self.curve.eval(p)
        } else {
            None
        }
    }

    /// The pressure giving the response `r`, with its range flag.
    pub fn pressure(&self, r: f64) -> Calibrated {
        if let Some(p) = self.curve.inverse(r) {
            return Calibrated::InRange(p);
        }
        if r.is_nan() {
            return Calibrated::BelowRange;
        }
        let (r0, r1) = self.response_range();
        // Which end is r beyond? The end whose side it lies on.
        let beyond_top = if r1 > r0 { r > r1 } else { r < r1 };
        if beyond_top {
            Calibrated::Saturated
        } else {
            Calibrated::BelowRange
        }
    }
}

/// The four curves of the LLW standard chart (by temperature and humidity of
/// the test; e.g. 25 °C / 60 %RH → B).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum LlwCurve {
    /// Curve A.
    A,
    /// Curve B.
    B,
    /// Curve C.
    C,
    /// Curve D.
    D,
}

impl std::str::FromStr for LlwCurve {
    type Err = FilmError;
    fn from_str(s: &str) -> Result<Self> {
        match s.trim() {
            "A" | "a" => Ok(Self::A),
            "B" | "b" => Ok(Self::B),
            "C" | "c" => Ok(Self::C),
            "D" | "d" => Ok(Self::D),
            _ => Err(FilmError::InvalidCalibration(format!(
                "unknown LLW curve {s:?} (A, B, C or D)"
            ))),
        }
    }
}

/// The LLW density chart: pressures (Pa) and densities of curves A–D.
#[derive(Debug, Clone, PartialEq)]
pub struct LlwChart {
    /// Pressures, Pa.
    pub pressure_pa: Vec<f64>,
    /// Densities of curves A, B, C, D at those pressures.
    pub density: [Vec<f64>; 4],
}

impl LlwChart {
    /// The shipped chart ([`LLW_CHART_CSV`]).
    pub fn standard() -> Result<Self> {
        Self::parse_csv(LLW_CHART_CSV, Path::new("fuji-llw-density-curves.csv"))
    }

    /// Parses a chart in the shipped format: `#` comment lines, a header
    /// `pressure_mpa,density_a,density_b,density_c,density_d`, rows in MPa.
    pub fn parse_csv(text: &str, source: &Path) -> Result<Self> {
        let csv_err = |line: usize, message: String| FilmError::Csv {
            path: source.to_path_buf(),
            line,
            message,
        };
        const HEADER: [&str; 5] = [
            "pressure_mpa",
            "density_a",
            "density_b",
            "density_c",
            "density_d",
        ];
        let mut seen_header = false;
        let mut chart = LlwChart {
            pressure_pa: Vec::new(),
            density: Default::default(),
        };
        for (n, line) in crate::data_lines(text) {
            let cols: Vec<&str> = line.split(',').map(str::trim).collect();
            if !seen_header {
                if cols != HEADER {
                    return Err(csv_err(
                        n + 1,
                        format!("expected header {:?}", HEADER.join(",")),
                    ));
                }
                seen_header = true;
                continue;
            }
            if cols.len() != 5 {
                return Err(csv_err(
                    n + 1,
                    format!("expected 5 columns, got {}", cols.len()),
                ));
            }
            let mut v = [0.0; 5];
            for (k, c) in cols.iter().enumerate() {
                v[k] = c
                    .parse()
                    .map_err(|_| csv_err(n + 1, format!("not a number: {c:?}")))?;
            }
            chart.pressure_pa.push(v[0] * 1e6);
            for c in 0..4 {
                chart.density[c].push(v[c + 1]);
            }
        }
        if !seen_header {
            return Err(csv_err(0, "no header line".into()));
        }
        Ok(chart)
    }

    /// Reads a chart file.
    pub fn read_csv(path: &Path) -> Result<Self> {
        let text = tyreroad_core::read_input_text(path).map_err(|reason| FilmError::Io {
            path: path.to_path_buf(),
            reason,
        })?;
        Self::parse_csv(&text, path)
    }

    /// The density calibration of one curve.
    pub fn calibration(&self, curve: LlwCurve) -> Result<Calibration> {
        let d = &self.density[curve as usize];
        let pairs: Vec<(f64, f64)> = d
            .iter()
            .zip(&self.pressure_pa)
            .map(|(&d, &p)| (d, p))
            .collect();
        Calibration::from_pairs(Response::Density, &pairs)
    }
}

/// The scanner relation between normalised grey level `g ∈ [0, 1]` and
/// optical density:
///
/// ```text
/// reflectance R = (g − black) / (white − black),    D = −log10(R)
/// g = black + (white − black) · 10^(−D)
/// ```
///
/// `white` is the grey level the scanner gives for a perfect white (R = 1,
/// D = 0) and `black` for no reflected light (R = 0); both are settable, e.g.
/// from a reference strip scanned with the film. Defaults: white 1, black 0.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Scanner {
    /// Grey level of the white reference (D = 0).
    pub white: f64,
    /// Grey level of the black reference (D = ∞).
    pub black: f64,
}

impl Default for Scanner {
    fn default() -> Self {
        Self {
            white: 1.0,
            black: 0.0,
        }
    }
}

impl Scanner {
    /// A scanner relation: `white` in `(0, 1]`, `black` in `[0, 1)`,
    /// `white > black`.
    pub fn new(white: f64, black: f64) -> Result<Self> {
        let s = Self { white, black };
        s.check()?;
        Ok(s)
    }

    /// Both references are grey levels of the scan, normalised to
    /// `[0, 1]`: a white of 2 puts every calibrated grey above any pixel,
    /// and the analysis would fail far from the value at fault.
    pub(crate) fn check(&self) -> Result<()> {
        let (white, black) = (self.white, self.black);
        if !(white > 0.0 && white <= 1.0) {
            return Err(FilmError::InvalidParameter {
                name: "scanner white reference",
                value: white,
                requirement: "a normalised grey level in (0, 1]",
            });
        }
        if !(0.0..1.0).contains(&black) {
            return Err(FilmError::InvalidParameter {
                name: "scanner black reference",
                value: black,
                requirement: "a normalised grey level in [0, 1)",
            });
        }
        if white <= black {
            return Err(FilmError::InvalidParameter {
                name: "scanner white reference",
                value: white,
                requirement: "above the black reference",
            });
        }
        Ok(())
    }

    /// Density of grey level `g`: `−log10((g − black)/(white − black))`;
    /// `+∞` at or below the black reference. Grey levels above white give a
    /// negative density. A NaN grey has a NaN density (not `+∞`: it is no
    /// reading, not the darkest one).
    pub fn density(&self, g: f64) -> f64 {
        let r = (g - self.black) / (self.white - self.black);
        if r > 0.0 {
            -r.log10()
        } else if r.is_nan() {
            f64::NAN
        } else {
            f64::INFINITY
        }
    }

    /// Grey level of density `d`: `black + (white − black)·10^(−d)`.
    pub fn grey(&self, d: f64) -> f64 {
        self.black + (self.white - self.black) * 10f64.powf(-d)
    }
}

/// A calibration together with the scanner relation: reads scanned grey
/// levels as pressures whatever the calibration's response variable.
#[derive(Debug, Clone, PartialEq)]
pub struct FilmResponse {
    /// The calibration curve.
    pub calibration: Calibration,
    /// The grey ↔ density relation of the scanner.
    pub scanner: Scanner,
}

impl FilmResponse {
    /// Combines a calibration and a scanner relation.
    pub fn new(calibration: Calibration, scanner: Scanner) -> Self {
        Self {
            calibration,
            scanner,
        }
    }

    /// The calibration's response for grey level `g`.
    pub fn response_of_grey(&self, g: f64) -> f64 {
        match self.calibration.response() {
            Response::Density => self.scanner.density(g),
            Response::Grey => g,
        }
    }

    /// Grey level for a calibration response value.
    pub fn grey_of_response(&self, r: f64) -> f64 {
        match self.calibration.response() {
            Response::Density => self.scanner.grey(r),
            Response::Grey => r,
        }
    }

    /// The pressure read from grey level `g`, flagged out of range. A NaN
    /// grey is [`Calibrated::BelowRange`], as a NaN response is for
    /// [`Calibration::pressure`]: never a pressure, and never read as a
    /// saturated print. (Scans refuse NaN greys on construction.)
    pub fn pressure_of_grey(&self, g: f64) -> Calibrated {
        self.calibration.pressure(self.response_of_grey(g))
    }

    /// The grey level a film pressed at `p` shows; `None` outside the
    /// calibrated range.
    pub fn grey_of_pressure(&self, p: f64) -> Option<f64> {
        self.calibration
            .response_at(p)
            .map(|r| self.grey_of_response(r))
    }

    /// The grey level at the lowest calibrated pressure (the faintest print
    /// the calibration can read).
    pub fn floor_grey(&self) -> f64 {
        self.grey_of_response(self.calibration.response_range().0)
    }

    /// The grey level at the highest calibrated pressure (saturation).
    pub fn ceiling_grey(&self) -> f64 {
        self.grey_of_response(self.calibration.response_range().1)
    }

    /// Density of grey level `g` through the scanner relation.
    pub fn density_of_grey(&self, g: f64) -> f64 {
        self.scanner.density(g)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// A negative pressure in a calibration is refused, naming it (a
    /// `0.9,-0.5` line in MPa was once calibrated as suction).
    #[test]
    fn a_negative_calibration_pressure_is_refused() {
        let pairs = [(0.2, 0.0), (0.5, 1e6), (0.9, -0.5e6)];
        let err = Calibration::from_pairs(Response::Density, &pairs)
            .err()
            .map(|e| e.to_string());
        assert!(
            err.as_deref()
                .is_some_and(|e| e.contains("negative pressure")),
            "{err:?}"
        );
        assert!(Calibration::from_pairs(Response::Density, &pairs[..2]).is_ok());
    }

    /// Regression (adversarial run, 2026-11-29): a point at 1e30 Pa gave
    /// 6.3e23 N per print, and greys outside [0, 1] were accepted.
    #[test]
    fn calibration_values_no_film_records_are_refused_naming_them() {
        let refused = |response, pairs: &[(f64, f64)]| {
            Calibration::from_pairs(response, pairs)
                .err()
                .map(|e| e.to_string())
                .unwrap_or_default()
        };
        let e = refused(Response::Density, &[(0.2, 1e5), (0.9, 1e30)]);
        assert!(e.contains("1e30 Pa") && e.contains("pressure_mpa"), "{e}");
        let e = refused(Response::Grey, &[(0.9, 1e5), (1.5, 1e6)]);
        assert!(e.contains("grey 1.5") && e.contains("0 to 1"), "{e}");
        let e = refused(Response::Density, &[(-0.2, 1e5), (0.9, 1e6)]);
        assert!(e.contains("density -0.2"), "{e}");
        assert!(Calibration::from_pairs(Response::Grey, &[(0.9, 1e5), (0.3, 1e6)]).is_ok());
    }
}
