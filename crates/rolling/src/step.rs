//! One step of the path: the footprint's asperities selected by an
//! x-window, the sub-problem's gaps, and its solve warm-started from the
//! previous step's state ([`Carry`]).

use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::{
    Control, Convergence, PairCorrection, Par, Problem, Recovery, Solution, SolveError,
    SolverOptions, overlapping_contacts, solve_corrected,
};

use crate::coupling::{
    CouplingState, FixedPoint, FixedPointDamping, KeptCoupling, Start, StepCoupling, first_solve,
    force_scale, kept_stagnated,
};
use crate::placement::{placed_laws, step_laws, unplaced};
use crate::slope::SlopeMixer;
use crate::slope_rounds::{
    HELD_SLOPES_LIMIT, consistent_start, contact_radii, deformed_slopes, settle_slopes,
};
use crate::{
    ContactSlope, Road, RollingConfig, RollingControl, RollingError, StepRecord, StepStatus, Tread,
};

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
    unplaced(road)?;
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
    let laws = step_laws(road, ids, None);
    build_at(road, material, config, xc, ids, &laws, false, None)
}

/// [`build`], with the asperities placed at their contact points instead
/// of their summits when `at_contact_points` (a coupled step: its
/// correction places each asperity's pressure where its contact is, and
/// the point kernel it corrects must start from the same place), and the
/// tread tilted further at each asperity by `slopes` (the deformation's,
/// [`crate::deformation_slopes`]; `None`: the undeformed profile). `laws`
/// are the step's, one per id ([`step_laws`]).
#[allow(clippy::too_many_arguments)]
pub(crate) fn build_at<'p, L: ContactLaw>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    xc: f64,
    ids: &[usize],
    laws: &[&'p L],
    at_contact_points: bool,
    slopes: Option<&[[f64; 2]]>,
) -> Result<Problem<&'p L>, RollingError> {
    let (pos, z, top) = (road.positions(), road.heights(), road.top());
    let yc = config.lateral;
    // The gap at each cap's contact point (the summit's when the road has
    // no summit radii): under a sloping tread it lies off the summit.
    let (mut positions, mut gaps) = (Vec::with_capacity(ids.len()), Vec::with_capacity(ids.len()));
    for (a, &i) in ids.iter().enumerate() {
        let extra = slopes.map_or([0.0, 0.0], |s| s[a]);
        let touch = config.tread.contact_gap_sloped(
            pos[i][0] - xc,
            pos[i][1] - yc,
            road.summit_radius(i),
            extra,
        );
        let offset = touch.map_or([0.0, 0.0], |(_, d)| d);
        positions.push(if at_contact_points {
            [pos[i][0] + offset[0], pos[i][1] + offset[1]]
        } else {
            pos[i]
        });
        gaps.push(top - z[i] + touch.map_or(f64::INFINITY, |(s, _)| s));
    }
    Problem::new(positions, gaps, laws.to_vec(), material).map_err(|source| RollingError::Solve {
        position: xc,
        source,
    })
}

/// One footprint position solved cold as an uncoupled rolling step solves
/// it (the deformed tread's slopes settled with the forces when the
/// configuration asks for them): the selected ids, the problem the step
/// settled on, its solution and each asperity's contact point. For
/// diagnostics that re-solve a run's step under another control.
#[derive(Debug)]
pub struct SettledStep<'r, L> {
    /// Road-local ids, in the problem's order.
    pub ids: Vec<usize>,
    /// The step's problem (gaps at the settled contact points).
    pub problem: Problem<&'r L>,
    /// Its solution.
    pub solution: Solution,
    /// Each asperity's contact point (m), problem order.
    pub contact_points: Vec<[f64; 2]>,
}

/// [`SettledStep`] at footprint centre `xc` under `control`; `None` when
/// nothing lies under the footprint.
///
/// # Errors
/// [`RollingError::Solve`] when the solve or the slopes' iteration fails.
pub fn settled_step<'r, L: ContactLaw + Sync>(
    road: &'r Road<L>,
    material: Material,
    config: &RollingConfig,
    xc: f64,
    control: Control,
) -> Result<Option<SettledStep<'r, L>>, RollingError> {
    unplaced(road)?;
    let mut ids = Vec::new();
    select(road, config, xc, &mut ids);
    if ids.is_empty() {
        return Ok(None);
    }
    let mut slopes =
        (config.contact_slope == ContactSlope::Deformed).then(|| vec![[0.0, 0.0]; ids.len()]);
    let laws = step_laws(road, &ids, None);
    let mut problem = build_at(
        road,
        material,
        config,
        xc,
        &ids,
        &laws,
        false,
        slopes.as_deref(),
    )?;
    let options = SolverOptions {
        tolerance: config.tolerance,
        max_iterations: config.max_iterations,
        par: Par::Seq,
        ..SolverOptions::default()
    };
    let at = (road, material, config, xc);
    let solved = settle_slopes(
        at,
        (&ids, &laws),
        (&mut problem, &mut slopes),
        (control, &options),
        None,
    )?;
    // As the run's step: slopes that do not settle leave it to the profile's.
    let solved = or_on_the_profile_slope(solved, (&mut problem, &mut slopes), || {
        let mut retry = build_at(road, material, config, xc, &ids, &laws, false, None)?;
        let solved = settle_slopes(
            at,
            (&ids, &laws),
            (&mut retry, &mut None),
            (control, &options),
            None,
        )?;
        Ok(solved.ok().map(|s| (retry, s)))
    })?;
    let solution = solved.map_err(|source| RollingError::Solve {
        position: xc,
        source,
    })?;
    let contact_points = ids
        .iter()
        .enumerate()
        .map(|(a, &i)| {
            let extra = slopes.as_ref().map_or([0.0, 0.0], |s| s[a]);
            sloped_contact_point(road, config, xc, i, extra)
        })
        .collect();
    Ok(Some(SettledStep {
        ids,
        problem,
        solution,
        contact_points,
    }))
}

/// Where asperity `id`'s contact patch is centred under the footprint at
/// `xc`: its summit shifted towards the tread's lowest point
/// ([`crate::Tread::contact_gap`]); the summit without radii.
pub fn contact_point<L>(road: &Road<L>, config: &RollingConfig, xc: f64, id: usize) -> [f64; 2] {
    sloped_contact_point(road, config, xc, id, [0.0, 0.0])
}

fn sloped_contact_point<L>(
    road: &Road<L>,
    config: &RollingConfig,
    xc: f64,
    id: usize,
    extra: [f64; 2],
) -> [f64; 2] {
    let p = road.positions()[id];
    let (xi, eta) = (p[0] - xc, p[1] - config.lateral);
    match config
        .tread
        .contact_gap_sloped(xi, eta, road.summit_radius(id), extra)
    {
        Some((_, [dx, dy])) => [p[0] + dx, p[1] + dy],
        None => p,
    }
}

/// The contact points of a step's loaded asperities (`ids` road-local,
/// `forces` and contact `radii` in the same order) as the step placed
/// them: under the deformed tread ([`crate::ContactSlope::Deformed`], the
/// displacement slope of the other forces added to the profile's) or the
/// profile's ([`contact_point`]). For recounting a finished step's
/// sensors from its forces.
pub fn contact_points<L>(
    road: &Road<L>,
    material: Material,
    config: &RollingConfig,
    xc: f64,
    ids: &[usize],
    forces: &[f64],
    radii: &[f64],
) -> Vec<[f64; 2]> {
    let slopes = deformed_slopes(road, material, config, ids, forces, radii);
    ids.iter()
        .enumerate()
        .map(|(a, &i)| {
            let extra = slopes.as_ref().map_or([0.0, 0.0], |s| s[a]);
            sloped_contact_point(road, config, xc, i, extra)
        })
        .collect()
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
    pub(crate) correction: KeptCoupling,
    /// The last settled deformation slope of each asperity (road-local id;
    /// zero where none): the next step's first guess.
    pub(crate) slopes: Vec<[f64; 2]>,
}

impl Scratch {
    pub(crate) fn new(len: usize) -> Self {
        Self {
            dense: vec![0.0; len],
            ids: Vec::new(),
            index: vec![usize::MAX; len],
            correction: KeptCoupling::default(),
            slopes: vec![[0.0, 0.0]; len],
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
    // Under the deformed tread the slopes are the step's unknowns too: start
    // from each asperity's last ones.
    let mut slopes: Option<Vec<[f64; 2]>> = (config.contact_slope == ContactSlope::Deformed)
        .then(|| ids.iter().map(|&i| scratch.slopes[i]).collect());
    // The step's laws: placed at this footprint when the road says so.
    let placed = placed_laws(road, &ids, xc);
    let laws = step_laws(road, &ids, placed.as_deref());
    let at = (road, material, config, xc);
    let coupled = coupling.is_some();
    let (mut problem, initial, warm_correction) = step_start(
        at,
        (&ids, &laws),
        coupled,
        slopes.as_deref(),
        carry.as_ref(),
        scratch,
    )?;
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
    let laws_of = (ids.as_slice(), laws.as_slice());
    let how = (control, &options, coupling);
    let solved = solve_once(
        at,
        laws_of,
        how,
        (&mut problem, &mut slopes),
        (initial.as_ref(), &warm_correction),
        &mut scratch.correction,
    )?;
    // The deformed tread's slopes that do not settle (a ridge of flat tiles
    // along the path, whose contact points swing from end to end with the
    // slope) leave the step to the profile's slope, warm-started as the
    // step was, and marked: the step is kept short of the deformed tread by
    // the slopes' last move.
    let solved = or_on_the_profile_slope(solved, (&mut problem, &mut slopes), || {
        let (mut retry, initial, warm) =
            step_start(at, (&ids, &laws), coupled, None, carry.as_ref(), scratch)?;
        let warm = (initial.as_ref(), &warm);
        let kept = &mut scratch.correction;
        let solved = solve_once(at, laws_of, how, (&mut retry, &mut None), warm, kept)?;
        Ok(solved.ok().map(|s| (retry, s)))
    })?;
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
            let extra = slopes.as_ref().map_or([0.0, 0.0], |s| s[a]);
            let centre = sloped_contact_point(road, config, xc, i, extra);
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
    if let Some(slopes) = &slopes {
        for (&i, &g) in ids.iter().zip(slopes) {
            scratch.slopes[i] = g;
        }
    }
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
fn fixed_point<'p, L: ContactLaw + Sync>(
    (problem, slopes): (&mut Problem<&'p L>, &mut Option<Vec<[f64; 2]>>),
    (ids, laws): (&[usize], &[&'p L]),
    (control, options): (Control, &SolverOptions),
    initial: Option<&Solution>,
    warm: &PairCorrection,
    coupling: &dyn StepCoupling<L>,
    (road, material, config, xc): (&Road<L>, Material, &RollingConfig, f64),
) -> Result<Result<(Solution, PairCorrection), SolveError>, RollingError> {
    let carried = initial.is_some() || !warm.is_empty();
    let first = first_solve(carried, |start| match start {
        Start::Warm => solve_corrected(problem, control, options, initial, warm),
        Start::Cold => solve_corrected(problem, control, options, None, &PairCorrection::default()),
    });
    let first = match first {
        Ok(first) => first,
        Err(e) => return Ok(Err(e)),
    };
    let used = match first.start {
        Start::Warm => warm.clone(),
        Start::Cold => PairCorrection::default(),
    };
    let iterations = first.spent + first.solution.iterations;
    let scale = force_scale(control, &first.solution.forces);
    if !(scale > 0.0) {
        // Nothing in contact: nothing to couple.
        coupling.settled(0);
        return Ok(Ok((first.solution, PairCorrection::default())));
    }
    let mut fp = FixedPoint::new(first.solution, used, iterations);
    let offsets_of = |problem: &Problem<&L>| -> Vec<[f64; 2]> {
        ids.iter()
            .zip(problem.positions())
            .map(|(&i, p)| {
                let summit = road.positions()[i];
                [p[0] - summit[0], p[1] - summit[1]]
            })
            .collect()
    };
    let mut offsets = offsets_of(problem);
    // The rounds with the slopes moving; when those end unsettled, the same
    // fixed point again with the slopes held where they left them
    // (`HELD_SLOPES_LIMIT`), its residual the moving rounds' last change.
    //
    // Still unsettled at fixed slopes (held, or the profile's), the same
    // fixed point goes on from where it stopped under Aitken's damping
    // (`FixedPointDamping::aitken`): a contact drawing load round after
    // round crawls under the halving rule's floor.
    let mut held_after = None;
    for pass in [Pass::MovingSlopes, Pass::HeldSlopes, Pass::Aitken] {
        let change = fp.change;
        let unsettled = change > coupling.acceptable_tolerance();
        match pass {
            Pass::MovingSlopes => {}
            Pass::HeldSlopes if slopes.is_none() || !unsettled || change > HELD_SLOPES_LIMIT => {
                continue;
            }
            Pass::HeldSlopes => held_after = Some(change),
            // Slopes still moving too far to hold: the step's failure.
            Pass::Aitken if !unsettled || (slopes.is_some() && held_after.is_none()) => break,
            Pass::Aitken => {}
        }
        let move_slopes = pass == Pass::MovingSlopes;
        let mut damping = match pass {
            Pass::Aitken => FixedPointDamping::aitken(),
            _ => FixedPointDamping::default(),
        };
        let mut mixer = SlopeMixer::default();
        for round in 1..=coupling.max_rounds() {
            // The deformed tread's slopes follow the last round's forces (mixed
            // with the rounds before, as the uncoupled step's); the contact
            // points, gaps and kernel move with them.
            if let Some(current) = slopes.as_mut().filter(|_| move_slopes) {
                let radii = contact_radii(&fp.solution, problem);
                if let Some(next) =
                    deformed_slopes(road, material, config, ids, &fp.solution.forces, &radii)
                {
                    *current = mixer.next(current, &next);
                }
                *problem = build_at(road, material, config, xc, ids, laws, true, Some(current))?;
                offsets = offsets_of(problem);
                fp.solution = consistent_start(problem, &fp.solution, &fp.used);
            }
            let state = CouplingState {
                ids,
                problem,
                offsets: &offsets,
                depths: &fp.solution.depths,
                forces: &fp.solution.forces,
            };
            let c = coupling.correction(&state).map_err(|m| {
                RollingError::InvalidInput(format!("step at x = {xc} m: coupling: {m}"))
            })?;
            let c = damping
                .relax(round, &fp.used, c, problem.len())
                .map_err(|source| RollingError::Solve {
                    position: xc,
                    source,
                })?;
            let next = match solve_corrected(problem, control, options, Some(&fp.solution), &c) {
                Ok(next) => next,
                Err(e) => return Ok(Err(e)),
            };
            if fp.take((round, next, c), &mut damping, scale, coupling) {
                let s = match held_after {
                    Some(moving) => kept_stagnated(fp.solution, moving),
                    None => fp.solution,
                };
                return Ok(Ok((s, fp.used)));
            }
        }
    }
    Ok(fp.ended(held_after, coupling.acceptable_tolerance()))
}

/// The passes of a coupled step's fixed point ([`fixed_point`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Pass {
    /// The rounds, the deformed tread's slopes moving with them (or the
    /// profile's, fixed).
    MovingSlopes,
    /// The same fixed point with the slopes held where the first pass
    /// left them.
    HeldSlopes,
    /// The same again, at fixed slopes, under Aitken's damping.
    Aitken,
}

/// A step's problem under `slopes` ([`build_at`]; `None`: the profile's)
/// and its warm start: the previous step's forces mapped by asperity id
/// (new ones at zero) with consistent interpenetrations, and for a
/// `coupled` step the previous step's coupling on the pairs still
/// selected, at this problem's contact points.
#[allow(clippy::type_complexity)]
fn step_start<'p, L: ContactLaw>(
    (road, material, config, xc): (&Road<L>, Material, &RollingConfig, f64),
    (ids, laws): (&[usize], &[&'p L]),
    coupled: bool,
    slopes: Option<&[[f64; 2]]>,
    carry: Option<&Carry>,
    scratch: &mut Scratch,
) -> Result<(Problem<&'p L>, Option<Solution>, PairCorrection), RollingError> {
    let problem = build_at(road, material, config, xc, ids, laws, coupled, slopes)?;
    let correction = if coupled {
        scratch
            .correction
            .warm(
                ids,
                problem.positions(),
                material.boussinesq_factor(),
                &mut scratch.index,
            )
            .map_err(|source| RollingError::Solve {
                position: xc,
                source,
            })?
    } else {
        PairCorrection::default()
    };
    let initial = carry.map(|c| {
        for (&i, &p) in c.ids.iter().zip(&c.forces) {
            scratch.dense[i] = p;
        }
        let forces: Vec<f64> = ids.iter().map(|&i| scratch.dense[i]).collect();
        for &i in &c.ids {
            scratch.dense[i] = 0.0;
        }
        // Consistent local interpenetrations of the mapped state (the
        // solver may iterate on them).
        Solution::consistent_warm_start(&problem, forces, c.approach, &correction)
    });
    Ok((problem, initial, correction))
}

/// One attempt at a step's solve: the uncoupled step's slopes settled
/// ([`settle_slopes`]) or the coupled step's fixed point ([`fixed_point`]),
/// whose correction is kept in `kept` for the next step's warm start.
fn solve_once<'p, L: ContactLaw + Sync>(
    at: (&Road<L>, Material, &RollingConfig, f64),
    (ids, laws): (&[usize], &[&'p L]),
    (control, options, coupling): (Control, &SolverOptions, Option<&dyn StepCoupling<L>>),
    (problem, slopes): (&mut Problem<&'p L>, &mut Option<Vec<[f64; 2]>>),
    (initial, warm): (Option<&Solution>, &PairCorrection),
    kept: &mut KeptCoupling,
) -> Result<Result<Solution, SolveError>, RollingError> {
    let Some(coupling) = coupling else {
        return settle_slopes(
            at,
            (ids, laws),
            (problem, slopes),
            (control, options),
            initial,
        );
    };
    let fixed = fixed_point(
        (problem, slopes),
        (ids, laws),
        (control, options),
        initial,
        warm,
        coupling,
        at,
    )?;
    Ok(fixed.map(|(solution, correction)| {
        let factor = at.1.boussinesq_factor();
        kept.keep(ids, &correction, problem.positions(), factor);
        solution
    }))
}

/// `solved` (a step's solve under `slopes`) as it is, or, when the
/// deformed tread's slopes did not settle, `retry`'s solve of the step
/// under the profile's slope with its problem ([`on_the_profile_slope`]);
/// `problem` and `slopes` are then the retry's. A retry that fails too
/// leaves the first failure.
fn or_on_the_profile_slope<'p, L>(
    solved: Result<Solution, SolveError>,
    (problem, slopes): (&mut Problem<&'p L>, &mut Option<Vec<[f64; 2]>>),
    retry: impl FnOnce() -> Result<Option<(Problem<&'p L>, Solution)>, RollingError>,
) -> Result<Result<Solution, SolveError>, RollingError> {
    let (
        Err(SolveError::NotConverged {
            residual,
            iterations,
            ..
        }),
        Some(_),
    ) = (&solved, &*slopes)
    else {
        return Ok(solved);
    };
    let (moving, spent) = (*residual, *iterations);
    Ok(match retry()? {
        Some((on_profile, s)) => {
            *problem = on_profile;
            *slopes = None;
            Ok(on_the_profile_slope(s, moving, spent))
        }
        None => solved,
    })
}

/// A step solved under the tread's profile slope after its deformed
/// slopes did not settle: kept, marked stagnated at the slopes' last move
/// `moving` (over the load) with [`Recovery::ProfileSlope`], the failed
/// attempt's iterations `spent` counted.
fn on_the_profile_slope(s: Solution, moving: f64, spent: usize) -> Solution {
    let mut s = kept_stagnated(s, moving);
    s.recovery = Recovery::ProfileSlope;
    s.iterations += spent;
    s
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
