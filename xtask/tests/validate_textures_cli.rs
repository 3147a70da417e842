//! `cargo xtask validate --textures` refuses an unknown rung name, in
//! `--rungs` or `--segmentation-rung`, before it builds a road or runs a
//! BEM, and names the option; so does `--max-cap-width` with a width that
//! is not a positive number.

use std::process::Command;

fn validate_textures(args: &[&str]) -> std::process::Output {
    let out = std::env::temp_dir().join(format!("tyreroad-vt-cli-{}", std::process::id()));
    Command::new(env!("CARGO_BIN_EXE_xtask"))
        .args([
            "validate",
            "--textures",
            "--no-resolution",
            "--texture-cells",
            "16",
        ])
        .args(args)
        .arg("--out")
        .arg(&out)
        .output()
        .expect("xtask runs")
}

#[test]
fn an_unknown_rung_name_is_refused_by_its_option() {
    for (option, args) in [
        ("--rungs", vec!["--rungs", "calibrated,fancy"]),
        (
            "--segmentation-rung",
            vec!["--segmentation", "--segmentation-rung", "fancy"],
        ),
    ] {
        let out = validate_textures(&args);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{option} fancy exited 0");
        assert!(
            stderr.contains(option) && stderr.contains("fancy"),
            "{option}: {stderr}"
        );
    }
}

#[test]
fn a_tile_width_that_is_not_positive_is_refused_by_max_cap_width() {
    for width in ["0", "-2", "nan", "inf"] {
        let option = format!("--max-cap-width={width}");
        let out = validate_textures(&[&option]);
        let stderr = String::from_utf8_lossy(&out.stderr);
        assert!(!out.status.success(), "{option} exited 0");
        assert!(stderr.contains("--max-cap-width"), "{option}: {stderr}");
    }
}
