//! NumPy height maps: a 2-D `float64` or `float32` array, `heights[j, i]`
//! the height (m) at `x = i·dx`, `y = j·dy` (shape `(ny, nx)`, C or Fortran
//! order), NaN where not measured.
//!
//! A `.npy` file holds no spacing: give it ([`read_npy`]) or put it in a
//! sidecar text file beside the array, `NAME.npy.spacing`, holding `dx` and
//! `dy` in metres (one number: the same both ways), which [`read_any`]
//! reads. A `.npz` archive carries its own: members `heights` (the array)
//! and `spacing` (`[dx, dy]`), what `numpy.savez(path, heights=h,
//! spacing=[dx, dy])` and the scenario layer's height-map output write.
//!
//! [`read_any`]: super::read_any

use std::io::Read;
use std::path::Path;

use tyreroad_core::validate;

use crate::{HeightMap, TextureError};

const NPY: &str = "NumPy";

/// Reads a `.npy` height map with grid spacing `dx`, `dy` (m).
///
/// # Errors
/// [`TextureError`] if the file cannot be read, is not a 2-D float array,
/// or the spacing is not finite and > 0.
pub fn read_npy(path: impl AsRef<Path>, dx: f64, dy: f64) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| TextureError::io(path, e))?;
    npy_from_bytes(&bytes, dx, dy)
}

/// Reads a `.npy` height map whose spacing is in the sidecar file
/// `NAME.npy.spacing` (see the module documentation).
///
/// # Errors
/// As [`read_npy`], and a missing or malformed sidecar.
pub fn read_npy_with_sidecar(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let (dx, dy) = sidecar_spacing(path)?;
    read_npy(path, dx, dy)
}

/// The spacing `(dx, dy)` (m) of a `.npy` height map, from its sidecar
/// file `NAME.npy.spacing` (one number for both, or two), so that a window
/// of the map ([`super::window::read_npy_window`]) is read as the whole
/// map would be ([`read_npy_with_sidecar`]).
///
/// # Errors
/// A missing or malformed sidecar.
pub fn sidecar_spacing(path: impl AsRef<Path>) -> Result<(f64, f64), TextureError> {
    let path = path.as_ref();
    let mut sidecar = path.as_os_str().to_os_string();
    sidecar.push(".spacing");
    let sidecar = Path::new(&sidecar);
    let text = std::fs::read_to_string(sidecar).map_err(|e| TextureError::io(sidecar, e))?;
    let values: Vec<f64> = text
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| TextureError::format(NPY, format!("{}: not numbers", sidecar.display())))?;
    let (dx, dy) = match values[..] {
        [d] => (d, d),
        [dx, dy] => (dx, dy),
        _ => {
            return Err(TextureError::format(
                NPY,
                format!("{}: give dx and dy (m)", sidecar.display()),
            ));
        }
    };
    Ok((dx, dy))
}

/// Reads a `.npz` height map (members `heights` and `spacing`).
///
/// # Errors
/// [`TextureError`] if the archive cannot be read or lacks either member.
pub fn read_npz(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let file = std::fs::File::open(path).map_err(|e| TextureError::io(path, e))?;
    let mut zip = zip::ZipArchive::new(file)
        .map_err(|e| TextureError::format(NPY, format!("{}: {e}", path.display())))?;
    let mut member = |name: &str| -> Result<Vec<u8>, TextureError> {
        let mut f = zip
            .by_name(name)
            .map_err(|_| TextureError::format(NPY, format!("no `{name}` in {}", path.display())))?;
        let mut bytes = Vec::new();
        f.read_to_end(&mut bytes)
            .map_err(|e| TextureError::io(path, e))?;
        Ok(bytes)
    };
    let heights = member("heights.npy")?;
    let spacing = floats(&member("spacing.npy")?)?.1;
    let (dx, dy) = match spacing[..] {
        [d] => (d, d),
        [dx, dy] => (dx, dy),
        _ => return Err(TextureError::format(NPY, "`spacing` must hold [dx, dy]")),
    };
    npy_from_bytes(&heights, dx, dy)
}

/// A height map from the bytes of a `.npy` file and its spacing (m).
///
/// # Errors
/// Not a 2-D `float64`/`float32` array, or a spacing that is not > 0.
pub fn npy_from_bytes(bytes: &[u8], dx: f64, dy: f64) -> Result<HeightMap, TextureError> {
    validate::positive("dx", dx)?;
    validate::positive("dy", dy)?;
    let (file_shape, values, fortran) = floats_nd(bytes)?;
    let [ny, nx] = file_shape[..] else {
        return Err(TextureError::format(
            NPY,
            format!("a height map is a 2-D array, this one has shape {file_shape:?}"),
        ));
    };
    let heights = if fortran {
        // Column-major: element (j, i) at i·ny + j.
        let mut h = vec![0.0; nx * ny];
        for i in 0..nx {
            for j in 0..ny {
                h[j * nx + i] = values[i * ny + j];
            }
        }
        h
    } else {
        values
    };
    HeightMap::from_nan_heights(nx, ny, dx, dy, heights)
}

fn floats(bytes: &[u8]) -> Result<(Vec<usize>, Vec<f64>), TextureError> {
    floats_nd(bytes).map(|(s, v, _)| (s, v))
}

/// Shape, values (file order) and whether the order is Fortran's.
fn floats_nd(bytes: &[u8]) -> Result<(Vec<usize>, Vec<f64>, bool), TextureError> {
    let bad = |e: std::io::Error| TextureError::format(NPY, e.to_string());
    let file = npyz::NpyFile::new(bytes).map_err(bad)?;
    let shape: Vec<usize> = file.shape().iter().map(|&n| n as usize).collect();
    let fortran = file.order() == npyz::Order::Fortran;
    let npyz::DType::Plain(ty) = file.dtype() else {
        return Err(TextureError::unsupported(NPY, "structured arrays"));
    };
    let values = match (ty.type_char(), ty.size_field()) {
        (npyz::TypeChar::Float, 8) => file.into_vec::<f64>().map_err(bad)?,
        (npyz::TypeChar::Float, 4) => file
            .into_vec::<f32>()
            .map_err(bad)?
            .into_iter()
            .map(f64::from)
            .collect(),
        _ => {
            return Err(TextureError::unsupported(
                NPY,
                format!("dtype {ty}: height maps are float64 or float32"),
            ));
        }
    };
    Ok((shape, values, fortran))
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use npyz::WriterBuilder;

    fn npy<T: npyz::AutoSerialize + Copy>(shape: &[u64], data: &[T]) -> Vec<u8> {
        let mut bytes = Vec::new();
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .writer(&mut bytes)
            .begin_nd()
            .unwrap();
        w.extend(data.iter().copied()).unwrap();
        w.finish().unwrap();
        bytes
    }

    #[test]
    fn float64_and_float32_maps_read_row_major() {
        let bytes = npy(&[2, 3], &[0.0f64, 1.0, 2.0, 3.0, f64::NAN, 5.0]);
        let map = npy_from_bytes(&bytes, 1e-4, 2e-4).unwrap();
        assert_eq!((map.nx(), map.ny()), (3, 2));
        assert_eq!(map.get(2, 0), Some(2.0));
        assert_eq!(map.get(0, 1), Some(3.0));
        assert_eq!(map.get(1, 1), None);
        assert_eq!(map.dy(), 2e-4);
        let bytes = npy(&[1, 2], &[0.5f32, 1.5]);
        assert_eq!(
            npy_from_bytes(&bytes, 1e-4, 1e-4).unwrap().get(1, 0),
            Some(1.5)
        );
    }

    #[test]
    fn wrong_shapes_types_and_spacings_are_refused() {
        assert!(npy_from_bytes(&npy(&[3], &[0.0f64, 1.0, 2.0]), 1e-4, 1e-4).is_err());
        assert!(npy_from_bytes(&npy(&[1, 2], &[1i32, 2]), 1e-4, 1e-4).is_err());
        assert!(npy_from_bytes(&npy(&[1, 2], &[1.0f64, 2.0]), 0.0, 1e-4).is_err());
        assert!(npy_from_bytes(b"not numpy", 1e-4, 1e-4).is_err());
    }

    #[test]
    fn sidecar_and_npz_give_the_spacing() {
        let dir = std::env::temp_dir().join(format!("tyreroad-npy-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("h.npy");
        std::fs::write(&path, npy(&[2, 2], &[0.0f64, 1.0, 2.0, 3.0])).unwrap();
        assert!(super::super::read_any(&path).is_err(), "no sidecar");
        std::fs::write(dir.join("h.npy.spacing"), "1e-4 2e-4\n").unwrap();
        let map = super::super::read_any(&path).unwrap();
        assert_eq!((map.dx(), map.dy()), (1e-4, 2e-4));

        let npz = dir.join("h.npz");
        let mut zip = zip::ZipWriter::new(std::fs::File::create(&npz).unwrap());
        let opts = zip::write::SimpleFileOptions::default();
        zip.start_file("heights.npy", opts).unwrap();
        std::io::Write::write_all(&mut zip, &npy(&[2, 2], &[0.0f64, 1.0, 2.0, 3.0])).unwrap();
        zip.start_file("spacing.npy", opts).unwrap();
        std::io::Write::write_all(&mut zip, &npy(&[2], &[3e-4f64, 3e-4])).unwrap();
        zip.finish().unwrap();
        let map = super::super::read_any(&npz).unwrap();
        assert_eq!((map.nx(), map.dx()), (2, 3e-4));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
