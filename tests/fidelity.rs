//! The fidelity ladder end to end: `[model] fidelity` in a scenario, and
//! the calibrated rung against the full BEM on a small texture of balls
//! (the heavy, seven-road comparison is `cargo xtask validate --textures`).
#![allow(clippy::unwrap_used)]

use tyreroad::contact_law::Material;
use tyreroad::fidelity::compare::{CompareOptions, compare_texture};
use tyreroad::fidelity::{CalibrationOptions, Fidelity, RUNGS};
use tyreroad::multipoint::SolverOptions;
use tyreroad::scenario::{RunOptions, Scenario, ScenarioError, ScenarioResult};
use tyreroad::texture::HeightMap;
use tyreroad::texture_road::TextureRoadOptions;

type TestResult = Result<(), Box<dyn std::error::Error>>;

fn texture_scenario(fidelity: &str) -> String {
    format!(
        "name = \"f\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
         [model]\nfidelity = \"{fidelity}\"\n[static]\nloads = [\"5 N\", \"20 N\"]\n\
         [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
         [texture.synth]\nkind = \"aggregate\"\nnx = 120\nny = 120\nspacing = \"0.1 mm\"\n\
         grading = \"4/6\"\nseed = 3\n"
    )
}

#[test]
fn an_unknown_or_misplaced_fidelity_is_a_named_error() {
    let e = Scenario::parse(&texture_scenario("clusters"), "t").unwrap_err();
    assert!(
        matches!(&e, ScenarioError::Value { key, .. } if key.ends_with("[model] fidelity")),
        "{e}"
    );
    let s = Scenario::parse(&texture_scenario("distributed"), "t").unwrap();
    assert_eq!(s.fidelity().unwrap(), Fidelity::Distributed);
    let s = Scenario::parse(&texture_scenario("clustered"), "t").unwrap();
    assert_eq!(s.fidelity().unwrap(), Fidelity::Clustered);
    // Calibrated laws are built from a texture's caps: not for balls.
    for fidelity in [
        "calibrated",
        "distributed",
        "clustered",
        "calibrated_fields",
    ] {
        let balls = format!(
            "name = \"b\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [model]\nfidelity = \"{fidelity}\"\n[static]\nloads = [\"5 N\"]\n\
             [default_shape]\nkind = \"sphere\"\nradius = \"5 mm\"\n\
             [[asperity]]\nx = \"0 mm\"\ny = \"0 mm\"\n"
        );
        let e = Scenario::parse(&balls, "b").unwrap_err();
        assert!(e.to_string().contains("[model] fidelity"), "{e}");
    }
    // The field coupling is a static texture rung: accepted there, refused
    // on balls (no caps to calibrate) like the other calibrated rungs.
    let s = Scenario::parse(&texture_scenario("calibrated_fields"), "t").unwrap();
    assert_eq!(s.fidelity().unwrap(), Fidelity::CalibratedFields);
    // Absent means the paper's law.
    let s = Scenario::parse(
        &texture_scenario("wilke").replace("[model]\nfidelity = \"wilke\"\n", ""),
        "t",
    )
    .unwrap();
    assert_eq!(s.fidelity().unwrap(), Fidelity::Wilke);
}

#[test]
fn a_calibrated_texture_run_balances_every_load() -> TestResult {
    let mut approaches = std::collections::HashMap::new();
    for fidelity in ["wilke", "calibrated", "clustered", "calibrated_fields"] {
        let s = Scenario::parse(&texture_scenario(fidelity), fidelity)?;
        let ScenarioResult::Texture(r) = s.run(&RunOptions::new("."))? else {
            return Err("not a texture result".into());
        };
        approaches.insert(fidelity, r.statics.runs.last().map(|run| run.approach));
        assert!(r.statics.failed_loads.is_empty(), "{fidelity}");
        for run in &r.statics.runs {
            let total: f64 = r
                .statics
                .at_load(run.load)
                .iter()
                .map(|row| row.force)
                .sum();
            assert!(
                (total - run.load).abs() < 1e-6 * run.load,
                "{fidelity}: {total} vs {}",
                run.load
            );
        }
    }
    // The field coupling acts (it is not the point-coupled calibrated run
    // under another name) and moves the approach by little on separated
    // chippings (0.0-0.7 % in docs/validation.md's seven roads).
    let (c, f) = (approaches["calibrated"], approaches["calibrated_fields"]);
    let (c, f) = (c.ok_or("no calibrated load")?, f.ok_or("no fields load")?);
    let moved = (f - c).abs() / c;
    assert!(
        moved > 1e-9 && moved < 0.05,
        "approach {c} -> {f} ({moved:e})"
    );
    Ok(())
}

/// One ball R = 2 mm on a plane 1 mm below, 0.4 mm cells, its apex
/// 0.2 and 0.15 mm off the nearest grid point: the fitted summit stands
/// 25 µm above the map's highest point, 11 % of the approach at 2 N (the
/// run was 10.9 % off the BEM when it reported from the summit, 0.007 %
/// now).
fn ball_between_grid_points() -> Result<HeightMap, Box<dyn std::error::Error>> {
    let (r, apex) = (2e-3, [6.2e-3, 6.15e-3]);
    Ok(HeightMap::from_fn(31, 31, 4e-4, 4e-4, move |x, y| {
        let d2 = (x - apex[0]).powi(2) + (y - apex[1]).powi(2);
        if d2 < r * r {
            ((r * r - d2).sqrt() - (r - 1e-3)).max(0.0)
        } else {
            0.0
        }
    })?)
}

#[test]
fn a_static_texture_run_measures_its_approach_from_the_maps_highest_point() -> TestResult {
    let map = ball_between_grid_points()?;
    let load = 2.0;
    let dir = tempfile::tempdir()?;
    tyreroad::texture::io::text::write_ascii_grid(&map, dir.path().join("ball.asc"))?;
    let toml = "name = \"ball\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\n\
                poisson_ratio = 0.5\n[model]\nfidelity = \"calibrated\"\n\
                [static]\nloads = [\"2 N\"]\n[texture]\nfile = \"ball.asc\"\n\
                min_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n";
    let ScenarioResult::Texture(r) =
        Scenario::parse(toml, "ball")?.run(&RunOptions::new(dir.path()))?
    else {
        return Err("not a texture result".into());
    };
    let approach = r.statics.runs.first().ok_or("no load solved")?.approach;

    // The reference: the BEM on the same map measures from its highest cell.
    use tyreroad::bem::{self, BemOptions, Control, Grid, Solver};
    let grid = Grid::new(map.nx(), map.ny(), map.dx(), map.dy())?;
    let surface = bem::HeightMap::new(grid.clone(), map.heights().to_vec())?;
    let material = Material::new(6.54e6, 0.5)?;
    let bem = Solver::new(&grid, &material, &BemOptions::default())?
        .solve(&surface, Control::Load(load))?;
    // The test bites: the summit plane is well off the map's.
    let road = tyreroad::texture_road::texture_road(
        &map,
        material,
        &TextureRoadOptions::new(0.2e-3, 2e-6),
    )?;
    let summit_above_map = road.set.top() - road.top;
    assert!(
        summit_above_map > 0.03 * bem.approach,
        "{summit_above_map} vs {}",
        bem.approach
    );
    // One calibrated cap on the BEM's own grid: the same solve, up to the
    // table's interpolation (docs/validation.md: ~0.3 % on two balls).
    let error = approach / bem.approach - 1.0;
    assert!(
        error.abs() < 0.01,
        "model {approach} vs BEM {} ({error:+.4})",
        bem.approach
    );
    Ok(())
}

/// Two equal balls R = 5 mm, 12 mm apart, summits on cell centres, on a
/// plane 1.5 mm below, 0.1 mm cells.
fn two_balls() -> Result<HeightMap, Box<dyn std::error::Error>> {
    balls(241, 121, 1e-4, [[6e-3, 6e-3], [18e-3, 6e-3]])
}

/// Balls of 5 mm radius standing 1.5 mm proud of a flat at `centres`, on
/// `nx × ny` points at `dx`.
fn balls(
    nx: usize,
    ny: usize,
    dx: f64,
    centres: [[f64; 2]; 2],
) -> Result<HeightMap, Box<dyn std::error::Error>> {
    let r = 5e-3;
    Ok(HeightMap::from_fn(nx, ny, dx, dx, move |x, y| {
        centres
            .iter()
            .map(|c| {
                let d2 = (x - c[0]).powi(2) + (y - c[1]).powi(2);
                if d2 < r * r {
                    (r * r - d2).sqrt() - (r - 1.5e-3)
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    })?)
}

#[test]
fn calibrated_laws_bring_the_model_onto_the_bem_on_two_balls() -> TestResult {
    let map = two_balls()?;
    let options = CompareOptions {
        loads: vec![10.0, 40.0],
        road: TextureRoadOptions::new(0.2e-3, 2e-6),
        calibration: CalibrationOptions::default(),
        rungs: RUNGS.to_vec(),
        solver: SolverOptions::default(),
        neighbour_passes: 0,
    };
    let c = compare_texture(&map, Material::new(6.54e6, 0.5)?, &options)?;
    assert_eq!(c.asperities, 2);
    // The two caps are the same shape: one calibration solve, which the
    // calibrated, distributed, clustered and calibrated_fields rungs share
    // (seven cache hits).
    assert_eq!((c.cache.solved, c.cache.memory_hits), (1, 7));
    assert_eq!(c.rungs[4].fidelity, Fidelity::CalibratedFields);
    assert_eq!(c.rungs[1].fidelity, Fidelity::Calibrated);
    assert_eq!(c.rungs[2].fidelity, Fidelity::Distributed);
    assert_eq!(c.rungs[3].fidelity, Fidelity::Clustered);
    // 12 mm apart, no patches overlap: the clustered rung is the
    // calibrated one, bit for bit.
    for (a, b) in c.rungs[1].loads.iter().zip(&c.rungs[3].loads) {
        let (a, b) = (
            a.as_ref().map_err(|e| e.clone())?,
            b.as_ref().map_err(|e| e.clone())?,
        );
        assert_eq!(a.approach_error.to_bits(), b.approach_error.to_bits());
        assert_eq!(a.wrong_asperity.to_bits(), b.wrong_asperity.to_bits());
    }
    for l in c.rungs[1]
        .loads
        .iter()
        .chain(&c.rungs[2].loads)
        .chain(&c.rungs[4].loads)
    {
        let l = l.as_ref().map_err(|e| e.clone())?;
        // Two balls 12 mm apart at a ≤ 1.4 mm: the point coupling (and
        // the distributed one, which tends to it) is within 0.5 % of the
        // BEM's; the law is the BEM's own to its
        // tolerance and the PCHIP error. What remains is the BEM's
        // discretisation (docs/bem.md: ~0.3 % on the approach).
        assert!(l.approach_error.abs() < 0.01, "{l:?}");
        // Equal balls carry equal loads in both.
        assert!(l.wrong_asperity < 0.005, "{l:?}");
        // Areas: cell counts on both sides, the calibrated one interpolated
        // between its knots: ±½ cell on ≥ 13 cells per radius is ±4 % of
        // the area (measured 3.2 % at 10 N).
        assert!(l.area_error.abs() < 0.05, "{l:?}");
        // Forces as fields: the ball at (6, 6) mm straddles the 5 mm
        // blocks' edges at x = y = 5 mm. At its summit its whole force lands
        // in one block (measured 3.4 % of W on the wrong 5 mm block at
        // 10 N, 21.5 % at 40 N); its two-scale pressure spreads over the
        // four blocks as the BEM's does (0.50 % and 0.53 %: the local and
        // the map grids' discretisations).
        assert!(l.field_block[0] < 0.002 && l.field_block[1] < 0.01, "{l:?}");
        assert!(l.field_block[1] < 0.5 * l.wrong_block[1], "{l:?}");
    }
    let at_40 = c.rungs[1].loads[1].as_ref().map_err(|e| e.clone())?;
    assert!(at_40.wrong_block[1] > 0.1, "{at_40:?}");
    assert!(c.rungs.iter().all(|r| r.unavailable.is_none()));
    Ok(())
}

/// Segmentation invariance on a small self-affine texture (16 × 16 mm at
/// 0.1 mm, H 0.7, Sq 0.3 mm) at 40 N: the calibrated rung with
/// `min_prominence` 0.2 mm and 0.4 mm, which keep different asperities.
/// (About 3 min in the dev profile on the loaded 2-core machine: the
/// calibration solves of both segmentations.)
#[test]
fn a_coarser_segmentation_moves_the_outputs_little() -> TestResult {
    use tyreroad::fidelity::Calibrator;
    use tyreroad::fidelity::segmentation::segmentation_spread;
    let text = "name = \"seg\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
         [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
         [texture.synth]\nkind = \"self_affine\"\nnx = 160\nny = 160\nspacing = \"0.1 mm\"\n\
         seed = 7\nrms = \"0.3 mm\"\nhurst = 0.7\nlambda_long = \"8 mm\"\nlambda_short = \"0.5 mm\"\n";
    let s = Scenario::parse(text, "seg")?;
    let map = s
        .texture
        .as_ref()
        .ok_or("no texture")?
        .height_map(std::path::Path::new("."))?;
    let material = Material::new(6.54e6, 0.5)?;
    let fine = TextureRoadOptions::new(0.2e-3, 2e-6);
    let coarse = TextureRoadOptions::new(0.4e-3, 2e-6);
    let rows = segmentation_spread(
        &map,
        material,
        &[40.0],
        [&fine, &coarse],
        Fidelity::Calibrated,
        &SolverOptions::default(),
        &tyreroad::two_scale::TwoScaleOptions::default(),
        &Calibrator::new(material, CalibrationOptions::default()),
    )?;
    let [r] = rows.as_slice() else {
        return Err("one load, one row".into());
    };
    // The coarser segmentation merges asperities (10 kept, then 7): the
    // test compares two different splittings of one surface. Measured
    // (40 N): approach −0.44 %, area +0.60 %, load moved between 10 mm
    // blocks 0.60 %, between 5 mm blocks 0.77 % (issue 15's 1 % target;
    // the 40 × 40 mm roads of docs/validation.md move more).
    assert!(r.asperities[0] > r.asperities[1], "{r:?}");
    assert!(r.approach_change().abs() < 0.01, "{r:?}");
    assert!(r.area_change().abs() < 0.01, "{r:?}");
    assert!(r.block_moved.iter().all(|&m| m < 0.01), "{r:?}");
    Ok(())
}

/// Regression (2026-11-30, `validate --textures --scenario` on a 120 ×
/// 90 mm road): the block fields' rebuild assembled its pressure map at
/// the local fields' cell (tens of µm), over the whole road: 6e7 cells,
/// past the map's limit, and every load of the rung failed. The metrics
/// read the local fields only; the map is assembled at the texture's
/// spacing. Two balls at opposite corners of a 150 mm road, light loads
/// (contacts of about 0.4 mm: a local cell near 10 µm), each load solved,
/// the calibrated rung's approach on the BEM's to 2 %.
#[test]
fn a_wide_road_with_small_contacts_is_compared_not_failed_on_its_map() -> TestResult {
    let map = balls(400, 400, 3.75e-4, [[10e-3, 10e-3], [140e-3, 140e-3]])?;
    let options = CompareOptions {
        loads: vec![0.5, 1.0],
        road: TextureRoadOptions::new(0.2e-3, 2e-6),
        calibration: CalibrationOptions::default(),
        rungs: vec![Fidelity::Wilke, Fidelity::Calibrated],
        solver: SolverOptions::default(),
        neighbour_passes: 0,
    };
    let c = compare_texture(&map, Material::new(6.54e6, 0.5)?, &options)?;
    assert_eq!(c.asperities, 2);
    for rung in &c.rungs {
        for load in &rung.loads {
            let load = load
                .as_ref()
                .map_err(|e| format!("{}: {e}", rung.fidelity))?;
            assert!(load.field_block[0].is_finite(), "{load:?}");
            if rung.fidelity == Fidelity::Calibrated {
                assert!(load.approach_error.abs() < 0.02, "{load:?}");
            }
        }
    }
    Ok(())
}

/// Regression (adversarial run of the texture comparison, 2026-11-30): a
/// missing scan line through a ball's summit split it into two asperities
/// 0.6 µm apart, and the comparison reported an approach error of
/// +57 000 % as an ordinary row; a load pressing the road flat, or one
/// whose contact is a cell or two, gave rows of "perfect agreement" that
/// say nothing. Each is now said: the row's warning names the summits
/// inside each other's patch, and the comparison's notes say what the
/// reference cannot (missing points filled, the map pressed flat, a
/// contact of too few cells).
#[test]
fn a_comparison_says_what_its_rows_cannot() -> TestResult {
    let material = Material::new(6.54e6, 0.5)?;
    let options = |loads: Vec<f64>| CompareOptions {
        loads,
        road: TextureRoadOptions::new(0.2e-3, 2e-6),
        calibration: CalibrationOptions::default(),
        rungs: vec![Fidelity::Wilke],
        solver: SolverOptions::default(),
        neighbour_passes: 0,
    };
    // A scan line missing through the first ball's summit (y = 6 mm).
    let whole = two_balls()?;
    let mut heights = whole.heights().to_vec();
    for i in 0..whole.nx() {
        heights[60 * whole.nx() + i] = f64::NAN;
    }
    let holed = HeightMap::from_nan_heights(whole.nx(), whole.ny(), 1e-4, 1e-4, heights)?;
    let c = compare_texture(&holed, material, &options(vec![10.0]))?;
    let warnings: Vec<&String> = c.rungs[0]
        .loads
        .iter()
        .flatten()
        .flat_map(|l| &l.warnings)
        .collect();
    assert!(
        warnings
            .iter()
            .any(|w| w.contains("inside a contact patch")),
        "{warnings:?}"
    );
    // The whole ball map: no warning, no note at a load it carries.
    let c = compare_texture(&whole, material, &options(vec![10.0]))?;
    assert!(c.notes.is_empty(), "{:?}", c.notes);
    assert!(
        c.rungs[0]
            .loads
            .iter()
            .flatten()
            .all(|l| l.warnings.is_empty())
    );
    // Pressed flat, and a contact of a cell or two; a load given twice is
    // compared once, and said.
    let c = compare_texture(&whole, material, &options(vec![5000.0, 1e-6, 5000.0]))?;
    assert_eq!(
        c.bem.iter().map(|b| b.load).collect::<Vec<_>>(),
        [1e-6, 5000.0]
    );
    assert!(
        c.notes
            .iter()
            .any(|n| n.starts_with("1 load(s) listed more than once")),
        "{:?}",
        c.notes
    );
    assert!(
        c.notes
            .iter()
            .any(|n| n.contains("cell(s)") && n.contains("0.000001 N")),
        "{:?}",
        c.notes
    );
    assert!(
        c.notes
            .iter()
            .any(|n| n.contains("pressed flat") && n.contains("5000 N")),
        "{:?}",
        c.notes
    );
    Ok(())
}
