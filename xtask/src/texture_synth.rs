//! The arguments of `cargo xtask texture synth`: the grid and output
//! options every kind shares, and the hard road kinds of
//! `tyreroad_texture::roads` (docs/texture.md), each with its physical
//! defaults, the options overriding the main parameters.

use std::path::PathBuf;

use anyhow::Result;
use tyreroad::scenario::MAX_MAP_POINTS;
use tyreroad::texture;
use tyreroad::texture::roads::{self, RoadGrid};

/// Grid and output options shared by the synthesis subcommands.
#[derive(Debug, Clone, clap::Args)]
pub struct GridArgs {
    /// Points along x (the driving direction).
    #[arg(long, default_value_t = 800)]
    pub nx: usize,
    /// Points along y.
    #[arg(long, default_value_t = 400)]
    pub ny: usize,
    /// Spacing along x and y (m).
    #[arg(long, default_value_t = 0.25e-3)]
    pub dx: f64,
    /// Seed of the random generator.
    #[arg(long, default_value_t = 1)]
    pub seed: u64,
    /// X3P z data type: I (int16), L (int32), F (float32) or D (float64).
    #[arg(long, default_value = "D")]
    pub data_type: String,
    /// Output X3P file.
    #[arg(long)]
    pub out: PathBuf,
}

/// Groove options shared by the two tinings.
#[derive(Debug, Clone, clap::Args)]
pub struct TiningArgs {
    /// Groove width (m).
    #[arg(long, default_value_t = 3e-3)]
    pub groove_width: f64,
    /// Groove depth (m).
    #[arg(long, default_value_t = 4e-3)]
    pub groove_depth: f64,
    /// Smallest centre-to-centre groove spacing (m).
    #[arg(long, default_value_t = 12.5e-3)]
    pub pitch_min: f64,
    /// Largest spacing (m) for random tining (default: regular, `pitch_min`).
    #[arg(long)]
    pub pitch_max: Option<f64>,
}

/// The hard road kinds.
#[derive(Debug, Clone, clap::Subcommand)]
pub enum RoadKind {
    /// Tined concrete, grooves across the driving direction.
    TransverseTining {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Grooves.
        #[command(flatten)]
        grooves: TiningArgs,
    },
    /// Tined concrete, grooves along the driving direction.
    LongitudinalTining {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Grooves.
        #[command(flatten)]
        grooves: TiningArgs,
    },
    /// Brushed concrete: fine transverse striations on mortar.
    BrushedConcrete {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Root mean square height of the striations (m).
        #[arg(long, default_value_t = 0.2e-3)]
        striation_rms: f64,
        /// Length-to-width ratio of the striations.
        #[arg(long, default_value_t = 20.0)]
        elongation: f64,
    },
    /// Exposed-aggregate concrete: chippings out of a flat mortar plane.
    ExposedAggregate {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Summed plan area of the chippings over the map area.
        #[arg(long, default_value_t = 0.8)]
        coverage: f64,
        /// Smallest exposed fraction of a chipping's height.
        #[arg(long, default_value_t = 0.25)]
        exposure_min: f64,
        /// Largest exposed fraction of a chipping's height.
        #[arg(long, default_value_t = 0.4)]
        exposure_max: f64,
    },
    /// Porous (open-graded) asphalt: flat tops, deep voids.
    PorousAsphalt {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Summed plan area of the chippings over the map area.
        #[arg(long, default_value_t = 3.0)]
        coverage: f64,
        /// Depth of the voids below the chippings' base plane (m).
        #[arg(long, default_value_t = 3e-3)]
        pore_depth: f64,
        /// Fraction of the area flattened at the top.
        #[arg(long, default_value_t = 0.2)]
        plateau_fraction: f64,
    },
    /// Worn chip seal: rounded 6/10 mm chippings ground flat on top.
    WornChipSeal {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Fraction of the area worn flat.
        #[arg(long, default_value_t = 0.1)]
        plateau_fraction: f64,
    },
    /// Pavé (setts): blocks with rounded edges separated by joints.
    Pave {
        /// Grid and output.
        #[command(flatten)]
        grid: GridArgs,
        /// Block length along x (m).
        #[arg(long, default_value_t = 100e-3)]
        block_length: f64,
        /// Block width along y (m).
        #[arg(long, default_value_t = 100e-3)]
        block_width: f64,
        /// Joint width (m).
        #[arg(long, default_value_t = 10e-3)]
        joint_width: f64,
        /// Joint depth below the block tops (m).
        #[arg(long, default_value_t = 4e-3)]
        joint_depth: f64,
        /// Edge radius of the blocks (m).
        #[arg(long, default_value_t = 5e-3)]
        edge_radius: f64,
        /// Rows in line instead of a running bond.
        #[arg(long)]
        no_stagger: bool,
    },
}

fn road_grid(g: &GridArgs) -> Result<RoadGrid> {
    g.check()?;
    Ok(RoadGrid::square(g.nx, g.ny, g.dx))
}

fn tining(
    g: &GridArgs,
    t: &TiningArgs,
    direction: roads::TiningDirection,
) -> Result<texture::HeightMap> {
    let mut p = roads::Tining::transverse(road_grid(g)?, g.seed);
    p.direction = direction;
    p.groove_width = t.groove_width;
    p.groove_depth = t.groove_depth;
    p.pitch = (t.pitch_min, t.pitch_max.unwrap_or(t.pitch_min));
    Ok(roads::tining(&p)?)
}

impl GridArgs {
    /// Refuses a grid no machine could synthesise (more points than a
    /// scenario's `[texture.synth]` takes: an FFT over 2^30 points needs
    /// 16 GiB and more, and aborted in the allocator) or a spacing that is
    /// no length, before anything is allocated.
    pub fn check(&self) -> Result<()> {
        let points = self.nx as f64 * self.ny as f64;
        if self.nx < 2 || self.ny < 2 || points > MAX_MAP_POINTS {
            anyhow::bail!(
                "--nx {} --ny {}: expected at least 2 points each way and at most {MAX_MAP_POINTS:e} \
                 points in all",
                self.nx,
                self.ny
            );
        }
        if !(self.dx.is_finite() && self.dx > 0.0) {
            anyhow::bail!(
                "--dx {}: expected a spacing in metres, finite and > 0",
                self.dx
            );
        }
        // The file is an X3P whatever its name: another extension would be
        // read back by that format's reader (an `.asc` as "not UTF-8 text").
        let x3p = self
            .out
            .extension()
            .is_some_and(|e| e.eq_ignore_ascii_case("x3p"));
        if !x3p {
            anyhow::bail!(
                "--out {}: synth writes an X3P file; name it .x3p",
                self.out.display()
            );
        }
        Ok(())
    }
}

impl RoadKind {
    /// Synthesises the road; returns it with its grid and output options.
    pub fn build(&self) -> Result<(texture::HeightMap, &GridArgs)> {
        use roads::TiningDirection as D;
        Ok(match self {
            Self::TransverseTining { grid, grooves } => {
                (tining(grid, grooves, D::Transverse)?, grid)
            }
            Self::LongitudinalTining { grid, grooves } => {
                (tining(grid, grooves, D::Longitudinal)?, grid)
            }
            Self::BrushedConcrete {
                grid,
                striation_rms,
                elongation,
            } => {
                let mut p = roads::BrushedConcrete::new(road_grid(grid)?, grid.seed);
                p.striation_rms = *striation_rms;
                p.elongation = *elongation;
                (roads::brushed_concrete(&p)?, grid)
            }
            Self::ExposedAggregate {
                grid,
                coverage,
                exposure_min,
                exposure_max,
            } => {
                let mut p = roads::ExposedAggregate::new(road_grid(grid)?, grid.seed);
                p.coverage = *coverage;
                p.exposure = (*exposure_min, *exposure_max);
                (roads::exposed_aggregate(&p)?, grid)
            }
            Self::PorousAsphalt {
                grid,
                coverage,
                pore_depth,
                plateau_fraction,
            } => {
                let mut p = roads::PorousAsphalt::new(road_grid(grid)?, grid.seed);
                p.coverage = *coverage;
                p.pore_depth = *pore_depth;
                p.plateau_fraction = *plateau_fraction;
                (roads::porous_asphalt(&p)?, grid)
            }
            Self::WornChipSeal {
                grid,
                plateau_fraction,
            } => {
                let mut p = roads::WornChipSeal::new(road_grid(grid)?, grid.seed);
                p.plateau_fraction = *plateau_fraction;
                (roads::worn_chip_seal(&p)?, grid)
            }
            Self::Pave {
                grid,
                block_length,
                block_width,
                joint_width,
                joint_depth,
                edge_radius,
                no_stagger,
            } => {
                let mut p = roads::Pave::new(road_grid(grid)?, grid.seed);
                p.block_length = *block_length;
                p.block_width = *block_width;
                p.joint_width = *joint_width;
                p.joint_depth = *joint_depth;
                p.edge_radius = *edge_radius;
                p.stagger = !no_stagger;
                (roads::pave(&p)?, grid)
            }
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (adversarial run, 2026-11-29): 32768 × 32768 points were
    /// accepted and aborted in the allocator (16 GiB for the FFT).
    #[test]
    fn a_grid_no_machine_could_synthesise_is_refused_before_allocating() {
        let grid = |nx, ny, dx| GridArgs {
            nx,
            ny,
            dx,
            seed: 1,
            data_type: "D".into(),
            out: PathBuf::from("unused.x3p"),
        };
        assert!(grid(800, 400, 0.25e-3).check().is_ok());
        let mut asc = grid(800, 400, 0.25e-3);
        asc.out = PathBuf::from("road.asc");
        let e = asc.check().expect_err("an X3P named .asc").to_string();
        assert!(e.contains("name it .x3p"), "{e}");
        for (nx, ny, dx) in [(32768, 32768, 1e-4), (1, 400, 1e-4), (800, 400, 0.0)] {
            let e = grid(nx, ny, dx).check().expect_err("refused").to_string();
            assert!(e.contains("--nx") || e.contains("--dx"), "{e}");
        }
    }
}
