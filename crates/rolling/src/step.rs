//! One step of the path: the footprint's asperities selected by an
//! x-window, the sub-problem's gaps, and its solve warm-started from the
//! previous step's state ([`Carry`]).

use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::{
    Boussinesq, Control, Convergence, PairCorrection, Par, Problem, Recovery, Solution, SolveError,
    SolverOptions, overlapping_contacts, solve_corrected, solve_from,
};

use crate::coupling::{CouplingState, KeptCorrection, StepCoupling};
use crate::{Road, RollingConfig, RollingControl, RollingError, StepRecord, StepStatus, Tread};

/// The selected asperity ids and the multipoint problem on them.
pub type StepProblem<'r, L> = (Vec<usize>, Problem<&'r L>);

/// The sub-problem of one footprint position: the selected asperity ids and
/// the multipoint problem on them (gaps `H_i = z_max − z_i + s*`, the tread profile at the cap's contact
/// point, [`crate::Tread::contact_gap`]). `None` when nothing lies under the footprint.
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

pub(crate) fn select<L>(road: &Road<L>, config: &RollingConfig, xc: f64, ids: &mut Vec<usize>) {
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

pub(crate) fn build<'r, L: ContactLaw>(
    road: &'r Road<L>,
    material: Material,
    config: &RollingConfig,
    xc: f64,
    ids: &[usize],
) -> Result<Problem<&'r L>, RollingError> {
    build_at(road, material, config, xc, ids, false)
}

/// [`build`], with the asperities placed at their contact points instead
/// of their summits when `at_contact_points` (a coupled step: its
/// correction places each asperity's pressure where its contact is, and
/// the point kernel it corrects must start from the same place).
pub(crate) fn build_at<'r, L: ContactLaw>(
    road: &'r Road<L>,
    material: Material,
    config: &RollingConfig,
    xc: f64,
    ids: &[usize],
    at_contact_points: bool,
) -> Result<Problem<&'r L>, RollingError> {
    let (pos, z, laws, top) = (road.positions(), road.heights(), road.laws(), road.top());
    let yc = config.lateral;
    let positions = ids
        .iter()
        .map(|&i| {
            if at_contact_points {
                contact_point(road, config, xc, i)
            } else {
                pos[i]
            }
        })
        .collect();
    // The gap at each cap's contact point (the summit's when the road has
    // no summit radii): under a sloping tread it lies off the summit.
    let gaps = ids
        .iter()
        .map(|&i| {
            top - z[i]
                + config
                    .tread
                    .contact_gap(pos[i][0] - xc, pos[i][1] - yc, road.summit_radius(i))
                    .map_or(f64::INFINITY, |(s, _)| s)
        })
        .collect();
    let laws = ids.iter().map(|&i| &laws[i]).collect();
    Problem::new(positions, gaps, laws, material).map_err(|source| RollingError::Solve {
        position: xc,
        source,
    })
}

/// Where asperity `id`'s contact patch is centred under the footprint at
/// `xc`: its summit shifted towards the tread's lowest point
/// ([`crate::Tread::contact_gap`]); the summit without radii.
pub fn contact_point<L>(road: &Road<L>, config: &RollingConfig, xc: f64, id: usize) -> [f64; 2] {
    let p = road.positions()[id];
    let (xi, eta) = (p[0] - xc, p[1] - config.lateral);
    match config.tread.contact_gap(xi, eta, road.summit_radius(id)) {
        Some((_, [dx, dy])) => [p[0] + dx, p[1] + dy],
        None => p,
    }
}

pub(crate) fn imposed<L>(road: &Road<L>, control: RollingControl) -> Control {
    match control {
        RollingControl::Load(w) => Control::Load(w),
        RollingControl::Approach(d) => Control::Approach(d),
        RollingControl::TreadHeight(h) => Control::Approach(road.top() - h),
    }
}

#[cfg(test)]
thread_local! {
    /// Test hook: the step whose solve is made to fail (on this thread).
    pub(crate) static FAIL_STEP: std::cell::Cell<Option<usize>> =
        const { std::cell::Cell::new(None) };
}

/// The state carried from one step to the next (warm start): forces by
/// asperity (the road's local indices while rolling, global ids in a
/// checkpoint file; absent ones carry zero) and the approach.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Carry {
    pub ids: Vec<usize>,
    pub forces: Vec<f64>,
    pub approach: f64,
}

/// Per-chunk scratch: a dense id → force map for warm-start mapping, a
/// dense id → step index map, and the previous step's coupling
/// correction (road-local ids; empty when the previous step failed or
/// there was none).
pub(crate) struct Scratch {
    pub(crate) dense: Vec<f64>,
    pub(crate) ids: Vec<usize>,
    pub(crate) index: Vec<usize>,
    pub(crate) correction: KeptCorrection,
}

impl Scratch {
    pub(crate) fn new(len: usize) -> Self {
        Self {
            dense: vec![0.0; len],
            ids: Vec::new(),
            index: vec![usize::MAX; len],
            correction: Vec::new(),
        }
    }
}

pub(crate) fn solve_step<L: ContactLaw + Sync>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    k: usize,
    carry: &mut Option<Carry>,
    scratch: &mut Scratch,
    coupling: Option<&dyn StepCoupling<L>>,
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
        status: StepStatus::Converged,
        recovery: Recovery::None,
        residual: 0.0,
        clearance: boundary - approach,
        overlapping: 0,
        sensor_forces: vec![0.0; config.sensors.len()],
        contact_ids: Vec::new(),
        contact_forces: Vec::new(),
    };
    if scratch.ids.is_empty() {
        *carry = None;
        scratch.correction.clear();
        return match control {
            Control::Approach(d) => Ok(empty(d)),
            // No load and no asperity: the approach is undefined (−∞).
            Control::Load(0.0) => Ok(empty(f64::NEG_INFINITY)),
            Control::Load(_) => Err(RollingError::NoSupport { position: xc }),
        };
    }
    let ids = std::mem::take(&mut scratch.ids);
    let problem = build_at(road, material, config, xc, &ids, coupling.is_some())?;
    // The previous step's correction on the pairs still selected, in this
    // step's indices: the warm start of the coupling's fixed point.
    let warm_correction = match coupling {
        Some(_) => {
            for (a, &i) in ids.iter().enumerate() {
                scratch.index[i] = a;
            }
            let pairs: Vec<_> = scratch
                .correction
                .iter()
                .filter_map(|&(i, j, c)| {
                    let (a, b) = (scratch.index[i], scratch.index[j]);
                    (a != usize::MAX && b != usize::MAX).then_some((a, b, c))
                })
                .collect();
            for &i in &ids {
                scratch.index[i] = usize::MAX;
            }
            PairCorrection::new(ids.len(), pairs).map_err(|source| RollingError::Solve {
                position: xc,
                source,
            })?
        }
        None => PairCorrection::default(),
    };
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
        warm_correction.apply_add(&forces, &mut u);
        let depths = problem
            .gaps()
            .iter()
            .zip(&u)
            .map(|(h, u)| c.approach - h - u)
            .collect();
        Solution::warm_start(forces, depths, c.approach)
    });
    let options = SolverOptions {
        tolerance: config.tolerance,
        max_iterations: config.max_iterations,
        par: Par::Seq,
        ..SolverOptions::default()
    };
    #[cfg(test)]
    if FAIL_STEP.with(std::cell::Cell::get) == Some(k) {
        *carry = None;
        return Ok(failed_step(config, k, ids.len(), 0, 1.0));
    }
    let solved = match coupling {
        None => solve_from(&problem, control, &options, initial.as_ref()),
        Some(coupling) => {
            let fixed = fixed_point(
                &problem,
                &ids,
                (control, &options),
                initial.as_ref(),
                &warm_correction,
                coupling,
                (road, xc),
            )?;
            match fixed {
                Ok((solution, correction)) => {
                    scratch.correction = correction
                        .pairs()
                        .iter()
                        .map(|&(a, b, c)| (ids[a], ids[b], c))
                        .collect();
                    Ok(solution)
                }
                Err(e) => Err(e),
            }
        }
    };
    let solution = match solved {
        Ok(solution) => solution,
        // One step that does not converge is that step's failure, not the
        // run's: it is recorded with NaN values and the next step
        // cold-starts (a warm start from a failed state could only hurt).
        Err(SolveError::NotConverged {
            iterations,
            residual,
            ..
        }) => {
            *carry = None;
            scratch.correction.clear();
            return Ok(failed_step(config, k, ids.len(), iterations, residual));
        }
        Err(source) => {
            return Err(RollingError::Solve {
                position: xc,
                source,
            });
        }
    };
    let status = match solution.convergence {
        Convergence::Converged => StepStatus::Converged,
        Convergence::Stagnated { .. } => StepStatus::Stagnated,
    };
    let contacts = solution.local_contacts(&problem);
    let mut sensor_forces = vec![0.0; config.sensors.len()];
    let mut area = 0.0;
    let in_contact = solution.contact_count();
    let mut contact_ids = Vec::with_capacity(in_contact);
    let mut contact_forces = Vec::with_capacity(in_contact);
    for (a, (&i, &p)) in ids.iter().zip(&solution.forces).enumerate() {
        if p > 0.0 {
            contact_ids.push(road.global_id(i));
            contact_forces.push(p);
            area += contacts[a].area();
            // The patch is centred on the contact point, not the summit.
            let centre = contact_point(road, config, xc, i);
            let spread = coupling.and_then(|c| c.spread(problem.laws()[a], solution.depths[a]));
            for (f, s) in sensor_forces.iter_mut().zip(&config.sensors) {
                *f += match &spread {
                    Some(spread) => s.share_spread(centre, p, spread),
                    None => s.share(centre, &contacts[a]),
                };
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
        contacts: in_contact,
        selected: ids.len(),
        iterations: solution.iterations,
        status,
        recovery: solution.recovery,
        residual: solution.residual,
        clearance: boundary - solution.approach,
        overlapping: overlapping_contacts(problem.positions(), &contacts).len(),
        sensor_forces,
        contact_ids,
        contact_forces,
    };
    *carry = Some(Carry {
        ids,
        forces: solution.forces,
        approach: solution.approach,
    });
    Ok(record)
}

/// The coupled step's fixed point (crate::coupling): the solution and the
/// correction it was solved with, or the step's failure as a
/// [`SolveError::NotConverged`] (a round's solve that failed, or a fixed
/// point still moving after the coupling's rounds, its residual the last
/// change over the scale). The outer error is the run's.
#[allow(clippy::too_many_arguments)]
fn fixed_point<L: ContactLaw + Sync>(
    problem: &Problem<&L>,
    ids: &[usize],
    (control, options): (Control, &SolverOptions),
    initial: Option<&Solution>,
    warm: &PairCorrection,
    coupling: &dyn StepCoupling<L>,
    (road, xc): (&Road<L>, f64),
) -> Result<Result<(Solution, PairCorrection), SolveError>, RollingError> {
    let mut iterations = 0;
    let mut s = match solve_corrected(problem, control, options, initial, warm) {
        Ok(s) => s,
        Err(e) => return Ok(Err(e)),
    };
    iterations += s.iterations;
    let scale = match control {
        Control::Load(w) => w,
        Control::Approach(_) => s.forces.iter().sum(),
    };
    if !(scale > 0.0) {
        // Nothing in contact: nothing to couple.
        coupling.settled(0);
        return Ok(Ok((s, PairCorrection::default())));
    }
    let offsets: Vec<[f64; 2]> = ids
        .iter()
        .zip(problem.positions())
        .map(|(&i, p)| {
            let summit = road.positions()[i];
            [p[0] - summit[0], p[1] - summit[1]]
        })
        .collect();
    let mut change = f64::INFINITY;
    let mut previous = f64::INFINITY;
    let mut used = warm.clone();
    let mut weight = 1.0;
    for round in 1..=coupling.max_rounds() {
        let state = CouplingState {
            ids,
            problem,
            offsets: &offsets,
            depths: &s.depths,
            forces: &s.forces,
        };
        let mut c = coupling.correction(&state).map_err(|m| {
            RollingError::InvalidInput(format!("step at x = {xc} m: coupling: {m}"))
        })?;
        // From round DAMPED_AFTER + 1 on, a relaxed step `(1 − β) C_used +
        // β C(δ)`, β halved (down to 1/16) whenever a round did not halve
        // the change: two contacts whose patches overlap can make the
        // plain iteration cycle; the blend keeps the same fixed point
        // (where C(δ) is the C solved with) and damps the cycle.
        if round > DAMPED_AFTER {
            c = blend(&used, &c, weight, problem.len(), xc)?;
        }
        let next = match solve_corrected(problem, control, options, Some(&s), &c) {
            Ok(next) => next,
            Err(e) => return Ok(Err(e)),
        };
        iterations += next.iterations;
        used = c;
        change = next
            .forces
            .iter()
            .zip(&s.forces)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / scale;
        s = next;
        if round >= DAMPED_AFTER && change > 0.5 * previous {
            weight = (0.5 * weight).max(1.0 / 16.0);
        }
        previous = change;
        if change <= coupling.tolerance() {
            coupling.settled(round);
            s.iterations = iterations;
            return Ok(Ok((s, used)));
        }
    }
    Ok(Err(SolveError::NotConverged {
        iterations,
        load_steps: 0,
        residual: change,
    }))
}

/// Rounds of a coupled step's fixed point taken whole before each new
/// correction is blended with the one last solved with.
const DAMPED_AFTER: usize = 4;

/// `(1 − β) a + β b` pair by pair (a pair missing from one counts 0
/// there), for a problem of `n` asperities.
fn blend(
    a: &PairCorrection,
    b: &PairCorrection,
    beta: f64,
    n: usize,
    xc: f64,
) -> Result<PairCorrection, RollingError> {
    let mut sum: std::collections::BTreeMap<(usize, usize), f64> = Default::default();
    for (&(i, j, c), w) in a
        .pairs()
        .iter()
        .map(|p| (p, 1.0 - beta))
        .chain(b.pairs().iter().map(|p| (p, beta)))
    {
        *sum.entry((i.min(j), i.max(j))).or_insert(0.0) += w * c;
    }
    PairCorrection::new(n, sum.into_iter().map(|((i, j), c)| (i, j, c)).collect()).map_err(
        |source| RollingError::Solve {
            position: xc,
            source,
        },
    )
}

/// The record of a step whose solve failed: NaN values, no contacts.
pub(crate) fn failed_step(
    config: &RollingConfig,
    k: usize,
    selected: usize,
    iterations: usize,
    residual: f64,
) -> StepRecord {
    let xc = config.position(k);
    StepRecord {
        index: k,
        position: xc,
        time: xc / config.speed,
        total_force: f64::NAN,
        approach: f64::NAN,
        contact_area: f64::NAN,
        contacts: 0,
        selected,
        iterations,
        status: StepStatus::Failed,
        recovery: Recovery::None,
        residual,
        clearance: f64::NAN,
        overlapping: 0,
        sensor_forces: vec![f64::NAN; config.sensors.len()],
        contact_ids: Vec::new(),
        contact_forces: Vec::new(),
    }
}
