//! `cargo xtask history SCENARIO [--viscoelastic E_INF,E1@TAU1,...] [--out DIR]`:
//! a static scenario's `[static.history]` run by the hereditary model with
//! the scenario's `[material.viscoelastic]` tread, or the one given here
//! (docs/viscoelastic.md, "Loading history in scenario files"); prints one
//! line per step and writes `history.csv`. `cargo xtask run` on such a
//! scenario does the same with the scenario's tread.

use std::path::PathBuf;

use anyhow::Result;
use tyreroad::scenario::output::OutputSet;
use tyreroad::scenario::{HistoryResult, Scenario, run_load_history_scenario, write_history_csv};

use crate::rolling_visco_bem_cmd::parse_prony;

/// Arguments of `history`.
#[derive(clap::Args)]
pub struct HistoryArgs {
    /// A static scenario with a `[static.history]` on an `[[asperity]]` list.
    pub scenario: PathBuf,
    /// The viscoelastic tread `E_INF,E1@TAU1,E2@TAU2,...` (Pa, s), with the
    /// scenario's Poisson's ratio; default: the scenario's
    /// `[material.viscoelastic]`.
    #[arg(long)]
    pub viscoelastic: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "validation/history")]
    pub out: PathBuf,
}

/// Runs the history, prints the steps, writes `history.csv`.
pub fn run(args: &HistoryArgs) -> Result<()> {
    let scenario = Scenario::from_path(&args.scenario)?;
    let base = args.scenario.parent().unwrap_or(std::path::Path::new("."));
    let (tread, note) = match &args.viscoelastic {
        Some(text) => (
            Some(parse_prony(text, scenario.material()?.poisson_ratio())?),
            None,
        ),
        None => scenario
            .viscoelastic_material_noted(base)?
            .map_or((None, None), |(tread, note)| (Some(tread), note)),
    };
    // No tread at all: the library's named `[material]` refusal.
    let mut result = run_load_history_scenario(&scenario, tread.as_ref())?;
    result.warnings.extend(note);
    report(&result, &args.out)
}

/// Prints the steps, writes `history.csv` into `out` (whole, or not at
/// all), and fails after writing when the history stopped early.
pub fn report(result: &HistoryResult, out: &std::path::Path) -> Result<()> {
    say!(
        "{:>12} {:>12} {:>14} {:>9}",
        "time (ms)",
        "load (N)",
        "approach (mm)",
        "receding"
    );
    for s in &result.steps {
        say!(
            "{:>12.4} {:>12.4} {:>14.6} {:>9}",
            1e3 * s.time,
            s.load,
            1e3 * s.approach,
            s.receding
        );
    }
    if let Some(failure) = &result.failure {
        say!("stopped early: {failure}");
    }
    for warning in &result.warnings {
        say!("warning: {warning}");
    }
    let mut set = OutputSet::new(out)?;
    write_history_csv(result, &mut set)?;
    for path in set.commit()? {
        say!("wrote {}", path.display());
    }
    if result.failure.is_some() {
        anyhow::bail!("the history stopped before its end (outputs written)");
    }
    Ok(())
}
