//! A rolling path that misses the road is refused naming the keys and the
//! road's extent, not with a bare "no asperity under the footprint".

use tyreroad::scenario::{RunOptions, Scenario};

#[test]
fn a_path_beside_the_road_names_the_path_keys_and_the_road_extent() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/fixtures/rolling_small.toml");
    let text = std::fs::read_to_string(path).expect("fixture");
    assert!(text.contains("lateral = \"2 mm\""));
    let text = text.replace("lateral = \"2 mm\"", "lateral = \"0.5 m\"");
    let scenario = Scenario::parse(&text, "off_road").expect("parses");
    let e = scenario
        .run(&RunOptions::new(env!("CARGO_MANIFEST_DIR")))
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        e.contains("[rolling] start/end/lateral")
            && e.contains("no asperity under the footprint")
            && e.contains("the road's asperities span x ∈ [0.0"),
        "{e}"
    );
}
