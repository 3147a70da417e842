//! `Material` and `Asperity`: the cap measures Ω, Σ, Γ of one rigid
//! asperity and its Wilke–Sameur potential law (docs/theory.md §1).

use std::sync::Arc;

use numpy::{PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tyreroad::asperity::{
    CapGeometry, CapMeasures, Cone, EllipticParaboloid, MeshAsperity, Sphere,
};
use tyreroad::contact_law::{ContactLaw, LocalRule, PotentialLaw};
use tyreroad::shared::Material as RustMaterial;

use crate::arrays::{slice, to_numpy1, view1};
use crate::errors::{OrRaise, input_error};

/// An elastic half-space: Young's modulus E (Pa) and Poisson's ratio ν.
#[pyclass(frozen, module = "tyreroad._tyreroad")]
#[derive(Clone)]
pub struct Material {
    pub(crate) inner: RustMaterial,
}

#[pymethods]
impl Material {
    /// A material; `CoreError` unless `E > 0` and `-1 < ν ≤ 0.5`, finite.
    #[new]
    fn new(youngs_modulus: f64, poisson_ratio: f64) -> PyResult<Self> {
        Ok(Self {
            inner: RustMaterial::new(youngs_modulus, poisson_ratio).or_raise()?,
        })
    }
    /// Young's modulus E (Pa).
    #[getter]
    fn youngs_modulus(&self) -> f64 {
        self.inner.youngs_modulus()
    }
    /// Poisson's ratio ν.
    #[getter]
    fn poisson_ratio(&self) -> f64 {
        self.inner.poisson_ratio()
    }
    /// Reduced modulus E* = E / (1 − ν²) (Pa).
    #[getter]
    fn reduced_modulus(&self) -> f64 {
        self.inner.reduced_modulus()
    }
    fn __repr__(&self) -> String {
        format!(
            "Material(youngs_modulus={}, poisson_ratio={})",
            self.inner.youngs_modulus(),
            self.inner.poisson_ratio()
        )
    }
}

/// The law of one shape; each variant keeps its geometry for `cap`.
#[derive(Clone)]
enum Law {
    Sphere(Arc<PotentialLaw<Sphere>>),
    Cone(Arc<PotentialLaw<Cone>>),
    Paraboloid(Arc<PotentialLaw<EllipticParaboloid>>),
    Mesh(Arc<PotentialLaw<MeshAsperity>>),
}

macro_rules! each_law {
    ($law:expr, $l:ident => $body:expr) => {
        match $law {
            Law::Sphere($l) => $body,
            Law::Cone($l) => $body,
            Law::Paraboloid($l) => $body,
            Law::Mesh($l) => $body,
        }
    };
}

/// One rigid asperity with its contact law `P(δ) = dU/dδ` (N) against the
/// material it was built with. Build with `sphere`, `cone`, `ellipsoid` or
/// `mesh`.
#[pyclass(frozen, module = "tyreroad._tyreroad")]
#[derive(Clone)]
pub struct Asperity {
    law: Law,
    kind: &'static str,
}

impl Asperity {
    /// The law as the solver takes it (shared, not copied).
    pub fn contact_law(&self) -> Arc<dyn ContactLaw + Send + Sync> {
        each_law!(&self.law, l => l.clone() as Arc<dyn ContactLaw + Send + Sync>)
    }

    fn measures(&self, depth: f64) -> CapMeasures {
        each_law!(&self.law, l => l.geometry().cap(depth))
    }
}

fn with_constant<G: CapGeometry>(
    law: PotentialLaw<G>,
    constant: Option<f64>,
) -> PyResult<PotentialLaw<G>> {
    match constant {
        Some(c) => law.with_constant(c).or_raise(),
        None => Ok(law),
    }
}

/// The depths of a 1-D float64 array, each a number or −∞ (out of
/// contact): a NaN would otherwise read as out of contact, a zero force.
fn checked_depths<'a>(view: &'a numpy::PyReadonlyArray1<'_, f64>) -> PyResult<&'a [f64]> {
    let depths = slice(view)?;
    if let Some((i, d)) = depths
        .iter()
        .enumerate()
        .find(|(_, d)| d.is_nan() || **d == f64::INFINITY)
    {
        return Err(input_error(format!(
            "depths[{i}] = {d}: a depth is a finite number of metres (−inf: out of contact)"
        )));
    }
    Ok(depths)
}

/// Applies `f` to each depth of a 1-D float64 array.
fn map_depths<'py>(
    py: Python<'py>,
    depths: &Bound<'py, PyAny>,
    f: impl Fn(f64) -> f64,
) -> PyResult<Bound<'py, PyAny>> {
    let view = view1(depths, "depths")?;
    Ok(to_numpy1(
        py,
        checked_depths(&view)?.iter().map(|&d| f(d)).collect(),
    ))
}

#[pymethods]
impl Asperity {
    /// A sphere of radius `radius` (m); `constant` is the law's shape
    /// constant c (default 0.36, the paper's).
    #[staticmethod]
    #[pyo3(signature = (radius, material, constant=None))]
    fn sphere(radius: f64, material: &Material, constant: Option<f64>) -> PyResult<Self> {
        let law = PotentialLaw::sphere(Sphere::new(radius).or_raise()?, material.inner);
        Ok(Self {
            law: Law::Sphere(Arc::new(with_constant(law, constant)?)),
            kind: "sphere",
        })
    }

    /// A cone of half-angle `half_angle` (rad, in (0, π/2)).
    #[staticmethod]
    #[pyo3(signature = (half_angle, material, constant=None))]
    fn cone(half_angle: f64, material: &Material, constant: Option<f64>) -> PyResult<Self> {
        let law = PotentialLaw::cone(Cone::new(half_angle).or_raise()?, material.inner);
        Ok(Self {
            law: Law::Cone(Arc::new(with_constant(law, constant)?)),
            kind: "cone",
        })
    }

    /// An elliptic paraboloid with summit curvature radii `radius_x`,
    /// `radius_y` (m): the ellipsoid's cap near its summit.
    #[staticmethod]
    #[pyo3(signature = (radius_x, radius_y, material, constant=None))]
    fn ellipsoid(
        radius_x: f64,
        radius_y: f64,
        material: &Material,
        constant: Option<f64>,
    ) -> PyResult<Self> {
        let law = PotentialLaw::paraboloid(
            EllipticParaboloid::new(radius_x, radius_y).or_raise()?,
            material.inner,
        );
        Ok(Self {
            law: Law::Paraboloid(Arc::new(with_constant(law, constant)?)),
            kind: "ellipsoid",
        })
    }

    /// A closed triangle mesh: `vertices` float64 (V, 3) in m (z up, the
    /// summit is the highest vertex), `faces` integer (F, 3) vertex indices,
    /// outward (counter-clockwise) orientation. Open, non-manifold or
    /// inward meshes raise `GeometryError`.
    #[staticmethod]
    #[pyo3(signature = (vertices, faces, material, constant=0.36))]
    fn mesh(
        vertices: &Bound<'_, PyAny>,
        faces: &Bound<'_, PyAny>,
        material: &Material,
        constant: f64,
    ) -> PyResult<Self> {
        let v = crate::arrays::view2(vertices, "vertices")?;
        if v.shape()[1] != 3 {
            return Err(input_error(format!(
                "vertices: expected shape (V, 3), got {:?}",
                v.shape()
            )));
        }
        let vertices: Vec<[f64; 3]> = slice(&v)?
            .chunks_exact(3)
            .map(|p| [p[0], p[1], p[2]])
            .collect();
        // Integer arrays only: `astype` would truncate 0.9 to 0, parse
        // strings and drop an imaginary part without a word.
        let kind: Option<String> = faces
            .getattr("dtype")
            .and_then(|d| d.getattr("kind"))
            .and_then(|k| k.extract())
            .ok();
        if let Some(kind) = kind.filter(|k| k != "i" && k != "u") {
            let dtype = faces
                .getattr("dtype")
                .map(|d| d.to_string())
                .unwrap_or(kind);
            return Err(input_error(format!(
                "faces: expected integer vertex indices, got dtype {dtype}"
            )));
        }
        let f: PyReadonlyArray2<'_, i64> = faces
            .call_method1("astype", ("int64",))
            .and_then(|a| a.extract())
            .map_err(|_| input_error("faces: expected an integer (F, 3) numpy array"))?;
        if f.shape()[1] != 3 {
            return Err(input_error(format!(
                "faces: expected shape (F, 3), got {:?}",
                f.shape()
            )));
        }
        let mut indices = Vec::with_capacity(f.shape()[0]);
        for t in f.as_array().rows() {
            let mut tri = [0u32; 3];
            for (k, &i) in t.iter().enumerate() {
                tri[k] = u32::try_from(i)
                    .ok()
                    .filter(|&i| (i as usize) < vertices.len())
                    .ok_or_else(|| {
                        input_error(format!(
                            "faces: index {i} outside 0..{} vertices",
                            vertices.len()
                        ))
                    })?;
            }
            indices.push(tri);
        }
        let geometry = MeshAsperity::new(&vertices, &indices).or_raise()?;
        let law = PotentialLaw::new(geometry, material.inner, constant, LocalRule::HalfSection)
            .or_raise()?;
        Ok(Self {
            law: Law::Mesh(Arc::new(law)),
            kind: "mesh",
        })
    }

    /// Cap measures at each interpenetration depth δ (m) of a float64 1-D
    /// array: a dict of arrays `volume` Ω (m³), `base_area` Σ (m²),
    /// `perimeter` Γ (m), `d_base_area` dΣ/dδ (m), `d_perimeter` dΓ/dδ.
    fn cap<'py>(
        &self,
        py: Python<'py>,
        depths: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyDict>> {
        let view = view1(depths, "depths")?;
        let m: Vec<CapMeasures> = checked_depths(&view)?
            .iter()
            .map(|&d| self.measures(d))
            .collect();
        let out = PyDict::new(py);
        let column = |f: fn(&CapMeasures) -> f64| to_numpy1(py, m.iter().map(f).collect());
        out.set_item("volume", column(|c| c.volume))?;
        out.set_item("base_area", column(|c| c.base_area))?;
        out.set_item("perimeter", column(|c| c.perimeter))?;
        out.set_item("d_base_area", column(|c| c.d_base_area))?;
        out.set_item("d_perimeter", column(|c| c.d_perimeter))?;
        Ok(out)
    }

    /// The law's force P(δ) (N) at each depth (m).
    fn force<'py>(
        &self,
        py: Python<'py>,
        depths: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        map_depths(
            py,
            depths,
            |d| each_law!(&self.law, l => l.evaluate(d).force),
        )
    }

    /// The law's stiffness k(δ) = dP/dδ (N/m) at each depth (m).
    fn stiffness<'py>(
        &self,
        py: Python<'py>,
        depths: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        map_depths(
            py,
            depths,
            |d| each_law!(&self.law, l => l.evaluate(d).stiffness),
        )
    }

    /// The potential U(δ) (J) at each depth (m).
    fn potential<'py>(
        &self,
        py: Python<'py>,
        depths: &Bound<'py, PyAny>,
    ) -> PyResult<Bound<'py, PyAny>> {
        map_depths(py, depths, |d| each_law!(&self.law, l => l.potential(d)))
    }

    /// The law's shape constant c.
    #[getter]
    fn constant(&self) -> f64 {
        each_law!(&self.law, l => l.constant())
    }

    /// `"sphere"`, `"cone"`, `"ellipsoid"` or `"mesh"`.
    #[getter]
    fn kind(&self) -> &'static str {
        self.kind
    }

    fn __repr__(&self) -> String {
        format!("Asperity.{}(constant={})", self.kind, self.constant())
    }
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<Material>()?;
    m.add_class::<Asperity>()?;
    Ok(())
}
