//! Laws placed along the path (`Placement`, `Road::with_placement`): each
//! step solves the laws its placement hands out, the checkpoint key tells
//! a placed road from an unplaced one, and the diagnostics that borrow the
//! road's laws refuse a placed road.

use tyreroad_contact_law::{ContactLaw, HertzLaw, Material};
use tyreroad_multipoint::{AsperitySet, Control, Problem, SolverOptions, solve};
use tyreroad_rolling::{
    Road, RollingConfig, RollingControl, RollingError, RunOptions, Tread, input_hash, roll,
    settled_step, step_problem,
};

type TestResult = Result<(), Box<dyn std::error::Error>>;

const R: f64 = 5e-3;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("material")
}

/// Ahead of the footprint's centre a cap meets the tread as a sphere four
/// times as large; behind it, as itself.
fn larger_ahead(_: &HertzLaw, xi: f64) -> Option<HertzLaw> {
    (xi > 0.0)
        .then(|| HertzLaw::new(4.0 * R, rubber()).ok())
        .flatten()
}

/// Two rows of spheres at 4 mm pitch, 3 µm height steps.
fn road() -> Road<HertzLaw> {
    let n = 40;
    let positions = (0..n)
        .map(|i| [(i / 2) as f64 * 4e-3, if i % 2 == 0 { -3e-3 } else { 3e-3 }])
        .collect();
    let heights = (0..n).map(|i| (i % 3) as f64 * 3e-6).collect();
    let laws = vec![HertzLaw::new(R, rubber()).expect("law"); n];
    Road::new(AsperitySet::new(positions, heights, laws).expect("set"))
}

fn config() -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.2,
        length: 0.03,
        width: 0.02,
    };
    RollingConfig::new(tyre, [0.03, 0.05, 5e-3], 10.0, RollingControl::Load(20.0))
}

/// Each step of a placed road is the static solve, written from the
/// definition, of the laws the placement gives at that step's offsets.
#[test]
fn each_step_solves_the_laws_placed_at_its_offsets() -> TestResult {
    let (material, config) = (rubber(), config());
    let plain = road();
    let placed = road().with_placement(larger_ahead)?;
    let run = roll(&placed, material, &config, &RunOptions::default())?;
    let unplaced = roll(&plain, material, &config, &RunOptions::default())?;
    let (hx, hy) = config.tread.half_extents();
    let top = plain.top();
    for (step, other) in run.steps.iter().zip(&unplaced.steps) {
        let xc = step.position;
        let (mut ids, mut pos, mut gaps, mut laws) = (vec![], vec![], vec![], vec![]);
        for i in 0..plain.len() {
            let [x, y] = plain.positions()[i];
            if (x - xc).abs() <= hx && y.abs() <= hy {
                ids.push(i);
                pos.push([x, y]);
                gaps.push(top - plain.heights()[i] + (x - xc).powi(2) / 0.6 + y * y / 0.4);
                let r = if x - xc > 0.0 { 4.0 * R } else { R };
                laws.push(HertzLaw::new(r, material)?);
            }
        }
        let problem = Problem::new(pos, gaps, laws, material)?;
        let options = SolverOptions {
            tolerance: config.tolerance,
            ..SolverOptions::default()
        };
        let s = solve(&problem, Control::Load(20.0), &options)?;
        assert!(
            (step.approach - s.approach).abs() <= 1e-9 * s.approach,
            "{step:?}"
        );
        for (&id, &f) in step.contact_ids.iter().zip(&step.contact_forces) {
            let a = ids.iter().position(|&i| i == id).expect("selected");
            assert!(
                (f - s.forces[a]).abs() <= 1e-9 * 20.0,
                "{id}: {f} {}",
                s.forces[a]
            );
        }
        // The larger caps ahead carry the load shallower than the plain road.
        assert!(
            step.approach < other.approach,
            "{} {}",
            step.approach,
            other.approach
        );
        // The placed law a recount sees is the step's.
        let ahead = ids
            .iter()
            .copied()
            .find(|&i| plain.positions()[i][0] > xc)
            .expect("a cap ahead");
        let law = placed.law_at(ahead, xc);
        assert_eq!(
            law.force(1e-5),
            HertzLaw::new(4.0 * R, material)?.force(1e-5)
        );
    }
    Ok(())
}

#[test]
fn a_placed_road_keys_its_runs_apart_and_lends_no_step_problem() -> TestResult {
    let (material, config) = (rubber(), config());
    let placed = road().with_placement(larger_ahead)?;
    assert_ne!(
        input_hash(&placed, &material, &config),
        input_hash(&road(), &material, &config)
    );
    assert!(matches!(
        step_problem(&placed, material, &config, 0.04),
        Err(RollingError::InvalidInput(_))
    ));
    assert!(matches!(
        settled_step(&placed, material, &config, 0.04, Control::Load(20.0)),
        Err(RollingError::InvalidInput(_))
    ));
    assert!(step_problem(&road(), material, &config, 0.04)?.is_some());
    Ok(())
}
