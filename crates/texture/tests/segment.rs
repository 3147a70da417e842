//! Segmentation and caps: spheres on a plane.
#![allow(clippy::unwrap_used)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_asperity::{CapGeometry, Sphere};
use tyreroad_texture::{CapOptions, GridCap, HeightMap, SegmentOptions, asperity_cap, segment};

const R: f64 = 5e-3;
const DX: f64 = 1e-4;

/// Balls (centre x, y, summit height above the plane z = 0).
fn balls() -> Vec<(f64, f64, f64)> {
    vec![
        (6.03e-3, 5.57e-3, 2.6e-3),
        (17.41e-3, 6.12e-3, 2.2e-3),
        (28.76e-3, 5.33e-3, 1.8e-3),
        (8.88e-3, 17.64e-3, 2.4e-3),
        (21.27e-3, 18.05e-3, 2.0e-3),
        (33.52e-3, 19.91e-3, 1.6e-3),
    ]
}

fn sphere_map(noise: f64, seed: u64) -> HeightMap {
    let b = balls();
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (nx, ny) = (400, 250);
    let mut h = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 * DX, j as f64 * DX);
            let mut z: f64 = 0.0;
            for &(cx, cy, top) in &b {
                let d2 = (x - cx).powi(2) + (y - cy).powi(2);
                if d2 < R * R {
                    z = z.max((R * R - d2).sqrt() - R + top);
                }
            }
            h.push(z + noise * (2.0 * rng.random::<f64>() - 1.0));
        }
    }
    HeightMap::new(nx, ny, DX, DX, h).unwrap()
}

fn opts() -> SegmentOptions {
    SegmentOptions {
        min_prominence: 0.2e-3,
        min_area: 1e-6,
    }
}

#[test]
fn spheres_are_split_back_and_caps_match_closed_forms() {
    let map = sphere_map(0.0, 0);
    let seg = segment(&map, &opts()).unwrap();
    let b = balls();
    assert_eq!(seg.asperities().len(), b.len());
    let ball = Sphere::new(R).unwrap();
    let mut worst = [0.0f64; 3];
    for (k, a) in seg.asperities().iter().enumerate() {
        // Highest first: the balls sorted by summit height.
        let &(cx, cy, top) = b
            .iter()
            .find(|(cx, cy, _)| (a.summit[0] - cx).abs() < DX && (a.summit[1] - cy).abs() < DX)
            .unwrap_or_else(|| panic!("asperity {k} at {:?} matches no ball", a.summit));
        let (gi, gj) = a.summit_cell;
        assert!((gi as f64 * DX - cx).abs() <= DX && (gj as f64 * DX - cy).abs() <= DX);
        assert!(
            (a.summit_height - top).abs() < 1e-6,
            "{} vs {top}",
            a.summit_height
        );
        let fit = a.fit.unwrap();
        assert!((fit.radii.0 / R - 1.0).abs() < 0.05 && (fit.radii.1 / R - 1.0).abs() < 0.05);
        let cap = asperity_cap(&map, &seg, k, &CapOptions::default()).unwrap();
        let grid = GridCap::new(&map, &seg, k).unwrap();
        assert!(
            (grid.max_depth() - top).abs() < 1e-3,
            "max depth {}",
            grid.max_depth()
        );
        for d in [0.002e-3, 0.01e-3, 0.05e-3, 0.2e-3, 0.5e-3, 1.0e-3] {
            let (t, e) = (cap.cap(d), ball.cap(d));
            let errs = [
                t.volume / e.volume - 1.0,
                t.base_area / e.base_area - 1.0,
                t.perimeter / e.perimeter - 1.0,
            ];
            for (w, err) in worst.iter_mut().zip(errs) {
                *w = w.max(err.abs());
            }
            assert!(
                errs.iter().all(|e| e.abs() < 0.02),
                "ball {k} (centre {cx}, {cy}) at δ = {d}: Ω, Σ, Γ errors {errs:?}"
            );
        }
        // Derivatives are consistent: dΩ/dδ = Σ and P stays smooth near onset.
        let (c1, c2) = (cap.cap(0.1e-3), cap.cap(0.1e-3 + 1e-9));
        assert!(((c2.volume - c1.volume) / 1e-9 / c1.base_area - 1.0).abs() < 1e-4);
    }
    eprintln!("worst relative errors Ω, Σ, Γ over 6 balls and 6 depths: {worst:?}");
}

#[test]
fn grid_cap_is_exact_for_a_pyramid() {
    // A square pyramid z = 1 mm − |x| − |y| (slope 1) sampled on a grid
    // whose nodes include the apex: its linear interpolant is exact on the
    // 4 faces except the cells crossing the diagonals' edges, which the
    // 4-triangle split resolves exactly too.
    let n = 41;
    let d = 5e-5;
    let c = 20.0 * d;
    let map = HeightMap::from_fn(n, n, d, d, |x, y| {
        (1e-3 - (x - c).abs() - (y - c).abs()).max(0.0)
    })
    .unwrap();
    let seg = segment(&map, &opts()).unwrap();
    assert_eq!(seg.asperities().len(), 1);
    let g = GridCap::new(&map, &seg, 0).unwrap();
    let delta = 0.4123e-3;
    let m = g.cap(delta);
    // Section: a square of half-diagonal δ: Σ = 2δ², Γ = 4√2 δ, Ω = 2δ³/3.
    assert!((m.base_area / (2.0 * delta * delta) - 1.0).abs() < 1e-9);
    assert!((m.perimeter / (4.0 * 2f64.sqrt() * delta) - 1.0).abs() < 1e-9);
    assert!((m.volume / (2.0 * delta.powi(3) / 3.0) - 1.0).abs() < 1e-9);
    assert!((m.d_base_area / (4.0 * delta) - 1.0).abs() < 1e-9);
    assert!((m.d_perimeter / (4.0 * 2f64.sqrt()) - 1.0).abs() < 1e-9);
}

#[test]
fn segmentation_is_stable_to_small_noise() {
    let clean = segment(&sphere_map(0.0, 0), &opts()).unwrap();
    for seed in 1..4 {
        // ±2 µm uniform noise, 100 × below the 0.2 mm prominence threshold.
        let noisy = segment(&sphere_map(2e-6, seed), &opts()).unwrap();
        assert_eq!(
            noisy.asperities().len(),
            clean.asperities().len(),
            "seed {seed}"
        );
        for (a, b) in noisy.asperities().iter().zip(clean.asperities()) {
            assert!(
                (a.summit[0] - b.summit[0]).abs() <= DX && (a.summit[1] - b.summit[1]).abs() <= DX,
                "seed {seed}: summit {:?} vs {:?}",
                a.summit,
                b.summit
            );
        }
    }
}

#[test]
fn prominence_and_area_thresholds_merge_small_bumps() {
    // A big bump and a 50 µm one on the plane beside it: merged at 0.2 mm.
    let map = HeightMap::from_fn(120, 120, DX, DX, |x, y| {
        let big = (2e-3 - ((x - 5e-3).powi(2) + (y - 6e-3).powi(2)) / (2.0 * R)).max(0.0);
        let small = (50e-6 - ((x - 10.5e-3).powi(2) + (y - 6e-3).powi(2)) / (2.0 * 1e-3)).max(0.0);
        big + small
    })
    .unwrap();
    let seg = segment(&map, &opts()).unwrap();
    assert_eq!(seg.asperities().len(), 1);
    let seg = segment(
        &map,
        &SegmentOptions {
            min_prominence: 1e-6,
            min_area: 0.0,
        },
    )
    .unwrap();
    assert_eq!(seg.asperities().len(), 2);
    assert!((seg.asperities()[1].prominence - 50e-6).abs() < 1e-9);
    let labelled = seg
        .labels()
        .iter()
        .filter(|l| **l != tyreroad_texture::UNLABELLED)
        .count();
    assert_eq!(labelled, 120 * 120);
}

/// A ball's top (R = 3 mm, its summit between grid points) on 0.25 mm
/// cells, cut `cliff` cells beside its summit point by a pore 3 mm deep
/// (`None`: no pore), as a porous asphalt's chippings are.
fn ball_beside_a_pore(cliff: Option<usize>) -> HeightMap {
    let (r, h) = (3e-3, 0.25e-3);
    let (cx, cy) = (20.3 * h, 20.2 * h);
    HeightMap::from_fn(41, 41, h, h, |x, y| {
        if cliff.is_some_and(|c| x > (20 + c) as f64 * h - 1e-9) {
            return -3e-3;
        }
        let d2 = (x - cx).powi(2) + (y - cy).powi(2);
        ((r * r - d2).max(0.0).sqrt() - r).max(-1e-3)
    })
    .unwrap()
}

/// A least-squares paraboloid through a chipping's top and the pore wall
/// beside it put summits up to 1.5 mm above every cell of a synthetic
/// porous asphalt, and the road's approach was measured from them
/// (docs/texture.md, "Summits"). The fit is refused there: the summit is
/// its highest grid point. Without the pore the same ball keeps its fit.
#[test]
fn a_summit_beside_a_pore_does_not_stand_above_its_cells() {
    let smooth = ball_beside_a_pore(None);
    let seg = segment(&smooth, &opts()).unwrap();
    let a = &seg.asperities()[0];
    let fit = a.fit.expect("the smooth ball keeps its paraboloid");
    assert!((fit.radii.0 / 3e-3 - 1.0).abs() < 0.05, "{:?}", fit.radii);
    let z0 = smooth.get(a.summit_cell.0, a.summit_cell.1).unwrap();
    // The vertex within a cell of its grid point: at most h²/(4R) above it
    // for the ball itself (5.2 µm).
    assert!(a.summit_height - z0 < 6e-6, "{}", a.summit_height - z0);
    for cliff in [1, 2] {
        let map = ball_beside_a_pore(Some(cliff));
        let seg = segment(&map, &opts()).unwrap();
        let a = &seg.asperities()[0];
        let z0 = map.get(a.summit_cell.0, a.summit_cell.1).unwrap();
        assert!(
            a.summit_height - z0 < 6e-6,
            "pore {cliff} cells away: summit {} mm above its grid point",
            (a.summit_height - z0) * 1e3
        );
    }
}
