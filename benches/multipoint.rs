//! Static multipoint solves: the paper's 25 balls, and random ball fields of
//! N = 100 and N = 1000 summits with random radii and heights.
//!
//! Targets (issue 2): 25 balls under 100 µs, N = 1000 under 0.5 s on the
//! project's 2-core machine.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use tyreroad::asperity::Sphere;
use tyreroad::contact_law::PotentialLaw;
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};

#[path = "common/mod.rs"]
mod common;

use common::{Law, random_field, rubber, tyre_like_load};

fn paper_grid() -> Problem<Law> {
    let ball = PotentialLaw::sphere(Sphere::new(5e-3).expect("radius"), rubber());
    let positions: Vec<[f64; 2]> = (0..25)
        .map(|k| [((k % 5) as f64 - 2.0) * 0.01, ((k / 5) as f64 - 2.0) * 0.01])
        .collect();
    Problem::new(positions, vec![0.0; 25], vec![ball; 25], rubber()).expect("problem")
}

fn bench_paper(c: &mut Criterion) {
    let problem = paper_grid();
    let opts = SolverOptions::default();
    c.bench_function("multipoint/paper_25_spheres_500N", |b| {
        b.iter(|| solve(&problem, Control::Load(500.0), &opts).expect("converges"))
    });
}

fn bench_random(c: &mut Criterion) {
    let mut group = c.benchmark_group("multipoint/random_spheres");
    group.sample_size(10);
    for n in [100, 1000] {
        let problem = random_field(n, 2006);
        let load = tyre_like_load(n);
        let opts = SolverOptions::default();
        let s = solve(&problem, Control::Load(load), &opts).expect("converges");
        eprintln!(
            "N = {n}: load {load:.1} N, {} in contact, {} iterations, {} load steps",
            s.contact_count(),
            s.iterations,
            s.load_steps
        );
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| solve(&problem, Control::Load(load), &opts).expect("converges"))
        });
    }
    group.finish();
}

criterion_group!(benches, bench_paper, bench_random);
criterion_main!(benches);
