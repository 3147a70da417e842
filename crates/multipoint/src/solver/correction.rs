//! A fixed, caller-supplied correction of the coupling: the solver solves
//!
//! ```text
//! P_i = P_i^law(δ0 − H_i − Σ_j (T_ij + C_ij) P_j)
//! ```
//!
//! with `T` the point kernel (exact or fast) and `C` a sparse symmetric
//! matrix of numbers the caller computed, e.g. from each asperity's own
//! pressure field (the `calibrated_fields` rung of `tyreroad::fidelity`).
//! The solver knows nothing of where `C` comes from; it adds `C P` to every
//! displacement (residuals, final `u`), `C_AA` to the dense active matrix
//! and `C x` to the Krylov products, exactly as it does for the
//! distributed kernel's near pairs (`near.rs`). A caller whose `C` depends
//! on the state iterates outside: solve, recompute `C` at the solution,
//! solve again from it.
//!
//! Clusters are not applied to a corrected solve: a merged body has no
//! entry in `C`, so a solve that needs them fails with
//! [`SolveError::NotConverged`] instead of silently dropping the
//! correction.

use tyreroad_contact_law::ContactLaw;

use super::options::{Clusters, CoarseLevels};
use super::{Control, SolverOptions, solve_attempts};
use crate::{Problem, Solution, SolveError};

/// A sparse symmetric correction `C` of the interaction matrix: entries
/// `(i, j, C_ij)` with `i ≠ j`, each unordered pair at most once (m/N).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PairCorrection {
    pairs: Vec<(usize, usize, f64)>,
}

impl PairCorrection {
    /// The correction of a problem of `n` asperities.
    ///
    /// # Errors
    /// [`SolveError::InvalidInput`] for an index `≥ n`, a diagonal entry
    /// (`i = j`: the self-compliance belongs to the law), a non-finite
    /// value, or an unordered pair given twice.
    pub fn new(n: usize, pairs: Vec<(usize, usize, f64)>) -> Result<Self, SolveError> {
        let mut seen = std::collections::HashSet::with_capacity(pairs.len());
        for &(i, j, c) in &pairs {
            if i >= n || j >= n {
                return Err(SolveError::InvalidInput(format!(
                    "pair correction ({i}, {j}) out of {n} asperities"
                )));
            }
            if i == j {
                return Err(SolveError::InvalidInput(format!(
                    "pair correction ({i}, {i}) is diagonal: the self-compliance is the law's"
                )));
            }
            if !c.is_finite() {
                return Err(SolveError::InvalidInput(format!(
                    "pair correction ({i}, {j}) = {c}: expected a finite value (m/N)"
                )));
            }
            if !seen.insert((i.min(j), i.max(j))) {
                return Err(SolveError::InvalidInput(format!(
                    "pair correction ({i}, {j}) given twice"
                )));
            }
        }
        Ok(Self { pairs })
    }

    /// The entries `(i, j, C_ij)`, each unordered pair once.
    pub fn pairs(&self) -> &[(usize, usize, f64)] {
        &self.pairs
    }

    /// Number of pairs.
    pub fn len(&self) -> usize {
        self.pairs.len()
    }

    /// Whether there are no pairs (the plain kernel).
    pub fn is_empty(&self) -> bool {
        self.pairs.is_empty()
    }

    /// `out += C x` (`x`, `out` of the problem's length).
    pub fn apply_add(&self, x: &[f64], out: &mut [f64]) {
        for &(i, j, c) in &self.pairs {
            out[i] += c * x[j];
            out[j] += c * x[i];
        }
    }
}

/// Solves `problem` under `control` with the coupling `T + C`, from
/// `initial` (warm) or cold. An empty `correction` is [`super::solve_from`]
/// exactly (clusters included); a non-empty one skips the clusters (module
/// docs).
///
/// # Errors
/// As [`super::solve_from`]; [`SolveError::InvalidInput`] when the
/// correction was built for another number of asperities (an index out of
/// range).
pub fn solve_corrected<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    control: Control,
    options: &SolverOptions,
    initial: Option<&Solution>,
    correction: &PairCorrection,
) -> Result<Solution, SolveError> {
    if correction.is_empty() {
        return super::solve_from(problem, control, options, initial);
    }
    let n = problem.len();
    if let Some(&(i, j, _)) = correction.pairs.iter().find(|(i, j, _)| *i >= n || *j >= n) {
        return Err(SolveError::InvalidInput(format!(
            "pair correction ({i}, {j}) out of {n} asperities"
        )));
    }
    let options = SolverOptions {
        clusters: Clusters::Off,
        ..*options
    };
    solve_attempts(
        problem,
        control,
        &options,
        initial,
        &CoarseLevels::DEFAULT,
        &correction.pairs,
    )
    .and_then(|s| super::checked(s, control, &options))
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use crate::{LinearSolver, Problem};
    use tyreroad_asperity::Sphere;
    use tyreroad_contact_law::{Material, PotentialLaw};

    fn problem(n: usize) -> Problem<PotentialLaw<Sphere>> {
        let m = Material::new(6.54e6, 0.5).unwrap();
        let law = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), m);
        let positions = (0..n).map(|k| [k as f64 * 6e-3, 0.0]).collect();
        let heights = (0..n).map(|k| -(k as f64) * 5e-6).collect();
        Problem::new(positions, heights, vec![law; n], m).unwrap()
    }

    #[test]
    fn bad_pairs_are_named_errors() {
        for pairs in [
            vec![(0, 3, 1.0)],
            vec![(1, 1, 1.0)],
            vec![(0, 1, f64::NAN)],
            vec![(0, 1, 1.0), (1, 0, 2.0)],
        ] {
            assert!(matches!(
                PairCorrection::new(3, pairs),
                Err(SolveError::InvalidInput(_))
            ));
        }
        let c = PairCorrection::new(5, vec![(0, 4, 1.0)]).unwrap();
        assert!(matches!(
            solve_corrected(
                &problem(3),
                Control::Load(1.0),
                &SolverOptions::default(),
                None,
                &c
            ),
            Err(SolveError::InvalidInput(_))
        ));
    }

    /// A correction that cancels the point kernel between two asperities
    /// (`C_01 = −T_01`) uncouples them: each then carries what its law
    /// gives at the common approach, whatever the other does. Dense and
    /// Krylov agree.
    #[test]
    fn cancelling_the_kernel_uncouples_the_pair() {
        let p = problem(3);
        let f = p.material().boussinesq_factor();
        let t01 = f / 6e-3;
        let c = PairCorrection::new(3, vec![(0, 1, -t01)]).unwrap();
        for linear_solver in [LinearSolver::Dense, LinearSolver::Krylov] {
            let options = SolverOptions {
                linear_solver,
                ..SolverOptions::default()
            };
            let s = solve_corrected(&p, Control::Load(6.0), &options, None, &c).unwrap();
            assert!((s.forces.iter().sum::<f64>() - 6.0).abs() < 1e-9);
            // u_0 comes from asperity 2 alone (12 mm away), u_1 from
            // asperity 2 (6 mm): u = δ0 − H − δ of the solution.
            let u = |i: usize| s.approach - p.gaps()[i] - s.depths[i];
            let u0 = f / 12e-3 * s.forces[2];
            let u1 = f / 6e-3 * s.forces[2];
            assert!(
                (u(0) - u0).abs() < 1e-7 * u0,
                "{linear_solver:?}: {} vs {u0}",
                u(0)
            );
            assert!(
                (u(1) - u1).abs() < 1e-7 * u1,
                "{linear_solver:?}: {} vs {u1}",
                u(1)
            );
        }
        // The empty correction is the plain solve, bit for bit.
        let empty = PairCorrection::default();
        let a = solve_corrected(
            &p,
            Control::Load(6.0),
            &SolverOptions::default(),
            None,
            &empty,
        )
        .unwrap();
        let b = crate::solve(&p, Control::Load(6.0), &SolverOptions::default()).unwrap();
        assert_eq!(a.forces, b.forces);
    }
}
