//! Asperity fields shared by the benchmarks.
// Each benchmark uses a part of this module.
#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::Problem;

/// The benchmarks' ball law.
pub type Law = PotentialLaw<Sphere>;

/// The paper's rubber with the film (E = 6.54 MPa, ν = 0.5).
pub fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("valid material")
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
pub fn tyre_like_load(n: usize) -> f64 {
    0.2e6 * 9e-6 * n as f64
}
