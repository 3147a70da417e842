//! A rolling path that misses the road is refused naming the keys and the
//! road's extent, not with a bare "no asperity under the footprint"; what
//! a path misses or overloads (a footprint off the road, a sensor no
//! footprint covers, a load no linear tread carries) is warned of.

use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};

/// Why the scenario `text` (files under `base`) does not run (empty if it
/// runs).
fn refusal(text: &str, base: &str) -> String {
    Scenario::parse(text, "off_road")
        .expect("parses")
        .run(&RunOptions::new(base))
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
}

/// The road summary's warnings of the rolling scenario `text`, run.
fn road_warnings(text: &str) -> Vec<String> {
    let ScenarioResult::Rolling(run) = Scenario::parse(text, "warned")
        .expect("parses")
        .run(&RunOptions::new("."))
        .expect("runs")
    else {
        panic!("not a rolling run");
    };
    run.road.warnings().to_vec()
}

#[test]
fn a_path_beside_the_road_names_the_path_keys_and_the_road_extent() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/rolling_small.toml");
    let text = std::fs::read_to_string(path).expect("fixture");
    assert!(text.contains("lateral = \"2 mm\""));
    let text = text.replace("lateral = \"2 mm\"", "lateral = \"0.5 m\"");
    let e = refusal(&text, env!("CARGO_MANIFEST_DIR"));
    assert!(
        e.contains("[rolling] start/end/lateral")
            && e.contains("no asperity under the footprint")
            && e.contains("the road's asperities span x ∈ [0.0"),
        "{e}"
    );
}

/// The calibrated default (an elastic rolling run on a texture) sizes its
/// tables by a Wilke run first: a path off the road is refused by that run
/// in the same terms as a Wilke run, not blamed on `[model] fidelity`.
#[test]
fn a_calibrated_path_beside_the_road_is_refused_as_a_wilke_one_is() {
    let text = "name = \"off\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [rolling]\nstart = \"24 mm\"\nend = \"36 mm\"\nstep = \"1 mm\"\nspeed = \"10 m/s\"\n\
                lateral = \"0.5 m\"\ncheckpoint = false\nthreads = 1\n\
                [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.1 m\"\nradius_y = \"0.1 m\"\n\
                length = \"30 mm\"\nwidth = \"24 mm\"\n\
                [rolling.control]\nload = \"150 N\"\n\
                [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
                [texture.synth]\nkind = \"aggregate\"\nnx = 300\nny = 200\nspacing = \"0.2 mm\"\n\
                grading = \"4/6\"\nseed = 2006\n";
    let scenario = Scenario::parse(text, "off_road").expect("parses");
    assert_eq!(
        scenario.fidelity().expect("a rung").to_string(),
        "calibrated"
    );
    let e = refusal(text, ".");
    assert!(
        e.contains("[rolling] start/end/lateral")
            && e.contains("no asperity under the footprint")
            && e.contains("put the path on the road")
            && !e.contains("[model] fidelity"),
        "{e}"
    );
}

/// Regression (adversarial run, 2026-11-30): a path along the edge of a
/// synthetic road, its footprint a quarter off the road, got only the
/// clearance warning, where a texture map's is named. The road summary
/// now warns with both extents; the fixture's own path is not warned of.
#[test]
fn a_footprint_reaching_off_a_synthetic_road_is_warned_of() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/rolling_small.toml");
    let text = std::fs::read_to_string(path).expect("fixture");
    let warnings = road_warnings;
    assert!(warnings(&text).is_empty());
    let edge = text.replace("lateral = \"2 mm\"", "lateral = \"30 mm\"");
    let w = warnings(&edge);
    assert!(
        w.iter().any(|w| w.starts_with(
            "the tread's footprint (50.0 × 40.0 mm) reaches off the synthetic road (120.0 × 80.0 mm)"
        ) && w.contains("y = 10.0 … 50.0 mm")),
        "{w:?}"
    );
}

/// Regression (adversarial run, 2026-11-30): a sensor off the road (x =
/// 500–600 mm on a 120 mm road) ran with an all-zero column and only the
/// note a sensor the path merely misses gets. Each sensor outside the
/// region the path's footprints and margins reach is now warned of with
/// both rectangles; one that region just reaches is not.
#[test]
fn a_sensor_no_footprint_covers_is_warned_of() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/rolling_small.toml");
    let text = std::fs::read_to_string(path).expect("fixture");
    let warnings = road_warnings;
    let sensor = "x0 = \"55 mm\"\nx1 = \"65 mm\"";
    assert!(text.contains(sensor));
    let off = text.replace(sensor, "x0 = \"500 mm\"\nx1 = \"600 mm\"");
    let w = warnings(&off);
    assert!(
        w.iter().any(|w| w.starts_with(
            "sensor \"centre\" (x = 500.0 … 600.0 mm, y = -10.0 … 10.0 mm) lies outside the \
             region the path's footprints and their margins reach (x = 2.5 … 116.5 mm, \
             y = -30.0 … 34.0 mm)"
        )),
        "{w:?}"
    );
    // Beside the path: the fixture's footprints span y = -18 … 22 mm, their
    // 10 mm margins and a tenth of the half-width more -30 … 34 mm. A
    // sensor at 23–30 mm, inside the margin, reads force (review,
    // 2026-11-30: 1.95 N at 300 N) and is not warned of.
    let sensor_at = |y0: &str| {
        text.replace(
            "y0 = \"-10 mm\"\ny1 = \"10 mm\"",
            &format!("y0 = \"{y0}\"\ny1 = \"40 mm\""),
        )
    };
    assert_eq!(warnings(&sensor_at("35 mm")).len(), 1);
    for y0 in ["33 mm", "23 mm"] {
        assert!(warnings(&sensor_at(y0)).is_empty(), "{y0}");
    }
}

/// Regression (adversarial run, 2026-11-30): 1e7 N on a 30 × 30 mm
/// footprint (1700 times the tread's modulus) ran to a 26 m approach with
/// every step `converged` and no word but the clearance warning. A load
/// whose nominal pressure passes a tenth of the modulus is now warned of;
/// the fixture's (0.2 %) and a load just under the line are not.
#[test]
fn a_load_no_linear_tread_carries_is_warned_of() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/rolling_small.toml");
    let text = std::fs::read_to_string(path).expect("fixture");
    let pressure_warnings = |load: &str| {
        let text = text.replace("load = \"30 N\"", &format!("load = \"{load}\""));
        road_warnings(&text)
            .into_iter()
            .filter(|w| w.starts_with("the load over the tread's footprint"))
            .collect::<Vec<_>>()
    };
    assert!(text.contains("load = \"30 N\""));
    assert!(pressure_warnings("30 N").is_empty());
    // 50 × 40 mm at 6.54 MPa: the line is at 1308 N.
    assert!(pressure_warnings("1300 N").is_empty());
    let w = pressure_warnings("1400 N");
    assert!(
        w.len() == 1
            && w[0].contains("is 0.700 MPa, 11 % of the tread's Young's modulus (6.540 MPa)"),
        "{w:?}"
    );
}

/// A run whose approach passed the tread's profile at the selection
/// window's edge says so in the library's warnings (Python's
/// `warnings` and `cargo xtask run` print the same line), not in the
/// runner's code alone.
#[test]
fn an_approach_past_the_window_s_edge_is_a_warning_of_the_run() {
    let text = "name = \"sparse\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [rolling]\nstart = \"25 mm\"\nend = \"55 mm\"\nstep = \"1 mm\"\nspeed = \"50 km/h\"\n\
                threads = 1\ncheckpoint = false\n\
                [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\n\
                length = \"50 mm\"\nwidth = \"40 mm\"\n\
                [rolling.control]\nload = \"50 N\"\n\
                [rolling.synthetic_road]\nlength = \"0.1 m\"\nwidth = \"0.05 m\"\ndensity = 40000\n";
    let run = |text: &str| {
        Scenario::parse(text, "sparse")
            .expect("parses")
            .run(&RunOptions::new("."))
            .expect("runs")
    };
    let result = run(text);
    let ScenarioResult::Rolling(rolled) = &result else {
        panic!("not a rolling run");
    };
    let clearance = rolled.result.min_clearance();
    assert!(clearance < 0.0, "{clearance}");
    let warnings = result.warnings();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("the approach exceeds the tread profile at the selection boundary")),
        "{warnings:?}"
    );
    // A light load stays inside the window: no such warning.
    let light = run(&text.replace("load = \"50 N\"", "load = \"0.2 N\""));
    let ScenarioResult::Rolling(rolled) = &light else {
        panic!("not a rolling run");
    };
    assert!(
        rolled.result.min_clearance() > 0.0,
        "{}",
        rolled.result.min_clearance()
    );
    assert!(
        !light
            .warnings()
            .iter()
            .any(|w| w.contains("selection boundary"))
    );
}
