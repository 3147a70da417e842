//! Timed full run: a tyre on synthetic dense asphalt, ~1500 asperities under
//! the footprint, 1000 steps of 1 mm at 50 km/h, load control.
//!
//! ```text
//! cargo run --release -p tyreroad-rolling --example rolling_dense_asphalt [STEPS] [LOAD_N]
//! ```

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Instant;

use tyreroad_contact_law::Material;
use tyreroad_rolling::{
    Par, Progress, RollingConfig, RollingControl, RunOptions, SyntheticRoad, Tread, third_octave,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let steps: usize = args.next().map(|s| s.parse()).transpose()?.unwrap_or(1000);
    let load: f64 = args
        .next()
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(1500.0);
    let rubber = Material::new(6.54e6, 0.5)?;
    let (length, width, dx) = (0.12, 0.15, 1e-3);
    // A road long enough for the path plus the footprint.
    let spec = SyntheticRoad {
        length: steps as f64 * dx + length + 0.01,
        ..SyntheticRoad::default()
    };
    let t0 = Instant::now();
    let road = spec.sphere_road(rubber)?;
    println!(
        "road: {} summits on {:.3} m x {:.3} m, built in {:.2?}",
        road.len(),
        spec.length,
        spec.width,
        t0.elapsed()
    );
    let tread = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.5,
        length,
        width,
    };
    let start = 0.5 * length + 0.005;
    let end = start + (steps - 1) as f64 * dx;
    let config = RollingConfig::new(
        tread,
        [start, end, dx],
        50.0 / 3.6,
        RollingControl::Load(load),
    );
    let shown = AtomicUsize::new(0);
    let progress = |p: Progress| {
        let tenth = p.done * 10 / p.total;
        if shown.fetch_max(tenth, Ordering::Relaxed) < tenth {
            eprintln!("  {} / {} steps", p.done, p.total);
        }
        ControlFlow::Continue(())
    };
    let t1 = Instant::now();
    let result = tyreroad_rolling::roll(
        &road,
        rubber,
        &config,
        &RunOptions {
            par: Par::rayon(0),
            progress: Some(&progress),
            ..RunOptions::default()
        },
    )?;
    let elapsed = t1.elapsed();
    if std::env::var_os("ROLLING_VERBOSE").is_some() {
        for s in &result.steps {
            eprintln!(
                "step {} x {:.4} it {} contacts {} clearance {:.3e}",
                s.index, s.position, s.iterations, s.contacts, s.clearance
            );
        }
    }
    let n = result.steps.len() as f64;
    let mean = |f: &dyn Fn(&tyreroad_rolling::StepRecord) -> f64| {
        result.steps.iter().map(f).sum::<f64>() / n
    };
    println!(
        "{} steps in {:.2?} ({:.1} ms/step, {} threads): {:.0} asperities selected, \
         {:.0} in contact, {:.1} Newton iterations per step on average; min clearance {:.3e} m",
        result.steps.len(),
        elapsed,
        elapsed.as_secs_f64() * 1e3 / n,
        rayon::current_num_threads(),
        mean(&|s| s.selected as f64),
        mean(&|s| s.contacts as f64),
        mean(&|s| s.iterations as f64),
        result.min_clearance(),
    );
    println!(
        "approach {:.4e} … {:.4e} m; contact area mean {:.3e} m²",
        result
            .approach()
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min),
        result
            .approach()
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max),
        mean(&|s| s.contact_area),
    );
    let bands = third_octave(&result.approach(), result.sample_rate, 1e-6, None)?;
    for b in bands.iter().filter(|b| b.band.nominal >= 100.0) {
        println!("  {:>7} Hz  {:6.1} dB re 1 µm", b.band.nominal, b.level_db);
    }
    Ok(())
}
