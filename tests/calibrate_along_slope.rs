//! Caps calibrated along the tread's longitudinal slope
//! (`[model] calibrate_under = "tread_slope"`, `tyreroad::fidelity::PathNode`,
//! `tyreroad::rolling::Placement`) against caps calibrated under the tread
//! at the footprint's centre only (`"tread"`), both rolled under a tyre
//! and measured against the project's BEM rolling reference.
#![allow(clippy::unwrap_used)]

use crate::common;

use tyreroad::bem_rolling::{BemRollingOptions, roll_bem, texture_field};
use tyreroad::contact_law::{ContactLaw, Material};
use tyreroad::fidelity::CalibratedLaw;
use tyreroad::fidelity::rolling_fields::FieldRolling;
use tyreroad::fidelity::under_tread::{CalibrateUnder, SLOPE_NODES, slope_nodes};
use tyreroad::rolling::{
    ContactSlope, Road, RollingConfig, RollingControl, RollingResult, RunOptions, Sensor, Tread,
    input_hash, roll, roll_coupled,
};
use tyreroad::shared::Par;
use tyreroad::texture::HeightMap;

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn material() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

/// The ridge's middle along x (m).
const RIDGE_X: f64 = 24e-3;

/// One ridge along the driving direction: 10 mm long, cross radius 4 mm,
/// ends rounded to 2 mm, tilted down along +x by 30 µm/mm (its summit at
/// the rear end), clipped 1.2 mm below the top; 48 × 16 mm at 0.2 mm.
/// Under a tyre of `Rx = 0.1 m` the tread over it slopes `ξ/Rx`: the
/// tread's lowest point over the ridge lies `tilt · Rx = 3 mm` behind the
/// footprint's centre, so as the footprint passes the contact runs from
/// the rear end to the front end. A model summit at the rear end stays
/// there. A bump 1.5 mm above the ridge, 14 mm ahead of it and 5 mm
/// across, where the crown (`Ry = 5 mm`) keeps it at least 1.2 mm off
/// the tread, never touches: it makes the ridge's summit not the road's
/// highest, so that a node may raise it to where its cap first touches
/// ([`tyreroad::fidelity::PathNode`]'s delays; the highest summit is the
/// approach's reference and is never raised).
fn ridge_along_x() -> HeightMap {
    let (tilt, half, rend, rcross, yc) = (3e-2, 5e-3, 2e-3, 4e-3, 8e-3);
    HeightMap::from_fn(241, 81, 2e-4, 2e-4, move |x, y| {
        let along = (x - RIDGE_X).abs() - half;
        let end = if along > 0.0 {
            along * along / (2.0 * rend)
        } else {
            0.0
        };
        let ridge = -(y - yc).powi(2) / (2.0 * rcross) - tilt * (x - RIDGE_X) - end;
        let (bx, by) = (x - RIDGE_X - 14e-3, y - yc - 5e-3);
        let bump = 1.5e-3 - (bx * bx + by * by) / (2.0 * 2e-3);
        ridge.max(bump).max(-1.2e-3)
    })
    .unwrap()
}

fn config(load: f64) -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.1,
        radius_y: 5e-3,
        length: 28e-3,
        width: 12e-3,
    };
    let mut config = RollingConfig::new(
        tyre,
        [RIDGE_X - 2e-3, RIDGE_X + 8e-3, 2e-3],
        10.0,
        RollingControl::Load(load),
    );
    config.contact_slope = ContactSlope::Profile;
    // The rear half of the ridge, road-fixed (the map's y is centred on
    // the path).
    config.sensors = vec![Sensor {
        name: "rear".into(),
        x: [-1.0, RIDGE_X],
        y: [-4e-3, 4e-3],
    }];
    config
}

/// The calibrated rolling road of `map` (with fields), caps under `under`,
/// and the largest approach its tables cover (m).
fn calibrated(
    map: &HeightMap,
    config: &RollingConfig,
    under: CalibrateUnder,
) -> (Road<CalibratedLaw>, f64) {
    common::calibrated_road(map, material(), config, under)
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

fn rear(r: &RollingResult) -> Vec<f64> {
    r.steps.iter().map(|s| s.sensor_forces[0]).collect()
}

/// The ridge's rear-half force by the BEM falls from the whole load to
/// nothing as the footprint passes; calibrated at the footprint's centre
/// only, the model's field stays at the summit (rear) end. Calibrated at
/// five offsets and blended per step, it follows the BEM.
#[test]
fn a_ridge_along_the_path_follows_the_bem_when_calibrated_along_the_slope() -> TestResult {
    let (m, map, load) = (material(), ridge_along_x(), 3.0);
    let config = config(load);
    let bem = roll_bem(
        &texture_field(&map)?,
        m,
        &config,
        &BemRollingOptions {
            par: Par::Seq,
            ..BemRollingOptions::default()
        },
    )?;
    let bem_a: Vec<f64> = bem.steps.iter().map(|s| s.approach).collect();
    let mean = bem_a.iter().sum::<f64>() / bem_a.len() as f64;
    let bem_rear: Vec<f64> = bem.steps.iter().map(|s| s.sensor_forces[0]).collect();
    println!("BEM rear: {bem_rear:.3?}");
    // The case does what it is for: the BEM's contact runs the ridge's
    // length (the whole load behind its middle, then none).
    assert!(bem_rear[0] > 0.95 * load && *bem_rear.last().unwrap() < 0.05 * load);
    let mut rows = Vec::new();
    for under in [CalibrateUnder::Tread, CalibrateUnder::TreadSlope] {
        let (road, _) = calibrated(&map, &config, under);
        assert_eq!(road.len(), 2);
        assert_eq!(
            road.placement().is_some(),
            under == CalibrateUnder::TreadSlope
        );
        let coupling = FieldRolling::with_defaults(&m)?;
        let fields = roll_coupled(&road, m, &config, &RunOptions::default(), &coupling)?;
        let point = roll(&road, m, &config, &RunOptions::default())?;
        let row = (
            max_error(&rear(&fields), &bem_rear, load),
            max_error(&approaches(&fields), &bem_a, mean),
            max_error(&approaches(&point), &bem_a, mean),
        );
        println!(
            "{under}: rear {:.3?}, rear error {:.4}, approach fields {:.5} point {:.5}",
            rear(&fields),
            row.0,
            row.1,
            row.2
        );
        rows.push(row);
    }
    let [tread, slope] = rows[..] else {
        unreachable!()
    };
    // Measured (rear sensor, % of the load; approach, fields / point, %
    // of the BEM's mean): tread 87.9; 20.3 / 20.2; tread_slope 26.8; 1.9 /
    // 1.9. The nodes lie 7 mm apart, the contact runs 7 mm between them:
    // the blended field shares the load between the two nodes' places
    // where the BEM has one (the worst steps lie between nodes; at the
    // node ξ = −7 mm the rear force is the BEM's to 0.01 N).
    assert!(slope.0 < 0.3, "tread_slope rear sensor {}", slope.0);
    assert!(
        tread.0 > slope.0 + 0.4,
        "tread {}, tread_slope {}",
        tread.0,
        slope.0
    );
    assert!(slope.1 < 0.03 && slope.2 < 0.03, "approach {slope:?}");
    assert!(tread.1 > slope.1 + 0.1, "approach {tread:?} {slope:?}");
    Ok(())
}

/// A law along the path keeps the law contract wherever it is placed, is
/// continuous in the offset, is the blend at the footprint's centre when
/// unplaced, is not placed twice; its nodes differ (the tilt moves the
/// law); the road's checkpoint key tells a placed road from the same laws
/// unplaced.
#[test]
fn a_law_along_the_path_is_its_nodes_blended_and_keys_its_runs_apart() -> TestResult {
    let (m, map) = (material(), ridge_along_x());
    let config = config(3.0);
    let (road, _) = calibrated(&map, &config, CalibrateUnder::TreadSlope);
    let nodes = slope_nodes(&config.tread, config.margin);
    assert_eq!(nodes, [-14e-3, -7e-3, 0.0, 7e-3, 14e-3]);
    assert_eq!(nodes.len(), SLOPE_NODES);
    let ridge = road
        .positions()
        .iter()
        .position(|p| (p[0] - RIDGE_X).abs() < 6e-3)
        .unwrap();
    let law = &road.laws()[ridge];
    assert!(law.is_along_path());
    let depths = [1e-4, 3e-4, 6e-4, 1e-3];
    for xi in [-14e-3, -10e-3, -7e-3, -3.5e-3, 0.0, 5e-3, 20e-3] {
        let placed = law.at_offset(xi).unwrap();
        // A placed law is not placed again.
        assert!(placed.at_offset(1e-3).is_none());
        assert_eq!(placed.force(0.0), 0.0);
        assert_eq!(placed.force(-1e-4), 0.0);
        let near = law.at_offset(xi + 1e-9).unwrap();
        let scale = placed.force(1e-3);
        assert!(scale > 0.0);
        for d in depths {
            let (f, k) = (placed.force(d), placed.evaluate(d).stiffness);
            // Continuous in ξ.
            assert!((near.force(d) - f).abs() <= 1e-6 * scale, "{xi} {d}");
            // k = dP/dδ (central difference over 1 µm).
            let h = 1e-7;
            let fd = (placed.force(d + h) - placed.force(d - h)) / (2.0 * h);
            assert!((fd - k).abs() <= 1e-3 * k.max(1.0), "{xi} {d}: {fd} {k}");
            // Non-decreasing.
            assert!(placed.force(d * 1.1) >= f);
        }
    }
    let centre = law.at_offset(0.0).unwrap();
    let (rear, front) = (
        law.at_offset(nodes[1]).unwrap(),
        law.at_offset(nodes[3]).unwrap(),
    );
    for d in depths {
        assert_eq!(law.force(d), centre.force(d));
    }
    // The tilt moves the law: under the footprint's front, where the
    // tread slopes down over the ridge's summit end, it is not the
    // centre's.
    let d = 6e-4;
    println!(
        "at {d} m: rear node {} N, centre {} N, front node {} N",
        rear.force(d),
        centre.force(d),
        front.force(d)
    );
    assert!(centre.force(d) > 0.0);
    assert!((rear.force(d) - centre.force(d)).abs() > 1e-2 * centre.force(d));
    let unplaced = Road::new(road.set().clone());
    assert_ne!(
        input_hash(&road, &m, &config),
        input_hash(&unplaced, &m, &config)
    );
    Ok(())
}
