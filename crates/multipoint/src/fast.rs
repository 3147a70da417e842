//! A fast Boussinesq product `u = T · x` with controlled accuracy: a
//! kernel-independent (Chebyshev-interpolation, "black-box") fast multipole
//! method on a uniform quadtree.
//!
//! # Method
//!
//! The bounding square of the summits is cut into `4^D` leaf boxes (`D` chosen
//! so that a leaf holds about [`FastOptions::leaf_size`] summits on average).
//! Boxes that touch (including the box itself) interact exactly (`1/r`
//! summed pair by pair, the "near field"). Well-separated boxes — at least one
//! box of their size between them — interact through Chebyshev interpolation
//! of the kernel on `n × n` nodes per box (`n` = [`FastOptions::order`]) in
//! both the source and the target variable: upward pass (leaf moments, then
//! child-to-parent interpolation), one `n² × n²` kernel matrix per box pair of
//! the interaction list (`1/r` is homogeneous, so the 40 distinct matrices of
//! a unit box serve every level, scaled by `1/h`), downward pass, and
//! interpolation back to the summits. Cost `O(N (s + n² + 27 n⁴/s))` for
//! `s` summits per leaf, memory `O(N + 4^D n²)`.
//!
//! # Accuracy
//!
//! The far field is the only approximation; its error decays geometrically
//! with the order, about `10^(−0.8 n)`. Measured relative error
//! `‖T̃x − Tx‖₂ / ‖Tx‖₂` on random layouts (uniform, and five tight
//! clusters) with random non-negative `x` (test `fast_operator_accuracy`,
//! N = 2000–3000, 24 summits per leaf): `1e-5`–`4e-5` at `n = 4`,
//! `2e-7`–`5e-7` at `n = 6`, `1e-8` at `n = 8`, `2e-10`–`7e-10` at `n = 10`.
//! The error bound [`FastBoussinesq::error_bound`] documents that table; it
//! is an empirical bound measured on uniform and clustered random layouts,
//! not a proof.
//!
//! Layouts far from uniform (dense clusters in a large empty square) remain
//! exact to the same accuracy but lose speed: the tree is uniform, not
//! adaptive, so crowded leaves make the near field grow.

use faer::Par;
use rayon::prelude::*;

/// Accuracy and granularity of a [`FastBoussinesq`] operator.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FastOptions {
    /// Chebyshev nodes per box side `n` (2..=16); the far-field error decays
    /// like `10^(−0.8 n)` (see [`FastBoussinesq::error_bound`]).
    pub order: usize,
    /// Average summits per leaf box (the near field is exact).
    pub leaf_size: usize,
}

impl Default for FastOptions {
    fn default() -> Self {
        Self {
            order: 10,
            leaf_size: 48,
        }
    }
}

/// `u = T · x` for the Boussinesq kernel `T_ij = f / r_ij` (`T_ii = 0`) by a
/// fast multipole method: exact near field, interpolated far field (see the
/// module documentation). Build once per layout, apply many times. Summits
/// at the same position do not interact (a [`crate::Problem`] refuses them
/// anyway).
#[derive(Clone, Debug)]
pub struct FastBoussinesq {
    factor: f64,
    order: usize,
    depth: usize,
    origin: [f64; 2],
    side: f64,
    /// Sorted slot → original index.
    perm: Vec<usize>,
    /// Positions in sorted (leaf-by-leaf) order.
    pts: Vec<[f64; 2]>,
    /// Leaf `b` holds sorted slots `leaf_start[b]..leaf_start[b + 1]`.
    leaf_start: Vec<usize>,
    /// Summits per box, per level.
    counts: Vec<Vec<usize>>,
    nodes: Vec<f64>,
    weights: Vec<f64>,
    /// Child-to-parent interpolation, `[k * n + k']`, for the low and high child.
    m2m: [Vec<f64>; 2],
    /// Unit-box kernel matrices for offsets `(ox, oy) ∈ [-3, 3]²`, `|o|∞ ≥ 2`.
    m2l: Vec<Vec<f64>>,
}

/// `Σ_j q_j / |(x, y) − p_j|` over a run of summits, pairs at distance 0
/// (the target itself) skipped. Four independent partial sums, so the loop
/// vectorises (a single running sum is a serial dependency chain).
#[inline]
pub(crate) fn near_sum(x: f64, y: f64, q: &[f64], pts: &[[f64; 2]]) -> f64 {
    let mut acc = [0.0; 4];
    let (qc, qr) = q.split_at(q.len() - q.len() % 4);
    let (pc, pr) = pts.split_at(qc.len());
    for (q4, p4) in qc.chunks_exact(4).zip(pc.chunks_exact(4)) {
        let mut r2 = [0.0; 4];
        for k in 0..4 {
            let (dx, dy) = (x - p4[k][0], y - p4[k][1]);
            r2[k] = dx * dx + dy * dy;
        }
        // Arithmetic masks rather than branches, so the lanes vectorise.
        for k in 0..4 {
            let on = f64::from(u8::from(r2[k] > 0.0));
            acc[k] += on * q4[k] / (r2[k] + (1.0 - on)).sqrt();
        }
    }
    let mut sum = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (&qj, pj) in qr.iter().zip(pr) {
        let (dx, dy) = (x - pj[0], y - pj[1]);
        let r2 = dx * dx + dy * dy;
        if r2 > 0.0 {
            sum += qj / r2.sqrt();
        }
    }
    sum
}

fn m2l_slot(ox: i64, oy: i64) -> usize {
    ((oy + 3) * 7 + (ox + 3)) as usize
}

impl FastBoussinesq {
    /// The operator for `positions` and compliance factor `f = (1 − ν²)/(π E)`.
    /// `options.order` is clamped to `2..=16`, `options.leaf_size` to ≥ 4.
    pub fn new(positions: &[[f64; 2]], factor: f64, options: FastOptions) -> Self {
        let n_pts = positions.len();
        let order = options.order.clamp(2, 16);
        let leaf = options.leaf_size.max(4);
        let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
        for p in positions {
            for k in 0..2 {
                lo[k] = lo[k].min(p[k]);
                hi[k] = hi[k].max(p[k]);
            }
        }
        if n_pts == 0 {
            lo = [0.0; 2];
            hi = [0.0; 2];
        }
        let mut side = (hi[0] - lo[0]).max(hi[1] - lo[1]);
        side = if side > 0.0 { side * (1.0 + 1e-9) } else { 1.0 };
        let mut depth = 0;
        while depth < 12 && n_pts > leaf * (1usize << (2 * depth)) {
            depth += 1;
        }
        let per_side = 1usize << depth;
        let h = side / per_side as f64;
        let leaf_of = |p: &[f64; 2]| -> usize {
            let ix = (((p[0] - lo[0]) / h) as usize).min(per_side - 1);
            let iy = (((p[1] - lo[1]) / h) as usize).min(per_side - 1);
            iy * per_side + ix
        };
        let n_leaves = per_side * per_side;
        let mut leaf_start = vec![0usize; n_leaves + 1];
        for p in positions {
            leaf_start[leaf_of(p) + 1] += 1;
        }
        for b in 0..n_leaves {
            leaf_start[b + 1] += leaf_start[b];
        }
        let mut fill = leaf_start.clone();
        let mut perm = vec![0usize; n_pts];
        for (i, p) in positions.iter().enumerate() {
            let b = leaf_of(p);
            perm[fill[b]] = i;
            fill[b] += 1;
        }
        let pts = perm.iter().map(|&i| positions[i]).collect();
        let mut counts = vec![Vec::new(); depth + 1];
        counts[depth] = (0..n_leaves)
            .map(|b| leaf_start[b + 1] - leaf_start[b])
            .collect();
        for l in (0..depth).rev() {
            let ps = 1usize << l;
            let mut c = vec![0usize; ps * ps];
            for iy in 0..2 * ps {
                for ix in 0..2 * ps {
                    c[(iy / 2) * ps + ix / 2] += counts[l + 1][iy * 2 * ps + ix];
                }
            }
            counts[l] = c;
        }
        let nodes: Vec<f64> = (0..order)
            .map(|k| ((2 * k + 1) as f64 * std::f64::consts::PI / (2 * order) as f64).cos())
            .collect();
        let weights: Vec<f64> = (0..order)
            .map(|k| {
                let s = ((2 * k + 1) as f64 * std::f64::consts::PI / (2 * order) as f64).sin();
                if k % 2 == 0 { s } else { -s }
            })
            .collect();
        let mut op = Self {
            factor,
            order,
            depth,
            origin: lo,
            side,
            perm,
            pts,
            leaf_start,
            counts,
            nodes,
            weights,
            m2m: [Vec::new(), Vec::new()],
            m2l: Vec::new(),
        };
        let n = order;
        let mut basis = vec![0.0; n];
        for (c, shift) in [(0usize, -0.5), (1, 0.5)] {
            let mut a = vec![0.0; n * n];
            for kp in 0..n {
                op.lagrange(shift + 0.5 * op.nodes[kp], &mut basis);
                for k in 0..n {
                    a[k * n + kp] = basis[k];
                }
            }
            op.m2m[c] = a;
        }
        let nn = n * n;
        op.m2l = vec![Vec::new(); 49];
        if depth >= 2 {
            for oy in -3i64..=3 {
                for ox in -3i64..=3 {
                    if ox.abs().max(oy.abs()) < 2 {
                        continue;
                    }
                    let mut k = vec![0.0; nn * nn];
                    for a in 0..nn {
                        let (ta, ma) = (op.nodes[a / n], op.nodes[a % n]);
                        for b in 0..nn {
                            let (tb, mb) = (op.nodes[b / n], op.nodes[b % n]);
                            let dx = 0.5 * ta - (ox as f64 + 0.5 * tb);
                            let dy = 0.5 * ma - (oy as f64 + 0.5 * mb);
                            k[a * nn + b] = 1.0 / (dx * dx + dy * dy).sqrt();
                        }
                    }
                    op.m2l[m2l_slot(ox, oy)] = k;
                }
            }
        }
        op
    }

    /// Number of summits.
    pub fn len(&self) -> usize {
        self.pts.len()
    }

    /// True without summits.
    pub fn is_empty(&self) -> bool {
        self.pts.is_empty()
    }

    /// The Chebyshev order in use.
    pub fn order(&self) -> usize {
        self.order
    }

    /// Depth of the quadtree (0: everything near field, i.e. exact).
    pub fn depth(&self) -> usize {
        self.depth
    }

    /// The empirical bound on the relative 2-norm error of [`Self::apply`]
    /// for the order in use: `10^(0.5 − 0.8 n)` (≥ 30× the error measured on
    /// uniform and clustered random layouts with non-negative `x`, test
    /// `fast_operator_accuracy`).
    /// Exact (0) when the tree is too shallow to have a far field.
    pub fn error_bound(&self) -> f64 {
        if self.depth < 2 {
            0.0
        } else {
            10f64.powf(0.5 - 0.8 * self.order as f64)
        }
    }

    /// Lagrange basis at the Chebyshev nodes, evaluated at `t ∈ [−1, 1]`
    /// (barycentric form).
    fn lagrange(&self, t: f64, out: &mut [f64]) {
        let mut sum = 0.0;
        for k in 0..self.order {
            let d = t - self.nodes[k];
            if d == 0.0 {
                out.iter_mut().for_each(|o| *o = 0.0);
                out[k] = 1.0;
                return;
            }
            out[k] = self.weights[k] / d;
            sum += out[k];
        }
        let inv = 1.0 / sum;
        out.iter_mut().for_each(|o| *o *= inv);
    }

    fn box_center(&self, level: usize, b: usize) -> [f64; 2] {
        let ps = 1usize << level;
        let h = self.side / ps as f64;
        [
            self.origin[0] + ((b % ps) as f64 + 0.5) * h,
            self.origin[1] + ((b / ps) as f64 + 0.5) * h,
        ]
    }

    /// Leaves as lists of original indices (empty leaves skipped), and the
    /// coarse boxes at `level` (≤ depth) that contain each leaf.
    pub(crate) fn clusters(&self, level: usize) -> (Vec<&[usize]>, Vec<usize>) {
        let level = level.min(self.depth);
        let ps = 1usize << self.depth;
        let shift = self.depth - level;
        let cps = 1usize << level;
        let mut leaves = Vec::new();
        let mut coarse = Vec::new();
        for b in 0..ps * ps {
            let r = self.leaf_start[b]..self.leaf_start[b + 1];
            if r.is_empty() {
                continue;
            }
            leaves.push(&self.perm[r]);
            let (ix, iy) = (b % ps, b / ps);
            coarse.push((iy >> shift) * cps + (ix >> shift));
        }
        (leaves, coarse)
    }

    /// `out = T · x` (original order). Honours `par`: `Par::Seq` runs on the
    /// calling thread only.
    ///
    /// # Panics
    /// When `x` or `out` does not hold one value per summit.
    pub fn apply(&self, x: &[f64], out: &mut [f64], par: Par) {
        let n_pts = self.pts.len();
        assert!(
            x.len() == n_pts && out.len() == n_pts,
            "FastBoussinesq::apply: {} forces and {} outputs for {n_pts} summits",
            x.len(),
            out.len()
        );
        let q: Vec<f64> = self.perm.iter().map(|&i| x[i]).collect();
        let n = self.order;
        let nn = n * n;
        let depth = self.depth;
        let seq = matches!(par, Par::Seq);
        // Upward pass: multipole weights per level (only levels ≥ 2 are used).
        let mut mult: Vec<Vec<f64>> = vec![Vec::new(); depth + 1];
        let mut local: Vec<Vec<f64>> = vec![Vec::new(); depth + 1];
        if depth >= 2 {
            let ps = 1usize << depth;
            let h = self.side / ps as f64;
            let mut m = vec![0.0; ps * ps * nn];
            let p2m = |b: usize, mb: &mut [f64]| {
                let r = self.leaf_start[b]..self.leaf_start[b + 1];
                if r.is_empty() {
                    return;
                }
                let c = self.box_center(depth, b);
                let (mut wx, mut wy) = (vec![0.0; n], vec![0.0; n]);
                for s in r {
                    if q[s] == 0.0 {
                        continue;
                    }
                    self.lagrange(2.0 * (self.pts[s][0] - c[0]) / h, &mut wx);
                    self.lagrange(2.0 * (self.pts[s][1] - c[1]) / h, &mut wy);
                    for k in 0..n {
                        let a = q[s] * wx[k];
                        for (mm, w) in mb[k * n..(k + 1) * n].iter_mut().zip(&wy) {
                            *mm += a * w;
                        }
                    }
                }
            };
            if seq {
                m.chunks_mut(nn).enumerate().for_each(|(b, mb)| p2m(b, mb));
            } else {
                m.par_chunks_mut(nn)
                    .enumerate()
                    .for_each(|(b, mb)| p2m(b, mb));
            }
            mult[depth] = m;
            for l in (2..depth).rev() {
                let ps = 1usize << l;
                let child = &mult[l + 1];
                let mut m = vec![0.0; ps * ps * nn];
                let m2m = |b: usize, mb: &mut [f64]| {
                    if self.counts[l][b] == 0 {
                        return;
                    }
                    let (ix, iy) = (b % ps, b / ps);
                    let mut tmp = vec![0.0; nn];
                    for cy in 0..2 {
                        for cx in 0..2 {
                            let cb = (2 * iy + cy) * 2 * ps + 2 * ix + cx;
                            if self.counts[l + 1][cb] == 0 {
                                continue;
                            }
                            let mc = &child[cb * nn..(cb + 1) * nn];
                            let (ax, ay) = (&self.m2m[cx], &self.m2m[cy]);
                            // tmp[k'][m] = Σ_m' ay[m][m'] mc[k'][m']
                            for kp in 0..n {
                                for mm in 0..n {
                                    let mut s = 0.0;
                                    for mp in 0..n {
                                        s += ay[mm * n + mp] * mc[kp * n + mp];
                                    }
                                    tmp[kp * n + mm] = s;
                                }
                            }
                            for k in 0..n {
                                for kp in 0..n {
                                    let a = ax[k * n + kp];
                                    for mm in 0..n {
                                        mb[k * n + mm] += a * tmp[kp * n + mm];
                                    }
                                }
                            }
                        }
                    }
                };
                if seq {
                    m.chunks_mut(nn).enumerate().for_each(|(b, mb)| m2m(b, mb));
                } else {
                    m.par_chunks_mut(nn)
                        .enumerate()
                        .for_each(|(b, mb)| m2m(b, mb));
                }
                mult[l] = m;
            }
            // Interaction lists, then the downward pass.
            for l in 2..=depth {
                let ps = 1usize << l;
                let scale = self.factor * ps as f64 / self.side;
                let mut loc = vec![0.0; ps * ps * nn];
                let ml = &mult[l];
                let parent = &local[l - 1];
                let m2l = |b: usize, lb: &mut [f64]| {
                    if self.counts[l][b] == 0 {
                        return;
                    }
                    let (ix, iy) = ((b % ps) as i64, (b / ps) as i64);
                    let (px, py) = (ix / 2, iy / 2);
                    for jy in (2 * (py - 1)).max(0)..=(2 * (py + 1) + 1).min(ps as i64 - 1) {
                        for jx in (2 * (px - 1)).max(0)..=(2 * (px + 1) + 1).min(ps as i64 - 1) {
                            let (ox, oy) = (jx - ix, jy - iy);
                            if ox.abs().max(oy.abs()) < 2 {
                                continue;
                            }
                            let sb = jy as usize * ps + jx as usize;
                            if self.counts[l][sb] == 0 {
                                continue;
                            }
                            let k = &self.m2l[m2l_slot(ox, oy)];
                            let ms = &ml[sb * nn..(sb + 1) * nn];
                            for (a, la) in lb.iter_mut().enumerate() {
                                let row = &k[a * nn..(a + 1) * nn];
                                let mut s = 0.0;
                                for (kk, mm) in row.iter().zip(ms) {
                                    s += kk * mm;
                                }
                                *la += scale * s;
                            }
                        }
                    }
                    if l > 2 {
                        // L2L from the parent: lb[k'][m'] += Σ ax[k][k'] ay[m][m'] lp[k][m].
                        let pb = (iy as usize / 2) * (ps / 2) + ix as usize / 2;
                        let lp = &parent[pb * nn..(pb + 1) * nn];
                        let (ax, ay) = (&self.m2m[(ix % 2) as usize], &self.m2m[(iy % 2) as usize]);
                        let mut tmp = vec![0.0; nn];
                        // tmp[k][m'] = Σ_m ay[m][m'] lp[k][m]
                        for k in 0..n {
                            for mm in 0..n {
                                let v = lp[k * n + mm];
                                for mp in 0..n {
                                    tmp[k * n + mp] += ay[mm * n + mp] * v;
                                }
                            }
                        }
                        for k in 0..n {
                            for kp in 0..n {
                                let a = ax[k * n + kp];
                                for mp in 0..n {
                                    lb[kp * n + mp] += a * tmp[k * n + mp];
                                }
                            }
                        }
                    }
                };
                if seq {
                    loc.chunks_mut(nn)
                        .enumerate()
                        .for_each(|(b, lb)| m2l(b, lb));
                } else {
                    loc.par_chunks_mut(nn)
                        .enumerate()
                        .for_each(|(b, lb)| m2l(b, lb));
                }
                local[l] = loc;
            }
        }
        // Leaves: far field from the local expansion, near field exactly.
        let ps = 1usize << depth;
        let h = self.side / ps as f64;
        let mut u = vec![0.0; n_pts];
        let leaf_local = &local[depth];
        let leaf_work = |b: usize, ub: &mut [f64]| {
            let start = self.leaf_start[b];
            let (ix, iy) = ((b % ps) as i64, (b / ps) as i64);
            for (t, ut) in ub.iter_mut().enumerate() {
                let s = start + t;
                let [xs, ys] = self.pts[s];
                let mut sum = 0.0;
                for jy in (iy - 1).max(0)..=(iy + 1).min(ps as i64 - 1) {
                    // The three leaves of a row are contiguous in the
                    // sorted order: one branch-free sweep (the summit
                    // itself, at distance 0, contributes 0).
                    let row = jy as usize * ps;
                    let first = row + (ix - 1).max(0) as usize;
                    let last = row + (ix + 1).min(ps as i64 - 1) as usize;
                    let range = self.leaf_start[first]..self.leaf_start[last + 1];
                    sum += near_sum(xs, ys, &q[range.clone()], &self.pts[range]);
                }
                *ut = self.factor * sum;
            }
            if depth >= 2 && !ub.is_empty() {
                let lb = &leaf_local[b * nn..(b + 1) * nn];
                let c = self.box_center(depth, b);
                let (mut wx, mut wy) = (vec![0.0; n], vec![0.0; n]);
                for (t, ut) in ub.iter_mut().enumerate() {
                    let [xs, ys] = self.pts[start + t];
                    self.lagrange(2.0 * (xs - c[0]) / h, &mut wx);
                    self.lagrange(2.0 * (ys - c[1]) / h, &mut wy);
                    let mut s = 0.0;
                    for k in 0..n {
                        let mut r = 0.0;
                        for (l, w) in lb[k * n..(k + 1) * n].iter().zip(&wy) {
                            r += l * w;
                        }
                        s += wx[k] * r;
                    }
                    *ut += s;
                }
            }
        };
        // Split u into per-leaf chunks.
        let mut chunks: Vec<(usize, &mut [f64])> = Vec::with_capacity(ps * ps);
        let mut rest: &mut [f64] = &mut u;
        for b in 0..ps * ps {
            let len = self.leaf_start[b + 1] - self.leaf_start[b];
            let (head, tail) = rest.split_at_mut(len);
            if len > 0 {
                chunks.push((b, head));
            }
            rest = tail;
        }
        if seq {
            chunks.into_iter().for_each(|(b, ub)| leaf_work(b, ub));
        } else {
            chunks
                .into_par_iter()
                .with_max_len(4)
                .for_each(|(b, ub)| leaf_work(b, ub));
        }
        for (s, &i) in self.perm.iter().enumerate() {
            out[i] = u[s];
        }
    }
}
