//! `cargo xtask texture`: inspect and synthesise road textures.
//!
//! - `texture info FILE`: `key: value` lines (grid, spacings, Sq, MPD);
//! - `texture synth self-affine|aggregate ... --out FILE.x3p`: a synthetic
//!   surface, reproducible from its seed, written as X3P (whole or not at
//!   all: a temporary file, then a rename); also the hard road kinds
//!   (`transverse-tining`, `pave`, ..., see [`crate::texture_synth`]).

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use tyreroad::texture;

use crate::texture_synth::GridArgs;

/// Subcommands of `cargo xtask texture`.
#[derive(Debug, Clone, clap::Subcommand)]
pub enum TextureCommand {
    /// Print a height map's grid and texture indicators as `key: value`
    /// lines (SI units). Formats by extension: .x3p, .sur, .xyz, anything
    /// else as an ASCII grid.
    Info {
        /// The height map file.
        file: PathBuf,
        /// MPD baseline in metres (default 0.1, the ISO 13473-1 value); a
        /// value that is not a positive length, or one the map cannot give an
        /// MPD for, is an error (non-zero exit).
        #[arg(long)]
        baseline: Option<f64>,
    },
    /// Synthesise a surface and write it as X3P.
    Synth {
        /// The kind of surface and its parameters.
        #[command(subcommand)]
        kind: SynthKind,
    },
}

/// Kinds of synthetic surface.
#[derive(Debug, Clone, clap::Subcommand)]
pub enum SynthKind {
    /// A self-affine Gaussian surface from its power spectrum.
    SelfAffine {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Root mean square height Sq (m).
        #[arg(long, default_value_t = 0.5e-3)]
        rms: f64,
        /// Hurst exponent, in (0, 1].
        #[arg(long, default_value_t = 0.8)]
        hurst: f64,
        /// Long cut-off (roll-off) wavelength (m).
        #[arg(long, default_value_t = 50e-3)]
        lambda_long: f64,
        /// Short cut-off wavelength (m).
        #[arg(long, default_value_t = 1e-3)]
        lambda_short: f64,
    },
    /// Chippings of a grading curve on a base plane.
    Aggregate {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Grading: `4-6` (4/6.3 mm), `6-10` (6/10 mm), or a list
        /// `SIZE_MM:PERCENT,...` of cumulative percentages passing.
        #[arg(long, default_value = "6-10")]
        grading: String,
        /// Summed plan area of the chippings over the map area.
        #[arg(long, default_value_t = 1.3)]
        coverage: f64,
        /// Chip shape: `ellipsoid` or `polyhedron`.
        #[arg(long, default_value = "ellipsoid")]
        shape: String,
        /// Smallest embedded fraction of a chipping's height.
        #[arg(long, default_value_t = 0.3)]
        embed_min: f64,
        /// Largest embedded fraction of a chipping's height.
        #[arg(long, default_value_t = 0.5)]
        embed_max: f64,
    },
    /// The hard road kinds (tining, brushed, exposed aggregate, porous
    /// asphalt, worn chip seal, pavé).
    #[command(flatten)]
    Road(crate::texture_synth::RoadKind),
}

fn parse_grading(s: &str) -> Result<Vec<(f64, f64)>> {
    Ok(match s {
        "4-6" | "4/6" | "4-6.3" => texture::Aggregate::grading_4_6(),
        "6-10" | "6/10" => texture::Aggregate::grading_6_10(),
        list => list
            .split(',')
            .map(|p| {
                let (a, b) = p
                    .split_once(':')
                    .with_context(|| format!("grading point {p:?} is not SIZE_MM:PERCENT"))?;
                Ok((a.trim().parse::<f64>()? * 1e-3, b.trim().parse::<f64>()?))
            })
            .collect::<Result<Vec<_>>>()?,
    })
}

fn parse_type(s: &str) -> Result<texture::io::x3p::X3pDataType> {
    use texture::io::x3p::X3pDataType as T;
    Ok(match s {
        "I" | "i" | "int16" => T::I16,
        "L" | "l" | "int32" => T::I32,
        "F" | "f" | "float32" => T::F32,
        "D" | "d" | "float64" => T::F64,
        other => bail!("unknown X3P data type {other:?} (I, L, F or D)"),
    })
}

/// The `key: value` lines of `texture info` for a map.
pub fn info_lines(map: &texture::HeightMap, baseline: Option<f64>) -> Vec<String> {
    let mut out = vec![
        format!("nx: {}", map.nx()),
        format!("ny: {}", map.ny()),
        format!("dx_m: {:e}", map.dx()),
        format!("dy_m: {:e}", map.dy()),
        format!("valid_points: {}", map.valid_count()),
    ];
    let na = || "n/a".to_string();
    out.push(format!(
        "rms_m: {}",
        map.rms().map(|v| format!("{v:e}")).unwrap_or_else(na)
    ));
    if let Some((lo, hi)) = map.min_max() {
        out.push(format!("min_m: {lo:e}"));
        out.push(format!("max_m: {hi:e}"));
    }
    match texture::mean_profile_depth(map, baseline) {
        Ok(m) => {
            out.push(format!("mpd_m: {:e}", m.mpd));
            out.push(format!("mpd_baseline_m: {:e}", m.baseline));
            out.push(format!("mpd_segments: {}", m.segments));
        }
        Err(e) => out.push(format!("mpd_m: n/a ({e})")),
    }
    out
}

/// Runs `cargo xtask texture ...`.
pub fn run(cmd: &TextureCommand) -> Result<()> {
    match cmd {
        TextureCommand::Info { file, baseline } => {
            if let Some(b) = baseline
                && !(b.is_finite() && *b > 0.0)
            {
                anyhow::bail!(
                    "--baseline {b}: the MPD baseline must be a positive length in metres \
                     (ISO 13473-1 uses 0.1)"
                );
            }
            let read =
                texture::read_any(file).with_context(|| format!("reading {}", file.display()))?;
            // As a run reads it: "no data" markers are missing points.
            let markers = texture::find_sentinels(&read);
            let map = read.without_values(&markers)?;
            for marker in &markers {
                say!(
                    "no_data_marker_m: {:e} ({} points, read as missing)",
                    marker.value,
                    marker.points
                );
            }
            if let Some(b) = baseline
                && let Err(e) = texture::mean_profile_depth(&map, Some(*b))
            {
                // Asked for by name, so an MPD that cannot be had is the
                // command's failure, not an "n/a" line.
                anyhow::bail!("--baseline {b}: {e}");
            }
            for line in info_lines(&map, *baseline) {
                say!("{line}");
            }
            Ok(())
        }
        TextureCommand::Synth { kind } => {
            let (map, grid) = match kind {
                SynthKind::SelfAffine {
                    grid,
                    rms,
                    hurst,
                    lambda_long,
                    lambda_short,
                } => {
                    grid.check()?;
                    let p = texture::SelfAffine {
                        nx: grid.nx,
                        ny: grid.ny,
                        dx: grid.dx,
                        dy: grid.dx,
                        rms: *rms,
                        hurst: *hurst,
                        lambda_long: *lambda_long,
                        lambda_short: *lambda_short,
                        seed: grid.seed,
                    };
                    (texture::self_affine(&p)?, grid)
                }
                SynthKind::Aggregate {
                    grid,
                    grading,
                    coverage,
                    shape,
                    embed_min,
                    embed_max,
                } => {
                    grid.check()?;
                    let mut p = texture::Aggregate::new(
                        grid.nx,
                        grid.ny,
                        grid.dx,
                        grid.dx,
                        parse_grading(grading)?,
                        grid.seed,
                    );
                    p.coverage = *coverage;
                    p.embedding = (*embed_min, *embed_max);
                    p.shape = match shape.as_str() {
                        "ellipsoid" => texture::ChipShape::Ellipsoid,
                        "polyhedron" => texture::ChipShape::Polyhedron {
                            cuts: 6,
                            rounding: 0.1,
                        },
                        other => bail!("unknown shape {other:?} (ellipsoid, polyhedron)"),
                    };
                    (texture::aggregate(&p)?, grid)
                }
                SynthKind::Road(road) => road.build()?,
            };
            let ty = parse_type(&grid.data_type)?;
            texture::io::x3p::write_x3p(&map, &grid.out, ty)
                .with_context(|| format!("writing {}", grid.out.display()))?;
            say!("wrote {}", grid.out.display());
            for line in info_lines(&map, None) {
                say!("{line}");
            }
            Ok(())
        }
    }
}
