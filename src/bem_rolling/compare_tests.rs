//! The band comparison's spectra: a sensor's passage held whole by the
//! stretch is analysed as a transient (every band resolved), a signal cut
//! by the stretch by Welch; each band's error level bounds its difference.

use std::f64::consts::PI;

use super::compare::{Scale, SignalComparison, SpectrumKind, signal};
use super::{
    BemRollingError, BemRollingResult, BemStep, ERROR_DB_FOR_1DB, compare_references,
    third_octave_policy, transient_policy,
};
use crate::rolling::{Sensor, StepStatus};

/// The rolling fixtures' rate: 1 mm steps at 50 km/h.
const FS: f64 = 13_888.888_888_888_89;

/// A passage over a road-fixed sensor, at rest at both ends of 171
/// samples: a raised-cosine load of 90 samples with a ripple on its top.
fn passage(ripple: f64) -> Vec<f64> {
    (0..171)
        .map(|j| {
            let t = j as f64 - 5.0;
            if (0.0..=90.0).contains(&t) {
                let s = (PI * t / 90.0).sin();
                150.0 * s * s * (1.0 + ripple * (2.0 * PI * t / 7.3).sin())
            } else {
                0.0
            }
        })
        .collect()
}

fn compared(model: &[f64], reference: &[f64]) -> Result<SignalComparison, BemRollingError> {
    let segment = Some(170);
    let resolved_from = crate::rolling::resolved_from(FS, 170);
    let levels = |x: &[f64], kind| match kind {
        SpectrumKind::Welch => third_octave_policy(x, FS, 1.0, segment),
        SpectrumKind::Transient => transient_policy(x, FS, 1.0),
    };
    signal(
        "sensor",
        model,
        reference,
        Scale::Peak,
        &levels,
        resolved_from,
    )
}

/// A model 5 % above the reference everywhere: in every band 100 Hz …
/// 2 kHz the difference is `20 log10 1.05` and the error level `20 log10
/// 0.05` (1e-9 dB), and all 14 bands are resolved; under the single Hann
/// segment only those from 708 Hz were.
#[test]
fn a_passage_held_whole_is_compared_in_every_band() -> Result<(), BemRollingError> {
    let reference = passage(0.05);
    let model: Vec<f64> = reference.iter().map(|v| 1.05 * v).collect();
    let c = compared(&model, &reference)?;
    assert_eq!(c.spectrum, SpectrumKind::Transient);
    assert_eq!(c.bands.len(), 14);
    for b in &c.bands {
        assert!(b.resolved, "{b:?}");
        assert!(
            (b.difference_db - 20.0 * 1.05f64.log10()).abs() < 1e-9,
            "{b:?}"
        );
        assert!((b.error_db - 20.0 * 0.05f64.log10()).abs() < 1e-9, "{b:?}");
    }
    Ok(())
}

/// A signal not at rest at an end of the stretch (an approach, or a
/// passage the stretch cuts) stays with Welch and its unresolved bands.
#[test]
fn a_signal_cut_by_the_stretch_stays_with_welch() -> Result<(), BemRollingError> {
    let approach: Vec<f64> = (0..171)
        .map(|j| 6.7e-3 + 2e-6 * (0.9 * j as f64).sin() + 1e-6 * (0.13 * j as f64).cos())
        .collect();
    let model: Vec<f64> = approach.iter().map(|v| v * (1.0 + 1e-4)).collect();
    let c = compared(&model, &approach)?;
    assert_eq!(c.spectrum, SpectrumKind::Welch);
    // 708 Hz: the bands from 800 Hz hold two bins of the 170-sample segment.
    for b in &c.bands {
        assert_eq!(b.resolved, b.nominal >= 800.0, "{b:?}");
    }
    let mut cut = passage(0.05);
    cut.truncate(60); // the stretch ends while the sensor is loaded
    let model: Vec<f64> = cut.iter().map(|v| 1.05 * v).collect();
    assert_eq!(compared(&model, &cut)?.spectrum, SpectrumKind::Welch);
    Ok(())
}

/// Band levels are norms: an error of level `e` dB re the reference's band
/// moves the model's level by at most `−20 log10(1 − 10^(e/20))` dB, and
/// [`ERROR_DB_FOR_1DB`] is where that bound is 1 dB. Checked on a model
/// whose ripple differs from the reference's (an error in phase in some
/// bands, out of phase in others), under both spectra.
#[test]
fn the_error_level_bounds_the_band_difference() -> Result<(), BemRollingError> {
    assert!((-20.0 * (1.0 - 10f64.powf(ERROR_DB_FOR_1DB / 20.0)).log10() - 1.0).abs() < 1e-12);
    let reference = passage(0.05);
    let model = passage(0.08);
    let mut approach_ref = reference.clone();
    approach_ref.iter_mut().for_each(|v| *v += 10.0);
    let mut approach_model = model.clone();
    approach_model.iter_mut().for_each(|v| *v += 10.0);
    for (m, r, kind) in [
        (&model, &reference, SpectrumKind::Transient),
        (&approach_model, &approach_ref, SpectrumKind::Welch),
    ] {
        let c = compared(m, r)?;
        assert_eq!(c.spectrum, kind);
        for b in &c.bands {
            let ratio = 10f64.powf(b.error_db / 20.0);
            let upper = 20.0 * (1.0 + ratio).log10();
            assert!(b.difference_db <= upper + 1e-9, "{kind:?} {b:?}");
            if ratio < 1.0 {
                let lower = 20.0 * (1.0 - ratio).log10();
                assert!(b.difference_db >= lower - 1e-9, "{kind:?} {b:?}");
            }
        }
        // Not vacuous: some band holds an error within 20 dB of its level.
        assert!(c.bands.iter().any(|b| b.error_db > -20.0), "{kind:?}");
    }
    Ok(())
}

/// A BEM run of 171 steps: an approach that runs through the stretch and
/// one sensor's passage, each scaled by `scale`.
fn bem_run(scale: f64) -> BemRollingResult {
    let force = passage(0.05);
    BemRollingResult {
        steps: (0..171)
            .map(|j| BemStep {
                index: j,
                position: 0.065 + 1e-3 * j as f64,
                time: j as f64 / FS,
                total_force: 1500.0,
                approach: scale * (6.7e-3 + 2e-6 * (0.9 * j as f64).sin()),
                contact_area: 1e-3,
                iterations: 1,
                status: StepStatus::Converged,
                sensor_forces: vec![scale * force[j]],
            })
            .collect(),
        sample_rate: FS,
        window: (0, 0),
    }
}

/// Two BEM runs of the same stretch compared band by band: a run against
/// itself changes nothing (error `−∞`, difference 0 in every band), a run
/// 1 % off puts the error at `20 log10 0.01 = −40 dB` in every band of
/// both signals (1e-6 dB: the approach loses digits to its mean), the
/// passage as a transient, the approach by Welch; runs of different
/// lengths are refused.
#[test]
fn a_second_bem_run_is_compared_band_by_band() -> Result<(), BemRollingError> {
    let sensors = [Sensor {
        name: "centre".into(),
        x: [0.105, 0.125],
        y: [-0.01, 0.01],
    }];
    let reference = bem_run(1.0);
    let same = compare_references(&reference, &reference, &sensors, 1.0, Some(170))?;
    assert_eq!(same.len(), 2);
    for s in &same {
        assert!(s.bands.iter().all(|b| b.error_db == f64::NEG_INFINITY));
        assert!(s.bands.iter().all(|b| b.difference_db == 0.0));
    }
    let off = compare_references(&bem_run(1.01), &reference, &sensors, 1.0, Some(170))?;
    assert_eq!(off[0].spectrum, SpectrumKind::Welch);
    assert_eq!(off[1].spectrum, SpectrumKind::Transient);
    for b in off.iter().flat_map(|s| &s.bands) {
        assert!((b.error_db + 40.0).abs() < 1e-6, "{b:?}");
    }
    let mut short = bem_run(1.0);
    short.steps.pop();
    assert!(compare_references(&short, &reference, &sensors, 1.0, Some(170)).is_err());
    Ok(())
}
