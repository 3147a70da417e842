//! The multipoint solver against single-asperity laws, symmetry, balance and
//! the defining equations themselves.
#![allow(clippy::unwrap_used)]

use tyreroad_asperity::{Cone, Sphere};
use tyreroad_contact_law::{ContactLaw, LocalContact, Material, PotentialLaw, PressureProfile};
use tyreroad_multipoint::*;

type SphereLaw = PotentialLaw<Sphere>;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

fn ball(r: f64) -> SphereLaw {
    PotentialLaw::sphere(Sphere::new(r).unwrap(), rubber())
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// The paper's 5 × 5 grid of R = 5 mm balls at 10 mm pitch, coplanar.
fn paper_grid() -> Problem<SphereLaw> {
    let mut positions = Vec::new();
    for j in -2..=2 {
        for i in -2..=2 {
            positions.push([i as f64 * 0.01, j as f64 * 0.01]);
        }
    }
    let n = positions.len();
    Problem::new(positions, vec![0.0; n], vec![ball(5e-3); n], rubber()).unwrap()
}

/// Deterministic pseudo-random numbers in [0, 1) (no RNG dependency needed).
fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// Checks the defining equations directly, independently of the solver.
fn assert_satisfies_equations<L: ContactLaw>(problem: &Problem<L>, s: &Solution, tol: f64) {
    let f = problem.material().boussinesq_factor();
    let pos = problem.positions();
    let scale = s.total_force();
    for i in 0..problem.len() {
        let u: f64 = (0..problem.len())
            .filter(|&j| j != i)
            .map(|j| {
                let r = ((pos[i][0] - pos[j][0]).powi(2) + (pos[i][1] - pos[j][1]).powi(2)).sqrt();
                f * s.forces[j] / r
            })
            .sum();
        let delta = s.approach - problem.gaps()[i] - u;
        assert!((delta - s.depths[i]).abs() <= 1e-12 * s.approach.abs().max(1e-9));
        let law = problem.laws()[i].force(delta);
        assert!(
            (s.forces[i] - law).abs() <= tol * scale,
            "asperity {i}: P = {}, law = {law}",
            s.forces[i]
        );
        assert!(s.forces[i] >= 0.0);
    }
}

#[test]
fn one_asperity_equals_its_law() {
    let law = ball(5e-3);
    let problem = Problem::new(vec![[0.0, 0.0]], vec![0.0], vec![law.clone()], rubber()).unwrap();
    let s = solve(&problem, Control::Load(20.0), &SolverOptions::default()).unwrap();
    assert!(rel(s.forces[0], 20.0) < 1e-12);
    assert!(rel(law.force(s.approach), 20.0) < 1e-10);
    let back = solve(
        &problem,
        Control::Approach(s.approach),
        &SolverOptions::default(),
    )
    .unwrap();
    assert!(rel(back.forces[0], 20.0) < 1e-10);
}

#[test]
fn two_asperities_far_apart_act_independently() {
    let (a, b) = (ball(5e-3), ball(2e-3));
    let d0 = 1e-4;
    let problem = Problem::new(
        vec![[0.0, 0.0], [1e3, 0.0]],
        vec![0.0, 2e-5],
        vec![a.clone(), b.clone()],
        rubber(),
    )
    .unwrap();
    let s = solve(&problem, Control::Approach(d0), &SolverOptions::default()).unwrap();
    // At 1 km the coupling displaces each summit by ~1e-11 of δ: independent.
    assert!(rel(s.forces[0], a.force(d0)) < 1e-6);
    assert!(rel(s.forces[1], b.force(d0 - 2e-5)) < 1e-6);
}

#[test]
fn paper_grid_is_symmetric_and_balanced() {
    let problem = paper_grid();
    for load in [289.0, 355.0, 419.0, 500.0] {
        let s = solve(&problem, Control::Load(load), &SolverOptions::default()).unwrap();
        assert!(rel(s.total_force(), load) < 1e-10, "load balance");
        let at = |i: i32, j: i32| s.forces[((j + 2) * 5 + (i + 2)) as usize];
        for i in -2..=2 {
            for j in -2..=2 {
                let p = at(i, j);
                for q in [at(-i, j), at(i, -j), at(j, i), at(-j, -i)] {
                    assert!((p - q).abs() <= 1e-9 * load, "symmetry");
                }
            }
        }
        // Interaction unloads the centre: corner > edge > centre.
        assert!(at(2, 2) > at(2, 0) && at(2, 0) > at(0, 0));
        assert_satisfies_equations(&problem, &s, 1e-10);
    }
}

#[test]
fn load_and_displacement_control_agree() {
    let mut seed = 7;
    let n = 60;
    let positions: Vec<[f64; 2]> = (0..n)
        .map(|_| [lcg(&mut seed) * 0.05, lcg(&mut seed) * 0.05])
        .collect();
    let gaps: Vec<f64> = (0..n).map(|_| lcg(&mut seed) * 2e-4).collect();
    let laws: Vec<SphereLaw> = (0..n).map(|_| ball(1e-3 + 4e-3 * lcg(&mut seed))).collect();
    let problem = Problem::new(positions, gaps, laws, rubber()).unwrap();
    let by_load = solve(&problem, Control::Load(150.0), &SolverOptions::default()).unwrap();
    let by_approach = solve(
        &problem,
        Control::Approach(by_load.approach),
        &SolverOptions::default(),
    )
    .unwrap();
    assert!(rel(by_approach.total_force(), 150.0) < 1e-9);
    for (a, b) in by_load.forces.iter().zip(&by_approach.forces) {
        assert!((a - b).abs() <= 1e-9 * 150.0);
    }
    assert_satisfies_equations(&problem, &by_load, 1e-10);
}

#[test]
fn asperities_out_of_contact_carry_exactly_zero() {
    // The middle ball sits 1 mm lower than its neighbours: out of reach.
    let problem = Problem::new(
        vec![[-0.01, 0.0], [0.0, 0.0], [0.01, 0.0]],
        vec![0.0, 1e-3, 0.0],
        vec![ball(5e-3); 3],
        rubber(),
    )
    .unwrap();
    let s = solve(&problem, Control::Load(40.0), &SolverOptions::default()).unwrap();
    assert_eq!(s.forces[1], 0.0);
    assert!(!s.in_contact(1) && s.depths[1] < 0.0);
    assert_eq!(s.contact_count(), 2);
    assert!(rel(s.forces[0], 20.0) < 1e-10);
}

#[test]
fn dense_random_layout_converges_from_a_cold_start() {
    // 400 balls at 1.5 mm pitch with heights spread over 0.3 mm, pressed hard:
    // strong coupling, many contacts entering during the solve.
    let mut seed = 42;
    let problem = layouts::dense_sphere_grid(rubber(), || lcg(&mut seed)).unwrap();
    for load in [1.0, 50.0, 400.0] {
        let s = solve(&problem, Control::Load(load), &SolverOptions::default()).unwrap();
        assert!(rel(s.total_force(), load) < 1e-10);
        assert!(s.contact_count() > 0 && s.contact_count() <= problem.len());
        assert_satisfies_equations(&problem, &s, 1e-9);
    }
}

#[test]
fn mixed_shapes_through_trait_objects() {
    let m = rubber();
    let laws: Vec<Box<dyn ContactLaw + Sync>> = vec![
        Box::new(ball(5e-3)),
        Box::new(PotentialLaw::cone(Cone::new(1.3).unwrap(), m)),
    ];
    let problem = Problem::new(vec![[0.0, 0.0], [0.01, 0.0]], vec![0.0, 0.0], laws, m).unwrap();
    let s = solve(&problem, Control::Load(10.0), &SolverOptions::default()).unwrap();
    assert!(rel(s.total_force(), 10.0) < 1e-10);
    assert_satisfies_equations(&problem, &s, 1e-10);
}

#[test]
fn warm_start_converges_in_fewer_iterations() {
    let problem = paper_grid();
    let opts = SolverOptions::default();
    let cold = solve(&problem, Control::Load(400.0), &opts).unwrap();
    let warm = solve_from(&problem, Control::Load(419.0), &opts, Some(&cold)).unwrap();
    let direct = solve(&problem, Control::Load(419.0), &opts).unwrap();
    for (a, b) in warm.forces.iter().zip(&direct.forces) {
        assert!((a - b).abs() < 1e-9 * 419.0);
    }
    assert!(warm.iterations <= direct.iterations);
}

#[test]
fn zero_load_and_short_approach_give_no_contact() {
    let problem = paper_grid();
    let s = solve(&problem, Control::Load(0.0), &SolverOptions::default()).unwrap();
    assert!(s.forces.iter().all(|&p| p == 0.0));
    let s = solve(
        &problem,
        Control::Approach(-1e-4),
        &SolverOptions::default(),
    )
    .unwrap();
    assert_eq!(s.contact_count(), 0);
}

#[test]
fn bad_input_is_refused_with_a_clear_error() {
    let m = rubber();
    let err = Problem::new(
        vec![[0.0, 0.0], [0.0, 0.0]],
        vec![0.0; 2],
        vec![ball(1e-3); 2],
        m,
    )
    .unwrap_err();
    assert_eq!(
        err,
        SolveError::CoincidentSummits {
            first: 0,
            second: 1
        }
    );
    assert!(Problem::new(vec![[f64::NAN, 0.0]], vec![0.0], vec![ball(1e-3)], m).is_err());
    assert!(Problem::new(vec![[0.0, 0.0]], vec![f64::INFINITY], vec![ball(1e-3)], m).is_err());
    assert!(Problem::new(vec![[0.0, 0.0]], vec![0.0, 1.0], vec![ball(1e-3)], m).is_err());
    assert!(Problem::<SphereLaw>::new(vec![], vec![], vec![], m).is_err());
    assert!(Problem::from_heights(vec![[0.0, 0.0]], &[f64::NAN], vec![ball(1e-3)], m).is_err());
    let problem = paper_grid();
    let opts = SolverOptions::default();
    assert!(solve(&problem, Control::Load(-1.0), &opts).is_err());
    assert!(solve(&problem, Control::Load(f64::NAN), &opts).is_err());
    assert!(solve(&problem, Control::Approach(f64::INFINITY), &opts).is_err());
    let message = solve(&problem, Control::Load(-1.0), &opts)
        .unwrap_err()
        .to_string();
    assert!(message.contains("load"), "{message}");
}

#[test]
fn non_convergence_is_reported_with_its_residual() {
    let problem = paper_grid();
    // Clusters off: the last recovery would merge overlapping contacts and
    // solve a different (reduced) problem, this test is about the report.
    let opts = SolverOptions {
        max_iterations: 1,
        max_load_steps: 2,
        clusters: Clusters::Off,
        ..SolverOptions::default()
    };
    match solve(&problem, Control::Load(500.0), &opts) {
        Err(SolveError::NotConverged {
            iterations,
            residual,
            ..
        }) => {
            assert!(iterations >= 1);
            assert!(residual > 1e-11 && residual.is_finite());
        }
        other => panic!("expected non-convergence, got {other:?}"),
    }
}

#[test]
fn pressure_map_integrates_to_the_total_force() {
    let problem = paper_grid();
    let s = solve(&problem, Control::Load(500.0), &SolverOptions::default()).unwrap();
    let contacts = s.local_contacts(&problem);
    // 1200² cells of 50 µm covering [−0.03, 0.03]², centres half a cell in.
    let grid = Grid::new(1200, 1200, 5e-5, 5e-5)
        .and_then(|g| g.with_origin([-0.03 + 2.5e-5, -0.03 + 2.5e-5]))
        .unwrap();
    let map = pressure_map(problem.positions(), &contacts, &grid).unwrap();
    let total: f64 = map.integral();
    assert!(rel(total, 500.0) < 2e-3, "integrated {total}");
    // Hertz radius of the corner ball from its force.
    let (p, r) = (s.forces[0], 5e-3);
    let a = (0.75 * p * r / rubber().reduced_modulus()).cbrt();
    assert!(rel(contacts[0].radius, a) < 1e-12);
}

/// Regression (adversarial run of the layer crates, 2026-11-30): a
/// negative force gave negative pressures, a NaN position an empty map,
/// both as maps. Each is refused naming the contact.
#[test]
fn a_pressure_map_of_contacts_no_solve_gives_is_refused() {
    let grid = Grid::new(20, 20, 1e-4, 1e-4).unwrap();
    let good = LocalContact {
        force: 1.0,
        radius: 5e-4,
        profile: PressureProfile::Hertz,
    };
    assert!(pressure_map(&[[1e-3, 1e-3]], &[good], &grid).is_ok());
    let cases = [
        (
            [1e-3, 1e-3],
            LocalContact {
                force: -1.0,
                ..good
            },
        ),
        ([f64::NAN, 1e-3], good),
        (
            [1e-3, 1e-3],
            LocalContact {
                radius: f64::INFINITY,
                ..good
            },
        ),
    ];
    for (position, contact) in cases {
        match pressure_map(&[position], &[contact], &grid) {
            Err(SolveError::InvalidInput(m)) => assert!(m.contains("contact 0"), "{m}"),
            other => panic!("{position:?} {contact:?}: {:?}", other.map(|_| ())),
        }
    }
}

/// A Hertz-like law `P = a δ^{3/2}` that turns 30 times stiffer past
/// `δ_k`: continuous `P`, a jump of `k`, like a tabulated law at a node or
/// at a ramp's end.
struct KinkedLaw {
    a: f64,
    kink: f64,
}

impl KinkedLaw {
    const RATIO: f64 = 30.0;
}

impl ContactLaw for KinkedLaw {
    fn evaluate(&self, depth: f64) -> tyreroad_contact_law::LawPoint {
        let (force, stiffness) = if !(depth > 0.0) {
            (0.0, 0.0)
        } else if depth <= self.kink {
            (self.a * depth.powf(1.5), 1.5 * self.a * depth.sqrt())
        } else {
            let k = Self::RATIO * 1.5 * self.a * self.kink.sqrt();
            (self.a * self.kink.powf(1.5) + k * (depth - self.kink), k)
        };
        tyreroad_contact_law::LawPoint { force, stiffness }
    }

    fn local_contact(&self, force: f64, _depth: f64) -> tyreroad_contact_law::LocalContact {
        tyreroad_contact_law::LocalContact {
            force,
            radius: 0.0,
            profile: tyreroad_contact_law::PressureProfile::Hertz,
        }
    }
}

#[test]
fn solution_at_a_law_kink_converges_at_the_default_tolerance() {
    // Five coupled asperities 30 mm apart; the gaps are built so that the
    // exact solution puts asperity 2 exactly on its kink and the others on
    // the smooth parts of their laws below it. (Soft laws and a wide pitch
    // keep diag(1/k) + T positive definite even past a kink, so the
    // solution is unique.) A tangent Newton step taken from either side of
    // the kink mispredicts that contact's force change 30-fold. (This small
    // case converges with or without the secant corrections; the stall they
    // cure needs a dense layout: tests/texture_rolling.rs at the root.)
    let m = rubber();
    let a = 2e5;
    let kink = 2e-4;
    let positions: Vec<[f64; 2]> = (0..5).map(|i| [i as f64 * 3e-2, 0.0]).collect();
    let depths = [1.5e-4, 1.8e-4, kink, 1.2e-4, 1.9e-4];
    let laws: Vec<KinkedLaw> = (0..5).map(|_| KinkedLaw { a, kink }).collect();
    let forces: Vec<f64> = depths.iter().zip(&laws).map(|(&d, l)| l.force(d)).collect();
    let mut u = vec![0.0; 5];
    Boussinesq::new(&positions, m.boussinesq_factor()).apply(&forces, &mut u, Par::Seq);
    let approach = 1e-3;
    let gaps: Vec<f64> = (0..5).map(|i| approach - depths[i] - u[i]).collect();
    let problem = Problem::new(positions, gaps, laws, m).unwrap();
    let total: f64 = forces.iter().sum();
    for control in [Control::Approach(approach), Control::Load(total)] {
        let s = solve(&problem, control, &SolverOptions::default()).unwrap();
        assert!(s.residual <= 1e-11, "{control:?}: {}", s.residual);
        for (got, want) in s.forces.iter().zip(&forces) {
            assert!(
                rel(*got, *want) < 1e-9,
                "{control:?}: {:?} vs {forces:?}",
                s.forces
            );
        }
        assert!((s.approach - approach).abs() < 1e-12, "{}", s.approach);
    }
}

#[test]
fn overlapping_contacts_are_the_pairs_whose_radii_exceed_their_spacing() {
    // The paper's grid at 500 N: radii ≈ 1.8–2.3 mm at a 10 mm pitch.
    let grid = paper_grid();
    let s = solve(&grid, Control::Load(500.0), &SolverOptions::default()).unwrap();
    let contacts = s.local_contacts(&grid);
    assert!(overlapping_contacts(grid.positions(), &contacts).is_empty());

    // Balls R = 5 mm at a 3 mm pitch pressed hard: Hertz radii of 2–3 mm.
    let positions: Vec<[f64; 2]> = (0..4).map(|i| [i as f64 * 3e-3, 0.0]).collect();
    let close = Problem::new(positions, vec![0.0; 4], vec![ball(5e-3); 4], rubber()).unwrap();
    let s = solve(&close, Control::Load(60.0), &SolverOptions::default()).unwrap();
    let contacts = s.local_contacts(&close);
    let pairs = overlapping_contacts(close.positions(), &contacts);
    assert!(
        pairs.contains(&(0, 1)) && pairs.contains(&(1, 2)),
        "{pairs:?}"
    );

    // Against the brute-force O(N²) search on a random field of radii.
    let mut seed = 7;
    let positions: Vec<[f64; 2]> = (0..300)
        .map(|_| [0.1 * lcg(&mut seed), 0.1 * lcg(&mut seed)])
        .collect();
    let contacts: Vec<tyreroad_contact_law::LocalContact> = (0..300)
        .map(|_| tyreroad_contact_law::LocalContact {
            force: if lcg(&mut seed) < 0.8 { 1.0 } else { 0.0 },
            radius: 4e-3 * lcg(&mut seed),
            profile: tyreroad_contact_law::PressureProfile::Hertz,
        })
        .collect();
    let mut brute = Vec::new();
    for i in 0..300 {
        for j in i + 1..300 {
            let (a, b) = (&contacts[i], &contacts[j]);
            let d2 = (positions[i][0] - positions[j][0]).powi(2)
                + (positions[i][1] - positions[j][1]).powi(2);
            if a.force > 0.0 && b.force > 0.0 && d2 < (a.radius + b.radius).powi(2) {
                brute.push((i, j));
            }
        }
    }
    assert!(brute.len() > 20, "{}", brute.len());
    assert_eq!(overlapping_contacts(&positions, &contacts), brute);
}

/// Regression (adversarial run of the Python bindings, 2026-11-30): an
/// approach of 1e160 m on one ball returned an infinite force marked
/// converged with a residual of 0, and 1e300 m on three balls depths of
/// −∞ and a NaN residual, still "converged". A solve that ends on numbers
/// that are not finite is an error naming the first of them; an approach
/// the law holds (10 µm, δ/R = 2e-3) still solves, to Hertz's force (the
/// paper's c is 0.23 % stiffer).
#[test]
fn a_solution_that_is_not_finite_is_an_error_not_converged() {
    let one = Problem::new(vec![[0.0, 0.0]], vec![0.0], vec![ball(5e-3)], rubber()).unwrap();
    let options = SolverOptions::default();
    let err = solve(&one, Control::Approach(1e160), &options).unwrap_err();
    assert!(
        matches!(&err, SolveError::NotFinite(what) if what.starts_with("force 0 = inf")),
        "{err}"
    );
    let three = Problem::new(
        vec![[0.0, 0.0], [0.01, 0.0], [0.0, 0.01]],
        vec![0.0; 3],
        vec![ball(5e-3); 3],
        rubber(),
    )
    .unwrap();
    let err = solve(&three, Control::Approach(1e300), &options).unwrap_err();
    assert!(matches!(err, SolveError::NotFinite(_)), "{err}");
    let s = solve(&one, Control::Approach(1e-5), &options).unwrap();
    let hertz = 4.0 / 3.0 * rubber().reduced_modulus() * (5e-3f64).sqrt() * 1e-5f64.powf(1.5);
    assert!(
        rel(s.forces[0], hertz) < 0.005,
        "{} vs {hertz}",
        s.forces[0]
    );
}

/// Regression (adversarial run of the Python bindings, 2026-11-30): three
/// summits 1e-302 m apart passed the coincidence check (relative to the
/// layout's own size) while `r²` underflowed to 0 in the coupling: solved
/// as uncoupled balls. They are coincident summits now.
#[test]
fn summits_closer_than_the_coupling_can_hold_are_coincident() {
    let result = Problem::new(
        vec![[0.0, 0.0], [1e-302, 0.0], [0.0, 1e-302]],
        vec![0.0; 3],
        vec![ball(5e-3); 3],
        rubber(),
    );
    assert!(
        matches!(result, Err(SolveError::CoincidentSummits { .. })),
        "{:?}",
        result.err()
    );
}

/// Regression (adversarial run of the layer crates, 2026-11-30): summits
/// at ±1e308 m overflowed the layout's extent to ∞, and the coincidence
/// check then took them for one point ("summits 0 and 1 coincide").
#[test]
fn summits_at_the_ends_of_the_floating_range_are_not_coincident() {
    let result = Problem::new(
        vec![[-1e308, 0.0], [1e308, 0.0]],
        vec![0.0; 2],
        vec![ball(5e-3); 2],
        rubber(),
    );
    assert!(result.is_ok(), "{:?}", result.err());
    // And a real coincidence among them is still found.
    let result = Problem::new(
        vec![[-1e308, 0.0], [1e308, 0.0], [1e308, 0.0]],
        vec![0.0; 3],
        vec![ball(5e-3); 3],
        rubber(),
    );
    assert!(matches!(
        result,
        Err(SolveError::CoincidentSummits {
            first: 1,
            second: 2
        })
    ));
}

/// Regression (adversarial run of the Python bindings, 2026-11-30): a
/// summit 1e300 m below two others made the solve fail with "asperity 0:
/// position [NaN, NaN] is not finite", a message about positions the user
/// never gave wrong: the clusters' recovery placed a body by forces that
/// had overflowed. The solve's own failure is reported, or a finite answer.
#[test]
fn an_overflowing_gap_is_not_reported_as_a_bad_position() {
    let problem = Problem::from_heights(
        vec![[0.0, 0.0], [0.01, 0.0], [0.0, 0.01]],
        &[0.0, -1e300, 0.0],
        vec![ball(5e-3); 3],
        rubber(),
    )
    .unwrap();
    match solve(&problem, Control::Load(1.0), &SolverOptions::default()) {
        Ok(s) => assert!(s.forces.iter().all(|f| f.is_finite()), "{:?}", s.forces),
        Err(e) => assert!(!e.to_string().contains("position"), "{e}"),
    }
}
