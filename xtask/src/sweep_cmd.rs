//! `cargo xtask sweep SWEEP.toml`: every run of a sweep (docs/distributed.md)
//! rolled and written (`OUT/run_NNNN/`, the files of `cargo xtask run`), and
//! one table, `OUT/sweep.csv`, one row per run. With `--mpi` (an xtask built
//! with `--features mpi`, started by `mpirun`) rank 0 hands the runs out to
//! the other ranks; without, they run on a rayon pool. Both write the same
//! table.
//!
//! `mpi-run SCENARIO.toml` (feature `mpi`): one rolling run split over the
//! ranks; rank 0 writes the files `cargo xtask run` writes.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result};
use clap::Args;
use tyreroad::scenario::output::OutputSet;
use tyreroad::scenario::{Par, RunOptions, ScenarioResult};
use tyreroad_distributed::sweep::{RunSummary, Sweep, SweepRow, SweepRun, run_local, table_csv};

use crate::rolling_cmd::write_outputs;

/// `cargo xtask sweep`'s arguments.
#[derive(Args)]
pub struct SweepArgs {
    /// The sweep file (TOML).
    pub sweep: PathBuf,
    /// Output directory: `sweep.csv` and one `run_NNNN/` per run.
    #[arg(long, default_value = "sweep")]
    pub out: PathBuf,
    /// Worker threads on one machine (0: every core); ignored with `--mpi`.
    #[arg(long, default_value_t = 0, value_parser = crate::parse_threads)]
    pub threads: usize,
    /// Distribute the runs over MPI ranks (needs `--features mpi`).
    #[arg(long)]
    pub mpi: bool,
    /// Exit non-zero when any run failed (its table is written all the
    /// same); without it only a sweep none of whose runs ran fails.
    #[arg(long)]
    pub strict: bool,
}

/// One run, rolled on the calling thread and written to `out/run_NNNN`;
/// its failure is its row's error.
fn run_one(run: &SweepRun, base_dir: &Path, out: &Path) -> SweepRow {
    let outcome = (|| -> Result<RunSummary> {
        let scenario = run.parse()?;
        let options = RunOptions {
            base_dir: base_dir.to_path_buf(),
            par: Some(Par::Seq),
            progress: None,
            checkpoint_dir: None,
        };
        let ScenarioResult::Rolling(rolled) = scenario.run(&options)? else {
            anyhow::bail!("the scenario has no [rolling] section");
        };
        // A manifest marks the folder as a sweep run's (`remove_stale_runs`).
        let mut set = OutputSet::replacing(out.join(run_folder(run.index)), RUN_PRODUCER)?;
        write_outputs(&rolled, &mut set)?;
        set.commit()?;
        Ok(RunSummary::of(&rolled))
    })();
    SweepRow {
        index: run.index,
        params: run.params.clone(),
        outcome: outcome.map_err(|e| format!("{e:#}")),
    }
}

/// `cargo xtask sweep`.
pub fn run(args: &SweepArgs) -> Result<()> {
    let sweep = Sweep::from_path(&args.sweep)?;
    let job = |run: &SweepRun| run_one(run, &sweep.base_dir, &args.out);
    let rows = if args.mpi {
        match mpi_rows(&sweep, &job)? {
            Some(rows) => rows,
            None => return Ok(()), // a worker rank: rank 0 writes
        }
    } else {
        run_local(&sweep.runs, args.threads, job)?
    };
    write_table(&rows, &args.out, args.strict)
}

/// The producer name of a sweep run's outputs: its folder's manifest.
const RUN_PRODUCER: &str = "sweep-run";

/// The folder of run `index` in the sweep's output folder.
fn run_folder(index: usize) -> String {
    format!("run_{index:04}")
}

/// Removes the run folders an earlier sweep left in `out` that this one
/// did not write: those of runs that failed now, and those past its last
/// run. Only folders a sweep marked as its own (their manifest) are
/// removed; anything else in `out` stays. Without this, a sweep with
/// fewer runs, or a run that failed, left an older sweep's outputs beside
/// a `sweep.csv` that does not list them.
fn remove_stale_runs(rows: &[SweepRow], out: &Path) -> Result<()> {
    let Ok(entries) = std::fs::read_dir(out) else {
        return Ok(());
    };
    let written: std::collections::HashSet<String> = rows
        .iter()
        .filter(|r| r.outcome.is_ok())
        .map(|r| run_folder(r.index))
        .collect();
    let manifest = format!(
        "{}{RUN_PRODUCER}",
        tyreroad::scenario::output::MANIFEST_PREFIX
    );
    for entry in entries.flatten() {
        let name = entry.file_name().to_string_lossy().into_owned();
        let is_run = name.len() >= 8
            && name.starts_with("run_")
            && name[4..].bytes().all(|b| b.is_ascii_digit());
        let path = entry.path();
        if is_run
            && !written.contains(&name)
            && path.is_dir()
            && !path.is_symlink()
            && path.join(&manifest).is_file()
        {
            std::fs::remove_dir_all(&path)
                .with_context(|| format!("removing an earlier sweep's {}", path.display()))?;
        }
    }
    Ok(())
}

fn write_table(rows: &[SweepRow], out: &Path, strict: bool) -> Result<()> {
    remove_stale_runs(rows, out)?;
    let mut set = OutputSet::new(out)?;
    set.write("sweep.csv", table_csv(rows).as_bytes())?;
    set.commit()?;
    let failed = rows.iter().filter(|r| r.outcome.is_err()).count();
    say!(
        "sweep: {} runs ({failed} failed), table {}",
        rows.len(),
        out.join("sweep.csv").display()
    );
    for r in rows {
        if let Err(e) = &r.outcome {
            say!("  run {}: {e}", r.index);
        }
    }
    // A failed run is its row's failure; a sweep none of whose runs ran
    // produced nothing, and a script calling it must see that.
    if !rows.is_empty() && failed == rows.len() {
        anyhow::bail!(
            "every run of the sweep failed (each row of {} says why)",
            out.join("sweep.csv").display()
        );
    }
    // A script that needs every run asks for it.
    if strict && failed > 0 {
        anyhow::bail!(
            "{failed} of {} runs of the sweep failed (--strict; each row of {} says why)",
            rows.len(),
            out.join("sweep.csv").display()
        );
    }
    Ok(())
}

#[cfg(feature = "mpi")]
fn mpi_rows(
    sweep: &Sweep,
    job: &(dyn Fn(&SweepRun) -> SweepRow + Sync),
) -> Result<Option<Vec<SweepRow>>> {
    use tyreroad_distributed::mpi;
    let universe = mpi::initialize().ok_or_else(|| anyhow::anyhow!("MPI already started"))?;
    Ok(mpi::run_sweep(&universe.world(), &sweep.runs, job)?)
}

#[cfg(not(feature = "mpi"))]
fn mpi_rows(
    _: &Sweep,
    _: &(dyn Fn(&SweepRun) -> SweepRow + Sync),
) -> Result<Option<Vec<SweepRow>>> {
    anyhow::bail!("--mpi needs an xtask built with `--features mpi` (docs/distributed.md)")
}

/// `mpi-run`'s arguments.
#[cfg(feature = "mpi")]
#[derive(Args)]
pub struct MpiRunArgs {
    /// The scenario (TOML) with a `[rolling]` section.
    pub scenario: PathBuf,
    /// Output directory (written by rank 0); checkpoints in `OUT/checkpoint`.
    #[arg(long, default_value = "validation")]
    pub out: PathBuf,
    /// Warm-up steps each rank solves before its part.
    #[arg(long, default_value_t = tyreroad_distributed::DEFAULT_WARMUP)]
    pub warmup: usize,
    /// Rank 0 gathers every record, then writes (the way before records
    /// were written as they arrive): the same files, with rank 0's memory
    /// growing with the path; for comparisons (docs/performance.md).
    #[arg(long)]
    pub gather: bool,
}

/// `mpi-run`: the rolling run split over the ranks, written by rank 0.
#[cfg(feature = "mpi")]
pub fn mpi_run(args: &MpiRunArgs) -> Result<()> {
    use tyreroad::scenario::Scenario;
    use tyreroad_distributed::mpi;
    let scenario = Scenario::from_path(&args.scenario)?;
    let base = args.scenario.parent().unwrap_or(Path::new("."));
    let universe = mpi::initialize().ok_or_else(|| anyhow::anyhow!("MPI already started"))?;
    let options = RunOptions {
        base_dir: base.to_path_buf(),
        // One rank per core: each rank steps on one thread.
        par: Some(Par::Seq),
        progress: None,
        checkpoint_dir: Some(args.out.join("checkpoint")),
    };
    use tyreroad::scenario::ScenarioError;
    use tyreroad::scenario::output::steps_stream::StepStream;
    let world = universe.world();
    if args.gather {
        if let Some(run) = mpi::roll(&world, &scenario, &options, args.warmup)? {
            crate::rolling_cmd::report_rolling(&run, &args.out)?;
        }
        return Ok(());
    }
    // Before any rank rolls: a streamed run cannot recount its sensors.
    scenario.check_streamed()?;
    // Rank 0 streams the records into the output set as they arrive
    // (docs/distributed.md, "Gather and write"). A set that cannot be
    // opened is reported at the first record, as rank 0's error, so the
    // other ranks' messages are still received.
    let mut writing = None;
    if mpi::is_root(&world) {
        let names: Vec<String> = scenario
            .rolling_config()?
            .sensors
            .iter()
            .map(|s| s.name.clone())
            .collect();
        writing = Some(
            OutputSet::replacing(&args.out, "rolling").and_then(|mut set| {
                let mut stream = StepStream::new(&mut set, &names)?;
                stream.reserve(scenario.rolling_steps()?);
                if let Some(tally) = scenario.past_cap_tally(&options)? {
                    stream.count_past_caps(tally);
                }
                Ok((set, stream))
            }),
        );
    }
    let mut sink = |record: tyreroad::rolling::StepRecord| -> Result<(), ScenarioError> {
        match writing.as_mut() {
            Some(Ok((_, stream))) => stream.push(&record),
            Some(Err(_)) => match writing.take() {
                Some(Err(e)) => Err(e),
                _ => Err(ScenarioError::Invalid("no output set".into())),
            },
            None => Err(ScenarioError::Invalid("no output set".into())),
        }
    };
    let Some(gathered) = mpi::roll_into(&world, &scenario, &options, args.warmup, &mut sink)?
    else {
        return Ok(());
    };
    let Some(Ok((mut set, stream))) = writing else {
        anyhow::bail!("rank 0 has no output set");
    };
    let signals = stream.finish(&mut set, scenario.rolling_config()?.lateral)?;
    let run = scenario.finish_streamed(&options, signals, gathered.resumed)?;
    crate::rolling_cmd::report_streamed(&run, set, &args.out)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    fn row(index: usize, outcome: Result<RunSummary, String>) -> SweepRow {
        SweepRow {
            index,
            params: vec![("load".into(), format!("{index}"))],
            outcome,
        }
    }

    /// Regression (adversarial run, 2026-11-29): a sweep all of whose runs
    /// failed exited 0. Its table is still written; the command fails.
    #[test]
    fn a_sweep_whose_every_run_failed_is_an_error_with_its_table_written() -> Result<()> {
        let out =
            std::env::temp_dir().join(format!("tyreroad-sweep-failed-{}", std::process::id()));
        let all_failed = [row(0, Err("bad".into())), row(1, Err("worse".into()))];
        let e = write_table(&all_failed, &out, false).expect_err("every run failed");
        assert!(
            e.to_string().contains("every run of the sweep failed"),
            "{e}"
        );
        let table = std::fs::read_to_string(out.join("sweep.csv"))?;
        assert!(table.contains("bad") && table.contains("worse"), "{table}");
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }

    /// Regression (adversarial run, 2026-11-30): a sweep of fewer runs, or
    /// with a run that failed, left an older sweep's run folders beside its
    /// table (a failed row over the old run's outputs). The sweep's own
    /// stale folders go; a folder it did not mark stays.
    #[test]
    fn an_earlier_sweeps_run_folders_that_this_one_did_not_write_are_removed() -> Result<()> {
        let out = std::env::temp_dir().join(format!("tyreroad-sweep-stale-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&out);
        let manifest = format!(
            "{}{RUN_PRODUCER}",
            tyreroad::scenario::output::MANIFEST_PREFIX
        );
        for index in 0..3 {
            let dir = out.join(run_folder(index));
            std::fs::create_dir_all(&dir)?;
            std::fs::write(dir.join(&manifest), "time_signals.csv\n")?;
            std::fs::write(dir.join("time_signals.csv"), "old")?;
        }
        let yours = out.join("run_0007");
        std::fs::create_dir_all(&yours)?;
        let summary = RunSummary {
            steps: 4,
            failed_steps: 0,
            mean_force: 1.0,
            level_of: "approach".into(),
            overall_db: 0.0,
            bands: Vec::new(),
        };
        let rows = [row(0, Ok(summary)), row(1, Err("diverged".into()))];
        // One run of two failed: the sweep's success unless `--strict`.
        let e = write_table(&rows, &out, true).expect_err("strict");
        assert!(
            e.to_string().starts_with("1 of 2 runs of the sweep failed"),
            "{e}"
        );
        write_table(&rows, &out, false)?;
        assert!(out.join("run_0000/time_signals.csv").is_file());
        assert!(!out.join("run_0001").exists(), "a failed run's old outputs");
        assert!(!out.join("run_0002").exists(), "past the last run");
        assert!(yours.is_dir(), "not a sweep's: kept");
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }
}
