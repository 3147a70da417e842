//! The multipoint rolling run against the BEM reference, step by step and
//! band by band.

use crate::rolling::{self, BandLevel, RollingResult, Sensor};

use super::{BemRollingError, BemRollingResult};

/// Band range of the spectral targets (nominal centres, Hz).
pub const BAND_RANGE: [f64; 2] = [100.0, 2000.0];

/// One one-third-octave band of a signal, model against reference.
#[derive(Clone, Debug, PartialEq)]
pub struct BandComparison {
    /// Nominal centre (Hz).
    pub nominal: f64,
    /// Model level (dB).
    pub model_db: f64,
    /// Reference (BEM) level (dB).
    pub reference_db: f64,
    /// `model − reference` (dB; 0 when both are silent).
    pub difference_db: f64,
    /// Level of the error signal `model − reference` in the band, re the
    /// reference's level there (dB; `−∞` when they agree). Band levels are
    /// norms, so whatever the error's phase `|difference_db| ≤ −20
    /// log10(1 − 10^(error_db/20))`: within 1 dB for certain when
    /// `error_db ≤` [`ERROR_DB_FOR_1DB`], by the error's phase alone
    /// between that and about −6 dB (an error uncorrelated with the
    /// reference adds `10 log10(1 + 10^(error_db/10))`).
    pub error_db: f64,
    /// Whether the band is resolved: a transient's bands always are
    /// ([`SpectrumKind::Transient`]); under Welch, a band with two bins or
    /// more in its width; unresolved bands hold their neighbours' leakage.
    pub resolved: bool,
}

/// The error level (dB re the reference's band) at or below which a band
/// is within 1 dB whatever the error's phase: `20 log10(1 − 10^(−1/20))`.
pub const ERROR_DB_FOR_1DB: f64 = -19.271_489_616_766_054;

/// How a signal's bands are computed (docs/validation.md, "Where the bands
/// miss").
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SpectrumKind {
    /// Welch's PSD (Hann segments, mean removed): a signal that runs
    /// through the stretch (the approach); bands below the comparison's
    /// `resolved_from` are unresolved.
    Welch,
    /// The whole record without a window
    /// ([`crate::shared::spectrum::transient_band_levels`]): both runs'
    /// signals start and end at rest inside the stretch (a sensor's
    /// passage), so the record holds the whole event and every band is
    /// resolved.
    Transient,
}

impl SpectrumKind {
    /// The name the reports and CSVs use: `"welch"`, `"transient"`.
    pub fn name(self) -> &'static str {
        match self {
            Self::Welch => "welch",
            Self::Transient => "transient",
        }
    }
}

/// One signal of the model against the same signal of the reference.
#[derive(Clone, Debug, PartialEq)]
pub struct SignalComparison {
    /// Signal name ("total", "approach", a sensor's name).
    pub name: String,
    /// What the per-step errors are relative to: the reference's value at
    /// each step (`total`), its mean magnitude (`approach`) or its peak
    /// over the run (sensors).
    pub scale: f64,
    /// Largest per-step `|model − reference| / scale` over steps where
    /// both have values.
    pub max_error: f64,
    /// Root-mean-square of the same.
    pub rms_error: f64,
    /// How the bands were computed.
    pub spectrum: SpectrumKind,
    /// Bands with centres from 100 Hz to 2 kHz (none for a signal that
    /// both runs hold constant, such as the total force under load
    /// control).
    pub bands: Vec<BandComparison>,
}

impl SignalComparison {
    /// Largest `|Δ dB|` over the bands 100 Hz … 2 kHz (resolved or not).
    pub fn max_band_db(&self) -> f64 {
        self.bands
            .iter()
            .map(|b| b.difference_db.abs())
            .fold(0.0, f64::max)
    }

    /// Largest `|Δ dB|` over the resolved bands 100 Hz … 2 kHz (0 when
    /// none is resolved).
    pub fn max_resolved_band_db(&self) -> f64 {
        self.bands
            .iter()
            .filter(|b| b.resolved)
            .map(|b| b.difference_db.abs())
            .fold(0.0, f64::max)
    }

    /// Largest error level ([`BandComparison::error_db`]) over the resolved
    /// bands 100 Hz … 2 kHz (`−∞` when none is resolved).
    pub fn max_resolved_error_db(&self) -> f64 {
        self.bands
            .iter()
            .filter(|b| b.resolved)
            .map(|b| b.error_db)
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// The whole comparison of one stretch.
#[derive(Clone, Debug, PartialEq)]
pub struct RollingComparison {
    /// Steps compared.
    pub steps: usize,
    /// Total force, error relative to the BEM's total at each step (0 by
    /// construction under load control).
    pub total: SignalComparison,
    /// Approach `δ0`, error relative to the BEM's mean approach; levels in
    /// dB re 1 µm.
    pub approach: SignalComparison,
    /// Each sensor, the model's forces as fields (each contact's pressure
    /// profile over its patch, `Sensor::share`), error relative to the
    /// BEM sensor's peak.
    pub sensors: Vec<SignalComparison>,
    /// Each sensor with the model's forces as points at the summits (the
    /// whole force of a contact to the sensor holding its summit), for the
    /// measure of what the fields bring.
    pub sensors_summit: Vec<SignalComparison>,
    /// Lowest band centre the Welch segment resolves (Hz), for the signals
    /// analysed by Welch ([`SpectrumKind::Welch`]).
    pub resolved_from: f64,
}

/// One-third-octave levels under the rolling runs' policy: failed samples
/// (NaN) bridged by linear interpolation ([`rolling::interpolate_failed`]),
/// the core's Welch PSD with `segment` samples (default: the core's
/// [`rolling::default_segment_len`]), levels re `reference`.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for a signal too short for the
/// segment or a non-positive reference.
pub fn third_octave_policy(
    signal: &[f64],
    sample_rate: f64,
    reference: f64,
    segment: Option<usize>,
) -> Result<Vec<BandLevel>, BemRollingError> {
    let (signal, _) = rolling::interpolate_failed(signal);
    rolling::third_octave(&signal, sample_rate, reference, segment)
        .map_err(|e| BemRollingError::InvalidInput(format!("one-third-octave spectrum: {e}")))
}

/// One-third-octave levels of a transient under the rolling runs' policy:
/// failed samples bridged as in [`third_octave_policy`], the bands below
/// the Nyquist frequency of the whole record without a window
/// ([`crate::shared::spectrum::transient_band_levels`]), levels re
/// `reference`.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for a signal too short or a
/// non-positive reference.
pub fn transient_policy(
    signal: &[f64],
    sample_rate: f64,
    reference: f64,
) -> Result<Vec<BandLevel>, BemRollingError> {
    let (signal, _) = rolling::interpolate_failed(signal);
    let bands = rolling::bands_below(0.5 * sample_rate);
    crate::shared::spectrum::transient_band_levels(&signal, sample_rate, &bands, reference)
        .map_err(|e| BemRollingError::InvalidInput(format!("transient spectrum: {e}")))
}

/// Whether a signal starts and ends at rest: its first and last samples
/// (failed ones bridged) within 1e-9 of its peak magnitude of zero.
fn at_rest(x: &[f64]) -> bool {
    let (x, _) = rolling::interpolate_failed(x);
    let peak = x.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    match (x.first(), x.last()) {
        (Some(a), Some(b)) => a.abs() <= 1e-9 * peak && b.abs() <= 1e-9 * peak,
        _ => false,
    }
}

/// Sensor forces with each contact's whole force at its summit: per sensor,
/// per step, the sum of the contact forces whose summit lies in the
/// half-open rectangle `[x0, x1) × [y0, y1)` (as `Sensor::share` counts a
/// zero-radius contact). `positions` are the road's summits by id.
pub fn summit_sensor_forces(
    result: &RollingResult,
    positions: &[[f64; 2]],
    sensors: &[Sensor],
) -> Vec<Vec<f64>> {
    sensors
        .iter()
        .map(|s| {
            result
                .steps
                .iter()
                .map(|step| {
                    if step.status == rolling::StepStatus::Failed {
                        return f64::NAN;
                    }
                    step.contact_ids
                        .iter()
                        .zip(&step.contact_forces)
                        .filter(|&(&id, _)| {
                            let [x, y] = positions[id];
                            s.x[0] <= x && x < s.x[1] && s.y[0] <= y && y < s.y[1]
                        })
                        .map(|(_, &p)| p)
                        .sum()
                })
                .collect()
        })
        .collect()
}

/// How per-step errors are scaled.
#[derive(Clone, Copy)]
pub(super) enum Scale {
    /// By the reference's value at each step.
    PerStep,
    /// By the reference's mean magnitude.
    Mean,
    /// By the reference's peak magnitude.
    Peak,
}

/// A signal's one-third-octave levels, computed the given way.
type Spectrum<'a> = &'a dyn Fn(&[f64], SpectrumKind) -> Result<Vec<BandLevel>, BemRollingError>;

/// Whether the finite samples of `x` agree to 1e-9 of their magnitude.
fn is_constant(x: &[f64]) -> bool {
    let finite = || x.iter().copied().filter(|v| v.is_finite());
    let (lo, hi) = (
        finite().fold(f64::INFINITY, f64::min),
        finite().fold(f64::NEG_INFINITY, f64::max),
    );
    hi - lo <= 1e-9 * lo.abs().max(hi.abs())
}

/// Compares `model` and `reference` signals of one quantity.
pub(super) fn signal(
    name: &str,
    model: &[f64],
    reference: &[f64],
    scale: Scale,
    spectrum: Spectrum<'_>,
    resolved_from: f64,
) -> Result<SignalComparison, BemRollingError> {
    let pairs: Vec<(f64, f64)> = model
        .iter()
        .zip(reference)
        .filter(|(m, r)| m.is_finite() && r.is_finite())
        .map(|(&m, &r)| (m, r))
        .collect();
    let magnitudes = pairs.iter().map(|&(_, r)| r.abs());
    let global = match scale {
        Scale::PerStep => f64::NAN,
        Scale::Mean => magnitudes.sum::<f64>() / pairs.len().max(1) as f64,
        Scale::Peak => magnitudes.fold(0.0, f64::max),
    };
    let errors: Vec<f64> = pairs
        .iter()
        .map(|&(m, r)| {
            let s = if matches!(scale, Scale::PerStep) {
                r.abs()
            } else {
                global
            };
            if s > 0.0 {
                (m - r).abs() / s
            } else if m == r {
                0.0
            } else {
                f64::INFINITY
            }
        })
        .collect();
    let max_error = errors.iter().copied().fold(0.0, f64::max);
    let rms_error = (errors.iter().map(|e| e * e).sum::<f64>() / errors.len().max(1) as f64).sqrt();
    // A signal held constant (the total force under load control) has
    // only rounding noise in its bands: nothing to compare.
    // A pulse the stretch holds whole is analysed whole: a window would
    // weigh its parts by where they fall in the stretch and leave its low
    // bands unresolved.
    let kind = if at_rest(model) && at_rest(reference) {
        SpectrumKind::Transient
    } else {
        SpectrumKind::Welch
    };
    if is_constant(model) && is_constant(reference) {
        return Ok(SignalComparison {
            name: name.into(),
            scale: global,
            max_error,
            rms_error,
            spectrum: kind,
            bands: Vec::new(),
        });
    }
    // The error signal's bands: a failed sample in either run is one in
    // the error, bridged like the others.
    let error: Vec<f64> = model.iter().zip(reference).map(|(m, r)| m - r).collect();
    let (lm, lr, le) = (
        spectrum(model, kind)?,
        spectrum(reference, kind)?,
        spectrum(&error, kind)?,
    );
    let bands = lm
        .iter()
        .zip(&lr)
        .zip(&le)
        .filter(|((m, _), _)| (BAND_RANGE[0]..=BAND_RANGE[1]).contains(&m.band.nominal))
        .map(|((m, r), e)| BandComparison {
            nominal: m.band.nominal,
            model_db: m.level_db,
            reference_db: r.level_db,
            difference_db: if m.level_db == r.level_db {
                0.0
            } else {
                m.level_db - r.level_db
            },
            error_db: if e.power == 0.0 {
                f64::NEG_INFINITY
            } else {
                e.level_db - r.level_db
            },
            resolved: kind == SpectrumKind::Transient || m.band.centre >= resolved_from,
        })
        .collect();
    Ok(SignalComparison {
        name: name.into(),
        scale: global,
        max_error,
        rms_error,
        spectrum: kind,
        bands,
    })
}

/// A signal's levels the given way (Welch with `segment`, or as a
/// transient), re `reference`.
fn levels(
    x: &[f64],
    kind: SpectrumKind,
    sample_rate: f64,
    reference: f64,
    segment: Option<usize>,
) -> Result<Vec<BandLevel>, BemRollingError> {
    match kind {
        SpectrumKind::Welch => third_octave_policy(x, sample_rate, reference, segment),
        SpectrumKind::Transient => transient_policy(x, sample_rate, reference),
    }
}

/// Is the reference converged in the bands compared? A second BEM run
/// `check` of the same stretch (another grid: the texture at twice the
/// spacing, say) in the model's place against `reference`: the approach,
/// then each sensor, per step and per band under the same rules as
/// [`compare`]. Each band's `error_db` is the level of `check −
/// reference` re the reference's: a model's error far above it is the
/// model's.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the runs differ in steps, rate
/// or sensors, or a spectrum cannot be computed.
pub fn compare_references(
    check: &BemRollingResult,
    reference: &BemRollingResult,
    sensors: &[Sensor],
    reference_force: f64,
    segment: Option<usize>,
) -> Result<Vec<SignalComparison>, BemRollingError> {
    let n = reference.steps.len();
    let differ = check.steps.len() != n
        || check.sample_rate != reference.sample_rate
        || check
            .steps
            .iter()
            .chain(&reference.steps)
            .any(|s| s.sensor_forces.len() != sensors.len());
    if differ {
        return Err(BemRollingError::InvalidInput(format!(
            "the BEM runs differ: {} and {n} steps at {} and {} Hz, {} sensors expected",
            check.steps.len(),
            check.sample_rate,
            reference.sample_rate,
            sensors.len()
        )));
    }
    let fs = reference.sample_rate;
    let resolved_from = rolling::resolved_from(fs, rolling::effective_segment_len(n, segment));
    let forces = |x: &[f64], kind| levels(x, kind, fs, reference_force, segment);
    let microns = |x: &[f64], kind| levels(x, kind, fs, 1e-6, segment);
    let mut out = vec![signal(
        "approach",
        &check.approach(),
        &reference.approach(),
        Scale::Mean,
        &microns,
        resolved_from,
    )?];
    for (k, s) in sensors.iter().enumerate() {
        out.push(signal(
            &s.name,
            &check.sensor(k),
            &reference.sensor(k),
            Scale::Peak,
            &forces,
            resolved_from,
        )?);
    }
    Ok(out)
}

/// Compares the multipoint run `model` (its sensors `sensors`, the road's
/// summits `positions` by id) with the BEM reference `reference` over the
/// same path: per-step errors and band levels (forces in dB re
/// `reference_force`, the approach in dB re 1 µm; Welch segment `segment`
/// or the core's default).
///
/// # Errors
/// [`BemRollingError::InvalidInput`] when the runs differ in steps or
/// sensors, or a spectrum cannot be computed.
pub fn compare(
    model: &RollingResult,
    positions: &[[f64; 2]],
    sensors: &[Sensor],
    reference: &BemRollingResult,
    reference_force: f64,
    segment: Option<usize>,
) -> Result<RollingComparison, BemRollingError> {
    let n = model.steps.len();
    if n != reference.steps.len() || model.sample_rate != reference.sample_rate {
        return Err(BemRollingError::InvalidInput(format!(
            "the runs differ: {n} steps at {} Hz against {} steps at {} Hz",
            model.sample_rate,
            reference.steps.len(),
            reference.sample_rate
        )));
    }
    if let Some(s) = reference
        .steps
        .iter()
        .find(|s| s.sensor_forces.len() != sensors.len())
    {
        return Err(BemRollingError::InvalidInput(format!(
            "the BEM run has {} sensors, the model {}",
            s.sensor_forces.len(),
            sensors.len()
        )));
    }
    let fs = model.sample_rate;
    let resolved_from = rolling::resolved_from(fs, rolling::effective_segment_len(n, segment));
    let forces = |x: &[f64], kind| levels(x, kind, fs, reference_force, segment);
    let microns = |x: &[f64], kind| levels(x, kind, fs, 1e-6, segment);
    let total = signal(
        "total",
        &model.total_force(),
        &reference.total_force(),
        Scale::PerStep,
        &forces,
        resolved_from,
    )?;
    let approach = signal(
        "approach",
        &model.approach(),
        &reference.approach(),
        Scale::Mean,
        &microns,
        resolved_from,
    )?;
    let summit = summit_sensor_forces(model, positions, sensors);
    let mut fields = Vec::with_capacity(sensors.len());
    let mut points = Vec::with_capacity(sensors.len());
    for (k, s) in sensors.iter().enumerate() {
        let r = reference.sensor(k);
        fields.push(signal(
            &s.name,
            &model.sensor(k),
            &r,
            Scale::Peak,
            &forces,
            resolved_from,
        )?);
        points.push(signal(
            &s.name,
            &summit[k],
            &r,
            Scale::Peak,
            &forces,
            resolved_from,
        )?);
    }
    Ok(RollingComparison {
        steps: n,
        total,
        approach,
        sensors: fields,
        sensors_summit: points,
        resolved_from,
    })
}
