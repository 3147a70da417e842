//! Every hard road kind survives the pipeline: segmentation into
//! asperities, one tabulated law per asperity ([`texture_road`]), and a
//! flat-block static multipoint contact at 50, 150 and 300 N that balances
//! the load. `cargo test --test integration road_kinds:: -- --nocapture` prints, per kind
//! and load, the asperities, Newton iterations, load steps and residual
//! (docs/texture.md has the table).

use tyreroad::contact_law::Material;
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};
use tyreroad::texture::{
    BrushedConcrete, ExposedAggregate, HeightMap, Pave, PorousAsphalt, RoadGrid, Tining,
    WornChipSeal, brushed_concrete, exposed_aggregate, pave, porous_asphalt, tining,
    worn_chip_seal,
};
use tyreroad::texture_road::{TextureRoadOptions, texture_road};

type TestResult = Result<(), Box<dyn std::error::Error>>;

const LOADS: [f64; 3] = [50.0, 150.0, 300.0];

/// The kinds with their defaults on 40 × 40 mm at 0.2 mm; pavé, whose
/// blocks are 100 mm, on 240 × 240 mm at 1 mm.
fn kinds() -> Result<Vec<(&'static str, HeightMap)>, Box<dyn std::error::Error>> {
    let g = RoadGrid::square(200, 200, 0.2e-3);
    let seed = 2026;
    Ok(vec![
        ("transverse tining", tining(&Tining::transverse(g, seed))?),
        (
            "longitudinal tining",
            tining(&Tining::longitudinal(g, seed))?,
        ),
        (
            "brushed concrete",
            brushed_concrete(&BrushedConcrete::new(g, seed))?,
        ),
        (
            "exposed aggregate",
            exposed_aggregate(&ExposedAggregate::new(g, seed))?,
        ),
        (
            "porous asphalt",
            porous_asphalt(&PorousAsphalt::new(g, seed))?,
        ),
        (
            "worn chip seal",
            worn_chip_seal(&WornChipSeal::new(g, seed))?,
        ),
        (
            "pave",
            pave(&Pave::new(RoadGrid::square(240, 240, 1e-3), seed))?,
        ),
    ])
}

#[test]
fn every_road_kind_segments_and_balances_the_load() -> TestResult {
    let material = Material::new(6.54e6, 0.5)?;
    let opts = TextureRoadOptions::new(0.2e-3, 2e-6);
    let solver = SolverOptions::default();
    let mut failures = Vec::new();
    println!("kind | segmented | laws | load N | iterations | load steps | residual | contacts");
    for (name, map) in kinds()? {
        let road = match texture_road(&map, material, &opts) {
            Ok(r) => r,
            Err(e) => {
                failures.push(format!("{name}: texture_road: {e}"));
                continue;
            }
        };
        let segmented = road.segmentation.asperities().len();
        let count = road.set.len();
        let problem = Problem::from_set(road.set, material)?;
        for load in LOADS {
            match solve(&problem, Control::Load(load), &solver) {
                Ok(s) => {
                    let contacts = s.forces.iter().filter(|&&f| f > 0.0).count();
                    println!(
                        "{name} | {segmented} | {} | {load} | {} | {} | {:.1e} | {contacts}",
                        count, s.iterations, s.load_steps, s.residual
                    );
                    let balance = (s.total_force() - load).abs() / load;
                    if balance > 1e-9 || s.forces.iter().any(|&f| f < 0.0) {
                        failures.push(format!(
                            "{name} at {load} N: load balance {balance:.1e}, min force {:e}",
                            s.forces.iter().copied().fold(f64::INFINITY, f64::min)
                        ));
                    }
                }
                Err(e) => failures.push(format!("{name} at {load} N: {e}")),
            }
        }
    }
    assert!(failures.is_empty(), "{failures:#?}");
    Ok(())
}
