//! Array arguments: read-only NumPy views checked for dtype, shape and
//! contiguity, and Rust vectors handed to NumPy without a copy.

use numpy::{
    IntoPyArray, PyArrayMethods, PyReadonlyArray1, PyReadonlyArray2, PyUntypedArrayMethods,
};
use pyo3::prelude::*;

use crate::errors::input_error;

/// What an array argument is, for messages: dtype and shape.
fn describe(obj: &Bound<'_, PyAny>) -> String {
    let dtype = obj
        .getattr("dtype")
        .map(|d| d.to_string())
        .unwrap_or_else(|_| obj.get_type().to_string());
    let shape = obj
        .getattr("shape")
        .map(|s| s.to_string())
        .unwrap_or_else(|_| "no shape".into());
    format!("dtype {dtype}, shape {shape}")
}

/// A float64 2-D C-contiguous view of `obj` (argument `name`).
pub fn view2<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<PyReadonlyArray2<'py, f64>> {
    let array: PyReadonlyArray2<'py, f64> = obj.extract().map_err(|_| {
        input_error(format!(
            "{name}: expected a float64 2-D numpy array, got {}",
            describe(obj)
        ))
    })?;
    if !array.is_c_contiguous() {
        return Err(input_error(format!(
            "{name}: the array is not C-contiguous (a slice or transpose?): \
             pass numpy.ascontiguousarray({name})"
        )));
    }
    Ok(array)
}

/// A float64 1-D contiguous view of `obj` (argument `name`).
pub fn view1<'py>(obj: &Bound<'py, PyAny>, name: &str) -> PyResult<PyReadonlyArray1<'py, f64>> {
    let array: PyReadonlyArray1<'py, f64> = obj.extract().map_err(|_| {
        input_error(format!(
            "{name}: expected a float64 1-D numpy array, got {}",
            describe(obj)
        ))
    })?;
    if !array.is_c_contiguous() {
        return Err(input_error(format!(
            "{name}: the array is not contiguous: pass numpy.ascontiguousarray({name})"
        )));
    }
    Ok(array)
}

/// The values of a contiguous view (checked contiguous on creation).
pub fn slice<'a, D: numpy::ndarray::Dimension>(
    array: &'a numpy::PyReadonlyArray<'_, f64, D>,
) -> PyResult<&'a [f64]> {
    array
        .as_slice()
        .map_err(|e| input_error(format!("array not contiguous: {e}")))
}

/// `(ny, nx)` of a 2-D view: rows are y, columns x (row-major maps).
pub fn rows_cols(array: &PyReadonlyArray2<'_, f64>) -> (usize, usize) {
    let s = array.shape();
    (s[0], s[1])
}

/// Moves `values` into a 1-D NumPy array (no copy).
pub fn to_numpy1<'py>(py: Python<'py>, values: Vec<f64>) -> Bound<'py, PyAny> {
    values.into_pyarray(py).into_any()
}

/// Moves `values` (row-major `ny × nx`) into a 2-D NumPy array (no copy:
/// the reshape is a view of the moved buffer).
pub fn to_numpy2<'py, T: numpy::Element>(
    py: Python<'py>,
    values: Vec<T>,
    ny: usize,
    nx: usize,
) -> PyResult<Bound<'py, PyAny>> {
    Ok(values.into_pyarray(py).reshape([ny, nx])?.into_any())
}

/// Positions `(N, 2)` as `[x, y]` pairs (copied: the Rust problem owns them).
pub fn positions(obj: &Bound<'_, PyAny>, name: &str) -> PyResult<Vec<[f64; 2]>> {
    let view = view2(obj, name)?;
    let (n, cols) = rows_cols(&view);
    if cols != 2 {
        return Err(input_error(format!(
            "{name}: expected shape (N, 2), got ({n}, {cols})"
        )));
    }
    Ok(slice(&view)?
        .chunks_exact(2)
        .map(|p| [p[0], p[1]])
        .collect())
}
