//! The tyreroad runner: `cargo xtask <command>`.
//!
//! - `validate [--out DIR]`: the paper's 25-ball experiment, solved and checked;
//!   `validate --textures`: every fidelity rung against the BEM on seven road kinds;
//! - `run SCENARIO.toml [--out DIR]`: a static scenario's loads (on its
//!   `[[asperity]]` list or its `[texture]`), or a rolling run when the
//!   scenario has a `[rolling]` section;
//! - `film SCAN --calibration ... --layout ... [--model CSV] [--out DIR]`: a
//!   pressure-film scan analysed print by print;
//! - `texture info FILE` / `texture synth ...`: road texture files;
//! - `rolling-bem SCENARIO [--steps N] [--out DIR]`: a rolling scenario on a
//!   texture against the full-BEM rolling reference; with
//!   `--viscoelastic E_INF,E1@TAU1,...` the viscoelastic rolling BEM.
//! - `history SCENARIO [--viscoelastic E_INF,E1@TAU1,...]`: a static
//!   scenario's `[static.history]` with a viscoelastic tread;
//! - `converge-sweep SCENARIO --loads 500..3000:100 --steps 0.25,0.5,1,2mm`:
//!   a rolling texture scenario at every load and step, steps converged,
//!   failed and recovered by clusters;
//! - `sweep SWEEP.toml [--mpi]`: a parameter sweep, one table row per run;
//!   `mpi-run SCENARIO.toml` (feature `mpi`): a rolling run over MPI ranks.
//! - `visco-sweep SCENARIO [--speeds 30..130] [--temperatures 0degC,20degC,40degC]`:
//!   viscoelastic rolling runs against speed and temperature, a table and
//!   charts of the overall and band levels.
//! - `calib-cost [--nodes N] [--tolerance T]`: the calibrated laws' cost per
//!   table on the seven texture kinds, and how far cheaper options move them.

/// `println!` that a closed stdout does not stop: `xtask run … | head`
/// closes the pipe after a line, and `println!` would panic there and lose
/// the run; what is printed is a report, the run's files are the result.
macro_rules! say {
    () => {
        $crate::print_to_stdout(format_args!("\n"))
    };
    ($($arg:tt)*) => {
        $crate::print_to_stdout(format_args!("{}\n", format_args!($($arg)*)))
    };
}

/// `print!` as [`say!`] is `println!`.
macro_rules! say_part {
    ($($arg:tt)*) => {
        $crate::print_to_stdout(format_args!($($arg)*))
    };
}

mod bem_validation;
mod calib_cost;
mod charts;
mod converge_sweep;
mod film_cmd;
mod history_cmd;
mod pressure_image;
mod rolling_bem_args;
mod rolling_bem_cmd;
mod rolling_bem_refine;
mod rolling_bem_saved;
mod rolling_cmd;
mod rolling_visco_bem_cmd;
mod statics;
mod summary;
mod sweep_cmd;
mod texture_cmd;
mod texture_static;
mod texture_synth;
mod torture;
mod validate;
mod validate_textures;
mod visco_sweep;

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::{Parser, Subcommand};
use tyreroad::scenario::output::OutputSet;
use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};

use crate::summary::Fallbacks;

#[derive(Parser)]
#[command(name = "cargo xtask", about = "tyreroad runner", version)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run the paper's 25-ball experiment and check it against references.
    Validate(validate::ValidateArgs),
    /// Solve a scenario file.
    Run {
        /// The scenario (TOML).
        scenario: PathBuf,
        /// Output directory.
        #[arg(long, default_value = "validation")]
        out: PathBuf,
        /// Exit non-zero when any item fell back to a lower-fidelity
        /// result, (rolling) any step is not `converged`, or the run
        /// printed a warning (the outputs are written all the same).
        #[arg(long)]
        strict: bool,
    },
    /// Solve and roll every hard road kind; print the table of what
    /// converged, what fell back and the time it took.
    Torture {
        /// Only this road kind (a `[texture.synth] kind`).
        #[arg(long)]
        kind: Option<String>,
    },
    /// Roll a texture scenario at every load and step length; print the
    /// table of steps converged, failed and recovered by clusters.
    ConvergeSweep(converge_sweep::ConvergeSweepArgs),
    /// Analyse a pressure-film scan: per-print forces, areas, radii.
    Film(Box<film_cmd::FilmArgs>),
    /// Road textures: `info FILE` (Sq, MPD, ...) and `synth ... --out FILE.x3p`.
    Texture {
        #[command(subcommand)]
        cmd: texture_cmd::TextureCommand,
    },
    /// Roll a texture scenario by the multipoint model and by the full BEM
    /// over the same steps; print and write the comparison.
    RollingBem(Box<rolling_bem_args::RollingBemArgs>),
    /// Run a parameter sweep (rayon, or MPI ranks with --mpi): one table row per run.
    Sweep(sweep_cmd::SweepArgs),
    /// Roll a scenario over MPI ranks (start with mpirun); rank 0 writes.
    #[cfg(feature = "mpi")]
    MpiRun(sweep_cmd::MpiRunArgs),
    /// Run a static scenario's `[static.history]` with a viscoelastic tread.
    History(history_cmd::HistoryArgs),
    /// Viscoelastic rolling runs of a scenario against speed and
    /// temperature: a table and charts of the overall and band levels.
    ViscoSweep(Box<visco_sweep::ViscoSweepArgs>),
    /// What a calibrated law's table costs on the seven texture kinds, and
    /// how far cheaper calibration options move the tables.
    CalibCost(calib_cost::CalibCostArgs),
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Command::Validate(args) => validate::run(&args),
        Command::Film(args) => film_cmd::run(&args),
        Command::Texture { cmd } => texture_cmd::run(&cmd),
        Command::Torture { kind } => torture::run(kind.as_deref()),
        Command::RollingBem(args) => rolling_bem_cmd::run(&args),
        Command::ConvergeSweep(args) => converge_sweep::run(&args),
        Command::Sweep(args) => sweep_cmd::run(&args),
        Command::History(args) => history_cmd::run(&args),
        Command::ViscoSweep(args) => visco_sweep::run(&args),
        Command::CalibCost(args) => calib_cost::run(&args),
        #[cfg(feature = "mpi")]
        Command::MpiRun(args) => sweep_cmd::mpi_run(&args),
        Command::Run {
            scenario,
            out,
            strict,
        } => run_scenario(&scenario, &out, strict),
    }
}

/// `cargo xtask run`: the library runs the scenario, this prints and writes,
/// then sums up what fell back (with `--strict`, a non-zero exit if any).
fn run_scenario(path: &Path, out: &Path, strict: bool) -> Result<()> {
    let s = Scenario::from_path(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    if s.rolling.is_some() {
        return rolling_cmd::run_rolling(&s, base, out)?.finish(strict);
    }
    let result = s.run(&RunOptions::new(base))?;
    let mut set = OutputSet::replacing(out, &s.name)?;
    let fallbacks = match result {
        ScenarioResult::Texture(r) => {
            texture_static::report_texture_static(&s.name, &r, &mut set)?;
            Fallbacks::from_texture(&r)
        }
        ScenarioResult::Static(r) => {
            statics::print_table(&r.rows);
            statics::print_runs(&r.runs);
            statics::print_failed_loads(&r.failed_loads);
            statics::write_static_outputs(&mut set, &s.name, &r.rows)?;
            Fallbacks::from_static(&r)
        }
        ScenarioResult::Rolling(run) => {
            return rolling_cmd::report_rolling(&run, out)?.finish(strict);
        }
        // A history stopped early fails after writing, strict or not: its
        // later steps depend on the failed one.
        ScenarioResult::History(r) => return history_cmd::report(&r, out),
    };
    if let Some(note) = set.landing_note() {
        say!("note: {note}");
    }
    statics::print_written(&set.commit()?);
    fallbacks.finish(strict)
}

/// `--threads N`: a count within the range a scenario's `[rolling] threads`
/// accepts (`tyreroad::scenario::check_threads`).
fn parse_threads(text: &str) -> Result<usize, String> {
    let n: usize = text
        .trim()
        .parse()
        .map_err(|_| format!("`{text}` is not a thread count (0 for every core)"))?;
    tyreroad::scenario::check_threads("--threads", n).map_err(|e| e.to_string())
}

/// Writes to stdout, ignoring a closed pipe (see [`say!`]).
fn print_to_stdout(args: std::fmt::Arguments<'_>) {
    use std::io::Write;
    let _ = std::io::stdout().lock().write_fmt(args);
}
