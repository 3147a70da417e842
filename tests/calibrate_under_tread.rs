//! Caps calibrated under the tread's local shape
//! (`tyreroad::fidelity::under_tread`, `[model] calibrate_under = "tread"`)
//! against caps calibrated under a flat punch, both rolled under a tyre and
//! measured against the project's BEM rolling reference.
#![allow(clippy::unwrap_used)]

use crate::common;

use tyreroad::bem_rolling::{BemRollingOptions, BemRollingResult, roll_bem, texture_field};
use tyreroad::contact_law::Material;
use tyreroad::fidelity::CalibratedLaw;
use tyreroad::fidelity::rolling_fields::FieldRolling;
use tyreroad::fidelity::under_tread::CalibrateUnder;
use tyreroad::rolling::{
    ContactSlope, Road, RollingConfig, RollingControl, RollingResult, RunOptions, Sensor, Tread,
    roll, roll_coupled,
};
use tyreroad::shared::Par;
use tyreroad::texture::HeightMap;

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn material() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

/// The calibrated rolling road of `map` (with fields), caps under `under`.
fn calibrated(
    map: &HeightMap,
    config: &RollingConfig,
    under: CalibrateUnder,
) -> Road<CalibratedLaw> {
    common::calibrated_road(map, material(), config, under).0
}

/// Largest per-step `|model − reference|` over `scale`.
/// The BEM rolling reference of `config` on `map`: the run, its approaches
/// and their mean.
fn bem_reference(
    map: &HeightMap,
    m: Material,
    config: &RollingConfig,
) -> Result<(BemRollingResult, Vec<f64>, f64), Box<dyn std::error::Error>> {
    let bem = roll_bem(
        &texture_field(map)?,
        m,
        config,
        &BemRollingOptions {
            par: Par::Seq,
            ..BemRollingOptions::default()
        },
    )?;
    let approaches: Vec<f64> = bem.steps.iter().map(|s| s.approach).collect();
    let mean = approaches.iter().sum::<f64>() / approaches.len() as f64;
    Ok((bem, approaches, mean))
}

fn max_error(model: &[f64], reference: &[f64], scale: f64) -> f64 {
    model
        .iter()
        .zip(reference)
        .map(|(m, r)| (m - r).abs() / scale)
        .fold(0.0, f64::max)
}

fn approaches(r: &RollingResult) -> Vec<f64> {
    r.steps.iter().map(|s| s.approach).collect()
}

fn sensor(r: &RollingResult, j: usize) -> Vec<f64> {
    r.steps.iter().map(|s| s.sensor_forces[j]).collect()
}

/// The ridges under a tyre whose crown (radius 1 m across) slopes up to
/// 0.005 over their ends, against their own tilt of 0.003: the BEM
/// meets each ridge along its length, a flat punch at its summit end.
/// Calibrated under the tread, the field rung's approach comes closer to
/// the BEM (the north sensor, half the road across, stays within 1 %).
#[test]
fn ridges_calibrated_under_the_tyre_roll_closer_to_the_bem_than_under_a_flat_punch() -> TestResult {
    let (m, map, load) = (material(), common::rolling_ridges(), 10.0);
    let tyre = Tread::Tyre {
        radius_x: 1.0,
        radius_y: 1.0,
        length: 24e-3,
        width: 16e-3,
    };
    let mut config = RollingConfig::new(
        tyre,
        [14e-3, 16e-3, 0.5e-3],
        10.0,
        RollingControl::Load(load),
    );
    config.contact_slope = ContactSlope::Profile;
    config.sensors = vec![
        Sensor {
            name: "south".into(),
            x: [-1.0, 1.0],
            y: [-1.0, 0.0],
        },
        Sensor {
            name: "north".into(),
            x: [-1.0, 1.0],
            y: [0.0, 1.0],
        },
    ];
    let (bem, bem_a, mean) = bem_reference(&map, m, &config)?;
    let bem_north: Vec<f64> = bem.steps.iter().map(|s| s.sensor_forces[1]).collect();
    let mut rows = Vec::new();
    for under in [CalibrateUnder::Flat, CalibrateUnder::Tread] {
        let road = calibrated(&map, &config, under);
        let point = roll(&road, m, &config, &RunOptions::default())?;
        let coupling = FieldRolling::with_defaults(&m)?;
        let fields = roll_coupled(&road, m, &config, &RunOptions::default(), &coupling)?;
        let row = (
            max_error(&approaches(&point), &bem_a, mean),
            max_error(&approaches(&fields), &bem_a, mean),
            max_error(&sensor(&point, 1), &bem_north, load),
            max_error(&sensor(&fields, 1), &bem_north, load),
        );
        println!(
            "{under}: approach point {:.4} fields {:.4}, north point {:.4} fields {:.4}",
            row.0, row.1, row.2, row.3,
        );
        rows.push(row);
    }
    let [flat, tread] = rows[..] else {
        unreachable!()
    };
    // Measured (approach point / fields, north sensor point / fields):
    // flat 1.39 / 4.11 %, 9.03 / 0.14 %; tread 5.40 / 0.21 %, 9.05 / 0.03 %.
    // The field rung, whose fields place each ridge's load, comes to the
    // BEM; the point rung (summits' kernel, discs) moves the other way:
    // its flat-punch approach was errors cancelling. (Before the summit
    // fit was checked against the grid, 2026-11-28, each ridge's summit
    // was a paraboloid vertex 3.5 µm above its highest cell and 0.17 mm
    // into the ridge, where the ridge is lower still: tread 3.05 / 2.33 %,
    // flat 0.52 / 5.74 %. The field rung gained from the true summit, the
    // point rung had gained from the phantom's extra height.)
    assert!(tread.1 < 0.01, "tread fields approach {}", tread.1);
    assert!(
        flat.1 > tread.1 + 0.02,
        "flat {}, tread {}",
        flat.1,
        tread.1
    );
    assert!(
        tread.3 < 0.01 && flat.3 < 0.01,
        "north {} {}",
        flat.3,
        tread.3
    );
    assert!(tread.0 < 0.07, "tread point approach {}", tread.0);
    Ok(())
}

/// One paraboloid cap (R = 5 mm, on a 30 × 10 mm map) 40 mm beside the path of a tyre whose
/// crown (0.4 m across) slopes 0.1 over it: calibrated under the tread its
/// table starts at the model's contact-point gap with the tread's
/// curvature in it (Hertz with `1/R + 1/Rx`, `1/R + 1/Ry`), and the
/// rolled approach is the BEM's.
#[test]
fn a_paraboloid_beside_the_path_rolls_as_the_bem_under_either_calibration() -> TestResult {
    let (m, r, load) = (material(), 5e-3, 2.0);
    let map = HeightMap::from_fn(301, 101, 1e-4, 1e-4, |x, y| {
        let (u, v) = (x - 15e-3, y - 5e-3);
        (-(u * u + v * v) / (2.0 * r)).max(-1e-3)
    })?;
    let (rx, ry) = (0.3, 0.4);
    let tyre = Tread::Tyre {
        radius_x: rx,
        radius_y: ry,
        length: 16e-3,
        width: 120e-3,
    };
    let mut config =
        RollingConfig::new(tyre, [14e-3, 16e-3, 1e-3], 10.0, RollingControl::Load(load));
    config.lateral = -0.04;
    config.contact_slope = ContactSlope::Profile;
    let (_, bem_a, mean) = bem_reference(&map, m, &config)?;
    // Hertz for the cap against the tread's crown: radii R Rx/(R + Rx) and
    // R Ry/(R + Ry), their geometric mean (the two differ by 0.4 %).
    let re = (r * rx / (r + rx) * r * ry / (r + ry)).sqrt();
    let hertz = |d: f64| 4.0 / 3.0 * m.reduced_modulus() * re.sqrt() * d.powf(1.5);
    // The table reaches past the approach's 2 mm of crown profile; the map
    // is a paraboloid to 1 mm below the summit, whose clipped rim the
    // tilted tread meets from about 0.7 mm: compared from 30 to 400 µm
    // (the run presses it 180 µm).
    let mut errors = Vec::new();
    for under in [CalibrateUnder::Flat, CalibrateUnder::Tread] {
        let road = calibrated(&map, &config, under);
        assert_eq!(road.len(), 1);
        let table = road.laws()[0].table();
        let law_error = table
            .knots()
            .filter(|&(d, _, _)| d > 3e-5 && d < 0.4e-3)
            .map(|(d, f, _)| (f - hertz(d)).abs() / hertz(d))
            .fold(0.0, f64::max);
        let run = roll(&road, m, &config, &RunOptions::default())?;
        let approach = max_error(&approaches(&run), &bem_a, mean);
        println!(
            "{under}: law against Hertz {law_error:.5}, approach against the BEM {approach:.5}"
        );
        errors.push((law_error, approach));
    }
    let [(flat_law, flat_a), (tread_law, tread_a)] = errors[..] else {
        unreachable!()
    };
    // Measured: the flat law 1.09 % off (it lacks the crown's curvature,
    // √(R/Re) = 1.007), the tread's 0.40 % (the BEM's 0.1 mm cells at the
    // shallowest knots); approach 0.036 % and 0.005 % off the BEM.
    assert!(tread_law < 0.006, "tread law {tread_law}");
    assert!(
        flat_law > tread_law + 0.003,
        "flat {flat_law}, tread {tread_law}"
    );
    assert!(tread_a < 2e-4, "tread approach {tread_a}");
    assert!(flat_a > tread_a, "flat {flat_a}, tread {tread_a}");
    Ok(())
}
