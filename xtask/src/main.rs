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
//!   texture against the full-BEM rolling reference.
//! - `converge-sweep SCENARIO --loads 500..3000:100 --steps 0.25,0.5,1,2mm`:
//!   a rolling texture scenario at every load and step, steps converged,
//!   failed and recovered by clusters;
//! - `sweep SWEEP.toml [--mpi]`: a parameter sweep, one table row per run;
//!   `mpi-run SCENARIO.toml` (feature `mpi`): a rolling run over MPI ranks.

mod bem_validation;
mod charts;
mod converge_sweep;
mod film_cmd;
mod pressure_image;
mod rolling_bem_cmd;
mod rolling_cmd;
mod statics;
mod sweep_cmd;
mod texture_cmd;
mod texture_static;
mod texture_synth;
mod torture;
mod validate;
mod validate_textures;

use std::path::{Path, PathBuf};

use anyhow::Result;
use clap::{Parser, Subcommand};
use tyreroad::scenario::output::OutputSet;
use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};

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
        /// result, or (rolling) any step is not `converged` (the outputs
        /// are written all the same).
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
    RollingBem(Box<rolling_bem_cmd::RollingBemArgs>),
    /// Run a parameter sweep (rayon, or MPI ranks with --mpi): one table row per run.
    Sweep(sweep_cmd::SweepArgs),
    /// Roll a scenario over MPI ranks (start with mpirun); rank 0 writes.
    #[cfg(feature = "mpi")]
    MpiRun(sweep_cmd::MpiRunArgs),
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
        #[cfg(feature = "mpi")]
        Command::MpiRun(args) => sweep_cmd::mpi_run(&args),
        Command::Run {
            scenario,
            out,
            strict,
        } => run_scenario(&scenario, &out, strict),
    }
}

/// `cargo xtask run`: the library runs the scenario, this prints and writes.
fn run_scenario(path: &Path, out: &Path, strict: bool) -> Result<()> {
    let s = Scenario::from_path(path)?;
    let base = path.parent().unwrap_or(Path::new("."));
    if s.rolling.is_some() {
        let unconverged = rolling_cmd::run_rolling(&s, base, out)?;
        return strict_rolling(strict, unconverged);
    }
    let result = s.run(&RunOptions::new(base))?;
    let mut set = OutputSet::replacing(out, &s.name)?;
    let mut fallbacks = 0;
    match result {
        ScenarioResult::Texture(r) => {
            fallbacks = texture_static::report_texture_static(&s.name, &r, &mut set)?;
        }
        ScenarioResult::Static(r) => {
            statics::print_table(&r.rows);
            statics::print_runs(&r.runs);
            fallbacks += statics::print_failed_loads(&r.failed_loads);
            statics::write_static_outputs(&mut set, &s.name, &r.rows)?;
        }
        ScenarioResult::Rolling(run) => {
            let unconverged = rolling_cmd::report_rolling(&run, out)?;
            return strict_rolling(strict, unconverged);
        }
    }
    statics::print_written(&set.commit()?);
    if strict && fallbacks > 0 {
        anyhow::bail!("--strict: {fallbacks} items fell back (outputs written)");
    }
    Ok(())
}

/// `--strict` on a rolling run: every step must have converged.
fn strict_rolling(strict: bool, unconverged: usize) -> Result<()> {
    if strict && unconverged > 0 {
        anyhow::bail!("--strict: {unconverged} steps did not converge (outputs written)");
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    #[test]
    fn strict_rolling_refuses_any_step_not_converged() {
        assert!(super::strict_rolling(true, 0).is_ok());
        assert!(super::strict_rolling(false, 3).is_ok());
        assert!(super::strict_rolling(true, 1).is_err());
    }
}
