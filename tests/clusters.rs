//! Clusters (docs/theory.md §3) against the project's BEM on two spheres
//! whose contact patches overlap: the merged body's force at a given
//! approach, and the load it carries conserved.
#![allow(clippy::unwrap_used)]

use tyreroad::asperity::Sphere as Ball;
use tyreroad::bem::{self, BemOptions, Grid, Sphere};
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Clusters, Control, Problem, Recovery, SolverOptions, solve};

const RADIUS: f64 = 20e-3;
const DROP: f64 = 10e-6;

fn material() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

/// Two 20 mm spheres `separation` apart, the second 10 µm lower.
fn pair(separation: f64) -> Problem<PotentialLaw<Ball>> {
    let law = PotentialLaw::sphere(Ball::new(RADIUS).unwrap(), material());
    Problem::new(
        vec![[0.0, 0.0], [separation, 0.0]],
        vec![0.0, DROP],
        vec![law; 2],
        material(),
    )
    .unwrap()
}

/// The pair pressed to the approach `approach`: the total force by the
/// BEM, by the point model (clusters off) and by the clustered model, and
/// the clustered model's cluster count.
fn forces(separation: f64, approach: f64) -> (f64, f64, f64, usize) {
    let material = material();
    let (radius, drop) = (RADIUS, DROP);
    let positions = vec![[0.0, 0.0], [separation, 0.0]];
    let dx = 5e-5;
    let (nx, ny) = (((separation + 10e-3) / dx) as usize, 200);
    let grid = Grid::new(nx, ny, dx, dx)
        .unwrap()
        .with_origin([-5e-3, -5e-3])
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
    let surface = bem::spherical_caps(&grid, &spheres, -radius).unwrap();
    let bem = bem::solve(
        &surface,
        &material,
        bem::Control::Approach(approach),
        &BemOptions::default(),
    )
    .unwrap()
    .force;
    let problem = pair(separation);
    let run = |clusters| {
        let options = SolverOptions {
            clusters,
            ..SolverOptions::default()
        };
        solve(&problem, Control::Approach(approach), &options).unwrap()
    };
    let point = run(Clusters::Off);
    let clustered = run(Clusters::Always);
    (
        bem,
        point.total_force(),
        clustered.total_force(),
        clustered.clusters.len(),
    )
}

#[test]
fn two_spheres_with_overlapping_patches_as_one_body_match_the_bem() {
    // Hertz radius at 0.1 mm: 1.41 mm, so the patches overlap below
    // 2.83 mm. Measured (BEM at 0.05 mm cells): clustered −0.7, −1.7 and
    // +2.2 % at 0.5, 1 and 2 mm, where the point model is −29, −9.8 and
    // −1.2 % off; at 3 mm nothing merges and both are the point model
    // (+0.2 %). Held to 3 %, the BEM's own grid error being about 1 %.
    for separation in [0.5e-3, 1e-3, 2e-3, 3e-3] {
        let (bem, point, clustered, n) = forces(separation, 0.1e-3);
        eprintln!(
            "{separation:e}: bem {bem:.5} point {point:.5} ({:+.2} %) clustered {clustered:.5} \
             ({:+.2} %) clusters {n}",
            100.0 * (point / bem - 1.0),
            100.0 * (clustered / bem - 1.0)
        );
        assert!(
            (clustered / bem - 1.0).abs() < 0.03,
            "{separation}: {clustered} vs {bem}"
        );
        assert_eq!(n, usize::from(separation < 2.8e-3));
        if n == 0 {
            assert_eq!(point, clustered);
        } else if separation < 1.41e-3 {
            // Closer than a radius the merged body is nearer the BEM than
            // the point model (at 2 mm the point model is still within
            // 1.2 %, the cluster within 2.2 %).
            assert!((clustered - bem).abs() < (point - bem).abs());
        }
    }
}

#[test]
fn a_cluster_carries_exactly_the_imposed_load() {
    let problem = pair(1e-3);
    let options = SolverOptions {
        clusters: Clusters::Always,
        ..SolverOptions::default()
    };
    for load in [0.5, 2.0, 8.0] {
        let s = solve(&problem, Control::Load(load), &options).unwrap();
        assert_eq!(s.recovery, Recovery::Clustered);
        assert_eq!(s.clusters, vec![vec![0, 1]]);
        assert!((s.total_force() - load).abs() <= 1e-9 * load);
        // The lower sphere carries less, both carry some.
        assert!(s.forces[1] > 0.0 && s.forces[1] < s.forces[0]);
    }
}
