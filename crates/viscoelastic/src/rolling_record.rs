//! The records of a viscoelastic rolling step (as the elastic run's
//! [`StepRecord`]) and the warm start mapped from the previous step.

use tyreroad_contact_law::{ContactLaw, LocalContact};
use tyreroad_multipoint::{
    Convergence, PairCorrection, Problem, Recovery, Solution, overlapping_contacts,
};
use tyreroad_rolling::{StepCoupling, StepRecord, StepStatus};

use super::Runner;
use crate::rolling_law::StepLaw;

impl<L: ContactLaw + Sync> Runner<'_, L> {
    /// The step's record; sensors count each contact at its `centres`
    /// entry on the coupling's spread when it gives one, else on its disc.
    pub(super) fn record(
        &self,
        k: usize,
        (ids, centres): (&[usize], &[[f64; 2]]),
        problem: &Problem<StepLaw<'_, L>>,
        solution: &Solution,
        boundary: f64,
        coupling: Option<&dyn StepCoupling<L>>,
    ) -> StepRecord {
        let config = self.config;
        let contacts: Vec<LocalContact> = solution.local_contacts(problem);
        let mut sensor_forces = vec![0.0; config.sensors.len()];
        let mut area = 0.0;
        let mut contact_ids = Vec::new();
        let mut contact_forces = Vec::new();
        for (a, (&i, &p)) in ids.iter().zip(&solution.forces).enumerate() {
            if p > 0.0 {
                contact_ids.push(i);
                contact_forces.push(p);
                area += contacts[a].area();
                let law = &self.road.laws()[i];
                let spread = coupling.and_then(|c| c.spread(law, solution.depths[a]));
                for (f, s) in sensor_forces.iter_mut().zip(&config.sensors) {
                    *f += match &spread {
                        Some(spread) => s.share_spread(centres[a], p, spread),
                        None => s.share(centres[a], &contacts[a]),
                    };
                }
            }
        }
        let xc = config.position(k);
        StepRecord {
            index: k,
            position: xc,
            time: xc / config.speed,
            total_force: contact_forces.iter().sum(),
            approach: solution.approach,
            contact_area: area,
            contacts: contact_ids.len(),
            selected: ids.len(),
            iterations: solution.iterations,
            status: match solution.convergence {
                Convergence::Converged => StepStatus::Converged,
                Convergence::Stagnated { .. } => StepStatus::Stagnated,
            },
            recovery: solution.recovery,
            residual: solution.residual,
            clearance: boundary - solution.approach,
            overlapping: overlapping_contacts(problem.positions(), &contacts).len(),
            sensor_forces,
            contact_ids,
            contact_forces,
        }
    }

    pub(super) fn empty_record(&self, k: usize, approach: f64, boundary: f64) -> StepRecord {
        let xc = self.config.position(k);
        StepRecord {
            index: k,
            position: xc,
            time: xc / self.config.speed,
            total_force: 0.0,
            approach,
            contact_area: 0.0,
            contacts: 0,
            selected: 0,
            iterations: 0,
            status: StepStatus::Converged,
            recovery: Recovery::None,
            residual: 0.0,
            clearance: boundary - approach,
            overlapping: 0,
            sensor_forces: vec![0.0; self.config.sensors.len()],
            contact_ids: Vec::new(),
            contact_forces: Vec::new(),
        }
    }

    pub(super) fn failed_record(
        &self,
        k: usize,
        selected: usize,
        iterations: usize,
        residual: f64,
    ) -> StepRecord {
        let nan = f64::NAN;
        StepRecord {
            total_force: nan,
            approach: nan,
            contact_area: nan,
            selected,
            iterations,
            status: StepStatus::Failed,
            residual,
            clearance: nan,
            sensor_forces: vec![nan; self.config.sensors.len()],
            ..self.empty_record(k, nan, nan)
        }
    }
}

/// The previous step's forces mapped by road id (new asperities at 0),
/// with consistent interpenetrations under the coupling `T + correction`;
/// `dense` is an id-indexed scratch of zeros, left zero.
pub(super) fn warm_start<L: ContactLaw>(
    carry: Option<&(Vec<usize>, Vec<f64>, f64)>,
    dense: &mut [f64],
    ids: &[usize],
    problem: &Problem<L>,
    correction: &PairCorrection,
) -> Option<Solution> {
    let (old_ids, old_forces, approach) = carry?;
    for (&i, &p) in old_ids.iter().zip(old_forces) {
        dense[i] = p;
    }
    let forces: Vec<f64> = ids.iter().map(|&i| dense[i]).collect();
    for &i in old_ids {
        dense[i] = 0.0;
    }
    Some(Solution::consistent_warm_start(
        problem, forces, *approach, correction,
    ))
}
