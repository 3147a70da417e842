//! Rolling: consistency with the static solver, independence of chunking
//! and threads, exact selection, spectral lines of a periodic road, resume.

use std::ops::ControlFlow;
use std::sync::atomic::{AtomicUsize, Ordering};
use std::time::Duration;

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::{AsperitySet, Control, Par, Problem, SolverOptions, solve};
use tyreroad_rolling::{
    Band, CheckpointOptions, Progress, Road, RollingConfig, RollingControl, RollingError,
    RollingResult, RunOptions, Sensor, StepRecord, SyntheticRoad, Tread, band_levels, bands_below,
    input_hash, roll, welch,
};

type Law = PotentialLaw<Sphere>;
type TestResult = Result<(), Box<dyn std::error::Error>>;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("material")
}

/// A small synthetic road: 0.2 m × 0.06 m, ~360 summits.
fn small_road() -> Road<Law> {
    SyntheticRoad {
        seed: 7,
        length: 0.2,
        width: 0.06,
        density: 30_000.0,
        ..SyntheticRoad::default()
    }
    .sphere_road(rubber())
    .expect("road")
}

fn tyre() -> Tread {
    Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.2,
        length: 0.1,
        width: 0.06,
    }
}

/// The tyre from x = 0.05 to 0.15 m in steps of `step` (m) under 120 N,
/// a 20 mm sensor at the path's middle.
fn tyre_with_sensor(step: f64) -> RollingConfig {
    let mut config = RollingConfig::new(
        tyre(),
        [0.05, 0.15, step],
        13.9,
        RollingControl::Load(120.0),
    );
    config.sensors.push(Sensor {
        name: "s".into(),
        x: [0.09, 0.11],
        y: [-0.01, 0.01],
    });
    config
}

fn close(a: f64, b: f64, rel: f64) -> bool {
    (a - b).abs() <= rel * a.abs().max(b.abs()).max(1e-300)
}

fn assert_same(a: &RollingResult, b: &RollingResult, rel: f64) {
    assert_eq!(a.steps.len(), b.steps.len());
    for (x, y) in a.steps.iter().zip(&b.steps) {
        assert_eq!(
            (x.index, x.contacts, x.selected),
            (y.index, y.contacts, y.selected)
        );
        assert_eq!(x.position, y.position);
        assert!(close(x.total_force, y.total_force, rel), "{x:?}\n{y:?}");
        assert!(close(x.approach, y.approach, rel), "{x:?}\n{y:?}");
        assert!(close(x.contact_area, y.contact_area, rel), "{x:?}\n{y:?}");
        // The same asperities in contact, each with the same force.
        assert_eq!(x.contact_ids, y.contact_ids);
        for (p, q) in x.contact_forces.iter().zip(&y.contact_forces) {
            assert!(
                (p - q).abs() <= rel * x.total_force.abs().max(1.0),
                "{x:?}\n{y:?}"
            );
        }
        for (p, q) in x.sensor_forces.iter().zip(&y.sensor_forces) {
            // Sensor forces are sums of a few forces: compare to the total.
            assert!(
                (p - q).abs() <= rel * x.total_force.abs().max(1.0),
                "{x:?}\n{y:?}"
            );
        }
    }
}

fn max_rel_diff(a: &RollingResult, b: &RollingResult, f: impl Fn(&StepRecord) -> f64) -> f64 {
    a.steps
        .iter()
        .zip(&b.steps)
        .map(|(x, y)| (f(x) - f(y)).abs() / f(x).abs().max(f(y).abs()).max(1e-300))
        .fold(0.0, f64::max)
}

#[test]
fn single_step_equals_direct_static_solve() -> TestResult {
    let road = small_road();
    let material = rubber();
    let tread = tyre();
    for control in [
        RollingControl::Load(120.0),
        RollingControl::Approach(1.2e-3),
    ] {
        let xc = 0.1;
        let config = RollingConfig::new(tread, [xc, xc, 1e-3], 13.9, control);
        let r = roll(&road, material, &config, &RunOptions::default())?;
        assert_eq!(r.steps.len(), 1);
        // The static problem written from the definition, independently.
        let (hx, hy) = tread.half_extents();
        let top = road.heights().iter().copied().fold(f64::MIN, f64::max);
        let (mut pos, mut gaps, mut laws) = (vec![], vec![], vec![]);
        for i in 0..road.len() {
            let [x, y] = road.positions()[i];
            if (x - xc).abs() <= hx && y.abs() <= hy {
                pos.push([x, y]);
                gaps.push(top - road.heights()[i] + (x - xc).powi(2) / 0.6 + y * y / 0.4);
                laws.push(road.laws()[i].clone());
            }
        }
        let problem = Problem::new(pos, gaps, laws, material)?;
        let ctl = match control {
            RollingControl::Load(w) => Control::Load(w),
            RollingControl::Approach(d) => Control::Approach(d),
            RollingControl::TreadHeight(_) => unreachable!(),
        };
        let options = SolverOptions {
            tolerance: 1e-12,
            ..SolverOptions::default()
        };
        let s = solve(&problem, ctl, &options)?;
        let step = &r.steps[0];
        assert_eq!(step.selected, problem.len());
        assert_eq!(step.contacts, s.contact_count());
        assert!(step.contacts > 5, "{step:?}");
        assert!(close(step.total_force, s.total_force(), 1e-10), "{step:?}");
        assert!(close(step.approach, s.approach, 1e-10), "{step:?}");
        let contacts = s.local_contacts(&problem);
        let area: f64 = contacts.iter().map(|c| c.area()).sum();
        assert!(close(step.contact_area, area, 1e-10), "{step:?} vs {area}");
        let overlapping = tyreroad_multipoint::overlapping_contacts(problem.positions(), &contacts);
        assert_eq!(step.overlapping, overlapping.len());
        assert_eq!(step.time, xc / 13.9);
    }
    Ok(())
}

#[test]
fn chunking_and_threads_do_not_change_results() -> TestResult {
    let road = small_road();
    let config = tyre_with_sensor(2e-3);
    let reference = roll(
        &road,
        rubber(),
        &config,
        &RunOptions {
            chunks: Some(1),
            ..RunOptions::default()
        },
    )?;
    assert_eq!(reference.steps.len(), 51);
    let mut worst = 0.0_f64;
    // Par::Rayon(3) differs from the test pool's thread count, so roll
    // builds its own pool; the others reuse the current one or none.
    let pars = [
        Par::Seq,
        Par::rayon(1),
        Par::rayon(2),
        Par::rayon(3),
        Par::rayon(0),
    ];
    for par in pars {
        for chunks in [None, Some(1), Some(4), Some(7)] {
            // The progress callback runs on the workers: it sees their pool
            // (none under Par::Seq: it stays on the calling thread).
            let caller = std::thread::current().id();
            let pool_size = AtomicUsize::new(0);
            let off_caller = AtomicUsize::new(0);
            let watch = |_: Progress| {
                pool_size.store(rayon::current_num_threads(), Ordering::SeqCst);
                if std::thread::current().id() != caller {
                    off_caller.fetch_add(1, Ordering::SeqCst);
                }
                ControlFlow::Continue(())
            };
            let r = roll(
                &road,
                rubber(),
                &config,
                &RunOptions {
                    chunks,
                    par,
                    progress: Some(&watch),
                    ..RunOptions::default()
                },
            )?;
            match par {
                Par::Seq => assert_eq!(off_caller.load(Ordering::SeqCst), 0),
                Par::Rayon(n) => assert_eq!(pool_size.load(Ordering::SeqCst), n.get()),
            }
            assert_same(&reference, &r, 1e-9);
            worst = worst.max(max_rel_diff(&reference, &r, |s| s.approach));
        }
    }
    println!("chunking/threads: worst relative approach difference {worst:.2e}");
    Ok(())
}

/// A road's reference plane (`Road::with_top`) moves the approach and
/// nothing else under load control: the same forces, contacts and sensor
/// signals, `δ0` larger by exactly the plane's rise; under approach
/// control the same plane and approach give the same run. It is part of
/// the checkpoint key, and a plane that is not finite is refused.
#[test]
fn the_reference_plane_moves_the_approach_only() -> TestResult {
    let road = small_road();
    let rise = 0.37e-3;
    let raised = small_road().with_top(road.top() + rise)?;
    let config = tyre_with_sensor(5e-3);
    let options = RunOptions::default();
    let a = roll(&road, rubber(), &config, &options)?;
    let b = roll(&raised, rubber(), &config, &options)?;
    assert_eq!(a.steps.len(), b.steps.len());
    for (x, y) in a.steps.iter().zip(&b.steps) {
        assert_eq!(x.contact_ids, y.contact_ids);
        assert!(close(x.total_force, y.total_force, 1e-9), "{x:?}\n{y:?}");
        for (f, g) in x.contact_forces.iter().zip(&y.contact_forces) {
            assert!((f - g).abs() <= 1e-7 * x.total_force, "{f} against {g}");
        }
        for (f, g) in x.sensor_forces.iter().zip(&y.sensor_forces) {
            assert!((f - g).abs() <= 1e-7 * x.total_force, "{f} against {g}");
        }
        // 1 nm of a 0.37 mm rise (the solver's tolerance on δ0).
        assert!(
            (y.approach - x.approach - rise).abs() < 1e-9,
            "{} {}",
            x.approach,
            y.approach
        );
    }
    // Under approach control the raised plane with the raised approach is
    // the same tread position: the same forces.
    let mut held = config.clone();
    held.control = RollingControl::Approach(a.steps[10].approach);
    let at_a = roll(&road, rubber(), &held, &options)?;
    held.control = RollingControl::Approach(a.steps[10].approach + rise);
    let at_b = roll(&raised, rubber(), &held, &options)?;
    for (x, y) in at_a.steps.iter().zip(&at_b.steps) {
        assert!(close(x.total_force, y.total_force, 1e-9), "{x:?}\n{y:?}");
    }
    assert_ne!(
        input_hash(&road, &rubber(), &config),
        input_hash(&raised, &rubber(), &config)
    );
    for bad in [f64::NAN, f64::INFINITY] {
        assert!(matches!(
            small_road().with_top(bad),
            Err(RollingError::InvalidInput(_))
        ));
    }
    Ok(())
}

#[test]
fn wider_margin_changes_nothing_and_force_is_continuous() -> TestResult {
    let road = small_road();
    let mut config = RollingConfig::new(
        tyre(),
        [0.05, 0.15, 1e-3],
        13.9,
        RollingControl::Approach(1.2e-3),
    );
    let narrow = roll(&road, rubber(), &config, &RunOptions::default())?;
    assert!(narrow.min_clearance() > 0.0, "{}", narrow.min_clearance());
    config.margin = 0.02;
    let wide = roll(&road, rubber(), &config, &RunOptions::default())?;
    assert!(
        wide.steps
            .iter()
            .zip(&narrow.steps)
            .all(|(w, n)| w.selected > n.selected)
    );
    let df = max_rel_diff(&narrow, &wide, |s| s.total_force);
    let da = max_rel_diff(&narrow, &wide, |s| s.contact_area);
    println!("margin 0 vs 20 mm: force {df:.2e}, area {da:.2e}");
    assert!(df <= 1e-12 && da <= 1e-12);
    // No jump when asperities enter or leave the selection: the largest
    // step-to-step change is of the order of the typical one.
    let f = narrow.total_force();
    let jumps: Vec<f64> = f.windows(2).map(|w| (w[1] - w[0]).abs()).collect();
    let mean = jumps.iter().sum::<f64>() / jumps.len() as f64;
    let max = jumps.iter().copied().fold(0.0, f64::max);
    println!("force steps: mean {mean:.3e} N, max {max:.3e} N");
    Ok(())
}

/// Identical balls at pitch 10 mm, rolled at 10 m/s: lines at V/L = 1 kHz
/// and its harmonics only; the 1 kHz third-octave band dominates.
#[test]
fn periodic_road_gives_lines_at_v_over_l() -> TestResult {
    let material = rubber();
    let ball = PotentialLaw::sphere(Sphere::new(4e-3)?, material);
    let pitch = 0.01;
    let mut positions = vec![];
    for i in 0..50 {
        for j in -2..=2 {
            // Staggered rows so the line is not trivially one asperity.
            let shift = if j % 2 == 0 { 0.0 } else { 0.5 * pitch };
            positions.push([-0.1 + i as f64 * pitch + shift, j as f64 * 0.008]);
        }
    }
    let n = positions.len();
    let road = Road::new(AsperitySet::new(positions, vec![0.0; n], vec![ball; n])?);
    let tread = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.3,
        length: 0.05,
        width: 0.05,
    };
    let (v, dx) = (10.0, 5e-4);
    let config = RollingConfig::new(
        tread,
        [0.05, 0.25 - dx, dx],
        v,
        RollingControl::Approach(3e-4),
    );
    let r = roll(&road, material, &config, &RunOptions::default())?;
    assert_eq!(r.steps.len(), 400); // 20 pitches, 20 samples each
    assert!(r.min_clearance() > 0.0);
    let force = r.total_force();
    let fs = r.sample_rate;
    assert!((fs - 20_000.0).abs() < 1e-6);
    // Narrow band: segments of 10 periods, df = 100 Hz, line at bin 10.
    let psd = welch(&force, fs, 200, true)?;
    let total = psd.total_power();
    assert!(total > 0.0);
    let mut off_line = 0.0;
    for (m, d) in psd.density.iter().enumerate() {
        let near_harmonic = [0, 1, 9].contains(&(m % 10)); // Hann: ±1 bin
        if !near_harmonic {
            off_line += d * psd.resolution;
        }
    }
    println!("off-line power fraction {:.2e}", off_line / total);
    assert!(off_line <= 1e-9 * total);
    let peak = (1..psd.density.len())
        .max_by(|&a, &b| psd.density[a].total_cmp(&psd.density[b]))
        .unwrap_or(0);
    assert_eq!(psd.frequencies[peak], v / pitch);
    // Third octaves: the band containing 1 kHz dominates.
    let levels = band_levels(&psd, &bands_below(fs / 2.0), 1.0)?;
    let best = levels
        .iter()
        .max_by(|a, b| a.power.total_cmp(&b.power))
        .ok_or("no band")?;
    assert_eq!(best.band, Band::new(0).ok_or("band")?);
    println!("1 kHz band level {:.2} dB re 1 N", best.level_db);
    Ok(())
}

#[test]
fn killed_run_resumes_from_checkpoint() -> TestResult {
    let road = small_road();
    let config = RollingConfig::new(
        tyre(),
        [0.05, 0.15, 2e-3],
        13.9,
        RollingControl::Load(120.0),
    );
    let total = config.steps();
    let base = std::env::temp_dir().join(format!("tyreroad-rolling-resume-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let ck = CheckpointOptions {
        dir: base.join("a"),
        interval: Duration::ZERO,
    };
    let options = |chunks| RunOptions {
        chunks: Some(chunks),
        ..RunOptions::default()
    };
    let uninterrupted = roll(&road, rubber(), &config, &options(3))?;
    // "Kill" after about half of the steps.
    let abort = |p: Progress| {
        if p.done >= total / 2 {
            ControlFlow::Break(())
        } else {
            ControlFlow::Continue(())
        }
    };
    let first = roll(
        &road,
        rubber(),
        &config,
        &RunOptions {
            chunks: Some(3),
            checkpoint: Some(&ck),
            progress: Some(&abort),
            ..RunOptions::default()
        },
    );
    let Err(RollingError::Interrupted { done, .. }) = first else {
        return Err(format!("expected an interruption, got {first:?}").into());
    };
    assert!(done >= total / 2 && done < total, "{done}");
    // A copy of the checkpoint, to resume it with another chunking too.
    let other_dir = base.join("b");
    std::fs::create_dir_all(&other_dir)?;
    for e in std::fs::read_dir(&ck.dir)? {
        let e = e?;
        std::fs::copy(e.path(), other_dir.join(e.file_name()))?;
    }
    // Resume with the same chunking: finished steps are not recomputed and
    // the whole run is bit-for-bit the uninterrupted one (the warm-start
    // state is checkpointed too).
    let computed = AtomicUsize::new(0);
    let count = |_: Progress| {
        computed.fetch_add(1, Ordering::SeqCst);
        ControlFlow::Continue(())
    };
    let resumed = roll(
        &road,
        rubber(),
        &config,
        &RunOptions {
            chunks: Some(3),
            checkpoint: Some(&ck),
            progress: Some(&count),
            ..RunOptions::default()
        },
    )?;
    assert_eq!(resumed.resumed, done);
    assert_eq!(computed.load(Ordering::SeqCst), total - done);
    assert_eq!(resumed.steps, uninterrupted.steps);
    // Each step's status, recovery and residual (checkpoint format 5) come
    // back as they were computed.
    let outcome = |r: &RollingResult| -> Vec<_> {
        r.steps
            .iter()
            .map(|s| (s.status, s.recovery, s.iterations, s.residual.to_bits()))
            .collect()
    };
    assert_eq!(outcome(&resumed), outcome(&uninterrupted));
    assert!(uninterrupted.all_converged());
    // The per-asperity forces (in `steps` above) spelt out: the same ids and
    // the same bits, restored from the checkpoint as well as recomputed.
    let bits = |r: &RollingResult| -> Vec<(usize, usize, u64)> {
        r.contact_triplets()
            .map(|(k, id, p)| (k, id, p.to_bits()))
            .collect()
    };
    assert_eq!(bits(&resumed), bits(&uninterrupted));
    for s in &uninterrupted.steps {
        assert_eq!(s.contact_ids.len(), s.contacts);
        assert_eq!(s.contact_forces.len(), s.contacts);
        assert!(s.contact_forces.iter().all(|&p| p > 0.0));
        // In selection order they sum to the total force bit for bit.
        assert_eq!(s.contact_forces.iter().sum::<f64>(), s.total_force);
    }
    assert!(uninterrupted.steps.iter().all(|s| s.contacts > 0));
    // Resume with another chunking: chunks that start after finished steps
    // may cold-start, equal to the solver tolerance.
    let other = roll(
        &road,
        rubber(),
        &config,
        &RunOptions {
            chunks: Some(5),
            checkpoint: Some(&CheckpointOptions {
                dir: other_dir,
                interval: Duration::from_secs(1),
            }),
            progress: None,
            par: Par::rayon(2),
        },
    )?;
    assert_eq!(other.resumed, done);
    assert_same(&uninterrupted, &other, 1e-11);
    // A third run loads everything.
    let again = roll(
        &road,
        rubber(),
        &config,
        &RunOptions {
            checkpoint: Some(&ck),
            ..RunOptions::default()
        },
    )?;
    assert_eq!(again.resumed, total);
    assert_eq!(again.steps, resumed.steps);
    assert_eq!(bits(&again), bits(&uninterrupted));
    // Other inputs, other hash: nothing is reused.
    let mut changed = config.clone();
    changed.control = RollingControl::Load(121.0);
    assert_ne!(
        tyreroad_rolling::input_hash(&road, &rubber(), &config),
        tyreroad_rolling::input_hash(&road, &rubber(), &changed)
    );
    std::fs::remove_dir_all(&base)?;
    Ok(())
}

#[test]
fn block_tread_and_sensors() -> TestResult {
    let road = small_road();
    let block = Tread::Block {
        length: 0.04,
        width: 0.04,
    };
    let mut config =
        RollingConfig::new(block, [0.05, 0.15, 2e-3], 10.0, RollingControl::Load(200.0));
    config.margin = 0.05; // ignored for a block
    config.sensors = vec![
        Sensor {
            name: "all".into(),
            x: [-1.0, 1.0],
            y: [-1.0, 1.0],
        },
        Sensor {
            name: "patch".into(),
            x: [0.09, 0.11],
            y: [-0.02, 0.02],
        },
    ];
    let r = roll(&road, rubber(), &config, &RunOptions::default())?;
    for s in &r.steps {
        assert!(close(s.total_force, 200.0, 1e-10));
        assert!(close(s.sensor_forces[0], s.total_force, 1e-12));
        assert!(s.sensor_forces[1] <= s.total_force + 1e-9);
        assert!(s.clearance.is_infinite());
    }
    // The patch sensor sees load only while the block passes over it.
    let patch = r.sensor(1);
    assert_eq!(patch[0], 0.0);
    assert!(patch.iter().copied().fold(0.0, f64::max) > 1.0);
    Ok(())
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let road = small_road();
    let m = rubber();
    let o = RunOptions::default();
    let good = RollingConfig::new(
        tyre(),
        [0.05, 0.06, 1e-3],
        10.0,
        RollingControl::Load(100.0),
    );
    let mut c = good.clone();
    c.step = 0.0;
    assert!(roll(&road, m, &c, &o).is_err());
    let mut c = good.clone();
    c.speed = f64::NAN;
    assert!(roll(&road, m, &c, &o).is_err());
    let mut c = good.clone();
    c.end = 0.0;
    assert!(roll(&road, m, &c, &o).is_err());
    // A step in the wrong unit: an error, not a step-count overflow or a
    // runaway allocation.
    for step in [1e-300, 1e-9] {
        let mut c = good.clone();
        c.step = step;
        assert!(matches!(
            roll(&road, m, &c, &o),
            Err(RollingError::InvalidInput(e)) if e.contains("steps")
        ));
    }
    let mut c = good.clone();
    c.tread = Tread::Block {
        length: -1.0,
        width: 1.0,
    };
    assert!(roll(&road, m, &c, &o).is_err());
    // Loaded footprint off the road.
    let mut c = good.clone();
    c.start = 5.0;
    c.end = 5.0;
    assert!(matches!(
        roll(&road, m, &c, &o),
        Err(RollingError::NoSupport { .. })
    ));
    // Displacement control off the road: zero force.
    c.control = RollingControl::Approach(1e-3);
    assert!(roll(&road, m, &c, &o).is_ok_and(|r| r.steps[0].total_force == 0.0));
    assert!(AsperitySet::<Law>::new(vec![], vec![], vec![]).is_err());
}

/// A tolerance of 1.0 rolled every step "converged" 10 % under the load;
/// a load of 1e-300 N rolled every step failed; a speed of 5e-324 m/s gave
/// infinite times. Each is refused naming its value, readably.
#[test]
fn loose_tolerances_vanishing_loads_and_speeds_without_a_time_are_refused() {
    let road = small_road();
    let (m, o) = (rubber(), RunOptions::default());
    let good = RollingConfig::new(
        tyre(),
        [0.05, 0.06, 1e-3],
        10.0,
        RollingControl::Load(100.0),
    );
    let refusal = |c: &RollingConfig| match roll(&road, m, c, &o) {
        Err(RollingError::InvalidInput(e)) => e,
        other => panic!(
            "expected InvalidInput, got {:?}",
            other.map(|r| r.steps.len())
        ),
    };
    for tolerance in [1.0, 2e-3] {
        let mut c = good.clone();
        c.tolerance = tolerance;
        let e = refusal(&c);
        assert!(e.contains("tolerance must be in (0, 1e-3]"), "{e}");
    }
    let mut c = good.clone();
    c.control = RollingControl::Load(1e-300);
    let e = refusal(&c);
    assert!(
        e.contains("at least 1e-100 N") && e.contains("got 1e-300"),
        "{e}"
    );
    for speed in [5e-324, f64::MAX] {
        let mut c = good.clone();
        c.speed = speed;
        let e = refusal(&c);
        assert!(e.contains("sample rate") && e.len() < 400, "{e}");
    }
    let mut c = good.clone();
    c.step = 5e-324;
    let e = refusal(&c);
    assert!(e.contains("by 5e-324 m") && e.len() < 300, "{e}");
    // The bound itself rolls.
    let mut c = good.clone();
    c.tolerance = 1e-3;
    assert!(roll(&road, m, &c, &o).is_ok());
}

#[test]
fn synthetic_road_is_deterministic_and_spaced() -> TestResult {
    let spec = SyntheticRoad::default();
    let a = spec.generate(rubber())?;
    let b = spec.generate(rubber())?;
    let radii = |set: &AsperitySet<Law>| -> Vec<f64> {
        set.laws().iter().map(|l| l.geometry().radius()).collect()
    };
    assert_eq!(a.positions(), b.positions());
    assert_eq!(a.heights(), b.heights());
    assert_eq!(radii(&a), radii(&b));
    let n = a.len();
    println!("default synthetic road: {n} summits");
    assert!(n > 6000, "{n}");
    assert!(radii(&a).iter().all(|r| (2e-3..=5e-3).contains(r)));
    assert!(a.heights().iter().all(|z| (0.0..=2e-3).contains(z)));
    // Minimum spacing, checked by sorting on x.
    let mut p = a.positions().to_vec();
    p.sort_by(|u, v| u[0].total_cmp(&v[0]));
    for i in 0..n {
        for j in i + 1..n {
            if p[j][0] - p[i][0] >= 2e-3 {
                break;
            }
            assert!((p[j][0] - p[i][0]).hypot(p[j][1] - p[i][1]) >= 2e-3);
        }
    }
    Ok(())
}
