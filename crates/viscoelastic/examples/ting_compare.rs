//! Receding contacts: the hereditary multipoint model with Lee–Radok's
//! recursion and with Ting's treatment against the viscoelastic BEM, on a
//! square field of spheres ramped, held and unloaded (docs/viscoelastic.md,
//! "Receding contacts: Ting's treatment"). Run with
//! `cargo run --release -p tyreroad-viscoelastic --example ting_compare -- SIDE PEAK FLOOR CELL PER_DECADE`
//! (defaults: 1 sphere, 20 N to 0.2 N, 0.25 mm cells, 20 bands per decade).

use tyreroad_viscoelastic::{
    Branch, Comparison, Prony, Receding, SphereField, compare_on_spheres_with, ramp_hold_unload,
};

/// `∫ W dδ0` over the history (trapezoids): the work the load did on the
/// tread, which a closed loop dissipates.
fn work(loads: &[f64], approach: &[f64]) -> f64 {
    let mut previous = (0.0, 0.0);
    let mut sum = 0.0;
    for (&w, &d) in loads.iter().zip(approach) {
        if previous.1 != 0.0 || previous.0 != 0.0 {
            sum += 0.5 * (w + previous.0) * (d - previous.1);
        }
        previous = (w, d);
    }
    sum
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize, default: f64| -> Result<f64, std::num::ParseFloatError> {
        args.get(k).map_or(Ok(default), |s| s.parse())
    };
    let side = arg(0, 1.0)? as usize;
    let peak = arg(1, 20.0)?;
    let floor = arg(2, 0.2)?;
    let cell = arg(3, 2.5e-4)?;
    let per_decade = arg(4, 20.0)? as usize;
    let branches = [(3e6, 1e-3), (5e6, 2e-5)]
        .map(|(modulus, relaxation_time)| Branch {
            modulus,
            relaxation_time,
        })
        .to_vec();
    let material = Prony::new(2e6, branches, 0.5)?;
    let gaps = (0..side * side)
        .map(|k| 1e-5 * ((3 * (k % side) + 7 * (k / side)) % 5) as f64)
        .collect();
    let field = SphereField {
        side,
        radius: 0.02,
        pitch: if side == 1 { 0.016 } else { 0.012 },
        gaps,
        cell,
    };
    let samples = ramp_hold_unload(peak, floor, 2e-3, 2e-3, 10);
    let start = std::time::Instant::now();
    let lee = compare_on_spheres_with(&field, &material, Receding::LeeRadok, &samples)?;
    let t_lee = start.elapsed();
    let start = std::time::Instant::now();
    let ting = compare_on_spheres_with(&field, &material, Receding::Ting { per_decade }, &samples)?;
    let t_ting = start.elapsed();
    println!(
        "step,time_s,load_N,bem_approach_m,lee_radok_err,ting_err,lee_force_diff,ting_force_diff"
    );
    let one = |c: &Comparison, k: usize| {
        Comparison {
            time: vec![c.time[k]],
            model: vec![c.model[k].clone()],
            bem: vec![c.bem[k].clone()],
            model_approach: vec![],
            bem_approach: vec![],
        }
        .worst_force_difference()
    };
    for (k, (t, load)) in samples.iter().enumerate() {
        let b = lee.bem_approach[k];
        println!(
            "{k},{t:.6},{load:.3},{b:.6e},{:+.4},{:+.4},{:.4},{:.4}",
            (lee.model_approach[k] - b) / b,
            (ting.model_approach[k] - b) / b,
            one(&lee, k),
            one(&ting, k)
        );
    }
    let loads: Vec<f64> = samples.iter().map(|s| s.1).collect();
    let (wb, wl, wt) = (
        work(&loads, &lee.bem_approach),
        work(&loads, &lee.model_approach),
        work(&loads, &ting.model_approach),
    );
    println!(
        "work W dδ (J): BEM {wb:.6e}, Lee–Radok {wl:.6e} ({:+.4}), Ting {wt:.6e} ({:+.4})",
        (wl - wb) / wb,
        (wt - wb) / wb
    );
    println!("runs (model + BEM): Lee–Radok {t_lee:.2?}, Ting {t_ting:.2?}");
    Ok(())
}
