//! Texture indicators: mean profile depth (ISO 13473-1) and the
//! one-third-octave texture spectrum (ISO/TS 13473-4).

// Numerical kernels index several arrays in step.
#![allow(clippy::needless_range_loop)]

use tyreroad_core::spectrum::{periodogram, third_octave_centre, third_octave_edges};
use tyreroad_core::validate;

use crate::error::TextureError;
use crate::heightmap::HeightMap;

/// The ISO 13473-1 baseline (m).
pub const MPD_BASELINE: f64 = 0.1;

/// Mean profile depth of a map and how it was computed.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Mpd {
    /// Mean profile depth (m): the mean of the segments' mean segment
    /// depths.
    pub mpd: f64,
    /// Baseline actually used (m): `samples · dx`.
    pub baseline: f64,
    /// Samples per baseline segment.
    pub samples: usize,
    /// Number of segments averaged (over all profiles).
    pub segments: usize,
}

/// Mean segment depth of one baseline segment (heights, NaN = missing):
/// `None` when fewer than 90 % of its points, or none of a half, are valid.
///
/// Procedure: the least-squares line through the valid points (index as
/// abscissa) is subtracted; the segment is split into a first half of
/// `⌊N/2⌋` samples and a second half of the rest; `MSD = (peak₁ + peak₂)/2`
/// of the detrended heights (whose mean over the valid points is 0 by
/// construction of the regression, so this is "mean of the two peaks minus
/// the mean level").
pub fn mean_segment_depth(seg: &[f64]) -> Option<f64> {
    let n = seg.len();
    let valid: Vec<(f64, f64)> = seg
        .iter()
        .enumerate()
        .filter(|(_, h)| h.is_finite())
        .map(|(i, h)| (i as f64, *h))
        .collect();
    if n < 2 || (valid.len() as f64) < 0.9 * n as f64 || valid.len() < 2 {
        return None;
    }
    let m = valid.len() as f64;
    let xm = valid.iter().map(|p| p.0).sum::<f64>() / m;
    let ym = valid.iter().map(|p| p.1).sum::<f64>() / m;
    let sxx = valid.iter().map(|p| (p.0 - xm).powi(2)).sum::<f64>();
    let sxy = valid.iter().map(|p| (p.0 - xm) * (p.1 - ym)).sum::<f64>();
    let slope = if sxx > 0.0 { sxy / sxx } else { 0.0 };
    let half = n / 2;
    let (mut p1, mut p2) = (f64::NEG_INFINITY, f64::NEG_INFINITY);
    for &(x, y) in &valid {
        let d = y - ym - slope * (x - xm);
        if (x as usize) < half {
            p1 = p1.max(d);
        } else {
            p2 = p2.max(d);
        }
    }
    (p1.is_finite() && p2.is_finite()).then_some(0.5 * (p1 + p2))
}

/// Mean profile depth along x (ISO 13473-1).
///
/// Each profile (row) is cut into consecutive, non-overlapping segments of
/// `N = round(baseline/dx)` samples from its start (a remainder shorter than
/// `N` is dropped); each segment gives a mean segment depth
/// ([`mean_segment_depth`]) and the MPD is their mean over all profiles.
/// `baseline = None` uses [`MPD_BASELINE`] (100 mm). When the profiles are
/// shorter than the baseline (`nx < N`), the whole profile (`N = nx`) is the
/// baseline: the result is then an MPD over a shorter baseline, reported in
/// [`Mpd::baseline`]. Segments with more than 10 % missing points are
/// skipped; an error if none is left or `N < 4`.
pub fn mean_profile_depth(map: &HeightMap, baseline: Option<f64>) -> Result<Mpd, TextureError> {
    let baseline = validate::positive("MPD baseline", baseline.unwrap_or(MPD_BASELINE))?;
    let nx = map.nx();
    let samples = ((baseline / map.dx()).round() as usize).clamp(1, nx);
    if samples < 4 {
        return Err(TextureError::NotEnoughData(format!(
            "an MPD baseline of {samples} sample(s): at least 4 are needed"
        )));
    }
    let (mut sum, mut count) = (0.0, 0usize);
    for j in 0..map.ny() {
        let row = map.row(j);
        for seg in row.chunks_exact(samples) {
            if let Some(msd) = mean_segment_depth(seg) {
                sum += msd;
                count += 1;
            }
        }
    }
    if count == 0 {
        return Err(TextureError::NotEnoughData(
            "no MPD segment with ≥ 90 % valid points".into(),
        ));
    }
    Ok(Mpd {
        mpd: sum / count as f64,
        baseline: samples as f64 * map.dx(),
        samples,
        segments: count,
    })
}

/// One one-third-octave band of the texture spectrum.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThirdOctaveBand {
    /// Band index `m`: centre wavelength `10^(m/10)` mm.
    pub index: i32,
    /// Exact centre wavelength `10^(m/10)` mm, in m (nominal values: 0.5,
    /// 0.63, 0.8, 1, 1.25, ... mm).
    pub centre: f64,
    /// Lower wavelength edge, `centre · 10^(−1/20)` (m).
    pub lower: f64,
    /// Upper wavelength edge, `centre · 10^(1/20)` (m).
    pub upper: f64,
    /// Band rms amplitude `a_rms` (m), from the profile-averaged band power.
    pub rms: f64,
    /// Texture level `L = 20 log10(a_rms / 1 µm)` (dB re 1 µm); −∞ when no
    /// power falls in the band.
    pub level_db: f64,
}

/// Fill missing points of a profile by linear interpolation (constant
/// beyond the end valid points); `None` if under 90 % are valid.
fn fill_profile(row: &[f64]) -> Option<Vec<f64>> {
    let n = row.len();
    let idx: Vec<usize> = (0..n).filter(|&i| row[i].is_finite()).collect();
    if idx.is_empty() || (idx.len() as f64) < 0.9 * n as f64 {
        return None;
    }
    let mut out = row.to_vec();
    let (first, last) = (idx[0], idx[idx.len() - 1]);
    for v in out.iter_mut().take(first) {
        *v = row[first];
    }
    for v in out.iter_mut().skip(last + 1) {
        *v = row[last];
    }
    for w in idx.windows(2) {
        let (a, b) = (w[0], w[1]);
        for i in a + 1..b {
            let t = (i - a) as f64 / (b - a) as f64;
            out[i] = row[a] + t * (row[b] - row[a]);
        }
    }
    Some(out)
}

/// One-third-octave texture spectrum of the profiles along x (ISO/TS
/// 13473-4).
///
/// Method: each profile (row, with ≥ 90 % valid points; missing points
/// linearly interpolated) of `N` samples is detrended (least-squares line
/// removed) and Fourier transformed without a window; its one-sided
/// periodogram `P_k = 2|X_k|²/N²` (`|X_{N/2}|²/N²` at Nyquist) sums to the
/// profile's mean square (Parseval). Bin `k` has wavelength `λ_k = N·dx/k`;
/// the band power is the sum of the `P_k` with `lower ≤ λ_k < upper`,
/// averaged over the profiles; `a_rms = √(band power)` and
/// `L = 20 log10(a_rms / 1 µm)`. The bands returned are those lying wholly
/// within `[2·dx, N·dx]` (Nyquist to profile length), shortest wavelength
/// first. A sine of amplitude `A` whose wavelength is a band centre and a
/// whole fraction of the profile length falls in one bin: `a_rms = A/√2`.
pub fn third_octave_spectrum(map: &HeightMap) -> Result<Vec<ThirdOctaveBand>, TextureError> {
    let n = map.nx();
    if n < 8 {
        return Err(TextureError::NotEnoughData(format!(
            "profiles of {n} points: at least 8 are needed for a spectrum"
        )));
    }
    let length = n as f64 * map.dx();
    let (lo_idx, hi_idx) = (
        (10.0 * (2.0 * map.dx() * 1e3).log10() + 0.5).ceil() as i32,
        (10.0 * (length * 1e3).log10() - 0.5).floor() as i32,
    );
    let mut bands: Vec<ThirdOctaveBand> = (lo_idx..=hi_idx)
        .map(|m| {
            let centre = third_octave_centre(1e-3, m);
            let (lower, upper) = third_octave_edges(centre);
            ThirdOctaveBand {
                index: m,
                centre,
                lower,
                upper,
                rms: 0.0,
                level_db: f64::NEG_INFINITY,
            }
        })
        .filter(|b| b.lower >= 2.0 * map.dx() * (1.0 - 1e-12) && b.upper <= length * (1.0 + 1e-12))
        .collect();
    if bands.is_empty() {
        return Err(TextureError::NotEnoughData(
            "no one-third-octave band fits between 2·dx and the profile length".into(),
        ));
    }
    let mut power = vec![0.0; bands.len()];
    let mut profiles = 0usize;
    let mut detrended = vec![0.0; n];
    for j in 0..map.ny() {
        let Some(p) = fill_profile(map.row(j)) else {
            continue;
        };
        let xm = (n - 1) as f64 / 2.0;
        let ym = p.iter().sum::<f64>() / n as f64;
        let sxx: f64 = (0..n).map(|i| (i as f64 - xm).powi(2)).sum();
        let sxy: f64 = (0..n).map(|i| (i as f64 - xm) * (p[i] - ym)).sum();
        let slope = sxy / sxx;
        for (i, d) in detrended.iter_mut().enumerate() {
            *d = p[i] - ym - slope * (i as f64 - xm);
        }
        let periodogram = periodogram(&detrended)
            .map_err(|e| TextureError::NotEnoughData(format!("profile {j}: {e}")))?;
        for (k, &pk) in periodogram.iter().enumerate().skip(1) {
            let lambda = length / k as f64;
            if let Some(b) = bands
                .iter()
                .position(|b| lambda >= b.lower && lambda < b.upper)
            {
                power[b] += pk;
            }
        }
        profiles += 1;
    }
    if profiles == 0 {
        return Err(TextureError::NotEnoughData(
            "no profile with ≥ 90 % valid points".into(),
        ));
    }
    for (b, pw) in bands.iter_mut().zip(&power) {
        let p = pw / profiles as f64;
        b.rms = p.sqrt();
        b.level_db = 10.0 * (p / 1e-12).log10();
    }
    Ok(bands)
}
