//! Clusters: asperities whose contact patches overlap, merged and solved as
//! one body (docs/theory.md §3, "Clusters").
//!
//! # Why
//!
//! Two Hertz-type contacts closer than about `0.6 a` have a mutual
//! compliance (point or distributed kernel) above their laws' tangent
//! self-compliance `1/k`: `diag(1/k) + T_AA` is indefinite along the
//! antisymmetric mode (one member loading, the other unloading) and the load
//! path folds before the imposed load. No step control reaches the load
//! from that branch. Merging the pair removes exactly that mode.
//!
//! # The cluster's law
//!
//! A cluster `c` of members `m` (gaps `H_m`) sits at the work-conjugate
//! centroid `x_c = Σ w_m x_m` (`w_m = P_m / Σ P` at the state it was found
//! in; equal weights without load), with gap `H_c = min H_m` and offsets
//! `h_m = H_m − H_c`. Its members share one interpenetration `D` less their
//! offsets, and the tread over them one displacement from the cluster's own
//! load, `s P_c`:
//!
//! ```text
//! P_c = g(δ_c − s P_c),   g(D) = Σ_m P_m^law(D − h_m),
//! s = κ f Σ_{m≠n} w_m w_n g(r_mn; a_m, a_n)        (f = 1/(π E*))
//! ```
//!
//! `s / κ` is the weighted mean of the members' mutual displacements under
//! the distributed (work-conjugate) kernel [`mutual_compliance`] at their
//! radii `a_m` (for two equal members, exactly the displacement each feels
//! from the other); `κ =` [`SHARED_DISPLACEMENT_SCALE`] `= 0.8` accounts for
//! the merged patch's pressure being spread over the union (calibrated on
//! the BEM). `P_c(δ_c)` is increasing with `dP_c/dδ_c = g'/(1 + s g')`
//! (the coarse start's law, [`ClusterLaw`]); the cluster couples to the
//! other bodies through the point (or distributed) kernel at its centroid.
//! Member forces are `P_m^law(D − h_m)`, scaled to sum to `P_c` exactly:
//! no load is lost or counted twice.
//!
//! # The outer loop
//!
//! Start from a state (the converged point solution under
//! [`Clusters::Always`]; the warm start and the uncoupled start after a
//! failure), merge every pair of bodies whose patches overlap there
//! (`r < a_m + a_n`), solve the reduced problem from the cold start, expand,
//! and repeat while the expanded state shows new overlaps (at most
//! [`MAX_ROUNDS`]). A reduced solve that fails widens the merging reach by
//! 1.5×, up to `2.25 (a_m + a_n)` (patches about to touch are merged too;
//! patches further apart stay separate, and the solve's failure is said). Merging only grows the
//! clusters, so the loop ends.

use tyreroad_contact_law::{ContactLaw, LawPoint, LocalContact, PressureProfile};
use tyreroad_core::UnionFind;

use super::options::{Clusters, CoarseLevels};
use super::start::uncoupled_start;
use super::{Control, SolverOptions, solve_attempts};
use crate::coarse::ClusterLaw;
use crate::{Problem, Recovery, Solution, SolveError, mutual_compliance};

/// The factor `κ` on the members' mean mutual displacement in a cluster's
/// shared displacement `s`: the patches of merged members are one patch,
/// whose pressure spreads over their union rather than peaking on each
/// summit, so they displace each other less than two separate Hertz patches
/// would. Calibrated on the project's BEM: two 20 mm spheres 0.5 to 2 mm
/// apart (0.35 to 1.4 Hertz radii) at 0.1 mm approach, where `κ = 1` gives
/// forces 4 to 10 % low, `κ = 0.8` within −1.7 … +2.2 %
/// (`tests/clusters.rs`).
pub(crate) const SHARED_DISPLACEMENT_SCALE: f64 = 0.8;

/// Most merge-and-solve rounds of one solve.
pub(crate) const MAX_ROUNDS: usize = 8;

/// The widest merging reach (in units of `a_m + a_n`) a failed reduced
/// solve may widen to: patches about to touch are merged, patches a few
/// radii apart are separate contacts, and merging them would replace the
/// model by another (three balls 10 mm apart merged into one body when the
/// inner solves were given one iteration).
const MAX_REACH: f64 = 2.25;

/// The law of one body of the clustered problem: an asperity alone, or a
/// cluster (see the module documentation).
pub(crate) struct BodyLaw<'a, L> {
    laws: &'a [L],
    cluster: ClusterLaw<'a, L>,
}

impl<L: ContactLaw> BodyLaw<'_, L> {
    fn single(&self) -> Option<usize> {
        match self.cluster.members() {
            [m] => Some(*m),
            _ => None,
        }
    }
}

impl<L: ContactLaw> ContactLaw for BodyLaw<'_, L> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        match self.single() {
            Some(m) => self.laws[m].evaluate(depth),
            None => self.cluster.evaluate(depth),
        }
    }

    /// A lone asperity's own contact; a cluster's is the circle of the
    /// members' summed areas (it only sizes the distributed kernel).
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if let Some(m) = self.single() {
            return self.laws[m].local_contact(force, depth);
        }
        if !(force > 0.0) {
            return LocalContact::NONE;
        }
        let d = self.cluster.inner_depth(depth);
        let area: f64 = self
            .cluster
            .members()
            .iter()
            .zip(self.cluster.offsets())
            .map(|(&m, &h)| {
                let law = &self.laws[m];
                law.local_contact(law.force(d - h), d - h).radius.powi(2)
            })
            .sum();
        LocalContact {
            force,
            radius: area.sqrt(),
            profile: PressureProfile::Hertz,
        }
    }
}

/// Pairs of loaded contacts with `r_ij < reach (a_i + a_j)`, by a sweep
/// along x (as [`overlapping_contacts`](crate::overlapping_contacts)).
fn near_pairs(
    positions: &[[f64; 2]],
    contacts: &[LocalContact],
    reach: f64,
) -> Vec<(usize, usize)> {
    let mut loaded: Vec<usize> = (0..contacts.len())
        .filter(|&i| contacts[i].force > 0.0 && contacts[i].radius > 0.0)
        .collect();
    let a = |i: usize| reach * contacts[i].radius;
    loaded.sort_by(|&i, &j| (positions[i][0] - a(i)).total_cmp(&(positions[j][0] - a(j))));
    let mut pairs = Vec::new();
    for (k, &i) in loaded.iter().enumerate() {
        let right = positions[i][0] + a(i);
        for &j in &loaded[k + 1..] {
            if positions[j][0] - a(j) >= right {
                break;
            }
            let (dx, dy) = (
                positions[i][0] - positions[j][0],
                positions[i][1] - positions[j][1],
            );
            if dx * dx + dy * dy < (a(i) + a(j)).powi(2) {
                pairs.push((i, j));
            }
        }
    }
    pairs
}

/// One body of the clustered problem.
struct Body {
    members: Vec<usize>,
    offsets: Vec<f64>,
    gap: f64,
    position: [f64; 2],
    compliance: f64,
}

/// The bodies of `groups` at the state `forces`, `contacts`.
fn bodies<L: ContactLaw>(
    problem: &Problem<L>,
    groups: Vec<Vec<usize>>,
    forces: &[f64],
    contacts: &[LocalContact],
) -> Vec<Body> {
    let (pos, gaps) = (problem.positions(), problem.gaps());
    let f = problem.material().boussinesq_factor();
    groups
        .into_iter()
        .map(|members| {
            if let [m] = members[..] {
                return Body {
                    members,
                    offsets: vec![0.0],
                    gap: gaps[m],
                    position: pos[m],
                    compliance: 0.0,
                };
            }
            let total: f64 = members.iter().map(|&m| forces[m].max(0.0)).sum();
            let w: Vec<f64> = members
                .iter()
                .map(|&m| {
                    if total > 0.0 {
                        forces[m].max(0.0) / total
                    } else {
                        1.0 / members.len() as f64
                    }
                })
                .collect();
            let mut position = [0.0; 2];
            for (&m, &wm) in members.iter().zip(&w) {
                position[0] += wm * pos[m][0];
                position[1] += wm * pos[m][1];
            }
            let mut s = 0.0;
            for (a, (&m, &wm)) in members.iter().zip(&w).enumerate() {
                for (&n, &wn) in members[a + 1..].iter().zip(&w[a + 1..]) {
                    let r = (pos[m][0] - pos[n][0]).hypot(pos[m][1] - pos[n][1]);
                    let g = mutual_compliance(r, contacts[m].radius, contacts[n].radius);
                    s += 2.0 * wm * wn * g;
                }
            }
            let gap = members
                .iter()
                .map(|&m| gaps[m])
                .fold(f64::INFINITY, f64::min);
            Body {
                offsets: members.iter().map(|&m| gaps[m] - gap).collect(),
                members,
                gap,
                position,
                compliance: SHARED_DISPLACEMENT_SCALE * f * s,
            }
        })
        .collect()
}

/// The clustered problem of `bodies`.
fn reduced<'a, L: ContactLaw>(
    problem: &'a Problem<L>,
    bodies: &[Body],
) -> Result<Problem<BodyLaw<'a, L>>, SolveError> {
    let laws = bodies
        .iter()
        .map(|b| BodyLaw {
            laws: problem.laws(),
            cluster: ClusterLaw::new(
                problem.laws(),
                b.members.clone(),
                b.offsets.clone(),
                b.compliance,
            ),
        })
        .collect();
    Problem::new(
        bodies.iter().map(|b| b.position).collect(),
        bodies.iter().map(|b| b.gap).collect(),
        laws,
        *problem.material(),
    )
}

/// The full problem's state from the clustered solution `rs`.
fn expand<L: ContactLaw>(
    problem: &Problem<L>,
    bodies: &[Body],
    rs: Solution,
    iterations: usize,
) -> Solution {
    let n = problem.len();
    let (mut forces, mut depths) = (vec![0.0; n], vec![0.0; n]);
    let mut clusters = Vec::new();
    for (b, body) in bodies.iter().enumerate() {
        let (pc, dc) = (rs.forces[b], rs.depths[b]);
        if let [m] = body.members[..] {
            forces[m] = pc;
            depths[m] = dc;
            continue;
        }
        let d = dc - body.compliance * pc;
        let mut sum = 0.0;
        for (&m, &h) in body.members.iter().zip(&body.offsets) {
            depths[m] = d - h;
            forces[m] = problem.laws()[m].force(d - h);
            sum += forces[m];
        }
        // g(D) differs from P_c by the body's residual: scale so that the
        // members carry exactly the cluster's force.
        if sum > 0.0 {
            for &m in &body.members {
                forces[m] *= pc / sum;
            }
        }
        clusters.push(body.members.clone());
    }
    Solution {
        forces,
        depths,
        approach: rs.approach,
        iterations,
        load_steps: rs.load_steps,
        residual: rs.residual,
        convergence: rs.convergence,
        recovery: Recovery::Clustered,
        clusters,
    }
}

/// Solves the problem of `bodies` and expands it; `spent` counts the
/// iterations of every attempt.
fn solve_bodies<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    levels: &CoarseLevels,
    bodies: &[Body],
    spent: &mut usize,
) -> Result<Solution, SolveError> {
    let small = reduced(problem, bodies)?;
    let attempt = solve_attempts(&small, control, options, None, levels, &[]);
    if std::env::var_os("TYREROAD_PROFILE").is_some() {
        let sizes: Vec<usize> = bodies
            .iter()
            .map(|b| b.members.len())
            .filter(|&m| m > 1)
            .collect();
        eprintln!(
            "clusters: {} bodies, cluster sizes {sizes:?}: residual {:?}",
            bodies.len(),
            attempt.as_ref().map(|s| s.residual)
        );
    }
    match attempt {
        Ok(rs) => {
            *spent += rs.iterations;
            Ok(expand(problem, bodies, rs, *spent))
        }
        Err(SolveError::NotConverged {
            iterations,
            load_steps,
            residual,
        }) => {
            *spent += iterations;
            Err(SolveError::NotConverged {
                iterations: *spent,
                load_steps,
                residual,
            })
        }
        Err(e) => Err(e),
    }
}

/// Applies [`SolverOptions::clusters`] to the point solve's `result`.
pub(super) fn refine<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    initial: Option<&Solution>,
    levels: &CoarseLevels,
    result: Result<Solution, SolveError>,
) -> Result<Solution, SolveError> {
    let positions = problem.positions();
    let mut uf = UnionFind::new(problem.len());
    let mut seeded = 0;
    let (mut state, mut spent, failure) = match (options.clusters, result) {
        (Clusters::Always, Ok(s)) => {
            let pairs = near_pairs(positions, &s.local_contacts(problem), 1.0);
            if pairs.is_empty() {
                return Ok(s);
            }
            (s, 0, None)
        }
        (Clusters::OnFailure | Clusters::Always, Err(e @ SolveError::NotConverged { .. })) => {
            let SolveError::NotConverged { iterations, .. } = e else {
                return Err(e);
            };
            // Where the fold is not known, merge what overlaps at the warm
            // start and at the uncoupled start (which overestimates the
            // loads of the highest summits, so errs towards merging).
            let zeros = vec![0.0; problem.len()];
            let (forces, d0) = uncoupled_start(problem, control, &zeros);
            let depths = problem.gaps().iter().map(|h| d0 - h).collect();
            let cold = Solution::warm_start(forces, depths, d0);
            for (i, j) in near_pairs(positions, &cold.local_contacts(problem), 1.0) {
                seeded += usize::from(uf.union(i, j));
            }
            let seed = match initial {
                Some(w) if w.forces.len() == problem.len() => w.clone(),
                _ => cold,
            };
            (seed, iterations, Some(e))
        }
        (_, result) => return result,
    };
    let inner = SolverOptions {
        clusters: Clusters::Off,
        ..*options
    };
    let (mut best, mut last_ok, mut last_err, mut reach) = (None, false, failure, 1.0);
    for _ in 0..MAX_ROUNDS {
        let contacts = state.local_contacts(problem);
        let mut merged = std::mem::take(&mut seeded);
        for (i, j) in near_pairs(positions, &contacts, reach) {
            merged += usize::from(uf.union(i, j));
        }
        let fresh = bodies(problem, uf.groups(), &state.forces, &contacts);
        if merged == 0 {
            if !last_ok {
                if reach >= MAX_REACH {
                    break;
                }
                // Nothing new to merge and no solution of these clusters:
                // merge the patches that are about to touch too.
                reach = (reach * 1.5).min(MAX_REACH);
                continue;
            }
            // Same clusters: done. (Re-solving with the weights and radii
            // of the clustered solution was tried: on two spheres it moved
            // the force away from the BEM's, −10 → −21 %.)
            break;
        }
        match solve_bodies(problem, control, &inner, levels, &fresh, &mut spent) {
            Ok(s) => {
                state = s.clone();
                best = Some(s);
                (last_ok, reach) = (true, 1.0);
            }
            Err(e @ SolveError::NotConverged { .. }) => {
                (last_ok, reach) = (false, (reach * 1.5).min(MAX_REACH));
                last_err = Some(e);
            }
            // A clustering that cannot be built (a body placed by forces
            // that overflowed: "position [NaN, NaN]") ends the recovery;
            // the solve's own failure, with its residual, is what to say.
            Err(_) if last_err.is_some() => break,
            Err(e) => return Err(e),
        }
    }
    match (best, last_err) {
        (Some(s), _) => Ok(s),
        (None, Some(e)) => Err(e),
        (None, None) => Err(SolveError::NotConverged {
            iterations: spent,
            load_steps: 0,
            residual: f64::NAN,
        }),
    }
}
