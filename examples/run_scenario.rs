//! Runs a scenario file as a library user would, without `cargo xtask`:
//!
//! ```text
//! cargo run --example run_scenario -- fixtures/paper_25_spheres.toml
//! ```

use std::path::Path;

use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let path = std::env::args()
        .nth(1)
        .unwrap_or_else(|| "fixtures/paper_25_spheres.toml".into());
    let scenario = Scenario::from_path(&path)?;
    let base_dir = Path::new(&path).parent().unwrap_or(Path::new("."));
    match scenario.run(&RunOptions::new(base_dir))? {
        ScenarioResult::Static(r) => {
            for run in &r.runs {
                println!(
                    "{}: {} N carried by {} asperities, approach {:.4} mm",
                    r.name,
                    run.load,
                    run.contacts,
                    run.approach * 1e3
                );
            }
        }
        ScenarioResult::Texture(r) => {
            for l in &r.loads {
                let area: f64 = l.two_scale.local.iter().map(|f| f.contact_area).sum();
                println!("{} N: two-scale contact area {:.2} mm²", l.load, area * 1e6);
            }
        }
        ScenarioResult::History(r) => {
            for s in &r.steps {
                println!(
                    "t = {:.3} ms: {:.2} N, approach {:.4} mm",
                    s.time * 1e3,
                    s.load,
                    s.approach * 1e3
                );
            }
        }
        ScenarioResult::Rolling(r) => {
            let peak = r.result.total_force().into_iter().fold(0.0, f64::max);
            println!(
                "{} steps, peak total force {peak:.1} N",
                r.result.steps.len()
            );
        }
    }
    Ok(())
}
