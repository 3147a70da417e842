//! Cost of a hereditary load history against the same history solved
//! elastically (warm-started elastic solves at each load): the viscoelastic
//! step must stay within 2× of the elastic one (issue #18). Each hereditary
//! history runs with Lee–Radok's recursion and with Ting's treatment of
//! receding contacts (docs/viscoelastic.md, "Cost"): on a ramp (every
//! contact grows) and on a ramp up and back down (every contact recedes).

use criterion::{Criterion, criterion_group, criterion_main};
use tyreroad_contact_law::Material;
use tyreroad_multipoint::layouts::road_like_field;
use tyreroad_multipoint::{Control, SolverOptions, solve_from};
use tyreroad_viscoelastic::{Branch, Prony, Receding, run_load_history_with};

fn bench_history(c: &mut Criterion) {
    let rubber = Material::new(2e6, 0.5).expect("valid");
    // A fixed linear congruential stream: the same field every run.
    let mut state = 2006u64;
    let uniform = move || {
        state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (state >> 11) as f64 / (1u64 << 53) as f64
    };
    let n = 400;
    let problem = road_like_field(n, rubber, uniform).expect("field");
    let material = Prony::new(
        2e6,
        [(3e6, 1e-3), (5e6, 2e-5)]
            .map(|(modulus, relaxation_time)| Branch {
                modulus,
                relaxation_time,
            })
            .to_vec(),
        0.5,
    )
    .expect("valid");
    let ramp: Vec<(f64, f64)> = (1..=20)
        .map(|j| (1e-4 * j as f64, 10.0 * j as f64))
        .collect();
    // Up to 200 N in 10 steps and back down to 10 N in 10.
    let up_down: Vec<(f64, f64)> = (1..=20)
        .map(|j| {
            let load = if j <= 10 {
                20.0 * j as f64
            } else {
                200.0 - 19.0 * (j - 10) as f64
            };
            (1e-4 * j as f64, load)
        })
        .collect();
    let options = SolverOptions::default();
    for (name, samples) in [("ramp", &ramp), ("up_down", &up_down)] {
        let mut group = c.benchmark_group(format!("viscoelastic/road_like_400_{name}_20_steps"));
        group.sample_size(10);
        group.bench_function("elastic", |b| {
            b.iter(|| {
                let mut previous = None;
                for &(_, load) in samples {
                    previous = Some(
                        solve_from(&problem, Control::Load(load), &options, previous.as_ref())
                            .expect("converges"),
                    );
                }
                previous
            })
        });
        for (label, receding) in [
            ("hereditary_lee_radok", Receding::LeeRadok),
            ("hereditary_ting", Receding::default()),
        ] {
            group.bench_function(label, |b| {
                b.iter(|| {
                    run_load_history_with(&problem, material.clone(), options, receding, samples)
                        .expect("converges")
                })
            });
        }
        group.finish();
    }
}

criterion_group!(benches, bench_history);
criterion_main!(benches);
