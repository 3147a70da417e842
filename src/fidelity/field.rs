//! Compact calibrated pressure fields (the `calibrated_fields` rung): each
//! calibration knot's BEM pressure lumped into at most
//! [`MAX_BINS_PER_SIDE`]² square bins, and the field-to-field compliance
//! the coupling is built from.
//!
//! A bin keeps the force of the cells whose centres fall in it and their
//! force-weighted centroid (so a bin's point carries the bin's first
//! moment exactly). The bin lattice is fixed per patch — side
//! `b = max(dx, dy, L / 16)` with `L` the patch's longest side — so the
//! knots of one table share it and a depth between two knots is the linear
//! blend of their bin forces and moments (a force-weighted blend of the two
//! fields). Positions are in the patch's frame (cell `(0, 0)` at the
//! origin); the law that owns the table knows where its summit is.
//!
//! The compliance of two unit-force fields `w_a`, `w_b` (weights summing to
//! one) at points `x_a`, `x_b`:
//!
//! ```text
//! G = Σ_a Σ_b w_a w_b / |x_a − x_b|       (divided by f = 1/(π E*))
//! ```
//!
//! is the work-conjugate (pressure-weighted) mean displacement of one field
//! under the other; it tends to `1/r` between the centroids as the fields
//! separate. Lumping a bin to a point errs by `O((b/r)²)` a pair of bins;
//! two bins closer than half a bin are held at half a bin (their exact
//! mutual mean is bounded, the point one is not).

/// Most bins along a side of a patch: ≤ 256 bins a knot.
pub const MAX_BINS_PER_SIDE: usize = 16;

/// One bin at one knot: force (N) and first moment (N·m) in the patch frame.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Bin {
    index: u32,
    force: f64,
    moment: [f64; 2],
}

/// The binned pressure fields of one calibrated table, one per knot.
#[derive(Clone, Debug, PartialEq)]
pub struct BinnedField {
    /// Bin side (m).
    bin: f64,
    /// Per knot, the non-empty bins sorted by index.
    knots: Vec<Vec<Bin>>,
}

/// A unit-force field: points (m) and weights summing to one.
pub type UnitField = Vec<([f64; 2], f64)>;

impl BinnedField {
    /// An empty field on the lattice of a `nx × ny` patch of cells
    /// `dx × dy`; knots are added with [`Self::push_knot`].
    pub(crate) fn new(nx: usize, ny: usize, dx: f64, dy: f64) -> Self {
        let longest = (nx as f64 * dx).max(ny as f64 * dy);
        let bin = dx.max(dy).max(longest / MAX_BINS_PER_SIDE as f64);
        Self {
            bin,
            knots: Vec::new(),
        }
    }

    /// The bin side (m).
    pub fn bin_size(&self) -> f64 {
        self.bin
    }

    /// Number of knots.
    pub fn knots(&self) -> usize {
        self.knots.len()
    }

    /// Appends a knot from a pressure field (Pa) on the patch's `nx × ny`
    /// cells of `dx × dy` (row-major); an empty knot (no force) for `None`.
    pub(crate) fn push_knot(&mut self, pressure: Option<&[f64]>, nx: usize, dx: f64, dy: f64) {
        let mut bins: Vec<Bin> = Vec::new();
        if let Some(pressure) = pressure {
            let per_row = ((nx as f64 * dx) / self.bin).ceil() as usize + 1;
            let mut map = std::collections::BTreeMap::<u32, Bin>::new();
            for (c, &p) in pressure.iter().enumerate() {
                if !(p > 0.0) {
                    continue;
                }
                let (x, y) = ((c % nx) as f64 * dx, (c / nx) as f64 * dy);
                let (bx, by) = ((x / self.bin) as usize, (y / self.bin) as usize);
                let index = (by * per_row + bx) as u32;
                let f = p * dx * dy;
                let b = map.entry(index).or_insert(Bin {
                    index,
                    force: 0.0,
                    moment: [0.0; 2],
                });
                b.force += f;
                b.moment[0] += f * x;
                b.moment[1] += f * y;
            }
            bins = map.into_values().collect();
        }
        self.knots.push(bins);
    }

    /// The bins of knot `k` as `(index, force, moment)`, by index (for
    /// the disk cache); none past the last knot.
    pub(crate) fn bins(&self, k: usize) -> impl Iterator<Item = (u32, f64, [f64; 2])> + '_ {
        self.knots
            .get(k)
            .into_iter()
            .flatten()
            .map(|b| (b.index, b.force, b.moment))
    }

    /// A field from its bin side (m) and each knot's bins as
    /// [`Self::bins`] gives them; `None` unless the side is finite and
    /// positive, every force finite and positive, every moment finite and
    /// each knot's indices strictly increasing (what [`Self::push_knot`]
    /// makes).
    pub(crate) fn from_bins(bin: f64, knots: Vec<Vec<(u32, f64, [f64; 2])>>) -> Option<Self> {
        if !(bin.is_finite() && bin > 0.0) {
            return None;
        }
        let knots = knots
            .into_iter()
            .map(|bins| {
                let ok = bins.windows(2).all(|w| w[0].0 < w[1].0)
                    && bins.iter().all(|&(_, f, m)| {
                        f.is_finite() && f > 0.0 && m[0].is_finite() && m[1].is_finite()
                    });
                ok.then(|| {
                    bins.into_iter()
                        .map(|(index, force, moment)| Bin {
                            index,
                            force,
                            moment,
                        })
                        .collect()
                })
            })
            .collect::<Option<Vec<_>>>()?;
        Some(Self { bin, knots })
    }

    /// The unit field at a depth between knots `k` and `k + 1` at fraction
    /// `t ∈ [0, 1]` (knot indices of the owning table), shifted by
    /// `origin` (m): the bins' forces and moments blended linearly, each
    /// bin at its blended centroid, weights normalised. An empty knot
    /// blends as the other one's shape; with both empty, the first
    /// non-empty knot (the shape at contact onset); `None` if every knot is
    /// empty.
    pub(crate) fn unit_field(&self, k: usize, t: f64, origin: [f64; 2]) -> Option<UnitField> {
        let empty = |k: usize| self.knots.get(k).is_none_or(|b| b.is_empty());
        let (a, b, t) = match (empty(k), empty(k + 1)) {
            (false, false) => (k, k + 1, t.clamp(0.0, 1.0)),
            (false, true) => (k, k, 0.0),
            (true, false) => (k + 1, k + 1, 0.0),
            (true, true) => {
                let first = (0..self.knots.len()).find(|&k| !empty(k))?;
                (first, first, 0.0)
            }
        };
        let mut merged: Vec<(f64, [f64; 2])> = Vec::new();
        let (lo, hi) = (&self.knots[a], &self.knots[b]);
        let (mut i, mut j) = (0, 0);
        let scaled = |bin: &Bin, s: f64| (s * bin.force, [s * bin.moment[0], s * bin.moment[1]]);
        while i < lo.len() || j < hi.len() {
            let (f, m) = match (lo.get(i), hi.get(j)) {
                (Some(x), Some(y)) if x.index == y.index => {
                    i += 1;
                    j += 1;
                    let (fa, ma) = scaled(x, 1.0 - t);
                    let (fb, mb) = scaled(y, t);
                    (fa + fb, [ma[0] + mb[0], ma[1] + mb[1]])
                }
                (Some(x), Some(y)) if x.index < y.index => {
                    i += 1;
                    scaled(x, 1.0 - t)
                }
                (Some(x), None) => {
                    i += 1;
                    scaled(x, 1.0 - t)
                }
                (_, Some(y)) => {
                    j += 1;
                    scaled(y, t)
                }
                (None, None) => break,
            };
            if f > 0.0 {
                merged.push((f, m));
            }
        }
        let total: f64 = merged.iter().map(|m| m.0).sum();
        if !(total > 0.0) {
            return None;
        }
        Some(
            merged
                .into_iter()
                .map(|(f, m)| ([origin[0] + m[0] / f, origin[1] + m[1] / f], f / total))
                .collect(),
        )
    }
}

/// `G = Σ_a Σ_b w_a w_b / max(|x_a − y_b|, floor)` between two unit fields
/// (1/m; module docs). `floor` (m) bounds the kernel between bins that
/// (nearly) coincide.
pub fn field_compliance(a: &[([f64; 2], f64)], b: &[([f64; 2], f64)], floor: f64) -> f64 {
    let mut sum = 0.0;
    for (x, wa) in a {
        let mut row = 0.0;
        for (y, wb) in b {
            let d = ((x[0] - y[0]).powi(2) + (x[1] - y[1]).powi(2)).sqrt();
            row += wb / d.max(floor);
        }
        sum += wa * row;
    }
    sum
}

/// Centroid of a unit field (m) and its largest distance from `about` (m).
pub(crate) fn centroid_and_reach(field: &[([f64; 2], f64)], about: [f64; 2]) -> ([f64; 2], f64) {
    let mut c = [0.0; 2];
    let mut reach = 0.0_f64;
    for (x, w) in field {
        c[0] += w * x[0];
        c[1] += w * x[1];
        reach = reach.max(((x[0] - about[0]).powi(2) + (x[1] - about[1]).powi(2)).sqrt());
    }
    (c, reach)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;

    /// A uniform pressure over the cells whose centres satisfy `inside`,
    /// binned as a one-knot field, shifted by `origin`.
    fn uniform(
        n: [usize; 2],
        cell: f64,
        inside: impl Fn(f64, f64) -> bool,
        origin: [f64; 2],
    ) -> UnitField {
        let mut p = vec![0.0; n[0] * n[1]];
        for (c, v) in p.iter_mut().enumerate() {
            let (x, y) = ((c % n[0]) as f64 * cell, (c / n[0]) as f64 * cell);
            if inside(x, y) {
                *v = 1.0;
            }
        }
        let mut f = BinnedField::new(n[0], n[1], cell, cell);
        f.push_knot(Some(&p), n[0], cell, cell);
        f.unit_field(0, 0.0, origin).unwrap()
    }

    #[test]
    fn two_uniform_discs_far_apart_couple_as_their_centres() {
        // Discs of radius 1 mm (0.05 mm cells, 16 × 16 bins of 0.1375 mm),
        // 20 mm apart: the exact mean of 1/r is (1/r)(1 + (a₁² + a₂²)/(8 r²)
        // + …) = (1/r)(1 + 6e-4): the double sum within 2e-4 of it.
        let (n, cell, a) = (45, 5e-5, 1e-3);
        let c = 22.0 * cell;
        let disc = |x: f64, y: f64| (x - c).powi(2) + (y - c).powi(2) <= a * a;
        let f1 = uniform([n, n], cell, disc, [0.0, 0.0]);
        let f2 = uniform([n, n], cell, disc, [20e-3, 0.0]);
        let r = 20e-3;
        let g = field_compliance(&f1, &f2, 1e-5);
        let exact = (1.0 + 2.0 * a * a / (8.0 * r * r)) / r;
        assert!(
            (g * r - exact * r).abs() < 2e-4,
            "{} vs {}",
            g * r,
            exact * r
        );
        assert!(f1.len() <= MAX_BINS_PER_SIDE * MAX_BINS_PER_SIDE);
        let w: f64 = f1.iter().map(|p| p.1).sum();
        assert!((w - 1.0).abs() < 1e-12);
    }

    #[test]
    fn two_parallel_strips_couple_by_the_mean_of_one_over_r() {
        // Two strips 40 mm × 0.1 mm, parallel, 10 mm apart: the mean of 1/r
        // between two parallel segments of length L at distance d is
        // (2/L²)(L asinh(L/d) − √(L² + d²) + d) (the strips' width adds
        // O((w/d)²) = 1e-4). The point kernel between their midpoints is
        // 52 % off; the 16 bins of 2.5 mm (lumping error ~(b/d)²/12) land
        // within 1 %.
        let (l, d, cell) = (40e-3, 10e-3, 1e-4);
        let n = [400, 1];
        let strip = |_: f64, _: f64| true;
        let s1 = uniform(n, cell, strip, [0.0, 0.0]);
        let s2 = uniform(n, cell, strip, [0.0, d]);
        let g = field_compliance(&s1, &s2, 1e-5);
        let exact = 2.0 / (l * l) * (l * (l / d).asinh() - (l * l + d * d).sqrt() + d);
        assert!((g / exact - 1.0).abs() < 0.01, "{g} vs {exact}");
        assert!((1.0 / d / exact - 1.0).abs() > 0.5);
        // Offset along their length by half a strip: still the double
        // integral, here by a fine independent midpoint rule.
        let s3 = uniform(n, cell, strip, [l / 2.0, d]);
        let m = 2000;
        let h = l / m as f64;
        let mut exact = 0.0;
        for p in 0..m {
            for q in 0..m {
                let dx = (p as f64 + 0.5) * h - (q as f64 + 0.5) * h - l / 2.0;
                exact += 1.0 / (dx * dx + d * d).sqrt();
            }
        }
        exact /= (m * m) as f64;
        let g = field_compliance(&s1, &s3, 1e-5);
        assert!((g / exact - 1.0).abs() < 0.01, "{g} vs {exact}");
    }

    #[test]
    fn knots_blend_linearly_and_empty_knots_take_the_neighbours_shape() {
        let (nx, cell) = (10, 1e-3);
        let mut f = BinnedField::new(nx, 1, cell, cell);
        f.push_knot(None, nx, cell, cell);
        let mut p = vec![0.0; nx];
        p[2] = 1.0;
        f.push_knot(Some(&p), nx, cell, cell);
        let mut q = vec![0.0; nx];
        q[2] = 1.0;
        q[7] = 3.0;
        f.push_knot(Some(&q), nx, cell, cell);
        // Below the first loaded knot: its shape, one point at x = 2 mm.
        let below = f.unit_field(0, 0.5, [0.0, 0.0]).unwrap();
        assert_eq!(below.len(), 1);
        assert!((below[0].0[0] - 2e-3).abs() < 1e-15);
        // Halfway: forces ½(1) + ½(1) = 1 at 2 mm and ½·3 at 7 mm.
        let half = f.unit_field(1, 0.5, [1.0, 0.0]).unwrap();
        assert_eq!(half.len(), 2);
        assert!((half[0].1 - 0.4).abs() < 1e-12 && (half[1].1 - 0.6).abs() < 1e-12);
        assert!((half[1].0[0] - (1.0 + 7e-3)).abs() < 1e-12);
        let all_empty = {
            let mut e = BinnedField::new(nx, 1, cell, cell);
            e.push_knot(None, nx, cell, cell);
            e
        };
        assert!(all_empty.unit_field(0, 0.0, [0.0; 2]).is_none());
    }
}
