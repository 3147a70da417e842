//! The potential law against its closed-form limits, and the law invariants.
#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;

use proptest::prelude::*;
use tyreroad_asperity::{CapGeometry, Cone, EllipticParaboloid, MeshAsperity, MeshBuffers, Sphere};
use tyreroad_contact_law::*;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

#[test]
fn exact_constants_are_the_closed_forms() {
    assert!(rel(C_HERTZ_EXACT, 2.0 / PI.powf(1.5)) < 1e-15);
    assert!(rel(C_SNEDDON_EXACT, 45.0 / (4.0 * 2f64.sqrt() * PI.powf(2.5))) < 1e-15);
}

#[test]
fn sphere_law_with_hertz_constant_tends_to_hertz() {
    let r = 5e-3;
    let law = PotentialLaw::sphere(Sphere::new(r).unwrap(), rubber())
        .with_constant(C_HERTZ_EXACT)
        .unwrap();
    let hertz = HertzLaw::new(r, rubber()).unwrap();
    for ratio in [1e-8, 1e-7] {
        let d = ratio * r;
        let (p, h) = (law.evaluate(d), hertz.evaluate(d));
        assert!(
            rel(p.force, h.force) < 1e-6,
            "δ/R = {ratio}: P off by {}",
            rel(p.force, h.force)
        );
        assert!(rel(p.stiffness, h.stiffness) < 1e-6);
    }
    // Away from the limit the exact cap departs from Hertz's paraboloid at O(δ/R).
    let d = 0.02 * r;
    let deviation = rel(law.force(d), hertz.force(d));
    assert!(deviation > 1e-4 && deviation < 0.05, "{deviation}");
}

#[test]
fn paper_sphere_constant_is_within_a_quarter_percent_of_hertz() {
    let law = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), rubber());
    let hertz = HertzLaw::new(5e-3, rubber()).unwrap();
    let d = 1e-9;
    assert!(rel(law.force(d), hertz.force(d) * C_SPHERE / C_HERTZ_EXACT) < 1e-6);
    assert!(rel(law.force(d), hertz.force(d)) < 2.5e-3);
}

#[test]
fn cone_law_with_sneddon_constant_is_sneddon_at_every_depth() {
    for alpha in [0.3, 1.0, 1.4] {
        let law = PotentialLaw::cone(Cone::new(alpha).unwrap(), rubber())
            .with_constant(C_SNEDDON_EXACT)
            .unwrap();
        let sneddon = SneddonLaw::new(alpha, rubber()).unwrap();
        for d in [1e-7, 1e-4, 1e-2] {
            let (p, s) = (law.evaluate(d), sneddon.evaluate(d));
            assert!(rel(p.force, s.force) < 1e-12);
            assert!(rel(p.stiffness, s.stiffness) < 1e-12);
        }
    }
}

#[test]
fn stiffness_agrees_with_finite_differences() {
    let m = rubber();
    let laws: Vec<Box<dyn ContactLaw>> = vec![
        Box::new(PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), m)),
        Box::new(PotentialLaw::cone(Cone::new(1.1).unwrap(), m)),
        Box::new(PotentialLaw::paraboloid(
            EllipticParaboloid::new(2e-3, 9e-3).unwrap(),
            m,
        )),
        Box::new(HertzLaw::new(3e-3, m).unwrap()),
        Box::new(SneddonLaw::new(0.7, m).unwrap()),
    ];
    for law in &laws {
        for d in [1e-6, 1e-4, 1e-3, 3e-3] {
            let h = d * 1e-6;
            let fd = (law.force(d + h) - law.force(d - h)) / (2.0 * h);
            let k = law.evaluate(d).stiffness;
            assert!(rel(k, fd) < 1e-6, "δ = {d}: k = {k}, FD = {fd}");
        }
    }
}

#[test]
fn force_is_zero_without_interpenetration() {
    let law = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), rubber());
    for d in [0.0, -1e-3, f64::NAN, f64::NEG_INFINITY] {
        assert_eq!(law.evaluate(d), LawPoint::default());
    }
    assert_eq!(law.local_contact(0.0, 0.0), LocalContact::NONE);
    // Tiny caps must not under/overflow into NaN.
    for d in [1e-300, 1e-200, 1e-100] {
        let p = law.evaluate(d);
        assert!(p.force.is_finite() && p.force >= 0.0 && p.stiffness.is_finite());
    }
}

#[test]
fn hertz_local_contact_matches_hertz_radius() {
    let (r, m) = (5e-3, rubber());
    let law = PotentialLaw::sphere(Sphere::new(r).unwrap(), m);
    let p = 20.0;
    let c = law.local_contact(p, 1e-4);
    let a = (3.0 * p * r / (4.0 * m.reduced_modulus())).cbrt();
    assert!(rel(c.radius, a) < 1e-14);
    // The Hertz profile integrates to the force: ∫ p 2πr dr = P.
    let n = 20_000;
    let integral: f64 = (0..n)
        .map(|i| {
            let rr = (i as f64 + 0.5) / n as f64 * a;
            c.pressure_at(rr) * 2.0 * PI * rr * a / n as f64
        })
        .sum();
    assert!(rel(integral, p) < 1e-5);
    assert_eq!(c.pressure_at(a * 1.01), 0.0);
}

#[test]
fn cone_local_contact_matches_sneddon() {
    let (alpha, m) = (1.2, rubber());
    let law = PotentialLaw::cone(Cone::new(alpha).unwrap(), m)
        .with_constant(C_SNEDDON_EXACT)
        .unwrap();
    let sneddon = SneddonLaw::new(alpha, m).unwrap();
    let d = 2e-4;
    let p = law.force(d);
    let (a, b) = (law.local_contact(p, d), sneddon.local_contact(p, d));
    assert!(rel(a.radius, b.radius) < 1e-12);
    let n = 200_000;
    let integral: f64 = (0..n)
        .map(|i| {
            let rr = (i as f64 + 0.5) / n as f64 * a.radius;
            a.pressure_at(rr) * 2.0 * PI * rr * a.radius / n as f64
        })
        .sum();
    assert!(rel(integral, p) < 1e-4);
}

#[test]
fn half_section_rule_is_hertz_for_a_paraboloid() {
    let (r, m) = (4e-3, rubber());
    let para = EllipticParaboloid::new(r, r).unwrap();
    let law = PotentialLaw::new(para, m, C_HERTZ_EXACT, LocalRule::HalfSection).unwrap();
    let d = 1e-5;
    let c = law.local_contact(law.force(d), d);
    assert!(rel(c.radius, (r * d).sqrt()) < 1e-12);
}

#[test]
fn invalid_material_and_constant_are_refused() {
    assert!(Material::new(0.0, 0.3).is_err());
    assert!(Material::new(f64::NAN, 0.3).is_err());
    assert!(Material::new(1e6, 0.51).is_err());
    assert!(Material::new(1e6, -1.0).is_err());
    assert!(Material::new(1e6, 0.5).is_ok());
    let law = PotentialLaw::sphere(Sphere::new(1e-3).unwrap(), rubber());
    assert!(law.clone().with_constant(0.0).is_err());
    assert!(law.with_constant(f64::INFINITY).is_err());
    assert!(HertzLaw::new(-1.0, rubber()).is_err());
    assert!(SneddonLaw::new(2.0, rubber()).is_err());
}

proptest! {
    #[test]
    fn potential_law_is_continuous_and_increasing(
        r in 1e-4f64..2e-2, frac_a in 1e-6f64..0.9, frac_b in 1e-6f64..0.9,
        rx in 1e-4f64..1e-2, ry in 1e-4f64..1e-2, alpha in 0.2f64..1.4,
    ) {
        let m = rubber();
        let (lo, hi) = if frac_a < frac_b { (frac_a, frac_b) } else { (frac_b, frac_a) };
        let sphere = PotentialLaw::sphere(Sphere::new(r).unwrap(), m);
        let cone = PotentialLaw::cone(Cone::new(alpha).unwrap(), m);
        let para = PotentialLaw::paraboloid(EllipticParaboloid::new(rx, ry).unwrap(), m);
        for law in [&sphere as &dyn ContactLaw, &cone, &para] {
            let (a, b) = (law.evaluate(lo * r), law.evaluate(hi * r));
            prop_assert!(a.force >= 0.0 && a.stiffness >= 0.0);
            prop_assert!(b.force >= a.force);
            // Continuity: a tiny step changes P by about k·dδ.
            let h = lo * r * 1e-7;
            let c = law.force(lo * r + h);
            prop_assert!((c - a.force).abs() <= 2.0 * a.stiffness * h + 1e-12 * a.force);
        }
    }
}

/// Regression: past a mesh's depth its cap went on as vertical walls at
/// once, and the potential law's force doubled there across a pyramid's
/// base (`Σ'` fell from `2Σ/δ` to 0): loads between the two forces had no
/// depth, and a Newton solve for them cycled.
#[test]
fn a_mesh_law_has_no_jump_at_the_mesh_depth() {
    for (name, buffers) in [
        ("tetrahedron", MeshBuffers::cone(0.9, 1e-3, 3).unwrap()),
        ("48-flank cone", MeshBuffers::cone(1.1, 2e-3, 48).unwrap()),
        ("icosphere", MeshBuffers::icosphere(1e-3, 2).unwrap()),
    ] {
        let mesh = MeshAsperity::from_buffers(&buffers).unwrap();
        let h = mesh.max_depth();
        let law = PotentialLaw::new(mesh, rubber(), C_CONE, LocalRule::HalfSection).unwrap();
        let (below, above) = (law.force(h * (1.0 - 1e-9)), law.force(h * (1.0 + 1e-9)));
        assert!(
            rel(above, below) < 1e-6,
            "{name}: {below} N just above its depth, {above} N just past it"
        );
        // Through the run-out and into the walls, the force keeps rising.
        let mut last = below;
        for k in 1..=60 {
            let point = law.evaluate(h * (1.0 + 0.005 * f64::from(k)));
            assert!(
                point.force > last && point.stiffness > 0.0,
                "{name}: at {k} × 0.5 % past its depth, {point:?} after {last} N"
            );
            last = point.force;
        }
    }
}

/// Regression (adversarial run, adv6 S5): a `LocalRule` with a negative or
/// NaN radius, or a half-angle outside (0, π/2), was accepted and gave local
/// contacts of radius −1.63 mm or NaN. It is refused as `HertzLaw::new` and
/// `SneddonLaw::new` refuse it; valid rules still build.
#[test]
fn a_local_rule_with_a_bad_radius_or_half_angle_is_refused() {
    let ball = Sphere::new(5e-3).unwrap();
    for rule in [
        LocalRule::Hertz { radius: -5e-3 },
        LocalRule::Hertz { radius: 0.0 },
        LocalRule::Hertz { radius: f64::NAN },
        LocalRule::Hertz {
            radius: f64::INFINITY,
        },
        LocalRule::Sneddon { half_angle: 3.0 },
        LocalRule::Sneddon { half_angle: -0.5 },
        LocalRule::Sneddon {
            half_angle: PI / 2.0,
        },
        LocalRule::Sneddon {
            half_angle: f64::NAN,
        },
    ] {
        match PotentialLaw::new(ball, rubber(), C_SPHERE, rule) {
            Err(e @ LawError::InvalidParameter { .. }) => {
                let m = e.to_string();
                assert!(m.contains("local rule"), "{m}");
            }
            other => panic!("{rule:?}: {other:?}"),
        }
    }
    let e = PotentialLaw::new(ball, rubber(), C_SPHERE, LocalRule::Hertz { radius: -5e-3 })
        .unwrap_err();
    assert_eq!(e.to_string(), "invalid local rule Hertz radius (m): -5e-3");
    for rule in [
        LocalRule::Hertz { radius: 5e-3 },
        LocalRule::Sneddon { half_angle: 1.2 },
        LocalRule::HalfSection,
    ] {
        let law = PotentialLaw::new(ball, rubber(), C_SPHERE, rule).unwrap();
        let lc = law.local_contact(10.0, 1e-3);
        assert!(lc.radius.is_finite() && lc.radius > 0.0, "{rule:?}");
    }
}

/// Regression (adversarial run, adv6 S6): `pressure_at(−2 mm)` on a 1 mm
/// contact gave NaN (the guard tested `r < a`, not `|r| < a`). A negative
/// `r` is a signed coordinate: outside is 0, inside is the pressure at `|r|`.
#[test]
fn pressure_at_a_negative_coordinate_is_that_at_its_distance_never_nan() {
    for profile in [PressureProfile::Hertz, PressureProfile::Cone] {
        let lc = LocalContact {
            force: 10.0,
            radius: 1e-3,
            profile,
        };
        assert_eq!(lc.pressure_at(-2e-3), 0.0, "{profile:?}");
        assert_eq!(lc.pressure_at(-1e-3), 0.0, "{profile:?}");
        assert_eq!(lc.pressure_at(f64::NAN), 0.0, "{profile:?}");
        assert_eq!(lc.pressure_at(f64::NEG_INFINITY), 0.0, "{profile:?}");
        let (neg, pos) = (lc.pressure_at(-0.5e-3), lc.pressure_at(0.5e-3));
        assert!(pos > 0.0 && neg == pos, "{profile:?}: {neg} vs {pos}");
    }
}

/// Regression (adversarial run, adv6 S7): a sphere's law gave `P = 0` but
/// `k = NaN` for δ from ~1e-161 to ~1.7e-154 m: `g ∼ 2/δ` squared overflows
/// and the cap's `Γ''` is huge, so `g² + g'` read `∞ − ∞`. The stiffness is
/// finite at every small depth: 0 where `U` underflows (rubber), and on a
/// material stiff enough for `U` to stay representable, Hertz's limit.
#[test]
fn stiffness_stays_finite_where_the_log_derivative_squared_overflows() {
    let depths: Vec<f64> = (0..=200)
        .map(|k| 10f64.powf(-170.0 + 0.1 * k as f64))
        .collect();
    for r in [1e-6, 5e-3, 1.0] {
        let shapes: Vec<Box<dyn ContactLaw>> = vec![
            Box::new(PotentialLaw::sphere(Sphere::new(r).unwrap(), rubber())),
            Box::new(PotentialLaw::paraboloid(
                EllipticParaboloid::new(r, 0.4 * r).unwrap(),
                rubber(),
            )),
        ];
        for law in &shapes {
            for &d in &depths {
                let p = law.evaluate(d);
                assert!(
                    p.force.is_finite() && p.force >= 0.0,
                    "R = {r:e}, δ = {d:e}: P = {:e}",
                    p.force
                );
                assert!(
                    p.stiffness.is_finite() && p.stiffness >= 0.0,
                    "R = {r:e}, δ = {d:e}: k = {:e}",
                    p.stiffness
                );
            }
        }
    }
    // The probe's case: rubber, R = 5 mm, δ = 1e-160: U underflows.
    let law = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), rubber());
    assert_eq!(law.evaluate(1e-160), LawPoint::default());
    // A stiff material keeps U representable there: k is Hertz's.
    let stiff = Material::new(1e300, 0.0).unwrap();
    let law = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), stiff)
        .with_constant(C_HERTZ_EXACT)
        .unwrap();
    let hertz = HertzLaw::new(5e-3, stiff).unwrap();
    for d in [1e-155, 1e-156, 1e-158] {
        let (p, h) = (law.evaluate(d), hertz.evaluate(d));
        assert!(
            rel(p.stiffness, h.stiffness) < 1e-6,
            "δ = {d:e}: {p:?} vs {h:?}"
        );
        assert!(rel(p.force, h.force) < 1e-6, "δ = {d:e}: {p:?} vs {h:?}");
    }
}
