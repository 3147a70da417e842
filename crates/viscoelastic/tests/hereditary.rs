//! The hereditary multipoint solve against its independent references: the
//! Lee–Radok closed form (one sphere at constant rate) and the elastic
//! solutions with `E∞` and `E∞ + Σ E_k` (slow and fast loading of 25 balls).

use tyreroad_contact_law::{HertzLaw, Material};
use tyreroad_multipoint::{Control, Problem, SolverOptions, solve};
use tyreroad_viscoelastic::{Hereditary, lee_radok_ramp_force, run_load_history};

use crate::support;
use support::{tread, twenty_five_balls};

#[test]
fn a_sphere_pressed_at_constant_rate_follows_lee_radok() {
    let material = tread();
    let radius = 5e-3;
    let reference = Material::new(1e6, 0.5).expect("valid");
    let law = HertzLaw::new(radius, reference).expect("valid");
    let problem = Problem::new(vec![[0.0, 0.0]], vec![0.0], vec![law], reference).expect("valid");
    let mut solver =
        Hereditary::new(&problem, material.clone(), SolverOptions::default()).expect("valid");
    // 3 ms to 0.2 mm: the slow branch is half relaxed, the fast one fully.
    let duration = 3e-3;
    let rate = 2e-4 / duration;
    // The scheme takes f linear over a step, while δ^{3/2} starts with zero
    // slope: the first step carries the largest error, about 0.05 Δt/τ_fast
    // (1.2 % at Δt = τ_fast/4, 0.6 % at τ_fast/8; 3e-5 by step 50).
    let steps = 1200;
    let dt = duration / steps as f64;
    let mut worst = 0.0f64;
    for n in 1..=steps {
        let t = n as f64 * dt;
        let step = solver.step_approach(dt, rate * t).expect("solves");
        let exact = lee_radok_ramp_force(&material, radius, rate, t).expect("finite");
        worst = worst.max((step.total_force() / exact - 1.0).abs());
        assert_eq!(step.receding, 0);
    }
    assert!(worst < 0.01, "worst relative error {worst}");
}

fn elastic_forces(problem: &Problem<HertzLaw>, modulus: f64, load: f64) -> Vec<f64> {
    // Forces scale with E at a given approach: solve the reference problem at
    // the load it carries at modulus `modulus`.
    let scale = modulus / problem.material().youngs_modulus();
    let solution = solve(
        problem,
        Control::Load(load / scale),
        &SolverOptions::default(),
    )
    .expect("elastic solve");
    solution.forces.iter().map(|f| f * scale).collect()
}

fn worst_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn slow_and_fast_ramps_reach_the_elastic_limits() {
    let problem = twenty_five_balls();
    let material = tread();
    let load = 200.0;
    let ramp = |duration: f64| -> Vec<(f64, f64)> {
        (1..=20)
            .map(|j| (duration * j as f64 / 20.0, load * j as f64 / 20.0))
            .collect()
    };
    // Slow: 100 s against τ ≤ 1 ms.
    let slow = run_load_history(
        &problem,
        material.clone(),
        SolverOptions::default(),
        &ramp(100.0),
    )
    .expect("slow ramp");
    let relaxed = elastic_forces(&problem, material.long_term(), load);
    let last = slow.last().expect("steps");
    assert!((last.total_force() - load).abs() < 1e-6 * load);
    let slow_error = worst_difference(&last.forces, &relaxed);
    assert!(slow_error < 5e-3, "slow: {slow_error}");
    // Fast: 1 ns against τ ≥ 20 µs.
    let fast = run_load_history(
        &problem,
        material.clone(),
        SolverOptions::default(),
        &ramp(1e-9),
    )
    .expect("fast ramp");
    let glassy = elastic_forces(&problem, material.instantaneous(), load);
    let fast_error = worst_difference(&fast.last().expect("steps").forces, &glassy);
    assert!(fast_error < 5e-3, "fast: {fast_error}");
    // The load is shared differently: a stiffer tread carries it on fewer,
    // more loaded summits, so the two limits differ well beyond the tolerance.
    assert!(worst_difference(&relaxed, &glassy) > 0.02);
}

#[test]
fn a_hold_relaxes_the_approach_and_unloading_is_counted_as_receding() {
    let problem = twenty_five_balls();
    let material = tread();
    let samples = tyreroad_viscoelastic::ramp_hold_unload(200.0, 100.0, 1e-4, 5e-3, 20);
    let steps =
        run_load_history(&problem, material, SolverOptions::default(), &samples).expect("history");
    // Creep under constant load: the approach grows during the hold.
    let end_ramp = &steps[19];
    let end_hold = &steps[39];
    assert!(end_hold.approach > end_ramp.approach * 1.05);
    for s in &steps[20..40] {
        assert!((s.total_force() - 200.0).abs() < 1e-6 * 200.0);
    }
    assert!(steps[..40].iter().all(|s| s.receding == 0));
    assert!(steps[40..].iter().any(|s| s.receding > 0));
}
