//! A rolling step on a segmented texture: the road of
//! `fixtures/rolling_tyre_dense_asphalt.toml` (4/6.3 chippings, 60–80 %
//! embedded, 0.5 × 0.15 m at 0.25 mm), the tyre at x = 111 mm under 1500 N.
//! Several contacts there sit on kinks of their tabulated laws (table nodes,
//! ramp ends), where Newton's tangent mispredicts the force change by
//! orders of magnitude; before the secant corrections this step stalled at
//! a relative residual of 5.2e-11 whatever the tolerance.

use tyreroad::contact_law::{ContactLaw, Material};
use tyreroad::multipoint::{Control, SolverOptions, solve};
use tyreroad::rolling::{Road, RollingConfig, RollingControl, Tread, step_problem};
use tyreroad::texture::{Aggregate, aggregate};
use tyreroad::texture_road::{TextureRoadOptions, texture_road};

type TestResult = Result<(), Box<dyn std::error::Error>>;

#[test]
fn dense_asphalt_step_with_contacts_on_law_kinks_converges_tightly() -> TestResult {
    let material = Material::new(6.54e6, 0.5)?;
    let mut synth = Aggregate::new(2000, 600, 0.25e-3, 0.25e-3, Aggregate::grading_4_6(), 2006);
    synth.coverage = 1.3;
    synth.embedding = (0.6, 0.8);
    let map = aggregate(&synth)?;
    let road = texture_road(&map, material, &TextureRoadOptions::new(0.1e-3, 1e-6))?;
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let road = Road::new(road.set.translated([0.0, -y_mid])?);
    let tread = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.5,
        length: 0.12,
        width: 0.15,
    };
    let load = 1500.0;
    let config = RollingConfig::new(
        tread,
        [0.065, 0.435, 1e-3],
        50.0 / 3.6,
        RollingControl::Load(load),
    );
    let (ids, problem) = step_problem(&road, material, &config, 0.111)?.ok_or("no asperity")?;
    let options = SolverOptions {
        tolerance: 1e-12,
        ..SolverOptions::default()
    };
    let s = solve(&problem, Control::Load(load), &options)?;
    assert!(s.residual <= 1e-12, "{}", s.residual);
    assert!((s.total_force() - load).abs() < 1e-9 * load);
    assert!(s.forces.iter().all(|&f| f >= 0.0));
    // The step does exercise the kinks: contacts on the ramps of their laws.
    let on_ramps = ids
        .iter()
        .enumerate()
        .filter(|&(a, &i)| {
            s.forces[a] > 0.0
                && road.laws()[i]
                    .ramps()
                    .iter()
                    .any(|r| s.depths[a] >= r.start && s.depths[a] < r.end)
        })
        .count();
    assert!(on_ramps >= 5, "{on_ramps} contacts on ramps");
    // Each force is its law's at the solved depth.
    for (a, &i) in ids.iter().enumerate() {
        let p = road.laws()[i].force(s.depths[a]);
        assert!(
            (p - s.forces[a]).abs() <= 1e-9 * load,
            "{i}: {p} vs {}",
            s.forces[a]
        );
    }
    Ok(())
}
