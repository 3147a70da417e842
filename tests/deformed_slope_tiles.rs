//! The deformed tread's slopes settle on a road of flat tiles: a porous
//! asphalt's plateaus split into 5 mm tiles, a fraction of a millimetre
//! apart, under a tyre at 1500 N with `contact_slope = "deformed"`. A tile
//! touching at its first contact has a patch of finite size, and the
//! slope kernel's floor jumped with it; the plain slope update cycled
//! between two tiles loaded in turn. Every step failed there before the
//! floor was made continuous and the slopes mixed (docs/validation.md,
//! "The deformed slope's cycle on tiles"). The coupled steps on such tiles
//! settle too: with the slopes held where their rounds end, and with
//! Aitken's damping after the halving ("Slopes held where their rounds
//! end").

use tyreroad::rolling::{Recovery, StepRecord, StepStatus};
use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};

type TestResult = Result<(), Box<dyn std::error::Error>>;

use crate::common::{TILED_LOAD as LOAD, tiled_road, under_tread};

fn tiles_scenario(slope: &str) -> String {
    tiled_road("porous_asphalt", 520, ("64 mm", "67 mm"), "wilke", slope)
}

/// The steps of the rolling scenario `text`, its outputs under `out`.
fn rolled(
    text: &str,
    out: &std::path::Path,
) -> Result<Vec<StepRecord>, Box<dyn std::error::Error>> {
    let s = Scenario::parse(text, "tiles")?;
    let ScenarioResult::Rolling(run) = s.run(&RunOptions::new(out))? else {
        return Err("not a rolling result".into());
    };
    Ok(run.result.steps)
}

/// `step` carries the load to 1e-6 and its approach lies within `within`
/// of the yardstick's (the same step of another run, converged), apart
/// from it when `apart`.
fn assert_beside(step: &StepRecord, yardstick: &StepRecord, within: f64, apart: bool) {
    assert_eq!(
        yardstick.status,
        StepStatus::Converged,
        "step {}",
        step.index
    );
    assert!(
        (step.total_force - LOAD).abs() < 1e-6 * LOAD,
        "step {} carries {} N",
        step.index,
        step.total_force
    );
    let gap = (step.approach - yardstick.approach).abs() / yardstick.approach;
    assert!(
        gap < within && (!apart || gap > 1e-6),
        "step {}: {} against {}",
        step.index,
        step.approach,
        yardstick.approach
    );
}

#[test]
fn deformed_slopes_on_split_plateaus_settle_at_every_step() -> TestResult {
    let dir = tempfile::tempdir()?;
    let mut approaches = Vec::new();
    for slope in ["profile", "deformed"] {
        let steps = &rolled(&tiles_scenario(slope), dir.path())?;
        assert_eq!(steps.len(), 4, "{slope}");
        for step in steps {
            assert_ne!(
                step.status,
                StepStatus::Failed,
                "{slope}: step {}",
                step.index
            );
            // Kept only within the coupled steps' acceptance: no force
            // moved by more than 1e-5 of the load in the last round.
            if step.status == StepStatus::Stagnated {
                assert!(step.residual <= 1e-5, "{slope}: {}", step.residual);
            }
            assert!(
                (step.total_force - LOAD).abs() < 1e-6 * LOAD,
                "{slope}: step {} carries {} N",
                step.index,
                step.total_force
            );
        }
        approaches.push(steps.iter().map(|s| s.approach).collect::<Vec<_>>());
    }
    // The deformed tread flattens the footprint: another approach, but
    // close to the profile's (measured 2–3 % apart; held within 10 %).
    for (p, d) in approaches[0].iter().zip(&approaches[1]) {
        assert!(p.is_finite() && d.is_finite() && *p > 0.0);
        assert!((p - d).abs() < 0.1 * p, "profile {p} vs deformed {d}");
        assert!((p - d).abs() > 1e-6 * p, "the slope changed nothing: {p}");
    }
    Ok(())
}

/// The exposed aggregate's 5 mm tiles (the chip-seal fixture's grid) from
/// x = 113 mm: cold, the Wilke steps under the deformed slope do not settle
/// (unloaded tiles beside a loaded one swing in and out of contact), and a
/// calibrated run refused itself because those steps size its tables. The
/// bound now falls back to the profile's Wilke steps, and the calibrated
/// run rolls every step under the deformed slope (docs/validation.md,
/// "The exposed aggregate with 5 mm tiles").
#[test]
fn a_calibrated_run_sizes_its_tables_where_the_deformed_wilke_steps_fail() -> TestResult {
    let dir = tempfile::tempdir()?;
    let run = |fidelity: &str, slope: &str| -> Result<_, Box<dyn std::error::Error>> {
        let road = tiled_road(
            "exposed_aggregate",
            1200,
            ("113 mm", "116 mm"),
            fidelity,
            slope,
        );
        rolled(&road, dir.path())
    };
    // What the bound meets: cold, no Wilke step's deformed slopes settle
    // (every step failed so). Each is now solved again under the profile's
    // slope and kept, marked: it is the profile's run's step, the slopes'
    // last move its residual.
    let wilke = run("wilke", "deformed")?;
    // The yardstick: the same steps under the profile's slope, which settle.
    let profile = run("wilke", "profile")?;
    assert_eq!((wilke.len(), profile.len()), (4, 4));
    for (step, yardstick) in wilke.iter().zip(&profile) {
        assert_eq!(
            (step.status, step.recovery),
            (StepStatus::Stagnated, Recovery::ProfileSlope),
            "step {}",
            step.index
        );
        assert!(
            step.residual > 1e-5 && step.residual.is_finite(),
            "{}",
            step.residual
        );
        // Solved after a failed attempt, from the same warm start as the
        // profile's run: the same solution to the solver's tolerance.
        assert_eq!(
            step.contact_ids, yardstick.contact_ids,
            "step {}",
            step.index
        );
        assert_beside(step, yardstick, 1e-9, false);
    }
    let calibrated = run("calibrated", "deformed")?;
    assert_eq!((calibrated.len(), profile.len()), (4, 4));
    for (step, yardstick) in calibrated.iter().zip(&profile) {
        assert_eq!(step.status, StepStatus::Converged, "step {}", step.index);
        // Measured 1.6-1.8 % deeper than the profile's Wilke approach
        // (5.28-5.29 against 5.19-5.20 mm); held within 5 %.
        assert_beside(step, yardstick, 0.05, false);
    }
    Ok(())
}

/// The porous asphalt's first steps under `calibrated_fields` with the
/// deformed slope and caps calibrated under the tread: the slopes' rounds
/// end with forces still moving by 2e-5 to 7e-5 of the load (contacts at
/// the tiles' edges turning on and off), and every one of these steps
/// failed. With the slopes held where their rounds ended, the field
/// coupling settles; the step is kept, marked stagnated at that change
/// (docs/validation.md, "Slopes held where their rounds end").
#[test]
fn slopes_that_do_not_settle_are_held_where_their_rounds_end() -> TestResult {
    let dir = tempfile::tempdir()?;
    let run = |slope: &str| -> Result<_, Box<dyn std::error::Error>> {
        let road = under_tread(&tiled_road(
            "porous_asphalt",
            1200,
            ("65 mm", "68 mm"),
            "calibrated_fields",
            slope,
        ));
        rolled(&road, dir.path())
    };
    let deformed = run("deformed")?;
    let profile = run("profile")?;
    assert_eq!((deformed.len(), profile.len()), (4, 4));
    let mut held = 0;
    for (step, yardstick) in deformed.iter().zip(&profile) {
        assert_ne!(step.status, StepStatus::Failed, "step {}", step.index);
        if step.status == StepStatus::Stagnated {
            assert!(
                step.residual <= 1e-2,
                "step {}: {}",
                step.index,
                step.residual
            );
            // Past the fixed point's own acceptance (1e-5): held.
            held += usize::from(step.residual > 1e-5);
        }
        // Measured 0.45 % shallower than the profile's (3.857-3.866
        // against 3.874-3.885 mm; the BEM's 3.810-3.819 mm); held within
        // 2 %, and apart.
        assert_beside(step, yardstick, 0.02, true);
    }
    assert!(held > 0, "no step was held: {deformed:?}");
    Ok(())
}

/// The exposed aggregate's 4 mm tiles under `calibrated_fields` (caps
/// under the tread, the profile's slope) from x = 88 mm: at each step one
/// contact coming in draws load from its neighbours round after round, each
/// change 0.97 of the last, while the halving damping sits at its floor of
/// 1/16; every step failed after its rounds at 1e-5 to 9e-5 of the load.
/// The same fixed point now goes on under Aitken's damping, and settles
/// (docs/rolling.md, "Coupled steps").
#[test]
fn a_contact_drawing_load_round_after_round_settles_under_aitkens_damping() -> TestResult {
    let dir = tempfile::tempdir()?;
    let run = |fidelity: &str| -> Result<_, Box<dyn std::error::Error>> {
        let road = under_tread(&tiled_road(
            "exposed_aggregate",
            1200,
            ("88 mm", "95 mm"),
            fidelity,
            "profile",
        ))
        .replace("max_cap_width = \"5 mm\"", "max_cap_width = \"4 mm\"");
        rolled(&road, dir.path())
    };
    let fields = run("calibrated_fields")?;
    // The yardstick: the point-coupled rung, no fixed point to settle.
    let point = run("calibrated")?;
    assert_eq!((fields.len(), point.len()), (8, 8));
    for (step, yardstick) in fields.iter().zip(&point) {
        assert_eq!(step.status, StepStatus::Converged, "step {}", step.index);
        // Measured 0.22–0.48 % deeper than the point coupling's (the BEM's
        // 5.289–5.312 mm against these 5.311–5.317); held within 1 %.
        assert_beside(step, yardstick, 0.01, true);
    }
    Ok(())
}
