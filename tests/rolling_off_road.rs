//! A rolling path that misses the road is refused naming the keys and the
//! road's extent, not with a bare "no asperity under the footprint".

use tyreroad::scenario::{RunOptions, Scenario};

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
    use tyreroad::scenario::ScenarioResult;
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/rolling_small.toml");
    let text = std::fs::read_to_string(path).expect("fixture");
    let warnings = |text: &str| {
        let ScenarioResult::Rolling(run) = Scenario::parse(text, "edge")
            .expect("parses")
            .run(&RunOptions::new("."))
            .expect("runs")
        else {
            panic!("not a rolling run");
        };
        run.road.warnings().to_vec()
    };
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
