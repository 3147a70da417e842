//! Spectra: one-third-octave band maths (IEC 61260-1, base-10 system), the
//! Welch power spectral density and band levels, and the plain one-sided
//! periodogram.
//!
//! A base-10 one-third-octave band `k` about a reference `r` has the exact
//! centre `r · 10^(k/10)` and edges `centre · 10^(∓1/20)`
//! ([`third_octave_centre`], [`third_octave_edges`]): in frequency with
//! `r = 1 kHz` ([`Band`]), in wavelength with `r = 1 mm` (road texture).

use std::f64::consts::PI;

use realfft::RealFftPlanner;

use crate::CoreError;
use crate::validate::positive;

/// The fewest samples (and the shortest Welch segment) a spectrum is
/// computed from: a Hann window of fewer has no interior point to weigh.
pub const MIN_SPECTRUM_SAMPLES: usize = 4;

/// Nominal mid-band frequencies (Hz) of the bands `k = −17 … 10`
/// (20 Hz … 10 kHz), IEC 61260-1 / ISO 266.
pub const NOMINAL_CENTRES: [f64; 28] = [
    20.0, 25.0, 31.5, 40.0, 50.0, 63.0, 80.0, 100.0, 125.0, 160.0, 200.0, 250.0, 315.0, 400.0,
    500.0, 630.0, 800.0, 1000.0, 1250.0, 1600.0, 2000.0, 2500.0, 3150.0, 4000.0, 5000.0, 6300.0,
    8000.0, 10000.0,
];

/// Band index of the first nominal band (20 Hz).
const FIRST_INDEX: i32 = -17;

/// One one-third-octave band (base 10): exact centre
/// `f_m = 1000 · 10^(k/10)` Hz, edges `f_m · 10^(∓1/20)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Band {
    /// Band number `k` (0 at 1 kHz).
    pub index: i32,
    /// Nominal label (Hz), e.g. 31.5.
    pub nominal: f64,
    /// Exact mid-band frequency (Hz).
    pub centre: f64,
    /// Lower edge (Hz).
    pub lower: f64,
    /// Upper edge (Hz).
    pub upper: f64,
}

impl Band {
    /// Band `k`, for `k` in `−17 ..= 10` (None otherwise).
    pub fn new(index: i32) -> Option<Self> {
        let nominal = *NOMINAL_CENTRES.get(usize::try_from(index - FIRST_INDEX).ok()?)?;
        let centre = third_octave_centre(1000.0, index);
        let (lower, upper) = third_octave_edges(centre);
        Some(Self {
            index,
            nominal,
            centre,
            lower,
            upper,
        })
    }
}

/// Exact centre `reference · 10^(index/10)` of the base-10 one-third-octave
/// band `index` about `reference` (any unit: Hz, m).
pub fn third_octave_centre(reference: f64, index: i32) -> f64 {
    reference * 10f64.powf(f64::from(index) / 10.0)
}

/// Edges `(centre · 10^(−1/20), centre · 10^(1/20))` of the base-10
/// one-third-octave band about `centre`.
pub fn third_octave_edges(centre: f64) -> (f64, f64) {
    (centre * 10f64.powf(-0.05), centre * 10f64.powf(0.05))
}

/// The nominal bands 20 Hz … 10 kHz whose upper edge does not exceed
/// `max_frequency` (the Nyquist frequency `fs/2` of a signal).
pub fn bands_below(max_frequency: f64) -> Vec<Band> {
    (FIRST_INDEX..=10)
        .filter_map(Band::new)
        .filter(|b| b.upper <= max_frequency)
        .collect()
}

/// A one-sided power spectral density.
#[derive(Clone, Debug, PartialEq)]
pub struct Psd {
    /// Bin frequencies `m · df` (Hz), `m = 0 … L/2`.
    pub frequencies: Vec<f64>,
    /// Density (signal unit² / Hz).
    pub density: Vec<f64>,
    /// Bin width `df = fs / L` (Hz).
    pub resolution: f64,
    /// Segments averaged.
    pub segments: usize,
}

impl Psd {
    /// `Σ density · df`: the (window-weighted) mean square of the analysed
    /// signal.
    pub fn total_power(&self) -> f64 {
        self.density.iter().sum::<f64>() * self.resolution
    }

    /// Power in `[lower, upper]` (Hz): each bin `m` stands for the interval
    /// `[f_m − df/2, f_m + df/2]` and counts with the fraction of that
    /// interval inside the band.
    pub fn band_power(&self, lower: f64, upper: f64) -> f64 {
        let df = self.resolution;
        self.frequencies
            .iter()
            .zip(&self.density)
            .map(|(&f, &d)| {
                let overlap = (f + 0.5 * df).min(upper) - (f - 0.5 * df).max(lower);
                if overlap > 0.0 { d * overlap } else { 0.0 }
            })
            .sum()
    }
}

/// Welch's averaged periodogram of `signal` sampled at `sample_rate` (Hz):
/// segments of `segment_len` samples (the whole signal if longer), 50 %
/// overlap (hop `⌊L/2⌋`; trailing samples that do not fill a segment are
/// dropped), each with its mean removed when `detrend` is true, multiplied
/// by the periodic Hann window `w_j = ½ (1 − cos(2π j / L))` and
/// transformed (realfft). Normalisation by the window power:
///
/// ```text
/// S(f_m) = c_m |X_m|² / (fs Σ_j w_j²),   c_m = 1 at DC and Nyquist, 2 between
/// ```
///
/// so that `Σ_m S(f_m) df = Σ_j (w_j x_j)² / Σ_j w_j²`, the window-weighted
/// mean square (Parseval), averaged over segments.
///
/// # Errors
/// [`CoreError::InvalidShape`] for fewer than [`MIN_SPECTRUM_SAMPLES`]
/// samples or a shorter segment; [`CoreError::InvalidValue`] for a
/// non-finite sample, a sample rate that is not finite and > 0 or so
/// extreme that `1/(fs Σw²)` or `df = fs/L` leaves the normal floats
/// (about `1e-300 < fs < 1e300`), or samples so large that the density
/// overflows (`|x|` beyond about 1e150).
pub fn welch(
    signal: &[f64],
    sample_rate: f64,
    segment_len: usize,
    detrend: bool,
) -> Result<Psd, CoreError> {
    positive("sample rate (Hz)", sample_rate)?;
    if signal.len() < MIN_SPECTRUM_SAMPLES || segment_len < MIN_SPECTRUM_SAMPLES {
        return Err(CoreError::InvalidShape {
            name: "spectrum input",
            message: format!(
                "a spectrum needs at least 4 samples and segments of at least 4, got {} and {segment_len}",
                signal.len()
            ),
        });
    }
    check_finite_samples(signal)?;
    let l = segment_len.min(signal.len());
    let hop = (l / 2).max(1);
    let segments = (signal.len() - l) / hop + 1;
    let window: Vec<f64> = (0..l)
        .map(|j| 0.5 * (1.0 - (2.0 * PI * j as f64 / l as f64).cos()))
        .collect();
    let power: f64 = window.iter().map(|w| w * w).sum();
    let scale = 1.0 / (sample_rate * power * segments as f64);
    let df = sample_rate / l as f64;
    if !(scale.is_normal() && df.is_normal()) {
        return Err(CoreError::InvalidValue {
            name: "sample rate (Hz)",
            value: sample_rate,
            expected: "such that 1/(fs Σw²) and the bin width fs/L are normal floats \
                       (about 1e-300 < fs < 1e300)",
        });
    }
    let mut planner = RealFftPlanner::<f64>::new();
    let fft = planner.plan_fft_forward(l);
    let mut input = fft.make_input_vec();
    let mut spectrum = fft.make_output_vec();
    let mut density = vec![0.0; spectrum.len()];
    for s in 0..segments {
        let seg = &signal[s * hop..s * hop + l];
        let mean = if detrend {
            seg.iter().sum::<f64>() / l as f64
        } else {
            0.0
        };
        for ((x, &v), &w) in input.iter_mut().zip(seg).zip(&window) {
            *x = (v - mean) * w;
        }
        fft.process(&mut input, &mut spectrum)?;
        for (d, c) in density.iter_mut().zip(&spectrum) {
            *d += c.norm_sqr();
        }
    }
    let last = density.len() - 1;
    for (m, d) in density.iter_mut().enumerate() {
        let one_sided = if m == 0 || (m == last && l.is_multiple_of(2)) {
            1.0
        } else {
            2.0
        };
        *d *= one_sided * scale;
    }
    if density.iter().any(|d| !d.is_finite()) {
        return Err(amplitude_error(signal));
    }
    Ok(Psd {
        frequencies: (0..density.len()).map(|m| m as f64 * df).collect(),
        density,
        resolution: df,
        segments,
    })
}

/// The level of one band.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BandLevel {
    /// The band.
    pub band: Band,
    /// Band mean square (signal unit²).
    pub power: f64,
    /// `L = 10 log10(power / ref²)` (dB; `−∞` for zero power).
    pub level_db: f64,
}

/// One-third-octave levels of a PSD over `bands`, in dB re `reference`
/// (1 N for forces): `L = 10 log10(P_band / ref²)`.
pub fn band_levels(psd: &Psd, bands: &[Band], reference: f64) -> Result<Vec<BandLevel>, CoreError> {
    positive("reference level", reference)?;
    Ok(bands
        .iter()
        .map(|&band| {
            let power = psd.band_power(band.lower, band.upper);
            BandLevel {
                band,
                power,
                level_db: 10.0 * (power / (reference * reference)).log10(),
            }
        })
        .collect())
}

/// Default Welch segment length for `n` samples: the largest even number
/// `≤ n/2` (three segments at 50 % overlap), at least 4 (or `n`).
pub fn default_segment_len(n: usize) -> usize {
    ((n / 2) & !1).max(4).min(n)
}

/// The Welch segment actually used for `n` samples: `segment_len` (or
/// [`default_segment_len`]) capped at the signal, as [`welch`] caps it.
pub fn effective_segment_len(n: usize, segment_len: Option<usize>) -> usize {
    segment_len.unwrap_or_else(|| default_segment_len(n)).min(n)
}

/// The lowest one-third-octave band centre (Hz) that Welch segments of
/// `segment_len` samples at `sample_rate` resolve: a band is resolved when
/// it holds at least two frequency bins, `f (10^0.05 − 10^−0.05) ≥ 2 fs / L`.
/// Pass the segment actually used ([`effective_segment_len`]): a segment
/// asked longer than the signal resolves only what the signal does.
pub fn resolved_from(sample_rate: f64, segment_len: usize) -> f64 {
    2.0 * sample_rate / segment_len as f64 / (10f64.powf(0.05) - 10f64.powf(-0.05))
}

/// One-third-octave spectrum of a signal in one call: Welch PSD
/// ([`welch`], mean removed, [`default_segment_len`] unless given), the
/// nominal bands below the Nyquist frequency ([`bands_below`]), levels in dB
/// re `reference`.
pub fn third_octave(
    signal: &[f64],
    sample_rate: f64,
    reference: f64,
    segment_len: Option<usize>,
) -> Result<Vec<BandLevel>, CoreError> {
    let l = segment_len.unwrap_or_else(|| default_segment_len(signal.len()));
    let psd = welch(signal, sample_rate, l, true)?;
    band_levels(&psd, &bands_below(0.5 * sample_rate), reference)
}

/// One-third-octave levels of a transient: a record that holds the whole
/// event (it starts and ends at rest), analysed without a window. Each
/// band's mean square is the exact integral of the record's discrete-time
/// Fourier transform over the band, per the record's length:
///
/// ```text
/// P = 2/(N fs) ∫_lower^upper |X(f)|² df,   |X(f)|² = r_0 + 2 Σ_{l≥1} r_l cos(2π f l / fs)
///   = 2/(N fs) [ r_0 (b − a) + Σ_{l≥1} r_l fs (sin(2π b l/fs) − sin(2π a l/fs)) / (π l) ]
/// ```
///
/// (`r_l = Σ_j x_j x_{j+l}`, `a`, `b` the band's edges), so the bands from
/// 0 to `fs/2` add up to the record's mean square (Parseval) and every
/// band is resolved, however narrow: nothing is cut off at the record's
/// ends, so there is no leakage to weigh against a band's width. No mean is
/// removed (a pulse's mean is part of it). Levels in dB re `reference`.
///
/// # Errors
/// [`CoreError::InvalidShape`] for fewer than [`MIN_SPECTRUM_SAMPLES`]
/// samples, [`CoreError::InvalidValue`] for a non-finite sample or a
/// non-positive sample rate or reference, samples so large that `Σ x²`
/// overflows, or a sample rate so small that a band's power does.
pub fn transient_band_levels(
    signal: &[f64],
    sample_rate: f64,
    bands: &[Band],
    reference: f64,
) -> Result<Vec<BandLevel>, CoreError> {
    positive("sample rate (Hz)", sample_rate)?;
    positive("reference level", reference)?;
    if signal.len() < MIN_SPECTRUM_SAMPLES {
        return Err(CoreError::InvalidShape {
            name: "spectrum input",
            message: format!(
                "a spectrum needs at least {MIN_SPECTRUM_SAMPLES} samples, got {}",
                signal.len()
            ),
        });
    }
    check_finite_samples(signal)?;
    let n = signal.len();
    let lags: Vec<f64> = (0..n)
        .map(|l| {
            signal[..n - l]
                .iter()
                .zip(&signal[l..])
                .map(|(a, b)| a * b)
                .sum()
        })
        .collect();
    // r_0 = Σ x² bounds every lag (Cauchy–Schwarz).
    if !lags[0].is_finite() {
        return Err(amplitude_error(signal));
    }
    let fs = sample_rate;
    bands
        .iter()
        .map(|&band| {
            let (a, b) = (band.lower.min(0.5 * fs), band.upper.min(0.5 * fs));
            let oscillating: f64 = lags
                .iter()
                .enumerate()
                .skip(1)
                .map(|(l, r)| {
                    let w = 2.0 * PI * l as f64 / fs;
                    r * ((w * b).sin() - (w * a).sin()) / w
                })
                .sum();
            let integral = lags[0] * (b - a).max(0.0) + 2.0 * oscillating;
            let raw = 2.0 * integral / (n as f64 * fs);
            // The clamp below would read a NaN as silence.
            if !raw.is_finite() {
                return Err(CoreError::InvalidValue {
                    name: "sample rate (Hz)",
                    value: sample_rate,
                    expected: "large enough that the band powers 2∫|X|²/(N fs) are finite",
                });
            }
            let power = raw.max(0.0);
            Ok(BandLevel {
                band,
                power,
                level_db: 10.0 * (power / (reference * reference)).log10(),
            })
        })
        .collect()
}

/// The one-sided periodogram of `samples` (no window, no mean removal):
/// `P_k = c_k |X_k|² / N²` for `k = 0 … ⌊N/2⌋`, `c_k = 1` at DC and (even
/// `N`) Nyquist, 2 between, so that `Σ_k P_k` is the mean square of the
/// samples (Parseval). Bin `k` stands for the frequency `k / (N Δ)` of
/// samples spaced by `Δ`.
///
/// # Errors
/// [`CoreError::InvalidShape`] for fewer than 2 samples,
/// [`CoreError::InvalidValue`] for a non-finite sample or samples so large
/// that `|X_k|²` overflows (`|x|` beyond about 1e150).
pub fn periodogram(samples: &[f64]) -> Result<Vec<f64>, CoreError> {
    let n = samples.len();
    if n < 2 {
        return Err(CoreError::InvalidShape {
            name: "periodogram input",
            message: format!("{n} sample(s): at least 2 are needed"),
        });
    }
    check_finite_samples(samples)?;
    let fft = RealFftPlanner::<f64>::new().plan_fft_forward(n);
    let mut input = samples.to_vec();
    let mut spectrum = fft.make_output_vec();
    fft.process(&mut input, &mut spectrum)?;
    let nn = (n * n) as f64;
    let power: Vec<f64> = spectrum
        .iter()
        .enumerate()
        .map(|(k, c)| {
            if k == 0 || 2 * k == n {
                c.norm_sqr() / nn
            } else {
                2.0 * c.norm_sqr() / nn
            }
        })
        .collect();
    if power.iter().any(|p| !p.is_finite()) {
        return Err(amplitude_error(samples));
    }
    Ok(power)
}

/// The error of samples whose power overflows, naming the largest one.
fn amplitude_error(samples: &[f64]) -> CoreError {
    CoreError::InvalidValue {
        name: "signal amplitude (largest |sample|)",
        value: samples.iter().fold(0.0, |m: f64, v| m.max(v.abs())),
        expected: "small enough that its power is finite (below about 1e150)",
    }
}

fn check_finite_samples(samples: &[f64]) -> Result<(), CoreError> {
    match samples.iter().find(|v| !v.is_finite()) {
        Some(&v) => Err(CoreError::InvalidValue {
            name: "signal sample",
            value: v,
            expected: "finite",
        }),
        None => Ok(()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn bands_match_iec_nominal_labels() {
        for k in -17..=10 {
            let b = Band::new(k).expect("band in range");
            // Exact and nominal centres agree to within 2 % (ISO 266 rounding).
            assert!((b.centre / b.nominal - 1.0).abs() < 0.02, "{b:?}");
            assert!((b.upper / b.lower - 10f64.powf(0.1)).abs() < 1e-12);
        }
        assert!(Band::new(-18).is_none() && Band::new(11).is_none());
        // Contiguous: each upper edge is the next lower edge.
        let bands = bands_below(1e5);
        assert_eq!(bands.len(), 28);
        for w in bands.windows(2) {
            assert!((w[0].upper / w[1].lower - 1.0).abs() < 1e-12);
        }
    }

    /// A sum of tones at bin frequencies inside 20 Hz … 5 kHz: the band
    /// powers add up to the mean square to 1e-10 relative (the Hann leakage
    /// of a bin-centred tone stays within ±1 bin, all inside the bands).
    #[test]
    fn band_powers_sum_to_mean_square() -> Result<(), CoreError> {
        let (fs, n, l) = (16384.0, 8192, 1024);
        let df = fs / l as f64; // 16 Hz
        let tones = [(5.0, 1.3), (37.0, 0.4), (180.0, 2.0), (250.0, 0.05)];
        let signal: Vec<f64> = (0..n)
            .map(|j| {
                let t = j as f64 / fs;
                tones
                    .iter()
                    .map(|&(m, a)| a * (2.0 * PI * m * df * t + m).sin())
                    .sum()
            })
            .collect();
        let mean_square = signal.iter().map(|v| v * v).sum::<f64>() / n as f64;
        let expected: f64 = tones.iter().map(|&(_, a)| 0.5 * a * a).sum();
        assert!((mean_square / expected - 1.0).abs() < 1e-12);
        let psd = welch(&signal, fs, l, true)?;
        assert!((psd.total_power() / expected - 1.0).abs() < 1e-10);
        let levels = band_levels(&psd, &bands_below(fs / 2.0), 1.0)?;
        let sum: f64 = levels.iter().map(|b| b.power).sum();
        assert!((sum / expected - 1.0).abs() < 1e-10, "{sum} vs {expected}");
        Ok(())
    }

    #[test]
    fn tone_at_band_centre_lands_in_its_band() -> Result<(), CoreError> {
        let fs = 48000.0;
        for k in [-10, 0, 5] {
            let band = Band::new(k).expect("band");
            let signal: Vec<f64> = (0..48000)
                .map(|j| 3.0 * (2.0 * PI * band.centre * j as f64 / fs).sin())
                .collect();
            let levels = third_octave(&signal, fs, 1.0, Some(8192))?;
            let best = levels
                .iter()
                .max_by(|a, b| a.power.total_cmp(&b.power))
                .expect("bands");
            assert_eq!(best.band.index, k);
            // 3 N amplitude: 4.5 N² → 6.53 dB re 1 N, within 0.1 dB.
            assert!(
                (best.level_db - 10.0 * 4.5f64.log10()).abs() < 0.1,
                "{best:?}"
            );
        }
        Ok(())
    }

    /// The closed-form spectrum of a Gaussian pulse, `|X(f)|² = fs² A²
    /// 2π σ² exp(−4π² σ² f²)` (sampled far above its bandwidth, so the
    /// discrete transform is `fs` times the continuous one), integrated by
    /// Simpson's rule over each band: the transient levels agree to 1e-6 dB
    /// wherever the pulse sits in the record, while one Hann segment of the
    /// same records moves the levels by decibels.
    #[test]
    fn transient_levels_match_a_gaussian_pulse_anywhere_in_the_record() -> Result<(), CoreError> {
        let (fs, n, amplitude, sigma) = (10_000.0, 200, 3.0, 3e-4);
        let pulse = |t0: f64| -> Vec<f64> {
            (0..n)
                .map(|j| {
                    let t = j as f64 / fs - t0;
                    amplitude * (-t * t / (2.0 * sigma * sigma)).exp()
                })
                .collect()
        };
        let bands: Vec<Band> = (-10..=3).filter_map(Band::new).collect(); // 100 Hz … 2 kHz
        let expected = |band: &Band| {
            let density = |f: f64| {
                fs * fs
                    * amplitude
                    * amplitude
                    * 2.0
                    * PI
                    * sigma
                    * sigma
                    * (-4.0 * PI * PI * sigma * sigma * f * f).exp()
            };
            let m = 2000;
            let h = (band.upper - band.lower) / m as f64;
            let simpson: f64 = (0..=m)
                .map(|i| {
                    let w = if i == 0 || i == m {
                        1.0
                    } else if i % 2 == 1 {
                        4.0
                    } else {
                        2.0
                    };
                    w * density(band.lower + i as f64 * h)
                })
                .sum::<f64>()
                * h
                / 3.0;
            10.0 * (2.0 * simpson / (n as f64 * fs)).log10()
        };
        let early = transient_band_levels(&pulse(0.004), fs, &bands, 1.0)?;
        let late = transient_band_levels(&pulse(0.010), fs, &bands, 1.0)?;
        for ((e, l), band) in early.iter().zip(&late).zip(&bands) {
            assert!((e.level_db - expected(band)).abs() < 1e-6, "{e:?}");
            assert!((l.level_db - e.level_db).abs() < 1e-6, "{l:?}");
        }
        // The Hann segment weighs the early pulse by the window's rising
        // flank: its levels are a window's, not the pulse's.
        let hann = |x: &[f64]| band_levels(&welch(x, fs, n, true)?, &bands, 1.0);
        let (he, hl) = (hann(&pulse(0.004))?, hann(&pulse(0.010))?);
        let moved = he
            .iter()
            .zip(&hl)
            .map(|(a, b)| (a.level_db - b.level_db).abs())
            .fold(0.0, f64::max);
        assert!(moved > 3.0, "Hann levels moved by {moved} dB only");
        Ok(())
    }

    /// One band from 0 to the Nyquist frequency holds the record's mean
    /// square (Parseval), for any record, not only a pulse.
    #[test]
    fn transient_levels_sum_to_the_mean_square() -> Result<(), CoreError> {
        let fs = 1000.0;
        let x: Vec<f64> = (0..37)
            .map(|j| (0.37 * j as f64).sin() + 0.2 * (j % 5) as f64)
            .collect();
        let whole = Band {
            index: 0,
            nominal: 0.0,
            centre: 0.25 * fs,
            lower: 0.0,
            upper: 0.5 * fs,
        };
        let p = transient_band_levels(&x, fs, &[whole], 1.0)?[0].power;
        let mean_square = x.iter().map(|v| v * v).sum::<f64>() / x.len() as f64;
        assert!(
            (p / mean_square - 1.0).abs() < 1e-12,
            "{p} vs {mean_square}"
        );
        assert!(transient_band_levels(&x[..3], fs, &[whole], 1.0).is_err());
        assert!(transient_band_levels(&[1.0, f64::NAN, 0.0, 0.0], fs, &[whole], 1.0).is_err());
        assert!(transient_band_levels(&x, fs, &[whole], 0.0).is_err());
        Ok(())
    }

    #[test]
    fn periodogram_sums_to_the_mean_square() -> Result<(), CoreError> {
        // Cosine of amplitude 2 on bin 3 of 16 samples, plus a mean of 0.5.
        let x: Vec<f64> = (0..16)
            .map(|j| 0.5 + 2.0 * (2.0 * PI * 3.0 * j as f64 / 16.0).cos())
            .collect();
        let p = periodogram(&x)?;
        assert_eq!(p.len(), 9);
        assert!((p[0] - 0.25).abs() < 1e-14);
        assert!((p[3] - 2.0).abs() < 1e-14);
        let total: f64 = p.iter().sum();
        assert!((total - 2.25).abs() < 1e-14);
        assert!(periodogram(&[1.0]).is_err());
        assert!(periodogram(&[1.0, f64::NAN]).is_err());
        Ok(())
    }

    #[test]
    fn bad_input_is_an_error() {
        assert!(welch(&[1.0; 3], 1.0, 4, true).is_err());
        assert!(welch(&[1.0, f64::NAN, 1.0, 1.0], 1.0, 4, true).is_err());
        assert!(welch(&[1.0; 8], 0.0, 4, true).is_err());
        let psd = welch(&[1.0, 2.0, 3.0, 4.0], 1.0, 4, false).ok();
        assert!(psd.is_some_and(|p| band_levels(&p, &[], 0.0).is_err()));
    }

    /// Regression (adversarial run): samples of amplitude 1e200 or a sample
    /// rate of 1e-320 gave an infinite density as Ok, and the transient's
    /// overflowing powers read as 0.
    #[test]
    fn a_spectrum_that_overflows_is_refused_naming_the_amplitude_or_the_rate() {
        let loud: Vec<f64> = (0..64).map(|i| 1e200 * (i as f64).sin()).collect();
        let quiet: Vec<f64> = (0..64).map(|i| (i as f64).sin()).collect();
        let is_amplitude = |e: CoreError| {
            let text = e.to_string();
            assert!(text.contains("1e200") || text.contains("e199"), "{text}");
            matches!(
                e,
                CoreError::InvalidValue {
                    name: "signal amplitude (largest |sample|)",
                    ..
                }
            )
        };
        assert!(is_amplitude(
            welch(&loud, 100.0, 16, true).expect_err("overflow")
        ));
        assert!(is_amplitude(
            third_octave(&loud, 100.0, 1.0, None).expect_err("overflow")
        ));
        assert!(is_amplitude(periodogram(&loud).expect_err("overflow")));
        let bands = bands_below(50.0);
        assert!(is_amplitude(
            transient_band_levels(&loud, 100.0, &bands, 1.0).expect_err("overflow")
        ));
        for fs in [1e-320, 1e308] {
            let e = welch(&quiet, fs, 16, true).expect_err("extreme sample rate");
            assert!(
                matches!(
                    e,
                    CoreError::InvalidValue {
                        name: "sample rate (Hz)",
                        ..
                    }
                ),
                "{e}"
            );
        }
        // 1e-200 amplitude and ordinary rates keep working.
        let faint: Vec<f64> = quiet.iter().map(|v| 1e-100 * v).collect();
        let psd = welch(&faint, 100.0, 16, true).expect("finite");
        assert!(psd.total_power() > 0.0 && psd.total_power().is_finite());
        assert!(
            periodogram(&faint)
                .expect("finite")
                .iter()
                .all(|p| p.is_finite())
        );
    }

    /// A segment asked longer than the signal is the signal: the band
    /// resolution follows the samples there are, not the request (a
    /// 6-sample stretch once claimed bands from 0 Hz up resolved).
    #[test]
    fn resolution_follows_the_segment_used_not_the_one_asked() {
        assert_eq!(effective_segment_len(6, Some(1_000_000_000)), 6);
        assert_eq!(effective_segment_len(1000, None), 500);
        assert_eq!(effective_segment_len(1000, Some(200)), 200);
        let fs = 13_888.9;
        let from_six = resolved_from(fs, effective_segment_len(6, Some(1_000_000_000)));
        // Two bins of fs/6 in a band of relative width 0.2303: ~20 kHz.
        assert!((from_six - 2.0 * fs / 6.0 / 0.230_3).abs() < 0.01 * from_six);
        assert!(
            from_six > 0.5 * fs,
            "nothing below Nyquist is resolved by 6 samples"
        );
    }
}
