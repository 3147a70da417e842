//! Viscoelastic rolling with a caller's pair correction of each step
//! ([`roll_viscoelastic_coupled`]; docs/viscoelastic.md, "Field coupling in
//! viscoelastic rolling").
//!
//! The elastic coupled step (docs/rolling.md, "Coupled steps") solves with
//! the interaction `T + C(δ)`, `C` a sparse correction of the point kernel
//! that the caller computes from the step's state. `C` is a compliance: at
//! modulus `E` it is `C̃/E*`-like, linear in `1/E` (the calibrated fields'
//! `f (G − 1/r)`, `f = (1 − ν²)/(π E)`). In the hereditary step the
//! unit-modulus interaction `K̃ + C̃` acts on the elastic-equivalent forces
//! `w_j = (p_j − h_j)/E_eff`, so the correction enters exactly where the
//! point compliance does, on the same force history:
//!
//! ```text
//! δ_i = δ0 − [H_i + Σ_j (T^eff_ij + C^eff_ij)(−h_j)] − Σ_j (T^eff_ij + C^eff_ij) p_j
//! C^eff = C_ref · E_ref / E_eff
//! ```
//!
//! (`C_ref` the caller's correction for the laws' reference modulus,
//! `E_ref`). Each round of the fixed point is therefore one elastic-cost
//! solve of modulus `E_eff` whose gaps are raised by the memory through
//! `T^eff + C^eff`, with `C` at the round's depths:
//!
//! ```text
//! round 0:  solve with C_prev (the previous step's, by road ids)
//! round r:  C(δʳ⁻¹), gaps raised by (T^eff + C^eff)(−h), solve from Pʳ⁻¹
//! stop when max_i |Pʳ_i − Pʳ⁻¹_i| ≤ tol · scale   (scale: the load, or Σ P)
//! ```
//!
//! with the elastic step's damping (from the fifth round, a blend of the
//! new correction with the last one solved with, its weight halved when a
//! round does not halve the change), and, as there, a fixed point those
//! rounds leave unsettled goes on under Aitken's weight for as many rounds
//! again (`FixedPointDamping::aitken`). A step still moving after them is
//! that step's recorded failure, its residual the
//! last change over the scale; its memories are held as for a failed
//! solve. The caller is handed the step's asperities at their contact
//! points, their depths, and as "forces" the drivers of the displacement,
//! `E_eff w_i = p_i − h_i ≥ 0`: an asperity out of contact whose memory
//! still depresses the tread is coupled too. Memory of asperities no longer
//! selected acts through the point kernel only. The sensors count each
//! contact on the coupling's spread ([`StepCoupling::spread`]) at its
//! contact point.
//!
//! Limits (tested by `tests/rolling_coupled.rs` here and the root crate's
//! `tests/visco_calibrated_fields.rs`): with
//! `h = 0` (very slow or very fast rolling) a step is the elastic coupled
//! step at `E_eff`, so the run is the elastic coupled run with `E∞`, or
//! with `E∞ + Σ E_k`.

use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::{
    Control, PairCorrection, Par, Problem, Solution, SolveError, SolverOptions, solve_corrected,
};
use tyreroad_rolling::{
    CouplingState, FixedPoint, FixedPointDamping, Road, RollingConfig, RollingError, Start,
    StepCoupling, StepRecord, contact_point, first_solve,
};

use super::{Runner, ViscoRollOptions, ViscoRolling, roll_with, warm_start};
use crate::rolling_law::StepLaw;
use crate::{Prony, ViscoError};

/// [`super::roll_viscoelastic`] with each step solved as the fixed point of
/// `coupling`'s pair correction (module docs). `coupling` computes its
/// correction for the laws' reference material `reference`; each step
/// scales it to the step's effective modulus.
///
/// # Errors
/// As [`super::roll_viscoelastic`]; [`ViscoError::Rolling`] with
/// [`RollingError::InvalidInput`] when the coupling cannot compute a
/// correction (a malformed road). A step whose fixed point does not settle
/// is that step's recorded failure, not the run's.
pub fn roll_viscoelastic_coupled<L: ContactLaw + Sync>(
    road: &Road<L>,
    reference: Material,
    tread: &Prony,
    config: &RollingConfig,
    options: &ViscoRollOptions<'_>,
    coupling: &dyn StepCoupling<L>,
) -> Result<ViscoRolling, ViscoError> {
    roll_with(road, reference, tread, config, options, Some(coupling))
}

/// What one step of the run has fixed before its solve.
pub(super) struct Step<'s> {
    pub(super) k: usize,
    /// The tread at `E_eff`.
    pub(super) material: Material,
    /// `E_eff` (Pa).
    pub(super) effective: f64,
    /// Each branch's `(decay, weight)` over the step.
    pub(super) coefficients: &'s [(f64, f64)],
    pub(super) relaxed: bool,
    pub(super) control: Control,
    /// The tread's profile at the window's edge (m), for the clearance.
    pub(super) boundary: f64,
}

/// A coupled step's fixed frame: the selection at its contact points, its
/// gaps raised by the memory through the point kernel, the memory drivers
/// `−h` and the scale of the reference correction.
struct Frame<'f, 'r, L> {
    ids: &'f [usize],
    points: &'f [[f64; 2]],
    /// `H_i + T^eff (−h)` (m).
    raised: &'f [f64],
    /// `−h_i ≥ 0` per selected asperity (N).
    memory: &'f [f64],
    elastic: &'f Problem<&'r L>,
    /// `E_ref / E_eff`.
    ratio: f64,
    step: &'f Step<'f>,
}

/// A fixed point's outcome: the solution and the reference correction it
/// was solved with, or the step's failure (the outer error is the run's).
type Settled = Result<(Solution, PairCorrection), SolveError>;

impl<'r, L: ContactLaw + Sync> Runner<'r, L> {
    /// Step `step.k` on the selection `ids` (`elastic`: its problem at the
    /// reference modulus, summits and gaps) under `coupling`; its record
    /// and count of shrinking patches.
    pub(super) fn coupled_step(
        &mut self,
        coupling: &dyn StepCoupling<L>,
        ids: Vec<usize>,
        elastic: &Problem<&'r L>,
        step: &Step<'_>,
    ) -> Result<(StepRecord, usize), ViscoError> {
        let (config, road, k) = (self.config, self.road, step.k);
        let xc = config.position(k);
        let solve_error = |source| ViscoError::Solve {
            step: k,
            time: xc / config.speed,
            source,
        };
        let points: Vec<[f64; 2]> = ids
            .iter()
            .map(|&i| contact_point(road, config, xc, i))
            .collect();
        let raised = self.point_raise(&ids, &points, elastic.gaps(), step.material, xc);
        let memory: Vec<f64> = ids.iter().map(|&i| -self.history[i]).collect();
        let warm = self
            .kept
            .warm(
                &ids,
                &points,
                self.reference.boussinesq_factor(),
                &mut self.index,
            )
            .map_err(solve_error)?;
        let mut dense = std::mem::take(&mut self.dense);
        let frame = Frame {
            ids: &ids,
            points: &points,
            raised: &raised,
            memory: &memory,
            elastic,
            ratio: self.reference.youngs_modulus() / step.effective,
            step,
        };
        let outcome = self
            .fixed_point(coupling, &frame, &warm, &mut dense)
            .and_then(|settled| match settled {
                Ok((solution, used)) => {
                    let (problem, _) = self.frame_problem(&frame, &used).map_err(solve_error)?;
                    let record = self.record(
                        k,
                        (&ids, &points),
                        &problem,
                        &solution,
                        step.boundary,
                        Some(coupling),
                    );
                    Ok(Ok((solution, used, record)))
                }
                Err(e) => Ok(Err(e)),
            });
        self.dense = dense;
        let (solution, used, record) = match outcome? {
            Ok(done) => done,
            Err(SolveError::NotConverged {
                iterations,
                residual,
                ..
            }) => {
                // That step's failure, not the run's (as an uncoupled
                // step's): every memory held, the next step cold-starts.
                self.carry = None;
                self.kept.clear();
                self.hold(step.coefficients, step.relaxed);
                return Ok((self.failed_record(k, ids.len(), iterations, residual), 0));
            }
            Err(source) => return Err(solve_error(source)),
        };
        let shrinking = self.remember(
            &ids,
            &solution.forces,
            &solution.depths,
            step.effective,
            step.coefficients,
            step.relaxed,
        );
        self.kept
            .keep(&ids, &used, &points, self.reference.boussinesq_factor());
        self.carry = Some((ids, solution.forces, solution.approach));
        Ok((record, shrinking))
    }

    /// The fixed point of the step (module docs), warm-started from `warm`
    /// (reference correction) and the previous step's forces.
    fn fixed_point(
        &self,
        coupling: &dyn StepCoupling<L>,
        frame: &Frame<'_, 'r, L>,
        warm: &PairCorrection,
        dense: &mut [f64],
    ) -> Result<Settled, ViscoError> {
        let (config, step) = (self.config, frame.step);
        let xc = config.position(step.k);
        let solve_error = |source| ViscoError::Solve {
            step: step.k,
            time: xc / config.speed,
            source,
        };
        let options = SolverOptions {
            tolerance: config.tolerance,
            max_iterations: config.max_iterations,
            par: Par::Seq,
            ..SolverOptions::default()
        };
        // Warm from the previous step, and cold (no correction) if that
        // does not converge, as the elastic coupled step
        // (`tyreroad_rolling::first_solve`).
        let cold = PairCorrection::default();
        let carried = self.carry.is_some() || !warm.is_empty();
        let (problem, c) = self.frame_problem(frame, warm).map_err(solve_error)?;
        let first = first_solve(carried, |start| match start {
            Start::Warm => {
                let initial = warm_start(self.carry.as_ref(), dense, frame.ids, &problem, &c);
                solve_corrected(&problem, step.control, &options, initial.as_ref(), &c)
            }
            // Nothing carried: the problem above already has no correction.
            Start::Cold if warm.is_empty() => {
                solve_corrected(&problem, step.control, &options, None, &c)
            }
            Start::Cold => {
                let (problem, c) = self.frame_problem(frame, &cold)?;
                solve_corrected(&problem, step.control, &options, None, &c)
            }
        });
        let first = match first {
            Ok(first) => first,
            Err(e) => return Ok(Err(e)),
        };
        let warm = match first.start {
            Start::Warm => warm,
            Start::Cold => &cold,
        };
        let iterations = first.spent + first.solution.iterations;
        let scale = match step.control {
            Control::Load(w) => w,
            Control::Approach(_) => first.solution.forces.iter().sum(),
        };
        if !(scale > 0.0) {
            // Nothing in contact: nothing to couple.
            coupling.settled(0);
            return Ok(Ok((first.solution, warm.clone())));
        }
        // The coupling's view: the elastic laws at the reference modulus,
        // at their contact points.
        let base = Problem::new(
            frame.points.to_vec(),
            frame.elastic.gaps().to_vec(),
            frame.elastic.laws().to_vec(),
            self.reference,
        )
        .map_err(solve_error)?;
        let summits = self.road.positions();
        let offsets: Vec<[f64; 2]> = frame
            .ids
            .iter()
            .zip(frame.points)
            .map(|(&i, p)| [p[0] - summits[i][0], p[1] - summits[i][1]])
            .collect();
        let mut fp = FixedPoint::new(first.solution, warm.clone(), iterations);
        // The rounds under the elastic step's halving damping; a fixed point
        // they leave unsettled goes on from where it stopped under Aitken's
        // (the elastic step's rescue pass, docs/rolling.md "Coupled steps").
        for mut damping in [FixedPointDamping::default(), FixedPointDamping::aitken()] {
            if fp.change <= coupling.acceptable_tolerance() {
                break;
            }
            for round in 1..=coupling.max_rounds() {
                // The displacement's drivers, `E_eff w = p − h`.
                let drivers: Vec<f64> = fp
                    .solution
                    .forces
                    .iter()
                    .zip(frame.memory)
                    .map(|(p, m)| p + m)
                    .collect();
                let state = CouplingState {
                    ids: frame.ids,
                    problem: &base,
                    offsets: &offsets,
                    depths: &fp.solution.depths,
                    forces: &drivers,
                };
                let mut c_ref = coupling
                    .correction(&state)
                    .map_err(|m| ViscoError::Rolling {
                        source: RollingError::InvalidInput(format!(
                            "step at x = {} m: coupling: {m}",
                            crate::significant(xc)
                        )),
                    })?;
                // The elastic step's damping (docs/rolling.md, "Coupled steps"):
                // the same fixed point, cycles between overlapping patches damped.
                c_ref = damping
                    .relax(round, &fp.used, c_ref, frame.ids.len())
                    .map_err(solve_error)?;
                let (problem, c) = self.frame_problem(frame, &c_ref).map_err(solve_error)?;
                let next =
                    match solve_corrected(&problem, step.control, &options, Some(&fp.solution), &c)
                    {
                        Ok(next) => next,
                        Err(e) => return Ok(Err(e)),
                    };
                if fp.take((round, next, c_ref), &mut damping, scale, coupling) {
                    return Ok(Ok((fp.solution, fp.used)));
                }
            }
        }
        Ok(fp.ended(None, coupling.acceptable_tolerance()))
    }

    /// The step's problem under the reference correction `c_ref`: modulus
    /// `E_eff`, gaps raised by the memory through `T^eff + C^eff`, the
    /// step's laws; with `C^eff`.
    fn frame_problem<'p>(
        &'p self,
        frame: &Frame<'_, 'p, L>,
        c_ref: &PairCorrection,
    ) -> Result<(Problem<StepLaw<'p, L>>, PairCorrection), SolveError> {
        let c = scaled(c_ref, frame.ratio, frame.ids.len())?;
        let mut gaps = frame.raised.to_vec();
        c.apply_add(frame.memory, &mut gaps);
        let laws = self.step_laws(frame.ids, frame.elastic.laws(), frame.step.effective);
        let problem = Problem::new(frame.points.to_vec(), gaps, laws, frame.step.material)?;
        Ok((problem, c))
    }

    /// `gaps` raised by the memory through the point kernel at `material`
    /// (`E_eff`), between contact points at `xc`: `H_i + T^eff (−h)` over
    /// every asperity holding memory, selected (`points`) or not.
    fn point_raise(
        &mut self,
        ids: &[usize],
        points: &[[f64; 2]],
        gaps: &[f64],
        material: Material,
        xc: f64,
    ) -> Vec<f64> {
        for (a, &i) in ids.iter().enumerate() {
            self.index[i] = a;
        }
        let held: Vec<(usize, [f64; 2], f64)> = self
            .active
            .iter()
            .map(|&j| {
                let at = match self.index[j] {
                    usize::MAX => contact_point(self.road, self.config, xc, j),
                    a => points[a],
                };
                (j, at, -self.history[j])
            })
            .collect();
        for &i in ids {
            self.index[i] = usize::MAX;
        }
        let factor = material.boussinesq_factor();
        ids.iter()
            .zip(points)
            .zip(gaps)
            .map(|((&i, p), &h)| {
                let raise: f64 = held
                    .iter()
                    .filter(|(j, _, _)| *j != i)
                    .map(|(_, q, m)| m / (p[0] - q[0]).hypot(p[1] - q[1]))
                    .sum();
                h + factor * raise
            })
            .collect()
    }
}

/// `c` times `ratio`, pair by pair.
fn scaled(c: &PairCorrection, ratio: f64, n: usize) -> Result<PairCorrection, SolveError> {
    PairCorrection::new(
        n,
        c.pairs()
            .iter()
            .map(|&(i, j, v)| (i, j, ratio * v))
            .collect(),
    )
}
