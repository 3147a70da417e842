//! The MPI paths (feature `mpi`, rsmpi): a rolling run split over the
//! ranks, and a sweep handed out run by run.
//!
//! Messages (docs/distributed.md): a rolling run sends nothing while it
//! steps; at the end every rank `r > 0` sends rank 0 its part's head
//! ([`crate::spill::encode_head`]) and its records in chunks read back
//! from its spill file, or its error, which rank 0 hands on a record at a
//! time to its writers ([`roll_into`]). A sweep's
//! workers send rank 0 a request (empty) or a finished row, and get back
//! the next run's number or [`STOP`].

use mpi::traits::{Communicator, CommunicatorCollectives, Destination, Source};
use tyreroad::scenario::{RollingRun, RunOptions, Scenario, ScenarioError};
use tyreroad_rolling::{RollingResult, StepRecord};

pub use mpi::environment::Universe;
pub use mpi::topology::SimpleCommunicator;

use crate::DistributedError;
use crate::plan::rank_range;
use crate::spill::{CHUNK, RecordChunks, RecordSpill, decode_head, encode_head};
use crate::sweep::{SweepRow, SweepRun};
use crate::sweep::{decode_row, encode_row};
use crate::wire::PartHead;

/// The job number that tells a sweep worker to stop.
pub const STOP: u64 = u64::MAX;

/// Starts MPI (once per process); `None` when it was already started.
pub fn initialize() -> Option<Universe> {
    mpi::initialize()
}

/// Whether this process is rank 0 of `world` (the one that writes).
pub fn is_root(world: &SimpleCommunicator) -> bool {
    world.rank() == 0
}

fn rank_of(world: &SimpleCommunicator) -> (usize, usize) {
    (
        usize::try_from(world.rank()).unwrap_or(0),
        usize::try_from(world.size()).unwrap_or(1),
    )
}

/// What rank 0 learns of a distributed rolling run besides its records.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Gathered {
    /// Records handed on (every step of the path, in order).
    pub steps: usize,
    /// Steps loaded from checkpoints instead of computed, over all ranks.
    pub resumed: usize,
    /// Hash of the inputs keying the checkpoints.
    pub input_hash: u64,
}

/// Where rank 0 puts the path's records, one at a time, in path order.
pub type RecordSink<'s> = dyn FnMut(StepRecord) -> Result<(), ScenarioError> + 's;

/// Rolls `scenario`'s `[rolling]` path over the ranks of `world` and hands
/// every record, in path order, to rank 0's `sink` as it arrives: rank `r`
/// of `n` rolls the steps [`rank_range`]`(total, r, n)` started `warmup`
/// steps early, checkpointing into `options.checkpoint_dir` (files named by
/// step range, so the ranks never share one and a killed job resumes, even
/// on another number of ranks). Rank 0 hands on its own records piece by
/// piece as it rolls them (1 m of path at a time on a synthetic road), then
/// each other rank's chunks, in rank order, decoded a record at a time as
/// they come: it never holds more than a piece of its own part or one
/// chunk, and a rank `r > 0` never more than a piece and a chunk, its part
/// waiting in its spill file (docs/distributed.md, "Gather and write"). Returns [`Gathered`] on rank
/// 0, `None` elsewhere; the other ranks' `sink` is never called.
///
/// Every rank must call it (it is collective). After any error rank 0
/// still receives every message (a rank must not wait forever on its
/// send) but hands nothing more to `sink`.
///
/// # Errors
/// On rank 0: the first error, in rank order: any rank's (named by its
/// rank), `sink`'s (as rank 0's), or a damaged message. On the other
/// ranks: their own error, after it was sent to rank 0.
pub fn roll_into(
    world: &SimpleCommunicator,
    scenario: &Scenario,
    options: &RunOptions<'_>,
    warmup: usize,
    sink: &mut RecordSink<'_>,
) -> Result<Option<Gathered>, DistributedError> {
    let (rank, ranks) = rank_of(world);
    if let (0, Some(dir)) = (rank, &options.checkpoint_dir) {
        // Killed runs' temporary files go before any rank writes its own
        // there. An unlistable directory is reported by the ranks' own
        // checkpoint load, so this error adds nothing.
        let _ = tyreroad_rolling::remove_unfinished_checkpoints(dir);
    }
    world.barrier();
    let part = scenario
        .rolling_steps()
        .map(|total| rank_range(total, rank, ranks));
    if rank > 0 {
        return send_part(world, scenario, options, part, (rank, warmup));
    }
    let mut gathered = Gathered {
        steps: 0,
        resumed: 0,
        input_hash: 0,
    };
    let mut first_error = None;
    // Rank 0's own records go on piece by piece, as they are rolled.
    let own = part.and_then(|range| {
        if range.is_empty() {
            return Ok(());
        }
        scenario.roll_part_into(options, range, warmup, &mut |piece| {
            gathered.resumed += piece.resumed;
            gathered.input_hash = piece.input_hash;
            for record in piece.steps {
                sink(record)?;
                gathered.steps += 1;
            }
            Ok(())
        })
    });
    if let Err(e) = own {
        first_error = Some(DistributedError::Rank {
            rank: 0,
            message: e.to_string(),
        });
    }
    for r in 1..ranks {
        receive_part(world, r, first_error.is_some(), &mut |record| {
            sink(record).map_err(|e| DistributedError::Rank {
                rank: 0,
                message: e.to_string(),
            })?;
            gathered.steps += 1;
            Ok(())
        })
        .map(|head| {
            if let Some(head) = head {
                gathered.resumed += head.resumed;
                gathered.input_hash = head.input_hash;
            }
        })
        .unwrap_or_else(|e| {
            first_error.get_or_insert(e);
        });
    }
    match first_error {
        Some(e) => Err(e),
        None if gathered.steps == 0 => Err(DistributedError::Wire("no rank sent records".into())),
        None => Ok(Some(gathered)),
    }
}

/// A rank `r > 0`'s side of [`roll_into`]: rolls its part into a spill
/// file (crate::spill), then sends rank 0 the part's head and its records
/// in chunks of at most [`CHUNK`] bytes, or its error. It holds a piece of
/// its part (1 m of path on a synthetic road) and a chunk, never the part.
fn send_part(
    world: &SimpleCommunicator,
    scenario: &Scenario,
    options: &RunOptions<'_>,
    part: Result<std::ops::Range<usize>, ScenarioError>,
    (rank, warmup): (usize, usize),
) -> Result<Option<Gathered>, DistributedError> {
    let root = world.process_at_rank(0);
    let spilled = part.map_err(DistributedError::from).and_then(|range| {
        if range.is_empty() {
            // More ranks than steps: this one has nothing to roll.
            return Ok(None);
        }
        // The node's scratch ($TMPDIR), not the output folder: rank 0
        // swaps that folder in whole at the end (docs/distributed.md).
        let mut spill = RecordSpill::create(&std::env::temp_dir(), rank)?;
        let mut spill_error = None;
        let rolled = scenario.roll_part_into(options, range, warmup, &mut |piece| {
            spill.push(piece).map_err(|e| {
                let message = e.to_string();
                spill_error = Some(e);
                ScenarioError::Invalid(message)
            })
        });
        match (rolled, spill_error) {
            (_, Some(e)) => Err(e),
            (Err(e), None) => Err(e.into()),
            (Ok(()), None) => Ok(Some(spill)),
        }
    });
    match spilled {
        Ok(None) => {
            root.send(&[1u8][..]);
            Ok(None)
        }
        Ok(Some(spill)) => {
            let (head, body) = spill.head();
            root.send(&encode_head(&[1], &head, body)[..]);
            // Once the head is sent rank 0 waits for `body` bytes: a spill
            // file that cannot be read back still sends them (zeros), so
            // that neither rank waits forever; rank 0 then fails on them.
            let mut sent = 0;
            let outcome = spill.send_chunks(CHUNK, &mut |chunk| {
                root.send(chunk);
                sent += chunk.len();
                Ok(())
            });
            let zeros = vec![0u8; CHUNK.min(body - sent)];
            while sent < body {
                let n = zeros.len().min(body - sent);
                root.send(&zeros[..n]);
                sent += n;
            }
            outcome.map(|()| None)
        }
        Err(e) => {
            let mut bytes = vec![0];
            bytes.extend(e.to_string().as_bytes());
            root.send(&bytes[..]);
            Err(e)
        }
    }
}

/// Rank 0 receives rank `r`'s part ([`send_part`]) and hands its records,
/// in order, to `each`, unless the run has `failed` already: then the
/// chunks are received (so rank `r` is not left waiting) and dropped.
/// Returns the part's head (`None` for an empty part or a failed run).
fn receive_part(
    world: &SimpleCommunicator,
    r: usize,
    failed: bool,
    each: &mut dyn FnMut(StepRecord) -> Result<(), DistributedError>,
) -> Result<Option<PartHead>, DistributedError> {
    let source = world.process_at_rank(i32::try_from(r).unwrap_or(i32::MAX));
    let bytes = source.receive_vec::<u8>().0;
    let head = match bytes.split_first() {
        Some((1, [])) => return Ok(None),
        Some((1, head)) => decode_head(head)?,
        Some((_, why)) => {
            return Err(DistributedError::Rank {
                rank: r,
                message: String::from_utf8_lossy(why).into_owned(),
            });
        }
        None => {
            return Err(DistributedError::Wire(format!(
                "empty message from rank {r}"
            )));
        }
    };
    let (head, body) = head;
    let mut chunks = RecordChunks::new(&head, body);
    let mut failed = failed;
    let mut outcome = Ok(Some(head));
    while !chunks.done() {
        let chunk = source.receive_vec::<u8>().0;
        if chunk.is_empty() {
            // A rank never sends an empty chunk: a damaged stream.
            return Err(DistributedError::Wire(format!(
                "an empty chunk from rank {r}"
            )));
        }
        if failed {
            // Count the bytes only, so that the loop ends when rank r's do.
            chunks.skip(chunk.len());
            continue;
        }
        if let Err(e) = chunks.push(&chunk, each) {
            failed = true;
            outcome = Err(e);
        }
    }
    outcome
}

/// [`roll_into`] with rank 0 gathering every record and finishing them into
/// the run (road summary, spectra) exactly as a single process would.
/// Rank 0 holds every record of the path: for long paths write them as
/// they arrive with [`roll_into`] instead. Returns the run on rank 0,
/// `None` elsewhere. Every rank must call it (it is collective).
///
/// # Errors
/// As [`roll_into`], and [`Scenario::finish_rolling`]'s.
pub fn roll(
    world: &SimpleCommunicator,
    scenario: &Scenario,
    options: &RunOptions<'_>,
    warmup: usize,
) -> Result<Option<RollingRun>, DistributedError> {
    let mut steps = Vec::new();
    if let Ok(total) = scenario.rolling_steps() {
        // Room for the whole path at once (growing by doubling would hold
        // up to twice the records at the last copy).
        steps.reserve_exact(total);
    }
    let gathered = roll_into(world, scenario, options, warmup, &mut |record| {
        steps.push(record);
        Ok(())
    })?;
    let Some(gathered) = gathered else {
        return Ok(None);
    };
    let config = scenario.rolling_config()?;
    let result = RollingResult {
        steps,
        sample_rate: config.sample_rate(),
        resumed: gathered.resumed,
        input_hash: gathered.input_hash,
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
