//! Clusters (docs/theory.md §3): overlapping contacts merged into one body
//! where the point-force model's load path folds.
#![allow(clippy::unwrap_used)]

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{ContactLaw, Material, PotentialLaw};
use tyreroad_multipoint::*;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

fn folding_layout() -> Problem<PotentialLaw<Sphere>> {
    let mut seed = 1;
    layouts::folding_field(rubber(), || lcg(&mut seed)).unwrap()
}

/// Every member's force is its law's at the cluster's shared depth less its
/// offset (up to the one scale that makes the members sum to the cluster's
/// force), and the load is conserved.
fn check_members(problem: &Problem<PotentialLaw<Sphere>>, s: &Solution, load: f64) {
    assert!(
        (s.total_force() - load).abs() <= 1e-9 * load,
        "load {} vs {load}",
        s.total_force()
    );
    for (i, (&p, &d)) in s.forces.iter().zip(&s.depths).enumerate() {
        assert!(p >= 0.0);
        let law = problem.laws()[i].force(d);
        assert!(
            (p - law).abs() <= 1e-8 * load,
            "asperity {i}: {p} vs law {law}"
        );
    }
    // Members of one cluster share one depth less their gap offsets.
    for c in &s.clusters {
        let shared = |m: usize| s.depths[m] + problem.gaps()[m];
        for &m in &c[1..] {
            assert!((shared(m) - shared(c[0])).abs() <= 1e-15 + 1e-12 * shared(c[0]).abs());
        }
    }
}

#[test]
fn the_folding_layout_converges_once_its_overlapping_contacts_are_one_body() {
    // Regression: at 100 N the point-force model's path folds before the
    // load on this layout (tests/recovery.rs); merged, it converges.
    let problem = folding_layout();
    let s = solve(&problem, Control::Load(100.0), &SolverOptions::default()).unwrap();
    assert_eq!(s.recovery, Recovery::Clustered);
    assert_eq!(s.convergence, Convergence::Converged);
    assert!(!s.clusters.is_empty());
    let merged: usize = s.clusters.iter().map(Vec::len).sum();
    eprintln!(
        "clusters {:?}, merged {merged}, iterations {}",
        s.clusters, s.iterations
    );
    check_members(&problem, &s, 100.0);
}

#[test]
fn clusters_leave_a_solve_without_overlaps_bit_for_bit() {
    // Three 5 mm balls 10 mm apart at 30 N: patches of ~1.4 mm, far apart.
    let ball = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), rubber());
    let problem = Problem::new(
        vec![[-0.01, 0.0], [0.0, 0.0], [0.01, 0.0]],
        vec![0.0, 5e-5, 0.0],
        vec![ball.clone(), ball.clone(), ball],
        rubber(),
    )
    .unwrap();
    let off = SolverOptions {
        clusters: Clusters::Off,
        ..SolverOptions::default()
    };
    let always = SolverOptions {
        clusters: Clusters::Always,
        ..SolverOptions::default()
    };
    let a = solve(&problem, Control::Load(30.0), &off).unwrap();
    let b = solve(&problem, Control::Load(30.0), &always).unwrap();
    assert_eq!(a, b);
    assert!(b.clusters.is_empty());
}

#[test]
fn always_merges_overlapping_contacts_of_a_converged_solve() {
    // Below the fold (50 N) the point model converges with overlapping
    // patches; `Always` merges them and conserves the load.
    let problem = folding_layout();
    let always = SolverOptions {
        clusters: Clusters::Always,
        ..SolverOptions::default()
    };
    let s = solve(&problem, Control::Load(50.0), &always).unwrap();
    assert_eq!(s.recovery, Recovery::Clustered);
    let contacts = s.local_contacts(&problem);
    let pairs = overlapping_contacts(problem.positions(), &contacts);
    // No overlap is left between two different bodies.
    let body = |i: usize| s.clusters.iter().position(|c| c.contains(&i));
    for (i, j) in pairs {
        assert!(
            body(i).is_some() && body(i) == body(j),
            "{i} and {j} overlap"
        );
    }
    check_members(&problem, &s, 50.0);
}
