//! Tests of `check.rs`: each bad value refused by its key.

#![allow(clippy::unwrap_used)]

use crate::scenario::Scenario;

const PAPER: &str = include_str!("../../fixtures/paper_25_spheres.toml");
const ROLLING: &str = include_str!("../../fixtures/rolling_tyre_dense_asphalt.toml");
const VISCO: &str = include_str!("../../fixtures/rolling_tyre_dense_asphalt_visco.toml");

/// `base` with `from` replaced by `to` must be refused with a message
/// naming `key`.
fn refused(base: &str, from: &str, to: &str, key: &str) {
    assert!(base.contains(from), "fixture lacks {from:?}");
    let text = base.replacen(from, to, 1);
    match Scenario::parse(&text, "case") {
        Ok(_) => panic!("{to:?} accepted"),
        Err(e) => assert!(e.to_string().contains(key), "{to:?}: {e} (expected {key})"),
    }
}

#[test]
fn fixtures_pass_the_checks() {
    assert!(Scenario::parse(PAPER, "paper").is_ok());
    assert!(Scenario::parse(ROLLING, "rolling").is_ok());
}

#[test]
fn out_of_range_static_values_name_their_key() {
    let n = "name = \"paper_25_spheres\"";
    refused(PAPER, n, "name = \"../x\"", "`case: name`");
    refused(PAPER, n, "name = \"/tmp/x\"", "`case: name`");
    refused(PAPER, n, "name = \"\"", "`case: name`");
    refused(PAPER, n, "name = \"a\\nb\"", "`case: name`");
    refused(
        PAPER,
        "\"6.54 MPa\"",
        "\"1e-300 Pa\"",
        "[material] youngs_modulus",
    );
    refused(
        PAPER,
        "[material]",
        "[solver]\ntolerance = 1e3\n\n[material]",
        "[solver] tolerance",
    );
    refused(PAPER, "\"500 N\"", "\"1e30 N\"", "[static] loads[3]");
    refused(PAPER, "\"289 N\"", "\"-1 N\"", "[static] loads[0]");
    refused(
        PAPER,
        "radius = \"5 mm\"",
        "radius = \"1e10 m\"",
        "[default_shape] radius",
    );
    refused(PAPER, "id = 2\n", "id = 1\n", "#2 id");
}

/// Regression (adversarial run, 2026-11-30): `density = 1` on a 0.12 ×
/// 0.08 m synthetic road made a road of no summit, refused at run time
/// as "no asperity" without naming the key.
#[test]
fn a_synthetic_road_density_that_places_no_summit_is_refused_by_key() {
    const SMALL: &str = include_str!("../../fixtures/rolling_small.toml");
    refused(
        SMALL,
        "density = 85000",
        "density = 1",
        "[rolling.synthetic_road] density",
    );
    // One summit (0.5 / area rounds up to one) is a road.
    assert!(
        Scenario::parse(
            &SMALL.replacen("density = 85000", "density = 105", 1),
            "one"
        )
        .is_ok()
    );
}

/// An unknown `[model]` name is refused with every name the key
/// accepts (a rung or a choice added later was once missing from
/// these messages), and every name listed is accepted.
#[test]
fn unknown_model_names_list_every_accepted_name() {
    let model = |body: &str| format!("[model]\n{body}\n\n[rolling]");
    for (key, listed) in [
        (
            "fidelity",
            "\"wilke\", \"calibrated\", \"distributed\", \"clustered\" or \"calibrated_fields\"",
        ),
        ("calibrate_under", "\"flat\", \"tread\" or \"tread_slope\""),
    ] {
        let text = ROLLING.replacen(
            "[rolling]",
            &model(
                &format!("fidelity = \"calibrated\"\n{key} = \"best\"").replacen(
                    "fidelity = \"calibrated\"\nfidelity",
                    "fidelity",
                    1,
                ),
            ),
            1,
        );
        let e = Scenario::parse(&text, "case").unwrap_err().to_string();
        assert!(e.contains(listed), "{e}");
        // Each listed name is known to the key's parser (a rung may
        // still be refused where it does not apply: static-only rungs
        // in a rolling run).
        for name in listed.split(['"', ',', ' ']).filter(|w| w.len() > 2) {
            let spec = crate::scenario::spec::ModelSpec {
                fidelity: Some(name.into()),
                calibrate_under: Some(name.into()),
            };
            let known = match key {
                "fidelity" => spec.fidelity().is_ok(),
                _ => spec.calibrate_under().is_ok(),
            };
            assert!(known, "{key} = {name:?}");
        }
    }
}

/// Without `[model] fidelity` an elastic rolling run on a texture takes
/// the calibrated laws and every other run Wilke's; a given fidelity
/// always wins.
#[test]
fn the_default_rung_is_calibrated_for_elastic_rolling_on_a_texture_only() {
    use crate::fidelity::Fidelity;
    let rung = |text: &str| Scenario::parse(text, "case").unwrap().fidelity().unwrap();
    assert_eq!(rung(ROLLING), Fidelity::Calibrated);
    assert_eq!(
        rung(include_str!("../../fixtures/rolling_tyre_chip_seal.toml")),
        Fidelity::Calibrated
    );
    assert_eq!(rung(VISCO), Fidelity::Wilke);
    assert_eq!(rung(PAPER), Fidelity::Wilke);
    assert_eq!(
        rung(include_str!("../../fixtures/texture_block_static.toml")),
        Fidelity::Wilke
    );
    assert_eq!(
        rung(include_str!("../../fixtures/rolling_small.toml")),
        Fidelity::Wilke
    );
    let wilke = ROLLING.replacen("[rolling]", "[model]\nfidelity = \"wilke\"\n\n[rolling]", 1);
    assert_eq!(rung(&wilke), Fidelity::Wilke);
    let visco_calibrated = VISCO.replacen(
        "[rolling]",
        "[model]\nfidelity = \"calibrated\"\n\n[rolling]",
        1,
    );
    assert_eq!(rung(&visco_calibrated), Fidelity::Calibrated);
}

/// `[model] calibrate_under`: known names only, and `"tread"` only
/// where a tread meets calibrated caps (a rolling run on a texture's
/// calibrated laws).
#[test]
fn calibrate_under_names_its_values_and_needs_calibrated_rolling() {
    let model = |body: &str| format!("[model]\n{body}\n\n[rolling]");
    let rolling = |body: &str| ROLLING.replacen("[rolling]", &model(body), 1);
    for fidelity in ["calibrated", "calibrated_fields"] {
        let text = rolling(&format!(
            "fidelity = \"{fidelity}\"\ncalibrate_under = \"tread\""
        ));
        let s = Scenario::parse(&text, "case").unwrap();
        assert_eq!(
            s.model.calibrate_under().unwrap(),
            crate::fidelity::under_tread::CalibrateUnder::Tread
        );
    }
    let flat = Scenario::parse(&rolling("calibrate_under = \"flat\""), "case").unwrap();
    assert_eq!(
        flat.model.calibrate_under().unwrap(),
        crate::fidelity::under_tread::CalibrateUnder::Flat
    );
    refused(
        ROLLING,
        "[rolling]",
        &model("fidelity = \"calibrated\"\ncalibrate_under = \"tilted\""),
        "[model] calibrate_under",
    );
    refused(
        ROLLING,
        "[rolling]",
        &model("fidelity = \"wilke\"\ncalibrate_under = \"tread\""),
        "[model] calibrate_under",
    );
    // Without a fidelity an elastic rolling texture takes calibrated
    // laws, and with them a tread to calibrate under.
    assert!(Scenario::parse(&rolling("calibrate_under = \"tread\""), "case").is_ok());
    refused(
        PAPER,
        "[material]",
        "[model]\ncalibrate_under = \"tread\"\n\n[material]",
        "[model] calibrate_under",
    );
    // Along the path: the same places, elastic treads only.
    let slope = Scenario::parse(
        &rolling("fidelity = \"calibrated_fields\"\ncalibrate_under = \"tread_slope\""),
        "case",
    )
    .unwrap();
    assert_eq!(
        slope.model.calibrate_under().unwrap(),
        crate::fidelity::under_tread::CalibrateUnder::TreadSlope
    );
    refused(
        ROLLING,
        "[rolling]",
        &model("fidelity = \"wilke\"\ncalibrate_under = \"tread_slope\""),
        "[model] calibrate_under",
    );
    refused(
        VISCO,
        "[rolling]",
        &model("fidelity = \"calibrated\"\ncalibrate_under = \"tread_slope\""),
        "[model] calibrate_under",
    );
}

#[test]
fn out_of_range_rolling_values_name_their_key() {
    refused(
        ROLLING,
        "step = \"1 mm\"",
        "step = \"1e-300 m\"",
        "[rolling] step",
    );
    refused(
        ROLLING,
        "step = \"1 mm\"",
        "step = \"0.001 um\"",
        "[rolling] step",
    );
    refused(
        ROLLING,
        "speed = \"50 km/h\"",
        "speed = \"1e30 m/s\"",
        "[rolling] speed",
    );
    refused(
        ROLLING,
        "speed = \"50 km/h\"",
        "speed = \"0 m/s\"",
        "[rolling] speed",
    );
    refused(
        ROLLING,
        "reference_force = \"1 N\"",
        "reference_force = \"1e-300 N\"",
        "[rolling] reference_force",
    );
    refused(
        ROLLING,
        "checkpoint = true",
        "checkpoint = true\nthreads = 100000",
        "[rolling] threads",
    );
    refused(
        ROLLING,
        "load = \"1500 N\"",
        "tread_height = \"-1 mm\"",
        "[rolling.control] tread_height",
    );
    // Regression (adversarial run, 2026-11-30): a rolling load of 1e-300 N
    // passed the open lower bound and failed every step.
    refused(
        ROLLING,
        "load = \"1500 N\"",
        "load = \"1e-300 N\"",
        "[rolling.control] load",
    );
    let wide = ROLLING.replacen("nx = 2000", "nx = 30000", 1);
    refused(&wide, "ny = 600", "ny = 30000", "[texture.synth] nx, ny");
    refused(
        ROLLING,
        "min_prominence = \"0.1 mm\"",
        "min_prominence = \"-0.1 mm\"",
        "[texture] min_prominence",
    );
    for width in ["0 mm", "-4 mm", "2 m"] {
        refused(
            ROLLING,
            "min_prominence = \"0.1 mm\"",
            &format!("min_prominence = \"0.1 mm\"\nmax_cap_width = \"{width}\""),
            "[texture] max_cap_width",
        );
    }
    refused(
        ROLLING,
        "name = \"shoulder\"",
        "name = \"centre\"",
        "#2 name",
    );
    refused(
        ROLLING,
        "name = \"shoulder\"",
        "name = \"a\\nb\"",
        "#2 name",
    );
    refused(
        ROLLING,
        "\n[material]\n",
        "\n[static]\nloads = [\"1 N\"]\n\n[material]\n",
        "[static]",
    );
}
