//! The hereditary multipoint model against the viscoelastic BEM on 25 balls
//! under a loading ramp, a hold and an unloading ramp (docs/viscoelastic.md).
//! Run with `cargo run --release -p tyreroad-viscoelastic --example bem_compare`.

use tyreroad_viscoelastic::{Branch, Prony, SphereField, compare_on_spheres, ramp_hold_unload};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let branches = [(3e6, 1e-3), (5e6, 2e-5)]
        .map(|(modulus, relaxation_time)| Branch {
            modulus,
            relaxation_time,
        })
        .to_vec();
    let material = Prony::new(2e6, branches, 0.5)?;
    let side = 5;
    let gaps = (0..side * side)
        .map(|k| 1e-5 * ((3 * (k % side) + 7 * (k / side)) % 5) as f64)
        .collect();
    let cell: f64 = std::env::args()
        .nth(1)
        .map(|s| s.parse())
        .transpose()?
        .unwrap_or(2.5e-4);
    let field = SphereField {
        side,
        radius: 0.02,
        pitch: 0.012,
        gaps,
        cell,
    };
    let samples = ramp_hold_unload(100.0, 60.0, 2e-3, 2e-3, 10);
    let c = compare_on_spheres(&field, &material, &samples)?;
    println!("time_s,load_N,model_approach_m,bem_approach_m,worst_force_difference");
    for (k, (t, load)) in samples.iter().enumerate() {
        let one = tyreroad_viscoelastic::Comparison {
            time: vec![*t],
            model: vec![c.model[k].clone()],
            bem: vec![c.bem[k].clone()],
            model_approach: vec![],
            bem_approach: vec![],
        };
        println!(
            "{t:.6},{load:.2},{:.6e},{:.6e},{:.4}",
            c.model_approach[k],
            c.bem_approach[k],
            one.worst_force_difference()
        );
    }
    println!("worst over the history: {:.4}", c.worst_force_difference());
    Ok(())
}
