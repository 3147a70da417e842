//! Rolling-time assembly (docs/rolling.md, Cesbron et al. 2006 §2.1): a tread
//! rolled along a road of asperities, one static multipoint solve per space
//! step, giving time signals and their one-third-octave spectra.
//!
//! # Road and tread
//!
//! The road is a generic set of asperities ([`Road`], built on an
//! [`AsperitySet`]): summit `i` (its id is its index) at `(x_i, y_i)` — x along the driving direction, y across — with
//! height `z_i` (up, towards the tread) and its own [`ContactLaw`]. The tread
//! ([`Tread`]) is centred at `(x_c, y_c)`; its undeformed surface lies
//! `s(ξ, η)` above its lowest point, `ξ = x − x_c`, `η = y − y_c`:
//!
//! ```text
//! block:  s = 0                      for |ξ| ≤ L/2, |η| ≤ W/2 (no tread outside)
//! tyre:   s = ξ²/(2 Rx) + η²/(2 Ry)  selected for |ξ| ≤ L/2 + m, |η| ≤ W/2 + m
//! ```
//!
//! (`L × W` the footprint, `m` the selection margin). The gaps of the
//! sub-problem at one step are measured from the road's **reference plane**
//! `z_max` ([`Road::top`]: the whole road's highest summit, or the highest
//! point of the height map it was measured on, [`Road::with_top`]; the
//! whole road's, not the footprint's, so that the approach is one
//! continuous signal):
//!
//! ```text
//! H_i = (z_max − z_i) + s(x_i − x_c, y_i − y_c),     δ_i = δ0 − H_i − u_i
//! ```
//!
//! so `δ0` is the approach of the tread's lowest point below `z_max`. Under
//! load control ([`RollingControl::Load`]) the wheel load `W = Σ P_i` is
//! imposed and `δ0` is an output; under displacement control (a fixed axle
//! height, [`RollingControl::Approach`] or [`RollingControl::TreadHeight`]
//! `h` with `δ0 = z_max − h`) the total force is the output.
//!
//! # Path and time
//!
//! Footprint centres `x_k = start + k Δx` (`k = 0, 1, …` while `x_k ≤ end`),
//! times `t_k = x_k / V`, sampling rate `fs = V / Δx`. At each step the
//! asperities under the footprint (plus margin) are found by binary search
//! in the x-sorted road, the sub-problem is built and solved
//! ([`tyreroad_multipoint::solve_from`]), warm started from the previous step
//! (forces mapped by asperity id, new asperities at 0). The path is split
//! into contiguous chunks, run one after another or in a rayon pool as the
//! caller's [`RunOptions::par`] says; each chunk cold-starts.
//!
//! # Signals
//!
//! Per step ([`StepRecord`]): total force `Σ P_i`, approach `δ0`, contact
//! area `Σ π a_i²` (local contacts rebuilt by each law, Hertz for spheres),
//! number of contacts, and the force on each virtual [`Sensor`]: each local
//! contact's pressure (Hertz or cone profile over its radius, centred on the
//! summit) integrated over the sensor's rectangle ([`Sensor::share`]), so a
//! contact straddling an edge is split between neighbouring sensors and
//! sensors tiling the road sum to the total force.
//!
//! # Spectra
//!
//! [`welch`]: Hann-windowed segments (periodic window `w_j = ½(1 − cos 2πj/L)`),
//! 50 % overlap, mean removed, one-sided PSD normalised by the window power
//!
//! ```text
//! S(f_m) = c_m |X_m|² / (fs Σ w_j²),  c_m = 1 at DC and Nyquist, 2 between,
//! Σ_m S(f_m) df = Σ (w_j x_j)² / Σ w_j²   (the mean square, Parseval)
//! ```
//!
//! One-third-octave bands ([`Band`], IEC 61260-1 base 10): `f_m = 1000 ·
//! 10^(k/10)` Hz, edges `f_m 10^(±1/20)`, nominal labels 20 Hz … 10 kHz
//! (`k = −17 … 10`). A band's power is the sum of the PSD bins, each
//! weighted by the fraction of its interval `[f − df/2, f + df/2]` inside the
//! band, times `df`; its level is `L = 10 log10(P_band / ref²)` dB (re 1 N
//! for forces).
//!
//! # Invariants
//!
//! - a step's result does not depend on where its solve started: the solver
//!   converges to a tight tolerance ([`RollingConfig::tolerance`], `1e-12`),
//!   so results agree across chunkings and thread counts (tested to 1e-9);
//! - the selection is exact when [`StepRecord::clearance`] is positive: every
//!   asperity left out has a gap larger than `δ0` (and `u_i ≥ 0`), so it would
//!   carry exactly zero; nothing jumps when an asperity enters the window;
//! - a step whose solve does not converge is recorded as
//!   [`StepStatus::Failed`] (NaN values, no contacts) and the run goes on,
//!   the next step cold-started; every step records its status, recovery,
//!   iterations and residual;
//! - a run killed part-way resumes from its checkpoint ([`CheckpointOptions`])
//!   without recomputing finished steps, bit for bit; a checkpoint that is
//!   damaged, edited or disagrees with the inputs is refused
//!   ([`RollingError::CheckpointRejected`]), never resumed;
//! - a window of a road ([`Road::window_of`], the synthetic road's from
//!   [`SyntheticRoad::windows`] without building the whole road) poses the
//!   whole road's sub-problem at every step whose footprint it covers (the
//!   same asperities in the same order, by their global ids, gaps from the
//!   whole road's `z_max`), so from the same warm start it gives the same
//!   record bit for bit;
//! - user input never panics: errors are [`RollingError`]s.
//!
//! # Example
//!
//! ```
//! use tyreroad_asperity::Sphere;
//! use tyreroad_contact_law::{Material, PotentialLaw};
//! use tyreroad_multipoint::AsperitySet;
//! use tyreroad_rolling::{roll, Road, RollingConfig, RollingControl, RunOptions, Tread};
//!
//! let rubber = Material::new(6.54e6, 0.5)?;
//! let ball = PotentialLaw::sphere(Sphere::new(5e-3)?, rubber);
//! // A row of balls at 10 mm pitch, two rows 10 mm apart.
//! let positions: Vec<[f64; 2]> = (0..40)
//!     .map(|i| [(i / 2) as f64 * 0.01, if i % 2 == 0 { -0.005 } else { 0.005 }])
//!     .collect();
//! let road = Road::new(AsperitySet::new(positions, vec![0.0; 40], vec![ball; 40])?);
//! let tyre = Tread::Tyre { radius_x: 0.3, radius_y: 0.3, length: 0.06, width: 0.06 };
//! let config = RollingConfig::new(tyre, [0.05, 0.15, 1e-3], 10.0, RollingControl::Load(10.0));
//! let result = roll(&road, rubber, &config, &RunOptions::default())?;
//! assert_eq!(result.steps.len(), 101);
//! assert!(result.steps.iter().all(|s| (s.total_force - 10.0).abs() < 1e-9));
//! assert!(result.min_clearance() > 0.0); // the footprint window is wide enough
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

mod checkpoint;
mod config;
mod coupling;
mod placement;
mod record;
mod road;
mod run;
mod sensor;
mod slope;
mod slope_rounds;
mod spectrum;
mod step;
mod synth;
mod synth_window;
mod tread;

pub use checkpoint::{RoadDigest, input_hash, remove_unfinished as remove_unfinished_checkpoints};
pub use config::{CheckpointOptions, MAX_STEPS, RollingConfig, RollingControl, path_steps};
pub use coupling::{
    CouplingState, FirstSolve, FixedPoint, FixedPointDamping, KeptCoupling, Spread, Start,
    StepCoupling, first_solve, stalled_fixed_point,
};
pub use placement::Placement;
pub use record::{
    Recovery, RollingResult, StepRecord, StepStatus, interpolate_failed, recovery_name,
};
pub use road::Road;
pub use run::{
    Progress, ProgressFn, RunOptions, roll, roll_coupled, roll_range, roll_range_coupled,
};
pub use sensor::{SHARE_RINGS, SHARE_SPOKES, Sensor};
pub use slope::{ContactSlope, deformation_slopes};
pub use spectrum::{
    Band, BandLevel, NOMINAL_CENTRES, Psd, band_levels, bands_below, default_segment_len,
    effective_segment_len, resolved_from, third_octave, welch,
};
pub use step::{
    SettledStep, StepProblem, contact_point, contact_points, settled_step, step_problem,
};
pub use synth::SyntheticRoad;
pub use synth_window::{SummitStream, SyntheticWindows};
pub use tread::Tread;
pub use tyreroad_contact_law::ContactLaw;
pub use tyreroad_multipoint::{AsperitySet, Par, SolveError};

/// What can go wrong in a rolling run.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RollingError {
    /// The road, tread, path or spectrum request is malformed.
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// The static solve of one step failed.
    #[error("step at x = {position} m: {source}")]
    Solve {
        /// Footprint centre (m).
        position: f64,
        /// The solver's error.
        source: SolveError,
    },
    /// Load control with no asperity under the footprint.
    #[error("step at x = {position} m: no asperity under the footprint to carry the load")]
    NoSupport {
        /// Footprint centre (m).
        position: f64,
    },
    /// The progress callback stopped the run; finished steps are in the
    /// checkpoint (when enabled).
    #[error("interrupted after {done} of {total} steps")]
    Interrupted {
        /// Steps finished (resumed ones included).
        done: usize,
        /// Steps on the path.
        total: usize,
    },
    /// A checkpoint file could not be read or written.
    #[error("checkpoint: {0}")]
    Checkpoint(String),
    /// A checkpoint file is damaged (checksum), edited, or disagrees with
    /// the inputs; it is not resumed. Delete it to recompute its steps.
    #[error("checkpoint {file} refused: {reason}; delete it to recompute its steps")]
    CheckpointRejected {
        /// The file's path.
        file: String,
        /// What is wrong with it.
        reason: String,
    },
}
