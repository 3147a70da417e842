//! Viscoelastic rolling in the multipoint model: the path turned into time
//! (`Δt = Δx / V`), each asperity's memory kept by its road id.
//!
//! # Formulation (docs/viscoelastic.md, "Rolling")
//!
//! With `ν` constant, the tread's surface obeys `p = ∫ E(t−s) dw/ds ds` and
//! `u = K̃ w`, `K̃` the unit-modulus Boussinesq operator and `w_i` asperity
//! `i`'s elastic-equivalent force (the force a unit-modulus tread would carry
//! with the same displacements). Over a step the Prony recursion gives, per
//! asperity and branch,
//!
//! ```text
//! p_i = E_eff w_i + h_i,    E_eff = E∞ + Σ_k E_k γ_k,   h_i = Σ_k (e^{−Δt/τ_k} q_ik − E_k γ_k w_i,old)
//! q_ik ← e^{−Δt/τ_k} q_ik + E_k γ_k (w_i − w_i,old),     γ_k = τ_k/Δt (1 − e^{−Δt/τ_k})
//! ```
//!
//! The interpenetration of asperity `i` is `δ_i = δ0 − H_i − Σ_{j≠i} K̃_ij w_j`
//! and, in contact, `w_i = P_i^law(δ_i)/E_ref` (the law at the laws'
//! reference modulus, scaled to unit modulus). Substituting
//! `w_j = (p_j − h_j)/E_eff`:
//!
//! ```text
//! δ_i = δ0 − [H_i + Σ_{j≠i} T^eff_ij (−h_j)] − Σ_{j≠i} T^eff_ij p_j,   T^eff = (1 − ν²)/(π E_eff r)
//! p_i = max(0, (E_eff/E_ref) P_i^law(δ_i) + h_i)
//! ```
//!
//! an elastic multipoint problem of modulus `E_eff` whose gaps are raised
//! by the displacement of the memory (`h ≤ 0`) of every asperity of the
//! window that still has some, and whose laws are offset by `h_i`
//! ([`crate::rolling_law`]); complementarity holds on the real force
//! `p_i ≥ 0`. An asperity of the window out of contact keeps
//! `w_i = −h_i/E_eff`: its memory decays. One step costs one warm-started
//! elastic solve plus `O(N_window · N_memory + N_memory · branches)`.
//!
//! Which rubber remembers ([`TrailingMemory`]): the window (the tread's box
//! plus margin, the selection of every step) is where the tread touches the
//! road. By default an asperity is forgotten as the window leaves it: the
//! rubber lifts off with its memory, as the viscoelastic rolling BEM forgets
//! the cells that leave its window, so both models hold the same memory.
//! [`TrailingMemory::Kept`] is Hunter's half-space attached to the road:
//! every asperity passed keeps acting on the footprint through `1/r` until
//! its memory is below `fade` of the largest force seen; against the BEM it
//! carries a depression the BEM does not, which grows along the path
//! (docs/viscoelastic.md, "Where the growing error came from").
//!
//! Invariants: `h_i ≤ 0` and `w_i ≥ 0` (the recursion is exact for `w`
//! linear over a step, and `q_k ≤ E_k w` whenever `w ≥ 0`, so rounding is all
//! that is clipped); slow rolling (`Δt ≫ τ`) is the elastic run with `E∞`,
//! fast rolling (`Δt ≪ τ`) the elastic run with `E∞ + Σ E_k` once the
//! footprint has moved past where it started (tested, 0.5 %).
//!
//! How the run starts ([`ViscoStart`]): by default the tread meets the road
//! at the first step with no history ([`ViscoStart::Fresh`]: the first step
//! is an ordinary step of `Δt` from rest), so both limits hold from the
//! first step. [`ViscoStart::Relaxed`] is a tread that has stood still at
//! the first position long enough to relax: the first step is the elastic
//! solve with `E∞`, every branch relaxed (`q = 0`, `w = p/E∞`); the
//! footprint's first asperities then stay softer until they leave it (and
//! with [`TrailingMemory::Kept`], under fast rolling, their depression
//! stays frozen behind the tread). Either
//! way the start is a transient about one footprint length long
//! ([`ViscoRolling::transient_steps`]).
//!
//! Within a patch ([`ViscoRollOptions::receding`]): with
//! [`Receding::Ting`] (the default, as in static histories) each
//! asperity's law is cut into depth bands with their own memory
//! ([`crate::ting`]), `p_i` and `w_i` are the band sums and `h_i` their
//! memories', the rest of the step unchanged; with [`Receding::LeeRadok`],
//! `w_i = P^law(δ_i)/E_ref` is Lee–Radok's replacement, which holds while
//! the patch grows, and a patch that shrinks while still touching (the
//! trailing edge) keeps it, so it over-relaxes and lifts off early there
//! (docs/viscoelastic.md, "Rolling against the viscoelastic BEM": Ting is
//! closer to the BEM on every measured row). Shrinking patches are
//! counted either way ([`ViscoRolling::receding`]). Between asperities the
//! complementarity is exact: an asperity whose memory keeps the tread away
//! simply carries nothing.

use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::{
    Control, PairCorrection, Par, Problem, SolveError, SolverOptions, solve_from,
};
use tyreroad_rolling::{
    KeptCoupling, Progress, ProgressFn, Road, RollingConfig, RollingControl, RollingError,
    RollingResult, StepCoupling, StepRecord, step_problem,
};

use crate::history::step_coefficients;
use crate::rolling_law::{MemoryLaw, StepLaw};
use crate::ting::{BandLaw, Bands};
use crate::{Prony, Receding, ViscoError};

#[path = "rolling_coupled.rs"]
mod coupled;
#[path = "rolling_record.rs"]
mod record;
pub use coupled::roll_viscoelastic_coupled;
use record::warm_start;

/// Default memory threshold: with [`TrailingMemory::Kept`], an asperity
/// behind the footprint is forgotten once its memory is below this fraction
/// of the largest force seen.
pub const DEFAULT_FADE: f64 = 1e-9;

/// The tread's state before the first step.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ViscoStart {
    /// No history: the tread meets the road during the first step.
    #[default]
    Fresh,
    /// Relaxed: the tread has stood at the first position for long; the
    /// first step is the elastic solve with `E∞`.
    Relaxed,
}

/// What becomes of an asperity's memory once the footprint window (the
/// tread's box plus margin, the selection of every step) has passed it.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum TrailingMemory {
    /// The rubber lifts off the road at the trailing edge of the window and
    /// takes its memory with it: the asperity is forgotten as it leaves the
    /// window, as the viscoelastic rolling BEM forgets the cells that leave
    /// its window (docs/viscoelastic.md, "Where the memory lives").
    #[default]
    LiftsOff,
    /// Hunter's idealisation: the half-space stays attached to the road
    /// behind the footprint, so the recovering depression of every asperity
    /// passed acts on the footprint through `1/r` until it fades.
    Kept,
}

/// How to run a viscoelastic rolling run (the run itself is sequential
/// along the path: each step needs the previous one's memory).
#[derive(Clone, Copy)]
pub struct ViscoRollOptions<'a> {
    /// Memory threshold, relative to the largest asperity force seen, below
    /// which an asperity out of the footprint is forgotten under
    /// [`TrailingMemory::Kept`] (`[0, 1)`; default [`DEFAULT_FADE`]).
    pub fade: f64,
    /// The state before the first step (default [`ViscoStart::Fresh`]).
    pub start: ViscoStart,
    /// The memory of the asperities the window has passed (default
    /// [`TrailingMemory::LiftsOff`]).
    pub trailing: TrailingMemory,
    /// Called after each step; `ControlFlow::Break(())` stops the run with
    /// [`RollingError::Interrupted`].
    pub progress: Option<ProgressFn<'a>>,
    /// How a patch that shrinks while touching is treated (default
    /// Ting's depth bands, [`Receding::default`]).
    pub receding: Receding,
}

impl Default for ViscoRollOptions<'_> {
    fn default() -> Self {
        Self {
            fade: DEFAULT_FADE,
            start: ViscoStart::Fresh,
            trailing: TrailingMemory::LiftsOff,
            progress: None,
            receding: Receding::default(),
        }
    }
}

/// A viscoelastic rolling run: the records in the elastic run's form, and
/// what only the viscoelastic run knows.
#[derive(Clone, Debug, PartialEq)]
pub struct ViscoRolling {
    /// One record per step, as [`tyreroad_rolling::roll`] gives them (no
    /// checkpoint: `resumed` is 0).
    pub result: RollingResult,
    /// Per step: asperities in contact whose elastic-equivalent force fell
    /// (a shrinking patch, where Lee–Radok is the documented approximation).
    pub receding: Vec<usize>,
    /// Per step: asperities carrying memory after the step (in the window;
    /// behind it too under [`TrailingMemory::Kept`]).
    pub memory: Vec<usize>,
    /// Steps from the start until the footprint has left its first position
    /// (its length plus twice the margin): those steps still hold asperities
    /// loaded at the start ([`ViscoStart`]).
    pub transient_steps: usize,
}

/// Rolls the viscoelastic tread `tread` along the path of `config` on
/// `road`, whose laws were built with the elastic reference material
/// `reference` (its Young's modulus is divided out; its Poisson's ratio must
/// be the tread's). Time is `t = x / V` with `config.speed`.
///
/// # Errors
/// [`ViscoError::InvalidValue`] for a Poisson's ratio that differs or a
/// fade outside `[0, 1)`; [`ViscoError::Rolling`] for an invalid
/// configuration, no asperity under a loaded footprint, or an interrupted
/// run; [`ViscoError::Solve`] for a malformed step problem. A step whose
/// solve does not converge is recorded as failed (NaN values) and the run
/// goes on, its asperities' memory held.
pub fn roll_viscoelastic<L: ContactLaw + Sync>(
    road: &Road<L>,
    reference: Material,
    tread: &Prony,
    config: &RollingConfig,
    options: &ViscoRollOptions<'_>,
) -> Result<ViscoRolling, ViscoError> {
    roll_with(road, reference, tread, config, options, None)
}

/// [`roll_viscoelastic`], each step under `coupling` when given
/// ([`roll_viscoelastic_coupled`]).
fn roll_with<L: ContactLaw + Sync>(
    road: &Road<L>,
    reference: Material,
    tread: &Prony,
    config: &RollingConfig,
    options: &ViscoRollOptions<'_>,
    coupling: Option<&dyn StepCoupling<L>>,
) -> Result<ViscoRolling, ViscoError> {
    config
        .validate()
        .map_err(|source| ViscoError::Rolling { source })?;
    if (reference.poisson_ratio() - tread.poisson_ratio()).abs() > 1e-12 {
        return Err(ViscoError::InvalidValue {
            name: "road laws' Poisson's ratio",
            value: reference.poisson_ratio(),
            expected: "equal to the viscoelastic tread's",
        });
    }
    options.receding.check()?;
    if !(options.fade.is_finite() && (0.0..1.0).contains(&options.fade)) {
        return Err(ViscoError::InvalidValue {
            name: "memory fade threshold",
            value: options.fade,
            expected: "in [0, 1)",
        });
    }
    let mut run = Runner::new(road, reference, tread, config, options, coupling);
    let total = config.steps();
    let mut steps = Vec::with_capacity(total);
    let mut receding = Vec::with_capacity(total);
    let mut memory = Vec::with_capacity(total);
    for k in 0..total {
        let (record, shrinking) = run.step(k)?;
        steps.push(record);
        receding.push(shrinking);
        memory.push(run.active.len());
        if let Some(progress) = options.progress {
            let done = k + 1;
            let report = Progress {
                done,
                total,
                resumed: 0,
            };
            if progress(report).is_break() {
                return Err(ViscoError::Rolling {
                    source: RollingError::Interrupted { done, total },
                });
            }
        }
    }
    let (hx, _) = config.tread.half_extents();
    let span = 2.0 * (hx + config.tread.effective_margin(config.margin));
    Ok(ViscoRolling {
        result: RollingResult {
            steps,
            sample_rate: config.sample_rate(),
            resumed: 0,
            input_hash: 0,
        },
        receding,
        memory,
        transient_steps: ((span / config.step).ceil() as usize).min(total),
    })
}

/// The state carried along the path.
struct Runner<'r, L> {
    road: &'r Road<L>,
    reference: Material,
    tread: &'r Prony,
    config: &'r RollingConfig,
    fade: f64,
    relaxed_start: bool,
    trailing: TrailingMemory,
    branches: usize,
    /// `w_i` per road id (m², force per unit modulus).
    unit: Vec<f64>,
    /// `q_ik` per road id and branch (N).
    branch: Vec<f64>,
    /// Road ids with memory, and a flag per id.
    active: Vec<usize>,
    is_active: Vec<bool>,
    /// `h_i` of the current step per road id (zero off `active`).
    history: Vec<f64>,
    /// Warm start: the previous step's ids, forces and approach.
    carry: Option<(Vec<usize>, Vec<f64>, f64)>,
    /// Scratch: id → force map for the warm start.
    dense: Vec<f64>,
    /// Largest asperity force seen (N), the scale of `fade`.
    largest: f64,
    /// Ting's bands per decade (`None`: Lee–Radok).
    per_decade: Option<usize>,
    /// Per road id, its depth bands (Ting only).
    bands: Vec<Bands>,
    /// The caller's pair correction of each step ([`roll_viscoelastic_coupled`]).
    coupling: Option<&'r dyn StepCoupling<L>>,
    /// The previous step's coupling by road ids, at the laws' reference
    /// modulus: the next step's warm start (empty after a failed step).
    kept: KeptCoupling,
    /// Scratch: road id → index in the step (`usize::MAX` elsewhere).
    index: Vec<usize>,
}

impl<'r, L: ContactLaw + Sync> Runner<'r, L> {
    fn new(
        road: &'r Road<L>,
        reference: Material,
        tread: &'r Prony,
        config: &'r RollingConfig,
        options: &ViscoRollOptions<'_>,
        coupling: Option<&'r dyn StepCoupling<L>>,
    ) -> Self {
        let n = road.len();
        let branches = tread.branches().len();
        Self {
            road,
            reference,
            tread,
            config,
            fade: options.fade,
            relaxed_start: options.start == ViscoStart::Relaxed,
            trailing: options.trailing,
            branches,
            unit: vec![0.0; n],
            branch: vec![0.0; n * branches],
            active: Vec::new(),
            is_active: vec![false; n],
            history: vec![0.0; n],
            carry: None,
            dense: vec![0.0; n],
            largest: 0.0,
            per_decade: match options.receding {
                Receding::LeeRadok => None,
                Receding::Ting { per_decade } => Some(per_decade),
            },
            bands: match options.receding {
                Receding::LeeRadok => Vec::new(),
                Receding::Ting { .. } => vec![Bands::default(); n],
            },
            coupling,
            kept: KeptCoupling::default(),
            index: vec![usize::MAX; n],
        }
    }

    /// Solves step `k`; returns its record and its count of shrinking
    /// patches.
    fn step(&mut self, k: usize) -> Result<(StepRecord, usize), ViscoError> {
        let config = self.config;
        let xc = config.position(k);
        let time = xc / config.speed;
        // A relaxed standing start: step 0 with E∞ and no memory (every
        // branch's decay and weight zero).
        let relaxed = k == 0 && self.relaxed_start;
        let coefficients = if relaxed {
            vec![(0.0, 0.0); self.branches]
        } else {
            step_coefficients(self.tread, config.step / config.speed)
        };
        let effective = self.tread.long_term() + coefficients.iter().map(|c| c.1).sum::<f64>();
        for &i in &self.active {
            if let Some(bands) = self.bands.get_mut(i) {
                bands.prepare(&coefficients);
                bands.touching_depths(effective);
                self.history[i] = bands.history_total().min(0.0);
                continue;
            }
            let h: f64 = coefficients
                .iter()
                .enumerate()
                .map(|(b, (decay, weight))| {
                    decay * self.branch[i * self.branches + b] - weight * self.unit[i]
                })
                .sum();
            // h ≤ 0 while w ≥ 0 (module docs): only rounding is clipped.
            self.history[i] = h.min(0.0);
        }
        let material = self.tread.elastic(effective)?;
        let solve_error = |source| ViscoError::Solve {
            step: k,
            time,
            source,
        };
        let control = match config.control {
            RollingControl::Load(w) => Control::Load(w),
            RollingControl::Approach(d) => Control::Approach(d),
            RollingControl::TreadHeight(h) => Control::Approach(self.road.top() - h),
        };
        let boundary = config
            .tread
            .boundary_profile(config.tread.effective_margin(config.margin));
        let Some((ids, elastic)) = step_problem(self.road, self.reference, config, xc)
            .map_err(|source| ViscoError::Rolling { source })?
        else {
            let approach = match control {
                Control::Approach(d) => d,
                Control::Load(0.0) => f64::NEG_INFINITY,
                Control::Load(_) => {
                    return Err(ViscoError::Rolling {
                        source: RollingError::NoSupport { position: xc },
                    });
                }
            };
            self.carry = None;
            self.kept.clear();
            self.remember(&[], &[], &[], effective, &coefficients, relaxed);
            return Ok((self.empty_record(k, approach, boundary), 0));
        };
        if let Some(coupling) = self.coupling {
            let step = coupled::Step {
                k,
                material,
                effective,
                coefficients: &coefficients,
                relaxed,
                control,
                boundary,
            };
            return self.coupled_step(coupling, ids, &elastic, &step);
        }
        let mut dense = std::mem::take(&mut self.dense);
        let problem = self
            .memory_problem(&ids, &elastic, material, effective)
            .map_err(solve_error)?;
        let initial = warm_start(
            self.carry.as_ref(),
            &mut dense,
            &ids,
            &problem,
            &PairCorrection::default(),
        );
        let options = SolverOptions {
            tolerance: config.tolerance,
            max_iterations: config.max_iterations,
            par: Par::Seq,
            ..SolverOptions::default()
        };
        let solution = match solve_from(&problem, control, &options, initial.as_ref()) {
            Ok(solution) => solution,
            Err(SolveError::NotConverged {
                iterations,
                residual,
                ..
            }) => {
                // That step's failure, not the run's: its forces are
                // unknown, so every memory is held (no increment) and the
                // next step cold-starts.
                drop(problem);
                self.dense = dense;
                self.carry = None;
                self.hold(&coefficients, relaxed);
                return Ok((self.failed_record(k, ids.len(), iterations, residual), 0));
            }
            Err(source) => return Err(solve_error(source)),
        };
        let summits: Vec<[f64; 2]> = ids.iter().map(|&i| self.road.positions()[i]).collect();
        let record = self.record(k, (&ids, &summits), &problem, &solution, boundary, None);
        drop(problem);
        self.dense = dense;
        let shrinking = self.remember(
            &ids,
            &solution.forces,
            &solution.depths,
            effective,
            &coefficients,
            relaxed,
        );
        self.carry = Some((ids, solution.forces, solution.approach));
        Ok((record, shrinking))
    }

    /// The step's problem: gaps raised by the memory's displacement, laws
    /// offset by each asperity's memory, modulus `E_eff`.
    fn memory_problem<'p>(
        &'p self,
        ids: &[usize],
        elastic: &Problem<&'p L>,
        material: Material,
        effective: f64,
    ) -> Result<Problem<StepLaw<'p, L>>, SolveError>
    where
        'r: 'p,
    {
        let factor = material.boussinesq_factor();
        let pos = self.road.positions();
        let gaps = ids
            .iter()
            .zip(elastic.gaps())
            .map(|(&i, &h)| {
                let raised: f64 = self
                    .active
                    .iter()
                    .filter(|&&j| j != i)
                    .map(|&j| {
                        let (dx, dy) = (pos[i][0] - pos[j][0], pos[i][1] - pos[j][1]);
                        -self.history[j] / dx.hypot(dy)
                    })
                    .sum();
                h + factor * raised
            })
            .collect();
        let laws = self.step_laws(ids, elastic.laws(), effective);
        Problem::new(elastic.positions().to_vec(), gaps, laws, material)
    }

    /// Each asperity's law of the step: Lee–Radok's offset law or Ting's
    /// bands, at the step's effective modulus.
    fn step_laws<'p>(
        &'p self,
        ids: &[usize],
        inner: &[&'p L],
        effective: f64,
    ) -> Vec<StepLaw<'p, L>> {
        let scale = effective / self.reference.youngs_modulus();
        let reference = self.reference.youngs_modulus();
        ids.iter()
            .zip(inner)
            .map(|(&i, &inner)| match self.bands.get(i) {
                Some(bands) => StepLaw::Ting(BandLaw {
                    inner,
                    reference,
                    effective,
                    bands,
                }),
                None => StepLaw::LeeRadok(MemoryLaw {
                    inner,
                    scale,
                    offset: self.history[i],
                }),
            })
            .collect()
    }

    /// Advances every memory over the step: asperities of the footprint with
    /// their solved forces, the others at `p = 0`. Returns the shrinking
    /// patches; forgets the asperities the window has left
    /// ([`TrailingMemory::LiftsOff`]) or, when kept, whose memory has faded.
    fn remember(
        &mut self,
        ids: &[usize],
        forces: &[f64],
        depths: &[f64],
        effective: f64,
        coefficients: &[(f64, f64)],
        relaxed: bool,
    ) -> usize {
        let mut shrinking = 0;
        let mut in_window = std::mem::take(&mut self.dense);
        for ((&i, &p), &depth) in ids.iter().zip(forces).zip(depths) {
            // Marks the footprint (force + 1 > 0 even for p = 0).
            in_window[i] = p + 1.0;
            self.largest = self.largest.max(p);
            let w = match self.ting_advance(i, depth, effective, coefficients) {
                Some(w) => w,
                None => (p - self.history[i]) / effective,
            };
            if p > 0.0 && w < self.unit[i] * (1.0 - 1e-9) {
                shrinking += 1;
            }
            if w > 0.0 && !self.is_active[i] {
                self.is_active[i] = true;
                self.active.push(i);
            }
            self.advance(i, w, coefficients, relaxed);
        }
        let instantaneous = self.tread.instantaneous();
        let threshold = self.fade * self.largest;
        let mut kept = Vec::with_capacity(self.active.len());
        for &i in &std::mem::take(&mut self.active) {
            if in_window[i] == 0.0 {
                // Out of the footprint nothing touches (depth 0: no band).
                let w = self
                    .ting_advance(i, 0.0, effective, coefficients)
                    .unwrap_or(-self.history[i] / effective);
                self.advance(i, w, coefficients, relaxed);
            }
            let q: f64 = (0..self.branches)
                .map(|b| self.branch[i * self.branches + b].abs())
                .sum();
            let faded = instantaneous * self.unit[i] + q <= threshold;
            let lifted = self.trailing == TrailingMemory::LiftsOff;
            if (faded || lifted) && in_window[i] == 0.0 {
                self.forget(i);
            } else {
                kept.push(i);
            }
        }
        self.active = kept;
        for &i in ids {
            in_window[i] = 0.0;
        }
        self.dense = in_window;
        shrinking
    }

    /// Under Ting's treatment, advances asperity `i`'s bands at
    /// interpenetration `depth` and returns its new `w_i`; `None` under
    /// Lee–Radok.
    fn ting_advance(
        &mut self,
        i: usize,
        depth: f64,
        effective: f64,
        coefficients: &[(f64, f64)],
    ) -> Option<f64> {
        let per_decade = self.per_decade?;
        let bands = self.bands.get_mut(i)?;
        bands.advance(
            depth,
            &self.road.laws()[i],
            self.reference.youngs_modulus(),
            effective,
            coefficients,
            per_decade,
        );
        Some(bands.unit_total())
    }

    /// Sets `w_i` and advances its branches (`q = 0` at the relaxed start).
    fn advance(&mut self, i: usize, w: f64, coefficients: &[(f64, f64)], relaxed: bool) {
        let old = self.unit[i];
        let branches = &mut self.branch[i * self.branches..(i + 1) * self.branches];
        if relaxed {
            branches.fill(0.0);
        } else {
            for (q, (decay, weight)) in branches.iter_mut().zip(coefficients) {
                *q = decay * *q + weight * (w - old);
            }
        }
        self.unit[i] = w;
    }

    /// A failed step: every `w` held, the branches relax.
    fn hold(&mut self, coefficients: &[(f64, f64)], relaxed: bool) {
        for a in 0..self.active.len() {
            let i = self.active[a];
            if let Some(bands) = self.bands.get_mut(i) {
                bands.hold(coefficients);
            }
            let w = self.unit[i];
            self.advance(i, w, coefficients, relaxed);
        }
    }

    fn forget(&mut self, i: usize) {
        if let Some(bands) = self.bands.get_mut(i) {
            *bands = Bands::default();
        }
        self.unit[i] = 0.0;
        self.history[i] = 0.0;
        self.is_active[i] = false;
        for b in 0..self.branches {
            self.branch[i * self.branches + b] = 0.0;
        }
    }
}
