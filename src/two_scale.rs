//! Two-scale local pressures: the "micro-scale" step of Dubois, Cesbron et
//! al. (2012) on top of a multipoint solution.
//!
//! The multipoint model ([`crate::multipoint`]) gives the force `P_i` of
//! every asperity from its contact law and the Boussinesq coupling between
//! summits. Its local picture (radius, pressure) comes from the law's local
//! rule (Hertz for spheres). The two-scale step rebuilds each asperity's
//! pressure field from its *real* shape instead: a full BEM contact solve
//! ([`crate::bem`]) of that asperity alone, under load control with the load
//! `P_i`. The local fields are then assembled on one global grid (the
//! pressure map of the whole patch, what a pressure film shows).
//!
//! This module is the only place where the layers meet: the laws and the
//! multipoint solver know nothing of the BEM, and the BEM knows nothing of
//! them.
//!
//! # Local problem
//!
//! Asperity `i` is described by its height relative to its summit,
//! `h_i(dx, dy) ≤ 0` ([`LocalShape`]). Its local grid is square, centred on
//! the summit (an odd number of cells, so the summit is a cell centre), of
//! half-width `half_width · a_i` with `cells_across` cells across the
//! expected contact diameter `2 a_i`, where `a_i = (3 P_i R_i / 4E*)^(1/3)`
//! is Hertz's radius for the shape's equivalent radius `R_i`. If the contact
//! reaches the edge of that grid the solve is repeated on a grid 1.5 times
//! wider (up to three times).
//!
//! All local grids have the same number of cells, only their cell size
//! differs. The elastic half-space has no length scale: scaling every length
//! (grid and heights) by `1/s` leaves the pressure unchanged and divides the
//! force by `s²` (Love's influence coefficient is homogeneous of degree 1 in
//! the lengths). Every local problem is therefore solved on one canonical
//! grid, and one [`bem::Solver`] (its kernel spectrum computed once) serves
//! every asperity (one per rayon worker).
//!
//! # Outputs
//!
//! Per asperity ([`LocalField`]): the pressure field on its own grid, the
//! contact area, the equivalent radius `√(A/π)`, the semi-axes from the
//! second moments of the contact area, the peak pressure. The global map
//! ([`TwoScale::map`]) is the sum of the local fields, remapped
//! conservatively (each local cell's force shared among the map cells it
//! overlaps, in proportion to the overlap area): it integrates to `Σ P_i`
//! to rounding.

use std::sync::Arc;

use rayon::prelude::*;

use tyreroad_core::{Field, Par, is_parallel, run_at};

use crate::bem::{self, BemError, BemOptions, Grid, HeightMap};
use crate::contact_law::Material;
use crate::multipoint::{ContactLaw, Problem, Solution};

/// Canonical cell size of the local BEM solves (m); any value would do (see
/// the module documentation on scaling).
const CANONICAL_CELL: f64 = 1e-4;

/// Number of widenings of a local grid whose contact reaches its edge.
const MAX_WIDENINGS: usize = 3;

/// The real shape of one asperity, as a height relative to its summit.
#[derive(Clone)]
pub enum LocalShape {
    /// A true sphere of radius `radius` (m): `√(R² − r²) − R` for `r < R`,
    /// `−R` beyond (a floor, as [`bem::spherical_caps`]).
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

    fn check(&self, index: usize) -> Result<(), TwoScaleError> {
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

/// Options of [`two_scale`].
#[derive(Debug, Clone, PartialEq)]
pub struct TwoScaleOptions {
    /// Half-width of each local grid, in units of the expected (Hertz)
    /// contact radius. Default `2.0`.
    pub half_width: f64,
    /// Cells across the expected contact diameter. Default `64`.
    pub cells_across: usize,
    /// Cell size of the global map (m); default (`None`): the median local
    /// cell size (smaller contacts are then spread over a few map cells,
    /// their force kept).
    pub map_cell: Option<f64>,
    /// Largest number of cells of the global map (a guard against a map cell
    /// far smaller than the patch). Default `16 · 2²⁰`.
    pub max_map_cells: usize,
    /// Local BEM solver options (`par` is ignored when
    /// [`TwoScaleOptions::par`] spreads the asperities over rayon).
    /// Default: tolerance `1e-8`.
    pub bem: BemOptions,
    /// Parallelism over the asperities: [`Par::Seq`] solves them one after
    /// the other (each local solve at `bem.par`), `Par::rayon(n)` spreads
    /// them over a rayon pool of `n` threads (the current pool when it has
    /// `n` threads). Default `Par::rayon(0)`: rayon's current pool.
    pub par: Par,
}

impl Default for TwoScaleOptions {
    fn default() -> Self {
        Self {
            half_width: 2.0,
            cells_across: 64,
            map_cell: None,
            max_map_cells: 16 << 20,
            bem: BemOptions::default(),
            par: Par::rayon(0),
        }
    }
}

/// A pressure field (Pa, ≥ 0) on a regular grid, row-major (`j · nx + i`,
/// cell centres at `origin + (i dx, j dy)`): the core's [`Field`], whose
/// [`Field::integral`] is the force (N), [`Field::max`] the peak pressure
/// and [`Field::positive_area`] the contact area.
pub type PressureField = Field;

/// The rebuilt local contact of one asperity.
#[derive(Debug, Clone, PartialEq)]
pub struct LocalField {
    /// Summit position (m).
    pub centre: [f64; 2],
    /// Force carried (N): `Σ p dA` of the local field, `P_i` to rounding.
    pub force: f64,
    /// Equivalent contact radius `√(A/π)` (m), 0 out of contact.
    pub radius: f64,
    /// Semi-axes (major, minor) of the contact area from its second moments
    /// (m); both equal the radius for a disc.
    pub semi_axes: [f64; 2],
    /// Contact area (m²).
    pub contact_area: f64,
    /// Peak pressure (Pa).
    pub max_pressure: f64,
    /// Local approach (m): how far the body came down past the summit.
    pub approach: f64,
    /// Hertz's radius for the shape's equivalent radius, used to size the
    /// grid (m).
    pub hertz_radius: f64,
    /// Conjugate-gradient iterations of the local solve.
    pub iterations: usize,
    /// The local pressure field on a grid centred on the summit (real
    /// coordinates); `None` out of contact.
    pub field: Option<PressureField>,
}

/// Result of [`two_scale`].
#[derive(Debug, Clone, PartialEq)]
pub struct TwoScale {
    /// One entry per asperity, in input order.
    pub local: Vec<LocalField>,
    /// The assembled pressure map of the whole patch; `None` if no asperity
    /// carries a force.
    pub map: Option<PressureField>,
}

/// What can go wrong in [`two_scale`].
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
#[non_exhaustive]
pub enum TwoScaleError {
    /// An input is out of range (the message names it).
    #[error("invalid input: {0}")]
    InvalidInput(String),
    /// A local BEM solve failed.
    #[error("asperity {index}: local BEM solve failed: {source}")]
    Bem {
        /// Asperity index.
        index: usize,
        /// The BEM error.
        #[source]
        source: BemError,
    },
    /// The contact still reaches the edge of the local grid after widening it.
    #[error(
        "asperity {index}: the contact reaches the edge of the local grid (half-width {half_width} × the Hertz radius); the shape is far blunter than its equivalent radius says"
    )]
    DomainTooSmall {
        /// Asperity index.
        index: usize,
        /// Last half-width tried (in Hertz radii).
        half_width: f64,
    },
    /// The global map would be too large.
    #[error("the pressure map would have {cells} cells, more than the limit {limit}")]
    MapTooLarge {
        /// Cells needed.
        cells: usize,
        /// [`TwoScaleOptions::max_map_cells`].
        limit: usize,
    },
}

/// Rebuilds the local pressure fields of a multipoint solution (forces
/// `solution.forces` at `problem.positions()`, material of the problem).
///
/// `shapes` has one entry per asperity, or a single entry for all.
///
/// # Errors
/// As [`two_scale`].
pub fn two_scale_solution<L: ContactLaw>(
    problem: &Problem<L>,
    solution: &Solution,
    shapes: &[LocalShape],
    options: &TwoScaleOptions,
) -> Result<TwoScale, TwoScaleError> {
    two_scale(
        problem.positions(),
        &solution.forces,
        shapes,
        problem.material(),
        options,
    )
}

/// Rebuilds the local pressure field of every asperity (summit at
/// `positions[i]`, force `forces[i]`, real shape `shapes[i]`) by a BEM solve
/// of that asperity alone under the load `forces[i]`, and assembles them on
/// one global map.
///
/// `shapes` has one entry per asperity, or a single entry for all.
///
/// # Errors
/// [`TwoScaleError::InvalidInput`] for mismatched lengths, non-finite
/// positions, negative or non-finite forces, invalid shapes or options;
/// [`TwoScaleError::Bem`] if a local solve fails;
/// [`TwoScaleError::DomainTooSmall`] if a contact keeps reaching the edge of
/// its grid; [`TwoScaleError::MapTooLarge`] if the map exceeds
/// [`TwoScaleOptions::max_map_cells`].
pub fn two_scale(
    positions: &[[f64; 2]],
    forces: &[f64],
    shapes: &[LocalShape],
    material: &Material,
    options: &TwoScaleOptions,
) -> Result<TwoScale, TwoScaleError> {
    let n = positions.len();
    if forces.len() != n {
        return Err(TwoScaleError::InvalidInput(format!(
            "{} positions but {} forces",
            n,
            forces.len()
        )));
    }
    if !(shapes.len() == n || shapes.len() == 1) {
        return Err(TwoScaleError::InvalidInput(format!(
            "{} positions but {} shapes (give one per asperity, or one for all)",
            n,
            shapes.len()
        )));
    }
    if !(options.half_width.is_finite() && options.half_width > 0.5) {
        return Err(TwoScaleError::InvalidInput(format!(
            "half_width must be finite and > 0.5, got {}",
            options.half_width
        )));
    }
    if options.cells_across < 4 {
        return Err(TwoScaleError::InvalidInput(format!(
            "cells_across must be >= 4, got {}",
            options.cells_across
        )));
    }
    if let Some(c) = options.map_cell
        && !(c.is_finite() && c > 0.0)
    {
        return Err(TwoScaleError::InvalidInput(format!(
            "map_cell must be finite and > 0, got {c}"
        )));
    }
    options
        .bem
        .validate()
        .map_err(|e| TwoScaleError::InvalidInput(e.to_string()))?;
    for (k, (p, f)) in positions.iter().zip(forces).enumerate() {
        if !(p[0].is_finite() && p[1].is_finite()) {
            return Err(TwoScaleError::InvalidInput(format!(
                "asperity {k}: position {p:?} is not finite"
            )));
        }
        if !(f.is_finite() && *f >= 0.0) {
            return Err(TwoScaleError::InvalidInput(format!(
                "asperity {k}: force must be finite and >= 0, got {f}"
            )));
        }
    }
    for (k, s) in shapes.iter().enumerate() {
        s.check(k)?;
    }
    let shape = |k: usize| {
        if shapes.len() == 1 {
            &shapes[0]
        } else {
            &shapes[k]
        }
    };
    let local: Vec<LocalField> = if is_parallel(options.par) {
        let bem_options = BemOptions {
            par: Par::Seq,
            ..options.bem.clone()
        };
        run_at(options.par, || {
            (0..n)
                .into_par_iter()
                .map_init(
                    || None,
                    |cache, k| {
                        solve_local(
                            k,
                            positions[k],
                            forces[k],
                            shape(k),
                            material,
                            &bem_options,
                            options,
                            cache,
                        )
                    },
                )
                .collect::<Result<_, _>>()
        })?
    } else {
        let mut cache = None;
        (0..n)
            .map(|k| {
                solve_local(
                    k,
                    positions[k],
                    forces[k],
                    shape(k),
                    material,
                    &options.bem,
                    options,
                    &mut cache,
                )
            })
            .collect::<Result<_, _>>()?
    };
    let map = assemble(&local, options)?;
    Ok(TwoScale { local, map })
}

/// Cells of a local grid of half-width `half_width` Hertz radii (odd).
fn local_cells(half_width: f64, cells_across: usize) -> usize {
    2 * (half_width * cells_across as f64 / 2.0).ceil() as usize + 1
}

/// Solves one asperity. `cache` keeps the canonical solver of the worker.
#[allow(clippy::too_many_arguments)]
fn solve_local(
    index: usize,
    centre: [f64; 2],
    force: f64,
    shape: &LocalShape,
    material: &Material,
    bem_options: &BemOptions,
    options: &TwoScaleOptions,
    cache: &mut Option<bem::Solver>,
) -> Result<LocalField, TwoScaleError> {
    let hertz_radius =
        (3.0 * force * shape.equivalent_radius() / (4.0 * material.reduced_modulus())).cbrt();
    if force == 0.0 {
        return Ok(LocalField {
            centre,
            force: 0.0,
            radius: 0.0,
            semi_axes: [0.0, 0.0],
            contact_area: 0.0,
            max_pressure: 0.0,
            approach: 0.0,
            hertz_radius,
            iterations: 0,
            field: None,
        });
    }
    let bem_err = |source: BemError| TwoScaleError::Bem { index, source };
    // Real cell size; the scale s maps the real problem onto the canonical one.
    let cell = 2.0 * hertz_radius / options.cells_across as f64;
    let s = cell / CANONICAL_CELL;
    let mut half_width = options.half_width;
    for _ in 0..=MAX_WIDENINGS {
        let m = local_cells(half_width, options.cells_across);
        let canonical =
            Grid::centered(m, m, CANONICAL_CELL, CANONICAL_CELL).map_err(|e| bem_err(e.into()))?;
        let reuse = cache.as_ref().is_some_and(|c| c.grid().nx() == m);
        if !reuse {
            *cache = Some(bem::Solver::new(&canonical, material, bem_options).map_err(bem_err)?);
        }
        let solver = cache
            .as_mut()
            .ok_or_else(|| TwoScaleError::InvalidInput("no local solver".into()))?;
        let surface = HeightMap::from_fn(canonical.clone(), |x, y| shape.height(x * s, y * s) / s)
            .map_err(|e| bem_err(e.into()))?;
        let sol = solver
            .solve(&surface, bem::Control::Load(force / (s * s)))
            .map_err(bem_err)?;
        let touches_edge = (0..m).any(|t| {
            sol.pressure[canonical.index(t, 0)] > 0.0
                || sol.pressure[canonical.index(t, m - 1)] > 0.0
                || sol.pressure[canonical.index(0, t)] > 0.0
                || sol.pressure[canonical.index(m - 1, t)] > 0.0
        });
        if touches_edge {
            half_width *= 1.5;
            continue;
        }
        let region = sol
            .regions(&vec![0; canonical.len()])
            .map_err(bem_err)?
            .into_iter()
            .next()
            .unwrap_or_default();
        let half = (m / 2) as f64 * cell;
        let grid = Grid::new(m, m, cell, cell)
            .and_then(|g| g.with_origin([centre[0] - half, centre[1] - half]))
            .map_err(|e| bem_err(e.into()))?;
        let field = Field::new(grid, sol.pressure).map_err(|e| bem_err(e.into()))?;
        return Ok(LocalField {
            centre,
            force: field.integral(),
            radius: region.equivalent_radius * s,
            semi_axes: [region.semi_axes[0] * s, region.semi_axes[1] * s],
            contact_area: region.contact_area * s * s,
            max_pressure: region.max_pressure,
            // The summit is the highest point of the canonical surface, so
            // the solver's reference is the summit.
            approach: sol.approach * s,
            hertz_radius,
            iterations: sol.iterations,
            field: Some(field),
        });
    }
    Err(TwoScaleError::DomainTooSmall { index, half_width })
}

/// Conservative remap of every local field onto one global grid.
fn assemble(
    local: &[LocalField],
    options: &TwoScaleOptions,
) -> Result<Option<PressureField>, TwoScaleError> {
    let fields: Vec<&PressureField> = local.iter().filter_map(|l| l.field.as_ref()).collect();
    if fields.is_empty() {
        return Ok(None);
    }
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    let mut cell_sizes = Vec::with_capacity(fields.len());
    for f in &fields {
        let g = f.grid();
        let o = g.origin();
        lo[0] = lo[0].min(o[0] - 0.5 * g.dx());
        lo[1] = lo[1].min(o[1] - 0.5 * g.dy());
        hi[0] = hi[0].max(o[0] + (g.nx() as f64 - 0.5) * g.dx());
        hi[1] = hi[1].max(o[1] + (g.ny() as f64 - 0.5) * g.dy());
        cell_sizes.push(g.dx());
    }
    cell_sizes.sort_by(f64::total_cmp);
    let h = options.map_cell.unwrap_or(cell_sizes[cell_sizes.len() / 2]);
    let nx = ((hi[0] - lo[0]) / h).ceil() as usize + 1;
    let ny = ((hi[1] - lo[1]) / h).ceil() as usize + 1;
    let cells = nx.saturating_mul(ny);
    if cells > options.max_map_cells {
        return Err(TwoScaleError::MapTooLarge {
            cells,
            limit: options.max_map_cells,
        });
    }
    // Map cell (i, j) covers [lo + i h, lo + (i + 1) h].
    let grid = Grid::new(nx, ny, h, h)
        .and_then(|g| g.with_origin([lo[0] + 0.5 * h, lo[1] + 0.5 * h]))
        .map_err(|e| TwoScaleError::InvalidInput(e.to_string()))?;
    let mut force = vec![0.0; cells];
    let mut ox = Vec::new();
    let mut oy = Vec::new();
    for f in &fields {
        let g = f.grid();
        let (dx, dy) = (g.dx(), g.dy());
        for j in 0..g.ny() {
            let yc = g.y(j);
            let row = f.row(j);
            if row.iter().all(|&p| p == 0.0) {
                continue;
            }
            overlaps(yc - 0.5 * dy, yc + 0.5 * dy, lo[1], h, ny, &mut oy);
            for (i, &p) in row.iter().enumerate() {
                if p == 0.0 {
                    continue;
                }
                let xc = g.x(i);
                overlaps(xc - 0.5 * dx, xc + 0.5 * dx, lo[0], h, nx, &mut ox);
                for &(jj, wy) in &oy {
                    for &(ii, wx) in &ox {
                        force[jj * nx + ii] += p * wx * wy;
                    }
                }
            }
        }
    }
    let area = h * h;
    let pressure = force.into_iter().map(|f| f / area).collect();
    Field::new(grid, pressure)
        .map(Some)
        .map_err(|e| TwoScaleError::InvalidInput(e.to_string()))
}

/// Lengths of overlap of `[a, b]` with the cells `[lo + k h, lo + (k+1) h]`,
/// `k < n`.
fn overlaps(a: f64, b: f64, lo: f64, h: f64, n: usize, out: &mut Vec<(usize, f64)>) {
    out.clear();
    let k0 = (((a - lo) / h).floor().max(0.0) as usize).min(n - 1);
    let mut k = k0;
    while k < n {
        let c0 = lo + k as f64 * h;
        if c0 >= b {
            break;
        }
        let w = b.min(c0 + h) - a.max(c0);
        if w > 0.0 {
            out.push((k, w));
        }
        k += 1;
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn overlaps_partition_an_interval() {
        let mut out = Vec::new();
        overlaps(0.25, 1.75, 0.0, 0.5, 10, &mut out);
        let total: f64 = out.iter().map(|o| o.1).sum();
        assert!((total - 1.5).abs() < 1e-15);
        assert_eq!(out.first().map(|o| o.0), Some(0));
        assert_eq!(out.last().map(|o| o.0), Some(3));
    }

    #[test]
    fn local_grid_is_odd() {
        assert_eq!(local_cells(2.0, 64), 129);
        assert_eq!(local_cells(1.5, 64), 97);
    }
}
