//! Scaling measurements behind docs/performance.md (the criterion version is
//! `benches/scaling.rs` at the workspace root).
//!
//! ```text
//! cargo run --release -p tyreroad-multipoint --example scaling -- solve N [dense|krylov|auto] [threads] [grid|random] [fast_min=K] [coarse_min=K] [krylov_min=K] [leaf=K]
//! cargo run --release -p tyreroad-multipoint --example scaling -- matvec N
//! cargo run --release -p tyreroad-multipoint --example scaling -- plot results.csv out.svg
//! ```
//!
//! `solve` prints one CSV line `N,solver,threads,active,iterations,seconds,peak_rss_mib`
//! (peak RSS from `/proc/self/status`, so run one N per process).

use std::time::Instant;

use plotters::prelude::*;
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::layouts::{Placement, SphereSummitField};
use tyreroad_multipoint::{
    Boussinesq, Control, FastBoussinesq, FastOptions, LinearSolver, Par, Problem, SolverOptions,
    layouts, solve,
};

type Law = PotentialLaw<Sphere>;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("valid material")
}

/// The field of `benches/multipoint.rs`: N balls over a square at 3 mm mean
/// spacing, radii 1–5 mm, heights spread over 0.5 mm.
fn random_field(n: usize, seed: u64) -> Problem<Law> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let field = SphereSummitField {
        placement: Placement::Scattered {
            count: n,
            side: 3e-3 * (n as f64).sqrt(),
        },
        ..SphereSummitField::road_like(n)
    };
    let set = field
        .generate(rubber(), || rng.random::<f64>())
        .expect("field");
    Problem::from_set(set, rubber()).expect("problem")
}

/// As [`random_field`] but with the summits on a 3 mm grid jittered by
/// ±1 mm (no two summits closer than 1 mm): `layouts::road_like_field`.
fn jittered_field(n: usize, seed: u64) -> Problem<Law> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    layouts::road_like_field(n, rubber(), || rng.random::<f64>()).expect("problem")
}

fn peak_rss_mib() -> f64 {
    std::fs::read_to_string("/proc/self/status")
        .ok()
        .and_then(|s| {
            s.lines()
                .find(|l| l.starts_with("VmHWM:"))
                .and_then(|l| l.split_whitespace().nth(1))
                .and_then(|v| v.parse::<f64>().ok())
        })
        .map_or(f64::NAN, |kib| kib / 1024.0)
}

/// CPU time of this process (user + system, s) from `/proc/self/stat`
/// (clock ticks of 10 ms): with one thread on a shared machine it measures
/// the work better than the wall clock.
fn cpu_seconds() -> f64 {
    std::fs::read_to_string("/proc/self/stat")
        .ok()
        .and_then(|s| {
            let rest = s.rsplit_once(')')?.1;
            let f: Vec<&str> = rest.split_whitespace().collect();
            let utime: f64 = f.get(11)?.parse().ok()?;
            let stime: f64 = f.get(12)?.parse().ok()?;
            Some((utime + stime) / 100.0)
        })
        .unwrap_or(f64::NAN)
}

fn par_of(threads: usize) -> Par {
    if threads <= 1 {
        Par::Seq
    } else {
        Par::rayon(threads)
    }
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let arg = |k: usize| args.get(k).map(String::as_str).unwrap_or("");
    match arg(0) {
        "solve" => {
            let n: usize = arg(1).parse().expect("N");
            let solver = match arg(2) {
                "dense" => LinearSolver::Dense,
                "krylov" => LinearSolver::Krylov,
                _ => LinearSolver::Auto,
            };
            let threads: usize = arg(3).parse().unwrap_or(2);
            let problem = if arg(4) == "grid" {
                jittered_field(n, 2006)
            } else {
                random_field(n, 2006)
            };
            let load = 0.2e6 * 9e-6 * n as f64;
            let mut opts = SolverOptions {
                linear_solver: solver,
                par: par_of(threads),
                ..SolverOptions::default()
            };
            // Optional overrides: fast_min=K, coarse_min=K, krylov_min=K, leaf=K.
            for a in args.iter().skip(5) {
                if let Some((k, v)) = a.split_once('=') {
                    let v: usize = v.parse().expect("integer");
                    match k {
                        "fast_min" => opts.fast_operator_min_n = v,
                        "coarse_min" => opts.coarse_start_min_n = v,
                        "krylov_min" => opts.krylov_min_active = v,
                        "leaf" => opts.fast_operator.leaf_size = v,
                        _ => panic!("unknown option {k}"),
                    }
                }
            }
            let t = Instant::now();
            let s = solve(&problem, Control::Load(load), &opts).expect("converges");
            let secs = t.elapsed().as_secs_f64();
            println!(
                "{n},{},{threads},{},{},{secs:.4},{:.1}",
                arg(2),
                s.contact_count(),
                s.iterations,
                peak_rss_mib()
            );
        }
        "matvec" => {
            let n: usize = arg(1).parse().expect("N");
            let problem = jittered_field(n, 2006);
            let f = problem.material().boussinesq_factor();
            let x = vec![1.0; n];
            let mut out = vec![0.0; n];
            // Streaming bandwidth: a = b + s c over 3 × 64 MiB.
            let m = 8 << 20;
            let (b, c) = (vec![1.0_f64; m], vec![2.0_f64; m]);
            let mut a = vec![0.0_f64; m];
            let t = Instant::now();
            for _ in 0..5 {
                a.iter_mut()
                    .zip(b.iter().zip(&c))
                    .for_each(|(a, (b, c))| *a = b + 0.5 * c);
            }
            let bw = 5.0 * 24.0 * m as f64 / t.elapsed().as_secs_f64() / 1e9;
            println!(
                "triad bandwidth (1 thread): {bw:.1} GB/s (checksum {})",
                a[7]
            );
            for threads in [1usize, 2] {
                let par = par_of(threads);
                let exact = Boussinesq::new(problem.positions(), f);
                if n > 30_000 {
                    eprintln!("N = {n}: exact T·x skipped (O(N²))");
                } else {
                    let reps = (2e8 / (n * n) as f64).clamp(1.0, 50.0) as usize;
                    let t = Instant::now();
                    for _ in 0..reps {
                        exact.apply(&x, &mut out, par);
                    }
                    let te = t.elapsed().as_secs_f64() / reps as f64;
                    println!(
                        "N = {n}, {threads} thread(s): exact T·x {:.3} ms ({:.2} G pairs/s, {:.1} GB/s of positions streamed)",
                        te * 1e3,
                        (n * n) as f64 / te / 1e9,
                        (n * n) as f64 * 24.0 / te / 1e9
                    );
                }
                for (order, leaf) in [(6, 48), (10, 48), (10, 133)] {
                    let t = Instant::now();
                    let op = FastBoussinesq::new(
                        problem.positions(),
                        f,
                        FastOptions {
                            order,
                            leaf_size: leaf,
                        },
                    );
                    let tb = t.elapsed().as_secs_f64();
                    let reps = 5;
                    let (t, c) = (Instant::now(), cpu_seconds());
                    for _ in 0..reps {
                        op.apply(&x, &mut out, par);
                    }
                    let tf = t.elapsed().as_secs_f64() / reps as f64;
                    let cf = (cpu_seconds() - c) / reps as f64;
                    println!(
                        "N = {n}, {threads} thread(s): fast T·x order {order} leaf {leaf}: build {:.1} ms, apply {:.3} ms wall, {:.3} ms CPU ({:.1} M summits/s)",
                        tb * 1e3,
                        tf * 1e3,
                        cf * 1e3,
                        n as f64 / tf / 1e6
                    );
                }
            }
        }
        "plot" => {
            let text = std::fs::read_to_string(arg(1)).expect("csv");
            let mut series: Vec<(String, Vec<(f64, f64)>)> = Vec::new();
            for line in text
                .lines()
                .filter(|l| !l.starts_with('N') && !l.is_empty())
            {
                let f: Vec<&str> = line.split(',').collect();
                let key = format!("{} ({} thr.)", f[1], f[2]);
                let pt = (f[0].parse().unwrap_or(1.0), f[5].parse().unwrap_or(1.0));
                match series.iter_mut().find(|(k, _)| *k == key) {
                    Some((_, v)) => v.push(pt),
                    None => series.push((key, vec![pt])),
                }
            }
            let root = SVGBackend::new(arg(2), (720, 480)).into_drawing_area();
            root.fill(&WHITE).expect("draw");
            let mut chart = ChartBuilder::on(&root)
                .caption(
                    "Static multipoint solve, 2-core machine",
                    ("sans-serif", 20),
                )
                .margin(12)
                .x_label_area_size(40)
                .y_label_area_size(60)
                .build_cartesian_2d((10f64..2e5).log_scale(), (1e-5f64..100.0).log_scale())
                .expect("chart");
            chart
                .configure_mesh()
                .x_desc("N asperities")
                .y_desc("solve time (s)")
                .draw()
                .expect("mesh");
            let colours = [RED, BLUE, GREEN, MAGENTA, BLACK];
            for (k, (name, pts)) in series.iter().enumerate() {
                let c = colours[k % colours.len()];
                chart
                    .draw_series(LineSeries::new(pts.clone(), c.stroke_width(2)))
                    .expect("line")
                    .label(name.clone())
                    .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], c));
                chart
                    .draw_series(pts.iter().map(|&p| Circle::new(p, 4, c.filled())))
                    .expect("points");
            }
            chart
                .configure_series_labels()
                .background_style(WHITE.mix(0.8))
                .border_style(BLACK)
                .draw()
                .expect("legend");
            root.present().expect("svg");
        }
        _ => eprintln!(
            "usage: scaling solve N [dense|krylov|auto] [threads] | matvec N | plot in.csv out.svg"
        ),
    }
}
