//! `[static.history]` read, run and written, against the elastic static
//! run (slow loading is the elastic solution with `E∞`).

use super::*;
use crate::scenario::{Scenario, run_static};
use tyreroad_viscoelastic::{Branch, Receding};

/// Three spheres at 12 mm pitch with summits 0, −20 and −40 µm.
fn scenario(modulus: &str, history: &str) -> String {
    let mut text = format!(
        "name = \"history\"\n\n[material]\nyoungs_modulus = \"{modulus}\"\npoisson_ratio = 0.5\n\n\
         [default_shape]\nkind = \"sphere\"\nradius = \"5 mm\"\n\n{history}\n"
    );
    for (k, h) in ["0 um", "-20 um", "-40 um"].iter().enumerate() {
        text.push_str(&format!(
            "[[asperity]]\nid = {}\nx = \"{} mm\"\ny = \"0 mm\"\nheight = \"{h}\"\n\n",
            k + 1,
            12 * k
        ));
    }
    text
}

/// Ramp to 20 N, hold, unload to 12 N, each segment `duration` long.
fn history(duration: &str) -> String {
    format!(
        "[static.history]\nsteps = 8\n\n\
         [[static.history.segment]]\nduration = \"{duration}\"\nload = \"20 N\"\n\n\
         [[static.history.segment]]\nduration = \"{duration}\"\nload = \"20 N\"\n\n\
         [[static.history.segment]]\nduration = \"{duration}\"\nload = \"12 N\"\nsteps = 4\n"
    )
}

fn tread() -> Prony {
    Prony::new(
        2e6,
        vec![
            Branch {
                modulus: 3e6,
                relaxation_time: 1e-3,
            },
            Branch {
                modulus: 5e6,
                relaxation_time: 2e-5,
            },
        ],
        0.5,
    )
    .expect("valid tread")
}

#[test]
fn segments_become_samples_with_their_units() {
    let s = Scenario::parse(&scenario("6 MPa", &history("2 ms")), "test").expect("parses");
    let samples = s
        .static_case
        .as_ref()
        .and_then(|c| c.history.as_ref())
        .expect("history")
        .samples()
        .expect("samples");
    assert_eq!(samples.len(), 8 + 8 + 4);
    let close = |a: f64, b: f64| (a - b).abs() < 1e-12 * b.abs().max(1.0);
    assert!(close(samples[0].0, 0.25e-3) && close(samples[0].1, 2.5));
    assert!(close(samples[7].0, 2e-3) && close(samples[7].1, 20.0));
    assert!(close(samples[15].1, 20.0));
    assert!(close(samples[19].0, 6e-3) && close(samples[19].1, 12.0));
}

#[test]
fn slow_loading_gives_the_elastic_static_solution_with_the_long_term_modulus() {
    // Segments of 100 s against τ ≤ 1 ms: fully relaxed at every step.
    let visco = Scenario::parse(&scenario("6 MPa", &history("100 s")), "visco").expect("parses");
    let result = run_load_history_scenario(&visco, Some(&tread())).expect("history runs");
    assert!(result.failure.is_none());
    assert_eq!(result.steps.len(), 20);
    // The elastic reference at the same loads, with E = E∞ = 2 MPa.
    let loads: Vec<String> = result
        .steps
        .iter()
        .map(|s| format!("\"{} N\"", s.load))
        .collect();
    let elastic = Scenario::parse(
        &scenario(
            "2 MPa",
            &format!("[static]\nloads = [{}]\n", loads.join(", ")),
        ),
        "elastic",
    )
    .expect("parses");
    let reference = run_static(&elastic).expect("elastic run");
    for (step, run) in result.steps.iter().zip(&reference.runs) {
        let error = (step.approach - run.approach).abs() / run.approach;
        assert!(error < 0.005, "t = {}: approach {error}", step.time);
        let rows = reference.at_load(run.load);
        for (force, row) in step.forces.iter().zip(rows) {
            assert!(
                (force - row.force).abs() < 0.005 * step.load,
                "t = {}: {force} vs {}",
                step.time,
                row.force
            );
        }
    }
}

#[test]
fn a_fast_history_creeps_during_the_hold_and_unloads_with_hysteresis() {
    let s = Scenario::parse(&scenario("6 MPa", &history("2 ms")), "test").expect("parses");
    let result = run_load_history_scenario(&s, Some(&tread())).expect("history runs");
    assert!(result.failure.is_none(), "{:?}", result.failure);
    let steps = &result.steps;
    // Load carried at every step.
    for s in steps {
        let total: f64 = s.forces.iter().sum();
        assert!(
            (total - s.load).abs() < 1e-6 * s.load,
            "{total} vs {}",
            s.load
        );
    }
    // Creep: the approach grows during the hold at 20 N.
    assert!(steps[15].approach > 1.05 * steps[7].approach);
    // Hysteresis: at 12.5 N the approach on the way down exceeds the one
    // on the way up (step 4 of the ramp: 12.5 N; unloading passes 12 N).
    let up = steps[4].approach;
    assert!((steps[4].load - 12.5).abs() < 1e-12);
    assert!(steps[19].approach > up, "{} vs {up}", steps[19].approach);
    // The CSV: one row per step and asperity.
    let dir = std::env::temp_dir().join(format!("tyreroad_history_{}", std::process::id()));
    let mut set = OutputSet::new(&dir).expect("output dir");
    write_history_csv(&result, &mut set).expect("csv");
    set.commit().expect("commit");
    let text = std::fs::read_to_string(dir.join("history.csv")).expect("read");
    let _ = std::fs::remove_dir_all(&dir);
    let mut lines = text.lines();
    assert_eq!(
        lines.next(),
        Some("time_s,load_n,approach_m,receding,id,force_n")
    );
    assert_eq!(lines.count(), 20 * 3);
}

#[test]
fn an_elastic_tread_and_bad_segments_are_refused_by_name() {
    let s = Scenario::parse(&scenario("6 MPa", &history("2 ms")), "test").expect("parses");
    for error in [
        run_load_history_scenario(&s, None).expect_err("elastic"),
        s.run(&crate::scenario::RunOptions::new("."))
            .expect_err("elastic"),
    ] {
        assert!(
            matches!(&error, ScenarioError::Value { key, .. } if key == "test: [material]"),
            "{error}"
        );
    }
    let bad = history("0 ms");
    let error = Scenario::parse(&scenario("6 MPa", &bad), "test").expect_err("zero duration");
    assert!(
        error
            .to_string()
            .contains("[[static.history.segment]] 1 duration"),
        "{error}"
    );
    let error = Scenario::parse(&scenario("6 MPa", "[static.history]\nsteps = 3\n"), "test")
        .expect_err("no segment");
    assert!(error.to_string().contains("segment"), "{error}");
}

/// `Scenario::run` on a `[static.history]` takes the scenario's own
/// `[material.viscoelastic]` tread: the same steps as the explicit call
/// with that series, to 1e-12 relative (the series is rebuilt from the
/// file's units, so the last bit may differ).
#[test]
fn a_history_with_a_viscoelastic_material_runs_from_the_scenario() {
    let tread_section = "[material.viscoelastic]\nlong_term = \"2 MPa\"\n\n\
        [[material.viscoelastic.branch]]\nmodulus = \"3 MPa\"\nrelaxation_time = \"1 ms\"\n\n\
        [[material.viscoelastic.branch]]\nmodulus = \"5 MPa\"\nrelaxation_time = \"20 us\"\n";
    let text = scenario("6 MPa", &history("2 ms")).replacen(
        "[default_shape]",
        &format!("{tread_section}\n[default_shape]"),
        1,
    );
    let s = Scenario::parse(&text, "test").expect("parses");
    let from_run = match s.run(&crate::scenario::RunOptions::new(".")).expect("runs") {
        crate::scenario::ScenarioResult::History(r) => r,
        _ => panic!("not a history run"),
    };
    let explicit = run_load_history_scenario(&s, Some(&tread())).expect("runs");
    assert!(from_run.failure.is_none());
    assert_eq!(from_run.steps.len(), explicit.steps.len());
    let close = |a: f64, b: f64| (a - b).abs() <= 1e-12 * a.abs().max(b.abs());
    for (a, b) in from_run.steps.iter().zip(&explicit.steps) {
        assert!(
            close(a.approach, b.approach) && a.load == b.load,
            "{a:?} vs {b:?}"
        );
        assert!(a.forces.iter().zip(&b.forces).all(|(x, y)| close(*x, *y)));
    }
    assert_eq!(from_run.steps.len(), 20);
}

/// `[static.history] receding` selects the treatment: unloading the three
/// spheres to 0.4 N (2 % of the peak), Lee–Radok's recursion over-relaxes
/// (a deeper approach than Ting's at the same load), and the keys are
/// checked when the file is read.
#[test]
fn receding_selects_ting_or_lee_radok_and_is_checked() {
    let deep = |receding: &str| {
        let text = history("2 ms").replace("load = \"12 N\"", "load = \"0.4 N\"");
        let text = text.replacen("steps = 8\n", &format!("steps = 8\n{receding}"), 1);
        Scenario::parse(&scenario("6 MPa", &text), "test")
    };
    let history_of = |s: &Scenario| {
        s.static_case
            .as_ref()
            .and_then(|c| c.history.as_ref())
            .expect("history")
            .receding()
            .expect("valid")
    };
    let ting = deep("").expect("parses");
    let lee = deep("receding = \"lee_radok\"\n").expect("parses");
    let fine = deep("receding = \"ting\"\nbands_per_decade = 40\n").expect("parses");
    assert_eq!(history_of(&ting), Receding::Ting { per_decade: 20 });
    assert_eq!(history_of(&lee), Receding::LeeRadok);
    assert_eq!(history_of(&fine), Receding::Ting { per_decade: 40 });
    let end = |s: &Scenario| {
        let r = run_load_history_scenario(s, Some(&tread())).expect("runs");
        assert!(r.failure.is_none(), "{:?}", r.failure);
        r.steps.last().expect("steps").approach
    };
    let (t, l, f) = (end(&ting), end(&lee), end(&fine));
    assert!(l > 1.02 * t, "Lee–Radok {l} vs Ting {t}");
    assert!((f - t).abs() < 0.01 * t, "40 bands {f} vs 20 {t}");
    for bad in [
        "bands_per_decade = 0\n",
        "receding = \"lee_radok\"\nbands_per_decade = 20\n",
    ] {
        let error = deep(bad).expect_err("refused");
        assert!(
            error
                .to_string()
                .contains("[static.history] bands_per_decade"),
            "{error}"
        );
    }
    assert!(deep("receding = \"bergstrom\"\n").is_err());
}
