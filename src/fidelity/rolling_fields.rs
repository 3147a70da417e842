//! The `calibrated_fields` rung in rolling (docs/validation.md,
//! "The `calibrated_fields` rung in rolling"): the calibrated road's
//! asperities coupled at each step through their own calibrated pressure
//! fields, and its sensors counted on the same fields.
//!
//! [`FieldRolling`] is the rolling crate's [`StepCoupling`] for laws
//! calibrated with fields ([`super::Calibrator::with_fields`]). At each
//! step the rolling crate places every asperity at its contact point and
//! runs the fixed point of docs/theory.md §3 "Field coupling", warm-started
//! from the previous step's correction; the correction of one round is
//! [`super::coupling::sparse_field_correction`] at the round's depths:
//!
//! ```text
//! C_ij = f (G_ij − 1/r_ij),  G_ij = Σ_a Σ_b w_ia w_jb / |x_ia − x_jb|   r < near (R_i + R_j)
//!        G_ij = 1/|c_i − c_j|                                            r < far (R_i + R_j)
//!        0 (the point kernel)                                            farther
//! ```
//!
//! (`x_ia` the bins of `i`'s unit field at `δ_i`, relative to its contact
//! point; `c_i` its centroid; `R_i` its largest bin distance.)
//!
//! Sensors ([`SensorAccounting::Fields`]): each contact's force `P_i` is
//! spread as its unit field at `δ_i`, the points relative to its contact
//! point, each bin's weight uniform over a square of the bin's side, and
//! integrated over the sensor's rectangle ([`crate::rolling::Sensor::share_spread`]).
//! [`SensorAccounting::Discs`] keeps the law's disc ([`crate::rolling::Sensor::share`]).
//! [`sensor_forces`] recounts a finished run's records either way
//! (each contact's depth recovered from its force by its law,
//! [`CalibratedLaw::depth_for`]).
//!
//! Invariants: each settled step balances the load to the solver's
//! tolerance (each round is a converged solve); sensors tiling the road sum
//! to the total force under either accounting; the fixed point's tolerance
//! (default 1e-6 of the load) is what two chunkings of the same run agree
//! to.

use std::sync::atomic::{AtomicUsize, Ordering};

use super::coupling::{FieldCouplingOptions, PairReach, PairSum, sparse_field_correction};
use super::{CalibratedLaw, FidelityError};
use crate::multipoint::PairCorrection;
use crate::rolling::{
    ContactLaw, CouplingState, Road, RollingConfig, RollingResult, Spread, StepCoupling,
    StepStatus, contact_points,
};

/// How a coupled run's sensors count each contact's force.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SensorAccounting {
    /// Spread as the contact's calibrated unit field at its depth.
    Fields,
    /// The law's Hertz or cone disc around the contact point.
    Discs,
}

/// Rounds and pairs of a coupled run, summed over its settled steps.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct FieldRollingStats {
    /// Steps whose fixed point settled.
    pub steps: usize,
    /// Rounds over those steps (corrected solves after the warm one).
    pub rounds: usize,
    /// Most rounds at one step.
    pub max_rounds: usize,
    /// Pairs computed by the binned double sum, over all rounds.
    pub field_pairs: usize,
    /// Pairs computed from the centroids, over all rounds.
    pub centroid_pairs: usize,
}

/// The field coupling of a calibrated rolling road (module docs).
#[derive(Debug)]
pub struct FieldRolling {
    options: FieldCouplingOptions,
    reach: PairReach,
    sum: PairSum,
    sensors: SensorAccounting,
    factor: f64,
    steps: AtomicUsize,
    rounds: AtomicUsize,
    max_rounds: AtomicUsize,
    field_pairs: AtomicUsize,
    centroid_pairs: AtomicUsize,
}

impl FieldRolling {
    /// The coupling for a road of `material` (its Boussinesq factor), the
    /// fixed point's tolerance and rounds from `options` (its `reach` is
    /// `reach.near`), pairs limited by `reach`, sensors counted as
    /// `sensors` says.
    ///
    /// # Errors
    /// [`FidelityError::InvalidInput`] for options out of range.
    pub fn new(
        material: &crate::shared::Material,
        options: FieldCouplingOptions,
        reach: PairReach,
        sensors: SensorAccounting,
    ) -> Result<Self, FidelityError> {
        let check = |ok: bool, key: &'static str, value: String, expected: &str| {
            if ok {
                Ok(())
            } else {
                Err(FidelityError::invalid(key, value, expected))
            }
        };
        check(
            reach.near.is_finite()
                && reach.far.is_finite()
                && reach.near >= 1.0
                && reach.far >= reach.near,
            "field coupling reach",
            format!("near {}, far {}", reach.near, reach.far),
            "finite, 1 <= near <= far",
        )?;
        check(
            options.tolerance.is_finite() && options.tolerance > 0.0,
            "field coupling tolerance",
            options.tolerance.to_string(),
            "finite and > 0",
        )?;
        check(
            options.max_rounds > 0,
            "field coupling rounds",
            options.max_rounds.to_string(),
            ">= 1",
        )?;
        Ok(Self {
            options: FieldCouplingOptions {
                reach: reach.near,
                ..options
            },
            reach,
            sum: PairSum::default(),
            sensors,
            factor: material.boussinesq_factor(),
            steps: AtomicUsize::new(0),
            rounds: AtomicUsize::new(0),
            max_rounds: AtomicUsize::new(0),
            field_pairs: AtomicUsize::new(0),
            centroid_pairs: AtomicUsize::new(0),
        })
    }

    /// The defaults: [`FieldCouplingOptions::default`],
    /// [`PairReach::default`], sensors on the fields.
    ///
    /// # Errors
    /// None with the defaults; the `Result` is [`Self::new`]'s.
    pub fn with_defaults(material: &crate::shared::Material) -> Result<Self, FidelityError> {
        Self::new(
            material,
            FieldCouplingOptions::default(),
            PairReach::default(),
            SensorAccounting::Fields,
        )
    }

    /// Near pairs' double sums evaluated as `sum` says (default
    /// [`PairSum::Packed`]).
    pub fn with_pair_sum(mut self, sum: PairSum) -> Self {
        self.sum = sum;
        self
    }

    /// How the sensors count.
    pub fn sensors(&self) -> SensorAccounting {
        self.sensors
    }

    /// Rounds and pairs so far.
    pub fn stats(&self) -> FieldRollingStats {
        FieldRollingStats {
            steps: self.steps.load(Ordering::Relaxed),
            rounds: self.rounds.load(Ordering::Relaxed),
            max_rounds: self.max_rounds.load(Ordering::Relaxed),
            field_pairs: self.field_pairs.load(Ordering::Relaxed),
            centroid_pairs: self.centroid_pairs.load(Ordering::Relaxed),
        }
    }
}

impl StepCoupling<CalibratedLaw> for FieldRolling {
    fn correction(
        &self,
        state: &CouplingState<'_, '_, CalibratedLaw>,
    ) -> Result<PairCorrection, String> {
        let c = sparse_field_correction(
            state.problem.positions(),
            state.problem.laws(),
            state.depths,
            state.forces,
            self.factor,
            self.reach,
            self.sum,
        )
        .map_err(|e| e.to_string())?;
        self.field_pairs.fetch_add(c.field_pairs, Ordering::Relaxed);
        self.centroid_pairs
            .fetch_add(c.centroid_pairs, Ordering::Relaxed);
        Ok(c.correction)
    }

    fn tolerance(&self) -> f64 {
        self.options.tolerance
    }

    fn max_rounds(&self) -> usize {
        self.options.max_rounds
    }

    fn key(&self) -> u64 {
        // The numbers that change the records, mixed (FNV-1a).
        let mut h: u64 = 0xcbf2_9ce4_8422_2325;
        let words = [
            self.options.tolerance.to_bits(),
            self.acceptable_tolerance().to_bits(),
            self.options.max_rounds as u64,
            self.reach.near.to_bits(),
            self.reach.far.to_bits(),
            match self.sensors {
                SensorAccounting::Fields => 1,
                SensorAccounting::Discs => 2,
            },
        ];
        // The exact sum moves a record by round-off only; it is still
        // another run's (the default's key is the one before it existed).
        let exact = (self.sum == PairSum::Exact).then_some(3);
        for w in words.into_iter().chain(exact) {
            for b in w.to_le_bytes() {
                h ^= u64::from(b);
                h = h.wrapping_mul(0x0000_0100_0000_01b3);
            }
        }
        h
    }

    fn spread(&self, law: &CalibratedLaw, depth: f64) -> Option<Spread> {
        match self.sensors {
            SensorAccounting::Fields => field_spread(law, depth),
            SensorAccounting::Discs => None,
        }
    }

    fn settled(&self, rounds: usize) {
        self.steps.fetch_add(1, Ordering::Relaxed);
        self.rounds.fetch_add(rounds, Ordering::Relaxed);
        self.max_rounds.fetch_max(rounds, Ordering::Relaxed);
    }
}

/// A calibrated law's unit field at `depth` as a sensor spread (points
/// relative to the summit, squares of the bin's side); `None` without
/// fields.
pub fn field_spread(law: &CalibratedLaw, depth: f64) -> Option<Spread> {
    let cell = law.table().field()?.bin_size();
    Some(Spread {
        points: law.unit_field(depth)?,
        cell,
    })
}

/// A finished run's sensor forces (one row per sensor, one value per step;
/// NaN at failed steps) recounted under `accounting`: each recorded
/// contact's depth recovered from its force by its law, its spread or disc
/// placed at its contact point at that step (under the deformed tread when
/// the run's [`RollingConfig::contact_slope`] says so, from the step's
/// recorded forces, [`crate::rolling::contact_points`]).
///
/// # Errors
/// [`FidelityError::InvalidInput`] when a record names an asperity the
/// road does not hold, or [`SensorAccounting::Fields`] meets a law without
/// fields.
pub fn sensor_forces(
    result: &RollingResult,
    road: &Road<CalibratedLaw>,
    material: crate::shared::Material,
    config: &RollingConfig,
    accounting: SensorAccounting,
) -> Result<Vec<Vec<f64>>, FidelityError> {
    let mut out = vec![vec![0.0; result.steps.len()]; config.sensors.len()];
    for (k, step) in result.steps.iter().enumerate() {
        if step.status == StepStatus::Failed {
            for row in &mut out {
                row[k] = f64::NAN;
            }
            continue;
        }
        let mut locals = Vec::with_capacity(step.contact_ids.len());
        for &id in &step.contact_ids {
            locals.push(road.local_id(id).ok_or_else(|| {
                FidelityError::invalid(
                    "rolling record",
                    format!("asperity {id} at step {}", step.index),
                    "an asperity of the road",
                )
            })?);
        }
        // Laws placed along the path are the step's.
        let laws: Vec<_> = locals
            .iter()
            .map(|&local| road.law_at(local, step.position))
            .collect();
        let depths: Vec<f64> = laws
            .iter()
            .zip(&step.contact_forces)
            .map(|(law, &force)| law.depth_for(force))
            .collect();
        let contacts: Vec<_> = laws
            .iter()
            .zip(&step.contact_forces)
            .zip(&depths)
            .map(|((law, &force), &depth)| law.local_contact(force, depth))
            .collect();
        let radii: Vec<f64> = contacts.iter().map(|c| c.radius.max(0.0)).collect();
        let centres = contact_points(
            road,
            material,
            config,
            step.position,
            &locals,
            &step.contact_forces,
            &radii,
        );
        for (a, &force) in step.contact_forces.iter().enumerate() {
            let law = &laws[a];
            match accounting {
                SensorAccounting::Fields => {
                    let spread = field_spread(law, depths[a]).ok_or_else(|| {
                        FidelityError::invalid(
                            "asperity law",
                            format!("asperity {} without a pressure field", step.contact_ids[a]),
                            "a table calibrated with fields (Calibrator::with_fields)",
                        )
                    })?;
                    for (row, s) in out.iter_mut().zip(&config.sensors) {
                        row[k] += s.share_spread(centres[a], force, &spread);
                    }
                }
                SensorAccounting::Discs => {
                    for (row, s) in out.iter_mut().zip(&config.sensors) {
                        row[k] += s.share(centres[a], &contacts[a]);
                    }
                }
            }
        }
    }
    Ok(out)
}
