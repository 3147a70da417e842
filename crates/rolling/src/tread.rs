//! The tread's shape: a flat block or a tyre envelope, and its footprint.

use crate::RollingError;

/// The tread pressed on the road, described in its own frame centred on the
/// footprint centre `(x_c, y_c)`: `ξ = x − x_c` along the driving direction,
/// `η = y − y_c` across.
///
/// Its shape enters the gaps through the profile height `s(ξ, η) ≥ 0`, the
/// height of the undeformed tread surface above its lowest point:
///
/// - [`Tread::Block`]: a flat rectangular block (the paper's rubber block),
///   `s = 0` for `|ξ| ≤ length/2` and `|η| ≤ width/2`; outside the block
///   there is no tread, the asperity is excluded (however wide the margin).
/// - [`Tread::Tyre`]: a tyre envelope, locally an elliptic paraboloid
///   `s = ξ²/(2 Rx) + η²/(2 Ry)`; only asperities inside the footprint
///   (`|ξ| ≤ length/2 + margin`, `|η| ≤ width/2 + margin`) take part.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Tread {
    /// A flat rectangular block.
    Block {
        /// Extent along the driving direction x (m).
        length: f64,
        /// Extent across, along y (m).
        width: f64,
    },
    /// A tyre envelope with longitudinal and transverse radii.
    Tyre {
        /// Longitudinal radius `Rx` (m): the tyre's rolling radius.
        radius_x: f64,
        /// Transverse radius `Ry` (m): the crown's curvature across.
        radius_y: f64,
        /// Footprint length along x (m).
        length: f64,
        /// Footprint width along y (m).
        width: f64,
    },
}

impl Tread {
    /// Checks every size is finite and positive.
    pub fn validate(&self) -> Result<(), RollingError> {
        let sizes: &[(&str, f64)] = match *self {
            Tread::Block { length, width } => &[("block length", length), ("block width", width)],
            Tread::Tyre {
                radius_x,
                radius_y,
                length,
                width,
            } => &[
                ("tyre radius_x", radius_x),
                ("tyre radius_y", radius_y),
                ("footprint length", length),
                ("footprint width", width),
            ],
        };
        for &(name, v) in sizes {
            if !(v.is_finite() && v > 0.0) {
                return Err(RollingError::InvalidInput(format!(
                    "{name} must be finite and > 0 m, got {v}"
                )));
            }
        }
        Ok(())
    }

    /// Half extents `(length/2, width/2)` of the footprint (m).
    pub fn half_extents(&self) -> (f64, f64) {
        match *self {
            Tread::Block { length, width } | Tread::Tyre { length, width, .. } => {
                (0.5 * length, 0.5 * width)
            }
        }
    }

    /// The selection margin that applies: `margin` for a tyre, zero for a
    /// block (nothing lies outside a block).
    pub fn effective_margin(&self, margin: f64) -> f64 {
        match self {
            Tread::Block { .. } => 0.0,
            Tread::Tyre { .. } => margin,
        }
    }

    /// Profile height `s(ξ, η)` (m) at offset `(ξ, η)` from the footprint
    /// centre, or `None` where there is no tread (outside a block). For a
    /// tyre it is defined everywhere; the footprint window is applied by the
    /// selection.
    pub fn profile(&self, xi: f64, eta: f64) -> Option<f64> {
        match *self {
            Tread::Block { length, width } => {
                (xi.abs() <= 0.5 * length && eta.abs() <= 0.5 * width).then_some(0.0)
            }
            Tread::Tyre {
                radius_x, radius_y, ..
            } => Some(xi * xi / (2.0 * radius_x) + eta * eta / (2.0 * radius_y)),
        }
    }

    /// The gap between the tread and a paraboloid summit of radius `radius`
    /// at offset `(ξ, η)`, measured at the contact point rather than at the
    /// summit, with that point's offset from the summit: `(s*, [dξ, dη])`,
    /// or `None` where there is no tread.
    ///
    /// Under a tyre the first point of contact of a summit
    /// `z = −(dξ² + dη²)/(2R)` is where tread minus surface is smallest:
    /// minimising `dξ²/(2R) + (ξ + dξ)²/(2Rx)` (and the same across) gives
    /// `dξ = −ξ R/(R + Rx)` and `s* = ξ²/(2(Rx + R)) + η²/(2(Ry + R))`,
    /// below the summit's `s(ξ, η)` by `½ σ² R Rx/(R + Rx)` for a slope
    /// `σ = ξ/Rx` (docs/validation.md, "Rolling against the BEM"). An
    /// infinite or non-positive `radius` (unknown) gives the summit's
    /// profile and no offset; a flat block has no slope and no offset.
    pub fn contact_gap(&self, xi: f64, eta: f64, radius: f64) -> Option<(f64, [f64; 2])> {
        match *self {
            Tread::Tyre {
                radius_x, radius_y, ..
            } if radius.is_finite() && radius > 0.0 => {
                let (cx, cy) = (radius / (radius + radius_x), radius / (radius + radius_y));
                let s =
                    xi * xi / (2.0 * (radius_x + radius)) + eta * eta / (2.0 * (radius_y + radius));
                Some((s, [-xi * cx, -eta * cy]))
            }
            _ => self.profile(xi, eta).map(|s| (s, [0.0, 0.0])),
        }
    }

    /// [`Tread::contact_gap`] under a tread tilted further by `extra`, the
    /// slope `∇u` of the displacement the step's other contacts cause
    /// ([`crate::ContactSlope::Deformed`]): with the local slope
    /// `σ = ∇s + ∇u` (`∇s = (ξ/Rx, η/Ry)` for a tyre, zero under a block),
    /// the first point of contact of a summit of radius `R` lies
    /// `dξ = −σx R Rx/(R + Rx)` off it (`R` under a block) and the gap there
    /// is `s(ξ, η) − ½ σx² R Rx/(R + Rx) − ½ σy² R Ry/(R + Ry)`. Zero
    /// `extra` is [`Tread::contact_gap`]; an unknown radius gives the
    /// summit's profile and no offset.
    pub fn contact_gap_sloped(
        &self,
        xi: f64,
        eta: f64,
        radius: f64,
        extra: [f64; 2],
    ) -> Option<(f64, [f64; 2])> {
        if extra == [0.0, 0.0] || !(radius.is_finite() && radius > 0.0) {
            return self.contact_gap(xi, eta, radius);
        }
        let s = self.profile(xi, eta)?;
        let ([sx, sy], [cx, cy]) = match *self {
            Tread::Tyre {
                radius_x, radius_y, ..
            } => (
                [xi / radius_x + extra[0], eta / radius_y + extra[1]],
                [
                    radius * radius_x / (radius + radius_x),
                    radius * radius_y / (radius + radius_y),
                ],
            ),
            Tread::Block { .. } => (extra, [radius, radius]),
        };
        Some((
            s - 0.5 * (sx * sx * cx + sy * sy * cy),
            [-sx * cx, -sy * cy],
        ))
    }

    /// The smallest profile height on the boundary of the selection window
    /// (footprint grown by `margin`): every asperity outside the window has
    /// a gap at least this large (the gaps are measured from the road's
    /// highest summit). Infinite for a block.
    pub fn boundary_profile(&self, margin: f64) -> f64 {
        match *self {
            Tread::Block { .. } => f64::INFINITY,
            Tread::Tyre {
                radius_x,
                radius_y,
                length,
                width,
            } => {
                let (hx, hy) = (0.5 * length + margin, 0.5 * width + margin);
                (hx * hx / (2.0 * radius_x)).min(hy * hy / (2.0 * radius_y))
            }
        }
    }
}
