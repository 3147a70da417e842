//! One asperity's local field: its BEM solve on a widening grid, or the
//! recorded fallback.

use tyreroad_core::Field;

use super::{
    CANONICAL_CELL, LocalField, LocalShape, LocalStatus, MAX_COARSENINGS, MAX_WIDENINGS,
    TwoScaleError, TwoScaleOptions,
};
use crate::bem::{self, BemError, BemOptions, Grid, HeightMap};
use crate::contact_law::Material;

/// Cells of a local grid of half-width `half_width` Hertz radii (odd).
pub(super) fn local_cells(half_width: f64, cells_across: usize) -> usize {
    2 * (half_width * cells_across as f64 / 2.0).ceil() as usize + 1
}

/// Solves one asperity. `cache` keeps the canonical solver of the worker.
#[allow(clippy::too_many_arguments)]
pub(super) fn solve_local(
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
            status: LocalStatus::Complete,
        });
    }
    match solve_local_bem(
        index,
        centre,
        force,
        shape,
        material,
        hertz_radius,
        bem_options,
        options,
        cache,
    ) {
        Ok(field) => Ok(field),
        Err(error) => hertz_fallback(
            centre,
            force,
            shape.equivalent_radius(),
            hertz_radius,
            options,
            error.to_string(),
        ),
    }
}

/// The local BEM solve of one asperity, its grid widened while the contact
/// reaches the edge (see the module documentation).
#[allow(clippy::too_many_arguments)]
fn solve_local_bem(
    index: usize,
    centre: [f64; 2],
    force: f64,
    shape: &LocalShape,
    material: &Material,
    hertz_radius: f64,
    bem_options: &BemOptions,
    options: &TwoScaleOptions,
    cache: &mut Option<bem::Solver>,
) -> Result<LocalField, TwoScaleError> {
    let bem_err = |source: BemError| TwoScaleError::Bem { index, source };
    let mut half_width = options.half_width;
    let mut m = local_cells(half_width, options.cells_across);
    let attempts = MAX_WIDENINGS + MAX_COARSENINGS;
    for attempt in 0..=attempts {
        // Widen at the same resolution first, then with the same cells.
        let cell = if attempt <= MAX_WIDENINGS {
            m = local_cells(half_width, options.cells_across);
            2.0 * hertz_radius / options.cells_across as f64
        } else {
            half_width * hertz_radius / (m / 2) as f64
        };
        // The scale s maps the real problem onto the canonical one.
        let s = cell / CANONICAL_CELL;
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
        let touching: Vec<usize> = edge_cells(m)
            .map(|(i, j)| canonical.index(i, j))
            .filter(|&k| sol.pressure[k] > 0.0)
            .collect();
        let status = if touching.is_empty() {
            LocalStatus::Complete
        } else if let Some(depth) = floor_under_edge(shape, surface.values(), &touching, m, s) {
            // The tread lies on the shape's floor at the edge: on a wider
            // grid it would only spread further over that floor.
            LocalStatus::PressedToFloor { depth }
        } else if attempt < attempts {
            half_width *= 1.5;
            continue;
        } else {
            LocalStatus::ClippedAtEdge { half_width }
        };
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
            status,
        });
    }
    Err(TwoScaleError::InvalidInput(format!(
        "asperity {index}: no local grid tried"
    )))
}

/// The cells on the border of an `m × m` grid (corners twice).
fn edge_cells(m: usize) -> impl Iterator<Item = (usize, usize)> {
    (0..m).flat_map(move |t| [(t, 0), (t, m - 1), (0, t), (m - 1, t)])
}

/// The depth (m) below the summit of the shape's floor when the contact
/// reaches the edge of the `m × m` canonical grid on it: one of the
/// `touching` edge cells lies at the grid's lowest height, and the ring out
/// to 1.5 times the grid's half-width holds no lower point (the shape is
/// flat beyond, as a basin's floor or a sphere's base; a paraboloid or a
/// cone still drops away there). `heights` are the canonical surface's,
/// lengths scaled by `1/s`.
fn floor_under_edge(
    shape: &LocalShape,
    heights: &[f64],
    touching: &[usize],
    m: usize,
    s: f64,
) -> Option<f64> {
    let lowest = heights.iter().copied().fold(f64::INFINITY, f64::min);
    let slack = 1e-9 * lowest.abs();
    if !touching.iter().any(|&k| heights[k] <= lowest + slack) {
        return None;
    }
    let half = (m / 2) as i64;
    let reach = (3 * half + 1) / 2;
    let drops_beyond = (-reach..=reach).any(|b| {
        (-reach..=reach).any(|a| {
            let beyond = a.abs() > half || b.abs() > half;
            let (x, y) = (a as f64 * CANONICAL_CELL, b as f64 * CANONICAL_CELL);
            beyond && shape.height(x * s, y * s) / s < lowest - slack
        })
    });
    (!drops_beyond).then_some(-lowest * s)
}

/// Hertz's field `p = p0 √(1 − r²/a²)` of the equivalent radius on the
/// first local grid, scaled so that it carries exactly `force`: the named
/// lower-fidelity field of an asperity whose local BEM solve failed.
fn hertz_fallback(
    centre: [f64; 2],
    force: f64,
    equivalent_radius: f64,
    a: f64,
    options: &TwoScaleOptions,
    reason: String,
) -> Result<LocalField, TwoScaleError> {
    let invalid = |e: tyreroad_core::CoreError| TwoScaleError::InvalidInput(e.to_string());
    let m = local_cells(options.half_width, options.cells_across);
    let cell = 2.0 * a / options.cells_across as f64;
    let half = (m / 2) as f64 * cell;
    let grid = Grid::new(m, m, cell, cell)
        .and_then(|g| g.with_origin([centre[0] - half, centre[1] - half]))
        .map_err(invalid)?;
    let mut pressure = vec![0.0; grid.len()];
    for j in 0..m {
        for i in 0..m {
            let (dx, dy) = (grid.x(i) - centre[0], grid.y(j) - centre[1]);
            let q = 1.0 - (dx * dx + dy * dy) / (a * a);
            if q > 0.0 {
                pressure[grid.index(i, j)] = q.sqrt();
            }
        }
    }
    let sum: f64 = pressure.iter().sum::<f64>() * grid.cell_area();
    if !(sum > 0.0) {
        return Err(TwoScaleError::InvalidInput(format!(
            "Hertz fallback at {centre:?}: no cell inside the radius {a} m ({reason})"
        )));
    }
    pressure.iter_mut().for_each(|p| *p *= force / sum);
    let field = Field::new(grid, pressure).map_err(invalid)?;
    Ok(LocalField {
        centre,
        force: field.integral(),
        radius: a,
        semi_axes: [a, a],
        contact_area: field.positive_area(),
        max_pressure: field.max(),
        approach: a * a / equivalent_radius,
        hertz_radius: a,
        iterations: 0,
        field: Some(field),
        status: LocalStatus::HertzFallback { reason },
    })
}
