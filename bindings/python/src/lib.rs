//! `tyreroad._tyreroad`: the Python face of tyreroad (docs/python.md).
//!
//! Every layer of the model, NumPy arrays in and out, SI units and float64:
//! geometry and laws ([`geometry`]), the multipoint solve ([`solve`]),
//! textures ([`texture`]), the full-grid BEM ([`bem`]), film analysis
//! ([`film`]), scenario files with rolling ([`scenario`]) and the fidelity
//! ladder against the BEM on a road of one's own ([`fidelity`]).
//!
//! Invariants kept across the boundary:
//! - arrays come in as read-only NumPy views (`PyReadonlyArray`): a wrong
//!   dtype, shape or a non-contiguous array is an `InputError` naming the
//!   argument, never a silent conversion; a copy is made only where the Rust
//!   type owns its data (a height map, a film scan) and is said so there;
//! - arrays go out by moving the Rust `Vec` into NumPy (no copy);
//! - every Rust error becomes the `tyreroad` exception of its crate
//!   ([`errors`]) with the same message;
//! - long work runs without the GIL; Ctrl-C is noticed between rolling
//!   steps ([`interrupt`]).

mod arrays;
mod bem;
mod errors;
mod fidelity;
mod film;
mod geometry;
mod interrupt;
mod scenario;
mod solve;
mod texture;

use pyo3::prelude::*;

/// The extension module: classes, functions and the exception hierarchy.
#[pymodule]
fn _tyreroad(m: &Bound<'_, PyModule>) -> PyResult<()> {
    errors::register(m)?;
    geometry::register(m)?;
    solve::register(m)?;
    texture::register(m)?;
    bem::register(m)?;
    film::register(m)?;
    fidelity::register(m)?;
    scenario::register(m)?;
    Ok(())
}
