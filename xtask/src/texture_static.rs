//! `cargo xtask run` for a `[texture]` scenario: a flat elastic block
//! pressed on a road texture. The texture becomes asperities through
//! `tyreroad::texture_road`; the pressure maps are the two-scale rebuild
//! (`tyreroad::two_scale`) on each asperity's real surface.

use std::path::Path;
use std::sync::Arc;

use anyhow::{Context, Result, bail};
use tyreroad::texture_road::texture_road;
use tyreroad::two_scale::{TwoScaleOptions, two_scale};
use tyreroad_multipoint::Problem;

use crate::output::Csv;
use crate::pressure_image::write_pressure_png;
use crate::scenario::Scenario;
use crate::statics::{print_table, run_static_problem, write_static_outputs};

/// Runs a scenario's `[static]` loads on its `[texture]`. Writes
/// - `out/NAME.csv` (indenter = asperity index + 1, highest summit first;
///   the radius column is the half-section rule's) and the force and radius
///   charts;
/// - `out/NAME_summary.csv`
///   (`load_n,total_n,approach_m,contacts,asperities,overlapping_pairs`: pairs
///   of contacts whose half-section radii overlap, where the model's premise
///   fails);
/// - `out/NAME_two_scale.csv`
///   (`load_n,indenter,force_n,contact_area_m2,radius_m,max_pressure_pa`):
///   each loaded asperity's contact rebuilt by a local BEM solve on its own
///   surface;
/// - one two-scale pressure map per load, `out/NAME_pressure_<load>N.png`,
///   at the texture's grid spacing.
///
/// `base_dir` is the scenario file's directory, against which
/// `[texture] file` is resolved.
pub fn run_texture_static(scenario: &Scenario, base_dir: &Path, out: &Path) -> Result<()> {
    let (Some(texture), Some(spec)) = (&scenario.texture, &scenario.static_case) else {
        bail!("scenario {}: needs [texture] and [static]", scenario.name);
    };
    if spec.loads.is_empty() {
        bail!("scenario {}: [static] loads is empty", scenario.name);
    }
    let map = Arc::new(texture.height_map(base_dir)?);
    let material = scenario.material()?;
    let road = texture_road(&map, material, &texture.road_options())
        .context("turning the texture into asperities")?;
    let segmented = road.segmentation.asperities().len();
    println!(
        "texture {} × {} at {:.3} × {:.3} mm: {} asperities ({} segmented, {} without depth range)",
        map.nx(),
        map.ny(),
        map.dx() * 1e3,
        map.dy() * 1e3,
        road.len(),
        segmented,
        segmented - road.len()
    );
    let shapes = road.local_shapes(&map)?;
    let positions = road.positions.clone();
    let ids: Vec<u32> = (1..=road.len() as u32).collect();
    let problem = Problem::from_heights(road.positions, &road.heights, road.laws, material)?;
    let loads: Vec<f64> = spec.loads.iter().map(|l| l.value()).collect();
    let (rows, runs, _) = run_static_problem(
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
    let mut summary = Csv::new("load_n,total_n,approach_m,contacts,asperities,overlapping_pairs");
    let mut local_csv =
        Csv::new("load_n,indenter,force_n,contact_area_m2,radius_m,max_pressure_pa");
    let options = TwoScaleOptions {
        map_cell: Some(map.dx().min(map.dy())),
        ..TwoScaleOptions::default()
    };
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
            r.overlapping.to_string(),
        ]);
        if r.overlapping > 0 {
            println!(
                "  note: {} pairs of contacts overlap (a_i + a_j > spacing): the multipoint \
                 model's point-force coupling does not hold there (docs/validation.md)",
                r.overlapping
            );
        }
        let forces: Vec<f64> = rows
            .iter()
            .filter(|row| row.load == r.load)
            .map(|row| row.force)
            .collect();
        let ts = two_scale(&positions, &forces, &shapes, &material, &options)
            .with_context(|| format!("two-scale pressure map at {} N", r.load))?;
        for (k, f) in ts.local.iter().enumerate().filter(|(_, f)| f.force > 0.0) {
            local_csv.row(&[
                format!("{}", r.load),
                ids[k].to_string(),
                format!("{:.9e}", f.force),
                format!("{:.9e}", f.contact_area),
                format!("{:.9e}", f.radius),
                format!("{:.9e}", f.max_pressure),
            ]);
        }
        if let Some(field) = &ts.map {
            let area: f64 = ts.local.iter().map(|f| f.contact_area).sum();
            println!(
                "  two-scale: contact area {:.2} mm², peak {:.2} MPa, map Σ p dA = {:.6} N",
                area * 1e6,
                field.max() * 1e-6,
                field.integral()
            );
            let path = out.join(format!("{}_pressure_{}N.png", scenario.name, r.load));
            write_pressure_png(&path, field, &format!("{} N", r.load))?;
            written.push(path.display().to_string());
        }
    }
    let path = out.join(format!("{}_summary.csv", scenario.name));
    summary.write(&path)?;
    written.push(path.display().to_string());
    let path = out.join(format!("{}_two_scale.csv", scenario.name));
    local_csv.write(&path)?;
    written.push(path.display().to_string());
    for w in written {
        println!("written {w}");
    }
    Ok(())
}
