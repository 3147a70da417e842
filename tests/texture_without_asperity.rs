//! A texture that yields no asperity (a map too small, or thresholds too
//! high) is refused naming the keys that decide it and the map's size, not
//! with a bare "the texture has no asperity".

use tyreroad::scenario::{RunOptions, Scenario};

fn run_error(text: &str) -> String {
    let scenario = Scenario::parse(text, "no_asperity").expect("parses");
    scenario
        .run(&RunOptions::new(env!("CARGO_MANIFEST_DIR")))
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default()
}

#[test]
fn a_texture_without_asperities_names_the_thresholds_and_the_map() {
    // A flat 3 × 3 map: nothing stands out, so nothing can touch first.
    let dir = tempfile::tempdir().expect("tempdir");
    let file = dir.path().join("flat.asc");
    std::fs::write(
        &file,
        "nx 3\nny 3\ndx 1e-4\ndy 1e-4\ndata\n0 0 0\n0 0 0\n0 0 0\n",
    )
    .expect("write");
    let text = format!(
        "name = \"flat\"\n\
         [material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
         [static]\nloads = [\"10 N\"]\n\
         [texture]\nfile = {:?}\nmin_prominence = \"0.1 mm\"\nmin_area = \"1 mm2\"\n",
        file.display().to_string()
    );
    let e = run_error(&text);
    assert!(
        e.contains("[texture] min_prominence, min_area") && e.contains("3 × 3 points"),
        "{e}"
    );
}
