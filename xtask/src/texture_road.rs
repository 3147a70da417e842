//! From a road texture to the multipoint model: the height map is split
//! into asperities (`tyreroad_texture::segment`), each asperity's basin is
//! tabulated into a cap (`asperity_cap`), and each cap gets the
//! interaction-potential law with the half-section local rule.

use std::path::Path;
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use tyreroad::bem::Grid;
use tyreroad::two_scale::PressureField;
use tyreroad_contact_law::{C_SPHERE, LocalRule, Material, PotentialLaw};
use tyreroad_multipoint::{PressureGrid, Problem, pressure_map};
use tyreroad_texture::{
    CapOptions, HeightMap, SegmentOptions, Segmentation, asperity_cap, segment,
};

use crate::output::Csv;
use crate::pressure_image::write_pressure_png;
use crate::scenario::{AsperityParts, DynLaw, Scenario};
use crate::statics::{print_table, run_static_problem, write_static_outputs};

/// How a texture is turned into asperities.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TextureRoadOptions {
    /// Smallest prominence (summit − key saddle) of an asperity (m).
    pub min_prominence: f64,
    /// Smallest basin area of an asperity (m²).
    pub min_area: f64,
    /// Shape constant `c` of the potential law (0.36 for smooth summits).
    pub constant: f64,
    /// Tabulation of the caps. `max_depth: None` tabulates each cap down to
    /// the lowest point of its basin (the cap is then the basin's own
    /// surface below its boundary, not the grid cap's exact range, which is
    /// empty for a basin whose summit lies on the map's edge).
    pub cap: CapOptions,
}

impl TextureRoadOptions {
    /// Options with the given thresholds, `c = 0.36` and the default caps.
    pub fn new(min_prominence: f64, min_area: f64) -> Self {
        Self {
            min_prominence,
            min_area,
            constant: C_SPHERE,
            cap: CapOptions::default(),
        }
    }
}

/// A texture ready for the multipoint model.
pub struct TextureRoad {
    /// Summit positions (m), summit heights (m) and laws, one per kept
    /// asperity.
    pub parts: AsperityParts,
    /// The segmentation of the height map.
    pub segmentation: Segmentation,
    /// For each entry of `parts`, the index of its asperity in
    /// `segmentation.asperities()` (asperities without a depth range are
    /// dropped).
    pub asperity_index: Vec<usize>,
}

/// Segments `map` and builds one tabulated cap and law per asperity.
///
/// Asperities whose basin has no depth range (summit at the height of the
/// basin's boundary, e.g. a single point on a plateau) are skipped; the
/// others keep the segmentation's order (highest summit first).
pub fn texture_road(
    map: &HeightMap,
    material: Material,
    opts: &TextureRoadOptions,
) -> Result<TextureRoad> {
    let seg = segment(
        map,
        &SegmentOptions {
            min_prominence: opts.min_prominence,
            min_area: opts.min_area,
        },
    )
    .context("segmenting the texture")?;
    let n = seg.asperities().len();
    let (mut positions, mut heights, mut laws, mut index) = (
        Vec::with_capacity(n),
        Vec::with_capacity(n),
        Vec::<DynLaw>::with_capacity(n),
        Vec::with_capacity(n),
    );
    for (k, a) in seg.asperities().iter().enumerate() {
        let cap = CapOptions {
            max_depth: opts.cap.max_depth.or_else(|| basin_depth(map, a)),
            ..opts.cap
        };
        let Ok(table) = asperity_cap(map, &seg, k, &cap) else {
            continue;
        };
        let law = PotentialLaw::new(
            Arc::new(table),
            material,
            opts.constant,
            LocalRule::HalfSection,
        )
        .with_context(|| format!("asperity {k}: law"))?;
        positions.push(a.summit);
        heights.push(a.summit_height);
        laws.push(Box::new(law));
        index.push(k);
    }
    anyhow::ensure!(
        !positions.is_empty(),
        "the texture has no asperity with a depth range ({n} segmented)"
    );
    Ok(TextureRoad {
        parts: (positions, heights, laws),
        segmentation: seg,
        asperity_index: index,
    })
}

/// Summit height minus the lowest valid point of the basin, if positive.
fn basin_depth(map: &HeightMap, a: &tyreroad_texture::Asperity) -> Option<f64> {
    let low = a
        .cells
        .iter()
        .filter(|&&c| map.valid()[c])
        .map(|&c| map.heights()[c])
        .fold(f64::INFINITY, f64::min);
    let d = a.summit_height - low;
    (d.is_finite() && d > 0.0).then_some(d)
}

/// Runs a scenario's `[static]` loads on its `[texture]` (a flat elastic
/// block pressed on the texture): writes `out/NAME.csv` (indenter =
/// asperity index + 1, highest summit first), the force and radius charts,
/// `out/NAME_summary.csv` (`load_n,total_n,approach_m,contacts,asperities`)
/// and one pressure map per load, `out/NAME_pressure_<load>N.png`
/// (half-section local contacts on the texture's grid). `base_dir` is the
/// scenario file's directory, against which `[texture] file` is resolved.
pub fn run_texture_static(scenario: &Scenario, base_dir: &Path, out: &Path) -> Result<()> {
    let (Some(texture), Some(spec)) = (&scenario.texture, &scenario.static_case) else {
        bail!("scenario {}: needs [texture] and [static]", scenario.name);
    };
    if spec.loads.is_empty() {
        bail!("scenario {}: [static] loads is empty", scenario.name);
    }
    let map = texture.height_map(base_dir)?;
    let material = scenario.material()?;
    let road = texture_road(&map, material, &texture.road_options())?;
    println!(
        "texture {} × {} at {:.3} × {:.3} mm: {} asperities ({} segmented, {} without depth range)",
        map.nx(),
        map.ny(),
        map.dx() * 1e3,
        map.dy() * 1e3,
        road.parts.0.len(),
        road.segmentation.asperities().len(),
        road.segmentation.asperities().len() - road.asperity_index.len()
    );
    let (positions, heights, laws) = road.parts;
    let ids: Vec<u32> = (1..=positions.len() as u32).collect();
    let problem = Problem::from_heights(positions, &heights, laws, material)?;
    let loads: Vec<f64> = spec.loads.iter().map(|l| l.value()).collect();
    let (rows, runs, locals) = run_static_problem(
        &scenario.name,
        &problem,
        &ids,
        &loads,
        &scenario.solver_options(),
    )?;
    if ids.len() <= 40 {
        print_table(&rows);
    }
    std::fs::create_dir_all(out).with_context(|| format!("creating {}", out.display()))?;
    let mut written = write_static_outputs(out, &scenario.name, &rows)?;
    let mut summary = Csv::new("load_n,total_n,approach_m,contacts,asperities");
    for r in &runs {
        println!(
            "load {} N: Σ P = {:.9} N, δ0 = {:.6e} m, {} contacts of {}, {} iterations",
            r.load,
            r.total,
            r.approach,
            r.contacts,
            ids.len(),
            r.iterations
        );
        summary.row(&[
            format!("{}", r.load),
            format!("{:.9e}", r.total),
            format!("{:.9e}", r.approach),
            r.contacts.to_string(),
            ids.len().to_string(),
        ]);
    }
    let path = out.join(format!("{}_summary.csv", scenario.name));
    summary.write(&path)?;
    written.push(path.display().to_string());
    let grid = PressureGrid {
        x0: -0.5 * map.dx(),
        y0: -0.5 * map.dy(),
        dx: map.dx(),
        dy: map.dy(),
        nx: map.nx(),
        ny: map.ny(),
    };
    let field_grid = Grid::new(map.nx(), map.ny(), map.dx(), map.dy())?;
    for (r, contacts) in runs.iter().zip(&locals) {
        let pressure = pressure_map(problem.positions(), contacts, &grid)?;
        let field = PressureField {
            grid: field_grid.clone(),
            pressure,
        };
        let path = out.join(format!("{}_pressure_{}N.png", scenario.name, r.load));
        write_pressure_png(&path, &field, &format!("{} N", r.load))?;
        written.push(path.display().to_string());
    }
    for w in written {
        println!("written {w}");
    }
    Ok(())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use tyreroad_multipoint::{Control, Problem, SolverOptions, solve};

    /// Four balls R = 5 mm at known places on a plane, summits 2.0, 1.9,
    /// 1.8, 1.7 mm above it, 0.1 mm grid.
    fn balls() -> (HeightMap, Vec<[f64; 3]>) {
        let r = 5e-3;
        let centres = vec![
            [6.03e-3, 6.01e-3, 2.0e-3],
            [18.02e-3, 6.04e-3, 1.9e-3],
            [6.01e-3, 18.03e-3, 1.8e-3],
            [18.04e-3, 18.02e-3, 1.7e-3],
        ];
        let c = centres.clone();
        let map = HeightMap::from_fn(240, 240, 1e-4, 1e-4, move |x, y| {
            c.iter()
                .map(|&[cx, cy, top]| {
                    let d2 = (x - cx).powi(2) + (y - cy).powi(2);
                    if d2 < r * r {
                        (r * r - d2).sqrt() - (r - top)
                    } else {
                        0.0
                    }
                })
                .fold(0.0, f64::max)
        })
        .unwrap();
        (map, centres)
    }

    #[test]
    fn balls_on_a_plane_give_four_asperities_and_a_balanced_solve() {
        let (map, centres) = balls();
        let material = Material::new(6.54e6, 0.5).unwrap();
        let road = texture_road(&map, material, &TextureRoadOptions::new(0.2e-3, 1e-6)).unwrap();
        let (positions, heights, laws) = road.parts;
        assert_eq!(positions.len(), 4);
        // Highest first, each within one cell of its ball's summit.
        for (k, [cx, cy, top]) in centres.iter().enumerate() {
            assert!((positions[k][0] - cx).abs() < 1e-4, "{k}: {positions:?}");
            assert!((positions[k][1] - cy).abs() < 1e-4, "{k}: {positions:?}");
            assert!((heights[k] - top).abs() < 1e-5, "{k}: {heights:?}");
        }
        let problem = Problem::from_heights(positions, &heights, laws, material).unwrap();
        let load = 50.0;
        let s = solve(&problem, Control::Load(load), &SolverOptions::default()).unwrap();
        assert!(
            (s.total_force() - load).abs() < 1e-6 * load,
            "{}",
            s.total_force()
        );
        assert!(s.forces.iter().all(|&f| f >= 0.0));
        // The highest ball carries the most.
        assert!(s.forces[0] >= s.forces[3], "{:?}", s.forces);
        assert!(s.approach > 0.0);
    }
}
