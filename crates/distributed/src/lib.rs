//! tyreroad beyond one machine (docs/distributed.md): a rolling run split
//! over MPI ranks, and parameter sweeps on one machine (rayon) or over MPI
//! ranks.
//!
//! # Distributed rolling
//!
//! The path's `N` steps are split into contiguous parts, rank `r` of `n`
//! taking [`rank_range`]`(N, r, n)` (sizes `⌊N/n⌋` or `⌈N/n⌉`, in rank
//! order). Each rank rolls its part with `tyreroad_rolling::roll_range`,
//! first solving `w` warm-up steps before its part ([`DEFAULT_WARMUP`]) so
//! that its first step starts as if the run had come from the start.
//! Because every step is solved to the rolling tolerance (`1e-12`), a
//! step's result does not depend on where its solve started: the gathered
//! signals equal a single process's to `1e-9` relative whatever `n` and
//! `w`, and the spectra are identical. A rank `r > 0` spills its records
//! to a file as it rolls them and sends them to rank 0 at the end, in
//! chunks of at most [`spill::CHUNK`] bytes ([`spill`], [`wire`]); rank 0
//! writes them as they arrive, in path order, through the writers a single process uses
//! (`tyreroad::scenario::output::steps_stream`), keeping only the few
//! signals per step the spectra need (`mpi::roll_into`), so the same
//! records give the same files and rank 0 does not hold the path's records.
//!
//! # Sweeps
//!
//! A sweep file ([`sweep`]) names a base scenario and lists of parameter
//! values, combined as a grid or a list; each run gives one row of the
//! result table ([`sweep::table_csv`]): its parameters, mean force, overall
//! level and per-band levels. [`sweep::run_local`] runs them on a rayon
//! pool; `mpi::run_sweep` (feature `mpi`) hands them out one at a time from
//! rank 0 to whichever rank is free. Both give the same rows (each run is
//! computed the same way, on one thread).
//!
//! # Invariants
//! - the parts of [`rank_range`] cover `0..N` exactly, in rank order;
//! - records and rows cross the wire bit for bit ([`wire`]);
//! - one failed sweep run is that row's error, not the sweep's;
//! - without the `mpi` feature nothing here needs a system library.

pub mod plan;
pub mod spill;
pub mod sweep;
pub mod wire;

#[cfg(feature = "mpi")]
pub mod mpi;

pub use plan::{DEFAULT_WARMUP, rank_range};

/// What can go wrong in a distributed run or a sweep.
#[derive(Debug, thiserror::Error)]
pub enum DistributedError {
    /// The scenario failed (on this rank).
    #[error(transparent)]
    Scenario(#[from] tyreroad::scenario::ScenarioError),
    /// Another rank failed; its message.
    #[error("rank {rank}: {message}")]
    Rank {
        /// The failing rank.
        rank: usize,
        /// Its error.
        message: String,
    },
    /// A message between ranks is damaged or truncated.
    #[error("message between ranks: {0}")]
    Wire(String),
    /// A sweep file is malformed.
    #[error("sweep {0}")]
    Sweep(String),
}
