//! Bad input on the viscoelastic surfaces of a scenario (issue #18
//! hardening, docs/viscoelastic.md "Limits of the input"): each is refused
//! with an error naming the file, the key, the value and the expectation,
//! never a panic, a runaway allocation or a silently wrong run. The cases
//! are those an adversarial run of `cargo xtask` found.

use std::path::PathBuf;

use tyreroad::scenario::{RunOptions, Scenario, ScenarioError, ScenarioResult, ViscoCase};

const ORIGIN: &str = "bad_visco.toml";

fn fixture(name: &str) -> String {
    let path = format!("{}/fixtures/{name}", env!("CARGO_MANIFEST_DIR"));
    std::fs::read_to_string(path).expect("fixture")
}

/// fixtures/rolling_small.toml with `visco` appended to its `[material]`.
fn rolling_with(visco: &str) -> String {
    fixture("rolling_small.toml").replace(
        "poisson_ratio = 0.5\n",
        &format!("poisson_ratio = 0.5\n\n{visco}\n"),
    )
}

const SERIES: &str = "[material.viscoelastic]\nlong_term = \"2 MPa\"\n\n\
    [[material.viscoelastic.branch]]\nmodulus = \"3 MPa\"\nrelaxation_time = \"1 ms\"\n";

/// [`SERIES`] with `keys` added to its `[material.viscoelastic]` table.
fn series_with(keys: &str) -> String {
    SERIES.replace(
        "long_term = \"2 MPa\"\n",
        &format!("long_term = \"2 MPa\"\n{keys}"),
    )
}

const WLF: &str = "[material.viscoelastic.shift]\nkind = \"wlf\"\nc1 = 8.86\nc2 = 101.6\n\
    reference = \"20 °C\"\n";

/// A fitted tread: `master_curve = "mc.csv"` with `per_decade`.
fn fitted(per_decade: usize) -> String {
    rolling_with(&format!(
        "[material.viscoelastic]\nmaster_curve = \"mc.csv\"\nper_decade = {per_decade}\n\
         temperature = \"20 °C\"\n\n{WLF}"
    ))
}

/// fixtures/history_three_spheres.toml with its `[material.viscoelastic]`
/// section (the series) replaced by `tread` (none when empty).
fn history_with_tread(tread: &str) -> String {
    let history = fixture("history_three_spheres.toml");
    let start = history
        .find("\n[material.viscoelastic]\n")
        .expect("section");
    let end = history.find("\n[default_shape]\n").expect("shape");
    format!("{}{tread}{}", &history[..start], &history[end..])
}

/// The error of parsing `text`, as a message.
fn refused(text: &str) -> String {
    match Scenario::parse(text, ORIGIN) {
        Ok(_) => panic!("accepted:\n{text}"),
        Err(e) => e.to_string(),
    }
}

/// A scratch directory of this test process holding `mc.csv` = `csv`.
fn with_curve(tag: &str, csv: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("visco_bad_input_{}_{tag}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("scratch dir");
    std::fs::write(dir.join("mc.csv"), csv).expect("curve");
    dir
}

/// The error of fitting the scenario's master curve `csv`.
fn fit_error(tag: &str, per_decade: usize, csv: &str) -> String {
    let dir = with_curve(tag, csv);
    let scenario = Scenario::parse(&fitted(per_decade), ORIGIN).expect("parses");
    let result = scenario.viscoelastic_material(&dir);
    std::fs::remove_dir_all(&dir).ok();
    match result {
        Ok(_) => panic!("{tag}: fitted"),
        Err(e) => e.to_string(),
    }
}

#[test]
fn a_master_curve_over_600_decades_is_refused_naming_per_decade_and_span() {
    let err = fit_error("span", 3, "f,E1,E2\n1e-300,4e6,1e5\n1e300,5e6,1e5\n");
    assert!(err.starts_with(&format!("scenario {ORIGIN}: ")), "{err}");
    assert!(
        err.contains("per_decade = 3") && err.contains("601 decades") && err.contains("200"),
        "{err}"
    );
}

#[test]
fn per_decade_above_the_cap_is_refused_when_the_file_is_read() {
    for per_decade in [0, 21, 10_000, 1_000_000] {
        let err = refused(&fitted(per_decade));
        assert!(
            err.contains(ORIGIN)
                && err.contains("[material.viscoelastic] per_decade")
                && err.contains(&per_decade.to_string())
                && err.contains("1 to 20"),
            "{per_decade}: {err}"
        );
    }
}

#[test]
fn a_master_curve_with_a_fourth_column_or_a_conflicting_frequency_is_refused() {
    let err = fit_error("cols", 3, "f,|E*|,E1,E2\n1,2e6,2e6,1e5\n10,3e6,3e6,4e5\n");
    assert!(
        err.starts_with(&format!("scenario {ORIGIN}: ")) && err.contains("4 columns found"),
        "{err}"
    );
    let err = fit_error("dup", 3, "f,E1,E2\n1,2e6,1e5\n10,3e6,4e5\n1,9e6,1e5\n");
    assert!(err.contains("lines 2 and 4"), "{err}");
    let err = fit_error("same", 3, "f,E1,E2\n1,2e6,1e5\n1,2e6,1e5\n");
    assert!(err.contains("1 distinct frequencies"), "{err}");
}

#[test]
fn a_runaway_history_step_count_is_refused_when_the_file_is_read() {
    let history = fixture("history_three_spheres.toml");
    assert!(history.contains("steps = 8"), "the fixture changed");
    let err = refused(&history.replace("steps = 8", "steps = 100000000"));
    assert!(
        err.contains(ORIGIN) && err.contains("[static.history] steps") && err.contains("1000000"),
        "{err}"
    );
    // Segments each under the cap, over it together.
    let err = refused(&history.replace("steps = 8", "steps = 400000"));
    assert!(err.contains("over the whole history"), "{err}");
}

#[test]
fn history_loads_and_durations_are_range_checked() {
    let history = fixture("history_three_spheres.toml");
    assert!(history.contains("load = \"20 N\""), "the fixture changed");
    let err = refused(&history.replacen("load = \"20 N\"", "load = \"1e30 N\"", 1));
    assert!(
        err.contains("[[static.history.segment]] 1 load") && err.contains("1e7"),
        "{err}"
    );
    let err = refused(&history.replacen("duration = \"2 ms\"", "duration = \"1e300 s\"", 1));
    assert!(
        err.contains("[[static.history.segment]] 1 duration") && err.contains("1e9"),
        "{err}"
    );
    // Within the range but lost in the rounding of the time before it.
    let err = refused(
        &history
            .replacen("duration = \"2 ms\"", "duration = \"1e9 s\"", 1)
            .replacen("duration = \"2 ms\"", "duration = \"1e-9 s\"", 1),
    );
    assert!(
        err.contains("[[static.history.segment]] 2 duration") && err.contains("advance"),
        "{err}"
    );
}

#[test]
fn static_loads_beside_a_history_are_refused_not_dropped() {
    let history = fixture("history_three_spheres.toml");
    let both = history.replace(
        "[static.history]",
        "[static]\nloads = [\"10 N\"]\n\n[static.history]",
    );
    let err = refused(&both);
    assert!(
        err.contains(ORIGIN) && err.contains("[static] loads") && err.contains("not both"),
        "{err}"
    );
}

#[test]
fn viscoelastic_moduli_and_times_are_range_checked_as_the_elastic_modulus() {
    for (from, to, key) in [
        (
            "long_term = \"2 MPa\"",
            "long_term = \"1e20 Pa\"",
            "long_term",
        ),
        ("long_term = \"2 MPa\"", "long_term = \"1 Pa\"", "long_term"),
        ("modulus = \"3 MPa\"", "modulus = \"-3 MPa\"", "#1 modulus"),
        (
            "relaxation_time = \"1 ms\"",
            "relaxation_time = \"1e300 s\"",
            "relaxation_time",
        ),
        (
            "relaxation_time = \"1 ms\"",
            "relaxation_time = \"0 s\"",
            "relaxation_time",
        ),
    ] {
        let err = refused(&rolling_with(&SERIES.replace(from, to)));
        assert!(err.contains(ORIGIN) && err.contains(key), "{to}: {err}");
    }
    Scenario::parse(&rolling_with(SERIES), ORIGIN).expect("the series itself is fine");
}

#[test]
fn wlf_c2_takes_kelvin_and_names_itself_otherwise() {
    let with_c2 = |c2: &str| {
        rolling_with(&format!(
            "{SERIES}\n{}",
            WLF.replace("c2 = 101.6", &format!("c2 = {c2}"))
        ))
    };
    let plain = Scenario::parse(&with_c2("101.6"), ORIGIN).expect("plain");
    let kelvin = Scenario::parse(&with_c2("\"101.6 K\""), ORIGIN).expect("kelvin");
    let c2 = |s: &Scenario| s.material.viscoelastic.as_ref().and_then(|v| v.shift());
    assert_eq!(c2(&plain), c2(&kelvin));
    let err = refused(&with_c2("\"101.6 °C\""));
    assert!(err.contains("`c2`") && err.contains("101.6 K"), "{err}");
}

#[test]
fn a_temperature_below_the_wlf_pole_is_named_without_float_noise() {
    // The pole is 20 °C − 101.6 K = 191.55 K = −81.6 °C.
    let text = rolling_with(&format!(
        "{}\n{WLF}",
        series_with("temperature = \"-90 °C\"\n")
    ));
    let err = refused(&text);
    assert!(
        err.contains("[material.viscoelastic] temperature")
            && err.contains("183.15 K")
            && err.contains("pole T_ref − C2 = 191.55 K (-81.6 °C)"),
        "{err}"
    );
    assert!(!err.contains("183.1499"), "{err}");
    let unshifted = refused(&rolling_with(&series_with("temperature = \"20 °C\"\n")));
    assert!(
        unshifted.contains("[material.viscoelastic.shift]"),
        "{unshifted}"
    );
}

#[test]
fn a_sweep_case_without_a_speed_or_above_absolute_zero_is_that_case_s_error() {
    let scenario = Scenario::parse(&rolling_with(SERIES), ORIGIN).expect("parses");
    let options = RunOptions::new(env!("CARGO_MANIFEST_DIR"));
    let cases = [
        ViscoCase {
            speed: Some(f64::NAN),
            temperature: None,
        },
        ViscoCase {
            speed: None,
            temperature: Some(-1.0),
        },
    ];
    let runs = scenario
        .roll_viscoelastic(&options, &cases)
        .expect("the road");
    let errors: Vec<String> = runs
        .into_iter()
        .map(|r| r.err().map(|e| e.to_string()).unwrap_or_default())
        .collect();
    assert!(
        errors[0].starts_with(&format!("`{ORIGIN}: sweep speed`")) && errors[0].contains("NaN m/s"),
        "{errors:?}"
    );
    assert!(errors[1].contains("absolute zero"), "{errors:?}");
}

#[test]
fn an_elastic_history_refusal_names_the_file() {
    let elastic = history_with_tread("");
    let scenario = Scenario::parse(&elastic, ORIGIN).expect("parses");
    let err = scenario
        .run(&RunOptions::new(env!("CARGO_MANIFEST_DIR")))
        .expect_err("no tread");
    assert!(matches!(err, ScenarioError::Value { .. }), "{err:?}");
    assert!(
        err.to_string()
            .starts_with(&format!("`{ORIGIN}: [material]")),
        "{err}"
    );
}

#[test]
fn a_rolling_receding_treatment_other_than_lee_radok_or_ting_is_that_run_s_error() {
    let options = RunOptions::new(env!("CARGO_MANIFEST_DIR"));
    let run = |value: &str| {
        let text = rolling_with(&series_with(&format!("receding = \"{value}\"\n")));
        let scenario = Scenario::parse(&text, ORIGIN).expect("parses");
        scenario
            .roll_viscoelastic(&options, &[ViscoCase::default()])
            .expect("the road")
            .remove(0)
    };
    let error = run("bergstrom").expect_err("refused").to_string();
    assert!(
        error.contains("[material.viscoelastic] receding") && error.contains("bergstrom"),
        "{error}"
    );
    // Both treatments run, and differ where patches recede (the approach
    // under load control, the force under approach control).
    let signal = |value: &str| -> Vec<f64> {
        let run = run(value).expect("runs");
        run.result
            .steps
            .iter()
            .map(|s| s.approach + s.total_force)
            .collect()
    };
    let (ting, lee) = (signal("ting"), signal("lee_radok"));
    assert_eq!(ting.len(), lee.len());
    assert!(
        ting.iter()
            .zip(&lee)
            .any(|(t, l)| (t - l).abs() > 1e-9 * l.abs())
    );
}

/// Regressions (second adversarial run, 2026-11-29): a tread at 1e30 K was
/// accepted; above the WLF pole a temperature where a large C1 makes a_T
/// overflow was refused as "below the pole"; `long_term` with no branch
/// rolled as an elastic tread without a word.
#[test]
fn a_temperature_past_any_tread_an_overflowing_shift_and_a_branchless_series_are_named() {
    let hot = refused(&rolling_with(&format!(
        "{}\n{WLF}",
        series_with("temperature = \"1e30 K\"\n")
    )));
    assert!(
        hot.contains("[material.viscoelastic] temperature") && hot.contains("at most 1000 K"),
        "{hot}"
    );
    // −20 °C is above the pole (−81.6 °C); with C1 = 1000, a_T overflows.
    let overflow = refused(&rolling_with(&format!(
        "{}\n{}",
        series_with("temperature = \"-20 °C\"\n"),
        WLF.replace("c1 = 8.86", "c1 = 1000")
    )));
    assert!(
        overflow.contains("shift factor") && !overflow.contains("pole"),
        "{overflow}"
    );
    let branchless = "[material.viscoelastic]\nlong_term = \"2 MPa\"\n";
    let scenario = Scenario::parse(&rolling_with(branchless), ORIGIN).expect("parses");
    let e = scenario
        .viscoelastic_material(std::path::Path::new("."))
        .expect_err("an elastic tread as a viscoelastic one")
        .to_string();
    assert!(
        e.contains("without any [[material.viscoelastic.branch]]"),
        "{e}"
    );
}

/// Regression (adversarial run): a master curve whose storage modulus
/// falls ninefold over two decades was fitted without a word. It is
/// refused, naming both points; a 5 % dip (measurement noise) rolls, and
/// every run says so in its road summary.
#[test]
fn a_storage_modulus_falling_with_frequency_is_refused_and_a_dip_is_warned_of() {
    let err = fit_error("falls", 3, "f,E1,E2\n1,9e6,1e5\n10,5e6,5e5\n100,1e6,1e6\n");
    assert!(err.starts_with(&format!("scenario {ORIGIN}: ")), "{err}");
    assert!(
        err.contains("falls from 9e6 Pa at 1 Hz to 1e6 Pa at 100 Hz (88.8889% lower)")
            && err.contains("over 20%"),
        "{err}"
    );
    let dir = with_curve("dip", "f,E1,E2\n1,2e6,1e5\n10,1.9e6,3e5\n100,4e6,1e6\n");
    let scenario = Scenario::parse(&fitted(3), ORIGIN).expect("parses");
    let runs = scenario
        .roll_viscoelastic(&RunOptions::new(&dir), &[ViscoCase::default()])
        .expect("the road");
    std::fs::remove_dir_all(&dir).ok();
    let run = runs.into_iter().next().expect("a case").expect("rolls");
    let dips: Vec<&String> = run
        .road
        .warnings()
        .iter()
        .filter(|w| w.contains("master curve mc.csv"))
        .collect();
    assert_eq!(dips.len(), 1, "{:?}", run.road.warnings());
    assert!(
        dips[0].contains("falls from 2e6 Pa at 1 Hz to 1.9e6 Pa at 10 Hz (5% lower)"),
        "{}",
        dips[0]
    );
}

/// A static load history on a tread fitted to a master curve whose
/// storage modulus dips (by 5 %) says so as a rolling run does; the dip was
/// warned of only in rolling runs.
#[test]
fn a_load_history_on_a_dipping_master_curve_is_warned_of() {
    let fitted = history_with_tread("\n[material.viscoelastic]\nmaster_curve = \"mc.csv\"\n");
    let scenario = Scenario::parse(&fitted, ORIGIN).expect("parses");
    let dir = with_curve(
        "history_dip",
        "f,E1,E2\n1,2e6,1e5\n10,1.9e6,3e5\n100,4e6,1e6\n",
    );
    let dipped = scenario.run(&RunOptions::new(&dir));
    let even = with_curve(
        "history_even",
        "f,E1,E2\n1,2e6,1e5\n10,2.5e6,3e5\n100,4e6,1e6\n",
    );
    let rising = scenario.run(&RunOptions::new(&even));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::remove_dir_all(&even).ok();
    let warnings = |run: Result<ScenarioResult, ScenarioError>| match run.expect("runs") {
        ScenarioResult::History(r) => {
            assert!(
                r.failure.is_none() && !r.steps.is_empty(),
                "{:?}",
                r.failure
            );
            r.warnings
        }
        _ => panic!("not a history"),
    };
    let dips = warnings(dipped);
    assert_eq!(dips.len(), 1, "{dips:?}");
    assert!(
        dips[0].contains("master curve mc.csv")
            && dips[0].contains("falls from 2e6 Pa at 1 Hz to 1.9e6 Pa at 10 Hz (5% lower)"),
        "{}",
        dips[0]
    );
    // A storage modulus that rises is nothing to say.
    assert_eq!(warnings(rising), Vec::<String>::new());
}

/// Regression (adversarial run): E' = E'' = 1e-3 Pa and 1e300 Pa both
/// failed as "invalid long-term modulus E∞ (Pa): 0". The curve's moduli
/// are read within `[material] youngs_modulus`'s range, the first out of
/// it named by its line, column and value.
#[test]
fn master_curve_moduli_out_of_range_are_named_by_their_row() {
    let err = fit_error("tiny", 3, "f,E1,E2\n1,1e-3,1e-3\n10,2e-3,1e-3\n");
    assert!(err.starts_with(&format!("scenario {ORIGIN}: ")), "{err}");
    assert!(
        err.contains("master curve line 2, column 2 (storage modulus E' (Pa)): 0.001 is out of range (expected within [1000, 1e12] Pa)"),
        "{err}"
    );
    assert!(!err.contains("E∞"), "{err}");
    let err = fit_error("huge", 3, "f,E1,E2\n1,1e300,1e300\n10,1e301,1e300\n");
    assert!(
        err.contains("line 2, column 2 (storage modulus E' (Pa)): 1e300 is out of range"),
        "{err}"
    );
}
