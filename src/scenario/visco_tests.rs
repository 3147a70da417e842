//! A viscoelastic tread in scenarios: rolled in time between its elastic
//! limits, sweeps, and bad sections named.
#![allow(clippy::unwrap_used)]

use super::{Temperature, ViscoCase};
use crate::scenario::{RunOptions, Scenario, ScenarioResult};

/// fixtures/rolling_small.toml's run with a viscoelastic tread.
fn small(material: &str) -> Scenario {
    let text = std::fs::read_to_string(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/fixtures/rolling_small.toml"
    ))
    .unwrap();
    let text = text.replace(
        "[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n",
        material,
    );
    Scenario::parse(&text, "small").unwrap()
}

const VISCO: &str = r#"[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5

[material.viscoelastic]
long_term = "2 MPa"

[[material.viscoelastic.branch]]
modulus = "3 MPa"
relaxation_time = "1 ms"

[[material.viscoelastic.branch]]
modulus = "5 MPa"
relaxation_time = "20 us"

[material.viscoelastic.shift]
kind = "wlf"
c1 = 8.86
c2 = 101.6
reference = "20 degC"
"#;

#[test]
fn a_viscoelastic_scenario_rolls_in_time_between_its_elastic_limits() {
    let visco = small(VISCO);
    let options = RunOptions::new(env!("CARGO_MANIFEST_DIR"));
    let approach = |run: &crate::scenario::RollingRun| run.result.approach();
    let run = |s: &Scenario| match s.run(&options).unwrap() {
        ScenarioResult::Rolling(r) => approach(&r),
        _ => panic!("not a rolling run"),
    };
    let at = |e: &str| {
        small(&format!(
            "[material]\nyoungs_modulus = \"{e}\"\npoisson_ratio = 0.5\n"
        ))
    };
    // Scenario::run rolls the viscoelastic tread at [rolling] speed.
    let rolled = run(&visco);
    let (relaxed, glassy) = (run(&at("2 MPa")), run(&at("10 MPa")));
    for k in 0..rolled.len() {
        assert!(glassy[k] < rolled[k] && rolled[k] < relaxed[k], "step {k}");
    }
    // The sweep: very slow is the relaxed elastic run (0.5 %); a cold
    // tread (slower relaxation, WLF) is stiffer than a warm one.
    let cases = [
        ViscoCase {
            speed: Some(1e-5),
            temperature: None,
        },
        ViscoCase {
            speed: None,
            temperature: Some(273.15),
        },
        ViscoCase {
            speed: None,
            temperature: Some(313.15),
        },
    ];
    let runs = visco.roll_viscoelastic(&options, &cases).unwrap();
    let runs: Vec<Vec<f64>> = runs.into_iter().map(|r| approach(&r.unwrap())).collect();
    for k in 0..rolled.len() {
        assert!((runs[0][k] / relaxed[k] - 1.0).abs() < 5e-3, "step {k}");
        assert!(runs[1][k] < rolled[k] && rolled[k] < runs[2][k], "step {k}");
    }
    // Split runs are refused: the memory runs along the whole path.
    assert!(visco.roll_part(&options, 0..10, 2).is_err());
}

#[test]
fn a_bad_viscoelastic_section_is_named() {
    let options = RunOptions::new(env!("CARGO_MANIFEST_DIR"));
    let neither = small(
        "[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\n[material.viscoelastic]\n",
    );
    let err = neither.run(&options).unwrap_err().to_string();
    assert!(err.contains("[material.viscoelastic]"), "{err}");
    let unshifted = small(&VISCO.replace("[material.viscoelastic.shift]\nkind = \"wlf\"\nc1 = 8.86\nc2 = 101.6\nreference = \"20 degC\"\n", ""));
    let case = [ViscoCase {
        speed: None,
        temperature: Some(300.0),
    }];
    let runs = unshifted.roll_viscoelastic(&options, &case).unwrap();
    let err = runs[0].as_ref().unwrap_err().to_string();
    assert!(err.contains("shift"), "{err}");
    let sticky = small(&VISCO.replace(
        "[material.viscoelastic]\n",
        "[material.viscoelastic]\ntrailing_memory = \"glued\"\nreceding = \"ting\"\n",
    ));
    let err = sticky
        .roll_viscoelastic(&options, &[ViscoCase::default()])
        .unwrap()[0]
        .as_ref()
        .unwrap_err()
        .to_string();
    assert!(
        err.contains("trailing_memory") && err.contains("glued"),
        "{err}"
    );
}

#[test]
fn temperatures_convert_to_kelvin() {
    assert_eq!(Temperature::parse("293.15 K").unwrap().0, 293.15);
    assert!((Temperature::parse("20 °C").unwrap().0 - 293.15).abs() < 1e-12);
    assert!((Temperature::parse("-10 degC").unwrap().0 - 263.15).abs() < 1e-12);
    assert!(Temperature::parse("-300 °C").is_err());
    assert!(Temperature::parse("warm").unwrap_err().contains("warm"));
}
