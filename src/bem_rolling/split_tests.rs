//! The asperity split ([`super::asperity_split`]) against the runs it
//! splits: its BEM sensor force is the BEM rolling reference's at the same
//! step, its model sensor force the scenario's rolling run's.

use std::path::Path;

use super::*;
use crate::scenario::{RunOptions, Scenario, ScenarioResult};

/// A tyre (the fixtures' 0.3 and 0.5 m radii: the tread slopes over the
/// caps) on a 30 × 20 mm aggregate texture, four steps (the spectra's
/// least), one sensor whose edge runs 0.2 mm past the footprint's centre;
/// the split is made at the third step.
const SCENARIO: &str = "name = \"split\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\n\
    poisson_ratio = 0.5\n\
    [rolling]\nstart = \"13 mm\"\nend = \"16 mm\"\nstep = \"1 mm\"\nspeed = \"10 m/s\"\n\
    checkpoint = false\nthreads = 1\n\
    [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\n\
    length = \"20 mm\"\nwidth = \"16 mm\"\n\
    [rolling.control]\nload = \"20 N\"\n\
    [[rolling.sensor]]\nname = \"side\"\nx0 = \"0 mm\"\nx1 = \"15.2 mm\"\ny0 = \"-10 mm\"\ny1 = \"10 mm\"\n\
    [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
    [texture.synth]\nkind = \"aggregate\"\nnx = 150\nny = 100\nspacing = \"0.2 mm\"\n\
    grading = \"4/6\"\nseed = 2006\n";

/// On both rungs the split can solve (the calibrated one on the tables of
/// a run of the whole path, not of the split's stretch).
#[test]
fn the_split_s_sensor_forces_are_the_runs_it_splits() {
    for fidelity in ["wilke", "calibrated"] {
        let text = SCENARIO.replace(
            "name = \"split\"\n",
            &format!("name = \"split\"\n[model]\nfidelity = \"{fidelity}\"\n"),
        );
        split_matches_its_runs(&text);
    }
}

fn split_matches_its_runs(text: &str) {
    let scenario = Scenario::parse(text, "split").expect("scenario");
    let options = BemRollingOptions {
        par: Par::Seq,
        ..BemRollingOptions::default()
    };
    let split = asperity_split(
        Scenario::parse(text, "split").expect("scenario"),
        Path::new("."),
        &[15e-3],
        0,
        Par::Seq,
        &options,
    )
    .expect("split");
    let s = &split[0];
    let ScenarioResult::Rolling(run) = scenario.run(&RunOptions::new(".")).expect("rolling run")
    else {
        panic!("not a rolling run");
    };
    let map = scenario
        .texture
        .as_ref()
        .expect("texture")
        .height_map(Path::new("."))
        .expect("map");
    let field = texture_field(&map).expect("field");
    let bem = roll_bem(
        &field,
        scenario.material().expect("material"),
        &run.config,
        &options,
    )
    .expect("BEM rolling");
    let load = 20.0;
    let bem_sensor = bem.steps[2].sensor_forces[0];
    let model_sensor = run.result.steps[2].sensor_forces[0];
    assert!(
        bem_sensor > 0.05 * load,
        "the sensor is loaded: {bem_sensor} N, {s:?}"
    );
    assert!(
        (s.bem_sensor - bem_sensor).abs() < 1e-5 * load,
        "split {} N, BEM rolling {bem_sensor} N",
        s.bem_sensor
    );
    assert!(
        (s.model_sensor - model_sensor).abs() < 1e-5 * load,
        "split {} N, rolling run {model_sensor} N",
        s.model_sensor
    );
    assert!(
        (s.bem_approach - bem.steps[2].approach).abs() < 1e-9,
        "approach {} m against {} m",
        s.bem_approach,
        bem.steps[2].approach
    );
    // The reported asperities hold the sensor's load (those under 1 mN
    // left out).
    let held: f64 = s.asperities.iter().map(|a| a.bem_sensor).sum();
    assert!(
        (held + s.bem_sensor_unlabelled - s.bem_sensor).abs() < 0.02 * s.bem_sensor,
        "asperities {held} N of {} N",
        s.bem_sensor
    );
}

/// A coupled rung's step is not one solve the split can repeat: it is
/// refused by name, where it used to be split on the Wilke laws without a
/// word.
#[test]
fn a_rung_the_split_cannot_solve_is_refused_by_name() {
    let text = SCENARIO.replace(
        "name = \"split\"\n",
        "name = \"split\"\n[model]\nfidelity = \"calibrated_fields\"\n",
    );
    let error = asperity_split(
        Scenario::parse(&text, "split").expect("scenario"),
        Path::new("."),
        &[15e-3],
        0,
        Par::Seq,
        &BemRollingOptions::default(),
    )
    .expect_err("calibrated_fields cannot be split");
    assert!(error.to_string().contains("not supported"), "{error}");
}
