//! Rebuilding each cap under its neighbours' displacement (issue 15's
//! rung 4, "forces as fields"; docs/theory.md §3).
//!
//! A cap solved alone under its force carries its load as if the rest of
//! the half-space were unloaded. On the road its neighbours' pressures press
//! the surface down by
//!
//! ```text
//! u_i(x) = 1/(π E*) Σ_{j ≠ i} ∫ p_j(x') / |x − x'| dA'
//! ```
//!
//! which, to cap `i`, is the road lowered by `u_i`: its shape becomes
//! `h_i(x) − (u_i(x) − u_i(x_i))` (only the variation across the cap
//! matters under load control; the constant part is taken by the local
//! approach). Each pass takes the neighbours' fields of the pass before,
//! each binned into at most [`BINS`] × [`BINS`] force-weighted bins, and
//! evaluates `u_i` on a [`LATTICE`] × [`LATTICE`] lattice over the cap's
//! previous grid widened by half, interpolated bilinearly in between and
//! held at its edge value beyond (where the cap carries no pressure).
//!
//! Invariants: the forces are the caller's (the multipoint model's); a lone
//! asperity, or one whose neighbours carry nothing, keeps its shape exactly.
//! Cost per pass: `O(N² · BINS² · LATTICE²)` for the displacements, plus
//! the local solves of the first pass.

use std::sync::Arc;

use super::{LocalField, LocalShape};
use crate::contact_law::Material;

/// Bins per side of a neighbour's binned field.
pub const BINS: usize = 16;

/// Lattice nodes per side of a cap's displacement table.
pub const LATTICE: usize = 33;

/// One neighbour's pressure as point forces: `(x, y, force, half bin)`.
type Bins = Vec<(f64, f64, f64, f64)>;

/// The force of `field`'s pressure lumped into at most `BINS × BINS` bins,
/// each at its force-weighted centroid.
fn binned(local: &LocalField) -> Bins {
    let Some(field) = local.field.as_ref() else {
        return Vec::new();
    };
    let g = field.grid();
    let (nx, ny) = (g.nx(), g.ny());
    let (bx, by) = (nx.div_ceil(BINS), ny.div_ceil(BINS));
    let cell_area = g.dx() * g.dy();
    let half_bin = 0.5 * (bx as f64 * g.dx()).max(by as f64 * g.dy());
    let (mx, my) = (nx.div_ceil(bx), ny.div_ceil(by));
    let mut acc = vec![(0.0, 0.0, 0.0); mx * my];
    for j in 0..ny {
        let row = field.row(j);
        let y = g.y(j);
        for (i, &p) in row.iter().enumerate() {
            if p <= 0.0 {
                continue;
            }
            let f = p * cell_area;
            let a = &mut acc[(j / by) * mx + i / bx];
            a.0 += f * g.x(i);
            a.1 += f * y;
            a.2 += f;
        }
    }
    acc.into_iter()
        .filter(|a| a.2 > 0.0)
        .map(|(sx, sy, f)| (sx / f, sy / f, f, half_bin))
        .collect()
}

/// Displacement (m) at `x` under the point forces `bins`; a bin closer
/// than its half-width counts as at its half-width (a bounded stand-in for
/// the integrable `1/r` inside it).
fn displacement(x: [f64; 2], bins: &[Bins], skip: usize, compliance: f64) -> f64 {
    let mut u = 0.0;
    for (j, b) in bins.iter().enumerate() {
        if j == skip {
            continue;
        }
        for &(bx, by, f, half) in b {
            let r = ((x[0] - bx).powi(2) + (x[1] - by).powi(2)).sqrt();
            u += f / r.max(half);
        }
    }
    compliance * u
}

/// A cap's neighbour displacement on a lattice around its summit.
struct Lattice {
    lo: [f64; 2],
    step: f64,
    values: Vec<f64>,
}

impl Lattice {
    /// Bilinear interpolation, held at the edge beyond the lattice.
    fn at(&self, x: f64, y: f64) -> f64 {
        let last = (LATTICE - 1) as f64;
        let s = ((x - self.lo[0]) / self.step).clamp(0.0, last);
        let t = ((y - self.lo[1]) / self.step).clamp(0.0, last);
        let (i, j) = ((s as usize).min(LATTICE - 2), (t as usize).min(LATTICE - 2));
        let (fs, ft) = (s - i as f64, t - j as f64);
        let v = |i: usize, j: usize| self.values[j * LATTICE + i];
        (1.0 - ft) * ((1.0 - fs) * v(i, j) + fs * v(i + 1, j))
            + ft * ((1.0 - fs) * v(i, j + 1) + fs * v(i + 1, j + 1))
    }
}

/// The shapes of the next pass: each cap's shape lowered by the variation
/// of its neighbours' displacement (the module documentation), from the
/// fields `local` of the pass before. `shape(k)` is asperity `k`'s shape
/// of the first pass.
pub(super) fn coupled_shapes<'s>(
    local: &[LocalField],
    shape: impl Fn(usize) -> &'s LocalShape,
    material: &Material,
) -> Vec<LocalShape> {
    let compliance = 1.0 / (std::f64::consts::PI * material.reduced_modulus());
    let bins: Vec<Bins> = local.iter().map(binned).collect();
    let any_other_load = |k: usize| {
        bins.iter()
            .enumerate()
            .any(|(j, b)| j != k && !b.is_empty())
    };
    local
        .iter()
        .enumerate()
        .map(|(k, l)| {
            let base = shape(k).clone();
            let Some(field) = l.field.as_ref().filter(|_| any_other_load(k)) else {
                return base;
            };
            let g = field.grid();
            let half = 0.75 * (g.nx() as f64 * g.dx()).max(g.ny() as f64 * g.dy());
            let step = 2.0 * half / (LATTICE - 1) as f64;
            let lo = [l.centre[0] - half, l.centre[1] - half];
            let values = (0..LATTICE * LATTICE)
                .map(|n| {
                    let x = [
                        lo[0] + (n % LATTICE) as f64 * step,
                        lo[1] + (n / LATTICE) as f64 * step,
                    ];
                    displacement(x, &bins, k, compliance)
                })
                .collect();
            let lattice = Lattice { lo, step, values };
            let centre = l.centre;
            let at_summit = lattice.at(centre[0], centre[1]);
            let equivalent_radius = base.equivalent_radius();
            LocalShape::Custom {
                height: Arc::new(move |dx, dy| {
                    base.height(dx, dy) - (lattice.at(centre[0] + dx, centre[1] + dy) - at_summit)
                }),
                equivalent_radius,
            }
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_lattice_interpolates_a_plane_exactly_and_holds_its_edge() {
        let values = (0..LATTICE * LATTICE)
            .map(|n| 2.0 * (n % LATTICE) as f64 + 3.0 * (n / LATTICE) as f64)
            .collect();
        let l = Lattice {
            lo: [0.0, 0.0],
            step: 1.0,
            values,
        };
        assert!((l.at(2.5, 7.25) - (5.0 + 21.75)).abs() < 1e-12);
        let last = (LATTICE - 1) as f64;
        assert!((l.at(100.0, -5.0) - 2.0 * last).abs() < 1e-12);
    }
}
