//! The tabulated caps of a segmented road texture as contact laws: the
//! regression of the multipoint Newton stall on self-affine textures
//! (a force jump past each table's last node, and forces that fell).
#![allow(clippy::unwrap_used)]

use std::sync::Arc;

use tyreroad_asperity::CapGeometry;
use tyreroad_contact_law::{C_SPHERE, ContactLaw, LocalRule, Material, PotentialLaw};
use tyreroad_texture::{
    CapOptions, SegmentOptions, SelfAffine, asperity_cap, segment, self_affine,
};

/// The laws of a self-affine texture's asperities, caps tabulated down to
/// the basin bottom (as `texture_road` does).
fn texture_laws() -> Vec<PotentialLaw<Arc<tyreroad_asperity::TabulatedCap>>> {
    let map = self_affine(&SelfAffine {
        nx: 200,
        ny: 200,
        dx: 1e-4,
        dy: 1e-4,
        rms: 0.5e-3,
        hurst: 0.8,
        lambda_long: 20e-3,
        lambda_short: 1e-3,
        seed: 1,
    })
    .unwrap();
    let seg = segment(
        &map,
        &SegmentOptions {
            min_prominence: 0.2e-3,
            min_area: 2e-6,
        },
    )
    .unwrap();
    let material = Material::new(6.54e6, 0.5).unwrap();
    let mut laws = vec![];
    for (k, a) in seg.asperities().iter().enumerate() {
        let low = a
            .cells
            .iter()
            .map(|&c| map.heights()[c])
            .fold(f64::INFINITY, f64::min);
        let opts = CapOptions {
            max_depth: Some(a.summit_height - low),
            ..CapOptions::default()
        };
        let Ok(table) = asperity_cap(&map, &seg, k, &opts) else {
            continue;
        };
        laws.push(
            PotentialLaw::new(Arc::new(table), material, C_SPHERE, LocalRule::HalfSection).unwrap(),
        );
    }
    laws
}

#[test]
fn segmented_texture_laws_are_continuous_and_never_decrease() {
    let laws = texture_laws();
    assert!(laws.len() >= 5, "{}", laws.len());
    // The raw potential law of these caps does fall: the ramps are what
    // keeps the laws monotone.
    assert!(laws.iter().any(|l| !l.ramps().is_empty()));
    for (i, l) in laws.iter().enumerate() {
        let max = l.geometry().max_depth();
        // Continuous at every node, past the last one, and at the ramps.
        let mut at = l.geometry().breakpoints();
        at.extend(
            l.ramps()
                .iter()
                .flat_map(|p| [p.start, p.end])
                .filter(|x| x.is_finite()),
        );
        for x in at {
            let (a, b) = (l.force(x.next_down()), l.force(x.next_up()));
            assert!(
                (a - b).abs() <= 1e-9 * b,
                "law {i}: P jumps at δ = {x}: {a} → {b}"
            );
        }
        // Non-decreasing (to rounding) with k ≥ 0, and k = dP/dδ (central differences away
        // from the nodes and ramp ends, where k is one-sided).
        let mut kinks = l.geometry().breakpoints();
        kinks.extend(l.ramps().iter().flat_map(|p| [p.start, p.end]));
        let mut last = 0.0;
        for k in 1..=3000 {
            let d = 1.3 * max * (f64::from(k) / 3000.0).powi(2);
            let p = l.evaluate(d);
            assert!(
                p.force >= last * (1.0 - 1e-12) && p.stiffness >= 0.0,
                "law {i} at δ = {d}"
            );
            last = p.force;
            let h = 1e-7 * d;
            if kinks.iter().all(|x| (x - d).abs() > 2.0 * h) {
                let fd = (l.force(d + h) - l.force(d - h)) / (2.0 * h);
                let scale = p.stiffness.max(p.force / d);
                assert!(
                    (fd - p.stiffness).abs() < 1e-4 * scale,
                    "law {i} at δ = {d}: k {} FD {fd}",
                    p.stiffness
                );
            }
        }
    }
}

/// Regression (adversarial run, adv6 U8 and P2): `CapOptions` with
/// `max_depth: Some(NaN)` or `Some(-1)` was refused as "no depth range
/// (summit at the basin's boundary height)", and `nodes: usize::MAX` aborted
/// on "capacity overflow". Both are refused as the option given.
#[test]
fn cap_options_out_of_range_are_refused_by_name() {
    use tyreroad_texture::{HeightMap, TextureError};
    let h = (0..3600)
        .map(|k| {
            let (x, y) = ((k % 60 % 15) as f64 - 7.0, (k / 60 % 15) as f64 - 7.0);
            -1e-5 * (x * x + y * y)
        })
        .collect();
    let map = HeightMap::new(60, 60, 1e-4, 1e-4, h).unwrap();
    let seg = segment(
        &map,
        &SegmentOptions {
            min_prominence: 1e-5,
            min_area: 0.0,
        },
    )
    .unwrap();
    assert!(asperity_cap(&map, &seg, 0, &CapOptions::default()).is_ok());
    for d in [f64::NAN, -1.0, 0.0, f64::INFINITY] {
        let opts = CapOptions {
            max_depth: Some(d),
            ..CapOptions::default()
        };
        match asperity_cap(&map, &seg, 0, &opts) {
            Err(e @ TextureError::InvalidParameter { .. }) => {
                let m = e.to_string();
                assert!(
                    m.contains("max_depth") && m.contains(&format!("{d:?}")),
                    "{m}"
                );
            }
            other => panic!("max_depth {d}: {other:?}"),
        }
    }
    for n in [0, 1, usize::MAX] {
        let opts = CapOptions {
            nodes: n,
            ..CapOptions::default()
        };
        match asperity_cap(&map, &seg, 0, &opts) {
            Err(TextureError::InvalidParameter { name, value, .. }) => {
                assert_eq!((name, value), ("cap options nodes", n as f64));
            }
            other => panic!("nodes {n}: {other:?}"),
        }
    }
}
