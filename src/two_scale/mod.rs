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
//! wider: three times at the same resolution, then up to six more times with
//! the same number of cells (coarser), so a blunt shape costs no more than a
//! sharp one.
//!
//! # Failure isolation
//!
//! One awkward asperity never loses the map. Its [`LocalField::status`] says
//! what it got: [`LocalStatus::Complete`] (the contact lies inside its
//! grid), [`LocalStatus::ClippedAtEdge`] (it still reaches the edge of the
//! widest grid: the field is that grid's BEM solution, whose force is exact
//! but whose area is cut by the edge), [`LocalStatus::PressedToFloor`]
//! (the contact reaches the edge on the shape's floor, flat beyond: the
//! asperity is pressed down to the surface around it and no wider grid
//! would bound the contact, so the widening stops there), or
//! [`LocalStatus::HertzFallback`]
//! (its local BEM solve failed: Hertz's field for its equivalent radius,
//! force exact, with the reason). [`TwoScale::fallbacks`] lists them.
//!
//! All local grids have the same number of cells, only their cell size
//! differs. The elastic half-space has no length scale: scaling every length
//! (grid and heights) by `1/s` leaves the pressure unchanged and divides the
//! force by `s²` (Love's influence coefficient is homogeneous of degree 1 in
//! the lengths). Every local problem is therefore solved on one canonical
//! grid, and one [`bem::Solver`](crate::bem::Solver) (its kernel spectrum computed once) serves
//! every asperity (one per rayon worker).
//!
//! # Beside the neighbours
//!
//! A cap solved alone carries its force as if the rest of the half-space
//! were unloaded. With [`TwoScaleOptions::neighbour_passes`] each pass
//! solves every cap again with its shape lowered by the variation across
//! it of the displacement its neighbours' fields (of the pass before) cause
//! ([`neighbours`]): the pressure moves away from a loaded neighbour as it
//! does in the full BEM. The forces stay the multipoint model's.
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

use rayon::prelude::*;

use tyreroad_core::{Field, Par, is_parallel, run_at};

use crate::bem::{BemError, BemOptions, Grid};
use crate::contact_law::Material;
use crate::multipoint::{ContactLaw, Problem, Solution};

/// Canonical cell size of the local BEM solves (m); any value would do (see
/// the module documentation on scaling).
const CANONICAL_CELL: f64 = 1e-4;

/// Widenings of a local grid whose contact reaches its edge, at the same
/// resolution (the cell count grows).
const MAX_WIDENINGS: usize = 3;

/// Further widenings with the cell count of the last one (coarser cells).
const MAX_COARSENINGS: usize = 6;

/// Most passes under the neighbours' displacement: two already agree with
/// the full BEM to a fraction of a percent (tests/two_scale_neighbours.rs);
/// more only cost time.
pub const MAX_NEIGHBOUR_PASSES: usize = 8;

mod local;
pub mod neighbours;
mod shape;

use local::solve_local;
pub use shape::LocalShape;

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
    /// Passes that solve each cap again under its neighbours' displacement,
    /// taken from the fields of the pass before ([`neighbours`]); at most
    /// [`MAX_NEIGHBOUR_PASSES`]. Default `0`: each cap alone.
    pub neighbour_passes: usize,
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
            neighbour_passes: 0,
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
    /// How the field was obtained (a fallback is recorded, not an error).
    pub status: LocalStatus,
}

/// How an asperity's local field was obtained.
#[derive(Debug, Clone, PartialEq)]
pub enum LocalStatus {
    /// The local BEM contact lies inside its grid (or nothing touches).
    Complete,
    /// The contact still reaches the edge of the widest local grid (its
    /// half-width in Hertz radii): the field is that grid's BEM solution,
    /// carrying the exact force, on an area cut by the edge.
    ClippedAtEdge {
        /// Half-width of the widest grid, in Hertz radii.
        half_width: f64,
    },
    /// The contact reaches the edge of the local grid on the shape's floor
    /// (its lowest level, flat beyond the grid): the asperity is pressed
    /// down to the surface around it, which no wider grid would bound. The
    /// field is that grid's BEM solution, carrying the exact force, on an
    /// area cut by the edge.
    PressedToFloor {
        /// Depth of the floor below the summit (m).
        depth: f64,
    },
    /// The local BEM solve failed: Hertz's field for the equivalent radius,
    /// carrying the exact force.
    HertzFallback {
        /// Why the BEM solve failed.
        reason: String,
    },
}

impl LocalStatus {
    /// A short name for tables: `complete`, `clipped`, `floor`, `hertz`.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Complete => "complete",
            Self::ClippedAtEdge { .. } => "clipped",
            Self::PressedToFloor { .. } => "floor",
            Self::HertzFallback { .. } => "hertz",
        }
    }
}

impl std::fmt::Display for LocalStatus {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::Complete => f.write_str("complete"),
            Self::ClippedAtEdge { half_width } => write!(
                f,
                "contact still at the edge of the widest local grid \
                 (half-width {half_width:.3} × the Hertz radius): area cut by the edge"
            ),
            // A tile of a split flat top has its floor level with its
            // summit: "-0.000 mm below" said nothing.
            Self::PressedToFloor { depth } if *depth < 0.5e-6 => f.write_str(
                "on a flat top, the surface around it level with its summit: \
                 contact on it reaches the edge of the local grid, area cut by the edge",
            ),
            Self::PressedToFloor { depth } => write!(
                f,
                "pressed down to the surface {} mm below the summit: \
                 contact on it reaches the edge of the local grid, area cut by the edge",
                tyreroad_core::readable3(depth * 1e3)
            ),
            Self::HertzFallback { reason } => write!(f, "Hertz field instead of BEM: {reason}"),
        }
    }
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

impl TwoScale {
    /// The asperities (index, status) whose field is a fallback.
    pub fn fallbacks(&self) -> impl Iterator<Item = (usize, &LocalStatus)> {
        self.local
            .iter()
            .enumerate()
            .filter(|(_, l)| l.status != LocalStatus::Complete)
            .map(|(k, l)| (k, &l.status))
    }
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
/// [`TwoScaleError::MapTooLarge`] if the map exceeds
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
    if options.neighbour_passes > MAX_NEIGHBOUR_PASSES {
        return Err(TwoScaleError::InvalidInput(format!(
            "neighbour_passes must be at most {MAX_NEIGHBOUR_PASSES}, got {}",
            options.neighbour_passes
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
    let mut local = solve_all(positions, forces, shape, material, options)?;
    for _ in 0..options.neighbour_passes {
        let coupled = neighbours::coupled_shapes(&local, shape, material);
        local = solve_all(positions, forces, |k| &coupled[k], material, options)?;
    }
    let map = assemble(&local, options)?;
    Ok(TwoScale { local, map })
}

/// One pass: every asperity's local solve under its own `shape(k)`.
fn solve_all<'s>(
    positions: &[[f64; 2]],
    forces: &[f64],
    shape: impl Fn(usize) -> &'s LocalShape + Sync,
    material: &Material,
    options: &TwoScaleOptions,
) -> Result<Vec<LocalField>, TwoScaleError> {
    let n = positions.len();
    Ok(if is_parallel(options.par) {
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
    })
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

    /// Regression (2026-11-30): a porous-asphalt tile's floor, level with
    /// its summit, was said as "-0.000 mm below the summit".
    #[test]
    fn a_floor_level_with_the_summit_is_said_as_a_flat_top() {
        let level = LocalStatus::PressedToFloor { depth: -1e-12 }.to_string();
        assert!(level.starts_with("on a flat top"), "{level}");
        let deep = LocalStatus::PressedToFloor { depth: 0.3e-3 }.to_string();
        assert!(
            deep.starts_with("pressed down to the surface 0.300 mm below"),
            "{deep}"
        );
    }

    #[test]
    fn local_grid_is_odd() {
        assert_eq!(local::local_cells(2.0, 64), 129);
        assert_eq!(local::local_cells(1.5, 64), 97);
    }
}
