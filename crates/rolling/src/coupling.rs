//! A caller's coupling of a step's asperities beyond the point kernel
//! ([`StepCoupling`]): each step solved as a fixed point of a sparse
//! correction `C` of the interaction matrix, recomputed by the caller from
//! the step's state (docs/rolling.md, "Coupled steps").
//!
//! At one step, with `T` the point kernel between the asperities' contact
//! points and `C(δ)` the caller's correction at the depths `δ`:
//!
//! ```text
//! round 0:  P⁰ = solve(T + C_prev)          (C_prev: the previous step's C, warm)
//! round r:  Pʳ = solve(T + C(δʳ⁻¹)) from Pʳ⁻¹
//! stop when max_i |Pʳ_i − Pʳ⁻¹_i| ≤ tol · scale   (scale: the load, or Σ P)
//! ```
//!
//! The crate knows nothing of where `C` comes from (the calibrated
//! pressure fields of `tyreroad::fidelity` are one source): it hands the
//! caller numbers (ids, positions, depths, forces) and gets numbers back.
//! A step whose fixed point has not settled after
//! [`StepCoupling::max_rounds`] rounds is that step's recorded failure,
//! its residual the last round's change over the scale.
//!
//! The caller may also say how a contact's force spreads over the road
//! ([`StepCoupling::spread`]): the sensors then count each contact on its
//! spread, placed at its contact point, instead of the law's Hertz or cone
//! disc ([`crate::Sensor::share_spread`]).

use tyreroad_multipoint::{PairCorrection, Problem, SolveError};

/// The state of one step that a correction is computed from.
#[derive(Debug)]
pub struct CouplingState<'s, 'r, L> {
    /// The road-local ids of the step's asperities, in the problem's order.
    pub ids: &'s [usize],
    /// The step problem; under a coupling its positions are the
    /// asperities' contact points ([`crate::contact_point`]), not their
    /// summits.
    pub problem: &'s Problem<&'r L>,
    /// Each asperity's contact point minus its summit (m), problem order.
    pub offsets: &'s [[f64; 2]],
    /// Local interpenetrations `δ_i` (m), problem order.
    pub depths: &'s [f64],
    /// Forces `P_i` (N), problem order.
    pub forces: &'s [f64],
}

/// A contact's force spread over the road: points relative to its summit
/// (m) with weights summing to one, each weight uniform over a square of
/// side [`Spread::cell`] centred on its point.
#[derive(Clone, Debug, PartialEq)]
pub struct Spread {
    /// `(point − summit, weight)`.
    pub points: Vec<([f64; 2], f64)>,
    /// Side of each point's square (m).
    pub cell: f64,
}

/// A caller-supplied coupling of each step's asperities (module docs).
pub trait StepCoupling<L>: Sync {
    /// The correction `C` at `state` (pairs indexed in the problem's
    /// order). An error is the run's (a malformed road), not a step's.
    ///
    /// # Errors
    /// A message naming what is wrong.
    fn correction(&self, state: &CouplingState<'_, '_, L>) -> Result<PairCorrection, String>;

    /// The fixed point stops when no force moves by more than this
    /// fraction of the scale between rounds.
    fn tolerance(&self) -> f64;

    /// Most rounds of the fixed point at one step.
    fn max_rounds(&self) -> usize;

    /// What the coupling changes in the results, for the checkpoint key
    /// (two couplings that may give different records differ here).
    fn key(&self) -> u64;

    /// How a contact of law `law` at depth `depth` (m) spreads its force
    /// over the road; `None`: the law's own disc ([`crate::Sensor::share`]).
    fn spread(&self, _law: &L, _depth: f64) -> Option<Spread> {
        None
    }

    /// Told after each settled step how many rounds it took (statistics).
    fn settled(&self, _rounds: usize) {}
}

/// A step's correction kept for the next step's warm start, by road-local
/// ids.
pub(crate) type KeptCorrection = Vec<(usize, usize, f64)>;

/// The damping of a coupled step's fixed point, shared by the elastic
/// step and the viscoelastic one (docs/rolling.md, "Coupled steps"): from
/// round [`FixedPointDamping::WHOLE_ROUNDS`] + 1 on, a relaxed correction
/// `(1 − β) C_used + β C(δ)`, β halved (down to 1/16) whenever a round did
/// not halve the change. Two contacts whose patches overlap can make the
/// plain iteration cycle; the blend keeps the same fixed point (where
/// `C(δ)` is the `C` solved with) and damps the cycle.
#[derive(Clone, Copy, Debug)]
pub struct FixedPointDamping {
    previous: f64,
    weight: f64,
}

impl Default for FixedPointDamping {
    fn default() -> Self {
        Self {
            previous: f64::INFINITY,
            weight: 1.0,
        }
    }
}

impl FixedPointDamping {
    /// Rounds taken whole before each new correction is blended.
    pub const WHOLE_ROUNDS: usize = 4;

    /// Round `round`'s correction `c`, blended with `used` (the one last
    /// solved with) once the whole rounds are spent; `n` asperities.
    ///
    /// # Errors
    /// A blend that is not a valid correction (cannot happen for two valid
    /// ones of `n` asperities).
    pub fn relax(
        &self,
        round: usize,
        used: &PairCorrection,
        c: PairCorrection,
        n: usize,
    ) -> Result<PairCorrection, SolveError> {
        if round <= Self::WHOLE_ROUNDS {
            return Ok(c);
        }
        let beta = self.weight;
        let mut sum: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
        for (&(i, j, v), w) in used
            .pairs()
            .iter()
            .map(|p| (p, 1.0 - beta))
            .chain(c.pairs().iter().map(|p| (p, beta)))
        {
            *sum.entry((i.min(j), i.max(j))).or_insert(0.0) += w * v;
        }
        PairCorrection::new(n, sum.into_iter().map(|((i, j), v)| (i, j, v)).collect())
    }

    /// The round's change, `max_i |next_i − last_i| / scale`, recorded to
    /// set the next rounds' weight.
    pub fn change(&mut self, round: usize, next: &[f64], last: &[f64], scale: f64) -> f64 {
        let change = next
            .iter()
            .zip(last)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / scale;
        if round >= Self::WHOLE_ROUNDS && change > 0.5 * self.previous {
            self.weight = (0.5 * self.weight).max(1.0 / 16.0);
        }
        self.previous = change;
        change
    }
}
