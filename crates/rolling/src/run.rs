//! Path stepping: one static multipoint solve per footprint position, warm
//! started along contiguous chunks of the path, chunks in parallel.

use std::ops::ControlFlow;
use std::path::PathBuf;
use std::sync::OnceLock;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::time::{Duration, Instant};

use rayon::prelude::*;
use tyreroad_contact_law::{ContactLaw, LocalContact, Material, PressureProfile};
use tyreroad_multipoint::{
    Boussinesq, Control, Par, Problem, Solution, SolverOptions, overlapping_contacts, solve_from,
};

use crate::checkpoint;
use crate::{Road, RollingError, Tread};

/// What is imposed on the tread at every step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RollingControl {
    /// Load control: the wheel load `W = Σ P_i` (N); the approach is an
    /// output.
    Load(f64),
    /// Displacement control at a fixed axle height, given as the approach
    /// `δ0` (m) of the tread's lowest point below the road's highest summit
    /// ([`Road::top`]); the total force is an output.
    Approach(f64),
    /// Displacement control at a fixed axle height, given as the height `h`
    /// (m) of the tread's lowest point above the road datum `z = 0`:
    /// `δ0 = z_max − h`.
    TreadHeight(f64),
}

/// A virtual force sensor: a rectangle fixed on the road, like one pressure
/// cell of a road-embedded array. Its force is the part of each local
/// contact's pressure that falls inside it ([`Sensor::share`]): a contact
/// straddling the sensor's edge is split, so the signal does not jump when a
/// summit crosses the edge.
#[derive(Clone, Debug, PartialEq)]
pub struct Sensor {
    /// Name (CSV column).
    pub name: String,
    /// `[x0, x1]` (m).
    pub x: [f64; 2],
    /// `[y0, y1]` (m).
    pub y: [f64; 2],
}

impl Sensor {
    /// Whether the point `(x, y)` lies inside the rectangle (edges included).
    pub fn contains(&self, [x, y]: [f64; 2]) -> bool {
        (self.x[0]..=self.x[1]).contains(&x) && (self.y[0]..=self.y[1]).contains(&y)
    }

    /// The part (N) of a local contact's force that the sensor sees: the
    /// contact's axisymmetric pressure (its profile and radius, centred on
    /// the summit `centre`) integrated over the rectangle.
    ///
    /// A contact wholly inside gives its whole force, one wholly outside 0.
    /// One that straddles an edge is integrated by an equal-force rule:
    /// [`SHARE_RINGS`] rings, each carrying the same force (radii from the
    /// profile's cumulative force), times [`SHARE_SPOKES`] spokes, each
    /// sample counted in the half-open rectangle `[x0, x1) × [y0, y1)` so
    /// that sensors tiling the road share a contact exactly. A straight
    /// edge through the centre gives exactly half, a corner a quarter.
    pub fn share(&self, centre: [f64; 2], contact: &LocalContact) -> f64 {
        let p = contact.force;
        let a = contact.radius;
        if !(p > 0.0) {
            return 0.0;
        }
        let [cx, cy] = centre;
        let inside =
            |x: f64, y: f64| self.x[0] <= x && x < self.x[1] && self.y[0] <= y && y < self.y[1];
        if !(a > 0.0) {
            return if inside(cx, cy) { p } else { 0.0 };
        }
        if cx - a >= self.x[0] && cx + a < self.x[1] && cy - a >= self.y[0] && cy + a < self.y[1] {
            return p;
        }
        if cx + a < self.x[0] || cx - a >= self.x[1] || cy + a < self.y[0] || cy - a >= self.y[1] {
            return 0.0;
        }
        let rings = ring_radii(contact.profile);
        let mut count = 0usize;
        for &rho in rings.iter() {
            for m in 0..SHARE_SPOKES {
                let phi = (m as f64 + 0.5) * std::f64::consts::TAU / SHARE_SPOKES as f64;
                if inside(cx + a * rho * phi.cos(), cy + a * rho * phi.sin()) {
                    count += 1;
                }
            }
        }
        p * count as f64 / (SHARE_RINGS * SHARE_SPOKES) as f64
    }
}

/// Rings of the equal-force rule of [`Sensor::share`].
pub const SHARE_RINGS: usize = 24;
/// Spokes of the equal-force rule of [`Sensor::share`] (a multiple of 4, so
/// the rule is symmetric about both axes and no sample lies on them).
pub const SHARE_SPOKES: usize = 48;

/// Ring radii `ρ_k / a` of the equal-force rule: the cumulative force
/// `F(ρ)/P` at the ring's midpoint `(k + ½)/K`, for each profile.
fn ring_radii(profile: PressureProfile) -> &'static [f64; SHARE_RINGS] {
    static HERTZ: OnceLock<[f64; SHARE_RINGS]> = OnceLock::new();
    static CONE: OnceLock<[f64; SHARE_RINGS]> = OnceLock::new();
    let (cell, cumulative): (_, fn(f64) -> f64) = match profile {
        // ∫ 3/(2πa²)·√(1 − r²/a²) over r < ρ = 1 − (1 − ρ²)^{3/2}.
        PressureProfile::Hertz => (&HERTZ, |r: f64| 1.0 - (1.0 - r * r).powf(1.5)),
        // ∫ 1/(πa²)·arcosh(a/r) over r < ρ = ρ² arcosh(1/ρ) + 1 − √(1 − ρ²).
        PressureProfile::Cone => (&CONE, |r: f64| {
            if r <= 0.0 {
                0.0
            } else {
                r * r * (1.0 / r).acosh() + 1.0 - (1.0 - r * r).sqrt()
            }
        }),
    };
    cell.get_or_init(|| {
        std::array::from_fn(|k| {
            let target = (k as f64 + 0.5) / SHARE_RINGS as f64;
            // The cumulative force increases from 0 to 1 on [0, 1]: bisect.
            let (mut lo, mut hi) = (0.0f64, 1.0f64);
            for _ in 0..60 {
                let mid = 0.5 * (lo + hi);
                if cumulative(mid) < target {
                    lo = mid;
                } else {
                    hi = mid;
                }
            }
            0.5 * (lo + hi)
        })
    })
}

/// Everything that defines a rolling run's results. Two runs with equal
/// configurations (and equal roads and material) give the same results to
/// the solver tolerance whatever the chunking and thread count.
#[derive(Clone, Debug, PartialEq)]
pub struct RollingConfig {
    /// The tread's shape.
    pub tread: Tread,
    /// Lateral position `y_c` of the footprint centre (m).
    pub lateral: f64,
    /// First footprint centre `x_c` (m).
    pub start: f64,
    /// Last footprint centre (m): steps run `x_k = start + k Δx` while
    /// `x_k ≤ end` (to `10⁻⁹ Δx`).
    pub end: f64,
    /// Space step `Δx` (m, > 0).
    pub step: f64,
    /// Driving speed `V` (m/s, > 0): `t = x / V`.
    pub speed: f64,
    /// What is imposed at each step.
    pub control: RollingControl,
    /// Selection margin (m) added around a tyre's footprint on every side.
    pub margin: f64,
    /// Virtual force sensors.
    pub sensors: Vec<Sensor>,
    /// Solver tolerance, relative to the force scale. Tight (default `1e-12`)
    /// so that a step's solution does not depend on its starting point.
    pub tolerance: f64,
    /// Newton iterations allowed per step (and load step).
    pub max_iterations: usize,
}

impl RollingConfig {
    /// A configuration with no sensor, no margin, tolerance `1e-12` and 60
    /// iterations.
    pub fn new(
        tread: Tread,
        [start, end, step]: [f64; 3],
        speed: f64,
        control: RollingControl,
    ) -> Self {
        Self {
            tread,
            lateral: 0.0,
            start,
            end,
            step,
            speed,
            control,
            margin: 0.0,
            sensors: Vec::new(),
            tolerance: 1e-12,
            max_iterations: 60,
        }
    }

    /// Checks the configuration.
    pub fn validate(&self) -> Result<(), RollingError> {
        self.tread.validate()?;
        let bad = |what: &str, v: f64| Err(RollingError::InvalidInput(format!("{what}: got {v}")));
        for (what, v) in [
            ("lateral", self.lateral),
            ("start", self.start),
            ("end", self.end),
        ] {
            if !v.is_finite() {
                return bad(&format!("path {what} must be finite"), v);
            }
        }
        if !(self.step.is_finite() && self.step > 0.0) {
            return bad("step must be finite and > 0 m", self.step);
        }
        if self.end < self.start {
            return bad("path end must not precede start", self.end);
        }
        if !(self.speed.is_finite() && self.speed > 0.0) {
            return bad("speed must be finite and > 0 m/s", self.speed);
        }
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            return bad("margin must be finite and ≥ 0 m", self.margin);
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) || self.max_iterations == 0 {
            return bad(
                "tolerance must be > 0 and max_iterations ≥ 1",
                self.tolerance,
            );
        }
        match self.control {
            RollingControl::Load(w) if !(w.is_finite() && w >= 0.0) => {
                return bad("wheel load must be finite and ≥ 0 N", w);
            }
            RollingControl::Approach(d) | RollingControl::TreadHeight(d) if !d.is_finite() => {
                return bad("imposed approach or height must be finite", d);
            }
            _ => {}
        }
        for s in &self.sensors {
            let ok = s.x.iter().chain(&s.y).all(|v| v.is_finite())
                && s.x[0] <= s.x[1]
                && s.y[0] <= s.y[1];
            if !ok {
                return Err(RollingError::InvalidInput(format!(
                    "sensor {:?}: needs finite x0 ≤ x1 and y0 ≤ y1, got x {:?}, y {:?}",
                    s.name, s.x, s.y
                )));
            }
        }
        Ok(())
    }

    /// Number of steps on the path.
    pub fn steps(&self) -> usize {
        ((self.end - self.start) / self.step + 1e-9).floor() as usize + 1
    }

    /// Footprint centre `x_k = start + k Δx` of step `k` (m).
    pub fn position(&self, k: usize) -> f64 {
        self.start + k as f64 * self.step
    }

    /// Sampling rate `V / Δx` (Hz) of the time signals.
    pub fn sample_rate(&self) -> f64 {
        self.speed / self.step
    }
}

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

/// Where and how often to checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointOptions {
    /// Directory of the checkpoint files (created when missing).
    pub dir: PathBuf,
    /// Each chunk rewrites its file at most this often (and always at its
    /// end, on an error or on an interruption). `Duration::ZERO`: every step.
    pub interval: Duration,
}

/// Progress callback: return `ControlFlow::Break(())` to stop the run (its
/// finished steps are checkpointed first).
pub type ProgressFn<'a> = &'a (dyn Fn(Progress) -> ControlFlow<()> + Sync);

/// How to run (nothing here changes the results).
#[derive(Clone, Copy, Default)]
pub struct RunOptions<'a> {
    /// Number of contiguous chunks of the path solved in parallel (each
    /// cold-starts its first step). `None`: twice the threads of the
    /// current rayon pool.
    pub chunks: Option<usize>,
    /// Checkpoint and resume; `None` for none.
    pub checkpoint: Option<&'a CheckpointOptions>,
    /// Called after each step, from the worker threads.
    pub progress: Option<ProgressFn<'a>>,
}

/// The outputs of one step.
#[derive(Clone, Debug, PartialEq)]
pub struct StepRecord {
    /// Step index `k`.
    pub index: usize,
    /// Footprint centre `x_c` (m).
    pub position: f64,
    /// Time `t = x_c / V` (s).
    pub time: f64,
    /// Total contact force `Σ P_i` (N).
    pub total_force: f64,
    /// Approach `δ0` of the tread below the road's highest summit (m).
    pub approach: f64,
    /// Contact area `Σ π a_i²` of the local contacts (m²).
    pub contact_area: f64,
    /// Asperities in contact.
    pub contacts: usize,
    /// Asperities selected under the footprint (problem size).
    pub selected: usize,
    /// Newton iterations spent.
    pub iterations: usize,
    /// `s_boundary − δ0` (m): when positive, every asperity left out of the
    /// selection has a gap larger than the approach, so it would carry
    /// exactly zero and the truncation is exact. Infinite for a block.
    pub clearance: f64,
    /// Pairs of contacts whose patches overlap (radii sum over their
    /// spacing), where the model's point-force coupling does not hold
    /// (`tyreroad_multipoint::overlapping_contacts`).
    pub overlapping: usize,
    /// Force on each sensor (N), in the order of [`RollingConfig::sensors`].
    pub sensor_forces: Vec<f64>,
}

/// The result of a rolling run: one record per step, in path order.
#[derive(Clone, Debug, PartialEq)]
pub struct RollingResult {
    /// One record per step.
    pub steps: Vec<StepRecord>,
    /// Sampling rate `V/Δx` (Hz).
    pub sample_rate: f64,
    /// Steps loaded from a checkpoint instead of computed.
    pub resumed: usize,
    /// Hash of the inputs keying the checkpoint.
    pub input_hash: u64,
}

impl RollingResult {
    /// Times `t_k` (s).
    pub fn times(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.time).collect()
    }
    /// Total force signal (N).
    pub fn total_force(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.total_force).collect()
    }
    /// Approach signal (m).
    pub fn approach(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.approach).collect()
    }
    /// Contact-area signal (m²).
    pub fn contact_area(&self) -> Vec<f64> {
        self.steps.iter().map(|s| s.contact_area).collect()
    }
    /// Force signal of sensor `k` (N).
    pub fn sensor(&self, k: usize) -> Vec<f64> {
        self.steps
            .iter()
            .map(|s| s.sensor_forces.get(k).copied().unwrap_or(0.0))
            .collect()
    }
    /// The smallest truncation clearance over the run (m); see
    /// [`StepRecord::clearance`].
    pub fn min_clearance(&self) -> f64 {
        self.steps
            .iter()
            .map(|s| s.clearance)
            .fold(f64::INFINITY, f64::min)
    }
}

/// The selected asperity ids and the multipoint problem on them.
pub type StepProblem<'r, L> = (Vec<usize>, Problem<&'r L>);

/// The sub-problem of one footprint position: the selected asperity ids and
/// the multipoint problem on them (gaps `H_i = z_max − z_i + s(x_i − x_c,
/// y_i − y_c)`). `None` when nothing lies under the footprint.
pub fn step_problem<'r, L: ContactLaw>(
    road: &'r Road<L>,
    material: Material,
    config: &RollingConfig,
    position: f64,
) -> Result<Option<StepProblem<'r, L>>, RollingError> {
    let mut ids = Vec::new();
    select(road, config, position, &mut ids);
    if ids.is_empty() {
        return Ok(None);
    }
    let problem = build(road, material, config, position, &ids)?;
    Ok(Some((ids, problem)))
}

fn select<L>(road: &Road<L>, config: &RollingConfig, xc: f64, ids: &mut Vec<usize>) {
    let (hx, hy) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    let yc = config.lateral;
    road.window([xc - hx - m, xc + hx + m], [yc - hy - m, yc + hy + m], ids);
    if matches!(config.tread, Tread::Block { .. }) {
        let pos = road.positions();
        ids.retain(|&i| {
            config
                .tread
                .profile(pos[i][0] - xc, pos[i][1] - yc)
                .is_some()
        });
    }
}

fn build<'r, L: ContactLaw>(
    road: &'r Road<L>,
    material: Material,
    config: &RollingConfig,
    xc: f64,
    ids: &[usize],
) -> Result<Problem<&'r L>, RollingError> {
    let (pos, z, laws, top) = (road.positions(), road.heights(), road.laws(), road.top());
    let yc = config.lateral;
    let positions = ids.iter().map(|&i| pos[i]).collect();
    let gaps = ids
        .iter()
        .map(|&i| {
            top - z[i]
                + config
                    .tread
                    .profile(pos[i][0] - xc, pos[i][1] - yc)
                    .unwrap_or(f64::INFINITY)
        })
        .collect();
    let laws = ids.iter().map(|&i| &laws[i]).collect();
    Problem::new(positions, gaps, laws, material).map_err(|source| RollingError::Solve {
        position: xc,
        source,
    })
}

fn imposed<L>(road: &Road<L>, control: RollingControl) -> Control {
    match control {
        RollingControl::Load(w) => Control::Load(w),
        RollingControl::Approach(d) => Control::Approach(d),
        RollingControl::TreadHeight(h) => Control::Approach(road.top() - h),
    }
}

/// The state carried from one step to the next (warm start): forces by
/// asperity id (ids absent carry zero) and the approach.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Carry {
    pub ids: Vec<usize>,
    pub forces: Vec<f64>,
    pub approach: f64,
}

/// Per-chunk scratch: a dense id → force map for warm-start mapping.
struct Scratch {
    dense: Vec<f64>,
    ids: Vec<usize>,
}

fn solve_step<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    k: usize,
    carry: &mut Option<Carry>,
    scratch: &mut Scratch,
) -> Result<StepRecord, RollingError> {
    let xc = config.position(k);
    let control = imposed(road, config.control);
    let margin = config.tread.effective_margin(config.margin);
    let boundary = config.tread.boundary_profile(margin);
    select(road, config, xc, &mut scratch.ids);
    let empty = |approach: f64| StepRecord {
        index: k,
        position: xc,
        time: xc / config.speed,
        total_force: 0.0,
        approach,
        contact_area: 0.0,
        contacts: 0,
        selected: 0,
        iterations: 0,
        clearance: boundary - approach,
        overlapping: 0,
        sensor_forces: vec![0.0; config.sensors.len()],
    };
    if scratch.ids.is_empty() {
        *carry = None;
        return match control {
            Control::Approach(d) => Ok(empty(d)),
            // No load and no asperity: the approach is undefined (−∞).
            Control::Load(0.0) => Ok(empty(f64::NEG_INFINITY)),
            Control::Load(_) => Err(RollingError::NoSupport { position: xc }),
        };
    }
    let ids = std::mem::take(&mut scratch.ids);
    let problem = build(road, material, config, xc, &ids)?;
    // Warm start: previous forces mapped by asperity id, new ones at 0.
    let initial = carry.as_ref().map(|c| {
        for (&i, &p) in c.ids.iter().zip(&c.forces) {
            scratch.dense[i] = p;
        }
        let forces: Vec<f64> = ids.iter().map(|&i| scratch.dense[i]).collect();
        for &i in &c.ids {
            scratch.dense[i] = 0.0;
        }
        // Consistent local interpenetrations δ_i = δ0 − H_i − (T P)_i of the
        // mapped state (the solver may iterate on them).
        let mut u = vec![0.0; forces.len()];
        Boussinesq::new(problem.positions(), material.boussinesq_factor()).apply(
            &forces,
            &mut u,
            Par::Seq,
        );
        let depths = problem
            .gaps()
            .iter()
            .zip(&u)
            .map(|(h, u)| c.approach - h - u)
            .collect();
        Solution {
            depths,
            forces,
            approach: c.approach,
            iterations: 0,
            load_steps: 0,
            residual: 0.0,
        }
    });
    let options = SolverOptions {
        tolerance: config.tolerance,
        max_iterations: config.max_iterations,
        par: Par::Seq,
        ..SolverOptions::default()
    };
    let solution = solve_from(&problem, control, &options, initial.as_ref()).map_err(|source| {
        RollingError::Solve {
            position: xc,
            source,
        }
    })?;
    let contacts = solution.local_contacts(&problem);
    let pos = road.positions();
    let mut sensor_forces = vec![0.0; config.sensors.len()];
    let mut area = 0.0;
    for (a, (&i, &p)) in ids.iter().zip(&solution.forces).enumerate() {
        if p > 0.0 {
            area += contacts[a].area();
            for (f, s) in sensor_forces.iter_mut().zip(&config.sensors) {
                *f += s.share(pos[i], &contacts[a]);
            }
        }
    }
    let record = StepRecord {
        index: k,
        position: xc,
        time: xc / config.speed,
        total_force: solution.total_force(),
        approach: solution.approach,
        contact_area: area,
        contacts: solution.contact_count(),
        selected: ids.len(),
        iterations: solution.iterations,
        clearance: boundary - solution.approach,
        overlapping: overlapping_contacts(problem.positions(), &contacts).len(),
        sensor_forces,
    };
    *carry = Some(Carry {
        ids,
        forces: solution.forces,
        approach: solution.approach,
    });
    Ok(record)
}

/// Rolls the tread along the path: one static solve per step, warm started
/// within contiguous chunks, chunks in parallel on the current rayon pool.
///
/// With [`RunOptions::checkpoint`], finished steps are loaded from the
/// checkpoint files keyed by the inputs' hash and not recomputed, and each
/// chunk writes its finished steps atomically as it goes.
///
/// Errors: invalid configuration, a step that does not converge (with its
/// position), no asperity under a loaded footprint, a checkpoint that cannot
/// be read or written, or [`RollingError::Interrupted`] when the progress
/// callback asked to stop.
pub fn roll<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    options: &RunOptions<'_>,
) -> Result<RollingResult, RollingError> {
    config.validate()?;
    let total = config.steps();
    let hash = checkpoint::input_hash(road, &material, config);
    let mut done: Vec<Option<StepRecord>> = vec![None; total];
    let mut states = std::collections::HashMap::new();
    if let Some(ck) = options.checkpoint {
        let loaded = checkpoint::load(ck, hash, config.sensors.len())?;
        states = loaded.states;
        for r in loaded.records {
            if r.index < total {
                let slot = r.index;
                done[slot] = Some(r);
            }
        }
    }
    let resumed = done.iter().filter(|d| d.is_some()).count();
    let chunks = options
        .chunks
        .unwrap_or(2 * rayon::current_num_threads())
        .clamp(1, total);
    let bounds: Vec<(usize, usize)> = (0..chunks)
        .map(|c| (c * total / chunks, (c + 1) * total / chunks))
        .collect();
    let counter = AtomicUsize::new(resumed);
    let stop = AtomicBool::new(false);
    let outcomes: Vec<Result<Vec<StepRecord>, RollingError>> = bounds
        .par_iter()
        .map(|&(a, b)| {
            run_chunk(
                road,
                material,
                config,
                options,
                hash,
                (a, b),
                (&done[a..b], &states),
                (&counter, &stop),
                (total, resumed),
            )
        })
        .collect();
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
    (loaded, states): (
        &[Option<StepRecord>],
        &std::collections::HashMap<usize, Carry>,
    ),
    (counter, stop): (&AtomicUsize, &AtomicBool),
    (total, resumed): (usize, usize),
) -> Result<Vec<StepRecord>, RollingError> {
    let mut records: Vec<StepRecord> = Vec::with_capacity(b - a);
    let mut scratch = Scratch {
        dense: vec![0.0; road.len()],
        ids: Vec::new(),
    };
    let mut carry = None;
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
                carry.as_ref(),
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
            continue;
        }
        let record = match solve_step(road, material, config, k, &mut carry, &mut scratch) {
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
