//! `cargo xtask run` on a rolling texture road notes the steps where
//! contact patches overlap only when the asperities are coupled by point
//! forces: the `calibrated_fields` rung couples overlapping patches through
//! their calibrated pressure fields, and the note ("the point-force coupling
//! does not hold there") would tell its user something false.

use std::path::{Path, PathBuf};
use std::process::Command;

/// Five steps of a small tyre over 80 × 60 mm of porous asphalt, where two
/// tiles' patches overlap at some steps under either rung.
fn scenario(fidelity: &str) -> String {
    format!(
        r#"name = "overlap_note_{fidelity}"
[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5

[rolling]
start = "40 mm"
end = "44 mm"
step = "1 mm"
speed = "50 km/h"
margin = "5 mm"
checkpoint = false

[rolling.tread]
kind = "tyre"
radius_x = "0.3 m"
radius_y = "0.5 m"
length = "40 mm"
width = "40 mm"

[rolling.control]
load = "200 N"

[texture]
min_prominence = "0.1 mm"
min_area = "1 mm2"

[texture.synth]
kind = "porous_asphalt"
nx = 320
ny = 240
spacing = "0.25 mm"
seed = 5

[model]
fidelity = "{fidelity}"
"#
    )
}

/// Runs the scenario of `fidelity` in a fresh folder: its stdout and the
/// `n_overlapping` column of its time signals.
fn run(dir: &Path, fidelity: &str) -> (String, Vec<usize>) {
    let file = dir.join(format!("{fidelity}.toml"));
    std::fs::write(&file, scenario(fidelity)).expect("scenario written");
    let out = dir.join(fidelity);
    let run = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .arg("run")
        .arg(&file)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("xtask runs");
    let stdout = String::from_utf8_lossy(&run.stdout).into_owned();
    assert!(
        run.status.success(),
        "{fidelity}: {stdout}\n{}",
        String::from_utf8_lossy(&run.stderr)
    );
    let signals = std::fs::read_to_string(out.join("time_signals.csv")).expect("time signals");
    let mut lines = signals.lines();
    let column = lines
        .next()
        .and_then(|h| h.split(',').position(|c| c == "n_overlapping"))
        .expect("an n_overlapping column");
    let overlapping = lines
        .map(|l| {
            l.split(',')
                .nth(column)
                .and_then(|v| v.parse().ok())
                .expect("a count")
        })
        .collect();
    (stdout, overlapping)
}

#[test]
fn the_overlap_note_is_the_point_couplings_and_not_the_field_runs() {
    let dir: PathBuf =
        std::env::temp_dir().join(format!("tyreroad-overlap-{}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("temp dir");
    const NOTE: &str = "some contact patches overlap";

    let (point, counts) = run(&dir, "calibrated");
    assert!(
        counts.iter().any(|&n| n > 0),
        "no overlap to note: {counts:?}"
    );
    assert!(point.contains(NOTE), "{point}");

    let (fields, counts) = run(&dir, "calibrated_fields");
    // The patches overlap in the field run too: the note is left out
    // because of the rung, not because nothing overlaps.
    assert!(
        counts.iter().any(|&n| n > 0),
        "no overlap in the field run: {counts:?}"
    );
    assert!(!fields.contains(NOTE), "{fields}");
    assert!(fields.contains("steps: 5 converged"), "{fields}");
    std::fs::remove_dir_all(&dir).ok();
}
