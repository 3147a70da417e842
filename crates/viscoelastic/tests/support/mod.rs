//! What the viscoelastic tests share: the test tread and the 25 balls.

#![allow(dead_code)] // each test file uses its own part

use tyreroad_contact_law::{HertzLaw, Material};
use tyreroad_multipoint::Problem;
use tyreroad_viscoelastic::{Branch, Prony};

/// The test tread: `E∞` = 2 MPa and two branches (3 MPa, 1 ms; 5 MPa,
/// 20 µs), `ν` = 0.5.
pub fn tread() -> Prony {
    let branches = [(3e6, 1e-3), (5e6, 2e-5)]
        .map(|(modulus, relaxation_time)| Branch {
            modulus,
            relaxation_time,
        })
        .to_vec();
    Prony::new(2e6, branches, 0.5).expect("valid")
}

/// 25 balls of R = 5 mm on a 5 × 5 grid of 8 mm pitch, gaps 0–40 µm in a
/// fixed pattern, Hertz laws at a 1 MPa reference modulus.
pub fn twenty_five_balls() -> Problem<HertzLaw> {
    let reference = Material::new(1e6, 0.5).expect("valid");
    let mut positions = Vec::new();
    let mut gaps = Vec::new();
    for i in 0..5 {
        for j in 0..5 {
            positions.push([8e-3 * i as f64, 8e-3 * j as f64]);
            gaps.push(1e-5 * ((3 * i + 7 * j) % 5) as f64);
        }
    }
    let law = HertzLaw::new(5e-3, reference).expect("valid");
    Problem::new(positions, gaps, vec![law; 25], reference).expect("valid")
}
