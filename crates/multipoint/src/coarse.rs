//! The coarse start of large cold solves: the same contact problem on
//! clusters of neighbouring asperities, solved first, gives Newton its
//! initial interpenetrations.
//!
//! # Why
//!
//! On a large patch the Boussinesq coupling dominates: at 0.2 MPa over a
//! square of side `L` the mean displacement is about `3 f p L`
//! (`f = (1 − ν²)/(π E)`), 24 mm for N = 10⁵ summits at 3 mm spacing against
//! interpenetrations of 0.1 mm. The uncoupled start (`T = 0`) ignores that
//! bowl entirely, so Newton spends most of its iterations moving the active
//! set from the uncoupled one to the punch-like one (loaded edges, unloaded
//! centre), with short, backtracked steps. A coarse problem on ~10³ clusters
//! captures the bowl at the cost of a small dense solve.
//!
//! # The coarse problem
//!
//! Cluster `c` (the members of a square cell of a regular grid) sits at its
//! members' centroid with gap `H_c = min_{i∈c} H_i`; member `i` has offset
//! `h_i = H_i − H_c ≥ 0`. Its law is the sum of its members' laws at a common
//! interpenetration `D`, `g_c(D) = Σ_i P_i^law(D − h_i)`, where `D` is the
//! cluster's interpenetration `δ_c` less the displacement of its own load
//! spread over the cell, `D = δ_c − s_c P_c`. With `a_c` the side of a square
//! holding the cluster's members at the layout's mean density, `s_c` is the
//! mean displacement of a unit force spread uniformly over that square,
//! `s_c = f · 2.9732 / a_c` (`2.9732… = 4 ln(1 + √2) − (4/3)(√2 − 1)`, the
//! mean of `1/r` over pairs of points of a unit square). So the cluster law
//! is implicit, `P_c = g_c(δ_c − s_c P_c)`; clusters interact through the
//! point-force Boussinesq coefficients between centroids. The fine start is
//! then `δ_i = D_c − h_i`, `δ0` the coarse approach.

use tyreroad_contact_law::{ContactLaw, LawPoint, LocalContact};

use crate::Problem;

/// Mean of `1/r` over pairs of points of the unit square:
/// `4 ln(1 + √2) − (4/3)(√2 − 1)`.
pub(crate) const SQUARE_MEAN_INVERSE_DISTANCE: f64 = 2.973_209_598_247_378_5;

/// The law of a cluster of asperities, with its self-compliance (see the
/// module documentation): `P = g(δ − sP)`, `g(D) = Σ_i P_i^law(D − h_i)`.
#[derive(Clone, Debug)]
pub(crate) struct ClusterLaw<'a, L> {
    laws: &'a [L],
    members: Vec<usize>,
    offsets: Vec<f64>,
    compliance: f64,
}

impl<'a, L: ContactLaw> ClusterLaw<'a, L> {
    /// The cluster of `members` (indices into `laws`) with offsets
    /// `h_i ≥ 0` and self-compliance `s ≥ 0` (m/N).
    pub(crate) fn new(laws: &'a [L], members: Vec<usize>, offsets: Vec<f64>, s: f64) -> Self {
        Self {
            laws,
            members,
            offsets,
            compliance: s,
        }
    }

    /// The members (indices of the fine problem).
    pub(crate) fn members(&self) -> &[usize] {
        &self.members
    }

    /// The members' offsets `h_i = H_i − H_c`.
    pub(crate) fn offsets(&self) -> &[f64] {
        &self.offsets
    }

    /// `g(D)` and `g'(D)`.
    fn sum(&self, d: f64) -> (f64, f64) {
        let (mut p, mut k) = (0.0, 0.0);
        for (&i, &h) in self.members.iter().zip(&self.offsets) {
            let l = self.laws[i].evaluate(d - h);
            p += l.force;
            k += l.stiffness;
        }
        (p, k)
    }

    /// The members' common interpenetration `D = δ − sP` at cluster depth `δ`.
    pub(crate) fn inner_depth(&self, depth: f64) -> f64 {
        depth - self.compliance * self.evaluate(depth).force
    }
}

impl<L: ContactLaw> ContactLaw for ClusterLaw<'_, L> {
    /// Solves `φ(P) = P − g(δ − sP) = 0`. `φ` increases (`φ' = 1 + s g' > 0`),
    /// `φ(0) = −g(δ) ≤ 0` and `φ(g(δ)) ≥ 0`, so Newton safeguarded by
    /// bisection on `[0, g(δ)]` converges; `dP/dδ = g'/(1 + s g')`.
    fn evaluate(&self, depth: f64) -> LawPoint {
        let (g0, k0) = self.sum(depth);
        if !(g0 > 0.0) || self.compliance == 0.0 {
            return LawPoint {
                force: g0.max(0.0),
                stiffness: k0.max(0.0),
            };
        }
        let s = self.compliance;
        let (mut lo, mut hi) = (0.0, g0);
        // Newton from the linearisation at P = 0: P ≈ g0 / (1 + s k0).
        let mut p = g0 / (1.0 + s * k0);
        let mut k = k0;
        for _ in 0..100 {
            let (g, gk) = self.sum(depth - s * p);
            k = gk;
            let phi = p - g;
            if phi <= 0.0 {
                lo = p;
            } else {
                hi = p;
            }
            if phi.abs() <= 1e-14 * g0 || hi - lo <= 1e-15 * g0 {
                break;
            }
            let next = p - phi / (1.0 + s * gk);
            p = if next > lo && next < hi {
                next
            } else {
                0.5 * (lo + hi)
            };
        }
        LawPoint {
            force: p,
            stiffness: k / (1.0 + s * k),
        }
    }

    /// Never used: the coarse problem only provides a start.
    fn local_contact(&self, _force: f64, _depth: f64) -> LocalContact {
        LocalContact::NONE
    }
}

/// The clusters of a coarse start: about `target` square cells of a regular
/// grid over the summits' bounding box (empty cells dropped), each as its
/// members, their offsets, its gap `H_c`, centroid and self-compliance.
pub(crate) struct Clusters {
    pub(crate) members: Vec<Vec<usize>>,
    pub(crate) gaps: Vec<f64>,
    pub(crate) centroids: Vec<[f64; 2]>,
    pub(crate) compliance: Vec<f64>,
}

impl Clusters {
    /// Bins `problem`'s summits into about `target` cells.
    pub(crate) fn new<L: ContactLaw>(problem: &Problem<L>, target: usize) -> Self {
        let (pos, gaps) = (problem.positions(), problem.gaps());
        let n = pos.len();
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in pos {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        let (wx, wy) = ((hi[0] - lo[0]).max(0.0), (hi[1] - lo[1]).max(0.0));
        // Square cells: nx × ny ≈ target with nx/ny ≈ wx/wy.
        let cell = if wx > 0.0 && wy > 0.0 {
            (wx * wy / target.max(1) as f64).sqrt()
        } else {
            (wx.max(wy) / target.max(1) as f64).max(f64::MIN_POSITIVE)
        };
        let nx = ((wx / cell).ceil() as usize).max(1);
        let ny = ((wy / cell).ceil() as usize).max(1);
        let mut cell_members: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
        for (i, p) in pos.iter().enumerate() {
            let ix = (((p[0] - lo[0]) / cell) as usize).min(nx - 1);
            let iy = (((p[1] - lo[1]) / cell) as usize).min(ny - 1);
            cell_members[iy * nx + ix].push(i);
        }
        let members: Vec<Vec<usize>> = cell_members.into_iter().filter(|m| !m.is_empty()).collect();
        // Side of a square holding m summits at the mean density.
        let area_per_summit = if wx > 0.0 && wy > 0.0 {
            wx * wy / n as f64
        } else {
            cell * cell
        };
        let factor = problem.material().boussinesq_factor();
        let mut out = Self {
            gaps: Vec::with_capacity(members.len()),
            centroids: Vec::with_capacity(members.len()),
            compliance: Vec::with_capacity(members.len()),
            members: Vec::new(),
        };
        for m in &members {
            let (mut x, mut y) = (0.0, 0.0);
            for &i in m {
                x += pos[i][0];
                y += pos[i][1];
            }
            out.centroids.push([x / m.len() as f64, y / m.len() as f64]);
            out.gaps
                .push(m.iter().map(|&i| gaps[i]).fold(f64::INFINITY, f64::min));
            let a = (m.len() as f64 * area_per_summit).sqrt();
            out.compliance
                .push(factor * SQUARE_MEAN_INVERSE_DISTANCE / a);
        }
        out.members = members;
        out
    }

    /// The cluster laws of `laws`.
    pub(crate) fn laws<'a, L: ContactLaw>(
        &self,
        laws: &'a [L],
        gaps: &[f64],
    ) -> Vec<ClusterLaw<'a, L>> {
        self.members
            .iter()
            .zip(self.gaps.iter().zip(&self.compliance))
            .map(|(m, (&hc, &s))| {
                ClusterLaw::new(
                    laws,
                    m.clone(),
                    m.iter().map(|&i| gaps[i] - hc).collect(),
                    s,
                )
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use tyreroad_asperity::Sphere;
    use tyreroad_contact_law::{Material, PotentialLaw};

    use super::*;

    fn laws() -> Vec<PotentialLaw<Sphere>> {
        let rubber = Material::new(6.54e6, 0.5).unwrap();
        [1e-3, 2.5e-3, 5e-3]
            .iter()
            .map(|&r| PotentialLaw::sphere(Sphere::new(r).unwrap(), rubber))
            .collect()
    }

    #[test]
    fn square_constant_is_the_mean_inverse_distance() {
        let exact = 4.0 * (1.0 + 2f64.sqrt()).ln() - 4.0 / 3.0 * (2f64.sqrt() - 1.0);
        assert!((SQUARE_MEAN_INVERSE_DISTANCE - exact).abs() < 1e-15);
    }

    /// The implicit law against its defining equation `P = g(δ − sP)`, its
    /// stiffness against central differences (1e-6 relative), and the
    /// limits: no force out of contact, the plain sum without compliance.
    #[test]
    fn cluster_law_solves_its_defining_equation() {
        let laws = laws();
        let offsets = vec![0.0, 2e-5, 7e-5];
        let s = 2e-6; // m/N, a strong self-compliance
        let law = ClusterLaw::new(&laws, vec![0, 1, 2], offsets.clone(), s);
        let plain = ClusterLaw::new(&laws, vec![0, 1, 2], offsets.clone(), 0.0);
        let g = |d: f64| -> f64 { laws.iter().zip(&offsets).map(|(l, h)| l.force(d - h)).sum() };
        assert_eq!(law.evaluate(0.0).force, 0.0);
        assert_eq!(law.evaluate(-1e-4).stiffness, 0.0);
        for delta in [1e-6, 3e-5, 1e-4, 4e-4] {
            let at = law.evaluate(delta);
            let p = at.force;
            assert!(p > 0.0 && p < g(delta));
            assert!((p - g(delta - s * p)).abs() <= 1e-12 * p, "δ = {delta}");
            assert!((law.inner_depth(delta) - (delta - s * p)).abs() < 1e-18);
            let h = 1e-4 * delta;
            let fd = (law.force(delta + h) - law.force(delta - h)) / (2.0 * h);
            assert!((at.stiffness - fd).abs() <= 1e-6 * fd, "δ = {delta}");
            assert!((plain.force(delta) - g(delta)).abs() <= 1e-14 * g(delta));
        }
    }
}
