//! Scaling of the static multipoint solve (issue "Solver scaling to 10^5
//! asperities"): solve time against N = 25 … 10⁵ on the road-like random
//! field of `benches/multipoint.rs`, the dense/Krylov crossover, T·x
//! throughput (exact against fast multipole) next to a streaming-bandwidth
//! figure, and thread scaling (`Par::Seq` against `Par::rayon(2)`).
//!
//! Targets on the project's 2-core machine: N = 10⁴ under 2 s, N = 10⁵
//! under 30 s. Results: docs/performance.md. The whole run takes about ten
//! minutes (`cargo bench --bench scaling`; a group alone with e.g.
//! `cargo bench --bench scaling -- scaling/matvec`).

use std::time::Duration;

use criterion::{BenchmarkId, Criterion, Throughput, criterion_group, criterion_main};
use rayon::prelude::*;
use tyreroad::multipoint::{
    Boussinesq, Control, FastBoussinesq, FastOptions, LinearSolver, Par, SolverOptions, solve,
};

#[path = "common/mod.rs"]
mod common;

use common::{random_field, tyre_like_load as load};

fn options(solver: LinearSolver, par: Par) -> SolverOptions {
    SolverOptions {
        linear_solver: solver,
        par,
        ..SolverOptions::default()
    }
}

fn bench_solve_vs_n(c: &mut Criterion) {
    let mut group = c.benchmark_group("scaling/solve_auto_2threads");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(200));
    for n in [25usize, 100, 1000, 10_000, 100_000] {
        let problem = random_field(n, 2006);
        let opts = options(LinearSolver::Auto, Par::rayon(2));
        let s = solve(&problem, Control::Load(load(n)), &opts).expect("converges");
        eprintln!(
            "N = {n}: {} in contact, {} iterations, {} load steps",
            s.contact_count(),
            s.iterations,
            s.load_steps
        );
        if n >= 10_000 {
            // Ten single-solve samples (criterion's minimum): N = 10⁵ takes
            // 15–25 s a solve, so this group alone runs for 3–5 minutes.
            group.sample_size(10);
            group.measurement_time(Duration::from_secs(1));
        }
        group.bench_with_input(BenchmarkId::from_parameter(n), &n, |b, _| {
            b.iter(|| solve(&problem, Control::Load(load(n)), &opts).expect("converges"))
        });
    }
    group.finish();
}

fn bench_crossover(c: &mut Criterion) {
    // Both paths at sizes around `SolverOptions::krylov_min_active` (active
    // count ≈ 0.73 N on this field), 2 threads.
    let mut group = c.benchmark_group("scaling/crossover");
    group.sample_size(10);
    group.warm_up_time(Duration::from_millis(200));
    for n in [1000usize, 1500, 2000, 3000] {
        let problem = random_field(n, 2006);
        for (name, solver) in [
            ("dense", LinearSolver::Dense),
            ("krylov", LinearSolver::Krylov),
        ] {
            let opts = options(solver, Par::rayon(2));
            let s = solve(&problem, Control::Load(load(n)), &opts).expect("converges");
            eprintln!(
                "crossover N = {n} {name}: {} in contact, {} iterations",
                s.contact_count(),
                s.iterations
            );
            group.bench_with_input(BenchmarkId::new(name, n), &n, |b, _| {
                b.iter(|| solve(&problem, Control::Load(load(n)), &opts).expect("converges"))
            });
        }
    }
    group.finish();
}

fn bench_matvec(c: &mut Criterion) {
    // Streaming bandwidth: a = b + s c over 3 × 64 MiB (24 bytes an element).
    let m = 8 << 20;
    let (b, cc) = (vec![1.0_f64; m], vec![2.0_f64; m]);
    let mut a = vec![0.0_f64; m];
    let mut group = c.benchmark_group("scaling/bandwidth");
    group.sample_size(10);
    group.throughput(Throughput::Bytes(24 * m as u64));
    group.bench_function("triad_1thread", |bench| {
        bench.iter(|| {
            a.iter_mut()
                .zip(b.iter().zip(&cc))
                .for_each(|(a, (b, c))| *a = b + 0.5 * c)
        })
    });
    group.bench_function("triad_2threads", |bench| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(2)
            .build()
            .expect("pool");
        bench.iter(|| {
            pool.install(|| {
                a.par_iter_mut()
                    .zip(b.par_iter().zip(&cc))
                    .for_each(|(a, (b, c))| *a = b + 0.5 * c)
            })
        })
    });
    group.finish();

    let mut group = c.benchmark_group("scaling/matvec");
    group.sample_size(10);
    for n in [10_000usize, 100_000] {
        let problem = random_field(n, 2006);
        let f = problem.material().boussinesq_factor();
        let x = vec![1.0; n];
        let mut out = vec![0.0; n];
        group.throughput(Throughput::Elements(n as u64));
        for (label, par) in [("seq", Par::Seq), ("rayon2", Par::rayon(2))] {
            if n <= 10_000 {
                let exact = Boussinesq::new(problem.positions(), f);
                group.bench_with_input(
                    BenchmarkId::new(format!("exact_{label}"), n),
                    &n,
                    |b, _| b.iter(|| exact.apply(&x, &mut out, par)),
                );
            }
            // Order 6 on 48-summit leaves: the Krylov products; order 10 on
            // 133-summit leaves: the solver's residual operator.
            for (order, leaf_size) in [(6usize, 48usize), (10, 133)] {
                let op =
                    FastBoussinesq::new(problem.positions(), f, FastOptions { order, leaf_size });
                group.bench_with_input(
                    BenchmarkId::new(format!("fast{order}_{label}"), n),
                    &n,
                    |b, _| b.iter(|| op.apply(&x, &mut out, par)),
                );
            }
        }
    }
    group.finish();
}

fn bench_threads(c: &mut Criterion) {
    let mut group = c.benchmark_group("scaling/threads");
    group.sample_size(10);
    let n = 10_000;
    let problem = random_field(n, 2006);
    for (label, par) in [("seq", Par::Seq), ("rayon2", Par::rayon(2))] {
        let opts = options(LinearSolver::Auto, par);
        group.bench_with_input(BenchmarkId::new(label, n), &n, |b, _| {
            b.iter(|| solve(&problem, Control::Load(load(n)), &opts).expect("converges"))
        });
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_solve_vs_n,
    bench_crossover,
    bench_matvec,
    bench_threads
);
criterion_main!(benches);
