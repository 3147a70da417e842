//! Windows of a rough map segmented on their own: every certified asperity
//! is the whole map's, bit for bit, and a window that certifies a range of
//! columns holds every whole-map asperity with its summit there.
#![allow(clippy::unwrap_used)]

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_texture::{
    CapOptions, HeightMap, SegmentOptions, WindowFrame, asperity_cap, segment, segment_window,
};

const DX: f64 = 0.5e-3;

/// A rough strip: random chippings (ellipsoidal caps of random sizes and
/// heights, some touching, some merging) on a noisy base, with a few
/// invalid points.
fn rough_map(nx: usize, ny: usize, seed: u64) -> HeightMap {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let (lx, ly) = (nx as f64 * DX, ny as f64 * DX);
    let chips: Vec<[f64; 5]> = (0..(nx * ny) / 60)
        .map(|_| {
            [
                rng.random::<f64>() * lx,
                rng.random::<f64>() * ly,
                (1.0 + 3.0 * rng.random::<f64>()) * 1e-3,
                (1.0 + 3.0 * rng.random::<f64>()) * 1e-3,
                (0.5 + 2.5 * rng.random::<f64>()) * 1e-3,
            ]
        })
        .collect();
    let mut h = Vec::with_capacity(nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            let (x, y) = (i as f64 * DX, j as f64 * DX);
            let mut z: f64 = 0.0;
            for &[cx, cy, ax, ay, top] in &chips {
                let q = ((x - cx) / ax).powi(2) + ((y - cy) / ay).powi(2);
                if q < 1.0 {
                    z = z.max(top * (1.0 - q).sqrt());
                }
            }
            let z = z + 20e-6 * (2.0 * rng.random::<f64>() - 1.0);
            h.push(if rng.random::<f64>() < 0.002 {
                f64::NAN
            } else {
                z
            });
        }
    }
    HeightMap::from_nan_heights(nx, ny, DX, DX, h).unwrap()
}

fn columns(map: &HeightMap, cols: std::ops::Range<usize>) -> HeightMap {
    let (nx, ny) = (map.nx(), map.ny());
    let w = cols.len();
    let mut h = Vec::with_capacity(w * ny);
    for j in 0..ny {
        h.extend_from_slice(&map.heights()[j * nx + cols.start..j * nx + cols.end]);
    }
    HeightMap::from_nan_heights(w, ny, map.dx(), map.dy(), h).unwrap()
}

fn first_point(map: &HeightMap) -> (usize, usize) {
    let h = map.heights();
    let k = (0..h.len())
        .filter(|&k| map.valid()[k])
        .min_by(|&a, &b| h[b].total_cmp(&h[a]).then(a.cmp(&b)))
        .unwrap();
    (k % map.nx(), k / map.nx())
}

/// Checks every certified asperity of `win` (columns `cols` of `map`)
/// against the whole map's, bit for bit; returns how many have their
/// summit point in `own`.
fn check_certified(
    map: &HeightMap,
    whole: &tyreroad_texture::Segmentation,
    win: &tyreroad_texture::WindowSegmentation,
    cols: std::ops::Range<usize>,
    own: &std::ops::Range<usize>,
) -> usize {
    let nx = map.nx();
    let by_index: std::collections::HashMap<usize, usize> = whole
        .asperities()
        .iter()
        .enumerate()
        .map(|(k, a)| (a.summit_cell.1 * nx + a.summit_cell.0, k))
        .collect();
    let cap = CapOptions::default();
    let sub = columns(map, cols.clone());
    let seg = &win.segmentation;
    let mut in_own = 0;
    for (k, a) in seg.asperities().iter().enumerate() {
        if !win.is_certified(k) {
            continue;
        }
        let g = win.whole_index(k).unwrap();
        let &w = by_index
            .get(&g)
            .unwrap_or_else(|| panic!("certified asperity at {g} is not the whole map's"));
        let b = &whole.asperities()[w];
        assert_eq!(a.summit[0].to_bits(), b.summit[0].to_bits());
        assert_eq!(a.summit[1].to_bits(), b.summit[1].to_bits());
        assert_eq!(a.summit_height.to_bits(), b.summit_height.to_bits());
        assert_eq!(a.prominence.to_bits(), b.prominence.to_bits());
        assert_eq!(a.area.to_bits(), b.area.to_bits());
        assert_eq!(a.fit, b.fit);
        let cells: Vec<usize> = a
            .cells
            .iter()
            .map(|&c| (c / sub.nx()) * nx + c % sub.nx() + cols.start)
            .collect();
        assert_eq!(cells, b.cells, "cells of the asperity at {g}");
        let ours = asperity_cap(&sub, seg, k, &cap).ok();
        let theirs = asperity_cap(map, whole, w, &cap).ok();
        assert_eq!(ours, theirs, "cap of the asperity at {g}");
        if own.contains(&(g % nx)) {
            in_own += 1;
        }
    }
    in_own
}

#[test]
fn certified_windows_are_the_whole_maps_asperities() {
    let (nx, ny) = (900, 70);
    for (seed, prominence) in [(17, 0.15e-3), (5, 0.4e-3), (29, 0.05e-3)] {
        let map = rough_map(nx, ny, seed);
        let opts = SegmentOptions {
            min_prominence: prominence,
            min_area: 1e-6,
        };
        let whole = segment(&map, &opts).unwrap();
        assert!(
            whole.asperities().len() > 50,
            "{}",
            whole.asperities().len()
        );
        let first = first_point(&map);
        let tile = 150;
        let (mut found, mut grown, mut widest) = (0, 0, 0);
        for t0 in (0..nx).step_by(tile) {
            let own = t0..(t0 + tile).min(nx);
            let mut halo = 2;
            loop {
                let cols = own.start.saturating_sub(halo)..(own.end + halo).min(nx);
                let frame = WindowFrame {
                    first_column: cols.start,
                    whole_nx: nx,
                    whole_first: first,
                };
                let win = segment_window(&columns(&map, cols.clone()), frame, &opts).unwrap();
                // Sound at every width, not only the one that certifies.
                let in_own = check_certified(&map, &whole, &win, cols.clone(), &own);
                if win.certifies(own.clone()) {
                    // Every whole-map asperity with its summit in the range.
                    let expected = whole
                        .asperities()
                        .iter()
                        .filter(|a| own.contains(&a.summit_cell.0))
                        .count();
                    assert_eq!(in_own, expected, "tile {own:?}");
                    found += in_own;
                    widest = widest.max(cols.len());
                    break;
                }
                assert!(cols.len() < nx, "the whole map must certify itself");
                halo *= 2;
                grown += 1;
            }
        }
        assert_eq!(found, whole.asperities().len());
        println!(
            "seed {seed}, prominence {prominence}: {} asperities, {grown} halo doublings, \
             widest window {widest} of {nx} columns",
            whole.asperities().len()
        );
        // Some windows had to grow (the retry is exercised), and they stay
        // local: none needed a large part of the map.
        assert!(grown > 0);
        assert!(widest < nx / 2, "widest window {widest} of {nx}");
    }
}

#[test]
fn a_window_outside_the_map_is_refused() {
    let map = rough_map(40, 20, 3);
    let frame = WindowFrame {
        first_column: 30,
        whole_nx: 60,
        whole_first: (0, 0),
    };
    let opts = SegmentOptions {
        min_prominence: 0.1e-3,
        min_area: 1e-7,
    };
    assert!(segment_window(&map, frame, &opts).is_err());
}
