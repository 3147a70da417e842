//! Each rung of the fidelity ladder (`tyreroad::fidelity`) on a road-like
//! field of 1500 summits: the static solve on every rung of
//! `fidelity::RUNGS` (Wilke laws, point coupling; BEM-calibrated laws with
//! point coupling, distributed near-pair coupling, clusters, and the
//! calibrated pressure fields' coupling by its fixed point), and the
//! calibration of one cap.
//! And the calibration of one road's caps, with the reference and the
//! default calibration options.
//! And rolling (issue #15: "the rolling fixture with the best rung must
//! stay within 3× of its time today"): 40 steps of the chip-seal fixture
//! (`fixtures/rolling_tyre_chip_seal.toml`) on its Wilke road and on its
//! calibrated road, plain (`calibrated`) and coupled through its fields
//! (`calibrated_fields`; and once more with the near pairs' double sums
//! bin by bin in `f64`, `PairSum::Exact`, to show what packing them
//! brings), the calibration (with fields) done once before timing (a later
//! run reading its tables back from the checkpoint folder pays only the
//! steps). And what a first calibrated run pays before its steps: the
//! calibration of the same 40 steps' road, its tables to the bound and to
//! their estimated depth (`tyreroad::fidelity::table_depth`).
//!
//! The field: `multipoint::layouts::road_like_field` (mean spacing 3 mm,
//! summit heights over 0.5 mm), its radii rounded to 0.5 mm classes so the
//! calibrated rung solves one cap per class (as a texture of repeated
//! chippings would); both rungs use the same rounded spheres. Load: a tyre's
//! 0.2 MPa over the field.

use criterion::{Criterion, criterion_group, criterion_main};
use tyreroad::asperity::Sphere;
use tyreroad::contact_law::PotentialLaw;
use tyreroad::fidelity::coupling::{FieldCouplingOptions, PairSum, solve_field_coupled};
use tyreroad::fidelity::rolling_fields::FieldRolling;
use tyreroad::fidelity::{
    CalibratedLaw, CalibrationOptions, Calibrator, CapPatch, Coupling, LawSource, RUNGS, calibrate,
};
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};

#[path = "common/mod.rs"]
mod common;

use common::{random_field, rubber, tyre_like_load};

const N: usize = 1500;
/// Depth range of the calibrated tables (m): past the approach at the
/// bench load (2.7 mm from the highest summit), so no law is extrapolated.
const DEPTH: f64 = 3.0e-3;
const CELL: f64 = 1e-4;

/// A true hemisphere of radius `r` on 0.1 mm cells (a cliff down to the
/// floor at its equator, as a chipping's basin ends), wide enough for the
/// contact at [`DEPTH`].
fn sphere_patch(r: f64) -> CapPatch {
    let reach = (2.0 * r * DEPTH).sqrt().min(r) + 4.0 * CELL;
    let n = 2 * (reach / CELL).ceil() as usize + 1;
    CapPatch::from_fn(n, CELL, |x, y| {
        let d2 = x * x + y * y;
        if d2 < r * r {
            (r * r - d2).sqrt() - r
        } else {
            -2.0 * DEPTH
        }
    })
    .expect("patch")
}

fn bench_rungs(c: &mut Criterion) {
    let field = random_field(N, 2006);
    let radii: Vec<f64> = field
        .laws()
        .iter()
        .map(|l| (l.geometry().radius() / 0.5e-3).round().max(1.0) * 0.5e-3)
        .collect();
    let positions = field.positions().to_vec();
    let gaps = field.gaps().to_vec();
    let wilke_laws: Vec<_> = radii
        .iter()
        .map(|&r| PotentialLaw::sphere(Sphere::new(r).expect("radius"), rubber()))
        .collect();
    // With fields, for the calibrated_fields rung (the laws are the same).
    let calibrator = Calibrator::new(rubber(), CalibrationOptions::default()).with_fields();
    let t = std::time::Instant::now();
    let calibrated_laws: Vec<CalibratedLaw> = radii
        .iter()
        .map(|&r| {
            calibrator
                .law(&sphere_patch(r), DEPTH)
                .expect("calibration")
        })
        .collect();
    eprintln!(
        "calibration: {:?} in {:.1} s",
        calibrator.counts(),
        t.elapsed().as_secs_f64()
    );
    let wilke = Problem::new(positions.clone(), gaps.clone(), wilke_laws, rubber()).expect("set");
    let calibrated = Problem::new(positions, gaps, calibrated_laws, rubber()).expect("set");
    let load = tyre_like_load(N);
    let mut group = c.benchmark_group("fidelity/road_like_1500");
    group.sample_size(10);
    for fidelity in RUNGS {
        let rung = fidelity.rung(&SolverOptions::default()).expect("rung");
        let control = Control::Load(load);
        let run = || match (rung.laws, rung.coupling) {
            (LawSource::Potential, _) => {
                solve(&wilke, control, &rung.solver).map_err(|e| e.to_string())
            }
            (LawSource::Calibrated, Coupling::Solver) => {
                solve(&calibrated, control, &rung.solver).map_err(|e| e.to_string())
            }
            (LawSource::Calibrated, Coupling::Fields) => solve_field_coupled(
                &calibrated,
                control,
                &rung.solver,
                &FieldCouplingOptions::default(),
                None,
            )
            .map(|f| f.solution)
            .map_err(|e| e.to_string()),
        };
        let s = run().expect("converges");
        eprintln!(
            "{}: {load:.0} N, {} in contact, approach {:.1} µm, {} iterations",
            fidelity.name(),
            s.contact_count(),
            s.approach * 1e6,
            s.iterations
        );
        group.bench_function(fidelity.name(), |b| b.iter(|| run().expect("converges")));
    }
    group.bench_function("calibrate_one_cap_R3mm", |b| {
        let patch = sphere_patch(3e-3);
        b.iter(|| calibrate(&patch, DEPTH, &rubber(), &CalibrationOptions::default()).expect("ok"))
    });
    group.finish();
}

/// Steps of the chip-seal path timed by [`bench_rolling`].
const ROLLING_STEPS: usize = 40;

/// The chip-seal fixture, its folder and its rolling path cut to
/// [`ROLLING_STEPS`] steps.
fn chip_seal_steps() -> (
    tyreroad::scenario::Scenario,
    std::path::PathBuf,
    tyreroad::rolling::RollingConfig,
) {
    let fixture = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
    let text =
        std::fs::read_to_string(fixture.join("rolling_tyre_chip_seal.toml")).expect("fixture");
    let scenario = tyreroad::scenario::Scenario::parse(&text, "rolling_tyre_chip_seal.toml")
        .expect("scenario");
    let mut config = scenario.rolling_config().expect("rolling");
    config.end = config.start + (ROLLING_STEPS - 1) as f64 * config.step;
    (scenario, fixture, config)
}

fn bench_rolling(c: &mut Criterion) {
    use tyreroad::rolling::{RunOptions, roll};
    use tyreroad::shared::Par;

    let (scenario, fixture, config) = chip_seal_steps();
    let material = scenario.material().expect("material");
    let wilke = scenario.texture_rolling_road(&fixture).expect("road");
    let t = std::time::Instant::now();
    let calibrated = calibrated_with_fields(&scenario, &fixture, &config);
    eprintln!(
        "calibration (with fields) of {} selectable asperities: {:.1} s",
        calibrated.len(),
        t.elapsed().as_secs_f64()
    );
    let coupling = FieldRolling::with_defaults(&material).expect("coupling");
    let options = RunOptions {
        par: Par::rayon(0),
        ..RunOptions::default()
    };
    let mut group = c.benchmark_group("fidelity/rolling_chip_seal_40_steps");
    group.sample_size(10);
    group.bench_function("wilke", |b| {
        b.iter(|| roll(&wilke, material, &config, &options).expect("roll"))
    });
    group.bench_function("calibrated", |b| {
        b.iter(|| roll(&calibrated, material, &config, &options).expect("roll"))
    });
    group.bench_function("calibrated_fields", |b| {
        b.iter(|| {
            tyreroad::rolling::roll_coupled(&calibrated, material, &config, &options, &coupling)
                .expect("roll")
        })
    });
    // The same with the near pairs' double sums bin by bin in f64 (the
    // reference the packed sums are tested against): what packing brings.
    let exact = FieldRolling::with_defaults(&material)
        .expect("coupling")
        .with_pair_sum(PairSum::Exact);
    group.bench_function("calibrated_fields_exact_sums", |b| {
        b.iter(|| {
            tyreroad::rolling::roll_coupled(&calibrated, material, &config, &options, &exact)
                .expect("roll")
        })
    });
    let st = coupling.stats();
    eprintln!(
        "calibrated_fields: {:.2} rounds a step (at most {}) over {} steps",
        st.rounds as f64 / st.steps.max(1) as f64,
        st.max_rounds,
        st.steps
    );
    group.finish();
}

/// The caps of one road calibrated from scratch (a new [`Calibrator`] per
/// iteration, one thread), with [`CalibrationOptions::reference`] and with
/// the default options (docs/performance.md, "Calibration cost"): the
/// chip seal of `cargo xtask validate --textures` on 20 × 20 mm at 0.1 mm,
/// each cap tabulated to 1.3 × the Wilke model's approach at 75 N (the
/// mean pressure of the harness's 300 N on its 40 × 40 mm).
fn bench_calibration(c: &mut Criterion) {
    use tyreroad::fidelity::calibrated_set;
    use tyreroad::texture_road::{TextureRoadOptions, texture_road};

    let text = "name = \"calibration\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\n\
                poisson_ratio = 0.5\n[texture]\nmin_prominence = \"0.2 mm\"\n\
                min_area = \"2 mm2\"\n[texture.synth]\nnx = 200\nny = 200\n\
                spacing = \"0.1 mm\"\nkind = \"worn_chip_seal\"\nseed = 19\n";
    let scenario = tyreroad::scenario::Scenario::parse(text, "chip seal").expect("scenario");
    let map = scenario
        .texture
        .as_ref()
        .expect("texture")
        .height_map(std::path::Path::new("."))
        .expect("map");
    let road = texture_road(&map, rubber(), &TextureRoadOptions::new(0.2e-3, 2e-6)).expect("road");
    let wilke = Problem::from_set(road.set.clone(), rubber()).expect("problem");
    let approach = solve(&wilke, Control::Load(75.0), &SolverOptions::default())
        .expect("wilke")
        .approach;
    let max_approach = tyreroad::fidelity::compare::APPROACH_MARGIN * approach;
    let mut group = c.benchmark_group("fidelity/calibrate_chip_seal_20mm");
    group.sample_size(10);
    for (name, options) in [
        ("reference", CalibrationOptions::reference()),
        ("default", CalibrationOptions::default()),
    ] {
        let run = || {
            let calibrator = Calibrator::new(rubber(), options);
            let pool = rayon::ThreadPoolBuilder::new()
                .num_threads(1)
                .build()
                .expect("pool");
            pool.install(|| calibrated_set(&road, &map, max_approach, &calibrator))
                .expect("calibration");
            calibrator.counts().solved
        };
        eprintln!("{name}: {} caps of {} asperities", run(), road.len());
        group.bench_function(name, |b| b.iter(run));
    }
    group.finish();
}

/// The fixture's texture road, its Wilke rolling road in the scenario's
/// frame (y centred on the map's mid-width; rolling order is not needed for
/// timing) and its height map.
fn texture_roads(
    scenario: &tyreroad::scenario::Scenario,
    base: &std::path::Path,
) -> (
    tyreroad::texture_road::TextureRoad,
    tyreroad::rolling::Road<tyreroad::texture_road::TextureLaw>,
    tyreroad::texture::HeightMap,
) {
    let texture = scenario.texture.as_ref().expect("texture");
    let map = texture.height_map(base).expect("map");
    let material = scenario.material().expect("material");
    let troad = tyreroad::texture_road::texture_road(&map, material, &texture.road_options())
        .expect("texture road");
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    let set = troad.set.clone().translated([0.0, -y_mid]).expect("set");
    let wilke =
        tyreroad::texture_road::rolling_road(set, troad.summit_radii(), troad.top).expect("radii");
    (troad, wilke, map)
}

/// The fixture's calibrated rolling road with its fields (what `[model]
/// fidelity = "calibrated_fields"` rolls; its laws are the `calibrated`
/// rung's, so both rungs are timed on it), calibrated over `config`'s path.
fn calibrated_with_fields(
    scenario: &tyreroad::scenario::Scenario,
    base: &std::path::Path,
    config: &tyreroad::rolling::RollingConfig,
) -> tyreroad::rolling::Road<CalibratedLaw> {
    let (troad, wilke, map) = texture_roads(scenario, base);
    let material = scenario.material().expect("material");
    let calibrator = Calibrator::new(material, CalibrationOptions::default()).with_fields();
    let cal = tyreroad::fidelity::rolling::calibrate_rolling_road(
        &troad,
        &wilke,
        &map,
        config,
        &calibrator,
        tyreroad::shared::Par::rayon(0),
    )
    .expect("calibration");
    let radii = troad.summit_radii();
    let radii = cal.kept.iter().map(|&i| radii[i]).collect();
    tyreroad::fidelity::rolling::calibrated_rolling_road(cal.set, radii, troad.top).expect("radii")
}

/// A rolling road's calibration (no fields, a new calibrator each time, so
/// every table is solved; both cores) on the chip-seal fixture's 40-step
/// path, its tables to the bound and to their estimated depth
/// (`tyreroad::fidelity::table_depth`): what a first calibrated run pays
/// before its steps.
fn bench_rolling_tables(c: &mut Criterion) {
    use tyreroad::fidelity::rolling::calibrate_rolling_road_under;
    use tyreroad::fidelity::table_depth::TablePlan;
    use tyreroad::fidelity::under_tread::CalibrateUnder;

    let (scenario, fixture, config) = chip_seal_steps();
    let material = scenario.material().expect("material");
    let (troad, wilke, map) = texture_roads(&scenario, &fixture);
    let mut group = c.benchmark_group("fidelity/rolling_tables_chip_seal_40_steps");
    group.sample_size(10);
    for (name, plan) in [
        ("bound", TablePlan::bound(CalibrateUnder::Flat)),
        ("estimated", TablePlan::new(CalibrateUnder::Flat)),
    ] {
        let run = || {
            let calibrator = Calibrator::new(material, CalibrationOptions::default());
            calibrate_rolling_road_under(
                &troad,
                &wilke,
                &map,
                &config,
                &calibrator,
                tyreroad::shared::Par::rayon(0),
                &plan,
            )
            .expect("calibration")
            .kept
            .len()
        };
        eprintln!("{name}: {} caps", run());
        group.bench_function(name, |b| b.iter(run));
    }
    group.finish();
}

criterion_group!(
    benches,
    bench_rungs,
    bench_rolling,
    bench_calibration,
    bench_rolling_tables
);
criterion_main!(benches);
