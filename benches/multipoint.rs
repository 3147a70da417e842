//! Static multipoint solves: the paper's 25 balls, and random ball fields of
//! N = 100 and N = 1000 summits with random radii and heights.
//!
//! Targets (issue 2): 25 balls under 100 µs, N = 1000 under 0.5 s on the
//! project's 2-core machine.

use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};

type Law = PotentialLaw<Sphere>;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("valid material")
}

fn paper_grid() -> Problem<Law> {
    let ball = PotentialLaw::sphere(Sphere::new(5e-3).expect("radius"), rubber());
    let positions: Vec<[f64; 2]> = (0..25)
        .map(|k| [((k % 5) as f64 - 2.0) * 0.01, ((k / 5) as f64 - 2.0) * 0.01])
        .collect();
    Problem::new(positions, vec![0.0; 25], vec![ball; 25], rubber()).expect("problem")
}

/// N balls at a mean spacing of 3 mm (road-like chipping density), radii
/// 1–5 mm, summit heights spread over 0.5 mm.
pub fn random_field(n: usize, seed: u64) -> Problem<Law> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    // Chippings do not overlap: summits on a 3 mm grid jittered by ±1 mm (a
    // uniform scatter puts summits microns apart, where the point-force
    // coupling 1/r swamps the laws and the model itself breaks down).
    let columns = (n as f64).sqrt().ceil() as usize;
    let positions = (0..n)
        .map(|k| {
            let (i, j) = ((k % columns) as f64, (k / columns) as f64);
            [
                3e-3 * i + 2e-3 * (rng.random::<f64>() - 0.5),
                3e-3 * j + 2e-3 * (rng.random::<f64>() - 0.5),
            ]
        })
        .collect();
    let heights: Vec<f64> = (0..n).map(|_| rng.random::<f64>() * 5e-4).collect();
    let laws = (0..n)
        .map(|_| {
            let r = 1e-3 + 4e-3 * rng.random::<f64>();
            PotentialLaw::sphere(Sphere::new(r).expect("radius"), rubber())
        })
        .collect();
    Problem::from_heights(positions, &heights, laws, rubber()).expect("problem")
}

/// A load giving a contact pressure of 0.2 MPa over the field, like a tyre.
fn tyre_like_load(n: usize) -> f64 {
    0.2e6 * 9e-6 * n as f64
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
