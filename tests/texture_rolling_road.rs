//! `Scenario::texture_rolling_road` (the road `cargo xtask converge-sweep`
//! builds once and rolls at every load) must be the road a scenario run
//! rolls: the same asperities and the same contact-point gaps. A road built
//! without the summit radii rolls a different model (gaps at the summits),
//! which the sweep once measured by mistake.

use std::path::Path;

use tyreroad::rolling::{self, RunOptions};
use tyreroad::scenario::units::Length;
use tyreroad::scenario::{RunOptions as ScenarioRunOptions, Scenario, ScenarioResult};

#[test]
fn the_converge_sweep_road_rolls_exactly_as_the_scenario_does() {
    let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures/rolling_visco_bem_small.toml");
    let mut scenario = Scenario::from_path(&path).expect("fixture");
    scenario.material.viscoelastic = None;
    // The sweep rolls the Wilke laws; an elastic texture run's default is
    // the calibrated rung.
    scenario.model.fidelity = Some("wilke".into());
    let spec = scenario.rolling.as_mut().expect("[rolling]");
    spec.end = Length::si(spec.start.value() + 7e-3); // 8 steps
    let base = path.parent().expect("fixtures dir");
    let ScenarioResult::Rolling(run) = scenario
        .run(&ScenarioRunOptions::new(base))
        .expect("scenario run")
    else {
        panic!("not a rolling result");
    };
    let road = scenario.texture_rolling_road(base).expect("road");
    let config = scenario.rolling_config().expect("config");
    let sweep = rolling::roll(
        &road,
        scenario.material().expect("material"),
        &config,
        &RunOptions::default(),
    )
    .expect("sweep road rolls");
    assert_eq!(run.result.steps.len(), 8);
    assert_eq!(sweep.steps.len(), run.result.steps.len());
    for (a, b) in sweep.steps.iter().zip(&run.result.steps) {
        // The same model and the same arithmetic: equal to rounding.
        assert!(
            (a.approach - b.approach).abs() <= 1e-12 * b.approach.abs(),
            "approach {} against {} at x = {}",
            a.approach,
            b.approach,
            b.position
        );
    }
    // The summit gaps would move the approach by micrometres on this road:
    // the test can tell the two roads apart.
    let summit_road = rolling::Road::new(road.set().clone());
    let summit = rolling::roll(
        &summit_road,
        scenario.material().expect("material"),
        &config,
        &RunOptions::default(),
    )
    .expect("summit road rolls");
    let moved = summit
        .steps
        .iter()
        .zip(&run.result.steps)
        .map(|(a, b)| (a.approach - b.approach).abs())
        .fold(0.0, f64::max);
    assert!(
        moved > 1e-7,
        "summit gaps moved the approach by only {moved} m"
    );
}

/// Regression (adversarial run, 2026-11-29): a footprint larger than the
/// whole map rolled with only the clearance warning, the load resting on
/// the part of the footprint that is on the map. The run now says so, with
/// the footprint's and the map's extents; a footprint within the map (or
/// past it by a sliver) is not warned of.
#[test]
fn a_footprint_reaching_off_the_map_is_warned_of() {
    use tyreroad::scenario::RoadSummary;
    use tyreroad::texture::HeightMap;
    use tyreroad::texture::io::text::write_ascii_grid;
    let dir = tempfile::tempdir().expect("temp dir");
    // 29.75 × 19.75 mm at 0.25 mm: two bumps.
    let (nx, ny, dx) = (120, 80, 2.5e-4);
    let heights = (0..nx * ny)
        .map(|k| {
            let (x, y) = ((k % nx) as f64 * dx, (k / nx) as f64 * dx);
            let bump = |cx: f64, cy: f64| {
                let r2 = (x - cx).powi(2) + (y - cy).powi(2);
                (1e-3 - r2 / 4e-3).max(0.0)
            };
            bump(10e-3, 10e-3) + bump(20e-3, 9e-3)
        })
        .collect();
    let map = HeightMap::new(nx, ny, dx, dx, heights).expect("map");
    write_ascii_grid(&map, dir.path().join("bumps.asc")).expect("write");
    let warnings = |length: &str, width: &str| -> Vec<String> {
        let text = format!(
            "name = \"bumps\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [model]\nfidelity = \"wilke\"\n\
             [rolling]\nstart = \"13 mm\"\nend = \"16 mm\"\nstep = \"1 mm\"\nspeed = \"50 km/h\"\n\
             margin = \"0 mm\"\n\
             [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\n\
             length = \"{length}\"\nwidth = \"{width}\"\n\
             [rolling.control]\nload = \"5 N\"\n\
             [texture]\nfile = \"bumps.asc\"\nmin_prominence = \"0.1 mm\"\nmin_area = \"0.01 mm2\"\n"
        );
        let s = Scenario::parse(&text, "bumps").expect("scenario");
        let ScenarioResult::Rolling(run) =
            s.run(&ScenarioRunOptions::new(dir.path())).expect("run")
        else {
            panic!("not a rolling result");
        };
        let RoadSummary::Texture(t) = &run.road else {
            panic!("not a texture road");
        };
        t.warnings.clone()
    };
    let off = |w: &[String]| w.iter().any(|w| w.contains("reaches off the map"));
    assert!(!off(&warnings("20 mm", "15 mm")), "within the map");
    assert!(!off(&warnings("20 mm", "20 mm")), "a sliver across");
    let wide = warnings("20 mm", "60 mm");
    assert!(
        wide.iter().any(|w| w.starts_with(
            "the tread's footprint (20.0 × 60.0 mm) reaches off the map (29.8 × 19.8 mm)"
        ) && w.contains("y = -30.0 … 30.0 mm")),
        "{wide:?}"
    );
    assert!(off(&warnings("60 mm", "15 mm")), "along the path");
}
