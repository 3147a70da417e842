//! `cargo xtask torture`: every hard road kind solved statically at three
//! loads and rolled over, with a table of what converged, what fell back and
//! what it cost (issue 14; docs/validation.md keeps the table).
//!
//! The scenarios are written here as TOML text, the way a user would write
//! them, and run through the library (`tyreroad::scenario`): the torture
//! run exercises the same path as `cargo xtask run`.

use std::time::Instant;

use anyhow::Result;
use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};

/// The road kinds of `[texture.synth]` put through the run, with a seed each.
const KINDS: [(&str, u64); 9] = [
    ("aggregate", 2006),
    ("self_affine", 7),
    ("transverse_tining", 14),
    ("longitudinal_tining", 15),
    ("brushed_concrete", 16),
    ("exposed_aggregate", 17),
    ("porous_asphalt", 18),
    ("worn_chip_seal", 19),
    ("pave", 20),
];

/// `[texture.synth]` of a kind on an `nx × ny` grid of `spacing` (text).
fn synth(kind: &str, seed: u64, nx: usize, ny: usize, spacing: &str) -> String {
    let extra = match kind {
        "aggregate" => "grading = \"4/6\"\ncoverage = 1.3\nembedding = [0.6, 0.8]\n",
        "self_affine" => {
            "rms = \"0.4 mm\"\nhurst = 0.7\nlambda_long = \"20 mm\"\nlambda_short = \"0.5 mm\"\n"
        }
        _ => "",
    };
    format!(
        "[texture.synth]\nkind = \"{kind}\"\nnx = {nx}\nny = {ny}\nspacing = \"{spacing}\"\n\
         seed = {seed}\n{extra}"
    )
}

const MATERIAL: &str = "[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n";

/// A flat block on 40 × 40 mm of the kind at 0.1 mm (pavé: 240 mm at 1 mm,
/// to hold whole setts), three loads.
fn static_scenario(kind: &str, seed: u64) -> String {
    let grid = if kind == "pave" {
        synth(kind, seed, 240, 240, "1 mm")
    } else {
        synth(kind, seed, 400, 400, "0.1 mm")
    };
    format!(
        "name = \"torture_{kind}_static\"\n{MATERIAL}\n[static]\nloads = [\"50 N\", \"150 N\", \
         \"300 N\"]\n\n[texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\n{grid}"
    )
}

/// A tyre rolling 200 steps of 1 mm at 50 km/h and 1500 N over 0.35 ×
/// 0.15 m of the kind at 0.25 mm.
fn rolling_scenario(kind: &str, seed: u64) -> String {
    let grid = synth(kind, seed, 1400, 600, "0.25 mm");
    format!(
        "name = \"torture_{kind}_rolling\"\n{MATERIAL}\n[rolling]\nstart = \"70 mm\"\nend = \
         \"269 mm\"\nstep = \"1 mm\"\nspeed = \"50 km/h\"\ncheckpoint = false\n\n\
         [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\nlength = \
         \"120 mm\"\nwidth = \"150 mm\"\n\n[rolling.control]\nload = \"1500 N\"\n\n[texture]\n\
         min_prominence = \"0.1 mm\"\nmin_area = \"1 mm2\"\n\n{grid}"
    )
}

/// One row of the table.
struct Row {
    kind: &'static str,
    asperities: usize,
    loads: String,
    fallbacks: usize,
    static_seconds: f64,
    steps: String,
    /// The rolling run's rung, and with calibrated laws the caps
    /// calibrated, those that kept their Wilke law, and the calibration's
    /// seconds.
    rung: String,
    rolling_seconds: f64,
}

/// Runs the torture table on `only` (or every kind) and prints it
/// (Markdown, for docs/validation.md). Fails (after the whole table) if any
/// load or step failed.
pub fn run(only: Option<&str>) -> Result<()> {
    if let Some(k) = only
        && !KINDS.iter().any(|(kind, _)| *kind == k)
    {
        let known: Vec<&str> = KINDS.iter().map(|(kind, _)| *kind).collect();
        anyhow::bail!("unknown road kind `{k}` (known: {})", known.join(", "));
    }
    let mut rows = Vec::new();
    let mut failures = 0;
    for (kind, seed) in KINDS
        .into_iter()
        .filter(|(k, _)| only.is_none_or(|o| o == *k))
    {
        eprintln!("torture: {kind} ...");
        let base = RunOptions::new(".");
        let t = Instant::now();
        let (asperities, loads, fallbacks) =
            match Scenario::parse(&static_scenario(kind, seed), kind)?.run(&base) {
                Ok(ScenarioResult::Texture(r)) => {
                    let converged = r.statics.runs.len();
                    let failed = r.statics.failed_loads.len();
                    if failed > 0 {
                        failures += 1;
                    }
                    let fallbacks = r
                        .loads
                        .iter()
                        .map(|l| l.two_scale.fallbacks().count())
                        .sum();
                    (
                        r.texture.asperities,
                        format!("{converged}/{}", converged + failed),
                        fallbacks,
                    )
                }
                Ok(_) => (0, "?".into(), 0),
                Err(e) => {
                    failures += 1;
                    eprintln!("  static: {e}");
                    (0, "failed".into(), 0)
                }
            };
        let static_seconds = t.elapsed().as_secs_f64();
        let t = Instant::now();
        let rolling = Scenario::parse(&rolling_scenario(kind, seed), kind)?;
        let mut rung = rolling.fidelity()?.to_string();
        let steps = match rolling.run(&base) {
            Ok(ScenarioResult::Rolling(run)) => {
                if let tyreroad::scenario::RoadSummary::Texture(t) = &run.road
                    && let Some(cal) = &t.calibration
                {
                    rung += &format!(
                        ": {} caps, {} on Wilke, {:.1} s",
                        cal.asperities,
                        cal.fallbacks.len(),
                        cal.time.as_secs_f64()
                    );
                    if cal.deepened > 0 {
                        rung += &format!(", run repeated with {} caps deepened", cal.deepened);
                    }
                    if cal.past_tables.contacts > 0 {
                        rung +=
                            &format!(", {} contacts past their tables", cal.past_tables.contacts);
                    }
                }
                let [converged, stagnated, failed] = run.result.status_counts();
                if failed > 0 {
                    failures += 1;
                }
                let total = run.result.steps.len();
                let mut cell = format!("{converged}/{total}");
                if stagnated > 0 {
                    cell += &format!(" ({stagnated} stagnated)");
                }
                let clustered = run
                    .result
                    .steps
                    .iter()
                    .filter(|s| s.recovery == tyreroad::rolling::Recovery::Clustered)
                    .count();
                if clustered > 0 {
                    cell += &format!(" ({clustered} by clusters)");
                }
                if failed > 0 {
                    cell += &format!(" ({failed} failed)");
                }
                cell
            }
            Ok(_) => "?".into(),
            Err(e) => {
                failures += 1;
                eprintln!("  rolling: {e}");
                "failed".into()
            }
        };
        rows.push(Row {
            kind,
            asperities,
            loads,
            fallbacks,
            static_seconds,
            steps,
            rung,
            rolling_seconds: t.elapsed().as_secs_f64(),
        });
    }
    say!(
        "| road kind | asperities (static) | loads converged | two-scale fallbacks | static s | \
         rolling steps converged | rolling rung (calibration) | rolling s |"
    );
    say!("|---|---:|---:|---:|---:|---:|---|---:|");
    for r in &rows {
        say!(
            "| {} | {} | {} | {} | {:.1} | {} | {} | {:.1} |",
            r.kind,
            r.asperities,
            r.loads,
            r.fallbacks,
            r.static_seconds,
            r.steps,
            r.rung,
            r.rolling_seconds
        );
    }
    if failures > 0 {
        anyhow::bail!("{failures} runs had a failed load or step");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_torture_scenario_parses_and_passes_the_checks() {
        for (kind, seed) in KINDS {
            assert!(
                Scenario::parse(&static_scenario(kind, seed), kind).is_ok(),
                "{kind}"
            );
            assert!(
                Scenario::parse(&rolling_scenario(kind, seed), kind).is_ok(),
                "{kind}"
            );
        }
    }
}
