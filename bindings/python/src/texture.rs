//! Textures: readers, synthesis, segmentation, MPD and the texture spectrum
//! (docs/texture.md).
//!
//! Heights are float64 `(ny, nx)` arrays, row `j` at `y = j·dy`, column `i`
//! at `x = i·dx` (m); NaN (or ±∞) marks a missing point. A `HeightMap` owns
//! its heights, so the view of the input array is copied once into it (the
//! only copy: validation reads the view in place).

use numpy::PyReadonlyArray2;
use pyo3::prelude::*;
use pyo3::types::PyDict;
use tyreroad::texture::{
    HeightMap, SegmentOptions, SelfAffine, mean_profile_depth as rust_mpd, read_any,
    segment as rust_segment, self_affine as rust_self_affine, third_octave_spectrum,
};

use crate::arrays::{rows_cols, slice, to_numpy1, to_numpy2, view2};
use crate::errors::OrRaise;

/// A height map from a `(ny, nx)` view: NaN marks missing points.
pub fn height_map(view: &PyReadonlyArray2<'_, f64>, dx: f64, dy: f64) -> PyResult<HeightMap> {
    let (ny, nx) = rows_cols(view);
    HeightMap::from_nan_heights(nx, ny, dx, dy, slice(view)?.to_vec()).or_raise()
}

/// `(heights (ny, nx), dx, dy)` of a map, moving its heights into NumPy.
fn map_out<'py>(py: Python<'py>, map: HeightMap) -> PyResult<(Bound<'py, PyAny>, f64, f64)> {
    let (nx, ny, dx, dy) = (map.nx(), map.ny(), map.dx(), map.dy());
    let heights = to_numpy2(py, map.into_field().into_values(), ny, nx)?;
    Ok((heights, dx, dy))
}

/// Reads a texture file of any format the Rust side reads (by extension:
/// .x3p, .sur, .asc, .xyz, .npy with its .spacing sidecar, .npz; an image
/// file is refused: it holds no heights): returns
/// `(heights (ny, nx) in m, dx, dy in m)`, NaN at missing points.
#[pyfunction]
fn read_texture<'py>(
    py: Python<'py>,
    path: std::path::PathBuf,
) -> PyResult<(Bound<'py, PyAny>, f64, f64)> {
    let map = py.detach(|| read_any(&path)).or_raise()?;
    map_out(py, map)
}

/// Mean profile depth (ISO 13473-1) of a map's x-profiles: a dict with
/// `mpd` (m), `baseline` (m), `samples`, `segments`. `baseline` (m)
/// defaults to 100 mm.
#[pyfunction]
#[pyo3(signature = (heights, dx, dy, baseline=None))]
fn mean_profile_depth<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    dx: f64,
    dy: f64,
    baseline: Option<f64>,
) -> PyResult<Bound<'py, PyDict>> {
    let map = height_map(&view2(heights, "heights")?, dx, dy)?;
    let m = rust_mpd(&map, baseline).or_raise()?;
    let out = PyDict::new(py);
    out.set_item("mpd", m.mpd)?;
    out.set_item("baseline", m.baseline)?;
    out.set_item("samples", m.samples)?;
    out.set_item("segments", m.segments)?;
    Ok(out)
}

/// The one-third-octave texture spectrum of the x-profiles: a dict of
/// arrays `centre`, `lower`, `upper` (band wavelengths, m), `rms` (m) and
/// `level_db` (dB re 1 µm), one entry per band.
#[pyfunction]
fn texture_spectrum<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    dx: f64,
    dy: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let map = height_map(&view2(heights, "heights")?, dx, dy)?;
    let bands = py.detach(|| third_octave_spectrum(&map)).or_raise()?;
    let out = PyDict::new(py);
    let column = |f: fn(&tyreroad::texture::ThirdOctaveBand) -> f64| {
        to_numpy1(py, bands.iter().map(f).collect())
    };
    out.set_item("centre", column(|b| b.centre))?;
    out.set_item("lower", column(|b| b.lower))?;
    out.set_item("upper", column(|b| b.upper))?;
    out.set_item("rms", column(|b| b.rms))?;
    out.set_item("level_db", column(|b| b.level_db))?;
    Ok(out)
}

/// Segments a map into asperities (watershed on summits, kept by
/// prominence and area): a dict with `labels` uint32 (ny, nx) (asperity
/// index, 2³²−1 for none) and the asperity table as arrays `x`, `y` (summit,
/// m), `z` (summit height, m), `prominence` (m), `area` (m²), and the fitted
/// summit curvature radii `radius_x`, `radius_y` (m, NaN where no fit).
#[pyfunction]
#[pyo3(signature = (heights, dx, dy, min_prominence, min_area=0.0))]
fn segment<'py>(
    py: Python<'py>,
    heights: &Bound<'py, PyAny>,
    dx: f64,
    dy: f64,
    min_prominence: f64,
    min_area: f64,
) -> PyResult<Bound<'py, PyDict>> {
    let map = height_map(&view2(heights, "heights")?, dx, dy)?;
    let options = SegmentOptions {
        min_prominence,
        min_area,
    };
    let seg = py.detach(|| rust_segment(&map, &options)).or_raise()?;
    let a = seg.asperities();
    let out = PyDict::new(py);
    let column =
        |f: &dyn Fn(&tyreroad::texture::Asperity) -> f64| to_numpy1(py, a.iter().map(f).collect());
    out.set_item("x", column(&|s| s.summit[0]))?;
    out.set_item("y", column(&|s| s.summit[1]))?;
    out.set_item("z", column(&|s| s.summit_height))?;
    out.set_item("prominence", column(&|s| s.prominence))?;
    out.set_item("area", column(&|s| s.area))?;
    out.set_item(
        "radius_x",
        column(&|s| s.fit.map_or(f64::NAN, |f| f.radii.0)),
    )?;
    out.set_item(
        "radius_y",
        column(&|s| s.fit.map_or(f64::NAN, |f| f.radii.1)),
    )?;
    let (nx, ny) = seg.size();
    out.set_item("labels", to_numpy2(py, seg.labels().to_vec(), ny, nx)?)?;
    Ok(out)
}

/// A self-affine (fractal) random surface: Hurst exponent `hurst`, rms
/// height `rms` (m), wavelengths between `lambda_short` and `lambda_long`
/// (m), reproducible from `seed`. Returns `(heights (ny, nx), dx, dy)`.
#[pyfunction]
#[pyo3(signature = (nx, ny, dx, dy, rms, hurst, lambda_long, lambda_short, seed=0))]
#[allow(clippy::too_many_arguments)]
fn self_affine<'py>(
    py: Python<'py>,
    nx: usize,
    ny: usize,
    dx: f64,
    dy: f64,
    rms: f64,
    hurst: f64,
    lambda_long: f64,
    lambda_short: f64,
    seed: u64,
) -> PyResult<(Bound<'py, PyAny>, f64, f64)> {
    let p = SelfAffine {
        nx,
        ny,
        dx,
        dy,
        rms,
        hurst,
        lambda_long,
        lambda_short,
        seed,
    };
    let map = py.detach(|| rust_self_affine(&p)).or_raise()?;
    map_out(py, map)
}

pub(crate) fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(read_texture, m)?)?;
    m.add_function(wrap_pyfunction!(mean_profile_depth, m)?)?;
    m.add_function(wrap_pyfunction!(texture_spectrum, m)?)?;
    m.add_function(wrap_pyfunction!(segment, m)?)?;
    m.add_function(wrap_pyfunction!(self_affine, m)?)?;
    Ok(())
}
