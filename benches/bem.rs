//! Benchmarks of the reference BEM contact solver (`tyreroad-bem`).
//!
//! ```text
//! cargo bench --bench bem                 # all
//! cargo bench --bench bem -- solve/512    # one
//! ```
//!
//! The case is the 25-ball experiment of docs/theory.md §4 (R = 5 mm balls at
//! 10 mm pitch, E = 6.54 MPa, ν = 0.5) at 500 N, load controlled, on a
//! 51.2 mm square domain: 512² cells of 0.1 mm and 1024² cells of 0.05 mm.
//! The influence operator is built once outside the timed loop (it is reused
//! across solves); `operator/*` times one application u = K p (two real 2D
//! FFTs of the zero-padded grid).

use std::hint::black_box;
use std::time::Duration;

use criterion::{Criterion, criterion_group, criterion_main};
use tyreroad_bem::{
    BemOptions, Control, Grid, HeightMap, Material, Solver, Sphere, spherical_caps,
};

fn balls_case(n: usize) -> (Grid, HeightMap, Material) {
    let dx = 0.0512 / n as f64;
    let grid = Grid::centered(n, n, dx, dx).expect("grid");
    let pos = [-0.02, -0.01, 0.0, 0.01, 0.02];
    let balls: Vec<Sphere> = pos
        .iter()
        .flat_map(|&y| {
            pos.iter().map(move |&x| Sphere {
                centre: [x, y],
                radius: 5e-3,
                summit: 0.0,
            })
        })
        .collect();
    let surface = spherical_caps(&grid, &balls, -5e-3).expect("surface");
    let material = Material::new(6.54e6, 0.5).expect("material");
    (grid, surface, material)
}

fn bench_bem(c: &mut Criterion) {
    let mut group = c.benchmark_group("bem");
    group
        .sample_size(10)
        .warm_up_time(Duration::from_millis(500))
        .measurement_time(Duration::from_secs(5));
    for n in [512usize, 1024] {
        let (grid, surface, material) = balls_case(n);
        let mut solver = Solver::new(&grid, &material, &BemOptions::default()).expect("solver");
        let probe = solver.solve(&surface, Control::Load(500.0)).expect("solve");
        eprintln!(
            "bem {n}²: {} iterations, residual {:.1e}, approach {:.4} mm",
            probe.iterations,
            probe.residual,
            probe.approach * 1e3
        );
        let p = probe.pressure.clone();
        group.bench_function(format!("operator/{n}"), |b| {
            b.iter(|| solver.displacement(black_box(&p)).expect("operator"))
        });
        group.bench_function(format!("solve/{n}"), |b| {
            b.iter(|| {
                solver
                    .solve(black_box(&surface), Control::Load(500.0))
                    .expect("solve")
            })
        });
    }
    group.finish();
}

criterion_group!(benches, bench_bem);
criterion_main!(benches);
