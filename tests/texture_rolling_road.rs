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
