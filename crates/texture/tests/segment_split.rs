//! `split_wide_tops`: which basins are split, into what, and what is kept.
#![allow(clippy::unwrap_used)]

use tyreroad_texture::{
    HeightMap, SegmentOptions, Segmentation, UNLABELLED, segment, split_wide_tops,
};

const CELL: f64 = 0.25e-3;

fn opts() -> SegmentOptions {
    SegmentOptions {
        min_prominence: 0.2e-3,
        min_area: 2e-6,
    }
}

/// A ground-flat mesa, top 24 × 12 mm at 1 mm (x 12–36 mm, y 6–18 mm),
/// sides falling over 1.5 mm, on a 48 × 24 mm map.
fn mesa() -> HeightMap {
    HeightMap::from_fn(193, 97, CELL, CELL, |x, y| {
        let out_x = (12e-3 - x).max(x - 36e-3).max(0.0);
        let out_y = (6e-3 - y).max(y - 18e-3).max(0.0);
        (1e-3 * (1.0 - out_x.max(out_y) / 1.5e-3)).max(0.0)
    })
    .unwrap()
}

/// Two balls: R = 20 mm at x = 10 mm and R = 40 mm at x = 34 mm (y = 12
/// mm), each standing 1.5 mm above the ground.
fn balls() -> HeightMap {
    HeightMap::from_fn(193, 97, CELL, CELL, |x, y| {
        [(10e-3, 20e-3), (34e-3, 40e-3)]
            .iter()
            .map(|&(cx, r)| {
                let d2: f64 = (x - cx).powi(2) + (y - 12e-3).powi(2);
                ((r * r - d2).max(0.0).sqrt() - (r - 1.5e-3)).max(0.0)
            })
            .fold(0.0, f64::max)
    })
    .unwrap()
}

/// Every labelled cell is in the cells of the asperity its label names,
/// and in no other.
fn assert_partition(seg: &Segmentation) {
    let mut seen = vec![0usize; seg.labels().len()];
    for (id, a) in seg.asperities().iter().enumerate() {
        for &c in &a.cells {
            assert_eq!(seg.labels()[c], id as u32, "cell {c}");
            seen[c] += 1;
        }
    }
    for (c, &l) in seg.labels().iter().enumerate() {
        assert_eq!(seen[c], usize::from(l != UNLABELLED), "cell {c}");
    }
}

#[test]
fn a_flat_mesa_is_tiled_with_each_force_at_its_tiles_middle() {
    let map = mesa();
    let seg = segment(&map, &opts()).unwrap();
    assert_eq!(seg.asperities().len(), 1);
    let split = split_wide_tops(&seg, &map, 4e-3).unwrap();
    assert_partition(&split);
    // The top (cells within 62.5 µm of it: the flat 24 × 12 mm, 97 × 49
    // cells, 24.25 × 12.25 mm of cell extent) in 7 × 4 tiles, none smaller
    // than a quarter of one.
    assert_eq!(split.asperities().len(), 28);
    let cells: usize = split.asperities().iter().map(|a| a.cells.len()).sum();
    assert_eq!(cells, seg.asperities()[0].cells.len());
    for pair in split.asperities().windows(2) {
        assert!(pair[0].summit_height >= pair[1].summit_height);
    }
    // Each tile is touched at the middle of its flat cells, at the top's
    // height, with no paraboloid (a plateau); the middles lie 3.46 mm
    // (24.25 / 7) apart along x.
    let mut xs = Vec::new();
    for a in split.asperities() {
        assert_eq!(a.summit_height, 1e-3);
        assert!(a.fit.is_none());
        assert_eq!(
            a.plateau,
            Some(0),
            "every tile names the mesa it was cut from"
        );
        let flat: Vec<usize> = a
            .cells
            .iter()
            .copied()
            .filter(|&c| map.heights()[c] == 1e-3)
            .collect();
        let n = flat.len() as f64;
        let middle = flat.iter().fold([0.0, 0.0], |[x, y], &c| {
            [
                x + (c % map.nx()) as f64 * CELL / n,
                y + (c / map.nx()) as f64 * CELL / n,
            ]
        });
        assert!(
            (a.summit[0] - middle[0]).abs() < 1e-12 && (a.summit[1] - middle[1]).abs() < 1e-12,
            "summit {:?}, middle {middle:?}",
            a.summit
        );
        if (a.summit[1] - 12e-3).abs() < 3e-3 {
            xs.push(a.summit[0]);
        }
    }
    xs.sort_by(f64::total_cmp);
    xs.dedup_by(|a, b| (*a - *b).abs() < 1e-9);
    assert_eq!(xs.len(), 7, "{xs:?}");
    for pair in xs.windows(2).skip(1).take(4) {
        assert!((pair[1] - pair[0] - 24.25e-3 / 7.0).abs() < CELL, "{xs:?}");
    }
}

#[test]
fn rounded_summits_are_left_whole_unless_flatter_than_eight_widths() {
    let map = balls();
    let seg = segment(&map, &opts()).unwrap();
    assert_eq!(seg.asperities().len(), 2);
    // Tops within 4 mm / 64 of the summits: 2·√(2·20·0.0625) = 3.2 mm and
    // 2·√(2·40·0.0625) = 4.5 mm wide (a sphere is split from R = 8 w).
    let kept = split_wide_tops(&seg, &map, 4e-3).unwrap();
    assert_eq!(
        kept.asperities().len(),
        5,
        "the 40 mm ball's top in 2 x 2 tiles"
    );
    // At 6 mm: 2·√(2·40·0.094) = 5.5 mm.
    let whole = split_wide_tops(&seg, &map, 6e-3).unwrap();
    assert_eq!(whole, seg, "no top wider than 6 mm: unchanged");
    // The small ball is kept bit for bit when the large one is split.
    let small = |s: &Segmentation| {
        s.asperities()
            .iter()
            .find(|a| (a.summit[0] - 10e-3).abs() < 1e-3)
            .cloned()
            .unwrap()
    };
    assert_eq!(small(&kept), small(&seg));
    assert_eq!(
        small(&kept).plateau,
        None,
        "a basin kept whole names no plateau"
    );
    // The large ball's four tiles name its basin in the input.
    let large = seg
        .asperities()
        .iter()
        .position(|a| (a.summit[0] - 34e-3).abs() < 1e-3);
    let tiles = kept.asperities().iter().filter(|a| a.plateau == large);
    assert_eq!(tiles.count(), 4);
    assert_partition(&kept);
}

#[test]
fn a_width_that_is_no_length_or_another_maps_segmentation_is_refused() {
    let map = mesa();
    let seg = segment(&map, &opts()).unwrap();
    for w in [0.0, -1e-3, f64::NAN, f64::INFINITY] {
        let e = split_wide_tops(&seg, &map, w).unwrap_err();
        assert!(e.to_string().contains("max_cap_width"), "{w}: {e}");
    }
    // Regression (adversarial run, 2026-11-29): a width below a few cells
    // was accepted and split nothing of a rounded top. Four cells is the
    // least.
    let e = split_wide_tops(&seg, &map, 3.9 * CELL)
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("invalid max_cap_width") && e.contains("at least four cells"),
        "{e}"
    );
    assert!(split_wide_tops(&seg, &map, 4.0 * CELL).is_ok());
    let other = balls();
    let small = HeightMap::from_fn(50, 50, CELL, CELL, |_, _| 0.0).unwrap();
    assert!(split_wide_tops(&segment(&other, &opts()).unwrap(), &small, 4e-3).is_err());
}

/// A tile inside the mesa's flat top is a flat punch of its shape at every
/// depth: it stands on the walls of its cut, down to the mesa's ground.
#[test]
fn a_tile_inside_a_flat_top_is_a_flat_punch_down_to_the_plateaus_floor() {
    use tyreroad_asperity::CapGeometry;
    let map = mesa();
    let split = split_wide_tops(&segment(&map, &opts()).unwrap(), &map, 4e-3).unwrap();
    let inner: Vec<usize> = (0..split.asperities().len())
        .filter(|&k| {
            split.asperities()[k]
                .cells
                .iter()
                .all(|&c| map.heights()[c] == 1e-3)
        })
        .collect();
    assert_eq!(inner.len(), 10, "5 x 2 tiles inside the top");
    for k in inner {
        let a = &split.asperities()[k];
        assert_eq!(a.floor, 0.0);
        let cap = tyreroad_texture::GridCap::new(&map, &split, k).unwrap();
        // The cells' bounding box less one cell each way: the complete
        // cells (their four corners in the tile).
        let (is, js): (Vec<usize>, Vec<usize>) = a
            .cells
            .iter()
            .map(|&c| (c % map.nx(), c / map.nx()))
            .unzip();
        let w = (is.iter().max().unwrap() - is.iter().min().unwrap()) as f64 * CELL;
        let h = (js.iter().max().unwrap() - js.iter().min().unwrap()) as f64 * CELL;
        assert_eq!(
            a.cells.len(),
            (w / CELL + 1.5) as usize * (h / CELL + 1.5) as usize
        );
        for depth in [1e-6, 0.3e-3, 0.99e-3] {
            let m = cap.cap(depth);
            assert!(
                (m.base_area - w * h).abs() < 1e-12 * w * h,
                "{k} {depth}: {m:?}"
            );
            assert!(
                (m.volume - w * h * depth).abs() < 1e-9 * w * h * depth,
                "{k}: {m:?}"
            );
            assert!((m.perimeter - 2.0 * (w + h)).abs() < 1e-12, "{k}: {m:?}");
        }
        let table = tyreroad_texture::asperity_cap(
            &map,
            &split,
            k,
            &tyreroad_texture::CapOptions {
                nodes: 40,
                max_depth: Some(a.summit_height - a.floor),
            },
        );
        assert!(table.is_ok(), "{k}: {:?}", table.err());
    }
}
