//! The full-grid BEM on a height array (docs/bem.md): a rigid rough surface
//! pressed into a flat elastic half-space, Love's influence coefficients
//! and the Polonsky–Keer conjugate gradient.

use pyo3::prelude::*;
use pyo3::types::PyDict;
use tyreroad::bem::{BemOptions, Control, Solver};
use tyreroad::shared::{Field, Grid};

use crate::arrays::{rows_cols, slice, to_numpy2, view2};
use crate::errors::{OrRaise, input_error};
use crate::geometry::Material;

/// Solves the BEM contact of a rigid surface `heights` float64 (ny, nx) (m,
/// up towards the half-space; every value finite) with cells `dx × dy` (m)
/// against `material`, under exactly one of `load` (N) or `approach` (m).
///
/// Returns a dict: `pressure`, `displacement`, `gap` float64 (ny, nx) (Pa,
/// m, m); `force` (N), `approach` (m), `contact_area` (m²), `contact_cells`,
/// `iterations`, `residual`. The heights are copied once into the solver's
/// field. Runs without the GIL; Ctrl-C is raised when the solve ends.
#[pyfunction]
#[pyo3(signature = (heights, dx, dy, material, *, load=None, approach=None, tolerance=1e-8, max_iterations=5000, periodic=false))]
#[allow(clippy::too_many_arguments)]
fn bem_solve<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    dx: f64,
    dy: f64,
    material: &Material,
    load: Option<f64>,
    approach: Option<f64>,
    tolerance: f64,
    max_iterations: usize,
    periodic: bool,
) -> PyResult<Bound<'py, PyDict>> {
    let control = match (load, approach) {
        (Some(w), None) => Control::Load(w),
        (None, Some(d)) => Control::Approach(d),
        _ => {
            return Err(input_error(
                "give exactly one of load= (N) or approach= (m)",
            ));
        }
    };
    let view = view2(heights, "heights")?;
    let (ny, nx) = rows_cols(&view);
    let grid = Grid::new(nx, ny, dx, dy).or_raise()?;
    let surface = Field::new(grid, slice(&view)?.to_vec()).or_raise()?;
    let options = BemOptions {
        tolerance,
        max_iterations,
        periodic,
        ..BemOptions::default()
    };
    let material = material.inner;
    let s = crate::interrupt::run(py, |_cancel| {
        Solver::new(surface.grid(), &material, &options)?.solve(&surface, control)
    })?
    .or_raise()?;
    let out = PyDict::new(py);
    out.set_item("force", s.force)?;
    out.set_item("approach", s.approach)?;
    out.set_item("contact_area", s.contact_area)?;
    out.set_item("contact_cells", s.contact_cells)?;
    out.set_item("iterations", s.iterations)?;
    out.set_item("residual", s.residual)?;
    out.set_item("pressure", to_numpy2(py, s.pressure, ny, nx)?)?;
    out.set_item("displacement", to_numpy2(py, s.displacement, ny, nx)?)?;
    out.set_item("gap", to_numpy2(py, s.gap, ny, nx)?)?;
    Ok(out)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(bem_solve, m)?)?;
    Ok(())
}
