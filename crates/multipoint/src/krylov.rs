//! Matrix-free Newton–Krylov: the active system
//! `M ΔP_A = b`, `M = diag(1/k_A) + T_AA`, solved by preconditioned conjugate
//! gradients, or restarted GMRES when CG meets non-positive curvature
//! (`pᵀMp ≤ 0`: M is indefinite).
//!
//! The preconditioner is two-level additive Schwarz: exact inverses of the
//! diagonal blocks of M on the quadtree's leaves (Cholesky; the diagonal
//! `1/k` when a block is not positive definite) plus a coarse correction on
//! piecewise-constant cluster functions of a coarser tree level, whose
//! Galerkin matrix `R₀ᵀ M R₀` is exact between neighbouring clusters and uses
//! centroids further away. Both parts are symmetric positive definite, so the
//! preconditioner is too, and CG stays applicable whenever M is.

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt;
use faer::{Mat, Par};
use rayon::prelude::*;

use crate::{Boussinesq, FastBoussinesq};

/// The interaction product in use: exact (`O(N · nnz)`) or fast multipole.
#[derive(Clone, Copy)]
pub(crate) enum Operator<'a> {
    Exact(Boussinesq<'a>),
    Fast(&'a FastBoussinesq),
}

impl Operator<'_> {
    pub(crate) fn apply(&self, x: &[f64], out: &mut [f64], par: Par) {
        match self {
            Self::Exact(op) => op.apply(x, out, par),
            Self::Fast(op) => op.apply(x, out, par),
        }
    }
}

/// What a Krylov solve reports.
#[derive(Clone, Copy, Debug, Default)]
pub(crate) struct KrylovStats {
    pub(crate) products: usize,
    pub(crate) breakdowns: usize,
}

/// The restricted operator `y = x/k + (T x̃)_A` on the active set.
pub(crate) struct ActiveOperator<'a> {
    pub(crate) op: Operator<'a>,
    pub(crate) active: &'a [usize],
    pub(crate) stiffness: &'a [f64],
    pub(crate) n: usize,
    pub(crate) par: Par,
    /// The distributed interaction's near-pair corrections `(i, j, C_ij)`
    /// (each unordered pair once), added to `T`; empty for the point kernel.
    pub(crate) near_pairs: &'a [(usize, usize, f64)],
}

impl ActiveOperator<'_> {
    fn apply(&self, x: &[f64], y: &mut [f64], full: &mut [f64], out: &mut [f64]) {
        full[..self.n].iter_mut().for_each(|v| *v = 0.0);
        for (a, &i) in self.active.iter().enumerate() {
            full[i] = x[a];
        }
        self.op.apply(&full[..self.n], &mut out[..self.n], self.par);
        for &(i, j, c) in self.near_pairs {
            out[i] += c * full[j];
            out[j] += c * full[i];
        }
        for (a, &i) in self.active.iter().enumerate() {
            y[a] = x[a] / self.stiffness[i] + out[i];
        }
    }
}

/// The two-level additive Schwarz preconditioner.
pub(crate) struct Preconditioner {
    /// Active-set indices of each block.
    blocks: Vec<Vec<usize>>,
    /// Lower Cholesky factor of each block (row-major), or empty: use 1/k.
    factors: Vec<Vec<f64>>,
    diag: Vec<f64>,
    /// Coarse cluster of each active unknown, and the coarse factor.
    coarse_of: Vec<usize>,
    coarse: Option<Mat<f64>>,
    coarse_stack: MemBuffer,
}

fn cholesky(a: &mut [f64], m: usize) -> bool {
    for j in 0..m {
        let mut d = a[j * m + j];
        for k in 0..j {
            d -= a[j * m + k] * a[j * m + k];
        }
        if !(d > 0.0) {
            return false;
        }
        let d = d.sqrt();
        a[j * m + j] = d;
        for i in j + 1..m {
            let mut s = a[i * m + j];
            for k in 0..j {
                s -= a[i * m + k] * a[j * m + k];
            }
            a[i * m + j] = s / d;
        }
    }
    true
}

fn cholesky_solve(l: &[f64], m: usize, x: &mut [f64]) {
    for i in 0..m {
        let mut s = x[i];
        for k in 0..i {
            s -= l[i * m + k] * x[k];
        }
        x[i] = s / l[i * m + i];
    }
    for i in (0..m).rev() {
        let mut s = x[i];
        for k in i + 1..m {
            s -= l[k * m + i] * x[k];
        }
        x[i] = s / l[i * m + i];
    }
}

impl Preconditioner {
    /// Builds the preconditioner for the active set. `leaves` are clusters of
    /// original indices with the coarse cluster of each; `slot[i]` is the
    /// active index of asperity `i` (or `usize::MAX`).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        exact: &Boussinesq<'_>,
        positions: &[[f64; 2]],
        leaves: &[&[usize]],
        leaf_coarse: &[usize],
        active: &[usize],
        stiffness: &[f64],
        slot: &[usize],
        par: Par,
    ) -> Self {
        let na = active.len();
        let diag: Vec<f64> = active.iter().map(|&i| 1.0 / stiffness[i]).collect();
        let mut blocks = Vec::new();
        let mut block_coarse = Vec::new();
        for (leaf, &c) in leaves.iter().zip(leaf_coarse) {
            let members: Vec<usize> = leaf
                .iter()
                .map(|&i| slot[i])
                .filter(|&a| a != usize::MAX)
                .collect();
            if !members.is_empty() {
                blocks.push(members);
                block_coarse.push(c);
            }
        }
        let factor_block = |members: &Vec<usize>| -> Vec<f64> {
            let m = members.len();
            let mut a = vec![0.0; m * m];
            for (r, &ar) in members.iter().enumerate() {
                for (c, &ac) in members.iter().enumerate() {
                    a[r * m + c] = if r == c {
                        diag[ar]
                    } else {
                        exact.coefficient(active[ar], active[ac])
                    };
                }
            }
            if cholesky(&mut a, m) { a } else { Vec::new() }
        };
        let factors: Vec<Vec<f64>> = match par {
            Par::Seq => blocks.iter().map(factor_block).collect(),
            Par::Rayon(_) => blocks.par_iter().map(factor_block).collect(),
        };
        // Coarse clusters: renumber the non-empty ones.
        let mut ids: Vec<usize> = block_coarse.clone();
        ids.sort_unstable();
        ids.dedup();
        let nc = ids.len();
        let mut coarse_of = vec![0usize; na];
        let mut members: Vec<Vec<usize>> = vec![Vec::new(); nc];
        for (b, block) in blocks.iter().enumerate() {
            let c = ids.binary_search(&block_coarse[b]).unwrap_or(0);
            for &a in block {
                coarse_of[a] = c;
                members[c].push(a);
            }
        }
        let mut coarse = None;
        let mut coarse_stack = MemBuffer::new(faer::dyn_stack::StackReq::EMPTY);
        if nc >= 2 {
            let centroid: Vec<[f64; 2]> = members
                .iter()
                .map(|m| {
                    let (mut x, mut y) = (0.0, 0.0);
                    for &a in m {
                        x += positions[active[a]][0];
                        y += positions[active[a]][1];
                    }
                    [x / m.len() as f64, y / m.len() as f64]
                })
                .collect();
            let radius: Vec<f64> = members
                .iter()
                .zip(&centroid)
                .map(|(m, c)| {
                    m.iter()
                        .map(|&a| {
                            let p = positions[active[a]];
                            (p[0] - c[0]).hypot(p[1] - c[1])
                        })
                        .fold(0.0, f64::max)
                })
                .collect();
            let factor = exact.factor();
            let row = |c: usize| -> Vec<f64> {
                (0..nc)
                    .map(|d| {
                        let (pc, pd) = (centroid[c], centroid[d]);
                        let dist = (pc[0] - pd[0]).hypot(pc[1] - pd[1]);
                        if c != d && dist > 1.2 * (radius[c] + radius[d]) {
                            factor * (members[c].len() * members[d].len()) as f64 / dist
                        } else {
                            let mut s = 0.0;
                            for &a in &members[c] {
                                for &b in &members[d] {
                                    s += if a == b {
                                        diag[a]
                                    } else {
                                        exact.coefficient(active[a], active[b])
                                    };
                                }
                            }
                            s
                        }
                    })
                    .collect()
            };
            let rows: Vec<Vec<f64>> = match par {
                Par::Seq => (0..nc).map(row).collect(),
                Par::Rayon(_) => (0..nc).into_par_iter().map(row).collect(),
            };
            let mut m0 = Mat::<f64>::zeros(nc, nc);
            for (c, r) in rows.iter().enumerate() {
                for (d, v) in r.iter().enumerate() {
                    // Symmetrise the centroid approximation.
                    m0[(c, d)] = 0.5 * (v + rows[d][c]);
                }
            }
            let req = llt::factor::cholesky_in_place_scratch::<f64>(nc, par, Default::default())
                .or(llt::solve::solve_in_place_scratch::<f64>(nc, 1, par));
            coarse_stack = MemBuffer::new(req);
            let ok = llt::factor::cholesky_in_place(
                m0.as_mut(),
                Default::default(),
                par,
                MemStack::new(&mut coarse_stack),
                Default::default(),
            )
            .is_ok();
            if ok {
                coarse = Some(m0);
            }
        }
        Self {
            blocks,
            factors,
            diag,
            coarse_of,
            coarse,
            coarse_stack,
        }
    }

    fn apply(&mut self, r: &[f64], z: &mut [f64], par: Par) {
        for (block, factor) in self.blocks.iter().zip(&self.factors) {
            if factor.is_empty() {
                for &a in block {
                    z[a] = r[a] / self.diag[a];
                }
            } else {
                let mut x: Vec<f64> = block.iter().map(|&a| r[a]).collect();
                cholesky_solve(factor, block.len(), &mut x);
                for (&a, v) in block.iter().zip(x) {
                    z[a] = v;
                }
            }
        }
        if let Some(l) = &self.coarse {
            let nc = l.nrows();
            let mut rc = Mat::<f64>::zeros(nc, 1);
            for (a, &c) in self.coarse_of.iter().enumerate() {
                rc[(c, 0)] += r[a];
            }
            llt::solve::solve_in_place(
                l.as_ref(),
                rc.as_mut(),
                par,
                MemStack::new(&mut self.coarse_stack),
            );
            for (a, &c) in self.coarse_of.iter().enumerate() {
                z[a] += rc[(c, 0)];
            }
        }
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

/// Solves `M x = b` to `‖b − Mx‖ ≤ rtol ‖b‖` from the initial guess in `x`:
/// preconditioned CG, switching to GMRES(m) on non-positive curvature.
/// Returns the statistics; `x` holds the best iterate.
pub(crate) fn solve(
    m: &ActiveOperator<'_>,
    pre: &mut Preconditioner,
    b: &[f64],
    x: &mut [f64],
    rtol: f64,
    max_products: usize,
) -> KrylovStats {
    let na = b.len();
    let mut full = vec![0.0; m.n];
    let mut out = vec![0.0; m.n];
    let mut stats = KrylovStats::default();
    let bnorm = dot(b, b).sqrt();
    if bnorm == 0.0 {
        x.iter_mut().for_each(|v| *v = 0.0);
        return stats;
    }
    let target = rtol * bnorm;
    let mut r = vec![0.0; na];
    let mut mp = vec![0.0; na];
    m.apply(x, &mut mp, &mut full, &mut out);
    stats.products += 1;
    for i in 0..na {
        r[i] = b[i] - mp[i];
    }
    if dot(&r, &r).sqrt() <= target {
        return stats;
    }
    let mut z = vec![0.0; na];
    pre.apply(&r, &mut z, m.par);
    let mut p = z.clone();
    let mut rz = dot(&r, &z);
    let mut indefinite = false;
    while stats.products < max_products {
        m.apply(&p, &mut mp, &mut full, &mut out);
        stats.products += 1;
        let curv = dot(&p, &mp);
        if !(curv > 0.0) || !(rz > 0.0) {
            indefinite = true;
            stats.breakdowns += 1;
            break;
        }
        let alpha = rz / curv;
        for i in 0..na {
            x[i] += alpha * p[i];
            r[i] -= alpha * mp[i];
        }
        if dot(&r, &r).sqrt() <= target {
            return stats;
        }
        pre.apply(&r, &mut z, m.par);
        let rz_new = dot(&r, &z);
        let beta = rz_new / rz;
        rz = rz_new;
        for i in 0..na {
            p[i] = z[i] + beta * p[i];
        }
    }
    if indefinite {
        gmres(m, pre, b, x, target, max_products, &mut stats, 40);
    }
    stats
}

/// Right-preconditioned restarted GMRES(`restart`).
#[allow(clippy::too_many_arguments)]
fn gmres(
    m: &ActiveOperator<'_>,
    pre: &mut Preconditioner,
    b: &[f64],
    x: &mut [f64],
    target: f64,
    max_products: usize,
    stats: &mut KrylovStats,
    restart: usize,
) {
    let na = b.len();
    let mut full = vec![0.0; m.n];
    let mut out = vec![0.0; m.n];
    let mut w = vec![0.0; na];
    let mut z = vec![0.0; na];
    while stats.products < max_products {
        m.apply(x, &mut w, &mut full, &mut out);
        stats.products += 1;
        let r: Vec<f64> = b.iter().zip(&w).map(|(b, w)| b - w).collect();
        let beta = dot(&r, &r).sqrt();
        if beta <= target {
            return;
        }
        let mut v: Vec<Vec<f64>> = vec![r.iter().map(|v| v / beta).collect()];
        let mut zs: Vec<Vec<f64>> = Vec::new();
        let mut h = vec![vec![0.0; restart]; restart + 1];
        let (mut cs, mut sn) = (vec![0.0; restart], vec![0.0; restart]);
        let mut g = vec![0.0; restart + 1];
        g[0] = beta;
        let mut k_used = 0;
        for k in 0..restart {
            pre.apply(&v[k], &mut z, m.par);
            zs.push(z.clone());
            m.apply(&z, &mut w, &mut full, &mut out);
            stats.products += 1;
            for (j, vj) in v.iter().enumerate() {
                let hjk = dot(&w, vj);
                h[j][k] = hjk;
                for i in 0..na {
                    w[i] -= hjk * vj[i];
                }
            }
            let hn = dot(&w, &w).sqrt();
            h[k + 1][k] = hn;
            for j in 0..k {
                let t = cs[j] * h[j][k] + sn[j] * h[j + 1][k];
                h[j + 1][k] = -sn[j] * h[j][k] + cs[j] * h[j + 1][k];
                h[j][k] = t;
            }
            let denom = h[k][k].hypot(h[k + 1][k]);
            (cs[k], sn[k]) = if denom > 0.0 {
                (h[k][k] / denom, h[k + 1][k] / denom)
            } else {
                (1.0, 0.0)
            };
            h[k][k] = cs[k] * h[k][k] + sn[k] * h[k + 1][k];
            h[k + 1][k] = 0.0;
            g[k + 1] = -sn[k] * g[k];
            g[k] *= cs[k];
            k_used = k + 1;
            if g[k + 1].abs() <= target || hn == 0.0 || stats.products >= max_products {
                break;
            }
            v.push(w.iter().map(|w| w / hn).collect());
        }
        let mut y = vec![0.0; k_used];
        for i in (0..k_used).rev() {
            let mut s = g[i];
            for j in i + 1..k_used {
                s -= h[i][j] * y[j];
            }
            y[i] = if h[i][i] != 0.0 { s / h[i][i] } else { 0.0 };
        }
        for (yj, zj) in y.iter().zip(&zs) {
            for i in 0..na {
                x[i] += yj * zj[i];
            }
        }
        if g[k_used].abs() <= target {
            return;
        }
    }
}
