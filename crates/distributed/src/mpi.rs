//! The MPI paths (feature `mpi`, rsmpi): a rolling run split over the
//! ranks, and a sweep handed out run by run.
//!
//! Messages (docs/distributed.md): a rolling run sends nothing while it
//! steps; at the end every rank `r > 0` sends rank 0 one buffer, its
//! records ([`crate::wire::encode_records`]) or its error. A sweep's
//! workers send rank 0 a request (empty) or a finished row, and get back
//! the next run's number or [`STOP`].

use mpi::traits::{Communicator, CommunicatorCollectives, Destination, Source};
use tyreroad::scenario::{RollingRun, RunOptions, Scenario};
use tyreroad_rolling::RollingResult;

pub use mpi::environment::Universe;
pub use mpi::topology::SimpleCommunicator;

use crate::DistributedError;
use crate::plan::rank_range;
use crate::sweep::{SweepRow, SweepRun};
use crate::sweep::{decode_row, encode_row};
use crate::wire::{decode_records, encode_records_owned};

/// The job number that tells a sweep worker to stop.
pub const STOP: u64 = u64::MAX;

/// Starts MPI (once per process); `None` when it was already started.
pub fn initialize() -> Option<Universe> {
    mpi::initialize()
}

fn rank_of(world: &SimpleCommunicator) -> (usize, usize) {
    (
        usize::try_from(world.rank()).unwrap_or(0),
        usize::try_from(world.size()).unwrap_or(1),
    )
}

/// Rolls `scenario`'s `[rolling]` path over the ranks of `world`: rank `r`
/// of `n` rolls the steps [`rank_range`]`(total, r, n)` started `warmup`
/// steps early, checkpointing into `options.checkpoint_dir` (files named by
/// step range, so the ranks never share one and a killed job resumes, even
/// on another number of ranks), then every rank sends its records to rank
/// 0, which finishes them into the run (road summary, spectra) exactly as a
/// single process would. Returns the run on rank 0, `None` elsewhere.
///
/// Every rank must call it (it is collective).
///
/// # Errors
/// On rank 0: any rank's error (named by its rank) or a damaged message.
/// On the other ranks: their own error, after it was sent to rank 0.
pub fn roll(
    world: &SimpleCommunicator,
    scenario: &Scenario,
    options: &RunOptions<'_>,
    warmup: usize,
) -> Result<Option<RollingRun>, DistributedError> {
    let (rank, ranks) = rank_of(world);
    if let (0, Some(dir)) = (rank, &options.checkpoint_dir) {
        // Killed runs' temporary files go before any rank writes its own
        // there. An unlistable directory is reported by the ranks' own
        // checkpoint load, so this error adds nothing.
        let _ = tyreroad_rolling::remove_unfinished_checkpoints(dir);
    }
    world.barrier();
    let mine = scenario.rolling_steps().and_then(|total| {
        let range = rank_range(total, rank, ranks);
        if range.is_empty() {
            // More ranks than steps: this one has nothing to roll.
            return Ok(None);
        }
        scenario.roll_part(options, range, warmup).map(Some)
    });
    if rank > 0 {
        // The records are freed as they are encoded (a rank holds its part
        // once, not twice); the status byte leads.
        let (bytes, outcome) = match mine {
            Ok(Some(part)) => (encode_records_owned(&[1], part), Ok(None)),
            Ok(None) => (vec![1], Ok(None)),
            Err(e) => {
                let mut bytes = vec![0];
                bytes.extend(e.to_string().as_bytes());
                (bytes, Err(DistributedError::from(e)))
            }
        };
        world.process_at_rank(0).send(&bytes[..]);
        return outcome;
    }
    let mut steps = Vec::new();
    let mut resumed = 0;
    let mut meta = None;
    let mut first_error = None;
    // Rank 0's own records are moved, not encoded: it holds one copy of
    // each record, and one rank's message at a time.
    match mine {
        Ok(Some(part)) => {
            resumed += part.resumed;
            meta = Some((part.sample_rate, part.input_hash));
            steps = part.steps;
        }
        Ok(None) => {}
        Err(ref e) => {
            first_error = Some(DistributedError::Rank {
                rank: 0,
                message: e.to_string(),
            });
        }
    }
    // Room for the whole path at once (growing by doubling would hold up to
    // twice the records at the last copy).
    let total = scenario.rolling_steps().unwrap_or(0);
    steps.reserve_exact(total.saturating_sub(steps.len()));
    for r in 1..ranks {
        let bytes = world
            .process_at_rank(i32::try_from(r).unwrap_or(i32::MAX))
            .receive_vec::<u8>()
            .0;
        match bytes.split_first() {
            Some((1, [])) => {}
            Some((1, body)) => {
                let part = decode_records(body)?;
                resumed += part.resumed;
                meta = Some((part.sample_rate, part.input_hash));
                steps.extend(part.steps);
            }
            Some((_, why)) => {
                first_error.get_or_insert_with(|| DistributedError::Rank {
                    rank: r,
                    message: String::from_utf8_lossy(why).into_owned(),
                });
            }
            None => {
                return Err(DistributedError::Wire(format!(
                    "empty message from rank {r}"
                )));
            }
        }
    }
    if let Some(e) = first_error {
        return Err(e);
    }
    let (sample_rate, input_hash) =
        meta.ok_or_else(|| DistributedError::Wire("no rank sent records".into()))?;
    let result = RollingResult {
        steps,
        sample_rate,
        resumed,
        input_hash,
    };
    Ok(Some(scenario.finish_rolling(options, result)?))
}

/// Runs a sweep over the ranks of `world` with dynamic distribution: rank 0
/// hands out run numbers, a worker that finishes a run sends its row and
/// gets the next, so long and short runs balance themselves. With one rank,
/// rank 0 runs them all. Returns every row, in run order, on rank 0 and
/// `None` elsewhere. Every rank must call it with the same runs.
///
/// # Errors
/// A damaged message or a run number out of range.
pub fn run_sweep<F>(
    world: &SimpleCommunicator,
    runs: &[SweepRun],
    run_one: F,
) -> Result<Option<Vec<SweepRow>>, DistributedError>
where
    F: Fn(&SweepRun) -> SweepRow,
{
    let (rank, ranks) = rank_of(world);
    if ranks == 1 {
        return Ok(Some(runs.iter().map(run_one).collect()));
    }
    if rank > 0 {
        let root = world.process_at_rank(0);
        root.send(&[0u8; 0][..]);
        loop {
            let (job, _) = root.receive::<u64>();
            if job == STOP {
                return Ok(None);
            }
            let run = usize::try_from(job)
                .ok()
                .and_then(|j| runs.get(j))
                .ok_or_else(|| DistributedError::Wire(format!("run number {job} out of range")))?;
            root.send(&encode_row(&run_one(run))[..]);
        }
    }
    let mut rows = Vec::with_capacity(runs.len());
    let mut next = 0usize;
    let mut working = ranks - 1;
    while working > 0 {
        let (bytes, status) = world.any_process().receive_vec::<u8>();
        if !bytes.is_empty() {
            rows.push(decode_row(&bytes)?);
        }
        let worker = world.process_at_rank(status.source_rank());
        if next < runs.len() {
            worker.send(&(next as u64));
            next += 1;
        } else {
            worker.send(&STOP);
            working -= 1;
        }
    }
    rows.sort_by_key(|r| r.index);
    Ok(Some(rows))
}
