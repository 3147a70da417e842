//! The multipoint solve under load or approach control (docs/theory.md §3).

use std::sync::Arc;

use pyo3::prelude::*;
use tyreroad::contact_law::{ContactLaw, LocalContact};
use tyreroad::multipoint::{Control, Problem, SolverOptions, pressure_map, solve as rust_solve};
use tyreroad::shared::Grid;

use crate::arrays::{positions as read_positions, slice, to_numpy1, to_numpy2, view1};
use crate::errors::{OrRaise, input_error};
use crate::geometry::{Asperity, Material};

type SharedLaw = Arc<dyn ContactLaw + Send + Sync>;

/// A converged multipoint solution (arrays in asperity order, SI units).
#[pyclass(frozen, module = "tyreroad._tyreroad")]
pub struct Solution {
    positions: Vec<[f64; 2]>,
    forces: Vec<f64>,
    depths: Vec<f64>,
    /// The laws, kept to rebuild local contacts on demand (not in every
    /// solve: that would be overhead the Rust caller does not pay).
    laws: Vec<SharedLaw>,
    /// Rigid approach δ0 of the tread (m).
    #[pyo3(get)]
    approach: f64,
    /// Newton iterations.
    #[pyo3(get)]
    iterations: usize,
    /// Final relative residual of the N equations.
    #[pyo3(get)]
    residual: f64,
    /// Σ P_i (N).
    #[pyo3(get)]
    total_force: f64,
    /// How the solve ended (`Debug` of the Rust `Convergence`).
    #[pyo3(get)]
    convergence: String,
    /// Recovery used, if any (`Debug` of the Rust `Recovery`).
    #[pyo3(get)]
    recovery: String,
}

impl Solution {
    /// Each asperity's local contact (radius, pressure profile) from its
    /// law's local rule, as `tyreroad_multipoint::Solution::local_contacts`.
    fn local_contacts(&self) -> Vec<LocalContact> {
        self.laws
            .iter()
            .zip(self.forces.iter().zip(&self.depths))
            .map(|(law, (&p, &d))| law.local_contact(p, d))
            .collect()
    }
}

#[pymethods]
impl Solution {
    /// Forces P_i (N), float64 (N,).
    #[getter]
    fn forces<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        to_numpy1(py, self.forces.clone())
    }
    /// Interpenetration depths δ_i (m), float64 (N,).
    #[getter]
    fn depths<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        to_numpy1(py, self.depths.clone())
    }
    /// Local contact radii a_i (m), float64 (N,): 0 out of contact.
    #[getter]
    fn radii<'py>(&self, py: Python<'py>) -> Bound<'py, PyAny> {
        to_numpy1(py, self.local_contacts().iter().map(|c| c.radius).collect())
    }
    /// Contacts carrying force.
    #[getter]
    fn contact_count(&self) -> usize {
        self.forces.iter().filter(|&&p| p > 0.0).count()
    }
    /// The two-scale pressure map (Pa): each contact's local pressure
    /// profile (Hertz, Sneddon or uniform, from its law's local rule) summed
    /// on a grid of `nx × ny` cells of `dx × dy` m whose first cell centre is
    /// `origin` (m). Returns float64 (ny, nx).
    #[pyo3(signature = (nx, ny, dx, dy, origin=(0.0, 0.0)))]
    fn pressure_map<'py>(
        &self,
        py: Python<'py>,
        nx: usize,
        ny: usize,
        dx: f64,
        dy: f64,
        origin: (f64, f64),
    ) -> PyResult<Bound<'py, PyAny>> {
        let grid = Grid::new(nx, ny, dx, dy)
            .and_then(|g| g.with_origin([origin.0, origin.1]))
            .or_raise()?;
        let contacts = self.local_contacts();
        let field = py
            .detach(|| pressure_map(&self.positions, &contacts, &grid))
            .or_raise()?;
        to_numpy2(py, field.into_values(), ny, nx)
    }
    fn __repr__(&self) -> String {
        format!(
            "Solution(total_force={}, approach={}, contacts={}, iterations={})",
            self.total_force,
            self.approach,
            self.contact_count(),
            self.iterations
        )
    }
}

/// One law per asperity: a list of `Asperity`, or one for all.
fn laws(asperities: &Bound<'_, PyAny>, n: usize) -> PyResult<Vec<SharedLaw>> {
    if let Ok(one) = asperities.cast::<Asperity>() {
        let law = one.get().contact_law();
        return Ok(vec![law; n]);
    }
    let list: Vec<Bound<'_, Asperity>> = asperities
        .extract()
        .map_err(|_| input_error("asperities: expected an Asperity or a sequence of Asperity"))?;
    if list.len() != n {
        return Err(input_error(format!(
            "asperities: {} for {n} positions",
            list.len()
        )));
    }
    Ok(list.iter().map(|a| a.get().contact_law()).collect())
}

/// Solves the multipoint contact of a flat elastic tread on rigid asperities.
///
/// `positions` float64 (N, 2) summit positions (m); `heights` float64 (N,)
/// summit heights (m, up: the tread first touches the highest);
/// `asperities` one `Asperity` for all or a sequence of N; exactly one of
/// `load` (N, total force imposed) or `approach` (m, tread approach δ0
/// imposed). `tolerance` overrides the solver's relative tolerance.
/// The GIL is released during the solve (one solve is not interruptible).
#[pyfunction]
#[pyo3(signature = (positions, heights, asperities, material, *, load=None, approach=None, tolerance=None))]
#[allow(clippy::too_many_arguments)]
fn solve(
    py: Python<'_>,
    positions: &Bound<'_, PyAny>,
    heights: &Bound<'_, PyAny>,
    asperities: &Bound<'_, PyAny>,
    material: &Material,
    load: Option<f64>,
    approach: Option<f64>,
    tolerance: Option<f64>,
) -> PyResult<Solution> {
    let control = match (load, approach) {
        (Some(w), None) => Control::Load(w),
        (None, Some(d)) => Control::Approach(d),
        _ => {
            return Err(input_error(
                "give exactly one of load= (N) or approach= (m)",
            ));
        }
    };
    let positions = read_positions(positions, "positions")?;
    let heights_view = view1(heights, "heights")?;
    let heights = slice(&heights_view)?;
    if heights.len() != positions.len() {
        return Err(input_error(format!(
            "heights: {} values for {} positions",
            heights.len(),
            positions.len()
        )));
    }
    let laws = laws(asperities, positions.len())?;
    let problem = Problem::from_heights(positions, heights, laws, material.inner).or_raise()?;
    let mut options = SolverOptions::default();
    if let Some(t) = tolerance {
        options.tolerance = t;
    }
    let s = py
        .detach(|| rust_solve(&problem, control, &options))
        .or_raise()?;
    Ok(Solution {
        total_force: s.total_force(),
        positions: problem.positions().to_vec(),
        forces: s.forces,
        depths: s.depths,
        laws: problem.laws().to_vec(),
        approach: s.approach,
        iterations: s.iterations,
        residual: s.residual,
        convergence: format!("{:?}", s.convergence),
        recovery: format!("{:?}", s.recovery),
    })
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Solution>()?;
    m.add_function(wrap_pyfunction!(solve, m)?)?;
    Ok(())
}
