//! A `.npy` texture road read by windows (docs/distributed.md, "Memory per
//! rank"): every window equals the whole build restricted to it (ids,
//! positions, heights, laws, summit radii, `z_max`, digest: bit for bit),
//! and a rolling run split into ranks' parts, each rolled on windows of the
//! file, equals the single process's run.
#![allow(clippy::unwrap_used)]

use std::io::Write;
use std::path::Path;

use tyreroad::contact_law::{ContactLaw, Material};
use tyreroad::rolling::{Road, RollingResult};
use tyreroad::scenario::{Par, RoadSummary, RunOptions, Scenario, ScenarioResult};
use tyreroad::texture::{Aggregate, HeightMap, aggregate, read_any};
use tyreroad::texture_road::window::NpyTextureRoad;
use tyreroad::texture_road::{
    ID_BLOCK_COLUMNS, TextureLaw, TextureRoad, TextureRoadOptions, texture_road,
};

/// 0.4 m × 40 mm of dense asphalt at 0.25 mm (several tiles of columns),
/// with a few invalid points.
fn asphalt() -> HeightMap {
    let mut synth = Aggregate::new(1600, 160, 0.25e-3, 0.25e-3, Aggregate::grading_4_6(), 7);
    synth.coverage = 1.3;
    synth.embedding = (0.6, 0.8);
    let map = aggregate(&synth).unwrap();
    let mut h = map.heights().to_vec();
    for k in (0..h.len()).step_by(9973) {
        h[k] = f64::NAN;
    }
    HeightMap::from_nan_heights(map.nx(), map.ny(), map.dx(), map.dy(), h).unwrap()
}

/// Writes `map` as a float64 C-order `.npy` with its spacing sidecar.
fn write_npy(map: &HeightMap, path: &Path) {
    let mut header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}",
        map.ny(),
        map.nx()
    );
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut f = std::fs::File::create(path).unwrap();
    f.write_all(b"\x93NUMPY\x01\x00").unwrap();
    f.write_all(&(header.len() as u16).to_le_bytes()).unwrap();
    f.write_all(header.as_bytes()).unwrap();
    let bytes: Vec<u8> = map.heights().iter().flat_map(|v| v.to_le_bytes()).collect();
    f.write_all(&bytes).unwrap();
    let mut sidecar = path.as_os_str().to_os_string();
    sidecar.push(".spacing");
    std::fs::write(sidecar, format!("{:e} {:e}\n", map.dx(), map.dy())).unwrap();
}

fn material() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

#[test]
fn windows_of_a_npy_texture_equal_the_whole_road_restricted_to_them() {
    let dir = tempfile::tempdir().unwrap();
    let path = dir.path().join("road.npy");
    write_npy(&asphalt(), &path);
    let opts = TextureRoadOptions::new(0.1e-3, 1e-6);
    // The whole build, as a rolling scenario makes it.
    let map = read_any(&path).unwrap();
    let built = texture_road(&map, material(), &opts).unwrap();
    let whole = rolling_road(&built, &map);
    // The rolling order is block-major: blocks never decrease along ids.
    let order = built.rolling_order();
    let block = |k: usize| {
        built.segmentation.asperities()[built.asperity_index[k]]
            .summit_cell
            .0
            / ID_BLOCK_COLUMNS
    };
    assert!(order.windows(2).all(|w| block(w[0]) <= block(w[1])));
    // Tiles of 512 columns: four tiles, the last one short; the result
    // does not depend on the tiling.
    for tile in [512, 4096] {
        let npy = NpyTextureRoad::open_tiled(&path, material(), &opts, tile).unwrap();
        assert_eq!(npy.len(), whole.len());
        assert_eq!(npy.segmented(), built.segmentation.asperities().len());
        assert_eq!(npy.top().to_bits(), whole.top().to_bits());
        // Regression (2026-11-30): the missing points are counted tile by
        // tile, as the whole map counts them (the asphalt lacks 26).
        assert_eq!(npy.valid_points(), (map.valid_count(), map.heights().len()));
        assert_eq!(map.heights().len() - map.valid_count(), 26);
        assert_eq!(npy.digest(), whole.digest());
        // Per-block counts: the blocks' ids tile 0..N, each block's the
        // whole road's asperities of that block.
        let starts = npy.block_start();
        assert_eq!((starts[0], *starts.last().unwrap()), (0, whole.len()));
        for (b, w) in starts.windows(2).enumerate() {
            let count = order.iter().filter(|&&k| block(k) == b).count();
            assert_eq!(w[1] - w[0], count, "block {b}");
        }
        // The streamed summits: ids 0..N each once, in order, the whole
        // road's positions and heights bit for bit.
        let mut next = 0;
        npy.summits(|id, p, z| {
            assert_eq!(id, next);
            let q = whole.positions()[id];
            assert_eq!(
                [p[0].to_bits(), p[1].to_bits(), z.to_bits()],
                [
                    q[0].to_bits(),
                    q[1].to_bits(),
                    whole.heights()[id].to_bits()
                ]
            );
            next += 1;
        })
        .unwrap();
        assert_eq!(next, whole.len());
        let mut seen = vec![false; whole.len()];
        for range in [
            [0.0, 0.07],
            [0.1, 0.25],
            [0.12, 0.128],
            [0.31, 0.4],
            [0.38, 0.5],
        ] {
            let w = npy.window(range).unwrap();
            assert!(w.is_window());
            assert_eq!(w.global_len(), whole.len());
            assert_eq!(w.top().to_bits(), whole.top().to_bits());
            assert_eq!(w.digest(), whole.digest());
            for l in 0..w.len() {
                let g = w.global_id(l);
                seen[g] = true;
                let (p, q) = (w.positions()[l], whole.positions()[g]);
                assert_eq!(
                    [p[0].to_bits(), p[1].to_bits()],
                    [q[0].to_bits(), q[1].to_bits()]
                );
                assert_eq!(w.heights()[l].to_bits(), whole.heights()[g].to_bits());
                assert_eq!(w.laws()[l].geometry(), whole.laws()[g].geometry());
                for d in [1e-7, 1e-5, 3e-4, 2e-3] {
                    let (a, b) = (w.laws()[l].evaluate(d), whole.laws()[g].evaluate(d));
                    assert_eq!(a.force.to_bits(), b.force.to_bits());
                    assert_eq!(a.stiffness.to_bits(), b.stiffness.to_bits());
                }
                assert_eq!(
                    w.summit_radius(l).to_bits(),
                    whole.summit_radius(g).to_bits()
                );
            }
            // Every whole-road asperity in the range is in the window.
            let inside = |r: &Road<_>| {
                r.positions()
                    .iter()
                    .filter(|p| (range[0]..=range[1]).contains(&p[0]))
                    .count()
            };
            assert_eq!(inside(&w), inside(&whole), "window {range:?}");
            assert!(inside(&w) > 0);
        }
        assert!(npy.window([0.5, 0.6]).is_err(), "a window off the map");
        // Windows covering the road give every id (each checked above).
        for x in (0..40).map(|k| f64::from(k) * 0.01) {
            let w = npy.window([x, x + 0.01]).unwrap();
            for l in 0..w.len() {
                seen[w.global_id(l)] = true;
            }
        }
        assert!(seen.iter().all(|&s| s), "some id is in no window");
    }
}

/// The whole road as a rolling scenario builds it: the texture's
/// asperities in the rolling order, y centred on the map's mid-width, the
/// approach from the map's highest point.
fn rolling_road(built: &TextureRoad, map: &HeightMap) -> Road<TextureLaw> {
    let (set, radii) = built.rolling_set().unwrap();
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    tyreroad::texture_road::rolling_road(set.translated([0.0, -y_mid]).unwrap(), radii, built.top)
        .unwrap()
}

fn compare(a: &RollingResult, b: &RollingResult) -> f64 {
    assert_eq!(a.steps.len(), b.steps.len());
    let mut worst = 0.0f64;
    for (x, y) in a.steps.iter().zip(&b.steps) {
        assert_eq!(
            (x.index, &x.contact_ids, x.status),
            (y.index, &y.contact_ids, y.status)
        );
        for (u, v) in [
            (x.total_force, y.total_force),
            (x.approach, y.approach),
            (x.contact_area, y.contact_area),
        ]
        .into_iter()
        .chain(
            x.sensor_forces
                .iter()
                .copied()
                .zip(y.sensor_forces.iter().copied()),
        ) {
            worst = worst.max((u - v).abs() / u.abs().max(v.abs()).max(1e-300));
        }
    }
    worst
}

#[test]
fn parts_rolled_on_npy_windows_equal_the_single_process() {
    let dir = tempfile::tempdir().unwrap();
    write_npy(&asphalt(), &dir.path().join("road.npy"));
    let toml = r#"
name = "texture_windows"
[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5
# The Wilke laws: the rung that reads a .npy road by windows.
[model]
fidelity = "wilke"
[rolling]
start = "40 mm"
end = "360 mm"
step = "5 mm"
speed = "50 km/h"
margin = "0 mm"
reference_force = "1 N"
[rolling.tread]
kind = "tyre"
radius_x = "0.3 m"
radius_y = "0.5 m"
length = "60 mm"
width = "40 mm"
[rolling.control]
load = "300 N"
[[rolling.sensor]]
name = "centre"
x0 = "200 mm"
x1 = "260 mm"
y0 = "-10 mm"
y1 = "10 mm"
[texture]
file = "road.npy"
min_prominence = "0.1 mm"
min_area = "1 mm2"
"#;
    let scenario_path = dir.path().join("texture_windows.toml");
    std::fs::write(&scenario_path, toml).unwrap();
    let scenario = Scenario::from_path(&scenario_path).unwrap();
    let options = RunOptions {
        par: Some(Par::Seq),
        ..RunOptions::new(dir.path())
    };
    let ScenarioResult::Rolling(single) = scenario.run(&options).unwrap() else {
        panic!("not a rolling scenario");
    };
    let total = scenario.rolling_steps().unwrap();
    assert!(
        single
            .result
            .steps
            .iter()
            .all(|s| !s.contact_ids.is_empty())
    );
    for ranks in [2, 3] {
        let mut steps = Vec::new();
        for rank in 0..ranks {
            let range = rank * total / ranks..(rank + 1) * total / ranks;
            steps.extend(scenario.roll_part(&options, range, 2).unwrap().steps);
        }
        let gathered = RollingResult {
            steps,
            ..single.result.clone()
        };
        let run = scenario.finish_rolling(&options, gathered).unwrap();
        let worst = compare(&run.result, &single.result);
        println!("{ranks} ranks on windows: largest relative difference {worst:.1e}");
        assert!(worst <= 1e-9, "{worst}");
        let levels = |s: &tyreroad::scenario::Spectra| -> Vec<f64> {
            let bands = s.primary.iter().chain(s.sensors.iter().flatten());
            bands.map(|b| b.level_db).collect()
        };
        let (a, b) = (levels(&run.spectra), levels(&single.spectra));
        assert_eq!(a.len(), b.len());
        assert!(
            a.iter().zip(&b).all(|(x, y)| (x - y).abs() <= 1e-9),
            "{a:?} {b:?}"
        );
        assert_eq!(run.road_positions, single.road_positions);
        assert_eq!(run.road_heights, single.road_heights);
        // The finish streamed the summits from the file (no whole build):
        // the same summary, Sq summed tile by tile to rounding.
        let (RoadSummary::Texture(a), RoadSummary::Texture(b)) = (&run.road, &single.road) else {
            panic!("not texture summaries: {:?} {:?}", run.road, single.road);
        };
        assert_eq!(
            (a.size, a.spacing, a.extent, a.asperities, a.segmented),
            (b.size, b.spacing, b.extent, b.asperities, b.segmented)
        );
        assert!(
            (a.rms - b.rms).abs() <= 1e-12 * b.rms,
            "{} {}",
            a.rms,
            b.rms
        );
        // Both say that points are missing, as a whole map's summary does.
        for summary in [a, b] {
            assert!(
                summary
                    .warnings
                    .iter()
                    .any(|w| w.starts_with("26 of 256000 points (0.01 %) are missing")),
                "{:?}",
                summary.warnings
            );
        }
    }
}
