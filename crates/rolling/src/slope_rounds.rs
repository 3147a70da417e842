//! A step's slopes under the deformed tread ([`crate::ContactSlope::Deformed`])
//! and the rounds that settle them with the step's solve (docs/rolling.md,
//! "Where the tread touches a cap").
//!
//! Each round: the slopes the last forces cause ([`deformed_slopes`],
//! each contact lending the kernel's floor its [`floor_radius`]), mixed
//! with the rounds before ([`SlopeMixer`]); the gaps and contact points
//! rebuilt at them; a solve warm-started from the last forces
//! ([`consistent_start`]). Settled when no gap moves by more than
//! `SLOPE_TOLERANCE` of the deepest interpenetration; kept with its slopes
//! held, marked stagnated, when the rounds are spent with no force moving
//! by more than `HELD_SLOPES_LIMIT` of the load; else the step's failure.
//!
//! Invariants: under the profile (`slopes` `None`) one solve, exactly the
//! step without this module; the fixed points are the plain iteration's.

use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::{
    Control, PairCorrection, Problem, Solution, SolveError, SolverOptions, solve_from,
};

use crate::coupling::{force_scale, largest_change, stalled_fixed_point};
use crate::slope::{SlopeMixer, floor_radius};
use crate::step::build_at;
use crate::{ContactSlope, Road, RollingConfig, RollingError, deformation_slopes};

/// The deformation's slopes at the summits of `ids` ([`crate::deformation_slopes`]),
/// or `None` when the run places contacts under the undeformed profile.
pub(crate) fn deformed_slopes<L>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    ids: &[usize],
    forces: &[f64],
    radii: &[f64],
) -> Option<Vec<[f64; 2]>> {
    if config.contact_slope != ContactSlope::Deformed {
        return None;
    }
    let summits: Vec<[f64; 2]> = ids.iter().map(|&i| road.positions()[i]).collect();
    let floors: Vec<f64> = ids
        .iter()
        .zip(forces.iter().zip(radii))
        .map(|(&i, (&p, &a))| floor_radius(a, p, road.summit_radius(i), material.reduced_modulus()))
        .collect();
    Some(deformation_slopes(
        &summits,
        forces,
        &floors,
        material.boussinesq_factor(),
    ))
}

/// Rounds of a step's slope iteration ([`settle_slopes`]) before the
/// step is recorded as failed.
const SLOPE_ROUNDS: usize = 30;

/// The largest move of a finite gap between two problems of the same
/// asperities (m).
fn largest_gap_move<L: ContactLaw>(a: &Problem<&L>, b: &Problem<&L>) -> f64 {
    a.gaps()
        .iter()
        .zip(b.gaps())
        .filter(|(a, b)| a.is_finite() && b.is_finite())
        .map(|(a, b)| (a - b).abs())
        .fold(0.0, f64::max)
}

/// A step whose slope rounds end unsettled, its last round having moved
/// no force by more than this fraction of the load, is kept with its slopes
/// held where the rounds left them: marked stagnated, its residual that
/// last change. The contact is then solved exactly for slopes a round
/// short of their own fixed point (an uncoupled step: the last round's
/// solve; a coupled one: the field coupling settled again with the slopes
/// held). Contacts at the edges of a split plateau's tiles turn on and off
/// between rounds and no more settles; on the porous asphalt's 100 steps
/// under `calibrated_fields` the held steps' last rounds moved 1e-5 to
/// 8e-4 of the load, and none of the sensors' largest errors against the
/// BEM moved (docs/validation.md, "Slopes held where their rounds end").
/// A larger change is the step's failure.
pub(crate) const HELD_SLOPES_LIMIT: f64 = 1e-2;

/// A step's gaps have settled when no gap moves by more than this
/// fraction of the deepest interpenetration between two rounds.
const SLOPE_TOLERANCE: f64 = 1e-7;

/// Each asperity's contact radius in `solution` (0 out of contact).
pub(crate) fn contact_radii<L: ContactLaw>(solution: &Solution, problem: &Problem<&L>) -> Vec<f64> {
    solution
        .local_contacts(problem)
        .iter()
        .map(|c| {
            if c.force > 0.0 {
                c.radius.max(0.0)
            } else {
                0.0
            }
        })
        .collect()
}

/// `solution`'s forces and approach with the interpenetrations of
/// `problem` (`Solution::consistent_warm_start`): a warm start after the
/// gaps moved, its iterations carried.
pub(crate) fn consistent_start<L: ContactLaw>(
    problem: &Problem<&L>,
    solution: &Solution,
    correction: &PairCorrection,
) -> Solution {
    let mut start = Solution::consistent_warm_start(
        problem,
        solution.forces.clone(),
        solution.approach,
        correction,
    );
    start.iterations = solution.iterations;
    start
}

/// An uncoupled step under the deformed tread: solve, move each gap to
/// the slopes the forces cause ([`crate::deformation_slopes`]), solve
/// again from there, until no gap moves by more than [`SLOPE_TOLERANCE`]
/// of the deepest interpenetration. Under the profile (`slopes` `None`)
/// one solve. The slopes are mixed with the rounds before
/// ([`SlopeMixer`]): two tiles a fraction of a millimetre apart tilt each
/// other, and the plain iteration can cycle between one loaded and the
/// other (porous asphalt's 5 mm tiles: 15 of 16 cold steps failed so); the
/// mix has the same fixed point. A step still moving after
/// [`SLOPE_ROUNDS`] is kept with its slopes held ([`HELD_SLOPES_LIMIT`]),
/// or is its failure, the last move over the depth its residual.
pub(crate) fn settle_slopes<'p, L: ContactLaw + Sync>(
    (road, material, config, xc): (&Road<L>, Material, &RollingConfig, f64),
    (ids, laws): (&[usize], &[&'p L]),
    (problem, slopes): (&mut Problem<&'p L>, &mut Option<Vec<[f64; 2]>>),
    (control, options): (Control, &SolverOptions),
    initial: Option<&Solution>,
) -> Result<Result<Solution, SolveError>, RollingError> {
    let mut s = match solve_from(problem, control, options, initial) {
        Ok(s) => s,
        Err(e) => return Ok(Err(e)),
    };
    let Some(current) = slopes.as_mut() else {
        return Ok(Ok(s));
    };
    let mut iterations = s.iterations;
    let (mut change, mut force_change) = (f64::INFINITY, f64::INFINITY);
    let mut mixer = SlopeMixer::default();
    let build =
        |slopes: &[[f64; 2]]| build_at(road, material, config, xc, ids, laws, false, Some(slopes));
    for _ in 0..SLOPE_ROUNDS {
        let radii = contact_radii(&s, problem);
        let Some(next) = deformed_slopes(road, material, config, ids, &s.forces, &radii) else {
            return Ok(Ok(s));
        };
        let depth = s.depths.iter().fold(0.0f64, |m, &d| m.max(d));
        change = largest_gap_move(&build(&next)?, problem) / depth.max(f64::MIN_POSITIVE);
        if change <= SLOPE_TOLERANCE {
            // Solved with gaps this close to the settled ones.
            *current = next;
            s.iterations = iterations;
            return Ok(Ok(s));
        }
        *current = mixer.next(current, &next);
        *problem = build(current)?;
        let start = consistent_start(problem, &s, &PairCorrection::default());
        let next = match solve_from(problem, control, options, Some(&start)) {
            Ok(next) => next,
            Err(e) => return Ok(Err(e)),
        };
        force_change = largest_change(&next.forces, &s.forces)
            / force_scale(control, &next.forces).max(f64::MIN_POSITIVE);
        s = next;
        iterations += s.iterations;
    }
    s.iterations = iterations;
    // Solved at the slopes the rounds ended on: kept when they came close.
    if let Some(s) = stalled_fixed_point(s, force_change, HELD_SLOPES_LIMIT) {
        return Ok(Ok(s));
    }
    Ok(Err(SolveError::NotConverged {
        iterations,
        load_steps: 0,
        residual: change,
    }))
}
