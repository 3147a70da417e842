//! `cargo xtask converge-sweep SCENARIO --loads 500..3000:100 --steps
//! 0.25,0.5,1,2mm`: a rolling scenario on a `[texture]` rolled at every load
//! and step length, and one table of how its steps ended (issue 14: Newton
//! converges everywhere; docs/validation.md keeps the table).
//!
//! The road is built once, on the Wilke laws whatever the scenario's
//! `[model] fidelity` (the sweep measures Newton's convergence on the
//! paper's laws; a calibrated road would be calibrated once per load); each
//! run is the scenario's `[rolling]` with its load and step replaced,
//! rolled on one thread as one warm-started chunk (as `cargo xtask run`
//! with one thread), at the scenario's tolerance.

use std::path::PathBuf;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use clap::Args;
use tyreroad::rolling::{self, Recovery, RollingControl, RunOptions, StepStatus};
use tyreroad::scenario::Scenario;

/// `cargo xtask converge-sweep`'s arguments.
#[derive(Args)]
pub struct ConvergeSweepArgs {
    /// The rolling scenario (TOML) with a `[texture]` road.
    pub scenario: PathBuf,
    /// Loads in newtons, `FIRST..LAST:STEP` (both ends included) or a
    /// comma-separated list.
    #[arg(long, default_value = "500..3000:100")]
    pub loads: String,
    /// Step lengths, a comma-separated list in millimetres (a trailing `mm`
    /// is allowed).
    #[arg(long, default_value = "0.25,0.5,1,2mm")]
    pub steps: String,
}

/// `FIRST..LAST:STEP` or `A,B,C` (newtons).
fn parse_loads(text: &str) -> Result<Vec<f64>> {
    let number = |s: &str| -> Result<f64> {
        let v: f64 = s
            .trim()
            .trim_end_matches('N')
            .trim()
            .parse()
            .with_context(|| format!("--loads: `{s}` is not a number of newtons"))?;
        if !(v.is_finite() && v > 0.0) {
            bail!("--loads: {v} N (expected a finite load > 0)");
        }
        Ok(v)
    };
    // A load within the range a scenario's `[rolling.control] load` takes.
    let load = |s: &str| -> Result<f64> {
        let v = number(s)?;
        let (lo, hi) = (
            tyreroad::scenario::MIN_STATIC_LOAD,
            tyreroad::scenario::LOAD_RANGE[1],
        );
        if !(lo..=hi).contains(&v) {
            bail!("--loads: {v:e} N (expected a load in [{lo:e}, {hi:e}] N)");
        }
        Ok(v)
    };
    if let Some((range, step)) = text.split_once(':') {
        let (first, last) = range
            .split_once("..")
            .with_context(|| format!("--loads `{text}`: expected FIRST..LAST:STEP"))?;
        let (first, last, step) = (load(first)?, load(last)?, number(step)?);
        if last < first || (last - first) / step > 1e4 {
            bail!("--loads `{text}`: expected FIRST ≤ LAST and at most 10⁴ loads");
        }
        let n = ((last - first) / step + 1e-9).floor() as usize;
        return Ok((0..=n).map(|i| first + i as f64 * step).collect());
    }
    text.split(',').map(load).collect()
}

/// `A,B,Cmm` (millimetres) → metres.
fn parse_steps(text: &str) -> Result<Vec<f64>> {
    text.trim()
        .trim_end_matches("mm")
        .split(',')
        .map(|s| {
            let v: f64 = s
                .trim()
                .trim_end_matches("mm")
                .parse()
                .with_context(|| format!("--steps: `{s}` is not a length in mm"))?;
            if !(v.is_finite() && v > 0.0) {
                bail!("--steps: {v} mm (expected a finite length > 0)");
            }
            Ok(v * 1e-3)
        })
        .collect()
}

/// Runs the sweep and prints the table (Markdown). Fails, after the table,
/// if any step failed.
pub fn run(args: &ConvergeSweepArgs) -> Result<()> {
    let loads = parse_loads(&args.loads)?;
    let steps = parse_steps(&args.steps)?;
    let scenario = Scenario::from_path(&args.scenario)?;
    let base = args
        .scenario
        .parent()
        .map(PathBuf::from)
        .unwrap_or_default();
    let material = scenario.material()?;
    let t = Instant::now();
    let road = scenario.texture_rolling_road(&base)?;
    eprintln!(
        "converge-sweep: road of {} asperities (Wilke laws) built in {:.1} s",
        road.len(),
        t.elapsed().as_secs_f64()
    );
    let base_config = scenario.rolling_config()?;
    say!(
        "| step (mm) | load (N) | steps | converged | stagnated | failed | recovered by clusters | other recoveries | s |"
    );
    say!("|---:|---:|---:|---:|---:|---:|---:|---:|---:|");
    let mut totals = Vec::new();
    let mut failed_total = 0;
    for &step in &steps {
        let (mut n, mut failed, mut clustered, mut seconds) = (0, 0, 0, 0.0);
        for &load in &loads {
            let mut config = base_config.clone();
            config.step = step;
            config.control = RollingControl::Load(load);
            let t = Instant::now();
            let result = rolling::roll(&road, material, &config, &RunOptions::default())
                .with_context(|| format!("step {} mm, {load} N", step * 1e3))?;
            let dt = t.elapsed().as_secs_f64();
            let count = |f: &dyn Fn(&rolling::StepRecord) -> bool| {
                result.steps.iter().filter(|s| f(s)).count()
            };
            let conv = count(&|s| s.status == StepStatus::Converged);
            let stag = count(&|s| s.status == StepStatus::Stagnated);
            let fail = count(&|s| s.status == StepStatus::Failed);
            let clus = count(&|s| s.recovery == Recovery::Clustered);
            let other = count(&|s| {
                !matches!(s.recovery, Recovery::None | Recovery::Clustered)
                    && s.status != StepStatus::Failed
            });
            say!(
                "| {} | {load} | {} | {conv} | {stag} | {fail} | {clus} | {other} | {dt:.1} |",
                step * 1e3,
                result.steps.len()
            );
            n += result.steps.len();
            failed += fail;
            clustered += clus;
            seconds += dt;
        }
        totals.push((step, n, failed, clustered, seconds));
        failed_total += failed;
    }
    say!();
    say!("| step (mm) | runs | steps | failed | recovered by clusters | s |");
    say!("|---:|---:|---:|---:|---:|---:|");
    for (step, n, failed, clustered, seconds) in totals {
        say!(
            "| {} | {} | {n} | {failed} | {clustered} | {seconds:.1} |",
            step * 1e3,
            loads.len()
        );
    }
    if failed_total > 0 {
        bail!("{failed_total} steps failed");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn load_ranges_and_step_lists_parse() -> Result<()> {
        let loads = parse_loads("500..3000:100")?;
        assert_eq!(loads.len(), 26);
        assert_eq!((loads[0], loads[25]), (500.0, 3000.0));
        assert_eq!(parse_loads("1300, 3000 N")?, vec![1300.0, 3000.0]);
        assert!(parse_loads("3000..500:100").is_err());
        assert!(parse_loads("0..1e9:1e-3").is_err());
        assert!(parse_loads("x").is_err());
        // Regression (adversarial run, 2026-11-30): 1e30 N "converged".
        let e = parse_loads("1e30").expect_err("too heavy").to_string();
        assert!(e.contains("expected a load in [1e-9, 1e7] N"), "{e}");
        assert!(parse_loads("1..1e30:1e29").is_err());
        assert_eq!(
            parse_steps("0.25,0.5,1,2mm")?,
            vec![0.25e-3, 0.5e-3, 1e-3, 2e-3]
        );
        assert!(parse_steps("-1mm").is_err());
        Ok(())
    }
}
