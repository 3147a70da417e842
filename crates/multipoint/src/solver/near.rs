//! The near-pair correction of [`Interaction::Distributed`]: the coupling
//! is the point operator (exact or fast) plus a sparse symmetric `C` with
//!
//! ```text
//! C_ij = f · b(r_ij / (a_i + a_j)) · (g(r_ij; a_i, a_j) − 1/r_ij)
//! ```
//!
//! for the pairs with at least one asperity in contact closer than
//! `2 c (a_i + a_j)` (`c` the near factor, `b` a smoothstep from 1 at `c`
//! to 0 at `2c`, `g` the mutual compliance of the two Hertz patches). An
//! asperity out of contact has `a = 0`: it feels the neighbour's patch
//! through the closed-form Hertz displacement, which is what decides
//! whether it comes into contact.
//!
//! The radii follow the state: every residual evaluation recomputes them
//! from the laws' local contacts at the iterate (so the residual, the merit
//! and the convergence test are those of the consistent problem), and the
//! Newton step's Jacobian uses `T + C` at the iterate's radii, leaving out
//! `∂C/∂a · ∂a/∂P`. That term is the change of a near pair's coupling with
//! the patch size, small next to `C` itself for separated patches; Newton
//! is then a quasi-Newton method converging linearly near the solution,
//! with a contraction that the tests and the sweeps of docs/validation.md
//! measure (a few extra iterations, no lost convergence).
//!
//! A fixed correction ([`PairCorrection`](super::correction::PairCorrection),
//! handed in by the caller) rides on the same pairs: its entries are kept
//! through every update and added after the distributed ones, so the
//! residual, the dense matrix and the Krylov products all see `T + C`.

use tyreroad_contact_law::ContactLaw;

use super::options::Interaction;
use crate::mutual_compliance;

pub(super) struct NearField {
    /// The distributed kernel's blend start, `None` when only the fixed
    /// correction is present.
    near_factor: Option<f64>,
    /// The caller's fixed pairs, appended after every update.
    fixed: Vec<(usize, usize, f64)>,
    factor: f64,
    /// Asperity indices sorted by x, and their x coordinates.
    order: Vec<usize>,
    xs: Vec<f64>,
    /// Local contact radius of each asperity at the last update (0 out of
    /// contact).
    pub(super) radii: Vec<f64>,
    /// `(i, j, C_ij)`, each unordered pair once.
    pub(super) pairs: Vec<(usize, usize, f64)>,
}

impl NearField {
    /// The correction for `interaction` plus the `fixed` pairs, or `None`
    /// for the point kernel without fixed pairs.
    pub(super) fn new(
        interaction: Interaction,
        positions: &[[f64; 2]],
        factor: f64,
        fixed: &[(usize, usize, f64)],
    ) -> Option<Self> {
        let near_factor = match interaction {
            Interaction::Distributed { near_factor } => Some(near_factor),
            Interaction::Point if fixed.is_empty() => return None,
            Interaction::Point => None,
        };
        let mut order: Vec<usize> = (0..positions.len()).collect();
        order.sort_by(|&a, &b| positions[a][0].total_cmp(&positions[b][0]));
        let xs = order.iter().map(|&i| positions[i][0]).collect();
        Some(Self {
            near_factor,
            fixed: fixed.to_vec(),
            factor,
            order,
            xs,
            radii: vec![0.0; positions.len()],
            pairs: fixed.to_vec(),
        })
    }

    /// Recomputes the radii from the forces `p` and interpenetrations
    /// `delta`, and the near pairs with their corrections.
    pub(super) fn update<L: ContactLaw>(
        &mut self,
        laws: &[L],
        positions: &[[f64; 2]],
        p: &[f64],
        delta: &[f64],
    ) {
        let Some(near_factor) = self.near_factor else {
            // Only the fixed pairs: nothing follows the state.
            return;
        };
        let mut a_max = 0.0_f64;
        for (i, a) in self.radii.iter_mut().enumerate() {
            *a = 0.0;
            if p[i] > 0.0 {
                let r = laws[i].local_contact(p[i], delta[i]).radius;
                if r.is_finite() && r > 0.0 {
                    *a = r;
                    a_max = a_max.max(r);
                }
            }
        }
        self.pairs.clear();
        let far = 2.0 * near_factor;
        for j in 0..p.len() {
            let aj = self.radii[j];
            if aj <= 0.0 {
                continue;
            }
            let [xj, yj] = positions[j];
            let reach = far * (a_max + aj);
            let lo = self.xs.partition_point(|&x| x < xj - reach);
            let hi = self.xs.partition_point(|&x| x <= xj + reach);
            for &i in &self.order[lo..hi] {
                let ai = self.radii[i];
                // Two contacts: the pair once, from its smaller index.
                if i == j || (ai > 0.0 && i < j) {
                    continue;
                }
                let [xi, yi] = positions[i];
                let r = ((xi - xj).powi(2) + (yi - yj).powi(2)).sqrt();
                let s = r / (ai + aj);
                if s >= far || r == 0.0 {
                    continue;
                }
                let t = ((s - near_factor) / near_factor).clamp(0.0, 1.0);
                let blend = 1.0 - t * t * (3.0 - 2.0 * t);
                let c = self.factor * blend * (mutual_compliance(r, ai, aj) - 1.0 / r);
                if c != 0.0 {
                    self.pairs.push((i, j, c));
                }
            }
        }
        self.pairs.extend_from_slice(&self.fixed);
    }

    /// `out += C x`.
    pub(super) fn add(&self, x: &[f64], out: &mut [f64]) {
        for &(i, j, c) in &self.pairs {
            out[i] += c * x[j];
            out[j] += c * x[i];
        }
    }
}
