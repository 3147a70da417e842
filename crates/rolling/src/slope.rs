//! Where the deformed tread touches each cap ([`ContactSlope`]).
//!
//! Under a tyre the undeformed profile slopes by `(ξ/Rx, η/Ry)`, up to 0.2
//! at a footprint's ends, and a summit of radius `R` is first touched
//! `σ R` off it, where the gap is `½ σ² R` smaller
//! ([`crate::Tread::contact_gap`]). But the surface a cap meets is the
//! profile plus the displacement `u` the step's other contacts cause, so
//! its local slope is
//!
//! ```text
//! σ_j = ∇s(x_j) + ∇u_j,   ∇u_j = − f Σ_{i≠j} P_i (x_j − x_i) / max(r_ij, a_i + a_j)³
//! ```
//!
//! (`f = 1/(π E*)`, the point kernel's gradient; `a_i` the contact radii,
//! which floor the distance where two patches would overlap and the
//! kernel's gradient across a patch no longer stands for it). A rolling
//! step passes each contact's law radius capped by the Hertz radius of its
//! force on its summit radius ([`floor_radius`]), so that the floor goes
//! to zero with the force: a flat top's law has a patch of finite size at
//! its first touch. Inside a footprint pressed flat the two slopes partly
//! cancel. With [`ContactSlope::Deformed`] each step iterates its solve
//! with the gaps and contact points of [`crate::Tread::contact_gap_sloped`]
//! at these slopes, mixed with the rounds before ([`SlopeMixer`]), until
//! no gap moves (docs/rolling.md, "Where the tread touches a cap").
//!
//! Invariants: with no other loaded contact `∇u = 0` and the profile's
//! contact point is recovered exactly; the slopes depend only on the
//! step's positions, forces and radii (not on the order or the chunking);
//! the floor radius is continuous in the force; the mixer's fixed points
//! are the plain update's.

/// How a rolling step finds where the tread touches each cap (on a road
/// with summit radii; without radii every gap is the summit's).
///
/// Measured against the BEM (docs/validation.md, "The deformed tread's
/// slope"): on the chip seal and the dense asphalt `Deformed` brings the
/// centre sensors closer (chip seal, `calibrated` rung: 5.0 % → 2.1 % of
/// the peak), but on a field of spheres under a strongly curved tyre
/// `Profile` is the closer (0.2 % against 1.2 % of the load on the wrong
/// column), and the dense asphalt's shoulder is further off. `Profile`
/// stays the default until that is understood.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ContactSlope {
    /// The undeformed profile's slope.
    #[default]
    Profile,
    /// The profile's slope plus the gradient of the displacement the
    /// step's other contacts cause, iterated with the step's solve.
    Deformed,
}

/// `∇u_j` at each position: the displacement slope the other loaded
/// contacts cause there (module docs). `forces` and `radii` in the same
/// order as `positions`; zero forces contribute nothing. `factor` is
/// `1/(π E*)` (m/N).
pub fn deformation_slopes(
    positions: &[[f64; 2]],
    forces: &[f64],
    radii: &[f64],
    factor: f64,
) -> Vec<[f64; 2]> {
    let loaded: Vec<usize> = (0..positions.len()).filter(|&i| forces[i] > 0.0).collect();
    positions
        .iter()
        .enumerate()
        .map(|(j, pj)| {
            let mut g = [0.0, 0.0];
            for &i in &loaded {
                if i == j {
                    continue;
                }
                let d = [pj[0] - positions[i][0], pj[1] - positions[i][1]];
                let r = (d[0] * d[0] + d[1] * d[1]).sqrt().max(radii[i] + radii[j]);
                if !(r > 0.0) {
                    continue;
                }
                let k = factor * forces[i] / (r * r * r);
                g[0] -= k * d[0];
                g[1] -= k * d[1];
            }
            g
        })
        .collect()
}

/// The radius a contact lends the slope kernel's floor
/// ([`crate::deformation_slopes`]): its law's contact radius `a`, but no
/// more than the Hertz radius `(3 P R / (4 E*))^(1/3)` of its force on its
/// summit radius `R`. A flat top's law has a patch of finite size at the
/// first touch, and the floor then jumped with it as the contact turned on
/// and off: the slope iteration had no fixed point to settle on (a 130 mm
/// porous-asphalt road, every step). The Hertz radius goes to zero with
/// the force, so the floor is continuous; on a rounded summit the two agree.
pub(crate) fn floor_radius(a: f64, force: f64, summit_radius: f64, reduced_modulus: f64) -> f64 {
    if !(force > 0.0) {
        return 0.0;
    }
    let hertz = (0.75 * force * summit_radius / reduced_modulus).cbrt();
    if hertz.is_finite() { a.min(hertz) } else { a }
}

/// Anderson mixing of a slope iteration `σ ← g(σ)` (depth
/// [`SlopeMixer::DEPTH`]): the next iterate combines the last iterates and
/// their images so that the combined residual `g(σ) − σ` is smallest in
/// least squares. A plain iteration that cycles (two tiles a fraction of
/// a millimetre apart tilting each other in turn) lands between the
/// states it cycles through; on a linear map it is a Krylov method. Its
/// fixed points are those of `g`.
#[derive(Debug, Default)]
pub(crate) struct SlopeMixer {
    /// `(σ_k, g(σ_k) − σ_k)`, oldest first, flattened.
    history: std::collections::VecDeque<(Vec<f64>, Vec<f64>)>,
}

impl SlopeMixer {
    /// Iterates remembered.
    pub(crate) const DEPTH: usize = 5;

    /// The next iterate after `x`, whose image is `gx`.
    pub(crate) fn next(&mut self, x: &[[f64; 2]], gx: &[[f64; 2]]) -> Vec<[f64; 2]> {
        let xk: Vec<f64> = x.iter().flatten().copied().collect();
        let fk: Vec<f64> = x
            .iter()
            .zip(gx)
            .flat_map(|(a, b)| [b[0] - a[0], b[1] - a[1]])
            .collect();
        if self
            .history
            .front()
            .is_some_and(|(x0, _)| x0.len() != xk.len())
        {
            self.history.clear();
        }
        // Differences to the newest iterate: dx_i = x_k − x_i, df_i = f_k − f_i.
        let (dx, df): (Vec<Vec<f64>>, Vec<Vec<f64>>) = self
            .history
            .iter()
            .map(|(xi, fi)| {
                (
                    xk.iter().zip(xi).map(|(a, b)| a - b).collect(),
                    fk.iter().zip(fi).map(|(a, b)| a - b).collect(),
                )
            })
            .unzip();
        let gamma = least_squares(&df, &fk);
        let mut out: Vec<f64> = xk.iter().zip(&fk).map(|(a, f)| a + f).collect();
        for ((g, dxi), dfi) in gamma.iter().zip(&dx).zip(&df) {
            for ((o, a), b) in out.iter_mut().zip(dxi).zip(dfi) {
                *o -= g * (a + b);
            }
        }
        self.history.push_back((xk, fk));
        if self.history.len() > Self::DEPTH {
            self.history.pop_front();
        }
        if out.iter().any(|v| !v.is_finite()) {
            self.history.clear();
            return gx.to_vec();
        }
        out.chunks_exact(2).map(|c| [c[0], c[1]]).collect()
    }
}

/// `γ` minimising `|f − Σ γ_i d_i|²` by the normal equations, lightly
/// regularised (a column that adds nothing gets `γ_i ≈ 0`).
fn least_squares(d: &[Vec<f64>], f: &[f64]) -> Vec<f64> {
    let m = d.len();
    let dot = |a: &[f64], b: &[f64]| a.iter().zip(b).map(|(x, y)| x * y).sum::<f64>();
    let mut a = vec![vec![0.0; m + 1]; m];
    let trace: f64 = d.iter().map(|di| dot(di, di)).sum();
    for i in 0..m {
        for j in 0..m {
            a[i][j] = dot(&d[i], &d[j]);
        }
        a[i][i] += 1e-10 * trace + f64::MIN_POSITIVE;
        a[i][m] = dot(&d[i], f);
    }
    // Gaussian elimination with partial pivoting on the augmented matrix.
    for c in 0..m {
        let p = (c..m)
            .max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))
            .unwrap_or(c);
        a.swap(c, p);
        let pivot = a[c][c];
        if !(pivot.abs() > 0.0) {
            return vec![0.0; m];
        }
        let (upper, lower) = a.split_at_mut(c + 1);
        let pivot_row = &upper[c];
        for row in lower {
            let k = row[c] / pivot;
            for (x, p) in row[c..].iter_mut().zip(&pivot_row[c..]) {
                *x -= k * p;
            }
        }
    }
    let mut g = vec![0.0; m];
    for c in (0..m).rev() {
        let s: f64 = (c + 1..m).map(|j| a[c][j] * g[j]).sum();
        g[c] = (a[c][m] - s) / a[c][c];
    }
    g
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_loaded_neighbour_tilts_the_tread_up_towards_itself() {
        // u = f P / r rises towards the neighbour: at x = 4 mm from a 10 N
        // contact the slope is −f P / r² along x.
        let f = 1e-7;
        let g = deformation_slopes(&[[0.0, 0.0], [4e-3, 0.0]], &[10.0, 0.0], &[0.0, 0.0], f);
        assert_eq!(g[0], [0.0, 0.0], "its own load does not tilt a contact");
        let expected = -f * 10.0 / (4e-3f64 * 4e-3);
        assert!((g[1][0] - expected).abs() < 1e-12 * expected.abs());
        assert_eq!(g[1][1], 0.0);
    }

    #[test]
    fn overlapping_patches_floor_the_distance_at_their_radii() {
        let f = 1e-7;
        let g = deformation_slopes(&[[0.0, 0.0], [1e-3, 0.0]], &[10.0, 5.0], &[1e-3, 1e-3], f);
        let expected = f * 10.0 * 1e-3 / (2e-3f64).powi(3);
        assert!((g[1][0] + expected).abs() < 1e-12 * expected);
        assert!((g[0][0] - 0.5 * expected).abs() < 1e-12 * expected);
    }

    /// Iterates `g` from `x` with the mixer until `g(x) = x` to `tol`;
    /// the rounds taken, or `None` after 50.
    fn settle(
        g: impl Fn(&[[f64; 2]]) -> Vec<[f64; 2]>,
        mut x: Vec<[f64; 2]>,
        tol: f64,
    ) -> Option<(usize, Vec<[f64; 2]>)> {
        let mut mixer = SlopeMixer::default();
        for round in 1..=50 {
            let gx = g(&x);
            let moved = x
                .iter()
                .zip(&gx)
                .map(|(a, b)| (a[0] - b[0]).abs().max((a[1] - b[1]).abs()))
                .fold(0.0, f64::max);
            if moved <= tol {
                return Some((round, x));
            }
            x = mixer.next(&x, &gx);
        }
        None
    }

    #[test]
    fn the_floor_radius_is_continuous_as_a_flat_top_comes_into_contact() {
        // A 5 mm tile's law has a 1.3 mm patch at its first touch; the
        // floor follows the Hertz radius up to it, from zero.
        let (a, r, e) = (1.3e-3, 2e-3, 8.72e6);
        assert_eq!(floor_radius(a, 0.0, r, e), 0.0);
        let tiny = floor_radius(a, 1e-6, r, e);
        assert!(tiny > 0.0 && tiny < 1e-5, "{tiny}");
        let hertz = (0.75 * 1.0 * r / e).cbrt();
        assert!((floor_radius(a, 1.0, r, e) - hertz).abs() < 1e-15);
        assert_eq!(floor_radius(a, 1e3, r, e), a, "capped by the law's patch");
        // An unknown summit radius leaves the law's.
        assert_eq!(floor_radius(a, 1.0, f64::INFINITY, e), a);
    }

    #[test]
    fn a_slope_iteration_that_cycles_between_two_states_settles_between_them() {
        // g(σ) = 2c − σ: the plain iteration flips between σ0 and 2c − σ0
        // for ever (two tiles tilting each other in turn); the fixed point
        // is c.
        let c = [[0.05, -0.02], [0.1, 0.3]];
        let g = |x: &[[f64; 2]]| -> Vec<[f64; 2]> {
            x.iter()
                .zip(&c)
                .map(|(a, c)| [2.0 * c[0] - a[0], 2.0 * c[1] - a[1]])
                .collect()
        };
        let x0 = vec![[0.0, 0.0]; 2];
        assert_eq!(g(&g(&x0)), x0, "the plain iteration cycles");
        let (rounds, x) = settle(g, x0, 1e-12).expect("settles");
        assert!(rounds <= 4, "{rounds} rounds");
        for (a, b) in x.iter().zip(&c) {
            assert!(
                (a[0] - b[0]).abs() < 1e-12 && (a[1] - b[1]).abs() < 1e-12,
                "{x:?}"
            );
        }
    }

    #[test]
    fn a_steep_nonlinear_slope_map_settles_on_its_own_fixed_point() {
        // Each slope pulled towards a steep, saturating function of its
        // neighbour's (a contact that loads and unloads): derivative −3 at
        // the fixed point, so the plain iteration diverges into a cycle.
        let g = |x: &[[f64; 2]]| -> Vec<[f64; 2]> {
            vec![
                [0.2 * (1.0 - (3.0 * (x[1][0] - 0.1) / 0.2).tanh()), 0.0],
                [0.2 * (1.0 - (3.0 * (x[0][0] - 0.1) / 0.2).tanh()), 0.0],
            ]
        };
        let x0 = vec![[0.0, 0.0], [0.3, 0.0]];
        let (_, x) = settle(g, x0, 1e-12).expect("settles");
        let gx = g(&x);
        assert!(
            (gx[0][0] - x[0][0]).abs() < 1e-12 && (gx[1][0] - x[1][0]).abs() < 1e-12,
            "{x:?}"
        );
    }
}
