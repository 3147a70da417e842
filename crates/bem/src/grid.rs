//! Height maps on the core's regular grid, and analytic height-map builders.

use tyreroad_core::{Field, Grid};

use crate::BemError;

/// A rigid surface: its heights (m, upward) at the cell centres of a
/// [`Grid`], row-major (the core's [`Field`]; its values are the heights).
pub type HeightMap = Field;

/// A sphere resting on the rigid surface, for [`spherical_caps`].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Sphere {
    /// Horizontal position `[x, y]` of the summit (m).
    pub centre: [f64; 2],
    /// Radius (m).
    pub radius: f64,
    /// Height of the summit (m).
    pub summit: f64,
}

/// Height map of the upper hemispheres of `spheres` (true spheres, not
/// paraboloids) standing on a flat floor at height `base`:
///
/// `h(x, y) = max(base, max_k [summit_k − R_k + √(R_k² − r_k²)])`,
/// over the spheres with `r_k = |(x, y) − centre_k| < R_k`.
///
/// # Errors
/// [`BemError::InvalidInput`] if a radius is not finite and > 0, a centre,
/// summit or `base` is not finite.
pub fn spherical_caps(grid: &Grid, spheres: &[Sphere], base: f64) -> Result<HeightMap, BemError> {
    if !base.is_finite() {
        return Err(BemError::invalid(format!(
            "floor height must be finite, got {base}"
        )));
    }
    for (k, s) in spheres.iter().enumerate() {
        if !(s.radius.is_finite() && s.radius > 0.0) {
            return Err(BemError::invalid(format!(
                "sphere {k}: radius must be finite and > 0, got {}",
                s.radius
            )));
        }
        if !(s.centre[0].is_finite() && s.centre[1].is_finite() && s.summit.is_finite()) {
            return Err(BemError::invalid(format!(
                "sphere {k}: centre and summit must be finite, got {:?}, {}",
                s.centre, s.summit
            )));
        }
    }
    let mut heights = vec![base; grid.len()];
    for s in spheres {
        let r2 = s.radius * s.radius;
        // Only visit the cells under the sphere's footprint.
        let (i0, i1) = index_range(
            s.centre[0] - s.radius,
            s.centre[0] + s.radius,
            grid.origin()[0],
            grid.dx(),
            grid.nx(),
        );
        let (j0, j1) = index_range(
            s.centre[1] - s.radius,
            s.centre[1] + s.radius,
            grid.origin()[1],
            grid.dy(),
            grid.ny(),
        );
        for j in j0..j1 {
            let ry = grid.y(j) - s.centre[1];
            for i in i0..i1 {
                let rx = grid.x(i) - s.centre[0];
                let d2 = rx * rx + ry * ry;
                if d2 < r2 {
                    let z = s.summit - s.radius + (r2 - d2).sqrt();
                    let h = &mut heights[j * grid.nx() + i];
                    if z > *h {
                        *h = z;
                    }
                }
            }
        }
    }
    Ok(HeightMap::new(grid.clone(), heights)?)
}

/// Range of cell indices whose centres may lie in `[lo, hi]`.
fn index_range(lo: f64, hi: f64, origin: f64, d: f64, n: usize) -> (usize, usize) {
    let a = ((lo - origin) / d).floor();
    let b = ((hi - origin) / d).ceil() + 1.0;
    let clamp = |v: f64| -> usize {
        if v <= 0.0 {
            0
        } else if v >= n as f64 {
            n
        } else {
            v as usize
        }
    };
    (clamp(a), clamp(b))
}

/// Labels every cell with the index of the nearest point of `centres`
/// (a Voronoi partition), for [`crate::BemSolution::force_per_region`]:
/// with the summits of the asperities as centres, it gives the force per
/// asperity.
///
/// All cells get label 0 when `centres` is empty.
pub fn nearest_labels(grid: &Grid, centres: &[[f64; 2]]) -> Vec<usize> {
    let mut labels = vec![0usize; grid.len()];
    if centres.is_empty() {
        return labels;
    }
    for j in 0..grid.ny() {
        let y = grid.y(j);
        for i in 0..grid.nx() {
            let x = grid.x(i);
            let mut best = 0;
            let mut best_d = f64::INFINITY;
            for (k, c) in centres.iter().enumerate() {
                let d = (x - c[0]).powi(2) + (y - c[1]).powi(2);
                if d < best_d {
                    best_d = d;
                    best = k;
                }
            }
            labels[j * grid.nx() + i] = best;
        }
    }
    labels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn height_maps_name_the_bad_cell() {
        let g = Grid::centered(5, 4, 1.0, 2.0).expect("valid");
        assert!(HeightMap::new(g.clone(), vec![0.0; 19]).is_err());
        let mut h = vec![0.0; 20];
        h[7] = f64::NAN;
        let e = HeightMap::new(g, h).expect_err("NaN");
        assert!(e.to_string().contains("(2, 1)"), "{e}");
    }

    #[test]
    fn caps_are_spheres() {
        let g = Grid::centered(21, 21, 0.5, 0.5).expect("valid");
        let s = Sphere {
            centre: [0.0, 0.0],
            radius: 4.0,
            summit: 1.0,
        };
        let h = spherical_caps(&g, &[s], -10.0).expect("valid");
        assert_eq!(h.at(10, 10), 1.0);
        // r = 2.5: z = 1 - 4 + sqrt(16 - 6.25)
        assert!((h.at(15, 10) - (-3.0 + (16.0f64 - 6.25).sqrt())).abs() < 1e-14);
        assert_eq!(h.at(0, 0), -10.0);
    }
}
