//! Regular grids, height maps and analytic height-map builders.

use crate::BemError;

/// Largest number of cells accepted along one axis (the non-periodic FFT
/// grid doubles it).
const MAX_CELLS_PER_AXIS: usize = 1 << 20;
/// Largest total number of cells accepted.
const MAX_CELLS: usize = 1 << 28;

/// A regular grid of `nx × ny` rectangular cells of size `dx × dy` (m).
///
/// Cell `(i, j)` (`0 ≤ i < nx` along x, `0 ≤ j < ny` along y) has its centre
/// at `(x0 + i·dx, y0 + j·dy)` where `origin = [x0, y0]` is the centre of
/// cell `(0, 0)`. Fields on the grid are stored row-major: value `(i, j)` is
/// at index `j·nx + i` (see [`Grid::index`]).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    origin: [f64; 2],
}

impl Grid {
    /// A grid of `nx × ny` cells of size `dx × dy`, with the centre of cell
    /// `(0, 0)` at the coordinate origin.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if a size is zero or too large, or a spacing
    /// is not finite and > 0.
    pub fn new(nx: usize, ny: usize, dx: f64, dy: f64) -> Result<Self, BemError> {
        if nx == 0 || ny == 0 {
            return Err(BemError::invalid(format!(
                "grid sizes must be >= 1, got nx = {nx}, ny = {ny}"
            )));
        }
        if nx > MAX_CELLS_PER_AXIS || ny > MAX_CELLS_PER_AXIS || nx.saturating_mul(ny) > MAX_CELLS {
            return Err(BemError::invalid(format!(
                "grid too large: nx = {nx}, ny = {ny} (at most {MAX_CELLS_PER_AXIS} per axis and {MAX_CELLS} cells)"
            )));
        }
        for (name, d) in [("dx", dx), ("dy", dy)] {
            if !(d.is_finite() && d > 0.0) {
                return Err(BemError::invalid(format!(
                    "grid spacing {name} must be finite and > 0, got {d}"
                )));
            }
        }
        Ok(Self {
            nx,
            ny,
            dx,
            dy,
            origin: [0.0, 0.0],
        })
    }

    /// A grid whose domain `[x0 − dx/2, x0 + (nx − ½)·dx] × …` is centred on
    /// the coordinate origin.
    ///
    /// With an odd `nx` a cell centre lies at x = 0; with an even `nx` the
    /// origin falls on a cell edge.
    ///
    /// # Errors
    /// As [`Grid::new`].
    pub fn centered(nx: usize, ny: usize, dx: f64, dy: f64) -> Result<Self, BemError> {
        let g = Self::new(nx, ny, dx, dy)?;
        let x0 = -0.5 * (nx as f64 - 1.0) * dx;
        let y0 = -0.5 * (ny as f64 - 1.0) * dy;
        g.with_origin([x0, y0])
    }

    /// The same grid with the centre of cell `(0, 0)` at `origin`.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if `origin` is not finite.
    pub fn with_origin(mut self, origin: [f64; 2]) -> Result<Self, BemError> {
        if !(origin[0].is_finite() && origin[1].is_finite()) {
            return Err(BemError::invalid(format!(
                "grid origin must be finite, got {origin:?}"
            )));
        }
        self.origin = origin;
        Ok(self)
    }

    /// Number of cells along x.
    pub fn nx(&self) -> usize {
        self.nx
    }
    /// Number of cells along y.
    pub fn ny(&self) -> usize {
        self.ny
    }
    /// Cell size along x (m).
    pub fn dx(&self) -> f64 {
        self.dx
    }
    /// Cell size along y (m).
    pub fn dy(&self) -> f64 {
        self.dy
    }
    /// Centre of cell `(0, 0)` (m).
    pub fn origin(&self) -> [f64; 2] {
        self.origin
    }
    /// Total number of cells `nx · ny`.
    pub fn len(&self) -> usize {
        self.nx * self.ny
    }
    /// Always `false`: a valid grid has at least one cell.
    pub fn is_empty(&self) -> bool {
        false
    }
    /// Area of one cell `dx · dy` (m²).
    pub fn cell_area(&self) -> f64 {
        self.dx * self.dy
    }
    /// Domain size `[nx · dx, ny · dy]` (m).
    pub fn size(&self) -> [f64; 2] {
        [self.nx as f64 * self.dx, self.ny as f64 * self.dy]
    }
    /// x coordinate of the centre of cells in column `i`.
    pub fn x(&self, i: usize) -> f64 {
        self.origin[0] + i as f64 * self.dx
    }
    /// y coordinate of the centre of cells in row `j`.
    pub fn y(&self, j: usize) -> f64 {
        self.origin[1] + j as f64 * self.dy
    }
    /// Row-major index `j · nx + i` of cell `(i, j)`.
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }
    /// Cell `(i, j)` of a row-major index.
    pub fn cell(&self, index: usize) -> (usize, usize) {
        (index % self.nx, index / self.nx)
    }
}

/// A rigid surface given by its heights (m, upward) at the cell centres of a
/// [`Grid`], row-major.
#[derive(Debug, Clone, PartialEq)]
pub struct HeightMap {
    grid: Grid,
    heights: Vec<f64>,
}

impl HeightMap {
    /// A height map from row-major heights (`heights[j·nx + i]` at cell `(i, j)`).
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if `heights.len() != nx·ny` or a height is
    /// not finite.
    pub fn new(grid: Grid, heights: Vec<f64>) -> Result<Self, BemError> {
        if heights.len() != grid.len() {
            return Err(BemError::invalid(format!(
                "height map has {} values, grid {}x{} needs {}",
                heights.len(),
                grid.nx,
                grid.ny,
                grid.len()
            )));
        }
        if let Some(k) = heights.iter().position(|h| !h.is_finite()) {
            let (i, j) = grid.cell(k);
            return Err(BemError::invalid(format!(
                "height at cell ({i}, {j}) is not finite: {}",
                heights[k]
            )));
        }
        Ok(Self { grid, heights })
    }

    /// Samples `f(x, y)` at every cell centre.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if `f` returns a non-finite value.
    pub fn from_fn(grid: Grid, f: impl Fn(f64, f64) -> f64) -> Result<Self, BemError> {
        let mut heights = Vec::with_capacity(grid.len());
        for j in 0..grid.ny {
            let y = grid.y(j);
            for i in 0..grid.nx {
                heights.push(f(grid.x(i), y));
            }
        }
        Self::new(grid, heights)
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }
    /// The heights, row-major (m).
    pub fn heights(&self) -> &[f64] {
        &self.heights
    }
    /// Consumes the map and returns its heights.
    pub fn into_heights(self) -> Vec<f64> {
        self.heights
    }
    /// Height of cell `(i, j)`.
    pub fn at(&self, i: usize, j: usize) -> f64 {
        self.heights[self.grid.index(i, j)]
    }
    /// Highest height (m).
    pub fn max(&self) -> f64 {
        self.heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

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
            grid.origin[0],
            grid.dx,
            grid.nx,
        );
        let (j0, j1) = index_range(
            s.centre[1] - s.radius,
            s.centre[1] + s.radius,
            grid.origin[1],
            grid.dy,
            grid.ny,
        );
        for j in j0..j1 {
            let ry = grid.y(j) - s.centre[1];
            for i in i0..i1 {
                let rx = grid.x(i) - s.centre[0];
                let d2 = rx * rx + ry * ry;
                if d2 < r2 {
                    let z = s.summit - s.radius + (r2 - d2).sqrt();
                    let h = &mut heights[j * grid.nx + i];
                    if z > *h {
                        *h = z;
                    }
                }
            }
        }
    }
    HeightMap::new(grid.clone(), heights)
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
    for j in 0..grid.ny {
        let y = grid.y(j);
        for i in 0..grid.nx {
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
            labels[j * grid.nx + i] = best;
        }
    }
    labels
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_validation() {
        assert!(Grid::new(0, 4, 1.0, 1.0).is_err());
        assert!(Grid::new(4, 4, 0.0, 1.0).is_err());
        assert!(Grid::new(4, 4, 1.0, f64::INFINITY).is_err());
        assert!(Grid::new(usize::MAX, 4, 1.0, 1.0).is_err());
        let g = Grid::centered(5, 4, 1.0, 2.0).expect("valid");
        assert_eq!(g.x(2), 0.0);
        assert_eq!(g.y(0), -3.0);
        assert_eq!(g.y(3), 3.0);
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
