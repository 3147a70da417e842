//! Across the layers: the multipoint solve of the paper's grid must not depend
//! on how the balls' caps are computed (closed form, table, triangle mesh),
//! beyond the geometric error of each representation.
#![allow(clippy::unwrap_used)]

use std::sync::Arc;

use tyreroad::asperity::{MeshAsperity, MeshBuffers, Sphere, TabulatedCap};
use tyreroad::contact_law::{C_SPHERE, ContactLaw, LocalRule, Material, PotentialLaw};
use tyreroad::multipoint::{Control, Problem, Solution, SolverOptions, solve};

const R: f64 = 5e-3;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

fn grid() -> Vec<[f64; 2]> {
    (0..25)
        .map(|k| [((k % 5) as f64 - 2.0) * 0.01, ((k / 5) as f64 - 2.0) * 0.01])
        .collect()
}

fn solve_with<L: ContactLaw + Sync + Clone>(law: L) -> Solution {
    let problem = Problem::new(grid(), vec![0.0; 25], vec![law; 25], rubber()).unwrap();
    solve(&problem, Control::Load(500.0), &SolverOptions::default()).unwrap()
}

fn max_rel_diff(a: &Solution, b: &Solution) -> f64 {
    a.forces
        .iter()
        .zip(&b.forces)
        .map(|(x, y)| (x - y).abs() / y)
        .fold(0.0, f64::max)
}

#[test]
fn tabulated_sphere_gives_the_closed_form_forces() {
    let sphere = Sphere::new(R).unwrap();
    let exact = solve_with(PotentialLaw::sphere(sphere, rubber()));
    let table = Arc::new(TabulatedCap::from_geometry(&sphere, 0.5 * R, 200).unwrap());
    let tabulated = solve_with(
        PotentialLaw::new(table, rubber(), C_SPHERE, LocalRule::Hertz { radius: R }).unwrap(),
    );
    // 200 nodes interpolate Ω, Σ, Γ to ~1e-5: forces follow to the same order.
    let diff = max_rel_diff(&tabulated, &exact);
    assert!(diff < 1e-4, "table vs closed form: {diff:.2e}");
}

#[test]
fn meshed_sphere_converges_to_the_closed_form_forces() {
    let sphere = Sphere::new(R).unwrap();
    let exact = solve_with(PotentialLaw::sphere(sphere, rubber()));
    let mut previous = f64::INFINITY;
    for subdivisions in [3, 4, 5] {
        let mesh =
            MeshAsperity::from_buffers(&MeshBuffers::icosphere(R, subdivisions).unwrap()).unwrap();
        let table = Arc::new(TabulatedCap::from_geometry(&mesh, 0.5 * R, 200).unwrap());
        let law =
            PotentialLaw::new(table, rubber(), C_SPHERE, LocalRule::Hertz { radius: R }).unwrap();
        let diff = max_rel_diff(&solve_with(law), &exact);
        // Each subdivision quarters the geometric error (docs/asperity.md).
        assert!(
            diff < previous,
            "n = {subdivisions}: {diff:.2e} ≥ {previous:.2e}"
        );
        previous = diff;
    }
    assert!(previous < 5e-3, "icosphere n = 5: {previous:.2e}");
}
