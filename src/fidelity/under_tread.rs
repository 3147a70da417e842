//! Caps calibrated under the tread's local shape instead of a flat punch
//! (docs/validation.md, "Caps calibrated under the tread").
//!
//! A rolling cap meets the tyre tilted and curved over it: at lateral
//! offset `η` from the path the tread slopes `η/Ry` across, and it curves
//! `1/Rx`, `1/Ry`. Calibrated under a flat punch, the cap's law and field
//! are those of the wrong contact: on a long or asymmetric cap the tilt
//! moves the contact (and its load) along the cap. What is fixed per cap
//! on a straight path is the tread's cross profile at `η` and its
//! longitudinal curvature; the longitudinal slope `ξ/Rx` changes with
//! every step and stays with the model's contact-point gap
//! ([`crate::rolling::Tread::contact_gap`]). So each cap is calibrated
//! with the cap under the footprint's centre (`ξ = 0`): its patch minus
//! the tread surface's rise from the summit,
//!
//! ```text
//! c'(dx, dy) = c(dx, dy) − [s(dx, η + dy) − s(0, η)] − L_model,
//! L_model    = s(0, η) − s*(0, η; R)
//! ```
//!
//! `s*` the model's contact-point gap for the cap's summit radius `R`, so
//! that the table's `δ = 0` is where the model's gap says the cap first
//! touches (a paraboloid cap has `max c' = 0`: Hertz's law from its first
//! contact). A real cap may touch earlier than the paraboloid formula
//! says (`max c' = e > 0`): the asperity's height is then raised by `e`
//! and the patch lowered by it, so the gap the model computes is the
//! cap's first contact; a lift that would take the asperity above the
//! highest calibrated summit (the approach's reference) is capped there
//! and the rest of the cap's top clipped.
//!
//! The calibrated field is the pressure under the tilted tread, already
//! off the summit across the path: the law's origin is moved back by the
//! model's lateral contact-point offset, which the coupled step and the
//! sensors add again, so it counts once.
//!
//! Invariants: under a flat block (no slope, no curvature) and for a cap
//! on the path's axis of a tread with no transverse curvature the patch
//! is the flat one; the cache key holds the reshaped heights, so a table
//! calibrated under one tread never stands in for another.

use std::fmt;
use std::str::FromStr;

use super::{CapPatch, FidelityError, cap_patch};
use crate::rolling::Tread;
use crate::texture::{Asperity, HeightMap};

/// What each rolling cap is calibrated under (`[model] calibrate_under`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum CalibrateUnder {
    /// A flat punch (each cap alone, as in the static rungs).
    #[default]
    Flat,
    /// The tread's local shape at the cap's lateral position (module docs).
    Tread,
    /// The tread's local shape at the cap's lateral position and at a few
    /// longitudinal offsets `ξ`, blended at each step's `ξ`
    /// ([`crate::fidelity::PathNode`], [`slope_nodes`]).
    TreadSlope,
}

impl CalibrateUnder {
    /// Every choice, in the order the errors list them.
    pub const ALL: [CalibrateUnder; 3] = [Self::Flat, Self::Tread, Self::TreadSlope];

    /// The scenario's name of this choice.
    pub fn name(self) -> &'static str {
        match self {
            Self::Flat => "flat",
            Self::Tread => "tread",
            Self::TreadSlope => "tread_slope",
        }
    }
}

impl fmt::Display for CalibrateUnder {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for CalibrateUnder {
    type Err = FidelityError;

    fn from_str(s: &str) -> Result<Self, Self::Err> {
        Self::ALL
            .into_iter()
            .find(|c| c.name() == s)
            .ok_or_else(|| {
                FidelityError::invalid(
                    "calibrate_under",
                    format!("{s:?}"),
                    crate::fidelity::one_of(Self::ALL.map(Self::name)),
                )
            })
    }
}

/// Offsets along the path at which [`CalibrateUnder::TreadSlope`]
/// calibrates each cap.
pub const SLOPE_NODES: usize = 5;

/// The offsets `ξ` (m) of [`CalibrateUnder::TreadSlope`]'s nodes:
/// [`SLOPE_NODES`] evenly spaced over `[−a, a]`, `a = L/2 + m` the
/// half-length of the window that selects an asperity (footprint and
/// `margin`): every offset at which a step can hand a cap its law. (The
/// approach alone would bound them closer, `√(2 Rx δ0)`, for a cap that
/// touches at its summit; a long cap whose summit lies at one end touches
/// with its other end further out.) One node at `ξ = 0` under a block (no
/// slope to follow).
pub fn slope_nodes(tread: &Tread, margin: f64) -> Vec<f64> {
    let Tread::Tyre { length, .. } = *tread else {
        return vec![0.0];
    };
    let a = 0.5 * length + tread.effective_margin(margin).max(0.0);
    if !(a > 0.0 && a.is_finite()) {
        return vec![0.0];
    }
    let h = (SLOPE_NODES - 1) as f64;
    (0..SLOPE_NODES)
        .map(|k| a * (2.0 * k as f64 / h - 1.0))
        .collect()
}

/// Where each cap of a road lies under the tread, by the road's index:
/// what [`calibrated_laws`](super::texture) needs to shape its patch.
#[derive(Clone, Debug)]
pub(crate) enum CapShape {
    /// Every cap under a flat punch.
    Flat,
    /// Each cap under `tread` at lateral offset `eta[i]` (m) from the path
    /// and longitudinal offset `xi` (m) from the footprint's centre, with
    /// summit radius `radius[i]` (m; the model's, for its gap).
    Tread {
        tread: Tread,
        xi: f64,
        eta: Vec<f64>,
        radius: Vec<f64>,
        /// The road's highest summit less each asperity's height (m): how
        /// far a lift may raise it.
        headroom: Vec<f64>,
    },
}

/// A cap's patch as calibrated, and how far the asperity's height is
/// raised so that the model's gap is the cap's first contact (m, ≥ 0).
#[derive(Clone, Debug)]
pub(crate) struct TreadPatch {
    pub patch: CapPatch,
    pub lift: f64,
}

impl CapShape {
    /// The patch of asperity `a` (the road's index `i`) for depths up to
    /// `depth` (m, from the model's contact-point gap).
    ///
    /// # Errors
    /// Those of [`cap_patch`]; [`FidelityError::InvalidInput`] for an index
    /// without a lateral offset.
    pub(crate) fn patch(
        &self,
        map: &HeightMap,
        a: &Asperity,
        i: usize,
        depth: f64,
    ) -> Result<TreadPatch, FidelityError> {
        let Self::Tread {
            tread,
            xi,
            eta,
            radius,
            headroom,
        } = self
        else {
            return Ok(TreadPatch {
                patch: cap_patch(map, a, depth)?,
                lift: 0.0,
            });
        };
        let (Some(&eta), Some(&radius), Some(&headroom)) =
            (eta.get(i), radius.get(i), headroom.get(i))
        else {
            return Err(FidelityError::invalid(
                "asperity index",
                i,
                format!("below the {} caps placed under the tread", eta.len()),
            ));
        };
        let Some(rise) = TreadRise::new(tread, *xi, eta, radius) else {
            return Ok(TreadPatch {
                patch: cap_patch(map, a, depth)?,
                lift: 0.0,
            });
        };
        // The tread falls away on the downhill side: cells deeper than the
        // range below the summit can touch there, so the patch reaches
        // deeper by the tread's largest fall over it.
        let first = cap_patch(map, a, depth)?;
        let fall = rise.largest_fall(&first, 2.0);
        let flat = cap_patch(map, a, depth + fall)?;
        Ok(rise.reshape(flat, depth + fall, headroom.max(0.0)))
    }
}

/// The tread surface's rise from a cap's summit (module docs).
struct TreadRise {
    radius_x: f64,
    radius_y: f64,
    xi: f64,
    eta: f64,
    /// `L_model`: how far below the summit's profile the model's gap lies.
    lateral_lift: f64,
    /// The model's contact-point offset (m).
    offset: [f64; 2],
}

impl TreadRise {
    /// The rise at longitudinal offset `xi` and lateral offset `eta`;
    /// `None` under a block (flat: nothing to reshape).
    fn new(tread: &Tread, xi: f64, eta: f64, radius: f64) -> Option<Self> {
        let Tread::Tyre {
            radius_x, radius_y, ..
        } = *tread
        else {
            return None;
        };
        let (gap, offset) = tread.contact_gap(xi, eta, radius)?;
        let summit = tread.profile(xi, eta)?;
        Some(Self {
            radius_x,
            radius_y,
            xi,
            eta,
            lateral_lift: summit - gap,
            offset,
        })
    }

    /// `s(ξ + dx, η + dy) − s(ξ, η)`.
    fn rise(&self, dx: f64, dy: f64) -> f64 {
        dx * (2.0 * self.xi + dx) / (2.0 * self.radius_x)
            + dy * (2.0 * self.eta + dy) / (2.0 * self.radius_y)
    }

    /// The largest fall of the tread below the summit's level over the
    /// patch grown `grow` times about the summit (m, ≥ 0).
    fn largest_fall(&self, p: &CapPatch, grow: f64) -> f64 {
        let corners = [
            p.origin,
            [
                p.origin[0] + (p.nx - 1) as f64 * p.dx,
                p.origin[1] + (p.ny - 1) as f64 * p.dy,
            ],
        ];
        // The rise is a sum of parabolas in dx and dy whose lowest points
        // are at dx = −ξ and dy = −η: each part's lowest value over the
        // grown patch, found apart.
        let lowest = |axis: usize, vertex: f64| {
            let ds = corners.map(|c| grow * c[axis]);
            let v = (-vertex).clamp(ds[0].min(ds[1]), ds[0].max(ds[1]));
            [ds[0], ds[1], v]
                .into_iter()
                .map(|d| {
                    if axis == 0 {
                        self.rise(d, 0.0)
                    } else {
                        self.rise(0.0, d)
                    }
                })
                .fold(f64::INFINITY, f64::min)
        };
        (-(lowest(0, self.xi) + lowest(1, self.eta))).max(0.0)
    }

    /// `flat` (cut at `reach` below its summit) less the tread's rise and
    /// the model's lateral lift; raised by up to `headroom` when the cap
    /// reaches above the model's gap, clipped beyond.
    fn reshape(&self, flat: CapPatch, reach: f64, headroom: f64) -> TreadPatch {
        let floor = -(1.5 * reach + flat.dx.max(flat.dy));
        let mut heights = Vec::with_capacity(flat.heights.len());
        let mut fall: f64 = 0.0;
        for (k, &z) in flat.heights.iter().enumerate() {
            let (dx, dy) = (
                flat.origin[0] + (k % flat.nx) as f64 * flat.dx,
                flat.origin[1] + (k / flat.nx) as f64 * flat.dy,
            );
            let rise = self.rise(dx, dy);
            fall = fall.max(-rise);
            // The floor marks cells that never touch: they stay below
            // whatever the tilt does.
            heights.push((z > floor).then_some(z - rise - self.lateral_lift));
        }
        let top = heights.iter().flatten().copied().fold(f64::MIN, f64::max);
        let lift = top.clamp(0.0, headroom);
        let floor = floor - fall - self.lateral_lift - lift;
        let heights = heights
            .into_iter()
            .map(|h| h.map_or(floor, |h| (h - lift).min(0.0)))
            .collect();
        TreadPatch {
            patch: CapPatch {
                heights,
                origin: [
                    flat.origin[0] - self.offset[0],
                    flat.origin[1] - self.offset[1],
                ],
                ..flat
            },
            lift,
        }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn tyre() -> Tread {
        Tread::Tyre {
            radius_x: 0.3,
            radius_y: 0.5,
            length: 0.1,
            width: 0.1,
        }
    }

    fn paraboloid(r: f64) -> CapPatch {
        CapPatch::from_fn(41, 1e-4, |x, y| -(x * x + y * y) / (2.0 * r)).unwrap()
    }

    #[test]
    fn calibrate_under_names_its_values_and_refuses_others() {
        assert_eq!(
            "flat".parse::<CalibrateUnder>().unwrap(),
            CalibrateUnder::Flat
        );
        assert_eq!(
            "tread".parse::<CalibrateUnder>().unwrap(),
            CalibrateUnder::Tread
        );
        assert_eq!(
            "tread_slope".parse::<CalibrateUnder>().unwrap(),
            CalibrateUnder::TreadSlope
        );
        let e = "tilted".parse::<CalibrateUnder>().unwrap_err().to_string();
        assert!(
            e.contains("calibrate_under") && e.contains("\"tread_slope\""),
            "{e}"
        );
        // Nodes over the selection window; one under a block.
        assert_eq!(
            slope_nodes(&tyre(), 0.02),
            [-0.07, -0.035, 0.0, 0.035, 0.07]
        );
        let block = Tread::Block {
            length: 0.1,
            width: 0.1,
        };
        assert_eq!(slope_nodes(&block, 0.02), [0.0]);
        assert_eq!(CalibrateUnder::default(), CalibrateUnder::Flat);
    }

    /// A paraboloid cap under the tyre's slope: its reshaped top is at the
    /// model's contact point, level with the law's zero (no lift), the
    /// field's origin moved back by the model's offset (which the step
    /// adds again: the field lands where the tilted solve put it).
    #[test]
    fn a_paraboloid_under_a_sloping_tyre_first_touches_at_the_models_contact_point() {
        let r = 5e-3;
        let eta = 0.05;
        let rise = TreadRise::new(&tyre(), 0.0, eta, r).unwrap();
        let flat = paraboloid(r);
        let out = rise.reshape(flat.clone(), 1e-3, 1.0);
        // The continuous maximum lies between cells: within the grid's
        // curvature over half a cell of the paraboloid's top.
        let half_cell = 0.5e-4;
        let tol = half_cell * half_cell / (2.0 * r);
        let top = out.patch.heights.iter().copied().fold(f64::MIN, f64::max);
        assert!(
            out.lift <= tol && top <= 0.0 && top >= -tol,
            "{top} {}",
            out.lift
        );
        // The top cell is the one nearest the contact point −η R/(R + Ry).
        let k = out
            .patch
            .heights
            .iter()
            .enumerate()
            .max_by(|a, b| a.1.total_cmp(b.1))
            .unwrap()
            .0;
        let dy = flat.origin[1] + (k / flat.nx) as f64 * flat.dy;
        assert!((dy - (-eta * r / (r + 0.5))).abs() <= half_cell, "{dy}");
        assert!((out.patch.origin[1] - (flat.origin[1] + eta * r / (r + 0.5))).abs() < 1e-15);
    }

    /// A cap flatter across than its summit radius says touches before
    /// the model's gap: the asperity is lifted by the difference, up to
    /// its headroom, the rest clipped.
    #[test]
    fn a_cap_reaching_above_the_models_gap_is_lifted_then_clipped() {
        let eta = 0.05;
        // Model radius 2 mm, true transverse radius 8 mm.
        let rise = TreadRise::new(&tyre(), 0.0, eta, 2e-3).unwrap();
        let flat = CapPatch::from_fn(81, 1e-4, |x, y| -x * x / 4e-3 - y * y / 16e-3).unwrap();
        let free = rise.reshape(flat.clone(), 1e-3, 1.0);
        // σ²/2 (Rt Ry/(Rt + Ry) − R Ry/(R + Ry)), σ = η/Ry, Rt = 8 mm, R = 2 mm.
        let (sigma, ry): (f64, f64) = (eta / 0.5, 0.5);
        let expected = 0.5 * sigma * sigma * (8e-3 * ry / (8e-3 + ry) - 2e-3 * ry / (2e-3 + ry));
        assert!(
            (free.lift - expected).abs() <= 0.01 * expected,
            "{} vs {expected}",
            free.lift
        );
        let top = free.patch.heights.iter().copied().fold(f64::MIN, f64::max);
        assert!(top <= 0.0 && top > -0.01 * expected, "{top}");
        let capped = rise.reshape(flat, 1e-3, 0.5 * free.lift);
        assert_eq!(capped.lift, 0.5 * free.lift);
        let top = capped
            .patch
            .heights
            .iter()
            .copied()
            .fold(f64::MIN, f64::max);
        assert_eq!(top, 0.0);
    }
}
