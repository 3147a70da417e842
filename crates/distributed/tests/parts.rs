//! The ranks of a distributed run without MPI: the parts of
//! `rank_range`, rolled by `Scenario::roll_part` with a warm-up, sent
//! through the wire format and finished by `Scenario::finish_rolling`,
//! equal the single process's run (`Scenario::run`) at full precision.
#![allow(clippy::unwrap_used)]

use std::path::Path;

use tyreroad::rolling::RollingResult;
use tyreroad::scenario::{Par, RunOptions, Scenario, ScenarioResult};
use tyreroad_distributed::rank_range;
use tyreroad_distributed::wire::{decode_records, encode_records};

fn fixtures() -> &'static Path {
    Path::new(concat!(env!("CARGO_MANIFEST_DIR"), "/../../fixtures"))
}

fn options() -> RunOptions<'static> {
    RunOptions {
        par: Some(Par::Seq),
        ..RunOptions::new(fixtures())
    }
}

/// Largest relative difference of the time signals (force, approach, area,
/// sensors) and whether the contacts (ids and counts) agree.
fn compare(a: &RollingResult, b: &RollingResult) -> f64 {
    assert_eq!(a.steps.len(), b.steps.len());
    let mut worst = 0.0f64;
    for (x, y) in a.steps.iter().zip(&b.steps) {
        assert_eq!(
            (x.index, &x.contact_ids, x.status),
            (y.index, &y.contact_ids, y.status)
        );
        let pairs = [
            (x.total_force, y.total_force),
            (x.approach, y.approach),
            (x.contact_area, y.contact_area),
        ];
        for (u, v) in pairs.into_iter().chain(
            x.sensor_forces
                .iter()
                .copied()
                .zip(y.sensor_forces.iter().copied()),
        ) {
            worst = worst.max((u - v).abs() / u.abs().max(v.abs()).max(1e-300));
        }
    }
    worst
}

/// 1 to 4 ranks, warm-ups of 0, 1, 2 and 5 steps: the signals equal the
/// single run to 1e-9 relative (the rolling tolerance is 1e-12, so a cold
/// start at a part's first step is already within it: the measured
/// difference is printed) and the spectra have the same bands, levels to
/// 1e-9 dB.
#[test]
fn parts_finished_on_rank_0_equal_the_single_process() {
    let scenario = Scenario::from_path(fixtures().join("rolling_small.toml")).unwrap();
    let ScenarioResult::Rolling(single) = scenario.run(&options()).unwrap() else {
        panic!("not a rolling scenario");
    };
    let total = scenario.rolling_steps().unwrap();
    assert_eq!(total, single.result.steps.len());
    for warmup in [0, 1, 2, 5] {
        for ranks in 1..=4 {
            let mut steps = Vec::new();
            for rank in 0..ranks {
                let part = scenario
                    .roll_part(&options(), rank_range(total, rank, ranks), warmup)
                    .unwrap();
                steps.extend(decode_records(&encode_records(&part)).unwrap().steps);
            }
            let gathered = RollingResult {
                steps,
                ..single.result.clone()
            };
            let run = scenario.finish_rolling(&options(), gathered).unwrap();
            let worst = compare(&run.result, &single.result);
            println!("warm-up {warmup}, {ranks} ranks: largest relative difference {worst:.1e}");
            assert!(worst <= 1e-9, "warm-up {warmup}, {ranks} ranks: {worst:e}");
            // The same bands, levels to 1e-9 dB (the written files, at 1e-3
            // dB, are byte-identical: xtask/tests/mpi.rs).
            let levels = |s: &tyreroad::scenario::Spectra| -> Vec<(f64, f64)> {
                s.primary
                    .iter()
                    .chain(s.sensors.iter().flatten())
                    .map(|b| (b.band.nominal, b.level_db))
                    .collect()
            };
            let (a, b) = (levels(&run.spectra), levels(&single.spectra));
            assert_eq!(a.len(), b.len());
            let close = a
                .iter()
                .zip(&b)
                .all(|(x, y)| x.0 == y.0 && (x.1 - y.1).abs() <= 1e-9);
            assert!(close, "spectra differ: warm-up {warmup}, {ranks} ranks");
            assert_eq!(run.road_positions, single.road_positions);
        }
    }
    // Records that do not cover the path are refused, not finished.
    let mut short = single.result.clone();
    short.steps.pop();
    assert!(scenario.finish_rolling(&options(), short).is_err());
}

/// A part longer than a rank's road window (1 m of path): each rank
/// rolls its part on several windows of the synthetic road, one after
/// another, and still gives the single process's records (same contact
/// ids, signals to 1e-9 relative), road (positions and heights bit for
/// bit) and input hash (so the same checkpoint files).
#[test]
fn parts_on_several_road_windows_equal_the_single_process() {
    let text = std::fs::read_to_string(fixtures().join("rolling_small.toml"))
        .unwrap()
        .replace("end = \"79 mm\"", "end = \"2240 mm\"")
        .replace("step = \"1 mm\"", "step = \"2 mm\"")
        .replace("length = \"0.12 m\"", "length = \"2.3 m\"");
    let scenario = Scenario::parse(&text, "long").unwrap();
    let ScenarioResult::Rolling(single) = scenario.run(&options()).unwrap() else {
        panic!("not a rolling scenario");
    };
    let total = scenario.rolling_steps().unwrap();
    assert_eq!(total, 1101);
    let ranks = 2;
    let mut steps = Vec::new();
    for rank in 0..ranks {
        let part = scenario
            .roll_part(&options(), rank_range(total, rank, ranks), 2)
            .unwrap();
        assert_eq!(part.input_hash, single.result.input_hash);
        steps.extend(part.steps);
    }
    let gathered = RollingResult {
        steps,
        ..single.result.clone()
    };
    let run = scenario.finish_rolling(&options(), gathered).unwrap();
    let worst = compare(&run.result, &single.result);
    println!("{ranks} ranks on windows: largest relative difference {worst:.1e}");
    assert!(worst <= 1e-9, "{worst:e}");
    assert_eq!(run.road_positions, single.road_positions);
    assert_eq!(run.road_heights, single.road_heights);
}
