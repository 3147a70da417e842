//! The height map: a regular grid of heights with a validity mask.

use tyreroad_core::{CoreError, Field, Grid, validate};

use crate::error::TextureError;

/// Most grid points a map may hold (2³⁰ ≈ 1.07e9, the core grid's
/// [`tyreroad_core::MAX_CELLS`]): larger sizes read from a file are refused
/// before anything is allocated.
pub const MAX_POINTS: usize = tyreroad_core::MAX_CELLS;

/// A road texture sampled on a regular grid: a core [`Field`] that always
/// carries its validity mask and sits at the coordinate origin.
///
/// Point `(i, j)` (`i < nx` along x, the driving direction; `j < ny` along
/// y) lies at `x = i·dx`, `y = j·dy` and is stored at index `j·nx + i`
/// (row-major, one row per profile along x). Heights are in metres.
///
/// # Invariants
///
/// - `nx ≥ 1`, `ny ≥ 1`, `nx·ny ≤` [`MAX_POINTS`];
/// - `dx`, `dy` finite and `> 0` (m);
/// - the grid's origin (centre of point `(0, 0)`) is `(0, 0)`;
/// - the mask is always present: `heights.len() == valid.len() == nx·ny`;
/// - every valid height is finite; an invalid (missing) point stores NaN.
#[derive(Clone, Debug, PartialEq)]
pub struct HeightMap {
    /// Always built by `Field::with_mask`: its mask is present.
    field: Field,
}

fn map_error(e: CoreError) -> TextureError {
    TextureError::InvalidMap(e.to_string())
}

impl HeightMap {
    /// A map whose points are all valid; every height must be finite.
    pub fn new(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        heights: Vec<f64>,
    ) -> Result<Self, TextureError> {
        let valid = vec![true; heights.len()];
        Self::with_mask(nx, ny, dx, dy, heights, valid)
    }

    /// A map where NaN heights mark invalid (unmeasured) points.
    ///
    /// # Errors
    /// An infinite height is refused, naming its point: it is no
    /// measurement of anything, and silently dropping it would hide a
    /// broken export.
    pub fn from_nan_heights(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        heights: Vec<f64>,
    ) -> Result<Self, TextureError> {
        if let Some(k) = heights.iter().position(|h| h.is_infinite()) {
            let (i, j) = (k % nx.max(1), k / nx.max(1));
            return Err(TextureError::InvalidMap(format!(
                "the height at point (i = {i}, j = {j}) is infinite ({}); missing points are NaN",
                heights[k]
            )));
        }
        let valid = heights.iter().map(|h| h.is_finite()).collect();
        Self::with_mask(nx, ny, dx, dy, heights, valid)
    }

    /// A map with an explicit validity mask (`true` = measured). Heights at
    /// invalid points are ignored (stored as NaN); heights at valid points
    /// must be finite.
    pub fn with_mask(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        heights: Vec<f64>,
        valid: Vec<bool>,
    ) -> Result<Self, TextureError> {
        check_size(nx, ny)?;
        validate::positive("dx", dx)?;
        validate::positive("dy", dy)?;
        let grid = Grid::new(nx, ny, dx, dy).map_err(map_error)?;
        let field = Field::with_mask(grid, heights, valid).map_err(map_error)?;
        Ok(Self { field })
    }

    /// A map sampled from `f(x, y)` at `x = i·dx`, `y = j·dy`; non-finite
    /// values are refused.
    pub fn from_fn(
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        f: impl Fn(f64, f64) -> f64,
    ) -> Result<Self, TextureError> {
        check_size(nx, ny)?;
        let mut h = Vec::with_capacity(nx * ny);
        for j in 0..ny {
            for i in 0..nx {
                h.push(f(i as f64 * dx, j as f64 * dy));
            }
        }
        Self::new(nx, ny, dx, dy, h)
    }

    /// The map as a core field (origin at `(0, 0)`, mask present).
    pub fn field(&self) -> &Field {
        &self.field
    }
    /// Consumes the map and returns its core field.
    pub fn into_field(self) -> Field {
        self.field
    }
    /// The grid (centre of point `(0, 0)` at the origin).
    pub fn grid(&self) -> &Grid {
        self.field.grid()
    }
    /// Number of points along x.
    pub fn nx(&self) -> usize {
        self.grid().nx()
    }
    /// Number of points along y (number of profiles).
    pub fn ny(&self) -> usize {
        self.grid().ny()
    }
    /// Spacing along x (m).
    pub fn dx(&self) -> f64 {
        self.grid().dx()
    }
    /// Spacing along y (m).
    pub fn dy(&self) -> f64 {
        self.grid().dy()
    }
    /// Heights (m), row-major (`j·nx + i`); NaN at invalid points.
    pub fn heights(&self) -> &[f64] {
        self.field.values()
    }
    /// Validity mask, row-major; `true` = measured.
    pub fn valid(&self) -> &[bool] {
        self.field.mask().unwrap_or(&[])
    }
    /// Index of point `(i, j)`.
    #[inline]
    pub fn index(&self, i: usize, j: usize) -> usize {
        self.grid().index(i, j)
    }
    /// Height at `(i, j)`, `None` if out of range or invalid.
    #[inline]
    pub fn get(&self, i: usize, j: usize) -> Option<f64> {
        self.field.get(i, j)
    }
    /// Profile `j` (heights along x), NaN at invalid points.
    pub fn row(&self, j: usize) -> &[f64] {
        self.field.row(j)
    }
    /// Number of valid points.
    pub fn valid_count(&self) -> usize {
        self.field.valid_count()
    }
    /// Length along x, `(nx − 1)·dx` (m).
    pub fn length_x(&self) -> f64 {
        (self.nx() - 1) as f64 * self.dx()
    }
    /// Length along y, `(ny − 1)·dy` (m).
    pub fn length_y(&self) -> f64 {
        (self.ny() - 1) as f64 * self.dy()
    }

    /// Mean height over valid points (`None` if none is valid).
    pub fn mean(&self) -> Option<f64> {
        self.field.mean()
    }

    /// `Sq`: root mean square of the heights about their mean, over valid
    /// points (`None` if none is valid).
    pub fn rms(&self) -> Option<f64> {
        self.field.rms()
    }

    /// Smallest and largest valid heights (`None` if none is valid).
    pub fn min_max(&self) -> Option<(f64, f64)> {
        self.field.min_max()
    }

    /// A copy with invalid points filled (all become valid): each invalid
    /// point takes the mean of its valid 4-neighbours, repeated until none
    /// is left (a diffusion front from the measured points). A map with no
    /// valid point is refused.
    pub fn filled(&self) -> Result<Self, TextureError> {
        if self.valid_count() == 0 {
            return Err(TextureError::NotEnoughData(
                "the map has no valid point to fill from".into(),
            ));
        }
        let mut h = self.heights().to_vec();
        let mut v = self.valid().to_vec();
        let (nx, ny) = (self.nx(), self.ny());
        loop {
            let mut changed = Vec::new();
            for j in 0..ny {
                for i in 0..nx {
                    let k = j * nx + i;
                    if v[k] {
                        continue;
                    }
                    let (mut s, mut c) = (0.0, 0);
                    let mut add = |kk: usize| {
                        if v[kk] {
                            s += h[kk];
                            c += 1;
                        }
                    };
                    if i > 0 {
                        add(k - 1);
                    }
                    if i + 1 < nx {
                        add(k + 1);
                    }
                    if j > 0 {
                        add(k - nx);
                    }
                    if j + 1 < ny {
                        add(k + nx);
                    }
                    if c > 0 {
                        changed.push((k, s / c as f64));
                    }
                }
            }
            if changed.is_empty() {
                break;
            }
            for (k, val) in changed {
                h[k] = val;
                v[k] = true;
            }
        }
        Self::new(nx, ny, self.dx(), self.dy(), h)
    }
}

pub(crate) fn check_size(nx: usize, ny: usize) -> Result<usize, TextureError> {
    if nx == 0 || ny == 0 {
        return Err(TextureError::InvalidMap(format!(
            "grid {nx} × {ny}: both sizes must be ≥ 1"
        )));
    }
    match nx.checked_mul(ny) {
        Some(n) if n <= MAX_POINTS => Ok(n),
        _ => Err(TextureError::InvalidMap(format!(
            "grid {nx} × {ny} exceeds {MAX_POINTS} points"
        ))),
    }
}
