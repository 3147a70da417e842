//! Ball summits inside another ball's contact patch during a rolling run
//! ([`InsidePatchTally`]): the rolling counterpart of a static run's
//! warning (`statics::summits_inside_patches`).
//!
//! The point kernel `1/(π E* r)` between two summits `r` apart stands for a
//! displacement that no pressure spread over a patch of radius `a > r`
//! gives: it grows without bound as `r → 0`, where the patch's own
//! displacement stays finite. Two summits 1 µm apart then carry almost
//! nothing between them and the approach runs away. A record holds forces,
//! not patches: each ball's patch is its Hertz radius
//! `a = (3 P R / 4 E*)^{1/3}` at its force (the Wilke law's radius is
//! within a few per cent of it), counted for balls only (`[[asperity]]`
//! spheres, synthetic roads' summits).

use crate::rolling::StepRecord;

/// Summits inside another's patch, counted over a rolling run's records.
pub(super) struct InsidePatchTally<'a> {
    positions: &'a [[f64; 2]],
    /// How the warning names asperity `id` to the user.
    name: &'a dyn Fn(usize) -> String,
    /// Each asperity's ball radius by road id (NaN: not a ball).
    radii: &'a [f64],
    reduced_modulus: f64,
}

/// The closest pair found: ids, spacing and the larger patch radius (m).
type Pair = (usize, usize, f64, f64);

impl<'a> InsidePatchTally<'a> {
    /// A tally for a road whose asperity `id` stands at `positions[id]`
    /// with ball radius `radii[id]` (NaN when not a ball), on a tread of
    /// plane-strain modulus `reduced_modulus` (Pa); `name(id)` names an
    /// asperity as the scenario does.
    pub(super) fn new(
        (positions, radii): (&'a [[f64; 2]], &'a [f64]),
        reduced_modulus: f64,
        name: &'a dyn Fn(usize) -> String,
    ) -> Self {
        Self {
            positions,
            name,
            radii,
            reduced_modulus,
        }
    }

    /// The pairs of `step`'s contacts where one summit lies inside the
    /// other's patch, the closest of them first (ids, spacing, radius).
    fn inside(&self, step: &StepRecord) -> Vec<Pair> {
        let mut balls: Vec<(usize, [f64; 2], f64)> = step
            .contact_ids
            .iter()
            .zip(&step.contact_forces)
            .filter_map(|(&id, &p)| {
                let r = *self.radii.get(id)?;
                let at = *self.positions.get(id)?;
                (r.is_finite() && p > 0.0)
                    .then(|| (id, at, (0.75 * p * r / self.reduced_modulus).cbrt()))
            })
            .collect();
        balls.sort_by(|a, b| a.1[0].total_cmp(&b.1[0]));
        let widest = balls.iter().map(|b| b.2).fold(0.0, f64::max);
        let mut pairs = Vec::new();
        for (k, &(i, pi, ai)) in balls.iter().enumerate() {
            for &(j, pj, aj) in &balls[k + 1..] {
                if pj[0] - pi[0] >= widest {
                    break;
                }
                let r = (pi[0] - pj[0]).hypot(pi[1] - pj[1]);
                if r < ai.max(aj) {
                    pairs.push((i.min(j), i.max(j), r, ai.max(aj)));
                }
            }
        }
        pairs.sort_by(|a, b| a.2.total_cmp(&b.2));
        pairs
    }

    /// The run's warning when any step had a summit inside another's
    /// patch: at how many steps, how many pairs, and the closest pair.
    pub(super) fn warning_over(&self, steps: &[StepRecord]) -> Option<String> {
        let (mut at_steps, mut pairs) = (0, 0);
        let mut closest: Option<Pair> = None;
        for step in steps {
            let inside = self.inside(step);
            if let Some(&first) = inside.first() {
                at_steps += 1;
                pairs += inside.len();
                if closest.is_none_or(|c| first.2 < c.2) {
                    closest = Some(first);
                }
            }
        }
        let (i, j, r, a) = closest?;
        Some(format!(
            "at {at_steps} of {} steps, {pairs} pairs of ball summits lay inside each other's \
             contact patch (closest: {} and {}, {:.4} mm apart, \
             patch radius {:.4} mm): the point-force coupling 1/r between them is far too \
             stiff there, and those steps' forces and approach are not physical; merge such \
             asperities or place them apart",
            steps.len(),
            (self.name)(i),
            (self.name)(j),
            r * 1e3,
            a * 1e3
        ))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rolling::{Recovery, StepStatus};

    fn step(ids: Vec<usize>, forces: Vec<f64>) -> StepRecord {
        StepRecord {
            index: 0,
            position: 0.0,
            time: 0.0,
            total_force: forces.iter().sum(),
            approach: 0.0,
            contact_area: 0.0,
            contacts: ids.len(),
            selected: ids.len(),
            iterations: 1,
            status: StepStatus::Converged,
            recovery: Recovery::None,
            residual: 0.0,
            clearance: f64::INFINITY,
            overlapping: 0,
            sensor_forces: Vec::new(),
            contact_ids: ids,
            contact_forces: forces,
        }
    }

    #[test]
    fn a_summit_inside_a_neighbours_hertz_patch_is_counted_and_apart_is_not() {
        // Balls of 5 mm on rubber (E* = 8.72 MPa): 1 N gives a = 0.75 mm.
        let positions = [[0.0, 0.0], [1e-6, 0.0], [10e-3, 0.0], [12e-3, 0.0]];
        let radii = [5e-3, 5e-3, 5e-3, f64::NAN];
        let name = |k: usize| format!("#{}", k + 1);
        let tally = InsidePatchTally::new((&positions, &radii), 6.54e6 / 0.75, &name);
        let close = step(vec![0, 1, 2], vec![1.0, 1.0, 1.0]);
        let inside = tally.inside(&close);
        assert_eq!(inside.len(), 1, "{inside:?}");
        let (i, j, r, a) = inside[0];
        assert_eq!((i, j), (0, 1));
        assert!((r - 1e-6).abs() < 1e-12);
        // Hertz by hand: (3 · 1 N · 5 mm / (4 · 8.72 MPa))^(1/3) = 0.75481 mm.
        assert!((a - 0.75481e-3).abs() < 1e-8, "{a}");
        // 2 mm apart under 1 N each, and a non-ball beside: nothing.
        assert!(tally.inside(&step(vec![2, 3], vec![1.0, 1.0])).is_empty());
        let warning = tally
            .warning_over(&[close.clone(), step(vec![2], vec![3.0]), close])
            .expect("warned");
        assert!(
            warning.starts_with("at 2 of 3 steps, 2 pairs of ball summits"),
            "{warning}"
        );
        assert!(
            warning.contains("(closest: #1 and #2, 0.0010 mm apart"),
            "{warning}"
        );
        assert_eq!(tally.warning_over(&[step(vec![2], vec![3.0])]), None);
    }
}
