//! The chunked runner: the path split into contiguous chunks, each stepped
//! with warm starts ([`crate::step`]), the chunks run one after another or in
//! a rayon pool as the caller's [`Par`] says, finished steps checkpointed.

use std::collections::HashMap;
use std::ops::ControlFlow;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::Instant;

use rayon::prelude::*;
use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::Par;

use crate::checkpoint;
use crate::coupling::StepCoupling;
use crate::step::{Carry, Scratch, solve_step};
use crate::{CheckpointOptions, Road, RollingConfig, RollingError, RollingResult, StepRecord};

/// Progress of a run, reported after each step.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Progress {
    /// Steps finished, those resumed from a checkpoint included.
    pub done: usize,
    /// Steps on the path.
    pub total: usize,
    /// Steps taken from the checkpoint rather than computed.
    pub resumed: usize,
}

/// Progress callback: return `ControlFlow::Break(())` to stop the run (its
/// finished steps are checkpointed first).
pub type ProgressFn<'a> = &'a (dyn Fn(Progress) -> ControlFlow<()> + Sync);

/// How to run (nothing here changes the results beyond the solver
/// tolerance: see [`roll`]).
#[derive(Clone, Copy)]
pub struct RunOptions<'a> {
    /// Number of contiguous chunks of the path (each cold-starts its first
    /// step). `None`: one under [`Par::Seq`], twice the threads under
    /// [`Par::Rayon`].
    pub chunks: Option<usize>,
    /// How the chunks run: [`Par::Seq`] one after another on the calling
    /// thread, `Par::Rayon(n)` in a rayon pool of `n` threads (the current
    /// pool when it has `n` threads, else a new one). Default `Par::Seq`:
    /// parallelism is the caller's choice, as in
    /// `tyreroad_multipoint::SolverOptions::par`.
    pub par: Par,
    /// Checkpoint and resume; `None` for none.
    pub checkpoint: Option<&'a CheckpointOptions>,
    /// Called after each step (from the worker threads under `Par::Rayon`).
    pub progress: Option<ProgressFn<'a>>,
}

impl Default for RunOptions<'_> {
    fn default() -> Self {
        Self {
            chunks: None,
            par: Par::Seq,
            checkpoint: None,
            progress: None,
        }
    }
}

/// Rolls the tread along the path: one static solve per step, warm started
/// within contiguous chunks, the chunks run as [`RunOptions::par`] says.
/// Results do not depend on the chunking or the parallelism beyond the
/// solver tolerance ([`RollingConfig::tolerance`]).
///
/// With [`RunOptions::checkpoint`], finished steps are loaded from the
/// checkpoint files keyed by the inputs' hash and not recomputed, and each
/// chunk writes its finished steps atomically as it goes.
///
/// A step whose solve does not converge is recorded as
/// [`StepStatus::Failed`](crate::StepStatus) and the run goes on (the next
/// step cold-starts).
///
/// Errors: invalid configuration, a malformed step problem (with its
/// position), no asperity under a loaded footprint, a checkpoint that cannot
/// be read or written or is refused, or [`RollingError::Interrupted`] when the progress
/// callback asked to stop.
pub fn roll<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    options: &RunOptions<'_>,
) -> Result<RollingResult, RollingError> {
    config.validate()?;
    if let Some(ck) = options.checkpoint {
        // The whole path in this process: no one else writes there.
        checkpoint::remove_unfinished(&ck.dir)?;
    }
    roll_range(road, material, config, 0..config.steps(), 0, options)
}

/// Rolls only the steps `range` of the path (one rank's part of a
/// distributed run, docs/distributed.md): the same as [`roll`] restricted to
/// those steps, each of its chunks started `warmup` steps early (those
/// warm-up steps are solved to warm-start the chunk's first step, then
/// dropped), so that the first kept step starts from the state a run from
/// the path's start would have reached.
///
/// The result holds the records of `range` only, in order
/// ([`RollingResult::steps`]`[j]` is step `range.start + j`); its
/// `resumed` counts the kept steps taken from the checkpoint. Checkpoints
/// are the same files as [`roll`]'s (keyed by the inputs' hash, one per
/// chunk), so ranks sharing a checkpoint directory never write the same
/// file and a resumed job may use another number of ranks. Unlike
/// [`roll`], it leaves the temporary files of killed runs in place (another
/// rank may be writing one): the job's coordinator removes them with
/// [`remove_unfinished_checkpoints`](crate::remove_unfinished_checkpoints)
/// before the ranks start.
///
/// Errors: as [`roll`], and [`RollingError::InvalidInput`] for a range that
/// is empty or runs past the path.
pub fn roll_range<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    range: std::ops::Range<usize>,
    warmup: usize,
    options: &RunOptions<'_>,
) -> Result<RollingResult, RollingError> {
    roll_range_coupled(road, material, config, range, warmup, options, None)
}

/// [`roll`] with each step solved as the fixed point of `coupling`'s
/// correction ([`StepCoupling`], docs/rolling.md "Coupled steps"): the
/// asperities at their contact points, each step warm-started from the
/// previous step's forces and correction, a step whose fixed point does
/// not settle recorded as failed with its last change as residual. The
/// checkpoint key includes [`StepCoupling::key`]. Results agree across
/// chunkings to the coupling's tolerance (not the solver's).
///
/// Errors: as [`roll`], and [`RollingError::InvalidInput`] when the
/// coupling cannot compute a correction.
pub fn roll_coupled<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    options: &RunOptions<'_>,
    coupling: &dyn StepCoupling<L>,
) -> Result<RollingResult, RollingError> {
    config.validate()?;
    if let Some(ck) = options.checkpoint {
        checkpoint::remove_unfinished(&ck.dir)?;
    }
    roll_range_coupled(
        road,
        material,
        config,
        0..config.steps(),
        0,
        options,
        Some(coupling),
    )
}

/// [`roll_range`] under an optional coupling ([`roll_coupled`]).
///
/// Errors: as [`roll_range`] and [`roll_coupled`].
pub fn roll_range_coupled<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    range: std::ops::Range<usize>,
    warmup: usize,
    options: &RunOptions<'_>,
    coupling: Option<&dyn StepCoupling<L>>,
) -> Result<RollingResult, RollingError> {
    config.validate()?;
    let path_steps = config.steps();
    if range.is_empty() || range.end > path_steps {
        return Err(RollingError::InvalidInput(format!(
            "step range {}..{} is empty or runs past the path's {path_steps} steps",
            range.start, range.end
        )));
    }
    let first = range.start;
    let total = range.len();
    let hash = match coupling {
        None => checkpoint::input_hash(road, &material, config),
        // A coupled run is another model: its steps never resume an
        // uncoupled run's, nor one of another coupling.
        Some(c) => {
            checkpoint::with_coupling(checkpoint::input_hash(road, &material, config), c.key())
        }
    };
    // Indexed from `first`: a rank holds its own steps only.
    let mut done: Vec<Option<StepRecord>> = vec![None; total];
    let mut states = HashMap::new();
    if let Some(ck) = options.checkpoint {
        let expect = checkpoint::Expect {
            hash,
            config,
            road_len: road.global_len(),
            boundary: config
                .tread
                .boundary_profile(config.tread.effective_margin(config.margin)),
        };
        let loaded = checkpoint::load(ck, &expect)?;
        // Files name asperities by global id; a state naming one outside
        // this road's window is dropped (its step's successor cold-starts,
        // equal to the solver tolerance).
        states = loaded
            .states
            .into_iter()
            .filter_map(|(k, c)| {
                let ids: Option<Vec<usize>> = c.ids.iter().map(|&g| road.local_id(g)).collect();
                ids.map(|ids| (k, Carry { ids, ..c }))
            })
            .collect();
        for r in loaded.records {
            if range.contains(&r.index) {
                let slot = r.index - first;
                done[slot] = Some(r);
            }
        }
    }
    let resumed = done.iter().filter(|d| d.is_some()).count();
    let chunks = options
        .chunks
        .unwrap_or(match options.par {
            Par::Seq => 1,
            Par::Rayon(threads) => 2 * threads.get(),
        })
        .clamp(1, total);
    let bounds: Vec<(usize, usize)> = (0..chunks)
        .map(|c| (first + c * total / chunks, first + (c + 1) * total / chunks))
        .collect();
    let counter = AtomicUsize::new(resumed);
    let stop = AtomicBool::new(false);
    let chunk = |&(a, b): &(usize, usize)| {
        run_chunk(
            road,
            material,
            config,
            options,
            hash,
            (a, b),
            warmup,
            (&done[a - first..b - first], &states),
            (&counter, &stop),
            (total, resumed),
            coupling,
        )
    };
    let outcomes: Vec<Result<Vec<StepRecord>, RollingError>> = match options.par {
        Par::Seq => bounds.iter().map(chunk).collect(),
        Par::Rayon(threads) if threads.get() == rayon::current_num_threads() => {
            bounds.par_iter().map(chunk).collect()
        }
        Par::Rayon(threads) => rayon::ThreadPoolBuilder::new()
            .num_threads(threads.get())
            .build()
            .map_err(|e| {
                RollingError::InvalidInput(format!("cannot build a pool of {threads} threads: {e}"))
            })?
            .install(|| bounds.par_iter().map(chunk).collect()),
    };
    let mut steps = Vec::with_capacity(total);
    let mut first_error = None;
    for o in outcomes {
        match o {
            Ok(records) => steps.extend(records),
            Err(e) => {
                // A real error wins over an interruption.
                let replace = match (&first_error, &e) {
                    (None, _) => true,
                    (Some(RollingError::Interrupted { .. }), RollingError::Interrupted { .. }) => {
                        false
                    }
                    (Some(RollingError::Interrupted { .. }), _) => true,
                    _ => false,
                };
                if replace {
                    first_error = Some(e);
                }
            }
        }
    }
    if let Some(e) = first_error {
        return Err(match e {
            RollingError::Interrupted { .. } => RollingError::Interrupted {
                done: counter.load(Ordering::SeqCst),
                total,
            },
            other => other,
        });
    }
    Ok(RollingResult {
        steps,
        sample_rate: config.sample_rate(),
        resumed,
        input_hash: hash,
    })
}

#[allow(clippy::too_many_arguments)]
fn run_chunk<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    options: &RunOptions<'_>,
    hash: u64,
    (a, b): (usize, usize),
    warmup: usize,
    (loaded, states): (&[Option<StepRecord>], &HashMap<usize, Carry>),
    (counter, stop): (&AtomicUsize, &AtomicBool),
    (total, resumed): (usize, usize),
    coupling: Option<&dyn StepCoupling<L>>,
) -> Result<Vec<StepRecord>, RollingError> {
    let mut records: Vec<StepRecord> = Vec::with_capacity(b - a);
    let mut scratch = Scratch::new(road.len());
    let mut carry = None;
    // Warm-up: the steps before the chunk, solved only for their final
    // state. Not when the chunk's first step is resumed from the checkpoint
    // (the saved state, if any, takes over there).
    if loaded.first().is_some_and(Option::is_none) {
        for k in a.saturating_sub(warmup)..a {
            solve_step(
                road,
                material,
                config,
                k,
                &mut carry,
                &mut scratch,
                coupling,
            )?;
        }
    }
    let mut last_write = Instant::now();
    let mut unsaved = false;
    let save = |records: &[StepRecord], carry: &Option<Carry>| -> Result<(), RollingError> {
        match options.checkpoint {
            Some(ck) => checkpoint::save(
                ck,
                hash,
                (a, b),
                config.sensors.len(),
                records,
                carry
                    .as_ref()
                    .map(|c| Carry {
                        ids: c.ids.iter().map(|&i| road.global_id(i)).collect(),
                        ..c.clone()
                    })
                    .as_ref(),
            ),
            None => Ok(()),
        }
    };
    for (k, prior) in (a..b).zip(loaded) {
        if stop.load(Ordering::SeqCst) {
            if unsaved {
                save(&records, &carry)?;
            }
            return Err(RollingError::Interrupted { done: 0, total });
        }
        if let Some(r) = prior {
            records.push(r.clone());
            // The next computed step warm-starts from the saved state when
            // there is one (then it is bit-for-bit what an uninterrupted run
            // computes), else cold: its result does not depend on the start
            // to the solver tolerance.
            carry = states.get(&k).cloned();
            // A coupled run's warm correction is not checkpointed: the
            // next computed step starts its fixed point afresh.
            scratch.correction.clear();
            continue;
        }
        let record = match solve_step(
            road,
            material,
            config,
            k,
            &mut carry,
            &mut scratch,
            coupling,
        ) {
            Ok(r) => r,
            Err(e) => {
                if unsaved {
                    save(&records, &carry)?;
                }
                return Err(e);
            }
        };
        records.push(record);
        unsaved = true;
        if options
            .checkpoint
            .is_some_and(|ck| last_write.elapsed() >= ck.interval)
        {
            save(&records, &carry)?;
            last_write = Instant::now();
            unsaved = false;
        }
        let n = counter.fetch_add(1, Ordering::SeqCst) + 1;
        if let Some(progress) = options.progress {
            let flow = progress(Progress {
                done: n,
                total,
                resumed,
            });
            if flow.is_break() {
                stop.store(true, Ordering::SeqCst);
            }
        }
    }
    if unsaved {
        save(&records, &carry)?;
    }
    Ok(records)
}

#[cfg(test)]
mod tests {
    use std::time::Duration;

    use tyreroad_asperity::Sphere;
    use tyreroad_contact_law::{Material, PotentialLaw};

    use super::*;
    use crate::step::FAIL_STEP;
    use crate::{StepStatus, SyntheticRoad, Tread};

    fn close(a: f64, b: f64) -> bool {
        (a - b).abs() <= 1e-9 * a.abs().max(b.abs()).max(1e-300)
    }

    type SphereRoad = Road<PotentialLaw<Sphere>>;

    /// A tyre at 120 N rolled in 2 mm steps from x = 0.05 m to `end` over a
    /// 0.2 × 0.06 m synthetic sphere road drawn from `seed`.
    fn small_run(
        rubber: Material,
        seed: u64,
        end: f64,
    ) -> Result<(SphereRoad, RollingConfig), Box<dyn std::error::Error>> {
        let road = SyntheticRoad {
            seed,
            length: 0.2,
            width: 0.06,
            density: 30_000.0,
            ..SyntheticRoad::default()
        }
        .sphere_road(rubber)?;
        let tyre = Tread::Tyre {
            radius_x: 0.3,
            radius_y: 0.2,
            length: 0.1,
            width: 0.06,
        };
        let config = RollingConfig::new(
            tyre,
            [0.05, end, 2e-3],
            13.9,
            crate::RollingControl::Load(120.0),
        );
        Ok((road, config))
    }

    /// One step forced to fail: the run completes, that step is marked
    /// failed with NaN values, the steps before it are bit for bit those of
    /// an uninterrupted run and the ones after it (the next cold-starts)
    /// equal them to the solver tolerance; a checkpoint keeps the failed
    /// step and resumes bit for bit.
    #[test]
    fn a_failed_step_is_recorded_and_the_run_goes_on() -> Result<(), Box<dyn std::error::Error>> {
        let rubber = Material::new(6.54e6, 0.5)?;
        let (road, config) = small_run(rubber, 7, 0.09)?;
        let clean = roll(&road, rubber, &config, &RunOptions::default())?;
        assert!(clean.all_converged());
        let failed_at = 7;
        FAIL_STEP.with(|f| f.set(Some(failed_at)));
        let dir = std::env::temp_dir().join(format!("tyreroad-failed-step-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let ck = CheckpointOptions {
            dir: dir.clone(),
            interval: Duration::ZERO,
        };
        let with_checkpoint = RunOptions {
            checkpoint: Some(&ck),
            ..RunOptions::default()
        };
        let run = roll(&road, rubber, &config, &with_checkpoint);
        FAIL_STEP.with(|f| f.set(None));
        let run = run?;
        assert_eq!(run.steps.len(), clean.steps.len());
        assert_eq!(run.status_counts(), [clean.steps.len() - 1, 0, 1]);
        assert!(!run.all_converged());
        let bad = &run.steps[failed_at];
        assert_eq!(bad.status, StepStatus::Failed);
        assert!(bad.total_force.is_nan() && bad.approach.is_nan() && bad.contact_ids.is_empty());
        assert_eq!(run.steps[..failed_at], clean.steps[..failed_at]);
        for (a, b) in run.steps.iter().zip(&clean.steps).skip(failed_at + 1) {
            assert_eq!(a.status, StepStatus::Converged);
            assert_eq!(
                (a.index, a.contact_ids.clone()),
                (b.index, b.contact_ids.clone())
            );
            assert!(close(a.total_force, b.total_force), "{a:?}\n{b:?}");
            assert!(close(a.approach, b.approach), "{a:?}\n{b:?}");
            assert!(close(a.contact_area, b.contact_area), "{a:?}\n{b:?}");
        }
        // The failed step comes back from the checkpoint as it was (NaN
        // compares unequal, so compare the bits through the Debug text).
        let again = roll(&road, rubber, &config, &with_checkpoint)?;
        assert_eq!(again.resumed, run.steps.len());
        assert_eq!(format!("{:?}", again.steps), format!("{:?}", run.steps));
        let _ = std::fs::remove_dir_all(&dir);
        Ok(())
    }

    /// A path split into ranges, each rolled on its own with a warm-up
    /// (as the ranks of a distributed run do), gives the single run's
    /// records: bit for bit the same steps and indices, values to 1e-9
    /// relative (the solver converges to 1e-12 from any start), with and
    /// without a warm-up; a bad range is a named error.
    #[test]
    fn ranges_with_warmup_equal_the_whole_run() -> Result<(), Box<dyn std::error::Error>> {
        let rubber = Material::new(6.54e6, 0.5)?;
        let (road, config) = small_run(rubber, 11, 0.1)?;
        let whole = roll(&road, rubber, &config, &RunOptions::default())?;
        let n = whole.steps.len();
        for warmup in [0, 3] {
            let mut joined = Vec::new();
            for (a, b) in [(0, 7), (7, 8), (8, n)] {
                let part =
                    roll_range(&road, rubber, &config, a..b, warmup, &RunOptions::default())?;
                assert_eq!(part.steps.len(), b - a);
                joined.extend(part.steps);
            }
            for (a, b) in joined.iter().zip(&whole.steps) {
                assert_eq!((a.index, &a.contact_ids), (b.index, &b.contact_ids));
                assert!(close(a.total_force, b.total_force), "{a:?}\n{b:?}");
                assert!(close(a.approach, b.approach), "{a:?}\n{b:?}");
                assert!(close(a.contact_area, b.contact_area), "{a:?}\n{b:?}");
            }
        }
        for bad in [3..3, 0..n + 1] {
            let err = roll_range(&road, rubber, &config, bad, 0, &RunOptions::default());
            assert!(matches!(err, Err(RollingError::InvalidInput(_))), "{err:?}");
        }
        Ok(())
    }
}
