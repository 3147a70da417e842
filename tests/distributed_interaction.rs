//! The distributed near-pair interaction against the project's BEM on two
//! spheres whose contact patches come close (docs/theory.md §3).
#![allow(clippy::unwrap_used)]

use tyreroad::asperity::Sphere as Ball;
use tyreroad::bem::{self, BemOptions, Grid, Sphere, nearest_labels, spherical_caps};
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Control, Interaction, Problem, SolverOptions, solve};

/// Two 20 mm spheres 5 mm apart, the second 10 µm lower, at 10 N: Hertz
/// radii ≈ 2 mm, so the gap between the patches is about a fifth of their
/// radius sum. Returns the second sphere's share of the load: BEM, point
/// kernel, distributed kernel.
fn shares(separation: f64) -> (f64, f64, f64) {
    let material = Material::new(6.54e6, 0.5).unwrap();
    let (radius, drop, load) = (20e-3, 10e-6, 10.0);
    let positions = vec![[0.0, 0.0], [separation, 0.0]];
    let dx = 5e-5;
    let (nx, ny) = (((separation + 12e-3) / dx) as usize, 240);
    let grid = Grid::new(nx, ny, dx, dx)
        .unwrap()
        .with_origin([-6e-3, -6e-3])
        .unwrap();
    let spheres: Vec<Sphere> = [0.0, drop]
        .iter()
        .zip(&positions)
        .map(|(&d, &c)| Sphere {
            centre: c,
            radius,
            summit: -d,
        })
        .collect();
    let surface = spherical_caps(&grid, &spheres, -radius).unwrap();
    let sol = bem::solve(
        &surface,
        &material,
        bem::Control::Load(load),
        &BemOptions::default(),
    )
    .unwrap();
    let forces = sol
        .force_per_region(&nearest_labels(&grid, &positions))
        .unwrap();
    let bem_share = forces[1] / forces.iter().sum::<f64>();
    let law = PotentialLaw::sphere(Ball::new(radius).unwrap(), material);
    let problem = Problem::new(positions, vec![0.0, drop], vec![law; 2], material).unwrap();
    let share = |interaction| {
        let options = SolverOptions {
            interaction,
            ..SolverOptions::default()
        };
        let s = solve(&problem, Control::Load(load), &options).unwrap();
        s.forces[1] / load
    };
    (
        bem_share,
        share(Interaction::Point),
        share(Interaction::DISTRIBUTED),
    )
}

#[test]
fn close_spheres_share_the_load_as_the_bem_says() {
    // Measured: at 4.5, 5 and 6 mm the BEM gives the lower sphere 47.49,
    // 47.58 and 47.72 % of the load; the point kernel is within 0.02 % of
    // the load of it, the distributed kernel within 0.07 % (its extra
    // coupling of the near pair moves load to the higher sphere). Both are
    // held to 0.1 % of the load, twenty times below the multipoint
    // model's 1.61 % force agreement on the 25-ball case.
    for separation in [4.5e-3, 5e-3, 6e-3] {
        let (bem, point, distributed) = shares(separation);
        eprintln!("{separation:e}: bem {bem:.5} point {point:.5} distributed {distributed:.5}");
        assert!((point - bem).abs() < 1e-3, "point {point} vs BEM {bem}");
        assert!(
            (distributed - bem).abs() < 1e-3,
            "distributed {distributed} vs BEM {bem}"
        );
        // The near pair is coupled more strongly than by the point kernel.
        assert!(distributed < point);
    }
}
