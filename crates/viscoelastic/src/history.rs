//! The hereditary multipoint solve: internal variables per Maxwell branch so
//! each time step costs one elastic multipoint solve.
//!
//! # Derivation
//!
//! With `ν` constant, every elastic multipoint solution at a given approach
//! is `E` times a unit-modulus one: the laws scale as `E*`, the Boussinesq
//! coefficients as `1/E*`, so the interpenetrations do not depend on `E`.
//! Let `f_i(δ0)` be asperity `i`'s force per unit modulus (m²). While every
//! contact grows, the Lee–Radok argument applies to the whole linear
//! half-space (its contact set only grows, so the elastic solution at each
//! instant is valid with the modulus replaced by the hereditary operator):
//! `P_i(t) = ∫_0^t E(t − s) df_i/ds ds`. With `f_i` linear in time over a
//! step `Δt`, the branch integral `q_ik = ∫ E_k e^{−(t−s)/τ_k} df_i` obeys
//! exactly
//!
//! ```text
//! q_ik,n+1 = e^{−Δt/τ_k} q_ik,n + E_k γ_k (f_i,n+1 − f_i,n),
//! γ_k = τ_k/Δt (1 − e^{−Δt/τ_k}),
//! P_i,n+1 = E∞ f_i,n+1 + Σ_k q_ik,n+1 = E_eff f_i,n+1 + h_i,
//! E_eff = E∞ + Σ_k E_k γ_k,   h_i = Σ_k (e^{−Δt/τ_k} q_ik,n − E_k γ_k f_i,n).
//! ```
//!
//! Under approach control `f_n+1 = f(δ0_n+1)` is one elastic solve. Under
//! load control `Σ P_i = W` gives `Σ f_i(δ0) = (W − Σ h_i)/E_eff`: one
//! load-controlled elastic solve, and every asperity's force comes from the
//! same `δ0`, so the per-asperity split is consistent with the elastic
//! coupling (not only the total).
//!
//! # Receding contacts
//!
//! When an asperity's unit force decreases (unloading, the trailing edge in
//! rolling) Lee–Radok no longer holds: Ting (1966) makes the force depend on
//! the history of the contact radius. [`Receding`] chooses the treatment:
//!
//! - [`Receding::Ting`] (the default) cuts each asperity's law into depth
//!   bands of independent springs with their own branch variables
//!   ([`crate::ting`], the method of dimensionality reduction). A band leaves
//!   contact when its force would turn negative and recovers on its own.
//!   Each step is then one elastic multipoint problem of modulus `E_eff`
//!   whose gaps are raised by the memory's displacement
//!   (`H_i + Σ_{j≠i} T^eff_ij (−h_j)`, `h_j = Σ_b h_jb ≤ 0`) and whose laws
//!   are the band sums: the solver's own Newton settles which bands touch,
//!   so a step that does not settle is that step's [`ViscoError::Solve`].
//!   While every band stays in contact this is the Lee–Radok recursion term
//!   by term.
//! - [`Receding::LeeRadok`] applies the recursion above to the whole force,
//!   also while it recedes: it over-relaxes near separation, and a load
//!   that the relaxing history alone already exceeds is refused with
//!   [`ViscoError::Separation`].
//!
//! Either way every step counts the asperities whose elastic-equivalent
//! force fell ([`ViscoStep::receding`]).

use tyreroad_contact_law::ContactLaw;
use tyreroad_multipoint::{Boussinesq, Control, Par, Problem, Solution, SolverOptions, solve_from};

use crate::error::{non_negative, positive};
use crate::ting::{BandLaw, Bands, Receding};
use crate::{Prony, ViscoError};

/// One step of a hereditary solve.
#[derive(Clone, Debug, PartialEq)]
pub struct ViscoStep {
    /// Time at the end of the step (s).
    pub time: f64,
    /// Rigid approach of the tread `δ0` (m).
    pub approach: f64,
    /// Asperity forces (N).
    pub forces: Vec<f64>,
    /// Asperities whose elastic-equivalent force decreased over the step:
    /// receding patches (Lee–Radok's recursion is then an approximation;
    /// [`Receding::Ting`] treats them).
    pub receding: usize,
}

impl ViscoStep {
    /// Total force (N).
    pub fn total_force(&self) -> f64 {
        self.forces.iter().sum()
    }
}

/// The hereditary multipoint solver: a problem whose laws were built with an
/// elastic reference material, the viscoelastic material and the internal
/// variables (per asperity, per branch).
pub struct Hereditary<'a, L> {
    problem: &'a Problem<L>,
    material: Prony,
    options: SolverOptions,
    reference_modulus: f64,
    time: f64,
    step: usize,
    /// `f_i,n` (m²).
    unit_forces: Vec<f64>,
    /// `q_ik,n` (N), asperity-major (Lee–Radok only).
    branch_forces: Vec<f64>,
    previous: Option<Solution>,
    receding: Receding,
    /// Per asperity, its depth bands (Ting only).
    bands: Vec<Bands>,
}

impl<'a, L: ContactLaw + Sync> Hereditary<'a, L> {
    /// A solver at rest (no contact, no history) at time 0 with the default
    /// treatment of receding contacts ([`Receding::default`]). `problem`'s
    /// laws and material are any elastic reference (its Young's modulus is
    /// divided out); its Poisson's ratio must be the material's.
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] when the Poisson's ratios differ.
    pub fn new(
        problem: &'a Problem<L>,
        material: Prony,
        options: SolverOptions,
    ) -> Result<Self, ViscoError> {
        Self::with_receding(problem, material, options, Receding::default())
    }

    /// As [`Hereditary::new`], with the treatment of receding contacts
    /// `receding`.
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] when the Poisson's ratios differ or for a
    /// band count out of range ([`Receding::check`]).
    pub fn with_receding(
        problem: &'a Problem<L>,
        material: Prony,
        options: SolverOptions,
        receding: Receding,
    ) -> Result<Self, ViscoError> {
        let receding = receding.check()?;
        let nu = problem.material().poisson_ratio();
        if (nu - material.poisson_ratio()).abs() > 1e-12 {
            return Err(ViscoError::InvalidValue {
                name: "problem's Poisson's ratio",
                value: nu,
                expected: "equal to the viscoelastic material's",
            });
        }
        let n = problem.len();
        let branches = material.branches().len();
        Ok(Self {
            problem,
            reference_modulus: problem.material().youngs_modulus(),
            material,
            options,
            time: 0.0,
            step: 0,
            unit_forces: vec![0.0; n],
            branch_forces: vec![0.0; n * branches],
            previous: None,
            receding,
            bands: match receding {
                Receding::LeeRadok => Vec::new(),
                Receding::Ting { .. } => vec![Bands::default(); n],
            },
        })
    }

    /// The treatment of receding contacts.
    pub fn receding(&self) -> Receding {
        self.receding
    }

    /// Time reached (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Advances by `dt` (s) to the total load `load` (N).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for `dt ≤ 0` or a negative load,
    /// [`ViscoError::Separation`] (Lee–Radok only), [`ViscoError::Solve`].
    pub fn step_load(&mut self, dt: f64, load: f64) -> Result<ViscoStep, ViscoError> {
        positive("time step (s)", dt)?;
        non_negative("load (N)", load)?;
        if let Receding::Ting { per_decade } = self.receding {
            return self.advance_ting(dt, Control::Load(load), per_decade);
        }
        let (effective, history) = self.history(dt);
        let total_history: f64 = history.iter().sum();
        let target = (load - total_history) / effective;
        if !(target > 0.0) {
            return Err(ViscoError::Separation {
                step: self.step,
                time: self.time + dt,
                load,
                history: total_history,
            });
        }
        let control = Control::Load(target * self.reference_modulus);
        self.advance(dt, control, effective, &history)
    }

    /// Advances by `dt` (s) to the rigid approach `approach` (m).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for `dt ≤ 0` or a non-finite approach,
    /// [`ViscoError::Solve`].
    pub fn step_approach(&mut self, dt: f64, approach: f64) -> Result<ViscoStep, ViscoError> {
        positive("time step (s)", dt)?;
        if !approach.is_finite() {
            return Err(ViscoError::InvalidValue {
                name: "approach (m)",
                value: approach,
                expected: "finite",
            });
        }
        if let Receding::Ting { per_decade } = self.receding {
            return self.advance_ting(dt, Control::Approach(approach), per_decade);
        }
        let (effective, history) = self.history(dt);
        self.advance(dt, Control::Approach(approach), effective, &history)
    }

    /// One step under Ting's treatment: the elastic problem of modulus
    /// `E_eff` on the gaps raised by the memory, with the band laws
    /// (module docs), then every band advanced at its asperity's solved
    /// interpenetration.
    fn advance_ting(
        &mut self,
        dt: f64,
        control: Control,
        per_decade: usize,
    ) -> Result<ViscoStep, ViscoError> {
        let time = self.time + dt;
        let solve_error = |step, source| ViscoError::Solve { step, time, source };
        let coefficients = step_coefficients(&self.material, dt);
        let effective = self.material.long_term() + coefficients.iter().map(|c| c.1).sum::<f64>();
        for bands in &mut self.bands {
            bands.prepare(&coefficients);
            bands.touching_depths(effective);
        }
        let material = self.material.elastic(effective)?;
        let positions = self.problem.positions();
        let coupling = Boussinesq::new(positions, material.boussinesq_factor());
        // The memory (h ≤ 0) displaces the surface as a force −h would.
        let memory: Vec<f64> = self.bands.iter().map(|b| -b.history_total()).collect();
        let mut raise = vec![0.0; memory.len()];
        coupling.apply(&memory, &mut raise, Par::Seq);
        let gaps: Vec<f64> = self
            .problem
            .gaps()
            .iter()
            .zip(&raise)
            .map(|(h, r)| h + r)
            .collect();
        let initial = self.previous.as_ref().map(|s| {
            let mut u = vec![0.0; s.forces.len()];
            coupling.apply(&s.forces, &mut u, Par::Seq);
            let depths = gaps
                .iter()
                .zip(&u)
                .map(|(h, u)| s.approach - h - u)
                .collect();
            Solution::warm_start(s.forces.clone(), depths, s.approach)
        });
        let laws = self
            .problem
            .laws()
            .iter()
            .zip(&self.bands)
            .map(|(inner, bands)| BandLaw {
                inner,
                reference: self.reference_modulus,
                effective,
                bands,
            })
            .collect();
        let step_problem = Problem::new(positions.to_vec(), gaps, laws, material)
            .map_err(|e| solve_error(self.step, e))?;
        let solution = solve_from(&step_problem, control, &self.options, initial.as_ref())
            .map_err(|e| solve_error(self.step, e))?;
        drop(step_problem);
        let mut receding = 0;
        for (i, bands) in self.bands.iter_mut().enumerate() {
            let old = bands.unit_total();
            bands.advance(
                solution.depths[i],
                &self.problem.laws()[i],
                self.reference_modulus,
                effective,
                &coefficients,
                per_decade,
            );
            let unit = bands.unit_total();
            if unit < old * (1.0 - 1e-9) {
                receding += 1;
            }
            self.unit_forces[i] = unit;
        }
        self.time = time;
        self.step += 1;
        let step = ViscoStep {
            time,
            approach: solution.approach,
            forces: solution.forces.clone(),
            receding,
        };
        self.previous = Some(solution);
        Ok(step)
    }

    /// `E_eff` and every asperity's `h_i` for a step of `dt`.
    fn history(&self, dt: f64) -> (f64, Vec<f64>) {
        let coefficients = step_coefficients(&self.material, dt);
        let effective = self.material.long_term() + coefficients.iter().map(|c| c.1).sum::<f64>();
        let branches = coefficients.len();
        let history = (0..self.unit_forces.len())
            .map(|i| {
                coefficients
                    .iter()
                    .enumerate()
                    .map(|(k, (decay, weight))| {
                        decay * self.branch_forces[i * branches + k] - weight * self.unit_forces[i]
                    })
                    .sum()
            })
            .collect();
        (effective, history)
    }

    fn advance(
        &mut self,
        dt: f64,
        control: Control,
        effective: f64,
        history: &[f64],
    ) -> Result<ViscoStep, ViscoError> {
        let time = self.time + dt;
        let solution = solve_from(self.problem, control, &self.options, self.previous.as_ref())
            .map_err(|source| ViscoError::Solve {
                step: self.step,
                time,
                source,
            })?;
        let coefficients = step_coefficients(&self.material, dt);
        let branches = coefficients.len();
        let mut receding = 0;
        let mut forces = Vec::with_capacity(history.len());
        for (i, h) in history.iter().enumerate() {
            let unit = solution.forces[i] / self.reference_modulus;
            let old = self.unit_forces[i];
            // Rounding-level decreases of a held contact are not recession.
            if unit < old * (1.0 - 1e-9) {
                receding += 1;
            }
            for (k, (decay, weight)) in coefficients.iter().enumerate() {
                let q = &mut self.branch_forces[i * branches + k];
                *q = decay * *q + weight * (unit - old);
            }
            self.unit_forces[i] = unit;
            forces.push(effective * unit + h);
        }
        self.time = time;
        self.step += 1;
        let approach = solution.approach;
        self.previous = Some(solution);
        Ok(ViscoStep {
            time,
            approach,
            forces,
            receding,
        })
    }
}

/// `(e^{−Δt/τ_k}, E_k γ_k)` per branch; `γ` through `expm1` so very short
/// steps keep their digits (`γ → 1`).
pub(crate) fn step_coefficients(material: &Prony, dt: f64) -> Vec<(f64, f64)> {
    material
        .branches()
        .iter()
        .map(|b| {
            let r = dt / b.relaxation_time;
            ((-r).exp(), b.modulus * (-(-r).exp_m1()) / r)
        })
        .collect()
}

/// A load history sampled as `(time (s), load (N))` points: a ramp from 0
/// to `peak` over `ramp` seconds, a hold of `hold` seconds and an unloading
/// ramp back to `floor` over `ramp` seconds, `steps` samples per segment
/// (time 0 excluded).
pub fn ramp_hold_unload(
    peak: f64,
    floor: f64,
    ramp: f64,
    hold: f64,
    steps: usize,
) -> Vec<(f64, f64)> {
    let mut samples = Vec::with_capacity(3 * steps);
    let n = steps.max(1) as f64;
    for j in 1..=steps.max(1) {
        let s = j as f64 / n;
        samples.push((s * ramp, s * peak));
    }
    for j in 1..=steps.max(1) {
        samples.push((ramp + j as f64 / n * hold, peak));
    }
    for j in 1..=steps.max(1) {
        let s = j as f64 / n;
        samples.push((ramp + hold + s * ramp, peak + s * (floor - peak)));
    }
    samples
}

/// Runs a load history (`(time, load)` samples, strictly increasing times
/// after 0) from rest; stops at the first failing step.
///
/// # Errors
/// [`ViscoError::InvalidValue`] for a non-increasing time; as
/// [`Hereditary::step_load`].
pub fn run_load_history<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    material: Prony,
    options: SolverOptions,
    samples: &[(f64, f64)],
) -> Result<Vec<ViscoStep>, ViscoError> {
    run_load_history_with(problem, material, options, Receding::default(), samples)
}

/// As [`run_load_history`], with the treatment of receding contacts
/// `receding`.
///
/// # Errors
/// As [`run_load_history`]; [`Receding::check`].
pub fn run_load_history_with<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    material: Prony,
    options: SolverOptions,
    receding: Receding,
    samples: &[(f64, f64)],
) -> Result<Vec<ViscoStep>, ViscoError> {
    let mut solver = Hereditary::with_receding(problem, material, options, receding)?;
    let mut steps = Vec::with_capacity(samples.len());
    for &(time, load) in samples {
        let dt = time - solver.time();
        if !(dt > 0.0) {
            return Err(ViscoError::InvalidValue {
                name: "load history time (s)",
                value: time,
                expected: "strictly increasing from 0",
            });
        }
        steps.push(solver.step_load(dt, load)?);
    }
    Ok(steps)
}
