//! Cost of a hereditary load history against the same history solved
//! elastically (warm-started elastic solves at each load): the viscoelastic
//! step must stay within 2× of the elastic one (issue #18).

use criterion::{Criterion, criterion_group, criterion_main};
use tyreroad_contact_law::Material;
use tyreroad_multipoint::layouts::road_like_field;
use tyreroad_multipoint::{Control, SolverOptions, solve_from};
use tyreroad_viscoelastic::{Branch, Prony, run_load_history};

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
    let samples: Vec<(f64, f64)> = (1..=20)
        .map(|j| (1e-4 * j as f64, 10.0 * j as f64))
        .collect();
    let options = SolverOptions::default();
    let mut group = c.benchmark_group("viscoelastic/road_like_400_ramp_20_steps");
    group.sample_size(10);
    group.bench_function("elastic", |b| {
        b.iter(|| {
            let mut previous = None;
            for &(_, load) in &samples {
                previous = Some(
                    solve_from(&problem, Control::Load(load), &options, previous.as_ref())
                        .expect("converges"),
                );
            }
            previous
        })
    });
    group.bench_function("hereditary", |b| {
        b.iter(|| {
            run_load_history(&problem, material.clone(), options, &samples).expect("converges")
        })
    });
    group.finish();
}

criterion_group!(benches, bench_history);
criterion_main!(benches);
