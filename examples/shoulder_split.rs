//! Where a sensor's load goes on a rolling texture scenario: at each given
//! footprint centre, the BEM's force per segmentation basin against the
//! model's force per asperity (docs/validation.md, "Where the shoulder's
//! load goes"):
//!
//! ```text
//! cargo run --release --example shoulder_split -- fixtures/rolling_tyre_dense_asphalt.toml 1 0.24 0.25 0.26
//! ```
//!
//! Arguments: the scenario, the sensor's index, footprint centres (m);
//! `FIDELITY=calibrated` in the environment picks the calibrated laws.

use std::path::Path;

use tyreroad::bem_rolling::{BemRollingOptions, asperity_split};
use tyreroad::scenario::Scenario;
use tyreroad::shared::Par;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .unwrap_or_else(|| "fixtures/rolling_tyre_dense_asphalt.toml".into());
    let sensor: usize = args.next().map_or(Ok(1), |s| s.parse())?;
    let positions: Vec<f64> = args.map(|s| s.parse()).collect::<Result<_, _>>()?;
    let mut scenario = Scenario::from_path(&path)?;
    // The rung from the environment (the fixtures do not name one).
    if let Ok(name) = std::env::var("FIDELITY") {
        scenario.model.fidelity = Some(name);
    }
    let base_dir = Path::new(&path).parent().unwrap_or(Path::new("."));
    let threads = std::thread::available_parallelism().map_or(1, |n| n.get());
    let split = asperity_split(
        scenario,
        base_dir,
        &positions,
        sensor,
        Par::rayon(threads),
        &BemRollingOptions::default(),
    )?;
    let mm = 1e3;
    let um = 1e6;
    for s in &split {
        println!(
            "x_c = {:.1} mm: approach BEM {:.1} µm, model {:.1} µm; sensor BEM {:.3} N \
             (of which {:.3} N on no basin), model {:.3} N, model at the BEM's approach {:.3} N \
             (total {:.1} N)",
            s.position * mm,
            s.bem_approach * um,
            s.model_approach * um,
            s.bem_sensor,
            s.bem_sensor_unlabelled,
            s.model_sensor,
            s.model_sensor_at_bem_approach,
            s.model_total_at_bem_approach
        );
        println!(
            "  basin   id   x mm   y mm   R mm  H-Hex µm  δ_i µm  BEM F   BEM sens  model F  model sens  @BEMδ0 sens  tilted F  local sens"
        );
        let (mut missing, mut held, mut tilted, mut model, mut local) = (0.0, 0.0, 0.0, 0.0, 0.0);
        for a in &s.asperities {
            println!(
                "  {:5} {:5} {:6.1} {:6.1} {:6.2} {:8.1} {:7.1} {:7.3} {:9.3} {:8.3} {:10.3} {:12.3} {:9.3} {:11.3}",
                a.basin,
                a.road_id.map_or(-1, |i| i as i64),
                a.summit[0] * mm,
                a.summit[1] * mm,
                a.radius * mm,
                (a.gap_model - a.gap_exact) * um,
                a.model_depth * um,
                a.bem_force,
                a.bem_sensor,
                a.model_force,
                a.model_sensor,
                a.model_sensor_at_bem_approach,
                a.tilted_force,
                a.local_sensor
            );
            local += a.local_sensor;
            if a.model_force > 0.0 {
                held += a.bem_sensor;
            } else {
                missing += a.bem_sensor;
            }
            if a.tilted_force.is_finite() && a.bem_sensor > 0.0 {
                tilted += a.tilted_force;
                model += a.model_force;
            }
        }
        println!(
            "  BEM sensor load on asperities the model touches {held:.3} N, on ones it does not \
             {missing:.3} N; over the BEM's loaded asperities: model force {model:.3} N, \
             tilted-cap BEM force at the model's depth {tilted:.3} N; \
             the model's forces spread as their caps' own BEM pressure put {local:.3} N on the sensor"
        );
    }
    Ok(())
}
