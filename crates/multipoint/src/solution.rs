//! The solved state, and what is rebuilt from it: local contacts and maps.

use tyreroad_contact_law::{ContactLaw, LocalContact};
use tyreroad_core::{Field, Grid};

use crate::{Boussinesq, PairCorrection, Par, Problem, SolveError};

/// The local interpenetrations `δ_i = δ0 − H_i − u_i` at approach `δ0`
/// and interaction displacements `u`.
pub(crate) fn interpenetrations<L: ContactLaw>(
    problem: &Problem<L>,
    approach: f64,
    u: &[f64],
) -> Vec<f64> {
    problem
        .gaps()
        .iter()
        .zip(u)
        .map(|(h, u)| approach - h - u)
        .collect()
}

/// How a returned solution met its convergence test (docs/theory.md §3).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Convergence {
    /// Every force residual and the load equation within
    /// [`SolverOptions::tolerance`](crate::SolverOptions) of the force scale
    /// (a residual may exceed it by its own rounding floor, see there).
    Converged,
    /// The iteration stagnated (no step length decreased the merit, after
    /// every recovery) with the load equation within the tolerance and the
    /// largest relative force residual `residual` between the tolerance and
    /// [`SolverOptions::acceptable_tolerance`](crate::SolverOptions).
    Stagnated {
        /// Largest force residual relative to the force scale.
        residual: f64,
    },
}

/// Which attempt produced a solution, in the order they are tried.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Recovery {
    /// The first Newton run from the given (warm or cold) start.
    None,
    /// Load (or approach) continuation after the first run failed.
    Continuation,
    /// A Newton run from the cold (uncoupled or coarse) start, after a warm
    /// start and the continuation failed.
    ColdRestart,
    /// Newton with dense factorizations, after Krylov steps stalled.
    DenseFallback,
    /// Newton with a Levenberg–Marquardt shift of the step's matrix, after
    /// every plain run stalled.
    Regularized,
    /// The asperities whose contact patches overlap merged into clusters,
    /// each solved as one body ([`Solution::clusters`], docs/theory.md §3):
    /// after every other recovery failed
    /// ([`Clusters::OnFailure`](crate::Clusters)), or because overlaps were
    /// found under [`Clusters::Always`](crate::Clusters).
    Clustered,
    /// Never set by the solver: a rolling step (`tyreroad-rolling`) whose
    /// deformed tread's slopes did not settle, solved again under the
    /// tread's undeformed profile.
    ProfileSlope,
}

/// A solved multipoint contact.
///
/// Invariants: `forces[i] ≥ 0`; an asperity out of contact
/// (`depths[i] ≤ 0`) carries exactly zero; every residual
/// `|P_i − P_i^law(δ_i)|` meets `convergence` (`residual` reports the
/// largest, relative to the force scale).
#[derive(Clone, Debug, PartialEq)]
pub struct Solution {
    /// Force `P_i` on each asperity (N).
    pub forces: Vec<f64>,
    /// Local interpenetration `δ_i = δ0 − H_i − u_i` (m); negative out of contact.
    pub depths: Vec<f64>,
    /// Rigid approach `δ0` of the tread (m).
    pub approach: f64,
    /// Newton iterations, all load steps included.
    pub iterations: usize,
    /// Load steps used (1 when the direct solve converged, 0 for a trivial
    /// contact-free problem).
    pub load_steps: usize,
    /// Final max-norm residual relative to the force scale.
    pub residual: f64,
    /// Whether the tolerance was met or the solve stagnated just above it.
    pub convergence: Convergence,
    /// The attempt that produced this solution.
    pub recovery: Recovery,
    /// The clusters the solution was solved with (asperity indices, each
    /// sorted, at least two members; empty unless
    /// [`Recovery::Clustered`]). A cluster's members share one
    /// interpenetration less their offsets; their forces sum to the
    /// cluster's.
    pub clusters: Vec<Vec<usize>>,
}

impl Solution {
    /// The solution with forces `forces` and their interaction
    /// displacements `u` (the depths are `δ0 − H − u`).
    pub(crate) fn assemble<L: ContactLaw>(
        problem: &Problem<L>,
        forces: Vec<f64>,
        approach: f64,
        iterations: usize,
        load_steps: usize,
        residual: f64,
        u: Vec<f64>,
    ) -> Self {
        Self {
            depths: interpenetrations(problem, approach, &u),
            forces,
            approach,
            iterations,
            load_steps,
            residual,
            convergence: Convergence::Converged,
            recovery: Recovery::None,
            clusters: Vec::new(),
        }
    }

    /// A warm start at `forces` and `approach` with the local
    /// interpenetrations they imply under the coupling `T + correction`,
    /// `δ = δ0 − H − (T + C) P` (a previous state carried to moved gaps or
    /// contact points; the solver may iterate on them).
    pub fn consistent_warm_start<L: ContactLaw>(
        problem: &Problem<L>,
        forces: Vec<f64>,
        approach: f64,
        correction: &PairCorrection,
    ) -> Self {
        let mut u = vec![0.0; forces.len()];
        Boussinesq::new(problem.positions(), problem.material().boussinesq_factor()).apply(
            &forces,
            &mut u,
            Par::Seq,
        );
        correction.apply_add(&forces, &mut u);
        let depths = interpenetrations(problem, approach, &u);
        Self::warm_start(forces, depths, approach)
    }

    /// A state to warm-start [`solve_from`](crate::solve_from) with: forces,
    /// local interpenetrations and approach (the bookkeeping fields empty).
    pub fn warm_start(forces: Vec<f64>, depths: Vec<f64>, approach: f64) -> Self {
        Self {
            forces,
            depths,
            approach,
            iterations: 0,
            load_steps: 0,
            residual: f64::NAN,
            convergence: Convergence::Converged,
            recovery: Recovery::None,
            clusters: Vec::new(),
        }
    }

    /// Assembles a converged state, zeroing exactly the forces left on
    /// asperities out of contact (they are below the tolerance already).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn finish<L: ContactLaw>(
        problem: &Problem<L>,
        forces: Vec<f64>,
        approach: f64,
        iterations: usize,
        load_steps: usize,
        residual: f64,
        u: Vec<f64>,
    ) -> Self {
        let mut s = Self::assemble(
            problem, forces, approach, iterations, load_steps, residual, u,
        );
        for (p, d) in s.forces.iter_mut().zip(&s.depths) {
            if !(*d > 0.0) || *p < 0.0 {
                *p = 0.0;
            }
        }
        s
    }

    /// `Σ P_i` (N).
    pub fn total_force(&self) -> f64 {
        self.forces.iter().sum()
    }

    /// Whether asperity `i` is in contact (carries a force).
    pub fn in_contact(&self, i: usize) -> bool {
        self.forces[i] > 0.0
    }

    /// Number of asperities in contact.
    pub fn contact_count(&self) -> usize {
        self.forces.iter().filter(|&&p| p > 0.0).count()
    }

    /// The local contact of every asperity (radius, pressure profile), from
    /// its law's local rule (Hertz for spheres).
    pub fn local_contacts<L: ContactLaw>(&self, problem: &Problem<L>) -> Vec<LocalContact> {
        problem
            .laws()
            .iter()
            .zip(self.forces.iter().zip(&self.depths))
            .map(|(law, (&p, &d))| law.local_contact(p, d))
            .collect()
    }
}

/// The pressure map (Pa) of the whole contact patch: the sum of every local
/// contact's pressure distribution centred on its summit, sampled at the
/// cell centres `origin + (i dx, j dy)` of `grid` (see docs/theory.md).
///
/// Sampled, not integrated: a contact whose patch holds no cell centre
/// (a radius under half a cell) is not on the map, and one holding a few
/// is coarsely resolved; take cells a fraction of the smallest contact
/// radius where the map's integral must be the load.
///
/// # Errors
/// [`SolveError::InvalidInput`] when the lengths differ, a position is not
/// finite, or a contact's force or radius is negative or not finite.
pub fn pressure_map(
    positions: &[[f64; 2]],
    contacts: &[LocalContact],
    grid: &Grid,
) -> Result<Field, SolveError> {
    if positions.len() != contacts.len() {
        return Err(SolveError::InvalidInput(format!(
            "{} positions for {} local contacts",
            positions.len(),
            contacts.len()
        )));
    }
    let bad = contacts.iter().zip(positions).position(|(c, p)| {
        !(p.iter().all(|v| v.is_finite())
            && c.force.is_finite()
            && c.force >= 0.0
            && c.radius.is_finite()
            && c.radius >= 0.0)
    });
    if let Some(i) = bad {
        return Err(SolveError::InvalidInput(format!(
            "contact {i} at {:?}: force {:e} N and radius {:e} m must be finite and ≥ 0, \
             its position finite",
            positions[i], contacts[i].force, contacts[i].radius
        )));
    }
    let (nx, ny) = (grid.nx(), grid.ny());
    let [x0, y0] = grid.origin();
    let mut map = vec![0.0; grid.len()];
    for (c, [xc, yc]) in contacts.iter().zip(positions) {
        if !(c.radius > 0.0) {
            continue;
        }
        // Only the cells whose centres can lie within the contact.
        let cell = |v: f64, v0: f64, d: f64, n: usize| -> usize {
            (((v - v0) / d).max(0.0) as usize).min(n)
        };
        let (i0, i1) = (
            cell(xc - c.radius, x0, grid.dx(), nx),
            (cell(xc + c.radius, x0, grid.dx(), nx) + 2).min(nx),
        );
        let (j0, j1) = (
            cell(yc - c.radius, y0, grid.dy(), ny),
            (cell(yc + c.radius, y0, grid.dy(), ny) + 2).min(ny),
        );
        for j in j0..j1 {
            let y = grid.y(j);
            for i in i0..i1 {
                let x = grid.x(i);
                map[grid.index(i, j)] += c.pressure_at((x - xc).hypot(y - yc));
            }
        }
    }
    Field::new(grid.clone(), map).map_err(|e| SolveError::InvalidInput(e.to_string()))
}

/// Pairs `(i, j)`, `i < j`, of loaded asperities whose local contacts
/// overlap: `a_i + a_j` greater than the distance between their summits.
///
/// The model couples asperities through point forces at their summits,
/// which holds while each contact patch is small against the distance to
/// its neighbours; overlapping patches (merging contacts on flat-topped
/// chippings, or summits of one ridge) are where the model's own premise
/// fails, and its forces there are to be read with care
/// (docs/validation.md). `contacts` are a solution's
/// [`Solution::local_contacts`], `positions` the problem's. Cost `O(N log N)` plus the pairs found:
/// a sweep along x over the contacts sorted by their left edge.
pub fn overlapping_contacts(
    positions: &[[f64; 2]],
    contacts: &[LocalContact],
) -> Vec<(usize, usize)> {
    let mut loaded: Vec<usize> = (0..contacts.len().min(positions.len()))
        .filter(|&i| contacts[i].force > 0.0 && contacts[i].radius > 0.0)
        .collect();
    let left = |i: usize| positions[i][0] - contacts[i].radius;
    loaded.sort_by(|&a, &b| left(a).total_cmp(&left(b)));
    let mut pairs = Vec::new();
    for (k, &i) in loaded.iter().enumerate() {
        let [xi, yi] = positions[i];
        let right = xi + contacts[i].radius;
        for &j in &loaded[k + 1..] {
            // Overlap needs x_j − a_j < x_i + a_i: sorted by left edge,
            // no later contact reaches i once one left edge is past.
            if left(j) >= right {
                break;
            }
            let [xj, yj] = positions[j];
            let reach = contacts[i].radius + contacts[j].radius;
            if (xi - xj).powi(2) + (yi - yj).powi(2) < reach * reach {
                pairs.push((i.min(j), i.max(j)));
            }
        }
    }
    pairs.sort_unstable();
    pairs
}
