//! The tread gap at a summit's contact point (`Tread::contact_gap`) against
//! a brute-force search over a true sphere, and the road's summit radii.
#![allow(clippy::unwrap_used)]

use tyreroad_contact_law::{HertzLaw, Material};
use tyreroad_rolling::{AsperitySet, Road, RollingError, Tread};

const TYRE: Tread = Tread::Tyre {
    radius_x: 0.3,
    radius_y: 0.5,
    length: 0.12,
    width: 0.15,
};

/// The smallest `s(ξ + dξ, η + dη) + (R − √(R² − dξ² − dη²))` (tread minus
/// a sphere of radius R below its summit) over a fine grid of offsets, and
/// where it lies.
fn brute_force(xi: f64, eta: f64, r: f64) -> (f64, [f64; 2]) {
    let (mut best, mut at) = (f64::INFINITY, [0.0, 0.0]);
    let n = 800;
    let span = 3e-3;
    for i in 0..=n {
        for j in 0..=n {
            let d = [
                span * (2.0 * i as f64 / n as f64 - 1.0),
                span * (2.0 * j as f64 / n as f64 - 1.0),
            ];
            let rho2 = d[0] * d[0] + d[1] * d[1];
            let gap = TYRE.profile(xi + d[0], eta + d[1]).unwrap() + (r - (r * r - rho2).sqrt());
            if gap < best {
                (best, at) = (gap, d);
            }
        }
    }
    (best, at)
}

#[test]
fn the_contact_point_gap_is_the_smallest_tread_to_sphere_gap() {
    // Footprint corner, edge and centre; a 4 mm and an 8 mm chipping.
    for (xi, eta) in [(0.05, 0.06), (-0.04, 0.0), (0.0, -0.05), (0.0, 0.0)] {
        for r in [4e-3, 8e-3] {
            let (gap, offset) = TYRE.contact_gap(xi, eta, r).unwrap();
            let (brute, at) = brute_force(xi, eta, r);
            // The closed form is exact for a paraboloid summit; a sphere
            // lies below it by `ρ⁴/(8R³)` at the offset ρ (0.8 µm for 0.8
            // mm on R = 4 mm), and the search grid's 7.5 µm spacing adds
            // ~`h²/(8R)`, 0.002 µm. Its offset moves by ~`ρ²/R²` of itself.
            let rho2 = offset[0] * offset[0] + offset[1] * offset[1];
            let bound = 1.2 * rho2 * rho2 / (8.0 * r * r * r) + 1e-8;
            assert!(
                (gap - brute).abs() <= bound,
                "({xi}, {eta}), R {r}: {gap} vs {brute} (bound {bound})"
            );
            for k in 0..2 {
                let tol = 2.0 * rho2 / (r * r) * offset[k].abs() + 1e-5;
                assert!((offset[k] - at[k]).abs() <= tol, "{offset:?} vs {at:?}");
            }
            // The summit's gap is larger by `½ Σ σ² R R_k/(R + R_k)`,
            // tens of µm here, far above the sphere's correction.
            let summit = TYRE.profile(xi, eta).unwrap();
            if xi != 0.0 || eta != 0.0 {
                assert!(summit - gap > 10.0 * bound, "{summit} vs {gap}");
            } else {
                assert_eq!(gap, summit);
            }
        }
    }
    // No radius, or a flat block: the summit's gap, no offset.
    assert_eq!(
        TYRE.contact_gap(0.05, 0.06, f64::INFINITY),
        Some((TYRE.profile(0.05, 0.06).unwrap(), [0.0, 0.0]))
    );
    let block = Tread::Block {
        length: 0.1,
        width: 0.1,
    };
    assert_eq!(block.contact_gap(0.01, 0.02, 4e-3), Some((0.0, [0.0, 0.0])));
    assert_eq!(block.contact_gap(0.2, 0.0, 4e-3), None);
}

#[test]
fn summit_radii_are_checked() {
    let law = HertzLaw::new(5e-3, Material::new(6.54e6, 0.5).unwrap()).unwrap();
    let set = AsperitySet::new(vec![[0.0, 0.0], [0.01, 0.0]], vec![0.0; 2], vec![law; 2]).unwrap();
    let road = Road::new(set);
    assert!(road.summit_radius(1).is_infinite());
    for bad in [
        vec![5e-3],
        vec![5e-3, -1e-3],
        vec![f64::NAN, 5e-3],
        vec![f64::INFINITY, 5e-3],
    ] {
        let e = road.clone().with_summit_radii(bad).unwrap_err();
        assert!(matches!(e, RollingError::InvalidInput(_)), "{e}");
    }
    // A sharp summit (radius 0) is accepted and touched at its tip: its
    // gap is the tread profile at the summit, with no offset.
    let sharp = road.clone().with_summit_radii(vec![0.0, 5e-3]).unwrap();
    assert_eq!(sharp.summit_radius(0), 0.0);
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.5,
        length: 0.1,
        width: 0.1,
    };
    let (xi, eta) = (0.02, 0.01);
    let profile = xi * xi / 0.6 + eta * eta / 1.0;
    assert_eq!(tyre.contact_gap(xi, eta, 0.0), Some((profile, [0.0, 0.0])));
    let road = road.with_summit_radii(vec![4e-3, 5e-3]).unwrap();
    assert_eq!(road.summit_radius(1), 5e-3);
}
