//! Asperity fields shared by the benchmarks.
// Each benchmark uses a part of this module.
#![allow(dead_code)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::Problem;
use tyreroad::multipoint::layouts::road_like_field;

/// The benchmarks' ball law.
pub type Law = PotentialLaw<Sphere>;

/// The paper's rubber with the film (E = 6.54 MPa, ν = 0.5).
pub fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("valid material")
}

/// N balls at a mean spacing of 3 mm (road-like chipping density), radii
/// 1–5 mm, summit heights spread over 0.5 mm:
/// `tyreroad::multipoint::layouts::road_like_field` drawn from ChaCha8.
pub fn random_field(n: usize, seed: u64) -> Problem<Law> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    road_like_field(n, rubber(), || rng.random::<f64>()).expect("problem")
}

/// A load giving a contact pressure of 0.2 MPa over the field, like a tyre.
pub fn tyre_like_load(n: usize) -> f64 {
    0.2e6 * 9e-6 * n as f64
}
