//! The binned double sum of the field coupling ([`super::field::field_compliance`])
//! laid out for the rolling steps' many near pairs: the same sum, reordered
//! and in single precision where that cannot matter.
//!
//! A [`PackedField`] holds one unit field's bins as separate `f32` arrays
//! of positions relative to the field's own centroid (so a coordinate is
//! at most the field's extent, a few mm, held to ~1e-10 m), padded with
//! zero-weight bins to a multiple of [`LANES`]. A pair's sum
//!
//! ```text
//! G = Σ_a w_a Σ_b w_b / max(|s + x_a − y_b|, floor),   s = c_A − c_B (f64, then f32)
//! ```
//!
//! runs its inner sum over [`LANES`] independent accumulators (which the
//! compiler turns into vector arithmetic) and each row's total into an
//! `f64`. Each term carries a relative error of a few `f32` ulps
//! (~2e-7) and each lane adds at most 32 terms (256 bins), so `G` is the
//! `f64` sum to ~1e-6 relative: a coupling error of 1e-6 of the point
//! kernel, a hundred times below what the coupling already leaves out
//! ([`super::coupling::NEGLIGIBLE`], 1e-4). Padding bins have zero weight
//! and add exactly zero. No allocation per pair.

/// Independent accumulators of the inner sum.
pub const LANES: usize = 8;

/// One unit field laid out for [`packed_compliance`] (module docs).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct PackedField {
    /// The field's centroid (m): the points' origin.
    centroid: [f64; 2],
    x: Vec<f32>,
    y: Vec<f32>,
    w: Vec<f32>,
}

impl PackedField {
    /// Packs `field` (points in m, weights summing to one) about its
    /// centroid `centroid` (m).
    pub fn new(field: &[([f64; 2], f64)], centroid: [f64; 2]) -> Self {
        let padded = field.len().div_ceil(LANES) * LANES;
        let mut packed = Self {
            centroid,
            x: Vec::with_capacity(padded),
            y: Vec::with_capacity(padded),
            w: Vec::with_capacity(padded),
        };
        for (p, w) in field {
            packed.x.push((p[0] - centroid[0]) as f32);
            packed.y.push((p[1] - centroid[1]) as f32);
            packed.w.push(*w as f32);
        }
        packed.x.resize(padded, 0.0);
        packed.y.resize(padded, 0.0);
        packed.w.resize(padded, 0.0);
        packed
    }

    /// Bins held, padding included.
    pub fn len(&self) -> usize {
        self.w.len()
    }

    /// Whether the field holds no bin.
    pub fn is_empty(&self) -> bool {
        self.w.is_empty()
    }
}

/// `G = Σ_a Σ_b w_a w_b / max(|x_a − y_b|, floor)` between two packed
/// fields (1/m; module docs): [`super::field::field_compliance`] to ~1e-6
/// relative.
pub fn packed_compliance(a: &PackedField, b: &PackedField, floor: f64) -> f64 {
    // Rows run over the smaller field: fewer row totals, longer inner loops.
    let (a, b) = if a.len() <= b.len() { (a, b) } else { (b, a) };
    if a.is_empty() {
        return 0.0;
    }
    let shift = [
        (a.centroid[0] - b.centroid[0]) as f32,
        (a.centroid[1] - b.centroid[1]) as f32,
    ];
    let floor2 = (floor * floor) as f32;
    let mut sum = 0.0_f64;
    for ((&xa, &ya), &wa) in a.x.iter().zip(&a.y).zip(&a.w) {
        if wa == 0.0 {
            continue;
        }
        let (px, py) = (xa + shift[0], ya + shift[1]);
        let mut acc = [0.0_f32; LANES];
        for ((xs, ys), ws) in
            b.x.chunks_exact(LANES)
                .zip(b.y.chunks_exact(LANES))
                .zip(b.w.chunks_exact(LANES))
        {
            for l in 0..LANES {
                let (dx, dy) = (px - xs[l], py - ys[l]);
                let d2 = (dx * dx + dy * dy).max(floor2);
                acc[l] += ws[l] / d2.sqrt();
            }
        }
        let row: f64 = acc.iter().map(|&v| f64::from(v)).sum();
        sum += f64::from(wa) * row;
    }
    sum
}

#[cfg(test)]
mod tests {
    use super::super::field::field_compliance;
    use super::*;

    /// A ragged field of `n` points around `at` (m) with uneven weights.
    fn field(n: usize, at: [f64; 2], spread: f64, seed: u64) -> Vec<([f64; 2], f64)> {
        let mut s = seed;
        let mut next = || {
            s = s
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (s >> 11) as f64 / (1u64 << 53) as f64
        };
        let mut f: Vec<([f64; 2], f64)> = (0..n)
            .map(|_| {
                (
                    [at[0] + spread * next(), at[1] + spread * next()],
                    0.1 + next(),
                )
            })
            .collect();
        let total: f64 = f.iter().map(|p| p.1).sum();
        f.iter_mut().for_each(|p| p.1 /= total);
        f
    }

    fn packed(f: &[([f64; 2], f64)]) -> PackedField {
        let c = super::super::field::centroid_and_reach(f, [0.0; 2]).0;
        PackedField::new(f, c)
    }

    #[test]
    fn packed_sum_is_the_double_sum_to_a_micro_relative() {
        // Fields of 3 to 256 bins (remainders of every lane count), apart,
        // touching and overlapping (the floor active), far from the origin
        // as a road's asperities are: the f64 double sum to 2e-6.
        for (k, (na, nb, gap)) in [
            (1, 1, 5e-3),
            (3, 250, 2e-3),
            (256, 256, 4e-3),
            (17, 64, 0.0),
            (100, 9, 1e-3),
            (256, 200, -1e-3),
        ]
        .into_iter()
        .enumerate()
        {
            let a = field(na, [0.12, 0.03], 4e-3, k as u64);
            let b = field(nb, [0.124 + gap, 0.031], 3e-3, 100 + k as u64);
            let floor = 1e-4;
            let exact = field_compliance(&a, &b, floor);
            let fast = packed_compliance(&packed(&a), &packed(&b), floor);
            assert!(
                (fast / exact - 1.0).abs() < 2e-6,
                "{na} × {nb} bins, gap {gap}: {fast} vs {exact}"
            );
            // Symmetric in its two fields.
            let swapped = packed_compliance(&packed(&b), &packed(&a), floor);
            assert!((swapped / exact - 1.0).abs() < 2e-6);
        }
    }

    #[test]
    fn an_empty_field_couples_to_nothing() {
        let a = field(10, [0.0; 2], 1e-3, 1);
        assert_eq!(
            packed_compliance(&packed(&a), &PackedField::default(), 1e-4),
            0.0
        );
    }
}
