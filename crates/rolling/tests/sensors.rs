//! Virtual sensors: each contact's pressure integrated over the sensor's
//! rectangle, checked against closed forms of the Hertz half-plane load and
//! against exact symmetry and partition properties; a rolling run whose
//! sensors tile the road sums to the total force.

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{LocalContact, Material, PotentialLaw, PressureProfile};
use tyreroad_rolling::{
    Road, RollingConfig, RollingControl, RunOptions, Sensor, SyntheticRoad, Tread, roll,
};

fn sensor(x: [f64; 2], y: [f64; 2]) -> Sensor {
    Sensor {
        name: "s".into(),
        x,
        y,
    }
}

fn contact(force: f64, radius: f64, profile: PressureProfile) -> LocalContact {
    LocalContact {
        force,
        radius,
        profile,
    }
}

const PROFILES: [PressureProfile; 2] = [PressureProfile::Hertz, PressureProfile::Cone];

#[test]
fn contact_wholly_inside_or_outside_counts_whole_or_nothing() {
    let s = sensor([0.0, 0.02], [0.0, 0.02]);
    for profile in PROFILES {
        let c = contact(3.0, 1e-3, profile);
        assert_eq!(s.share([0.01, 0.01], &c), 3.0);
        assert_eq!(s.share([0.03, 0.01], &c), 0.0);
        assert_eq!(s.share([0.0105, -0.0011], &c), 0.0);
    }
    // A contact without radius is a point force at its summit.
    let point = contact(2.0, 0.0, PressureProfile::Hertz);
    assert_eq!(s.share([0.01, 0.01], &point), 2.0);
    assert_eq!(s.share([0.03, 0.01], &point), 0.0);
    assert_eq!(
        s.share([0.01, 0.01], &contact(0.0, 1e-3, PressureProfile::Hertz)),
        0.0
    );
}

#[test]
fn edge_through_the_centre_takes_half_and_a_corner_a_quarter() {
    for profile in PROFILES {
        let c = contact(4.0, 2e-3, profile);
        let half = sensor([0.0, 1.0], [-1.0, 1.0]).share([0.0, 0.3], &c);
        assert!((half - 2.0).abs() < 1e-12, "{profile:?}: {half}");
        let quarter = sensor([0.0, 1.0], [0.0, 1.0]).share([0.0, 0.0], &c);
        assert!((quarter - 1.0).abs() < 1e-12, "{profile:?}: {quarter}");
    }
}

#[test]
fn sensors_tiling_the_plane_share_a_contact_exactly() {
    // Four quadrants around (1 mm, −0.4 mm), a contact of radius 1.5 mm at
    // the origin: the shares sum to the force.
    let (ex, ey) = (1e-3, -0.4e-3);
    let quadrants = [
        sensor([-1.0, ex], [-1.0, ey]),
        sensor([ex, 1.0], [-1.0, ey]),
        sensor([-1.0, ex], [ey, 1.0]),
        sensor([ex, 1.0], [ey, 1.0]),
    ];
    for profile in PROFILES {
        let c = contact(7.0, 1.5e-3, profile);
        let total: f64 = quadrants.iter().map(|s| s.share([0.0, 0.0], &c)).sum();
        assert!((total - 7.0).abs() < 1e-12, "{profile:?}: {total}");
    }
}

#[test]
fn hertz_share_beyond_a_straight_edge_matches_the_line_load_integral() {
    // Hertz pressure integrated across y is a line load ∝ a² − x², so the
    // force beyond x = t·a is (2 − 3t + t³)/4 of the total. The equal-force
    // rule (24 rings × 48 spokes) is a counting rule: measured within
    // 1.9e-3 of P at these edges, asserted within 3e-3.
    let c = contact(1.0, 1e-3, PressureProfile::Hertz);
    for t in [-0.8, -0.5, -0.2, 0.1, 0.3, 0.6, 0.9] {
        let s = sensor([t * 1e-3, 1.0], [-1.0, 1.0]);
        let got = s.share([0.0, 0.0], &c);
        let exact = (2.0 - 3.0 * t + t * t * t) / 4.0;
        assert!((got - exact).abs() < 3e-3, "t = {t}: {got} vs {exact}");
    }
}

#[test]
fn sensors_tiling_the_road_sum_to_the_total_force_at_every_step() {
    let material = Material::new(6.54e6, 0.5).expect("material");
    let road: Road<PotentialLaw<Sphere>> = SyntheticRoad {
        seed: 11,
        length: 0.12,
        width: 0.05,
        density: 30_000.0,
        ..SyntheticRoad::default()
    }
    .sphere_road(material)
    .expect("road");
    let tread = Tread::Block {
        length: 0.03,
        width: 0.03,
    };
    let mut config =
        RollingConfig::new(tread, [0.03, 0.09, 2e-3], 10.0, RollingControl::Load(150.0));
    // A 5 mm strip pattern across the path: contacts (radii ~1 mm) straddle
    // its edges at many steps.
    let edges: Vec<f64> = (0..=24).map(|k| k as f64 * 5e-3).collect();
    config.sensors = edges
        .windows(2)
        .map(|w| sensor([w[0], w[1]], [-1.0, 1.0]))
        .collect();
    let r = roll(&road, material, &config, &RunOptions::default()).expect("roll");
    let mut split = 0;
    for s in &r.steps {
        let sum: f64 = s.sensor_forces.iter().sum();
        assert!(
            (sum - s.total_force).abs() < 1e-9 * s.total_force,
            "x = {}: {sum} vs {}",
            s.position,
            s.total_force
        );
        split += s
            .sensor_forces
            .iter()
            .filter(|&&f| f > 0.0 && f < 1e-3 * s.total_force)
            .count();
    }
    // Some sensor got only a sliver of a contact at some step: the
    // contacts are indeed split, not attributed whole.
    assert!(split > 0);
}

/// A spread force ([`Sensor::share_spread`]): each point's square counted
/// with the fraction inside, so a square cut in half by an edge gives half
/// its weight, one wholly inside all of it, and sensors tiling the road
/// share the force exactly.
#[test]
fn a_spread_force_is_split_by_the_area_of_each_square() {
    let spread = tyreroad_rolling::Spread {
        points: vec![
            ([0.0, 0.0], 0.25),
            ([1e-3, 0.0], 0.5),
            ([-2e-3, 1e-3], 0.25),
        ],
        cell: 0.5e-3,
    };
    let centre = [0.01, 0.01];
    // Wholly inside: the force.
    let inside = sensor([0.0, 0.02], [0.0, 0.02]);
    assert!((inside.share_spread(centre, 4.0, &spread) - 4.0).abs() < 1e-12);
    // An edge through the first point's centre (x = 10 mm): half of its
    // weight, all of the second's, none of the third's.
    let right = sensor([0.01, 0.02], [0.0, 0.02]);
    let expected = 4.0 * (0.5 * 0.25 + 0.5);
    assert!((right.share_spread(centre, 4.0, &spread) - expected).abs() < 1e-12);
    // A 3 × 3 tiling with edges through the points: the shares sum to the
    // force.
    let edges = [-1.0, 0.0095, 0.01025, 1.0];
    let mut sum = 0.0;
    for i in 0..3 {
        for j in 0..3 {
            let s = sensor([edges[i], edges[i + 1]], [edges[j], edges[j + 1]]);
            sum += s.share_spread(centre, 4.0, &spread);
        }
    }
    assert!((sum - 4.0).abs() < 1e-12, "{sum}");
    assert_eq!(inside.share_spread(centre, 0.0, &spread), 0.0);
}
