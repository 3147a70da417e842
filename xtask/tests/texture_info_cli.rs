//! `cargo xtask texture info` refuses a baseline it cannot use with a
//! non-zero exit and a message naming the option (it used to print "n/a"
//! and exit 0).

use std::path::Path;
use std::process::Command;

fn info(baseline: &str) -> std::process::Output {
    let file = Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/texture/spheres.x3p");
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["texture", "info"])
        .arg(file)
        .arg(format!("--baseline={baseline}"))
        .output()
        .expect("xtask runs")
}

#[test]
fn texture_info_refuses_a_baseline_that_is_not_a_positive_length() {
    for bad in ["0", "-0.1", "NaN", "inf"] {
        let out = info(bad);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "--baseline {bad} exited 0");
        assert!(
            stderr.contains("--baseline") && stderr.contains("positive length"),
            "{bad}: {stderr}"
        );
    }
    // The default and a usable baseline still print the MPD.
    let out = Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args(["texture", "info"])
        .arg(Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures/texture/spheres.x3p"))
        .output()
        .expect("xtask runs");
    let stdout = String::from_utf8_lossy(&out.stdout);
    assert!(out.status.success(), "{stdout}");
    assert!(stdout.contains("nx: "), "{stdout}");
}
