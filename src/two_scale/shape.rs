//! The real shape of one asperity around its summit.

use std::sync::Arc;

use super::TwoScaleError;

/// The real shape of one asperity, as a height relative to its summit.
#[derive(Clone)]
pub enum LocalShape {
    /// A true sphere of radius `radius` (m): `√(R² − r²) − R` for `r < R`,
    /// `−R` beyond (a floor, as [`bem::spherical_caps`](crate::bem::spherical_caps)).
    Sphere {
        /// R (m).
        radius: f64,
    },
    /// An elliptic paraboloid `−x²/2Rx − y²/2Ry` (Hertz's geometry).
    Paraboloid {
        /// Rx (m).
        radius_x: f64,
        /// Ry (m).
        radius_y: f64,
    },
    /// Any shape: `height(dx, dy) ≤ 0` relative to the summit at `(0, 0)`,
    /// and the radius of curvature of the equivalent sphere at the summit,
    /// used only to size the local grid.
    Custom {
        /// Height relative to the summit (m) at the offset `(dx, dy)` (m).
        height: Arc<dyn Fn(f64, f64) -> f64 + Send + Sync>,
        /// Equivalent radius of curvature at the summit (m).
        equivalent_radius: f64,
    },
}

impl std::fmt::Debug for LocalShape {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Sphere { radius } => f.debug_struct("Sphere").field("radius", radius).finish(),
            Self::Paraboloid { radius_x, radius_y } => f
                .debug_struct("Paraboloid")
                .field("radius_x", radius_x)
                .field("radius_y", radius_y)
                .finish(),
            Self::Custom {
                equivalent_radius, ..
            } => f
                .debug_struct("Custom")
                .field("equivalent_radius", equivalent_radius)
                .finish_non_exhaustive(),
        }
    }
}

impl LocalShape {
    /// Height (m, ≤ 0) relative to the summit at the offset `(dx, dy)`.
    pub fn height(&self, dx: f64, dy: f64) -> f64 {
        match self {
            Self::Sphere { radius } => {
                let r2 = dx * dx + dy * dy;
                let rr = radius * radius;
                if r2 < rr {
                    (rr - r2).sqrt() - radius
                } else {
                    -radius
                }
            }
            Self::Paraboloid { radius_x, radius_y } => {
                -(dx * dx / (2.0 * radius_x) + dy * dy / (2.0 * radius_y))
            }
            Self::Custom { height, .. } => height(dx, dy),
        }
    }

    /// Radius of the equivalent sphere at the summit (m): `R`, `√(Rx Ry)`,
    /// or the given one.
    pub fn equivalent_radius(&self) -> f64 {
        match *self {
            Self::Sphere { radius } => radius,
            Self::Paraboloid { radius_x, radius_y } => (radius_x * radius_y).sqrt(),
            Self::Custom {
                equivalent_radius, ..
            } => equivalent_radius,
        }
    }

    pub(super) fn check(&self, index: usize) -> Result<(), TwoScaleError> {
        let ok = |v: f64| v.is_finite() && v > 0.0;
        let valid = match *self {
            Self::Sphere { radius } => ok(radius),
            Self::Paraboloid { radius_x, radius_y } => ok(radius_x) && ok(radius_y),
            Self::Custom {
                equivalent_radius, ..
            } => ok(equivalent_radius),
        };
        if valid {
            Ok(())
        } else {
            Err(TwoScaleError::InvalidInput(format!(
                "asperity {index}: shape {self:?} needs finite radii > 0"
            )))
        }
    }
}
