//! One load is one item: a load whose solve cannot converge is recorded and
//! the other loads of the sweep are solved and kept
//! (`tyreroad::scenario::run_static_problem`).

use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Clusters, Problem, SolverOptions, layouts};
use tyreroad::scenario::run_static_problem;

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// `layouts::folding_field` from seed 1: the point-force model's load path
/// folds at 88 % of 100 N (crates/multipoint/tests/recovery.rs), so 100 N
/// has no solution on the branch the solver follows while 40 and 50 N do.
/// (With clusters, the solver's default last recovery, 100 N converges as
/// one merged body, crates/multipoint/tests/clusters.rs; these tests keep
/// the point model, where it fails.)
fn folding_layout() -> Result<Problem<PotentialLaw<Sphere>>, Box<dyn std::error::Error>> {
    let mut seed = 1;
    Ok(layouts::folding_field(Material::new(6.54e6, 0.5)?, || {
        lcg(&mut seed)
    })?)
}

fn point_only() -> SolverOptions {
    SolverOptions {
        clusters: Clusters::Off,
        ..SolverOptions::default()
    }
}

#[test]
fn a_load_that_cannot_converge_is_recorded_and_the_others_are_solved()
-> Result<(), Box<dyn std::error::Error>> {
    let problem = folding_layout()?;
    let ids: Vec<u32> = (1..=36).collect();
    let solved = run_static_problem(
        "folding",
        &problem,
        &ids,
        &[50.0, 100.0, 40.0],
        &point_only(),
    )?;
    let r = &solved.result;
    let solved_loads: Vec<f64> = r.runs.iter().map(|run| run.load).collect();
    assert_eq!(solved_loads, vec![50.0, 40.0]);
    assert_eq!(r.failed_loads.len(), 1);
    assert_eq!(r.failed_loads[0].0, 100.0);
    assert!(
        r.failed_loads[0].1.contains("did not converge"),
        "{}",
        r.failed_loads[0].1
    );
    // The solved loads balance, and only they have rows.
    for run in &r.runs {
        assert!((run.total - run.load).abs() <= 1e-9 * run.load);
        assert_eq!(r.at_load(run.load).len(), 36);
    }
    assert!(r.at_load(100.0).is_empty());
    // With no load solved the sweep is an error that names the load.
    let e = run_static_problem("folding", &problem, &ids, &[100.0], &point_only())
        .expect_err("nothing solved");
    assert!(e.to_string().contains("100 N"), "{e}");
    Ok(())
}

/// Regression (adversarial run, 2026-11-29): a texture load whose contacts
/// spread too far for a pressure map at the texture's spacing failed the
/// whole run ("the pressure map would have 30316036 cells"), the light
/// load beside it lost. It now gets a coarser map, with a note, and both
/// loads are written; the light load's map keeps the texture's spacing.
#[test]
fn a_load_too_heavy_for_a_fine_pressure_map_gets_a_coarser_one_not_the_runs_failure()
-> Result<(), Box<dyn std::error::Error>> {
    use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
    let text = "name = \"tex\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [static]\nloads = [\"10 N\", \"1e7 N\"]\n\
                [texture]\nfile = \"texture/spheres.x3p\"\nmin_prominence = \"0.2 mm\"\n\
                min_area = \"2 mm2\"\n";
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let s = Scenario::parse(text, "tex")?;
    let ScenarioResult::Texture(r) = s.run(&RunOptions::new(&fixtures))? else {
        return Err("not a texture result".into());
    };
    assert_eq!(r.loads.len(), 2);
    let spacing = r.map.dx().min(r.map.dy());
    let (light, heavy) = (&r.loads[0], &r.loads[1]);
    assert!(light.notes.is_empty(), "{:?}", light.notes);
    let light_map = light.two_scale.map.as_ref().ok_or("no map at 10 N")?;
    assert!((light_map.grid().dx() - spacing).abs() < 1e-12);
    assert_eq!(heavy.notes.len(), 1, "{:?}", heavy.notes);
    assert!(
        heavy.notes[0].contains("more than the limit"),
        "{:?}",
        heavy.notes
    );
    let heavy_map = heavy.two_scale.map.as_ref().ok_or("no map at 1e7 N")?;
    assert!(heavy_map.grid().dx() > spacing);
    assert!((heavy_map.integral() - 1e7).abs() < 1e-6 * 1e7);
    Ok(())
}

/// Regression (adversarial run, 2026-11-29): heights of 1e100 m failed the
/// run with a bare "Newton-Raphson did not converge … residual 1.000e0",
/// the plausibility warning (printed with the report) never reached. A run
/// that fails outright now carries what looked wrong with the heights.
#[test]
fn a_run_that_fails_outright_says_what_looked_wrong_with_the_heights()
-> Result<(), Box<dyn std::error::Error>> {
    use tyreroad::scenario::{RunOptions, Scenario};
    use tyreroad::texture::HeightMap;
    use tyreroad::texture::io::text::write_ascii_grid;
    let dir = tempfile::tempdir()?;
    let n = 40;
    let heights: Vec<f64> = (0..n * n)
        // At 1e100 m the solve converges since 2026-12-01 (elastic contact
        // is scale-free; its start no longer stops at an absolute width)
        // and only warns; at 1e150 m Newton's arithmetic runs out of range.
        .map(|k| 1e150 * ((k % n) as f64 * 0.7).sin() * ((k / n) as f64 * 0.5).cos())
        .collect();
    write_ascii_grid(
        &HeightMap::new(n, n, 2.5e-4, 2.5e-4, heights)?,
        dir.path().join("huge.asc"),
    )?;
    let text = "name = \"tex\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [model]\nfidelity = \"wilke\"\n[static]\nloads = [\"10 N\"]\n\
                [texture]\nfile = \"huge.asc\"\nmin_prominence = \"0.1 mm\"\nmin_area = \"0.1 mm2\"\n";
    let s = Scenario::parse(text, "tex")?;
    let e = s
        .run(&RunOptions::new(dir.path()))
        .err()
        .map(|e| e.to_string())
        .ok_or("heights of 1e150 m solved")?;
    assert!(
        e.contains("(the heights: Sq ") && e.contains("e152 mm is no road"),
        "{e}"
    );
    Ok(())
}

/// Regression (adversarial run, 2026-11-30): two `[[asperity]]` summits
/// 1 µm apart carried almost nothing between them, a third ball 10 mm away
/// took the whole load, and the run ended "every item converged" with only
/// the overlap note: the point kernel 1/r between summits inside each
/// other's patch is far too stiff. Each such load is now warned of; the
/// same balls 5 mm apart are not.
#[test]
fn summits_inside_each_others_contact_patch_are_warned_of() -> Result<(), Box<dyn std::error::Error>>
{
    let run = |dx: &str| {
        static_warnings(
            "kind = \"sphere\"\nradius = \"5 mm\"",
            &format!(
                "[[asperity]]\nx = \"0 mm\"\ny = \"0 mm\"\n[[asperity]]\nx = \"{dx}\"\ny = \"0 mm\"\n\
                 [[asperity]]\nx = \"10 mm\"\ny = \"0 mm\"\n"
            ),
        )
    };
    let close = run("0.001 mm")?;
    assert_eq!(close.len(), 2, "{close:?}");
    assert!(
        close[1].starts_with("load 50 N: the summits of asperities 1 and 2 lie 0.0010 mm apart"),
        "{close:?}"
    );
    assert!(run("5 mm")?.is_empty());
    Ok(())
}

/// Cones at the ends of their half-angle range run, as the closed forms
/// allow, but their answers are no road's: a needle's flank (1e-6°) is
/// refused by the half-space's small slopes, and a cone of 89.999999°
/// spreads one contact over metres, past every other summit. Both are
/// warned of; cones of 60–85° on the same set are not.
#[test]
fn cones_at_the_ends_of_their_range_are_warned_of() -> Result<(), Box<dyn std::error::Error>> {
    let run = |angle: &str| {
        static_warnings(
            &format!("kind = \"cone\"\nhalf_angle = \"{angle}\""),
            "[[asperity]]\nx = \"0 mm\"\ny = \"0 mm\"\n\
             [[asperity]]\nx = \"10 mm\"\ny = \"0 mm\"\nheight = \"-0.1 mm\"\n",
        )
    };
    let needle = run("0.000001 deg")?;
    assert_eq!(needle.len(), 1, "{needle:?}");
    assert!(
        needle[0].starts_with("2 cone(s) with flanks steeper than 45°, the steepest asperity 1"),
        "{needle:?}"
    );
    assert!(needle[0].contains("cot α = 5.730e7"), "{needle:?}");
    let flat = run("89.999999 deg")?;
    assert_eq!(flat.len(), 2, "{flat:?}");
    for (w, load) in flat.iter().zip(["5", "50"]) {
        assert!(
            w.starts_with(&format!("load {load} N, asperity 1: a contact radius of ")),
            "{flat:?}"
        );
        assert!(
            w.contains("wider than the whole set of summits (10.0000 mm"),
            "{w}"
        );
    }
    for angle in ["60 deg", "85 deg"] {
        assert!(run(angle)?.is_empty(), "{angle}");
    }
    // 44° is steep, 46° is not.
    assert_eq!(run("44 deg")?.len(), 1);
    assert!(run("46 deg")?.is_empty());
    Ok(())
}

/// The warnings of a static run at 5 and 50 N on the rubber of the paper
/// of asperities `asperities` (TOML) of default shape `shape` (TOML keys).
fn static_warnings(
    shape: &str,
    asperities: &str,
) -> Result<Vec<String>, Box<dyn std::error::Error>> {
    use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
    let text = format!(
        "name = \"static\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
         [default_shape]\n{shape}\n[static]\nloads = [\"5 N\", \"50 N\"]\n{asperities}"
    );
    let ScenarioResult::Static(r) = Scenario::parse(&text, "static")?.run(&RunOptions::default())?
    else {
        return Err("not a static run".into());
    };
    Ok(r.warnings)
}

/// Regression (2026-11-30): the needle-cone warning was a static run's
/// only; rolled, elastic or viscoelastic, a list of 30° cones said
/// nothing. Each now says it in its road summary, as the static run does;
/// 70° cones are not warned of.
#[test]
fn a_rolling_road_of_needle_cones_is_warned_of() -> Result<(), Box<dyn std::error::Error>> {
    use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
    let dir = tempfile::tempdir()?;
    let run = |angle: &str, visco: &str| -> Result<Vec<String>, Box<dyn std::error::Error>> {
        let text = format!(
            "name = \"cones\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n{visco}\
             [default_shape]\nkind = \"cone\"\nhalf_angle = \"{angle}\"\n\
             [rolling]\nstart = \"20 mm\"\nend = \"23 mm\"\nstep = \"1 mm\"\n\
             speed = \"50 km/h\"\nmargin = \"0 mm\"\ncheckpoint = false\n\
             [rolling.tread]\nkind = \"block\"\nlength = \"60 mm\"\nwidth = \"20 mm\"\n\
             [rolling.control]\nload = \"3 N\"\n\
             [[asperity]]\nid = 1\nx = \"10 mm\"\ny = \"0 mm\"\n\
             [[asperity]]\nid = 2\nx = \"20 mm\"\ny = \"0 mm\"\n\
             [[asperity]]\nid = 3\nx = \"30 mm\"\ny = \"0 mm\"\n"
        );
        let s = Scenario::parse(&text, "cones")?;
        let ScenarioResult::Rolling(run) = s.run(&RunOptions::new(dir.path()))? else {
            return Err("not a rolling result".into());
        };
        Ok(run.road.warnings().to_vec())
    };
    let visco = "[material.viscoelastic]\nlong_term = \"5 MPa\"\n\
                 [[material.viscoelastic.branch]]\nmodulus = \"5 MPa\"\n\
                 relaxation_time = \"1 ms\"\n";
    for tread in ["", visco] {
        let steep = run("30 deg", tread)?;
        assert!(
            steep.iter().any(|w| w
                .starts_with("3 cone(s) with flanks steeper than 45°, the steepest asperity 1")),
            "{steep:?}"
        );
        assert!(run("70 deg", tread)?.is_empty(), "{tread}");
    }
    Ok(())
}

/// Regression (adversarial run of the Python bindings, 2026-11-30):
/// `loads = ["50 N", "50 N"]` on a texture failed the whole run with
/// "two-scale pressure map at 50 N: 4 positions but 8 forces", the rows of
/// both copies taken as one load's. Each listed load is its own run and
/// pressure map, carrying its load; a copy is the same contact.
#[test]
fn a_texture_load_listed_twice_is_solved_and_mapped_twice() -> Result<(), Box<dyn std::error::Error>>
{
    use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
    let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let text = "name = \"twice\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\n\
                poisson_ratio = 0.5\n[static]\nloads = [\"20 N\", \"5 N\", \"20 N\"]\n\
                [texture]\nfile = \"texture/spheres.x3p\"\nmin_prominence = \"0.2 mm\"\n\
                min_area = \"1 mm2\"\n";
    let scenario = Scenario::parse(text, "twice")?;
    let ScenarioResult::Texture(result) = scenario.run(&RunOptions::new(&fixtures))? else {
        return Err("not a texture run".into());
    };
    let loads: Vec<f64> = result.statics.runs.iter().map(|r| r.load).collect();
    assert_eq!(loads, [20.0, 5.0, 20.0]);
    assert_eq!(result.loads.len(), 3);
    let n = result.texture.asperities;
    assert!(n >= 2, "{n} asperities");
    for (k, load) in result.loads.iter().enumerate() {
        assert_eq!(result.statics.rows_of_run(k).len(), n);
        let carried: f64 = load.two_scale.local.iter().map(|l| l.force).sum();
        assert!(
            (carried - load.load).abs() < 1e-6 * load.load,
            "run {k}: {carried} N for {} N",
            load.load
        );
    }
    let forces = |k: usize| -> Vec<f64> {
        result
            .statics
            .rows_of_run(k)
            .iter()
            .map(|r| r.force)
            .collect()
    };
    for (a, b) in forces(0).iter().zip(&forces(2)) {
        assert!((a - b).abs() <= 1e-6 * 20.0, "{a} vs {b}");
    }
    Ok(())
}

/// Regression (adversarial run, 2026-12-01): a map whose export wrote
/// −9999 m at 2 % of its points, where it measured nothing, was solved as
/// a road of deep wells (warned of only through its Sq and Sdq, and the
/// two-scale stage widened every local grid around them). The repeated far
/// value is now read as missing points, said so, and the run gives what
/// the same map with NaN there gives.
#[test]
fn sentinel_heights_are_read_as_missing_points() -> Result<(), Box<dyn std::error::Error>> {
    use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
    use tyreroad::texture::HeightMap;
    use tyreroad::texture::io::text::write_ascii_grid;
    let dir = tempfile::tempdir()?;
    let n = 60;
    let marked = |marker: f64| -> Vec<f64> {
        (0..n * n)
            .map(|k| {
                let (x, y) = ((k % n) as f64, (k / n) as f64);
                if k % 50 == 3 {
                    marker
                } else {
                    // Domes 4 mm apart, 0.5 mm high, at 0.25 mm.
                    2.5e-4 * (1.0 + (x * 0.39).cos() * (y * 0.39).cos())
                }
            })
            .collect()
    };
    for (name, marker) in [("marked", -9999.0), ("nan", f64::NAN)] {
        let map = HeightMap::from_nan_heights(n, n, 2.5e-4, 2.5e-4, marked(marker))?;
        write_ascii_grid(&map, dir.path().join(format!("{name}.asc")))?;
    }
    let run = |name: &str| -> Result<_, Box<dyn std::error::Error>> {
        let text = format!(
            "name = \"{name}\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [model]\nfidelity = \"wilke\"\n[static]\nloads = [\"10 N\"]\n\
             [texture]\nfile = \"{name}.asc\"\nmin_prominence = \"0.1 mm\"\nmin_area = \"0.5 mm2\"\n"
        );
        let ScenarioResult::Texture(t) =
            Scenario::parse(&text, name)?.run(&RunOptions::new(dir.path()))?
        else {
            return Err("not a texture result".into());
        };
        Ok(t)
    };
    let (marked, nan) = (run("marked")?, run("nan")?);
    let missing = (0..n * n).filter(|k| k % 50 == 3).count();
    assert_eq!(marked.map.valid_count(), n * n - missing);
    // NaN at the missing points of both (NaN ≠ NaN: compare the masks).
    assert!(marked.map.valid() == nan.map.valid());
    let valid_heights = |t: &tyreroad::scenario::TextureResult| -> Vec<f64> {
        let m = &t.map;
        m.heights()
            .iter()
            .zip(m.valid())
            .filter_map(|(h, ok)| ok.then_some(*h))
            .collect()
    };
    assert!(valid_heights(&marked) == valid_heights(&nan));
    assert!(
        marked.texture.warnings[0].starts_with(&format!(
            "{missing} point(s) at -9.999e3 m, a value repeated far outside"
        )),
        "{:?}",
        marked.texture.warnings
    );
    assert!(nan.texture.warnings.iter().all(|w| !w.contains("no data")));
    // The same map, so the same contact: every asperity's force equal.
    let forces = |t: &tyreroad::scenario::TextureResult| -> Vec<f64> {
        t.statics.rows.iter().map(|r| r.force).collect()
    };
    assert!(!forces(&marked).is_empty());
    assert_eq!(forces(&marked), forces(&nan));
    Ok(())
}
