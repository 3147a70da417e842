//! Calibrated laws in viscoelastic rolling (`[model] fidelity =
//! "calibrated"` with `[material.viscoelastic]`, docs/viscoelastic.md,
//! "Calibrated laws in viscoelastic rolling"): each cap's hereditary law
//! takes its calibrated elastic law's shape, so very slow rolling is the
//! calibrated elastic run with `E∞` and very fast rolling the one with
//! `E∞ + Σ E_k`, to 0.5 %; and the laws are the calibrated ones, not
//! Wilke's.
#![allow(clippy::unwrap_used)]

use tyreroad::scenario::{RoadSummary, RunOptions, Scenario, ScenarioResult, ViscoCase};

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// A 20 × 16 mm block over a 30 × 20 mm aggregate texture (4/6 chippings,
/// 0.2 mm cells) for eight steps of 0.5 mm, at 5 N, with `material`.
fn scenario(fidelity: &str, material: &str) -> Result<Scenario, Box<dyn std::error::Error>> {
    let text = format!(
        "name = \"vc\"\n{material}\n\
         [model]\nfidelity = \"{fidelity}\"\n\
         [rolling]\nstart = \"13 mm\"\nend = \"16.5 mm\"\nstep = \"0.5 mm\"\nspeed = \"10 m/s\"\n\
         checkpoint = false\nthreads = 1\n\
         [rolling.tread]\nkind = \"block\"\nlength = \"20 mm\"\nwidth = \"16 mm\"\n\
         [rolling.control]\nload = \"5 N\"\n\
         [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
         [texture.synth]\nkind = \"aggregate\"\nnx = 150\nny = 100\nspacing = \"0.2 mm\"\n\
         grading = \"4/6\"\nseed = 2006\n"
    );
    Ok(Scenario::parse(&text, fidelity)?)
}

/// `[material]` at 6.54 MPa (the Wilke laws' modulus) with the test tread:
/// `E∞` = 2 MPa, branches 3 MPa at 1 ms and 5 MPa at 20 µs.
const VISCO: &str = "[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
     [material.viscoelastic]\nlong_term = \"2 MPa\"\n\
     [[material.viscoelastic.branch]]\nmodulus = \"3 MPa\"\nrelaxation_time = \"1 ms\"\n\
     [[material.viscoelastic.branch]]\nmodulus = \"5 MPa\"\nrelaxation_time = \"20 us\"\n";

fn elastic(modulus: &str) -> String {
    format!("[material]\nyoungs_modulus = \"{modulus}\"\npoisson_ratio = 0.5\n")
}

/// Per-step approaches of the viscoelastic run at `speed` (m/s).
fn visco_approaches(fidelity: &str, speed: f64) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    let s = scenario(fidelity, VISCO)?;
    let case = ViscoCase {
        speed: Some(speed),
        temperature: None,
    };
    let run = s
        .roll_viscoelastic(&RunOptions::new("."), &[case])?
        .pop()
        .ok_or("no run")??;
    if fidelity == "calibrated" {
        let RoadSummary::Texture(summary) = &run.road else {
            return Err("not a texture road".into());
        };
        assert!(summary.calibration.is_some(), "the road was not calibrated");
    }
    assert_eq!(
        run.status_counts()[2],
        0,
        "{fidelity} at {speed} m/s: failed steps"
    );
    Ok(run.result.steps.iter().map(|s| s.approach).collect())
}

fn elastic_approaches(modulus: &str) -> Result<Vec<f64>, Box<dyn std::error::Error>> {
    let s = scenario("calibrated", &elastic(modulus))?;
    let ScenarioResult::Rolling(run) = s.run(&RunOptions::new("."))? else {
        return Err("not a rolling result".into());
    };
    assert_eq!(run.status_counts()[2], 0, "{modulus}: failed steps");
    Ok(run.result.steps.iter().map(|s| s.approach).collect())
}

fn worst(a: &[f64], b: &[f64]) -> f64 {
    assert_eq!(a.len(), b.len());
    a.iter()
        .zip(b)
        .map(|(x, y)| (x / y - 1.0).abs())
        .fold(0.0, f64::max)
}

#[test]
fn calibrated_viscoelastic_rolling_is_the_calibrated_elastic_run_at_either_limit() -> TestResult {
    // 1e-6 m/s: a step lasts 500 s, every branch relaxes (E∞); 1e6 m/s: a
    // step lasts 0.5 ns, none does (E∞ + Σ E_k).
    let slow = visco_approaches("calibrated", 1e-6)?;
    let fast = visco_approaches("calibrated", 1e6)?;
    assert_eq!(slow.len(), 8);
    let (slow_error, fast_error) = (
        worst(&slow, &elastic_approaches("2 MPa")?),
        worst(&fast, &elastic_approaches("10 MPa")?),
    );
    eprintln!("slow {slow_error:.2e}, fast {fast_error:.2e}");
    assert!(slow_error < 5e-3, "slow limit off by {slow_error}");
    assert!(fast_error < 5e-3, "fast limit off by {fast_error}");
    // The limits are apart, so either check can fail.
    assert!(worst(&slow, &fast) > 0.1);
    // The laws are the calibrated ones: the Wilke road sinks otherwise
    // (elastically 2.4 % apart on this texture).
    let wilke = visco_approaches("wilke", 1e-6)?;
    assert!(worst(&slow, &wilke) > 1e-3, "calibrated = Wilke");
    Ok(())
}
