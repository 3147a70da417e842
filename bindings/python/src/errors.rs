//! The exception hierarchy: `tyreroad.Error` and one subclass per Rust
//! error type, each carrying the Rust message unchanged.

use pyo3::create_exception;
use pyo3::exceptions::PyException;
use pyo3::prelude::*;

create_exception!(
    _tyreroad,
    Error,
    PyException,
    "Base of every tyreroad error."
);
create_exception!(
    _tyreroad,
    InputError,
    Error,
    "A Python argument refused before Rust sees it: wrong dtype, shape, contiguity or type."
);
create_exception!(
    _tyreroad,
    CoreError,
    Error,
    "tyreroad-core: material, grid, spectrum."
);
create_exception!(
    _tyreroad,
    GeometryError,
    Error,
    "tyreroad-asperity: asperity shapes and meshes."
);
create_exception!(
    _tyreroad,
    LawError,
    Error,
    "tyreroad-contact-law: contact laws."
);
create_exception!(
    _tyreroad,
    SolveError,
    Error,
    "tyreroad-multipoint: the multipoint solve."
);
create_exception!(
    _tyreroad,
    TextureError,
    Error,
    "tyreroad-texture: height maps, readers, segmentation."
);
create_exception!(
    _tyreroad,
    BemError,
    Error,
    "tyreroad-bem: the full-grid BEM."
);
create_exception!(
    _tyreroad,
    FilmError,
    Error,
    "tyreroad-film: pressure-film analysis."
);
create_exception!(
    _tyreroad,
    RollingError,
    Error,
    "tyreroad-rolling: rolling runs."
);
create_exception!(
    _tyreroad,
    FidelityError,
    Error,
    "tyreroad.fidelity: calibrated laws and the ladder against the BEM."
);
create_exception!(
    _tyreroad,
    ScenarioError,
    Error,
    "tyreroad.scenario: scenario files and runs."
);

/// Maps a Rust error to its Python exception, message unchanged.
pub trait IntoPyErr {
    /// The exception carrying `self`'s `Display` message.
    fn into_py_err(self) -> PyErr;
}

macro_rules! maps_to {
    ($($rust:ty => $py:ident),* $(,)?) => {$(
        impl IntoPyErr for $rust {
            fn into_py_err(self) -> PyErr {
                $py::new_err(self.to_string())
            }
        }
    )*};
}

maps_to!(
    tyreroad::shared::CoreError => CoreError,
    tyreroad::asperity::GeometryError => GeometryError,
    tyreroad::contact_law::LawError => LawError,
    tyreroad::multipoint::SolveError => SolveError,
    tyreroad::texture::TextureError => TextureError,
    tyreroad::bem::BemError => BemError,
    tyreroad::film::FilmError => FilmError,
    tyreroad::rolling::RollingError => RollingError,
    tyreroad::scenario::ScenarioError => ScenarioError,
    tyreroad::fidelity::FidelityError => FidelityError,
);

/// `result.map_err(IntoPyErr::into_py_err)`, shorter.
pub trait OrRaise<T> {
    /// The value, or the error as its Python exception.
    fn or_raise(self) -> PyResult<T>;
}

impl<T, E: IntoPyErr> OrRaise<T> for Result<T, E> {
    fn or_raise(self) -> PyResult<T> {
        self.map_err(IntoPyErr::into_py_err)
    }
}

/// An `InputError` with `message`.
pub fn input_error(message: impl Into<String>) -> PyErr {
    InputError::new_err(message.into())
}

/// Raises `message` as a Python `UserWarning` (an error when the caller's
/// warning filters say so).
pub fn warn(py: Python<'_>, message: &str) -> PyResult<()> {
    let text = std::ffi::CString::new(message.replace('\0', " "))
        .map_err(|e| input_error(format!("warning text: {e}")))?;
    let category = py.get_type::<pyo3::exceptions::PyUserWarning>();
    PyErr::warn(py, category.as_any(), &text, 1)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    m.add("Error", py.get_type::<Error>())?;
    m.add("InputError", py.get_type::<InputError>())?;
    m.add("CoreError", py.get_type::<CoreError>())?;
    m.add("GeometryError", py.get_type::<GeometryError>())?;
    m.add("LawError", py.get_type::<LawError>())?;
    m.add("SolveError", py.get_type::<SolveError>())?;
    m.add("TextureError", py.get_type::<TextureError>())?;
    m.add("BemError", py.get_type::<BemError>())?;
    m.add("FilmError", py.get_type::<FilmError>())?;
    m.add("RollingError", py.get_type::<RollingError>())?;
    m.add("ScenarioError", py.get_type::<ScenarioError>())?;
    m.add("FidelityError", py.get_type::<FidelityError>())?;
    Ok(())
}
