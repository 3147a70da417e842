//! One regression test per class of bad value that issue 14 found ending in
//! a panic, a runaway allocation, silent nonsense or an unclear error: each
//! is now refused before anything is solved, by a message that names the
//! key, the value and the range it must lie in. The messages are those of
//! docs/validation.md's error-message audit.

use tyreroad::scenario::Scenario;

const PAPER: &str = include_str!("../fixtures/paper_25_spheres.toml");
const TEXTURE_ROLLING: &str = include_str!("../fixtures/rolling_tyre_dense_asphalt.toml");
const SMALL_ROLLING: &str = include_str!("../fixtures/rolling_small.toml");

/// The message `base` with `from` replaced by `to` is refused with; it must
/// contain every one of `needles` (the key, and the range or the reason).
fn refusal(base: &str, from: &str, to: &str, needles: &[&str]) -> String {
    assert!(base.contains(from), "the fixture lacks {from:?}");
    let text = base.replacen(from, to, 1);
    let message = match Scenario::parse(&text, "case") {
        Ok(_) => panic!("{to:?} accepted"),
        Err(e) => e.to_string(),
    };
    for needle in needles {
        assert!(
            message.contains(needle),
            "{to:?}: {message:?} lacks {needle:?}"
        );
    }
    // One line: a user reads it in a terminal, a CI log greps it.
    assert!(!message.contains('\n'), "{message:?}");
    eprintln!("{to:?} -> {message}");
    message
}

#[test]
fn absurd_radius_is_refused_with_its_key_and_range() {
    for radius in ["1e10 m", "1e-9 m", "0 m", "-5 mm"] {
        refusal(
            PAPER,
            "radius = \"5 mm\"",
            &format!("radius = \"{radius}\""),
            &["[default_shape] radius", "[1e-7, 1e3] m"],
        );
    }
    // An asperity's own shape names the asperity.
    refusal(
        PAPER,
        "id = 7\n",
        "id = 7\nshape = { kind = \"sphere\", radius = \"2 km\" }\n",
        &["[[asperity]] #7 shape radius"],
    );
}

#[test]
fn absurd_law_constant_is_refused_with_its_key_and_range() {
    for c in ["1e3", "1e-6", "0", "-0.36"] {
        refusal(
            PAPER,
            "constant = 0.36",
            &format!("constant = {c}"),
            &["[default_shape] constant", "[1e-3, 1e1]"],
        );
    }
}

#[test]
fn absurd_modulus_is_refused_with_its_key_and_range() {
    for e in ["1e-300 Pa", "1e13 Pa", "-1 MPa"] {
        refusal(
            PAPER,
            "\"6.54 MPa\"",
            &format!("\"{e}\""),
            &["[material] youngs_modulus", "[1e3, 1e12] Pa"],
        );
    }
}

#[test]
fn absurd_texture_scale_is_refused_with_its_key() {
    refusal(
        TEXTURE_ROLLING,
        "spacing = \"0.25 mm\"",
        "spacing = \"1e-9 m\"",
        &["[texture.synth] spacing", "[1e-7, 1e3] m"],
    );
    refusal(
        TEXTURE_ROLLING,
        "nx = 2000 ",
        "nx = 1 ",
        &["[texture.synth] nx, ny", "at least 2 × 2 points"],
    );
}

#[test]
fn threads_far_above_the_machines_parallelism_are_refused() {
    refusal(
        SMALL_ROLLING,
        "threads = 1",
        "threads = 100000",
        &["[rolling] threads", "cores"],
    );
}

#[test]
fn a_tolerance_that_misses_the_load_is_refused() {
    refusal(
        PAPER,
        "[material]",
        "[solver]\ntolerance = 1e3\n\n[material]",
        &["[solver] tolerance", "[1e-15, 1e-3]"],
    );
}

#[test]
fn loads_speeds_and_forces_out_of_any_physical_range_are_refused() {
    refusal(
        PAPER,
        "\"500 N\"",
        "\"1e30 N\"",
        &["[static] loads[3]", "N"],
    );
    // Not a contact either, and once printed with 300 digits.
    let tiny = refusal(
        PAPER,
        "\"500 N\"",
        "\"1e-300 N\"",
        &["[static] loads[3]", "[1e-9, 1e7] N"],
    );
    assert!(tiny.len() < 200, "{tiny}");
    refusal(
        SMALL_ROLLING,
        "speed = \"50 km/h\"",
        "speed = \"1e30 m/s\"",
        &["[rolling] speed", "5e2] m/s"],
    );
    refusal(
        TEXTURE_ROLLING,
        "reference_force = \"1 N\"",
        "reference_force = \"1e-300 N\"",
        &["[rolling] reference_force", "1e-12"],
    );
    refusal(
        SMALL_ROLLING,
        "load = \"30 N\"",
        "tread_height = \"-1 mm\"",
        &["[rolling.control] tread_height"],
    );
}

#[test]
fn a_step_that_overflows_or_allocates_without_bound_is_refused() {
    for step in ["1e-300 m", "0.001 um", "0 m", "-1 mm"] {
        refusal(
            SMALL_ROLLING,
            "step = \"1 mm\"",
            &format!("step = \"{step}\""),
            &["[rolling] step"],
        );
    }
}

/// A path too short for its spectra used to roll (and calibrate) every
/// step and only then fail in the spectrum (found by a probe of bad inputs).
#[test]
fn a_path_too_short_for_its_spectra_is_refused_before_it_rolls() {
    for end in ["40 mm", "41 mm", "42 mm"] {
        refusal(
            SMALL_ROLLING,
            "end = \"79 mm\"",
            &format!("end = \"{end}\""),
            &["[rolling] end", "at least 4 steps"],
        );
    }
    // Four steps (start, start + 3 step) roll.
    let four = SMALL_ROLLING.replacen("end = \"79 mm\"", "end = \"43 mm\"", 1);
    assert!(Scenario::parse(&four, "four").is_ok());
}

#[test]
fn a_synthetic_road_too_large_to_hold_is_refused() {
    refusal(
        SMALL_ROLLING,
        "density = 85000",
        "density = 85000\nmin_spacing = \"1e-9 m\"",
        &["[rolling.synthetic_road] min_spacing"],
    );
}

#[test]
fn an_output_name_leading_out_of_the_folder_is_refused() {
    for name in ["../x", "/tmp/x", "", "a\\nb", ".hidden"] {
        refusal(
            PAPER,
            "name = \"paper_25_spheres\"",
            &format!("name = \"{name}\""),
            &["`case: name`", "a plain file name"],
        );
    }
}

#[test]
fn duplicate_ids_and_sensor_names_are_refused() {
    refusal(PAPER, "id = 2\n", "id = 1\n", &["#2 id", "#1 has it too"]);
    // Regression (adversarial run, 2026-11-30): two summits at one point
    // were named by the solver's 0-based positions, twice. Now by entry
    // and id, once.
    refusal(
        PAPER,
        "id = 2\nx = \"10 mm\"",
        "id = 2\nx = \"20 mm\"",
        &[
            "[[asperity]] #1 (id 1) and #2 (id 2) lie at the same point",
            "merge them or move one",
        ],
    );
    refusal(
        TEXTURE_ROLLING,
        "name = \"shoulder\"",
        "name = \"centre\"",
        &["[[rolling.sensor]] #2 name", "no other sensor"],
    );
}

#[test]
fn sections_a_rolling_run_would_ignore_are_refused() {
    refusal(
        SMALL_ROLLING,
        "\n[rolling]\n",
        "\n[static]\nloads = [\"1 N\"]\n\n[rolling]\n",
        &["[static]", "absent in a rolling scenario"],
    );
    refusal(
        SMALL_ROLLING,
        "\n[rolling]\n",
        "\n[default_shape]\nkind = \"sphere\"\nradius = \"5 mm\"\n\n[rolling]\n",
        &["[default_shape]", "absent unless [[asperity]]"],
    );
    refusal(
        SMALL_ROLLING,
        "\n[rolling]\n",
        "\n[solver]\ntolerance = 1e-9\n\n[rolling]\ntolerance = 1e-9\n",
        &["[rolling] tolerance", "one of the two"],
    );
}

#[test]
fn a_negative_texture_threshold_is_refused() {
    refusal(
        TEXTURE_ROLLING,
        "min_prominence = \"0.1 mm\"",
        "min_prominence = \"-0.1 mm\"",
        &["[texture] min_prominence"],
    );
}

/// Regression (adversarial run, 2026-11-29): `chunks` equal to the path's
/// steps was refused when `(end − start) / step` rounded a hair under the
/// count (25 to 45 mm by 2 mm: 11 steps, the ratio 10.999999999999998).
#[test]
fn chunks_up_to_the_path_s_own_step_count_are_accepted() {
    let path = "start = \"25 mm\"\nend = \"45 mm\"\nstep = \"2 mm\"";
    let base = SMALL_ROLLING.replacen(
        "start = \"40 mm\"\nend = \"79 mm\"\nstep = \"1 mm\"",
        path,
        1,
    );
    assert!(base.contains(path), "the fixture's path lines moved");
    let with = |k: usize| base.replacen(path, &format!("{path}\nchunks = {k}"), 1);
    assert!(Scenario::parse(&with(11), "eleven").is_ok());
    refusal(
        &with(11),
        "chunks = 11",
        "chunks = 12",
        &["[rolling] chunks", "1 to the 11 steps"],
    );
}

/// Regression (adversarial run, 2026-11-29): `cargo xtask rolling-bem
/// --fidelity wilke --calibrate-under tread` ran, ignoring the option,
/// where the same keys in a scenario are refused. A runner that sets
/// `[model]` after the parse checks it again with `Scenario::check_model`.
#[test]
fn model_keys_set_after_the_parse_are_checked_as_the_parse_checks_them() {
    let mut scenario = Scenario::parse(TEXTURE_ROLLING, "dense").expect("the fixture parses");
    scenario.model.calibrate_under = Some("tread".into());
    assert!(
        scenario.check_model().is_ok(),
        "calibrated (the default) takes tread"
    );
    scenario.model.fidelity = Some("wilke".into());
    let message = scenario
        .check_model()
        .expect_err("wilke under the tread")
        .to_string();
    assert!(message.contains("[model] calibrate_under"), "{message}");
    scenario.model.calibrate_under = None;
    scenario.model.fidelity = Some("clustered".into());
    let message = scenario
        .check_model()
        .expect_err("clustered in rolling")
        .to_string();
    assert!(message.contains("[model] fidelity"), "{message}");
}

/// Regression (adversarial run, 2026-11-29): `distributed` or `clustered`
/// with `[texture] max_cap_width` failed only at the first solve meeting a
/// split plateau, in solver terms. Refused when the scenario is read.
#[test]
fn rungs_that_cannot_couple_tiles_are_refused_with_max_cap_width() {
    let text = "name = \"tiles\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
        [model]\nfidelity = \"distributed\"\n[static]\nloads = [\"5 N\"]\n\
        [texture]\nmin_prominence = \"0.1 mm\"\nmin_area = \"1 mm2\"\nmax_cap_width = \"2 mm\"\n\
        [texture.synth]\nkind = \"porous_asphalt\"\nnx = 100\nny = 100\nspacing = \"0.1 mm\"\nseed = 2006\n";
    for rung in ["distributed", "clustered"] {
        refusal(
            text,
            "fidelity = \"distributed\"",
            &format!("fidelity = \"{rung}\""),
            &["[model] fidelity", "max_cap_width"],
        );
    }
    let calibrated = text.replacen("\"distributed\"", "\"calibrated\"", 1);
    assert!(Scenario::parse(&calibrated, "tiles").is_ok());
}

/// A value of the wrong type inside a table that names its variant in
/// `kind` (`[texture.synth]`, `[rolling.tread]`, a `shape`,
/// `[material.viscoelastic.shift]`) names its key: such tables were read
/// as internally tagged enums, whose buffered reading lost the key ("invalid
/// value: integer `-1`, expected usize" and no more).
#[test]
fn a_wrong_type_inside_a_kind_table_names_its_key() {
    const VISCO: &str = include_str!("../fixtures/rolling_tyre_dense_asphalt_visco.toml");
    let message = |base: &str, from: &str, to: &str| -> String {
        assert!(base.contains(from), "the fixture lacks {from:?}");
        match Scenario::parse(&base.replacen(from, to, 1), "case") {
            Ok(_) => panic!("{to:?} accepted"),
            Err(e) => e.to_string(),
        }
    };
    let cases = [
        (TEXTURE_ROLLING, "nx = 2000", "nx = -1", "in `nx`"),
        (TEXTURE_ROLLING, "nx = 2000", "nx = \"2000\"", "in `nx`"),
        (
            TEXTURE_ROLLING,
            "length = \"120 mm\"",
            "length = true",
            "in `length`",
        ),
        (
            PAPER,
            "id = 7\n",
            "id = 7\nshape = { kind = \"sphere\", radius = true }\n",
            "in `radius`",
        ),
        (
            VISCO,
            "kind = \"wlf\"",
            "kind = \"wlf\"\nc1 = \"many\"",
            "c1",
        ),
    ];
    for (base, from, to, needle) in cases {
        let m = message(base, from, to);
        assert!(m.contains(needle), "{to:?}: {m:?} lacks {needle:?}");
    }
    // Unknown keys and variants are named as before; a missing `kind` is
    // said.
    let m = message(TEXTURE_ROLLING, "nx = 2000", "nx = 2000\nseedd = 3");
    assert!(m.contains("unknown field `seedd`"), "{m}");
    let m = message(
        TEXTURE_ROLLING,
        "kind = \"aggregate\"",
        "kind = \"aggregat\"",
    );
    assert!(m.contains("unknown variant `aggregat`"), "{m}");
    let m = message(TEXTURE_ROLLING, "kind = \"aggregate\"\n", "");
    assert!(m.contains("missing field `kind`"), "{m}");
}
