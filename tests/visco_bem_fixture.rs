//! The viscoelastic BEM comparison fixture keeps the loaded contact clear of
//! the selection window, which is also the BEM's window (docs/viscoelastic.md,
//! "Rolling against the viscoelastic BEM"). The window is an implementation
//! detail, not physics: where it cuts the contact, an asperity leaves the
//! multipoint selection at once while the BEM loses its cap cell by cell,
//! and the comparison measures that, not the model. The sensors must also be
//! reached by rolling (both runs start from fresh rubber, the whole first
//! footprint pressed at once) and be left before the last step.
//!
//! The check rolls the Wilke laws with the relaxed modulus `E∞`: the
//! softest tread has the largest contact at any speed.

use std::path::Path;

use tyreroad::rolling::{self, RunOptions};
use tyreroad::scenario::Scenario;
use tyreroad::scenario::units::Pressure;

/// What a relaxed run of a fixture's path shows.
struct Reach {
    /// Least distance from a loaded asperity's summit to the window's edge
    /// along x and across (m), over every step.
    clearance: [f64; 2],
    /// Whether every sensor lies ahead of the first window's leading edge.
    sensors_ahead: bool,
    /// The sensors' largest force (N) and their force at the last step.
    sensor_peak: f64,
    sensor_last: f64,
}

fn relaxed_reach(name: &str) -> Reach {
    let path = Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("fixtures")
        .join(name);
    let base = path.parent().expect("fixtures dir");
    let mut scenario = Scenario::from_path(&path).expect("fixture");
    let tread = scenario
        .viscoelastic_material(base)
        .expect("tread")
        .expect("a viscoelastic fixture");
    scenario.material.youngs_modulus = Pressure::si(tread.long_term());
    scenario.material.viscoelastic = None;
    let road = scenario.texture_rolling_road(base).expect("road");
    let config = scenario.rolling_config().expect("config");
    let run = rolling::roll(
        &road,
        scenario.material().expect("material"),
        &config,
        &RunOptions::default(),
    )
    .expect("rolls");
    let (hx, hy) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    let mut clearance = [f64::INFINITY; 2];
    for step in &run.steps {
        for &i in &step.contact_ids {
            let [x, y] = road.positions()[i];
            clearance[0] = clearance[0].min(hx + m - (x - step.position).abs());
            clearance[1] = clearance[1].min(hy + m - (y - config.lateral).abs());
        }
    }
    let lead = config.start + hx + m;
    let sensor_peak = run
        .steps
        .iter()
        .flat_map(|s| s.sensor_forces.iter().copied())
        .fold(0.0, f64::max);
    let last = run.steps.last().expect("steps");
    Reach {
        clearance,
        sensors_ahead: config.sensors.iter().all(|s| s.x[0] > lead),
        sensor_peak,
        sensor_last: last.sensor_forces.iter().copied().fold(0.0, f64::max),
    }
}

#[test]
fn the_visco_bem_comparison_fixture_keeps_the_contact_clear_of_the_window() {
    let clear = relaxed_reach("rolling_visco_bem_clear.toml");
    // Measured: 4.3 mm along x and 6.0 mm across (the summits; a loaded
    // cap's patch reaches a millimetre or two beyond its summit).
    assert!(
        clear.clearance[0] > 3e-3 && clear.clearance[1] > 3e-3,
        "clearance {:?} m",
        clear.clearance
    );
    assert!(clear.sensors_ahead);
    assert!(clear.sensor_peak > 5.0, "{}", clear.sensor_peak);
    assert_eq!(clear.sensor_last, 0.0);
    // The check can fail: on the first comparison fixture the 60 mm box cuts
    // the relaxed contact (loaded summits at its edge).
    let small = relaxed_reach("rolling_visco_bem_small.toml");
    assert!(
        small.clearance[0] < 1e-3 && small.clearance[1] < 1e-3,
        "clearance {:?} m",
        small.clearance
    );
}

#[test]
fn the_20mm_sensor_copy_of_the_clear_fixture_is_reached_and_left_by_rolling() {
    // Same window and stretch as the clear fixture; its 20 mm sensors reach
    // 10 mm further back (115 mm), which the relaxed contact, 41 mm behind
    // the last centre (156 mm), must have left.
    let copy = relaxed_reach("rolling_visco_bem_clear_20mm.toml");
    assert!(
        copy.clearance[0] > 3e-3 && copy.clearance[1] > 3e-3,
        "clearance {:?} m",
        copy.clearance
    );
    assert!(copy.sensors_ahead);
    assert!(copy.sensor_peak > 50.0, "{}", copy.sensor_peak);
    assert_eq!(copy.sensor_last, 0.0);
}
