//! Shapes whose caps have closed forms: sphere, cone, elliptic paraboloid.

use std::f64::consts::PI;

use crate::{CapGeometry, CapMeasures, GeometryError, error::check_positive};

/// A spherical asperity of radius `R` (a ball seated in the road).
///
/// Exact cap of height `δ ≤ R`: `Ω = π δ² (R − δ/3)`, `Σ = π (2Rδ − δ²)`,
/// `Γ = 2π √(2Rδ − δ²)`. Below its equator (`δ > R`) the ball is taken to
/// continue as a vertical cylinder of radius `R` (the section of a ball cannot
/// shrink under a plate it is seated in), which keeps `Σ` non-decreasing and
/// the measures C¹ at `δ = R`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sphere {
    radius: f64,
}

impl Sphere {
    /// A sphere of radius `radius` (m).
    pub fn new(radius: f64) -> Result<Self, GeometryError> {
        Ok(Self {
            radius: check_positive("sphere radius", radius)?,
        })
    }

    /// The radius (m).
    pub fn radius(&self) -> f64 {
        self.radius
    }
}

impl CapGeometry for Sphere {
    fn cap(&self, depth: f64) -> CapMeasures {
        // `!(depth > 0)` also rejects NaN.
        if depth.is_nan() || depth <= 0.0 {
            return CapMeasures::EMPTY;
        }
        let r = self.radius;
        if depth <= r {
            let s2 = depth * (2.0 * r - depth);
            let s = s2.sqrt();
            CapMeasures {
                volume: PI * depth * depth * (r - depth / 3.0),
                base_area: PI * s2,
                perimeter: 2.0 * PI * s,
                d_base_area: 2.0 * PI * (r - depth),
                d_perimeter: 2.0 * PI * (r - depth) / s,
                d2_base_area: -2.0 * PI,
                d2_perimeter: -2.0 * PI * r * r / (s2 * s),
            }
        } else {
            let hemisphere = 2.0 / 3.0 * PI * r * r * r;
            CapMeasures {
                volume: hemisphere + PI * r * r * (depth - r),
                base_area: PI * r * r,
                perimeter: 2.0 * PI * r,
                ..CapMeasures::EMPTY
            }
        }
    }

    fn max_depth(&self) -> f64 {
        self.radius
    }
}

/// A conical asperity of half-angle `α` (between the axis and the flank).
///
/// With `t = tan α`: `Ω = π t² δ³ / 3`, `Σ = π t² δ²`, `Γ = 2π t δ`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Cone {
    half_angle: f64,
}

impl Cone {
    /// A cone of half-angle `half_angle` (rad), strictly between 0 and π/2.
    pub fn new(half_angle: f64) -> Result<Self, GeometryError> {
        if half_angle.is_finite() && half_angle > 0.0 && half_angle < PI / 2.0 {
            Ok(Self { half_angle })
        } else {
            Err(GeometryError::InvalidParameter {
                name: "cone half-angle",
                value: half_angle,
                requirement: "strictly between 0 and π/2 rad",
            })
        }
    }

    /// The half-angle (rad).
    pub fn half_angle(&self) -> f64 {
        self.half_angle
    }
}

impl CapGeometry for Cone {
    fn cap(&self, depth: f64) -> CapMeasures {
        if depth.is_nan() || depth <= 0.0 {
            return CapMeasures::EMPTY;
        }
        let t = self.half_angle.tan();
        let t2 = t * t;
        CapMeasures {
            volume: PI * t2 * depth.powi(3) / 3.0,
            base_area: PI * t2 * depth * depth,
            perimeter: 2.0 * PI * t * depth,
            d_base_area: 2.0 * PI * t2 * depth,
            d_perimeter: 2.0 * PI * t,
            d2_base_area: 2.0 * PI * t2,
            d2_perimeter: 0.0,
        }
    }
}

/// An elliptic paraboloid `z = −x²/(2 Rx) − y²/(2 Ry)`: the non-axisymmetric
/// analytic shape (the local form of any smooth summit, principal radii
/// `Rx`, `Ry`).
///
/// Its section at depth `δ` is an ellipse of semi-axes `√(2 Rx δ)` and
/// `√(2 Ry δ)`, so `Σ = 2π √(Rx Ry) δ`, `Ω = π √(Rx Ry) δ²` and
/// `Γ = Γ₁ √δ` with `Γ₁` the perimeter of the ellipse of semi-axes
/// `√(2Rx)`, `√(2Ry)` (complete elliptic integral of the second kind,
/// computed by the arithmetic–geometric mean).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct EllipticParaboloid {
    radius_x: f64,
    radius_y: f64,
}

impl EllipticParaboloid {
    /// A paraboloid with principal radii of curvature `radius_x`, `radius_y` (m).
    pub fn new(radius_x: f64, radius_y: f64) -> Result<Self, GeometryError> {
        Ok(Self {
            radius_x: check_positive("paraboloid radius along x", radius_x)?,
            radius_y: check_positive("paraboloid radius along y", radius_y)?,
        })
    }

    /// Principal radii of curvature `(Rx, Ry)` (m).
    pub fn radii(&self) -> (f64, f64) {
        (self.radius_x, self.radius_y)
    }
}

impl CapGeometry for EllipticParaboloid {
    fn cap(&self, depth: f64) -> CapMeasures {
        if depth.is_nan() || depth <= 0.0 {
            return CapMeasures::EMPTY;
        }
        let g = (self.radius_x * self.radius_y).sqrt();
        let unit_perimeter =
            ellipse_perimeter((2.0 * self.radius_x).sqrt(), (2.0 * self.radius_y).sqrt());
        let perimeter = unit_perimeter * depth.sqrt();
        CapMeasures {
            volume: PI * g * depth * depth,
            base_area: 2.0 * PI * g * depth,
            perimeter,
            d_base_area: 2.0 * PI * g,
            d_perimeter: perimeter / (2.0 * depth),
            d2_base_area: 0.0,
            d2_perimeter: -perimeter / (4.0 * depth * depth),
        }
    }
}

/// Perimeter of the ellipse of semi-axes `a`, `b` by the arithmetic–geometric
/// mean (exact to rounding; converges quadratically).
pub fn ellipse_perimeter(a: f64, b: f64) -> f64 {
    let (a, b) = if a >= b { (a, b) } else { (b, a) };
    if b == 0.0 {
        // The degenerate ellipse is a segment traversed twice (K(1) diverges).
        return 4.0 * a;
    }
    // E(k) = K(k) (1 − Σ 2^(n−1) c_n²), K(k) = π / (2 AGM(1, k')), k² = 1 − b²/a².
    let mut an = 1.0;
    let mut bn = b / a;
    let mut sum = 0.5 * (1.0 - bn * bn);
    let mut weight = 0.5;
    for _ in 0..64 {
        let c = 0.5 * (an - bn);
        if c.abs() < 1e-17 {
            break;
        }
        weight *= 2.0;
        sum += weight * c * c;
        let next = 0.5 * (an + bn);
        bn = (an * bn).sqrt();
        an = next;
    }
    let k = PI / (2.0 * an);
    4.0 * a * k * (1.0 - sum)
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        (a - b).abs() / b.abs()
    }

    #[test]
    fn ellipse_perimeter_matches_reference_values() {
        assert!(rel(ellipse_perimeter(1.0, 1.0), 2.0 * PI) < 1e-15);
        // Reference value of 4·2·E(k²=3/4), k = √3/2.
        assert!(rel(ellipse_perimeter(2.0, 1.0), 9.688_448_220_547_675) < 1e-14);
        assert!(rel(ellipse_perimeter(1.0, 0.0), 4.0) < 1e-12);
        assert_eq!(ellipse_perimeter(0.0, 0.0), 0.0);
    }

    #[test]
    fn non_positive_or_nan_depth_gives_empty_cap() {
        let shapes: [&dyn CapGeometry; 3] = [
            &Sphere::new(5e-3).unwrap(),
            &Cone::new(1.0).unwrap(),
            &EllipticParaboloid::new(2e-3, 5e-3).unwrap(),
        ];
        for s in shapes {
            for d in [0.0, -1e-3, f64::NAN, f64::NEG_INFINITY] {
                assert_eq!(s.cap(d), CapMeasures::EMPTY);
            }
        }
    }

    #[test]
    fn sphere_equator_is_c1_with_cylinder_continuation() {
        let s = Sphere::new(2.0).unwrap();
        let below = s.cap(2.0 - 1e-9);
        let above = s.cap(2.0 + 1e-9);
        assert!(rel(below.volume, above.volume) < 1e-8);
        assert!(rel(below.base_area, above.base_area) < 1e-8);
        assert!(rel(below.perimeter, above.perimeter) < 1e-8);
        assert!(below.d_base_area.abs() < 1e-7 && above.d_base_area == 0.0);
    }

    #[test]
    fn derivatives_agree_with_finite_differences() {
        let shapes: [&dyn CapGeometry; 3] = [
            &Sphere::new(5e-3).unwrap(),
            &Cone::new(1.2).unwrap(),
            &EllipticParaboloid::new(2e-3, 7e-3).unwrap(),
        ];
        for s in shapes {
            for d in [1e-5, 3e-4, 2e-3] {
                let h = d * 1e-5;
                let (lo, mid, hi) = (s.cap(d - h), s.cap(d), s.cap(d + h));
                let fd = |f: fn(&CapMeasures) -> f64| (f(&hi) - f(&lo)) / (2.0 * h);
                assert!(rel(fd(|c| c.volume), mid.base_area) < 1e-7, "dΩ/dδ = Σ");
                assert!(rel(fd(|c| c.base_area), mid.d_base_area) < 1e-7);
                assert!(rel(fd(|c| c.perimeter), mid.d_perimeter) < 1e-7);
                if mid.d2_base_area != 0.0 {
                    assert!(rel(fd(|c| c.d_base_area), mid.d2_base_area) < 1e-6);
                }
                if mid.d2_perimeter != 0.0 {
                    assert!(rel(fd(|c| c.d_perimeter), mid.d2_perimeter) < 1e-6);
                }
            }
        }
    }

    #[test]
    fn round_paraboloid_matches_small_sphere_cap() {
        // A sphere and the paraboloid of the same radius agree to O(δ/R).
        let r = 5e-3;
        let (s, p) = (
            Sphere::new(r).unwrap(),
            EllipticParaboloid::new(r, r).unwrap(),
        );
        let d = r * 1e-6;
        let (cs, cp) = (s.cap(d), p.cap(d));
        assert!(rel(cs.volume, cp.volume) < 1e-5);
        assert!(rel(cs.base_area, cp.base_area) < 1e-5);
        assert!(rel(cs.perimeter, cp.perimeter) < 1e-5);
    }

    #[test]
    fn invalid_parameters_are_refused() {
        assert!(Sphere::new(0.0).is_err());
        assert!(Sphere::new(f64::NAN).is_err());
        assert!(Cone::new(PI / 2.0).is_err());
        assert!(Cone::new(-0.1).is_err());
        assert!(EllipticParaboloid::new(1.0, f64::INFINITY).is_err());
    }
}
