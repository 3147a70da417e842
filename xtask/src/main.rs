//! The tyreroad runner: `cargo xtask <command>`.
//!
//! - `validate [--out DIR]`: the paper's 25-ball experiment, solved and checked;
//! - `run SCENARIO.toml [--out DIR]`: a static scenario's loads (on its
//!   `[[asperity]]` list or its `[texture]`), or a rolling run when the
//!   scenario has a `[rolling]` section;
//! - `film SCAN --calibration ... --layout ... [--model CSV] [--out DIR]`: a
//!   pressure-film scan analysed print by print;
//! - `texture info FILE` / `texture synth ...`: road texture files.

mod bem_validation;
mod charts;
mod film_cmd;
mod output;
mod pressure_image;
mod rolling_cmd;
mod scenario;
mod statics;
mod texture_cmd;
mod texture_roads_cmd;
mod texture_static;
mod units;
mod validate;

use std::path::PathBuf;

use anyhow::Result;
use clap::{Parser, Subcommand};

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
    },
    /// Analyse a pressure-film scan: per-print forces, areas, radii.
    Film(Box<film_cmd::FilmArgs>),
    /// Road textures: `info FILE` (Sq, MPD, ...) and `synth ... --out FILE.x3p`.
    Texture {
        #[command(subcommand)]
        cmd: texture_cmd::TextureCommand,
    },
}

fn main() -> Result<()> {
    match Cli::parse().command {
        Command::Validate(args) => validate::run(&args),
        Command::Film(args) => film_cmd::run(&args),
        Command::Texture { cmd } => texture_cmd::run(&cmd),
        Command::Run { scenario, out } => {
            let text = std::fs::read_to_string(&scenario)
                .map_err(|e| anyhow::anyhow!("reading {}: {e}", scenario.display()))?;
            let s = scenario::Scenario::parse(&text, &scenario.display().to_string())?;
            let base = scenario.parent().unwrap_or(std::path::Path::new("."));
            if let (Some(spec), Some(texture)) = (&s.rolling, &s.texture) {
                let material = s.material()?;
                let road = rolling_cmd::texture_road_parts(texture, base, material)?;
                return rolling_cmd::run_rolling(material, Some(road), spec, &out);
            }
            if let Some(spec) = &s.rolling {
                let road = if s.asperities.is_empty() {
                    None
                } else {
                    let (positions, heights, laws) = s.asperity_parts()?;
                    Some(rolling_cmd::RoadParts {
                        positions,
                        heights,
                        laws,
                    })
                };
                return rolling_cmd::run_rolling(s.material()?, road, spec, &out);
            }
            if s.texture.is_some() {
                return texture_static::run_texture_static(&s, base, &out);
            }
            let (rows, runs) = statics::run_static(&s)?;
            statics::print_table(&rows);
            for r in &runs {
                println!(
                    "load {} N: Σ P = {:.9} N, δ0 = {:.6e} m, {} contacts, {} iterations",
                    r.load, r.total, r.approach, r.contacts, r.iterations
                );
                if r.overlapping > 0 {
                    println!(
                        "  note: {} pairs of contacts overlap: the point-force coupling \
                         does not hold there",
                        r.overlapping
                    );
                }
            }
            for w in statics::write_static_outputs(&out, &s.name, &rows)? {
                println!("written {w}");
            }
            Ok(())
        }
    }
}
