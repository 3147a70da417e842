//! Pressure-film (Fuji Prescale) post-processing for the multipoint contact
//! model of Cesbron et al. (2006, §3): calibration, print analysis, and
//! comparison of measured forces and radii with a model run.
//!
//! # Equations
//!
//! **Grey level ↔ density** ([`Scanner`]). Grey levels `g` are normalised to
//! `[0, 1]` (8- and 16-bit scans alike). With the scanner's white and black
//! references `g_w > g_b` (defaults 1 and 0),
//!
//! ```text
//! R = (g − g_b) / (g_w − g_b),      D = −log10 R,      g = g_b + (g_w − g_b)·10^(−D)
//! ```
//!
//! **Calibration** ([`Calibration`]). A film response `r` (density, or grey
//! level directly) against pressure `p` is interpolated by a monotone
//! piecewise-cubic Hermite curve `r(p)` (PCHIP, Fritsch–Carlson slopes: no
//! overshoot, so strictly monotone between strictly monotone data). Its
//! inverse `p(r)` is exact (bisection on the cubic). A response outside
//! `[r(p_min), r(p_max)]` is flagged [`Calibrated::BelowRange`] or
//! [`Calibrated::Saturated`], never extrapolated. A non-monotone curve is an
//! error. The LLW chart (curves A–D, 0.49–2.46 MPa) is shipped
//! ([`LlwChart`], [`Calibration::llw`]).
//!
//! **Print measures** ([`analyse`], [`Print`]). Reacted pixels are those with
//! `g < g_t` (by default half-way between the background and the grey of the
//! calibration floor; Otsu or given, [`Threshold`]); prints are
//! 8-connected components (4 optional). For a print of `N` pixels of side
//! `s`:
//!
//! ```text
//! area A = N s²
//! paper:        p̄ = p(mean g),            P = p̄ A                 (Estimator::MeanGrey)
//! pixel mean:   p̄ = mean_k p(g_k),        P = p̄ A = Σ p(g_k) s²   (Estimator::PixelMean)
//! ```
//!
//! The two differ because `p(g)` is not linear: by Jensen's inequality the
//! pressure of the mean grey is not the mean pressure. The paper converts
//! the mean grey; both are offered.
//!
//! **Ellipse from moments** ([`Ellipse::from_moments`]). With the central
//! second moments of the pixel set (each pixel a unit square: `+s²/12` on
//! the diagonal) `μ20, μ02, μ11`, the eigenvalues `λ1 ≥ λ2` of
//! `[[μ20, μ11], [μ11, μ02]]` give the semi-axes of the uniform ellipse with
//! the same moments, `a = 2√λ1 ≥ b = 2√λ2`, its major axis at
//! `θ = ½ atan2(2μ11, μ20 − μ02)` from +x (film frame, y up), and the
//! apparent radius `a_s = √(ab)`.
//!
//! **What the film sees.** LLW does not react below about 0.5 MPa, while a
//! Hertzian pressure `p(r) = p0 √(1 − r²/a²)` falls to 0 at the contact edge.
//! The reacted region is therefore the ellipse where `p ≥ p_min`, of radius
//! `a √(1 − (p_min/p0)²)`, and carries the fraction `1 − (p_min/p0)³` of the
//! force: the paper's estimators read radii and forces low (for the paper's
//! loads, p0 ≈ 1.9–2.3 MPa: about −3.5 % to −2.5 % on radii). The
//! [`Estimator::HertzFit`] estimator fits `p² = p0² (1 − ρ²/s²)` (linear in
//! `ρ²`) by least squares to the calibrated pixels with normalised radius
//! `ρ ≤ 0.85` inside the reacted ellipse, and reports the contact ellipse
//! `s·(a, b)`, radius `s√(ab)` and force `⅔ π (sa)(sb) p0`. It assumes a
//! smooth (paraboloidal) indenter, as the paper's balls; it also reads
//! through a saturated centre. See `docs/film.md` for measured biases.
//!
//! **Statistics** ([`compare`], [`AbsErrorStats`]). Per indenter
//! `ε_P = (P_meas − P_model)/P_model`, `ε_a = (a_meas − a_model)/a_model`; per
//! load, as in the paper's Table 1, the mean of `|ε|` and its sample standard
//! deviation (divisor `n − 1`).
//!
//! # Invariants
//!
//! - calibration inverse: `p(r(p)) = p` to round-off inside the range;
//! - no value outside a calibration's range is turned into a pressure;
//! - a [`Scan`] holds finite greys in `[0, 1]` and, when known, a pixel
//!   size of [`MIN_PIXEL_SIZE`] to [`MAX_PIXEL_SIZE`] (10 nm to 10 mm);
//! - ellipses have `semi_major ≥ semi_minor ≥ 0`, orientation in `(−π/2, π/2]`;
//! - user input (files, CSVs, layouts, calibrations) never panics: every
//!   failure is a [`FilmError`] naming the problem;
//! - renders are reproducible from their seed;
//! - a synthetic pressure map is a core [`Field`](tyreroad_core::Field) of
//!   square pixels, y up like every grid of the project ([`pixel_grid`],
//!   [`covering_grid`], [`add_hertz`]); scans run downward, and the row flip
//!   lives only in [`render`] and [`Frame::of_grid`].
//!
//! # Example
//!
//! A synthetic Hertzian print on LLW film, rendered and analysed:
//!
//! ```
//! use tyreroad_film::*;
//!
//! let film = FilmResponse::new(Calibration::llw(LlwCurve::B)?, Scanner::default());
//! // 16 N on a ball pressing a 1.9 mm contact: p0 ≈ 2.1 MPa.
//! let ball = HertzPrint { x: 0.0, y: 0.0, force: 16.0, radius: 1.9e-3 };
//! let map = hertz_pressure_map(&[ball], 240, 240, 25e-6)?;
//! let scan = render(&map, &film, &RenderOptions::default())?;
//! let det = analyse(&scan, &film, &AnalysisOptions::default())?;
//! assert_eq!(det.prints.len(), 1);
//! let print = &det.prints[0];
//! // The film misses the rim below 0.5 MPa: the reacted radius is short ...
//! let visible = 1.9e-3 * (1.0 - (0.486e6 / ball.peak_pressure()).powi(2)).sqrt();
//! assert!((print.apparent_radius / visible - 1.0).abs() < 0.01);
//! // ... the Hertz fit recovers the contact.
//! let f = print.force(Estimator::HertzFit).unwrap_or(f64::NAN);
//! let a = print.radius(Estimator::HertzFit).unwrap_or(f64::NAN);
//! assert!((f / 16.0 - 1.0).abs() < 0.03 && (a / 1.9e-3 - 1.0).abs() < 0.02);
//! # Ok::<(), FilmError>(())
//! ```
//!
//! Units: SI throughout the API (Pa, m, N); CSV files may give MPa, converted
//! on reading.

mod analysis;
mod annotate;
mod calibration;
mod compare;
mod error;
mod hertz_fit;
mod layout;
mod scan;
mod synthetic;

/// The data lines of a small CSV text, with their 0-based line index: trimmed,
/// blank lines and `#` comments skipped (every CSV this crate reads). A
/// UTF-8 byte-order mark (spreadsheet exports write one) is not data.
pub(crate) fn data_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.strip_prefix('\u{feff}')
        .unwrap_or(text)
        .lines()
        .map(str::trim)
        .enumerate()
        .filter(|(_, line)| !line.is_empty() && !line.starts_with('#'))
}

pub use analysis::{
    AnalysisOptions, BACKGROUND_PRINT_FRACTION, Connectivity, Detection, Ellipse, Estimator,
    HertzFit, Print, Threshold, analyse, connected_components, histogram, otsu,
};
pub use annotate::{annotate, annotated_png, draw_number};
pub use calibration::{
    Calibrated, Calibration, FilmResponse, LLW_CHART_CSV, LlwChart, LlwCurve, MonotoneCubic,
    Response, Scanner,
};
pub use compare::{
    AbsErrorStats, Comparison, IndenterComparison, MODEL_CSV_HEADER, ModelRow, Table1Row, compare,
    layout_of, loads, measurements, parse_model_csv, read_model_csv, rows_at_load,
};
pub use error::{FilmError, Result};
pub use layout::{Frame, Indenter, Layout, Match, Matching, Origin, detect_grid, match_layout};
pub use scan::{Channel, MAX_PIXEL_SIZE, MIN_PIXEL_SIZE, Scan};
pub use synthetic::{
    HertzPrint, RenderOptions, SyntheticLoad, SyntheticOptions, add_hertz, covering_grid,
    hertz_pressure_map, paper_hertz_rows, pixel_grid, render, synthetic_round_trip,
};
