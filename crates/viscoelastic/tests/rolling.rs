//! Viscoelastic rolling against its independent references: the elastic
//! rolling runs with `E∞` (slow) and `E∞ + Σ E_k` (fast), step by step and
//! asperity by asperity; one sphere under a rolling tyre against the
//! hereditary integral evaluated by quadrature; and a force signal that
//! changes with speed between the two limits.

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{HertzLaw, Material, PotentialLaw};
use tyreroad_multipoint::AsperitySet;
use tyreroad_rolling::{
    Road, RollingConfig, RollingControl, RollingResult, RunOptions, Sensor, SyntheticRoad, Tread,
    roll,
};
use tyreroad_viscoelastic::{
    ViscoError, ViscoRollOptions, ViscoRolling, ViscoStart, roll_viscoelastic,
};

use crate::support;
use support::tread;

/// 0.15 × 0.05 m of random spherical summits (radii 2–5 mm, heights over
/// 2 mm), laws on `material`.
fn road(material: Material) -> Road<PotentialLaw<Sphere>> {
    SyntheticRoad {
        seed: 18,
        length: 0.15,
        width: 0.05,
        ..SyntheticRoad::default()
    }
    .sphere_road(material)
    .expect("valid road")
}

/// A 40 × 40 mm tyre footprint from 30 to 120 mm by 1 mm, two sensors.
fn config(speed: f64, control: RollingControl) -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.3,
        length: 0.04,
        width: 0.04,
    };
    let mut config = RollingConfig::new(tyre, [0.03, 0.12, 1e-3], speed, control);
    config.sensors = vec![
        Sensor {
            name: "centre".into(),
            x: [0.07, 0.08],
            y: [-0.005, 0.005],
        },
        Sensor {
            name: "side".into(),
            x: [0.07, 0.08],
            y: [0.005, 0.015],
        },
    ];
    config
}

fn elastic(modulus: f64, config: &RollingConfig) -> RollingResult {
    let material = Material::new(modulus, 0.5).expect("valid");
    roll(&road(material), material, config, &RunOptions::default()).expect("elastic run")
}

fn viscoelastic(config: &RollingConfig) -> ViscoRolling {
    viscoelastic_from(config, ViscoStart::Fresh)
}

fn viscoelastic_from(config: &RollingConfig, start: ViscoStart) -> ViscoRolling {
    let reference = Material::new(1e6, 0.5).expect("valid");
    let options = ViscoRollOptions {
        start,
        ..ViscoRollOptions::default()
    };
    roll_viscoelastic(&road(reference), reference, &tread(), config, &options)
        .expect("viscoelastic run")
}

/// Worst per-step differences of `visco` from `elastic` from step `from`:
/// (total force or approach, relative; each asperity's force and each
/// sensor's, relative to the step's largest asperity force).
fn worst(visco: &RollingResult, elastic: &RollingResult, from: usize, load: bool) -> (f64, f64) {
    let mut primary = 0.0f64;
    let mut forces = 0.0f64;
    for (v, e) in visco.steps.iter().zip(&elastic.steps).skip(from) {
        let (a, b) = if load {
            (v.approach, e.approach)
        } else {
            (v.total_force, e.total_force)
        };
        primary = primary.max((a / b - 1.0).abs());
        let scale = e.contact_forces.iter().fold(0.0f64, |m, &p| m.max(p));
        let force_of = |ids: &[usize], ps: &[f64], id: usize| {
            ids.iter().position(|&i| i == id).map_or(0.0, |a| ps[a])
        };
        for &id in v.contact_ids.iter().chain(&e.contact_ids) {
            let d = force_of(&v.contact_ids, &v.contact_forces, id)
                - force_of(&e.contact_ids, &e.contact_forces, id);
            forces = forces.max(d.abs() / scale);
        }
        for (a, b) in v.sensor_forces.iter().zip(&e.sensor_forces) {
            forces = forces.max((a - b).abs() / scale);
        }
    }
    (primary, forces)
}

#[test]
fn slow_rolling_is_the_elastic_run_with_the_long_term_modulus() {
    let material = tread();
    // Δt = 1 mm / 1e-5 m/s = 100 s: every branch relaxes within a step.
    for control in [RollingControl::Approach(1.2e-3), RollingControl::Load(60.0)] {
        let config = config(1e-5, control);
        let visco = viscoelastic(&config);
        let reference = elastic(material.long_term(), &config);
        let load = matches!(control, RollingControl::Load(_));
        let (primary, forces) = worst(&visco.result, &reference, 0, load);
        eprintln!("{control:?}: primary {primary:.2e}, forces {forces:.2e}");
        assert!(
            primary < 5e-3,
            "{control:?}: primary signal off by {primary}"
        );
        assert!(forces < 5e-3, "{control:?}: forces off by {forces}");
        assert!(visco.result.steps.iter().all(|s| s.contacts > 0));
    }
}

#[test]
fn fast_rolling_is_the_elastic_run_with_the_instantaneous_modulus() {
    let material = tread();
    // Δt = 1 mm / 5e7 m/s = 20 ps: the 90 steps last 1e-4 of τ_min.
    for control in [RollingControl::Approach(1.2e-3), RollingControl::Load(60.0)] {
        let config = config(5e7, control);
        let visco = viscoelastic(&config);
        let reference = elastic(material.instantaneous(), &config);
        let load = matches!(control, RollingControl::Load(_));
        let (primary, forces) = worst(&visco.result, &reference, 0, load);
        eprintln!("{control:?}: primary {primary:.2e}, forces {forces:.2e}");
        assert!(
            primary < 5e-3,
            "{control:?}: primary signal off by {primary}"
        );
        assert!(forces < 5e-3, "{control:?}: forces off by {forces}");
        // A relaxed standing start is the elastic run with E∞ at its first
        // step, and stays off the glassy run while its first footprint's
        // depression lasts: the limits differ by far more than the
        // tolerance, so the checks above can fail.
        let relaxed = viscoelastic_from(&config, ViscoStart::Relaxed);
        let soft = elastic(material.long_term(), &config);
        let first = |r: &RollingResult| {
            if load {
                r.steps[0].approach
            } else {
                r.steps[0].total_force
            }
        };
        assert!((first(&relaxed.result) / first(&soft) - 1.0).abs() < 1e-9);
        let (start, _) = worst(&relaxed.result, &reference, 0, load);
        assert!(start > 0.05, "{control:?}: the relaxed start is not seen");
        eprintln!("{control:?}: relaxed start off the glassy run by {start:.3}");
    }
}

#[test]
fn the_rolling_signal_changes_with_speed_between_the_limits() {
    let material = tread();
    let kmh = 1.0 / 3.6;
    let control = RollingControl::Load(60.0);
    let slow = viscoelastic(&config(30.0 * kmh, control));
    let fast = viscoelastic(&config(130.0 * kmh, control));
    let relaxed = elastic(material.long_term(), &config(1.0, control));
    let glassy = elastic(material.instantaneous(), &config(1.0, control));
    let from = slow.transient_steps;
    let mut sensor_change = 0.0f64;
    for k in from..slow.result.steps.len() {
        let approach = |r: &RollingResult| r.steps[k].approach;
        // Faster is stiffer: the tread sinks less, and stays between the
        // glassy and the relaxed elastic runs.
        assert!(approach(&glassy) < approach(&fast.result), "step {k}");
        assert!(approach(&fast.result) < approach(&slow.result), "step {k}");
        assert!(approach(&slow.result) < approach(&relaxed), "step {k}");
        for (a, b) in slow.result.steps[k]
            .sensor_forces
            .iter()
            .zip(&fast.result.steps[k].sensor_forces)
        {
            sensor_change = sensor_change.max((a - b).abs());
        }
    }
    eprintln!("largest sensor change 30 vs 130 km/h: {sensor_change:.3} N");
    // The sensors see it too (the largest sensor force is about 10 N).
    assert!(sensor_change > 0.05, "sensor change {sensor_change} N");
}

/// One sphere under a tyre at a fixed axle height: while the footprint
/// approaches, its interpenetration `δ(t) = δ0 − (x_s − V t)²/(2 R_x)` grows
/// and Lee–Radok gives `P(t) = ∫ E(t − s) df/ds ds` with `f` the Hertz
/// force per unit modulus, here integrated by Simpson's rule on a fine grid.
#[test]
fn one_sphere_under_a_rolling_tyre_follows_the_hereditary_integral() {
    let material = tread();
    let reference = Material::new(1e6, 0.5).expect("valid");
    let radius = 5e-3;
    let law = HertzLaw::new(radius, reference).expect("valid");
    let set = AsperitySet::new(vec![[0.05, 0.0]], vec![0.0], vec![law]).expect("valid");
    let road = Road::new(set);
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.3,
        length: 0.06,
        width: 0.06,
    };
    let (speed, approach, rx) = (10.0, 5e-4, 0.3);
    // From 40 mm before the sphere to the footprint centre over it.
    let config = RollingConfig::new(
        tyre,
        [0.01, 0.05, 1e-4],
        speed,
        RollingControl::Approach(approach),
    );
    let run = roll_viscoelastic(
        &road,
        reference,
        &material,
        &config,
        &ViscoRollOptions::default(),
    )
    .expect("runs");
    let depth = |t: f64| approach - (0.05 - speed * t).powi(2) / (2.0 * rx);
    // Contact starts where δ = 0.
    let t0 = (0.05 - (2.0 * rx * approach).sqrt()) / speed;
    let exact = |t: f64| {
        let n = 20_000;
        let h = (t - t0) / n as f64;
        // ∫ E(t − s) f'(s) ds with f' = 2√R δ^{1/2} δ' / (1 − ν²).
        let integrand = |s: f64| {
            let slope = (0.05 - speed * s) * speed / rx;
            material.relaxation(t - s) * 2.0 * radius.sqrt() * depth(s).max(0.0).sqrt() * slope
                / 0.75
        };
        let mut sum = integrand(t0) + integrand(t);
        for j in 1..n {
            sum += integrand(t0 + j as f64 * h) * if j % 2 == 1 { 4.0 } else { 2.0 };
        }
        sum * h / 3.0
    };
    let mut checked = 0;
    let mut worst = 0.0f64;
    let peak = run.result.steps.last().expect("steps").total_force;
    for step in &run.result.steps {
        if step.total_force < 0.1 * peak {
            continue;
        }
        let expected = exact(step.time);
        let error = (step.total_force / expected - 1.0).abs();
        worst = worst.max(error);
        assert!(
            error < 0.01,
            "t = {} s: {} N vs {expected} N",
            step.time,
            step.total_force
        );
        checked += 1;
    }
    assert!(checked > 50, "{checked} steps checked");
    eprintln!("{checked} steps, worst {worst:.2e}");
    assert_eq!(run.receding.iter().sum::<usize>(), 0);
}

#[test]
fn bad_inputs_are_named_errors() {
    let reference = Material::new(1e6, 0.3).expect("valid");
    let config = config(10.0, RollingControl::Load(60.0));
    let err = roll_viscoelastic(
        &road(reference),
        reference,
        &tread(),
        &config,
        &ViscoRollOptions::default(),
    )
    .expect_err("Poisson's ratios differ");
    assert!(matches!(err, ViscoError::InvalidValue { .. }), "{err}");
    let reference = Material::new(1e6, 0.5).expect("valid");
    let mut bad = config.clone();
    bad.speed = -1.0;
    let err = roll_viscoelastic(
        &road(reference),
        reference,
        &tread(),
        &bad,
        &ViscoRollOptions::default(),
    )
    .expect_err("negative speed");
    assert!(matches!(err, ViscoError::Rolling { .. }), "{err}");
}
