//! How deep a rolling road's calibration tables reach (docs/performance.md,
//! "Tables as deep as the run presses").
//!
//! In a rolling step under load the tread's gap equation gives asperity `i`,
//! at footprint offset `(ξ, η_i)`, the indentation
//!
//! ```text
//! δ_i = δ0 − (z_top − z_i) − s_i(ξ) − u_i,     u_i = Σ_{j≠i} F_j / (π E* r_ij) ≥ 0
//! ```
//!
//! (`s_i` the tread's contact gap, [`crate::rolling::Tread::contact_gap`];
//! `u_i` the displacement the other contacts cause at `i`). The *bound*
//! drops `u_i`: a table to `margin · max δ0 − (z_top − z_i) − min_ξ s_i`
//! covers every step. But under a tyre `u_i` is most of the approach: the
//! tread's load sags the whole footprint by about `p̄ L / E*`, and the
//! bound's deep knots, the dearest to solve (the largest contacts), are
//! never reached (on the chip-seal fixture no cap used more than half its
//! range, 60 % of the caps none of it).
//!
//! The *estimate* keeps the part of `u_i` that does not depend on the
//! neighbours' contacts: the displacement of the contacts farther than `ρ`
//! from the point (`ρ` two mean asperity spacings), the tread's smooth
//! sag. [`BulkSag`] tabulates, on a grid of footprint offsets, the least of
//! that far-field displacement over the coarse Wilke steps that already
//! bound `max δ0`; each cap's table then reaches
//!
//! ```text
//! D_i = margin · (max δ0 − (z_top − z_i) − min_ξ [s_i(ξ) + sag · Û(ξ, η_i)])
//! ```
//!
//! over the footprint offsets its path reaches ([`estimated_lift`]: the
//! margin widens the cap's estimated indentation, where the bound widens
//! the whole approach). It is an estimate, not a
//! bound (the calibrated laws spread the load otherwise than the Wilke
//! ones): a whole run checks its contacts against their tables
//! ([`super::rolling::caps_past_tables`]) and repeats itself with the caps
//! it pressed past their tables tabulated to the bound
//! ([`TablePlan::deepened`]).
//!
//! Invariants: `sag = 0` is the bound, cap for cap; for `sag ≥ 0` no table
//! reaches deeper than the bound (`Û ≥ 0`); a cap listed in
//! [`TablePlan::deepen`] gets the bound whatever `sag`.

use super::FidelityError;
use super::under_tread::CalibrateUnder;
use crate::rolling::{self, RollingConfig, RollingResult, StepStatus};
use crate::texture_road::TextureLaw;

/// What tables a rolling road's calibration gives its caps: each cap under
/// what ([`CalibrateUnder`]) and how deep (module doc).
#[derive(Clone, Debug, PartialEq)]
pub struct TablePlan {
    /// The shape each cap is calibrated under.
    pub under: CalibrateUnder,
    /// Fraction of the estimated bulk sag taken off each table's depth:
    /// 1 the estimate, 0 the bound.
    pub sag: f64,
    /// Caps (indices in the calibrated road, the calibration's `kept`
    /// order) tabulated to the bound whatever `sag`: those a run pressed
    /// past their estimated tables. Sorted, without repeats.
    pub deepen: Vec<usize>,
}

impl TablePlan {
    /// Tables to the estimated depth, each cap under `under`.
    pub fn new(under: CalibrateUnder) -> Self {
        Self {
            under,
            sag: 1.0,
            deepen: Vec::new(),
        }
    }

    /// Tables to the bound, each cap under `under`: no run's contact passes
    /// them unless its approach passes the margin. For runs that cannot
    /// repeat themselves (a part of a distributed run, a viscoelastic run).
    pub fn bound(under: CalibrateUnder) -> Self {
        Self {
            sag: 0.0,
            ..Self::new(under)
        }
    }

    /// This plan with `caps` (indices in the calibrated road) also
    /// tabulated to the bound.
    #[must_use]
    pub fn deepened(&self, caps: &[usize]) -> Self {
        let mut deepen = self.deepen.clone();
        deepen.extend_from_slice(caps);
        deepen.sort_unstable();
        deepen.dedup();
        Self {
            deepen,
            ..self.clone()
        }
    }

    /// Whether every table reaches the bound.
    pub fn is_bound(&self) -> bool {
        self.sag == 0.0
    }

    /// Checks `sag` (finite, ≥ 0).
    ///
    /// # Errors
    /// [`FidelityError::InvalidInput`] otherwise.
    pub fn validate(&self) -> Result<(), FidelityError> {
        if self.sag.is_finite() && self.sag >= 0.0 {
            Ok(())
        } else {
            Err(FidelityError::invalid(
                "bulk sag fraction",
                self.sag,
                "finite and >= 0",
            ))
        }
    }
}

/// Nodes of a [`BulkSag`] grid along its longer side, at most.
pub const MAX_SAG_NODES: usize = 65;

/// The displacement (m) that far contacts leave under footprint offsets
/// `(ξ, η)`, on a regular grid over the selection window: at each node the
/// least, over the given steps, of `Σ F_j / (π E* r_j)` over the step's
/// contacts farther than `ρ` from the node.
#[derive(Clone, Debug, PartialEq)]
pub struct BulkSag {
    origin: [f64; 2],
    spacing: f64,
    size: [usize; 2],
    values: Vec<f64>,
}

impl BulkSag {
    /// The sag of `steps` (converged steps of a run on `road`, each with
    /// its contacts' ids and forces) under `config`'s footprint, contacts
    /// closer than `rho` (m) to a node left out, `factor` Boussinesq's
    /// `1 / (π E*)` (1/Pa). `None` when no step has contacts or `rho` is
    /// not positive.
    pub fn from_steps(
        road: &rolling::Road<TextureLaw>,
        config: &RollingConfig,
        steps: &RollingResult,
        rho: f64,
        factor: f64,
    ) -> Option<Self> {
        if !(rho.is_finite() && rho > 0.0 && factor.is_finite() && factor > 0.0) {
            return None;
        }
        let loaded: Vec<_> = steps
            .steps
            .iter()
            .filter(|s| s.status != StepStatus::Failed && !s.contact_ids.is_empty())
            .collect();
        if loaded.is_empty() {
            return None;
        }
        let (hx, hy) = config.tread.half_extents();
        let m = config.tread.effective_margin(config.margin);
        let (ax, ay) = (hx + m, hy + m);
        let spacing = sag_spacing(rho, [ax, ay]);
        let size = [sag_nodes(2.0 * ax, spacing), sag_nodes(2.0 * ay, spacing)];
        let origin = [-ax, -ay];
        let rho2 = rho * rho;
        let mut values = vec![f64::INFINITY; size[0] * size[1]];
        for step in loaded {
            let points: Vec<([f64; 2], f64)> = step
                .contact_ids
                .iter()
                .zip(&step.contact_forces)
                .filter_map(|(&id, &f)| road.positions().get(id).map(|&p| (p, f)))
                .collect();
            for (n, v) in values.iter_mut().enumerate() {
                let x = step.position + origin[0] + (n % size[0]) as f64 * spacing;
                let y = config.lateral + origin[1] + (n / size[0]) as f64 * spacing;
                let u = far_displacement(&points, [x, y], rho2) * factor;
                *v = v.min(u);
            }
        }
        Some(Self {
            origin,
            spacing,
            size,
            values,
        })
    }

    /// The sag (m) at footprint offset `(xi, eta)`, bilinear between nodes,
    /// the nearest edge's value outside the grid.
    pub fn at(&self, xi: f64, eta: f64) -> f64 {
        let locate = |v: f64, o: f64, n: usize| {
            let t = ((v - o) / self.spacing).clamp(0.0, (n - 1) as f64);
            let k = (t.floor() as usize).min(n.saturating_sub(2));
            (k, t - k as f64)
        };
        let [nx, ny] = self.size;
        if nx < 2 || ny < 2 {
            return self.values.iter().copied().fold(f64::INFINITY, f64::min);
        }
        let (i, tx) = locate(xi, self.origin[0], nx);
        let (j, ty) = locate(eta, self.origin[1], ny);
        let v = |i: usize, j: usize| self.values[j * nx + i];
        (1.0 - ty) * ((1.0 - tx) * v(i, j) + tx * v(i + 1, j))
            + ty * ((1.0 - tx) * v(i, j + 1) + tx * v(i + 1, j + 1))
    }

    /// The grid spacing (m).
    pub fn spacing(&self) -> f64 {
        self.spacing
    }

    /// The largest sag on the grid (m).
    pub fn max(&self) -> f64 {
        self.values.iter().copied().fold(0.0, f64::max)
    }
}

/// The spacing (m) of a [`BulkSag`] grid over half-extents `half` (m):
/// a quarter of the left-out radius `rho` (the far field varies on the
/// scale of ρ and more), but at most [`MAX_SAG_NODES`] nodes a side, so
/// that a road of tiny dense caps does not make the grid the run's dearest
/// part.
pub fn sag_spacing(rho: f64, half: [f64; 2]) -> f64 {
    (0.25 * rho).max(2.0 * half[0].max(half[1]) / (MAX_SAG_NODES - 1) as f64)
}

/// Nodes covering `extent` (m) at `spacing` (m), ends included (rounding
/// does not add one).
fn sag_nodes(extent: f64, spacing: f64) -> usize {
    (extent / spacing * (1.0 - 1e-12)).ceil() as usize + 1
}

/// `Σ F_j / r_j` over the `points` `(position, force)` farther than
/// `sqrt(rho2)` from `at` (1/m · N).
pub fn far_displacement(points: &[([f64; 2], f64)], at: [f64; 2], rho2: f64) -> f64 {
    points
        .iter()
        .map(|&([x, y], f)| {
            let r2 = (x - at[0]).powi(2) + (y - at[1]).powi(2);
            if r2 > rho2 { f / r2.sqrt() } else { 0.0 }
        })
        .sum()
}

/// The radius (m) within which contacts are left out of the sag: two mean
/// spacings of the `count` asperities `config`'s path can select over its
/// swept rectangle.
pub fn exclusion_radius(config: &RollingConfig, count: usize) -> f64 {
    let (hx, hy) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    let area = ((config.end - config.start).abs() + 2.0 * (hx + m)) * 2.0 * (hy + m);
    2.0 * (area / count.max(1) as f64).sqrt()
}

/// Each of `road`'s asperities `indices[k]`: the least, over the footprint
/// offsets `ξ` its path reaches, of the tread's contact gap plus `sag ×`
/// the bulk sag there (m); `profile[k]` (the gap alone, the bound's lift)
/// where the tread leaves no gap to sample.
pub fn sagged_lifts(
    road: &rolling::Road<TextureLaw>,
    config: &RollingConfig,
    indices: &[usize],
    profile: &[f64],
    bulk: &BulkSag,
    sag: f64,
) -> Vec<f64> {
    let (lo, hi) = (config.start.min(config.end), config.start.max(config.end));
    let (hx, _) = config.tread.half_extents();
    let ax = hx + config.tread.effective_margin(config.margin);
    // Half the grid's spacing: the gap's minimum is bracketed by the
    // samples and the sampled ξ nearest the footprint's centre.
    let step = 0.5 * bulk.spacing();
    indices
        .iter()
        .zip(profile)
        .map(|(&i, &fallback)| {
            let [x, y] = road.positions()[i];
            let eta = y - config.lateral;
            let radius = road.summit_radius(i);
            let (a, b) = ((x - hi).max(-ax), (x - lo).min(ax));
            if a > b {
                return fallback;
            }
            let n = ((b - a) / step).ceil() as usize;
            let centre = 0.0f64.clamp(a, b);
            (0..=n)
                .map(|k| a + (b - a) * k as f64 / n.max(1) as f64)
                .chain(std::iter::once(centre))
                .filter_map(|xi| {
                    config
                        .tread
                        .contact_gap(xi, eta, radius)
                        .map(|(gap, _)| gap.max(0.0) + sag * bulk.at(xi, eta))
                })
                .reduce(f64::min)
                .map_or(fallback, |v| v.max(fallback))
        })
        .collect()
}

/// The lift (m) that makes a cap's table reach the estimated depth
/// `margin · (δ0 − headroom − sagged)` instead of the bound's
/// `margin · δ0 − headroom − profile` (the tables' depth is `margin · δ0 −
/// headroom − lift`): `margin · sagged + (margin − 1) · headroom`, never
/// below `profile` (never deeper than the bound). The margin then widens
/// the cap's own estimated indentation, not the whole approach: the
/// indentation is what a calibrated run presses deeper than a Wilke one.
pub fn estimated_lift(sagged: f64, headroom: f64, profile: f64, margin: f64) -> f64 {
    (margin * sagged + (margin - 1.0) * headroom.max(0.0)).max(profile)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The far field of equal forces on a fine square grid is Boussinesq's
    /// displacement at the centre of a uniformly loaded square less a disc
    /// of radius ρ: `p (8 a asinh 1 − 2 π ρ)` per unit compliance.
    #[test]
    fn far_displacement_of_a_uniform_square_is_the_closed_form_less_the_disc() {
        let (a, h, p): (f64, f64, f64) = (20e-3, 0.1e-3, 0.1e6);
        let n = (2.0 * a / h).round() as i64;
        let points: Vec<_> = (0..n)
            .flat_map(|i| (0..n).map(move |j| (i, j)))
            .map(|(i, j)| {
                let x = -a + (i as f64 + 0.5) * h;
                let y = -a + (j as f64 + 0.5) * h;
                ([x, y], p * h * h)
            })
            .collect();
        let rho = 5e-3;
        let sum = far_displacement(&points, [0.0, 0.0], rho * rho);
        let exact = p * (8.0 * a * 1f64.asinh() - 2.0 * std::f64::consts::PI * rho);
        // Midpoint cells, the disc's rim cutting some: measured 0.011 %.
        assert!((sum - exact).abs() < 1e-3 * exact, "{sum} vs {exact}");
        // Nothing is left out at ρ = 0 but the point itself.
        let all = far_displacement(&points, [0.0, 0.0], 0.0);
        assert!(all > sum);
    }

    /// A quarter of ρ on the fixtures' roads; never more than 65 nodes a
    /// side however small ρ gets.
    #[test]
    fn the_sag_grid_follows_rho_within_a_bounded_size() {
        let half = [60e-3, 75e-3];
        assert_eq!(sag_spacing(20e-3, half), 5e-3);
        for rho in [1e-3, 1e-4, 1e-6] {
            let spacing = sag_spacing(rho, half);
            let nodes = sag_nodes(2.0 * half[1], spacing);
            assert!(nodes <= MAX_SAG_NODES, "ρ {rho}: {nodes} nodes");
        }
    }

    #[test]
    fn a_plan_deepens_caps_once_and_in_order() {
        let plan = TablePlan::new(CalibrateUnder::Tread).deepened(&[5, 2, 5]);
        assert_eq!(plan.deepen, vec![2, 5]);
        assert_eq!(plan.deepened(&[3, 2]).deepen, vec![2, 3, 5]);
        assert!(!plan.is_bound());
        assert!(TablePlan::bound(CalibrateUnder::Flat).is_bound());
        let bad = TablePlan {
            sag: f64::NAN,
            ..TablePlan::new(CalibrateUnder::Flat)
        };
        assert!(bad.validate().is_err());
    }
}
