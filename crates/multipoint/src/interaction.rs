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
    ///
    /// # Panics
    /// When `forces` or `out` does not hold one value per summit (an
    /// operator's product, like a slice's index, has no error to return).
    pub fn apply(&self, forces: &[f64], out: &mut [f64], par: Par) {
        let n = self.positions.len();
        assert!(
            forces.len() == n && out.len() == n,
            "Boussinesq::apply: {} forces and {} outputs for {n} summits",
            forces.len(),
            out.len()
        );
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

/// The displacement at distance `r` from the centre of a Hertz pressure
/// distribution of unit force over radius `a`, divided by the compliance
/// factor `f = (1 − ν²)/(π E)` (so it is `1/r` for a point force, `a = 0`):
///
/// ```text
/// r ≤ a:  w = 3π (2a² − r²) / (8 a³)
/// r > a:  w = 3 [(2a² − r²) asin(a/r) + a √(r² − a²)] / (4 a³)
/// ```
///
/// (Johnson, *Contact Mechanics*, §3.4; docs/theory.md §3). Outside the
/// patch `w = (1/r)(1 + a²/(10 r²) + O(a⁴/r⁴))`.
pub fn hertz_potential(r: f64, a: f64) -> f64 {
    if !(a > 0.0) {
        return 1.0 / r;
    }
    if r <= a {
        3.0 * std::f64::consts::PI * (2.0 * a * a - r * r) / (8.0 * a * a * a)
    } else {
        let s = (a / r).asin();
        3.0 * ((2.0 * a * a - r * r) * s + a * (r * r - a * a).sqrt()) / (4.0 * a * a * a)
    }
}

/// Gauss–Legendre nodes and weights on [0, 1] (8 points), for the radial
/// coordinate `v = √(1 − s²)` of a Hertz patch (`s = ρ/a`), in which the
/// pressure-weighted area element `s √(1 − s²) ds` becomes `v² dv`.
const GAUSS_NODES: [f64; 8] = [
    0.019_855_071_751_231_912,
    0.101_666_761_293_186_64,
    0.237_233_795_041_835_5,
    0.408_282_678_752_175_1,
    0.591_717_321_247_824_8,
    0.762_766_204_958_164_5,
    0.898_333_238_706_813_4,
    0.980_144_928_248_768_1,
];
const GAUSS_WEIGHTS: [f64; 8] = [
    0.050_614_268_145_188_53,
    0.111_190_517_226_687_21,
    0.156_853_322_938_943_44,
    0.181_341_891_689_180_83,
    0.181_341_891_689_180_83,
    0.156_853_322_938_943_44,
    0.111_190_517_226_687_21,
    0.050_614_268_145_188_53,
];
/// Angular midpoints over [0, π] (the integrand is even in the angle).
const ANGLES: usize = 12;

/// The mutual compliance of two Hertz pressure distributions of unit force,
/// radii `a_i` and `a_j`, centres `r` apart, divided by the compliance
/// factor `f`:
///
/// ```text
/// g(r; a_i, a_j) = ∫∫ q_i(x) q_j(y) / |x − y| dx dy
/// ```
///
/// with `q` the normalised Hertz pressure `3/(2π a²) √(1 − ρ²/a²)`: the
/// work-conjugate displacement of patch `j` under patch `i`'s load. It is
/// symmetric in `(a_i, a_j)` (computed with the larger patch as the source,
/// [`hertz_potential`] in closed form, averaged over the smaller one by an
/// 8 × 24-point product rule: a fixed O(1) cost a pair), positive definite
/// as the Gram matrix of the `1/r` kernel, bounded at `r = 0`, and tends to
/// `1/r` as `r/a` grows: `g = (1/r)(1 + (a_i² + a_j²)/(10 r²) + …)`.
pub fn mutual_compliance(r: f64, a_i: f64, a_j: f64) -> f64 {
    let (big, small) = if a_i >= a_j { (a_i, a_j) } else { (a_j, a_i) };
    if !(small > 0.0) {
        return hertz_potential(r, big);
    }
    let mut sum = 0.0;
    for (v, wv) in GAUSS_NODES.iter().zip(&GAUSS_WEIGHTS) {
        let rho = small * (1.0 - v * v).sqrt();
        let mut ring = 0.0;
        for k in 0..ANGLES {
            let phi = std::f64::consts::PI * (k as f64 + 0.5) / ANGLES as f64;
            let d = (r * r + 2.0 * r * rho * phi.cos() + rho * rho).sqrt();
            ring += hertz_potential(d, big);
        }
        sum += wv * v * v * ring / ANGLES as f64;
    }
    // ∫₀¹ v² dv = 1/3 normalises the radial weight.
    3.0 * sum
}

#[cfg(test)]
mod tests {
    use std::f64::consts::PI;

    use super::*;

    /// A brute-force double quadrature of `∫∫ q_i q_j / |x − y|` on polar
    /// grids over both patches (midpoint rule in `s²`, which integrates the
    /// Hertz weight `√(1 − s²)` smoothly), independent of the closed-form
    /// `hertz_potential` the production rule averages.
    fn brute(r: f64, ai: f64, aj: f64, n: usize) -> f64 {
        let patch = |a: f64| -> Vec<([f64; 2], f64)> {
            let mut pts = Vec::new();
            let m = 4 * n;
            for k in 0..n {
                let s2 = (k as f64 + 0.5) / n as f64;
                let rho = a * s2.sqrt();
                let w = (1.0 - s2).sqrt();
                for l in 0..m {
                    let phi = 2.0 * PI * (l as f64 + 0.5) / m as f64;
                    pts.push(([rho * phi.cos(), rho * phi.sin()], w));
                }
            }
            let total: f64 = pts.iter().map(|p| p.1).sum();
            pts.iter_mut().for_each(|p| p.1 /= total);
            pts
        };
        let (pi, pj) = (patch(ai), patch(aj));
        let mut sum = 0.0;
        for (x, wx) in &pi {
            for (y, wy) in &pj {
                let d = ((x[0] - y[0] - r).powi(2) + (x[1] - y[1]).powi(2)).sqrt();
                sum += wx * wy / d;
            }
        }
        sum
    }

    #[test]
    fn hertz_potential_is_continuous_and_a_point_force_far_away() {
        let a = 1e-3;
        let inside = hertz_potential(a * (1.0 - 1e-12), a);
        let outside = hertz_potential(a * (1.0 + 1e-12), a);
        assert!((inside - outside).abs() < 1e-9 * inside);
        // Centre: the Hertz approach 3P/(4 a E*) = f · 3π/(4a).
        assert!((hertz_potential(0.0, a) - 3.0 * PI / (4.0 * a)).abs() < 1e-12 / a);
        for k in [2.0, 5.0, 20.0] {
            let r = k * a;
            let expected = (1.0 + a * a / (10.0 * r * r)) / r;
            let rel = (hertz_potential(r, a) - expected).abs() * r;
            assert!(rel < 0.05 / k.powi(4), "r = {k} a: {rel:e}");
        }
    }

    #[test]
    fn coincident_equal_patches_have_the_hertz_energy() {
        // ∫ p u dA = 0.8 P δ for Hertz: g(0; a, a) = 0.8 · 3π/(4a) = 0.6π/a.
        let a = 2e-3;
        let g = mutual_compliance(0.0, a, a);
        assert!(
            (g * a / (0.6 * PI) - 1.0).abs() < 2e-3,
            "{}",
            g * a / (0.6 * PI)
        );
    }

    #[test]
    fn mutual_compliance_matches_a_brute_force_double_integral() {
        let a = 1e-3;
        for (r, ai, aj) in [
            (0.5 * a, a, 0.7 * a),
            (1.5 * a, a, a),
            (3.0 * a, 0.4 * a, a),
        ] {
            let g = mutual_compliance(r, ai, aj);
            let b = brute(r, ai, aj, 24);
            assert!(
                (g - b).abs() < 5e-3 * b,
                "r {r:e} ai {ai:e} aj {aj:e}: {g} vs {b}"
            );
        }
    }

    #[test]
    fn mutual_compliance_is_symmetric_and_tends_to_the_point_kernel() {
        let (ai, aj) = (1e-3, 0.6e-3);
        let mut previous = f64::INFINITY;
        for k in [1.0, 2.0, 4.0, 8.0, 16.0, 32.0] {
            let r = k * (ai + aj);
            let g = mutual_compliance(r, ai, aj);
            assert_eq!(g, mutual_compliance(r, aj, ai));
            let rel = (g * r - 1.0).abs();
            // The leading correction (a_i² + a_j²)/(10 r²).
            let leading = (ai * ai + aj * aj) / (10.0 * r * r);
            assert!(rel < previous, "not decreasing at {k}: {rel:e}");
            if k >= 4.0 {
                assert!(
                    (rel - leading).abs() < 0.1 * leading,
                    "{k}: {rel:e} vs {leading:e}"
                );
            }
            previous = rel;
        }
        assert!(previous < 1e-4);
    }
}
