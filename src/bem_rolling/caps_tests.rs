//! Sensor forces counted on each cap's own pressure
//! ([`crate::fidelity::cap_sensors::cap_sensor_forces`]) against the BEM rolling reference, on a
//! chipping whose summit lies at one end of a long top: the case where a
//! disc around the summit misplaces the load (docs/validation.md, "Where
//! the shoulder's load goes").

use super::*;
use crate::rolling::{Road, RunOptions, Tread, roll};
use crate::texture::HeightMap;
use crate::texture_road::{TextureRoadOptions, texture_road};

const E: f64 = 6.54e6;
const NU: f64 = 0.5;
const DX: f64 = 1e-4;
/// Summit radius across and on the short side, and on the long side (m).
const R_SHORT: f64 = 5e-3;
const R_LONG: f64 = 40e-3;
/// Summit position in the map frame (m).
const SUMMIT: [f64; 2] = [15e-3, 6e-3];
const LOAD: f64 = 5.0;

/// One chipping on a floor 1 mm below its summit: a paraboloid of radius
/// `R_SHORT` for `x ≥ x_s`, stretched to `R_LONG` along x for `x < x_s`,
/// so its contact reaches about `√(R_LONG/R_SHORT)` ≈ 2.8 times farther
/// towards −x than towards +x.
fn map() -> HeightMap {
    HeightMap::from_fn(301, 121, DX, DX, |x, y| {
        let (u, v) = (x - SUMMIT[0], y - SUMMIT[1]);
        let r = if u >= 0.0 { R_SHORT } else { R_LONG };
        (-(u * u) / (2.0 * r) - v * v / (2.0 * R_SHORT)).max(-1e-3)
    })
    .expect("valid map")
}

#[test]
fn cap_pressure_puts_a_long_chipping_s_load_where_the_bem_does() {
    let material = Material::new(E, NU).expect("valid material");
    let map = map();
    let troad =
        texture_road(&map, material, &TextureRoadOptions::new(1e-4, 1e-6)).expect("segmented road");
    assert_eq!(troad.len(), 1, "one chipping");
    let field = texture_field(&map).expect("complete map");
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let set = troad.set.clone().translated([0.0, -y_mid]).expect("set");
    let road = Road::new(set)
        .with_summit_radii(troad.summit_radii())
        .expect("radii");
    // A nearly flat tyre centred on the chipping, one step.
    let tyre = Tread::Tyre {
        radius_x: 1.0,
        radius_y: 1.0,
        length: 16e-3,
        width: 10e-3,
    };
    let xs = SUMMIT[0];
    let mut config = RollingConfig::new(tyre, [xs, xs, 1e-3], 10.0, RollingControl::Load(LOAD));
    // "cut": from 6 mm before the summit to 0.5 mm before it; "rest": the
    // remainder of the road, so the two tile it.
    config.sensors = vec![
        Sensor {
            name: "cut".into(),
            x: [xs - 6e-3, xs - 0.5e-3],
            y: [-1.0, 1.0],
        },
        Sensor {
            name: "rest".into(),
            x: [xs - 0.5e-3, 1.0],
            y: [-1.0, 1.0],
        },
        Sensor {
            name: "far".into(),
            x: [-1.0, xs - 6e-3],
            y: [-1.0, 1.0],
        },
    ];
    let options = BemRollingOptions {
        par: Par::Seq,
        ..BemRollingOptions::default()
    };
    let bem = roll_bem(&field, material, &config, &options).expect("BEM rolling");
    let run = roll(&road, material, &config, &RunOptions::default()).expect("rolling");
    let bem_options = options.cap_solve();
    let caps = crate::fidelity::cap_sensors::cap_sensor_forces(
        &run,
        road.positions(),
        &config,
        (&field, &troad, &material),
        (&bem_options, Par::Seq),
    )
    .expect("cap sensor forces");
    let bem_cut = bem.steps[0].sensor_forces[0];
    let disc_cut = run.steps[0].sensor_forces[0];
    let caps_cut = caps[0][0];
    // The BEM puts a good part of the load before the summit.
    assert!(bem_cut > 0.15 * LOAD, "BEM cut sensor {bem_cut} N");
    // The disc around the summit misses most of it (the case discriminates).
    assert!(
        (disc_cut - bem_cut).abs() > 0.1 * LOAD,
        "disc {disc_cut} N, BEM {bem_cut} N"
    );
    // The cap's own pressure finds it: within 1 % of the load (the one
    // difference is the model's force, the law's error on this cap).
    assert!(
        (caps_cut - bem_cut).abs() < 0.01 * LOAD,
        "caps {caps_cut} N, BEM {bem_cut} N"
    );
    // Sensors tiling the road share the contact's whole force.
    let sum: f64 = caps.iter().map(|s| s[0]).sum();
    assert!(
        (sum - run.steps[0].total_force).abs() < 1e-9 * LOAD,
        "caps sum {sum} N, force {} N",
        run.steps[0].total_force
    );
    // A cap solve that cannot converge is its step's failure: the count
    // step by step names the step (a run's recount keeps that step's own
    // accounting), the whole count stops on it.
    let starved = crate::bem::BemOptions {
        max_iterations: 1,
        ..bem_options
    };
    let cap_inputs = (&field, &troad, &material);
    let by_step = crate::fidelity::cap_sensors::cap_sensor_forces_by_step(
        &run,
        road.positions(),
        &config,
        cap_inputs,
        (&starved, Par::Seq),
    )
    .expect("the run's inputs are valid");
    assert!(
        matches!(
            by_step[..],
            [Err(crate::fidelity::FidelityError::CapSensors {
                step: 0,
                ..
            })]
        ),
        "{by_step:?}"
    );
    let whole = crate::fidelity::cap_sensors::cap_sensor_forces(
        &run,
        road.positions(),
        &config,
        cap_inputs,
        (&starved, Par::Seq),
    );
    assert!(
        matches!(
            whole,
            Err(crate::fidelity::FidelityError::CapSensors { step: 0, .. })
        ),
        "{whole:?}"
    );
}
