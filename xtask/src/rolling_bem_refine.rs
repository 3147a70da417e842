//! `cargo xtask rolling-bem SCENARIO --refine F --steps N [--from X]`: is
//! the BEM rolling reference converged in its grid? The stretch solved by
//! the BEM on the texture's grid and on one `F` times finer
//! (`tyreroad::bem_rolling::run_grid_convergence`); prints both runs'
//! approach and sensor forces per step and their largest changes, and
//! writes them to `OUT/rolling_bem_refine.csv`.

use std::path::Path;
use std::time::Instant;

use anyhow::Result;
use serde::Serialize;
use tyreroad::bem_rolling::{BemRollingOptions, Stretch, run_grid_convergence};
use tyreroad::scenario::output::{OutputSet, fmt};
use tyreroad::scenario::{Par, Scenario};

use crate::rolling_bem_args::RollingBemArgs;

/// One step on both grids.
#[derive(Serialize)]
struct RefineRow {
    step: usize,
    #[serde(serialize_with = "fmt::sci9")]
    position_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    approach_coarse_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    approach_fine_m: f64,
    sensor: String,
    #[serde(serialize_with = "fmt::sci9")]
    sensor_coarse_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    sensor_fine_n: f64,
}

/// Runs the check, prints the table, writes the file.
pub fn run(args: &RollingBemArgs, factor: usize) -> Result<()> {
    let scenario = Scenario::from_path(&args.scenario)?;
    let name = scenario.name.clone();
    let sensors: Vec<String> = scenario
        .rolling_config()?
        .sensors
        .iter()
        .map(|s| s.name.clone())
        .collect();
    let base = args.scenario.parent().unwrap_or(Path::new("."));
    let clock = Instant::now();
    let run = run_grid_convergence(
        scenario,
        base,
        Stretch {
            start: args.from,
            steps: Some(args.steps),
            segment: None,
        },
        factor,
        Par::rayon(args.threads),
        &BemRollingOptions {
            tolerance: args.tolerance,
            ..BemRollingOptions::default()
        },
    )?;
    say!(
        "{name}: {} steps by the BEM at {:.4} mm and {:.4} mm ({:?} refinement), windows {:?} and {:?}, {:.1} s; failed steps {} / {}",
        run.coarse.steps.len(),
        run.cells.0 * 1e3,
        run.cells.1 * 1e3,
        run.refinement,
        run.coarse.window,
        run.fine.window,
        clock.elapsed().as_secs_f64(),
        run.coarse.failed(),
        run.fine.failed()
    );
    let mut header = format!(
        "{:>6} {:>10} {:>22}",
        "step", "x (mm)", "approach (µm) c / f"
    );
    for s in &sensors {
        header.push_str(&format!(" {:>24}", format!("{s} (N) c / f")));
    }
    say!("{header}");
    let mut rows = Vec::new();
    for (c, f) in run.coarse.steps.iter().zip(&run.fine.steps) {
        let mut line = format!(
            "{:>6} {:>10.2} {:>10.2} / {:>9.2}",
            c.index,
            c.position * 1e3,
            c.approach * 1e6,
            f.approach * 1e6
        );
        for (k, s) in sensors.iter().enumerate() {
            let (fc, ff) = (c.sensor_forces[k], f.sensor_forces[k]);
            line.push_str(&format!(" {fc:>11.2} / {ff:>10.2}"));
            rows.push(RefineRow {
                step: c.index,
                position_m: c.position,
                approach_coarse_m: c.approach,
                approach_fine_m: f.approach,
                sensor: s.clone(),
                sensor_coarse_n: fc,
                sensor_fine_n: ff,
            });
        }
        say!("{line}");
    }
    say!(
        "largest change, fine − coarse, over the coarse peak: approach {:.2} %",
        100.0 * run.approach_change()
    );
    for (k, s) in sensors.iter().enumerate() {
        say!("  {s}: {:.2} %", 100.0 * run.sensor_change(k));
    }
    let mut set = OutputSet::new(&args.out)?;
    set.write_csv("rolling_bem_refine.csv", &rows)?;
    for path in set.commit()? {
        say!("wrote {}", path.display());
    }
    Ok(())
}
