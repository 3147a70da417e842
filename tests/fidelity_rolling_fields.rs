//! The `calibrated_fields` rung in rolling (`tyreroad::fidelity::rolling_fields`):
//! three tilted ridges rolled under a nearly flat tyre, by the point-coupled
//! calibrated road, by the field-coupled one and by the project's BEM
//! rolling reference; the field sensor accounting of one long chipping
//! against the BEM; the scenario's acceptance of the rung; and a fixed
//! point that does not settle recorded as its step's failure.
#![allow(clippy::unwrap_used)]

use crate::common;

use tyreroad::bem_rolling::{BemRollingOptions, roll_bem, texture_field};
use tyreroad::contact_law::Material;
use tyreroad::fidelity::coupling::{FieldCouplingOptions, PairReach, PairSum, solve_field_coupled};
use tyreroad::fidelity::rolling::calibrate_rolling_road;
use tyreroad::fidelity::rolling_fields::{FieldRolling, SensorAccounting, sensor_forces};
use tyreroad::fidelity::{CalibratedLaw, CalibrationOptions, Calibrator};
use tyreroad::multipoint::{Control, Problem, SolverOptions};
use tyreroad::rolling::{
    ContactSlope, Road, RollingConfig, RollingControl, RollingResult, RunOptions, Sensor,
    StepStatus, Tread, roll, roll_coupled, step_problem,
};
use tyreroad::scenario::{RunOptions as ScenarioRunOptions, Scenario, ScenarioResult};
use tyreroad::shared::Par;
use tyreroad::texture::HeightMap;
use tyreroad::texture_road::{TextureRoadOptions, texture_road};

type TestResult = Result<(), Box<dyn std::error::Error>>;

const LOAD: f64 = 10.0;

fn material() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

/// A nearly flat tyre (1 m radii), 24 × 16 mm, from x = 14 to 16 mm in
/// 0.5 mm steps under 10 N; sensors: the road's two halves across the
/// ridges (y < 0 and y ≥ 0, tiling it), so each ridge's load splits
/// between them and a disc around a summit at one end puts it all on one.
fn config() -> RollingConfig {
    let tyre = Tread::Block {
        length: 24e-3,
        width: 16e-3,
    };
    let mut c = RollingConfig::new(
        tyre,
        [14e-3, 16e-3, 0.5e-3],
        10.0,
        RollingControl::Load(LOAD),
    );
    // The static rung this test holds each step against has no deformed
    // tread's slope (the neighbours' tilt; tests/rolling_deformed_slope.rs).
    c.contact_slope = ContactSlope::Profile;
    c.sensors = vec![
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
    c
}

/// The ridges' calibrated rolling road (with fields).
fn calibrated_road(map: &HeightMap, config: &RollingConfig) -> Road<CalibratedLaw> {
    let road = calibrated_road_with(map, config, &TextureRoadOptions::new(0.2e-3, 2e-6));
    assert_eq!(road.len(), 3);
    road
}

/// A texture's calibrated rolling road (with fields), segmented with
/// `options`.
fn calibrated_road_with(
    map: &HeightMap,
    config: &RollingConfig,
    options: &TextureRoadOptions,
) -> Road<CalibratedLaw> {
    let m = material();
    let troad = texture_road(map, m, options).unwrap();
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let radii = troad.summit_radii();
    let wilke = Road::new(troad.set.clone().translated([0.0, -y_mid]).unwrap())
        .with_summit_radii(radii.clone())
        .unwrap();
    let calibrator = Calibrator::new(m, CalibrationOptions::default()).with_fields();
    let cal = calibrate_rolling_road(&troad, &wilke, map, config, &calibrator, Par::Seq).unwrap();
    let radii = cal.kept.iter().map(|&i| radii[i]).collect();
    Road::new(cal.set).with_summit_radii(radii).unwrap()
}

/// Largest and rms per-step `|model − reference|` over `scale`.
fn errors(model: &[f64], reference: &[f64], scale: f64) -> (f64, f64) {
    let e: Vec<f64> = model
        .iter()
        .zip(reference)
        .map(|(m, r)| (m - r).abs() / scale)
        .collect();
    let max = e.iter().copied().fold(0.0, f64::max);
    let rms = (e.iter().map(|x| x * x).sum::<f64>() / e.len() as f64).sqrt();
    (max, rms)
}

fn balanced(run: &RollingResult) {
    for s in &run.steps {
        assert_eq!(s.status, StepStatus::Converged, "step {}", s.index);
        assert!(
            (s.total_force - LOAD).abs() <= 1e-9 * LOAD,
            "step {}: {} N",
            s.index,
            s.total_force
        );
        // The two sensors tile the road: they share the whole load.
        let sum: f64 = s.sensor_forces.iter().sum();
        assert!(
            (sum - s.total_force).abs() <= 1e-9 * LOAD,
            "step {}: sensors {sum} N",
            s.index
        );
    }
}

#[test]
fn field_coupled_ridges_roll_closer_to_the_bem_than_point_coupled_ones() -> TestResult {
    let m = material();
    let map = common::rolling_ridges();
    let config = config();
    let road = calibrated_road(&map, &config);
    let point = roll(&road, m, &config, &RunOptions::default())?;
    let coupling = FieldRolling::with_defaults(&m)?;
    let fields = roll_coupled(&road, m, &config, &RunOptions::default(), &coupling)?;
    balanced(&point);
    balanced(&fields);
    let stats = coupling.stats();
    assert_eq!(stats.steps, config.steps());
    assert!(
        stats.rounds >= stats.steps && stats.max_rounds <= 30,
        "{stats:?}"
    );
    // The run's own sensors are its fields' (the default accounting), as
    // recounted from its records.
    let recount = sensor_forces(
        &fields,
        &road,
        material(),
        &config,
        SensorAccounting::Fields,
    )?;
    for (k, s) in fields.steps.iter().enumerate() {
        for (j, f) in s.sensor_forces.iter().enumerate() {
            assert!(
                (f - recount[j][k]).abs() <= 1e-9 * LOAD,
                "{f} vs {}",
                recount[j][k]
            );
        }
    }
    // Under the flat block each step is a static problem: the static
    // rung's fixed point (all pairs, solve_field_coupled) on the step's
    // problem gives the rolling step's forces, to the fixed point's
    // tolerance.
    for (k, s) in fields.steps.iter().enumerate() {
        let (ids, p) = step_problem(&road, m, &config, config.position(k))?.ok_or("no problem")?;
        let laws: Vec<CalibratedLaw> = p.laws().iter().map(|&l| l.clone()).collect();
        let owned = Problem::new(p.positions().to_vec(), p.gaps().to_vec(), laws, m)?;
        let f = solve_field_coupled(
            &owned,
            Control::Load(LOAD),
            &SolverOptions::default(),
            &FieldCouplingOptions::default(),
            None,
        )?;
        for (&id, &force) in s.contact_ids.iter().zip(&s.contact_forces) {
            let a = ids.iter().position(|&i| i == id).ok_or("id")?;
            let static_force = f.solution.forces[a];
            assert!(
                (force - static_force).abs() < 1e-5 * LOAD,
                "step {k}, asperity {id}: {force} N rolling, {static_force} N static"
            );
        }
    }
    // The coupled run keys its own checkpoints.
    assert_ne!(point.input_hash, fields.input_hash);

    let bem = roll_bem(
        &texture_field(&map)?,
        m,
        &config,
        &BemRollingOptions {
            par: Par::Seq,
            ..BemRollingOptions::default()
        },
    )?;
    let approach = |r: &RollingResult| -> Vec<f64> { r.steps.iter().map(|s| s.approach).collect() };
    let bem_approach: Vec<f64> = bem.steps.iter().map(|s| s.approach).collect();
    let mean = bem_approach.iter().sum::<f64>() / bem_approach.len() as f64;
    let (point_a, _) = errors(&approach(&point), &bem_approach, mean);
    let (fields_a, _) = errors(&approach(&fields), &bem_approach, mean);
    let sensor = |r: &RollingResult, j: usize| -> Vec<f64> {
        r.steps.iter().map(|s| s.sensor_forces[j]).collect()
    };
    let bem_north: Vec<f64> = bem.steps.iter().map(|s| s.sensor_forces[1]).collect();
    let (point_s, _) = errors(&sensor(&point, 1), &bem_north, LOAD);
    let (fields_s, _) = errors(&sensor(&fields, 1), &bem_north, LOAD);
    println!(
        "approaches point {:?}\nfields {:?}\nbem {:?}\nnorth point {:?} fields {:?} bem {:?}",
        approach(&point),
        approach(&fields),
        bem_approach,
        sensor(&point, 1),
        sensor(&fields, 1),
        bem_north
    );
    for s in &fields.steps {
        println!("fields contacts {:?} {:?}", s.contact_ids, s.contact_forces);
    }
    for s in &point.steps {
        println!("point contacts {:?} {:?}", s.contact_ids, s.contact_forces);
    }
    println!(
        "approach error: point {point_a:.5}, fields {fields_a:.5}; north sensor: point \
         {point_s:.5}, fields {fields_s:.5} of the load; {stats:?}"
    );
    // Both rungs are close in approach; the field rung no farther (with a
    // margin of 0.1 % of the approach for the two models' discretisations).
    assert!(fields_a < 0.03, "fields approach {fields_a}");
    assert!(
        fields_a <= point_a + 1e-3,
        "fields {fields_a}, point {point_a}"
    );
    // The point rung's discs put each tilted ridge's load at its summit's
    // end: the north sensor is far off; the fields split it as the BEM.
    assert!(point_s > 0.1, "point (discs) north sensor {point_s}");
    assert!(fields_s < 0.03, "fields north sensor {fields_s}");
    Ok(())
}

/// One chipping, a paraboloid of radius 5 mm whose −x side is stretched to
/// 40 mm (the caps accounting's case, `src/bem_rolling/caps_tests.rs`),
/// under 5 N, a sensor from 6 mm to 0.5 mm before its summit: the BEM puts
/// a good part of the load on it, the law's disc little, the calibrated
/// field nearly the BEM's.
#[test]
fn a_long_chipping_s_field_puts_its_load_where_the_bem_does() -> TestResult {
    let m = material();
    let (r_short, r_long, summit, load) = (5e-3, 40e-3, [15e-3, 6e-3], 5.0);
    let map = HeightMap::from_fn(301, 121, 1e-4, 1e-4, |x, y| {
        let (u, v) = (x - summit[0], y - summit[1]);
        let r = if u >= 0.0 { r_short } else { r_long };
        (-(u * u) / (2.0 * r) - v * v / (2.0 * r_short)).max(-1e-3)
    })?;
    let tyre = Tread::Tyre {
        radius_x: 1.0,
        radius_y: 1.0,
        length: 16e-3,
        width: 10e-3,
    };
    let xs = summit[0];
    let mut config = RollingConfig::new(tyre, [xs, xs, 1e-3], 10.0, RollingControl::Load(load));
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
    let troad = texture_road(&map, m, &TextureRoadOptions::new(1e-4, 1e-6))?;
    assert_eq!(troad.len(), 1);
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let radii = troad.summit_radii();
    let wilke =
        Road::new(troad.set.clone().translated([0.0, -y_mid])?).with_summit_radii(radii.clone())?;
    let calibrator = Calibrator::new(m, CalibrationOptions::default()).with_fields();
    let cal = calibrate_rolling_road(&troad, &wilke, &map, &config, &calibrator, Par::Seq)?;
    let road = Road::new(cal.set).with_summit_radii(radii)?;
    let coupling = FieldRolling::with_defaults(&m)?;
    let run = roll_coupled(&road, m, &config, &RunOptions::default(), &coupling)?;
    let discs = sensor_forces(&run, &road, material(), &config, SensorAccounting::Discs)?;
    let bem = roll_bem(
        &texture_field(&map)?,
        m,
        &config,
        &BemRollingOptions {
            par: Par::Seq,
            ..BemRollingOptions::default()
        },
    )?;
    let (bem_cut, field_cut, disc_cut) = (
        bem.steps[0].sensor_forces[0],
        run.steps[0].sensor_forces[0],
        discs[0][0],
    );
    println!("cut sensor: BEM {bem_cut} N, fields {field_cut} N, disc {disc_cut} N");
    assert!(bem_cut > 0.15 * load, "BEM {bem_cut} N");
    assert!((disc_cut - bem_cut).abs() > 0.1 * load, "disc {disc_cut} N");
    // The calibrated field is the cap's own BEM pressure under a flat
    // punch, at the force's depth, binned (0.8 mm bins over this 13 mm
    // patch): within 3 % of the load of the BEM's.
    assert!(
        (field_cut - bem_cut).abs() < 0.03 * load,
        "fields {field_cut} N, BEM {bem_cut} N"
    );
    let sum: f64 = run.steps[0].sensor_forces.iter().sum();
    assert!((sum - load).abs() < 1e-9 * load, "sensors {sum} N");
    Ok(())
}

/// A fixed point allowed one round at a tolerance no round can meet: every
/// loaded step is recorded as failed, with its last change as residual,
/// and the run goes on.
#[test]
fn a_fixed_point_that_does_not_settle_is_its_step_s_failure() -> TestResult {
    let m = material();
    let map = common::rolling_ridges();
    let mut config = config();
    config.end = config.start + 0.5e-3;
    let road = calibrated_road(&map, &config);
    let strict = FieldRolling::new(
        &m,
        FieldCouplingOptions {
            tolerance: 1e-300,
            max_rounds: 1,
            ..FieldCouplingOptions::default()
        },
        PairReach::default(),
        SensorAccounting::Fields,
    )?;
    let run = roll_coupled(&road, m, &config, &RunOptions::default(), &strict)?;
    assert_eq!(run.steps.len(), 2);
    for s in &run.steps {
        assert_eq!(s.status, StepStatus::Failed);
        assert!(s.total_force.is_nan());
        assert!(s.residual > 0.0 && s.residual.is_finite(), "{}", s.residual);
    }
    assert!(
        FieldRolling::new(
            &m,
            FieldCouplingOptions::default(),
            PairReach {
                near: 4.0,
                far: 2.0
            },
            SensorAccounting::Fields
        )
        .is_err()
    );
    Ok(())
}

/// A rolling scenario on a small aggregate texture (as
/// `tests/fidelity_rolling.rs`'s, at 40 N so that several chippings touch)
/// runs on `calibrated_fields`, balanced at every step, and not as the
/// point-coupled `calibrated` run; a
/// viscoelastic one takes it too, and refuses a static-only rung by name.
#[test]
fn a_rolling_texture_scenario_takes_the_field_rung() -> TestResult {
    let text = |fidelity: &str| {
        format!(
            "name = \"r\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [model]\nfidelity = \"{fidelity}\"\n\
             [rolling]\nstart = \"13 mm\"\nend = \"15 mm\"\nstep = \"0.5 mm\"\nspeed = \"10 m/s\"\n\
             checkpoint = false\nthreads = 1\n\
             [rolling.tread]\nkind = \"block\"\nlength = \"20 mm\"\nwidth = \"16 mm\"\n\
             [rolling.control]\nload = \"40 N\"\n\
             [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
             [texture.synth]\nkind = \"aggregate\"\nnx = 150\nny = 100\nspacing = \"0.2 mm\"\n\
             grading = \"4/6\"\nseed = 2006\n"
        )
    };
    let approaches = |fidelity: &str| -> Result<Vec<f64>, Box<dyn std::error::Error>> {
        let s = Scenario::parse(&text(fidelity), fidelity)?;
        let ScenarioResult::Rolling(run) = s.run(&ScenarioRunOptions::new("."))? else {
            return Err("not a rolling result".into());
        };
        assert_eq!(run.status_counts()[2], 0, "{fidelity}: failed steps");
        for st in &run.result.steps {
            assert!(
                (st.total_force - 40.0).abs() <= 1e-9 * 40.0,
                "{}",
                st.total_force
            );
            assert!(st.contacts > 1, "{fidelity}: {} contacts", st.contacts);
        }
        Ok(run.result.steps.iter().map(|s| s.approach).collect())
    };
    let point = approaches("calibrated")?;
    let fields = approaches("calibrated_fields")?;
    assert_eq!(point.len(), fields.len());
    assert!(
        point
            .iter()
            .zip(&fields)
            .any(|(p, f)| (p - f).abs() > 1e-6 * p),
        "{point:?} vs {fields:?}"
    );
    let visco = text("calibrated_fields").replace(
        "poisson_ratio = 0.5\n",
        "poisson_ratio = 0.5\n[material.viscoelastic]\nlong_term = \"2 MPa\"\n\
         [[material.viscoelastic.branch]]\nmodulus = \"3 MPa\"\nrelaxation_time = \"1 ms\"\n",
    );
    // A viscoelastic tread takes the rung too (tests/visco_calibrated_fields.rs
    // rolls it); the static-only rungs stay refused by name.
    Scenario::parse(&visco, "visco")?;
    match Scenario::parse(&visco.replace("calibrated_fields", "distributed"), "visco") {
        Ok(_) => Err("a viscoelastic distributed rolling run was accepted".into()),
        Err(e) => {
            assert!(e.to_string().contains("[model] fidelity"), "{e}");
            Ok(())
        }
    }
}

/// The packed near-pair sums (the default) against the `f64` bin-by-bin
/// sums they replace, rolled over an aggregate road (4/6 mm chippings,
/// 150 N on a 40 × 24 mm block: many loaded near pairs): every
/// step's approach, contact forces and sensor forces agree to 1e-5 of the
/// load. The packed sum is the `f64` one to ~1e-6 relative and the fixed
/// point stops at 1e-6 of the load, so the two runs can differ by a few
/// 1e-6 of it, not more.
#[test]
fn packed_pair_sums_give_the_exact_sums_step_forces() -> TestResult {
    let text = "name = \"r\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [rolling]\nstart = \"22 mm\"\nend = \"25 mm\"\nstep = \"0.5 mm\"\n\
                speed = \"10 m/s\"\n[rolling.tread]\nkind = \"block\"\nlength = \"40 mm\"\n\
                width = \"24 mm\"\n[rolling.control]\nload = \"150 N\"\n\
                [[rolling.sensor]]\nname = \"s\"\nx0 = \"18 mm\"\nx1 = \"26 mm\"\n\
                y0 = \"-4 mm\"\ny1 = \"3 mm\"\n\
                [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
                [texture.synth]\nkind = \"aggregate\"\nnx = 250\nny = 150\nspacing = \"0.2 mm\"\n\
                grading = \"4/6\"\nseed = 2006\n";
    let scenario = Scenario::parse(text, "aggregate")?;
    let texture = scenario.texture.as_ref().ok_or("no texture")?;
    let map = texture.height_map(std::path::Path::new("."))?;
    let config = scenario.rolling_config()?;
    let load = 150.0;
    let road = calibrated_road_with(&map, &config, &texture.road_options());
    let m = material();
    let packed = FieldRolling::with_defaults(&m)?;
    let exact = FieldRolling::with_defaults(&m)?.with_pair_sum(PairSum::Exact);
    let fast = roll_coupled(&road, m, &config, &RunOptions::default(), &packed)?;
    let reference = roll_coupled(&road, m, &config, &RunOptions::default(), &exact)?;
    let stats = packed.stats();
    assert!(stats.field_pairs > 20 * stats.steps, "{stats:?}");
    assert_eq!(fast.steps.len(), 7);
    let mut worst = 0.0_f64;
    for (a, b) in fast.steps.iter().zip(&reference.steps) {
        assert_eq!(a.status, StepStatus::Converged, "step {}", a.index);
        assert_eq!(b.status, StepStatus::Converged, "step {}", b.index);
        assert_eq!(a.contact_ids, b.contact_ids, "step {}", a.index);
        let forces = a.contact_forces.iter().zip(&b.contact_forces);
        let sensors = a.sensor_forces.iter().zip(&b.sensor_forces);
        for (x, y) in forces.chain(sensors) {
            worst = worst.max((x - y).abs() / load);
        }
        // The approach moves by the forces' change over the road's
        // stiffness: µm per N here, so 1e-5 of 40 N is well under 1 nm.
        assert!((a.approach - b.approach).abs() < 1e-9, "step {}", a.index);
    }
    assert!(
        worst <= 1e-5,
        "largest force difference {worst:e} of the load"
    );
    Ok(())
}
