//! The regular grid and the field of values on it, with an optional
//! validity mask.

use crate::CoreError;
use crate::validate::{finite, positive};

/// Largest total number of cells a [`Grid`] accepts (2³⁰ ≈ 1.07e9): larger
/// sizes (e.g. read from a file header) are refused before anything is
/// allocated.
pub const MAX_CELLS: usize = 1 << 30;

/// A regular grid of `nx × ny` rectangular cells of size `dx × dy` (m).
///
/// Cell `(i, j)` (`0 ≤ i < nx` along x, `0 ≤ j < ny` along y, y up) has its
/// centre at `(x0 + i·dx, y0 + j·dy)` where `origin = [x0, y0]` is the centre
/// of cell `(0, 0)`. Values on the grid are stored row-major: cell `(i, j)`
/// at index `j·nx + i` (see [`Grid::index`]).
///
/// Invariants: `1 ≤ nx`, `1 ≤ ny`, `nx·ny ≤` [`MAX_CELLS`]; `dx`, `dy`
/// finite and > 0, the extent `nx·dx × ny·dy` finite and the cell area
/// `dx·dy` finite and > 0; the origin and the farthest cell centre finite.
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
    /// [`CoreError::InvalidShape`] if a size is zero or the grid has more
    /// than [`MAX_CELLS`] cells, [`CoreError::InvalidValue`] if a spacing is
    /// not finite and > 0, if the extent `nx·dx` or `ny·dy` overflows, or
    /// if the cell area `dx·dy` under- or overflows.
    pub fn new(nx: usize, ny: usize, dx: f64, dy: f64) -> Result<Self, CoreError> {
        if nx == 0 || ny == 0 {
            return Err(CoreError::InvalidShape {
                name: "grid",
                message: format!("sizes must be >= 1, got nx = {nx}, ny = {ny}"),
            });
        }
        if nx.checked_mul(ny).is_none_or(|n| n > MAX_CELLS) {
            return Err(CoreError::InvalidShape {
                name: "grid",
                message: format!("nx = {nx}, ny = {ny} exceeds {MAX_CELLS} cells"),
            });
        }
        positive("grid spacing dx (m)", dx)?;
        positive("grid spacing dy (m)", dy)?;
        // Integrals multiply by the cell area and coordinates reach the
        // extent: both must be ordinary numbers, not just the spacings.
        for (name, spacing, n) in [
            ("grid spacing dx (m)", dx, nx),
            ("grid spacing dy (m)", dy, ny),
        ] {
            if !(n as f64 * spacing).is_finite() {
                return Err(CoreError::InvalidValue {
                    name,
                    value: spacing,
                    expected: "small enough that the grid's extent (cells × spacing) is finite",
                });
            }
        }
        let area = dx * dy;
        if !(area.is_finite() && area > 0.0) {
            return Err(CoreError::InvalidValue {
                name: "grid cell area dx·dy (m²)",
                value: area,
                expected: "finite and > 0 (the spacings' product under- or overflows)",
            });
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
    pub fn centered(nx: usize, ny: usize, dx: f64, dy: f64) -> Result<Self, CoreError> {
        let g = Self::new(nx, ny, dx, dy)?;
        let x0 = -0.5 * (nx as f64 - 1.0) * dx;
        let y0 = -0.5 * (ny as f64 - 1.0) * dy;
        g.with_origin([x0, y0])
    }

    /// The same grid with the centre of cell `(0, 0)` at `origin`.
    ///
    /// # Errors
    /// [`CoreError::InvalidValue`] if `origin` is not finite or puts the
    /// farthest cell centre `origin + ((nx − 1)·dx, (ny − 1)·dy)` past
    /// floating point.
    pub fn with_origin(mut self, origin: [f64; 2]) -> Result<Self, CoreError> {
        finite("grid origin x (m)", origin[0])?;
        finite("grid origin y (m)", origin[1])?;
        for (name, o, n, d) in [
            ("grid origin x (m)", origin[0], self.nx, self.dx),
            ("grid origin y (m)", origin[1], self.ny, self.dy),
        ] {
            if !(o + (n - 1) as f64 * d).is_finite() {
                return Err(CoreError::InvalidValue {
                    name,
                    value: o,
                    expected: "such that the farthest cell centre is finite",
                });
            }
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
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }
    /// Cell `(i, j)` of a row-major index.
    pub fn cell(&self, index: usize) -> (usize, usize) {
        (index % self.nx, index / self.nx)
    }
}

/// Values (e.g. heights in m, pressures in Pa) at the cell centres of a
/// [`Grid`], row-major, with an optional validity mask.
///
/// Invariants: `values.len() == grid.len()`; without a mask every value is
/// finite; with a mask (`true` = valid, same length) every valid value is
/// finite and every invalid one is stored as NaN.
#[derive(Debug, Clone, PartialEq)]
pub struct Field {
    grid: Grid,
    values: Vec<f64>,
    mask: Option<Vec<bool>>,
}

impl Field {
    /// A field without mask from row-major values (`values[j·nx + i]` at
    /// cell `(i, j)`).
    ///
    /// # Errors
    /// [`CoreError::InvalidShape`] if `values.len() != nx·ny`,
    /// [`CoreError::InvalidValue`] if a value is not finite (the message
    /// names the cell).
    pub fn new(grid: Grid, values: Vec<f64>) -> Result<Self, CoreError> {
        check_len(&grid, values.len(), "field values")?;
        if let Some(k) = values.iter().position(|v| !v.is_finite()) {
            let (i, j) = grid.cell(k);
            return Err(CoreError::InvalidShape {
                name: "field values",
                message: format!("value at cell ({i}, {j}) is not finite: {}", values[k]),
            });
        }
        Ok(Self {
            grid,
            values,
            mask: None,
        })
    }

    /// A field of zeros.
    pub fn zeros(grid: Grid) -> Self {
        let values = vec![0.0; grid.len()];
        Self {
            grid,
            values,
            mask: None,
        }
    }

    /// A field with an explicit validity mask (`true` = valid). Values at
    /// invalid cells are ignored (stored as NaN); valid values must be
    /// finite.
    ///
    /// # Errors
    /// [`CoreError::InvalidShape`] if a length does not match the grid or a
    /// valid value is not finite.
    pub fn with_mask(grid: Grid, mut values: Vec<f64>, mask: Vec<bool>) -> Result<Self, CoreError> {
        check_len(&grid, values.len(), "field values")?;
        check_len(&grid, mask.len(), "validity mask")?;
        for (k, (v, ok)) in values.iter_mut().zip(&mask).enumerate() {
            if *ok {
                if !v.is_finite() {
                    let (i, j) = grid.cell(k);
                    return Err(CoreError::InvalidShape {
                        name: "field values",
                        message: format!("value {v} at valid cell ({i}, {j}) is not finite"),
                    });
                }
            } else {
                *v = f64::NAN;
            }
        }
        Ok(Self {
            grid,
            values,
            mask: Some(mask),
        })
    }

    /// A masked field where the non-finite values (NaN, ±∞) mark the
    /// invalid cells.
    ///
    /// # Errors
    /// [`CoreError::InvalidShape`] if `values.len() != nx·ny`.
    pub fn from_nan(grid: Grid, values: Vec<f64>) -> Result<Self, CoreError> {
        let mask = values.iter().map(|v| v.is_finite()).collect();
        Self::with_mask(grid, values, mask)
    }

    /// Samples `f(x, y)` at every cell centre.
    ///
    /// # Errors
    /// As [`Field::new`] if `f` returns a non-finite value.
    pub fn from_fn(grid: Grid, f: impl Fn(f64, f64) -> f64) -> Result<Self, CoreError> {
        let mut values = Vec::with_capacity(grid.len());
        for j in 0..grid.ny {
            let y = grid.y(j);
            for i in 0..grid.nx {
                values.push(f(grid.x(i), y));
            }
        }
        Self::new(grid, values)
    }

    /// The grid.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }
    /// The values, row-major; NaN at invalid cells.
    pub fn values(&self) -> &[f64] {
        &self.values
    }
    /// Consumes the field and returns its values.
    pub fn into_values(self) -> Vec<f64> {
        self.values
    }
    /// The validity mask (`true` = valid), `None` when every cell is valid.
    pub fn mask(&self) -> Option<&[bool]> {
        self.mask.as_deref()
    }
    /// Whether the cell at row-major index `k` holds a valid value.
    #[inline]
    pub fn is_valid(&self, k: usize) -> bool {
        self.mask.as_ref().is_none_or(|m| m[k])
    }
    /// Value of cell `(i, j)` (NaN if invalid).
    ///
    /// # Panics
    /// If `i ≥ nx` or `j ≥ ny`, like slice indexing (a column past the row
    /// would otherwise read a cell of the next row); [`Field::get`] returns
    /// `None` instead.
    #[inline]
    pub fn at(&self, i: usize, j: usize) -> f64 {
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        assert!(
            i < nx && j < ny,
            "Field::at({i}, {j}) is outside the {nx} × {ny} grid"
        );
        self.values[self.grid.index(i, j)]
    }
    /// Value of cell `(i, j)`, `None` if out of range or invalid.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        if i < self.grid.nx && j < self.grid.ny {
            let k = self.grid.index(i, j);
            self.is_valid(k).then_some(self.values[k])
        } else {
            None
        }
    }
    /// Row `j` (values along x), NaN at invalid cells.
    ///
    /// # Panics
    /// If `j ≥ ny`, like slice indexing.
    pub fn row(&self, j: usize) -> &[f64] {
        let (nx, ny) = (self.grid.nx, self.grid.ny);
        assert!(j < ny, "Field::row({j}) is outside the {nx} × {ny} grid");
        &self.values[j * self.grid.nx..(j + 1) * self.grid.nx]
    }
    /// Number of valid cells.
    pub fn valid_count(&self) -> usize {
        match &self.mask {
            Some(m) => m.iter().filter(|v| **v).count(),
            None => self.values.len(),
        }
    }
    /// The valid values, row-major.
    pub fn valid_values(&self) -> impl Iterator<Item = f64> + '_ {
        self.values
            .iter()
            .enumerate()
            .filter(|(k, _)| self.is_valid(*k))
            .map(|(_, v)| *v)
    }
    /// Largest valid value (`−∞` if none is valid).
    pub fn max(&self) -> f64 {
        self.valid_values().fold(f64::NEG_INFINITY, f64::max)
    }
    /// Mean of the valid values (`None` if none is valid).
    pub fn mean(&self) -> Option<f64> {
        let n = self.valid_count();
        (n > 0).then(|| self.valid_values().sum::<f64>() / n as f64)
    }
    /// Root mean square of the valid values about their mean (`None` if
    /// none is valid).
    pub fn rms(&self) -> Option<f64> {
        let m = self.mean()?;
        let n = self.valid_count() as f64;
        Some((self.valid_values().map(|h| (h - m).powi(2)).sum::<f64>() / n).sqrt())
    }
    /// Smallest and largest valid values (`None` if none is valid).
    pub fn min_max(&self) -> Option<(f64, f64)> {
        self.valid_values().fold(None, |acc, h| match acc {
            None => Some((h, h)),
            Some((lo, hi)) => Some((lo.min(h), hi.max(h))),
        })
    }
    /// `Σ v · dx dy` over the valid cells: the force of a pressure field
    /// (N), the volume of a height field (m³).
    pub fn integral(&self) -> f64 {
        self.valid_values().sum::<f64>() * self.grid.cell_area()
    }
    /// Area of the valid cells with a value `> 0` (m²): the contact area of a
    /// pressure field.
    pub fn positive_area(&self) -> f64 {
        self.valid_values().filter(|&v| v > 0.0).count() as f64 * self.grid.cell_area()
    }
}

fn check_len(grid: &Grid, len: usize, name: &'static str) -> Result<(), CoreError> {
    if len == grid.len() {
        Ok(())
    } else {
        Err(CoreError::InvalidShape {
            name,
            message: format!(
                "{len} values for a {} × {} grid (expected {})",
                grid.nx,
                grid.ny,
                grid.len()
            ),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn grid_geometry_and_validation() {
        assert!(Grid::new(0, 4, 1.0, 1.0).is_err());
        assert!(Grid::new(4, 4, 0.0, 1.0).is_err());
        assert!(Grid::new(4, 4, 1.0, f64::INFINITY).is_err());
        assert!(Grid::new(usize::MAX, 4, 1.0, 1.0).is_err());
        assert!(
            Grid::new(4, 4, 1.0, 1.0)
                .and_then(|g| g.with_origin([f64::NAN, 0.0]))
                .is_err()
        );
        let g = Grid::centered(5, 4, 1.0, 2.0).expect("valid");
        assert_eq!(g.x(2), 0.0);
        assert_eq!(g.y(0), -3.0);
        assert_eq!(g.y(3), 3.0);
        assert_eq!(g.index(2, 1), 7);
        assert_eq!(g.cell(7), (2, 1));
        assert_eq!(g.size(), [5.0, 8.0]);
        assert_eq!(g.cell_area(), 2.0);
    }

    #[test]
    fn fields_check_values_and_keep_the_mask() {
        let g = Grid::new(3, 2, 0.5, 0.5).expect("valid");
        assert!(Field::new(g.clone(), vec![0.0; 5]).is_err());
        let e = Field::new(g.clone(), vec![0.0, 1.0, 2.0, 3.0, f64::NAN, 5.0]).expect_err("NaN");
        assert!(e.to_string().contains("(1, 1)"), "{e}");
        let f =
            Field::from_nan(g.clone(), vec![1.0, f64::NAN, 3.0, 4.0, 0.0, -2.0]).expect("masked");
        assert_eq!(f.valid_count(), 5);
        assert_eq!(f.get(1, 0), None);
        assert_eq!(f.get(2, 1), Some(-2.0));
        assert_eq!(f.max(), 4.0);
        assert_eq!(f.mean(), Some(1.2));
        assert_eq!(f.min_max(), Some((-2.0, 4.0)));
        // Σ valid = 6 on cells of 0.25 m²; three positive cells.
        assert_eq!(f.integral(), 1.5);
        assert_eq!(f.positive_area(), 0.75);
        let h = Field::from_fn(g, |x, y| x + 10.0 * y).expect("finite");
        assert_eq!(h.row(1), &[5.0, 5.5, 6.0]);
        assert!(h.mask().is_none());
        assert!((h.rms().expect("values") - (6.25f64 + 1.0 / 6.0).sqrt()).abs() < 1e-12);
    }

    #[test]
    #[should_panic(expected = "Field::at(3, 0) is outside the 3 × 2 grid")]
    fn a_column_past_the_row_panics_instead_of_reading_the_next_row() {
        let g = Grid::new(3, 2, 1.0, 1.0).expect("valid");
        let f = Field::new(g, vec![0.0, 1.0, 2.0, 3.0, 4.0, 5.0]).expect("finite");
        assert_eq!(f.at(2, 1), 5.0);
        // Row-major index 3 is cell (0, 1): `at` must not read it for (3, 0).
        let _ = f.at(3, 0);
    }

    #[test]
    #[should_panic(expected = "Field::at(5, 0) is outside the 3 × 1 grid")]
    fn a_cell_past_the_grid_panics_with_the_index_and_the_size() {
        let _ = Field::zeros(Grid::new(3, 1, 1.0, 1.0).expect("valid")).at(5, 0);
    }

    #[test]
    #[should_panic(expected = "Field::row(7) is outside the 3 × 1 grid")]
    fn a_row_past_the_grid_panics_with_the_index_and_the_size() {
        let _ = Field::zeros(Grid::new(3, 1, 1.0, 1.0).expect("valid")).row(7);
    }

    #[test]
    fn a_grid_whose_extent_or_cell_area_leaves_floating_point_is_refused() {
        // 3 × 1e308 m overflows the extent (and x(2) of the centred grid).
        let e = Grid::centered(3, 3, 1e308, 1e308).expect_err("infinite extent");
        assert!(
            matches!(
                e,
                CoreError::InvalidValue {
                    name: "grid spacing dx (m)",
                    ..
                }
            ),
            "{e}"
        );
        assert!(e.to_string().contains("extent"), "{e}");
        let e = Grid::new(3, 3, f64::MAX, 1.0).expect_err("infinite extent");
        assert!(e.to_string().contains("1.7976931348623157e308"), "{e}");
        // 5e-324² underflows to a zero cell area.
        let e = Grid::centered(3, 3, 5e-324, 5e-324).expect_err("zero cell area");
        assert!(
            matches!(e, CoreError::InvalidValue { name: "grid cell area dx·dy (m²)", value, .. } if value == 0.0),
            "{e}"
        );
        // An origin that pushes the last centre past f64::MAX.
        let e = Grid::new(2, 1, 5e307, 1.0)
            .and_then(|g| g.with_origin([1.5e308, 0.0]))
            .expect_err("last centre overflows");
        assert!(e.to_string().contains("farthest cell centre"), "{e}");
        // Large but representable grids stay valid.
        let g = Grid::centered(3, 3, 1e307, 1e-150).expect("finite extent and area");
        assert!(g.x(2).is_finite() && g.cell_area() > 0.0);
    }
}
