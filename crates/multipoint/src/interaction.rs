//! Boussinesq coupling between summits.

use faer::Par;
use rayon::prelude::*;

use crate::fast::near_sum;

/// The interaction coefficients `T_ij = (1 − ν²) / (π E r_ij)` for `i ≠ j`,
/// `T_ii = 0` (the self-compliance lives in each asperity's law).
///
/// Coefficients are computed on the fly from the positions: at N = 10⁴ a
/// stored T would take 800 MB while recomputing a row costs a few ns an entry.
#[derive(Clone, Copy, Debug)]
pub struct Boussinesq<'a> {
    positions: &'a [[f64; 2]],
    factor: f64,
}

impl<'a> Boussinesq<'a> {
    /// The operator for `positions` and compliance factor `(1 − ν²)/(π E)`.
    pub fn new(positions: &'a [[f64; 2]], factor: f64) -> Self {
        Self { positions, factor }
    }

    /// The compliance factor `f = (1 − ν²)/(π E)` (`T_ij = f / r_ij`).
    pub fn factor(&self) -> f64 {
        self.factor
    }

    /// `T_ij`.
    #[inline]
    pub fn coefficient(&self, i: usize, j: usize) -> f64 {
        if i == j {
            return 0.0;
        }
        let (a, b) = (self.positions[i], self.positions[j]);
        let (dx, dy) = (a[0] - b[0], a[1] - b[1]);
        self.factor / (dx * dx + dy * dy).sqrt()
    }

    /// `u = T · forces`: the displacement each summit receives from the forces
    /// on all the others. Only the non-zero forces are visited (gathered
    /// first, so the inner loop runs branch-free and vectorises); summits at
    /// the same position as the target, itself included, contribute nothing.
    pub fn apply(&self, forces: &[f64], out: &mut [f64], par: Par) {
        let (q, pts): (Vec<f64>, Vec<[f64; 2]>) = forces
            .iter()
            .zip(self.positions)
            .filter(|(p, _)| **p != 0.0)
            .map(|(&p, &x)| (p, x))
            .unzip();
        let row = |i: usize| -> f64 {
            let [xi, yi] = self.positions[i];
            self.factor * near_sum(xi, yi, &q, &pts)
        };
        match par {
            Par::Seq => out.iter_mut().enumerate().for_each(|(i, u)| *u = row(i)),
            Par::Rayon(_) => out
                .par_iter_mut()
                .with_min_len(64)
                .enumerate()
                .for_each(|(i, u)| *u = row(i)),
        }
    }
}
