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

use crate::{HeightMap, MAX_POINTS, TextureError};

const NPY: &str = "NumPy";

/// Reads a `.npy` height map with grid spacing `dx`, `dy` (m).
///
/// # Errors
/// [`TextureError`] if the file cannot be read, is not a 2-D float array,
/// or the spacing is not finite and > 0.
pub fn read_npy(path: impl AsRef<Path>, dx: f64, dy: f64) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let bytes = tyreroad_core::read_input_file(path).map_err(|e| TextureError::io(path, e))?;
    npy_from_bytes(&bytes, dx, dy)
}

/// Reads a `.npy` height map whose spacing is in the sidecar file
/// `NAME.npy.spacing` (see the module documentation).
///
/// # Errors
/// As [`read_npy`], and a missing or malformed sidecar.
pub fn read_npy_with_sidecar(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    // The array first: a missing `.npy` is named as such, not as its
    // missing sidecar.
    if let Err(e) = std::fs::metadata(path) {
        return Err(TextureError::io(path, e));
    }
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
    let text = tyreroad_core::read_input_text(sidecar).map_err(|e| TextureError::io(sidecar, e))?;
    let values: Vec<f64> = super::text::without_bom(&text)
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
    tyreroad_core::check_input_file(path).map_err(|e| TextureError::io(path, e))?;
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
    // The dtype check speaks of height maps; the spacing is said as itself.
    let spacing = floats(&member("spacing.npy")?)
        .map_err(|e| match e {
            TextureError::Unsupported { message, .. } => TextureError::format(
                NPY,
                format!(
                    "`spacing` in {} must hold [dx, dy] in metres as floats, not {}",
                    path.display(),
                    message.split(':').next().unwrap_or(&message)
                ),
            ),
            other => other,
        })?
        .1;
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
    check_declared_size(bytes)?;
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

/// Refuses a header whose declared shape cannot be this file's array:
/// more points than [`MAX_POINTS`] (or than `u128` counts), more data
/// than the bytes after the header hold, or, for a float array, fewer (the
/// reader would take the declared points and drop the rest silently: a
/// 200 × 200 map under a `(100, 100)` header read as a 100 × 100 one). The
/// reader multiplies the shape out before reading, so a forged header must
/// be caught first. A header this cannot parse is left to the reader's own
/// errors.
fn check_declared_size(bytes: &[u8]) -> Result<(), TextureError> {
    let Some((header, data)) = split_header(bytes) else {
        if bytes.starts_with(b"\x93NUMPY") {
            return Err(TextureError::format(
                NPY,
                format!(
                    "the header runs past the end of the file ({} bytes): the file is cut \
                     short, or its header length is wrong",
                    bytes.len()
                ),
            ));
        }
        return Ok(());
    };
    let Some(Ok(dims)) = header_shape::<u128>(&header) else {
        return Ok(());
    };
    let points = dims
        .iter()
        .try_fold(1u128, |n, &d| n.checked_mul(d))
        .filter(|&n| n <= MAX_POINTS as u128)
        .ok_or_else(|| {
            TextureError::format(
                NPY,
                format!("declared shape {dims:?} exceeds the {MAX_POINTS} points a map may hold"),
            )
        })?;
    // The element size from the descr's digits ('<f8' -> 8); 1 if unknown.
    let descr = header_descr(&header).unwrap_or("");
    let element = descr
        .trim_start_matches(|c: char| !c.is_ascii_digit())
        .parse::<u128>()
        .unwrap_or(1);
    let needed = points * element;
    let held = data.len() as u128;
    // Only a float's size is its descr's digits ('<U8' holds 32 bytes a
    // point), and only floats are read: other dtypes keep their own error.
    let float = descr
        .trim_start_matches(['<', '>', '=', '|'])
        .starts_with('f');
    if held < needed || (float && held > needed) {
        return Err(TextureError::format(
            NPY,
            format!(
                "declared shape {dims:?} ({points} points, {needed} bytes) but the file holds {held} \
                 bytes of data{}",
                if held > needed {
                    ": a wrong shape in the header, or data appended after the array"
                } else {
                    ""
                }
            ),
        ));
    }
    Ok(())
}

/// The text after `'key':` in a `.npy` header's dictionary.
pub(super) fn header_value<'h>(header: &'h str, key: &str) -> Option<&'h str> {
    let at = header.find(&format!("'{key}':"))? + key.len() + 3;
    Some(header[at..].trim_start())
}

/// The header's `descr` string (`<f8`, …).
pub(super) fn header_descr(header: &str) -> Option<&str> {
    header_value(header, "descr")
        .and_then(|v| v.strip_prefix('\''))
        .and_then(|v| v.split('\'').next())
}

/// The header's `shape` tuple: `None` when there is none, `Some(Err(()))`
/// when a dimension does not parse as `T`.
pub(super) fn header_shape<T: std::str::FromStr>(header: &str) -> Option<Result<Vec<T>, ()>> {
    let tuple = header_value(header, "shape")
        .and_then(|v| v.strip_prefix('('))
        .and_then(|v| v.split(')').next())?;
    Some(
        tuple
            .split(',')
            .map(str::trim)
            .filter(|d| !d.is_empty())
            .map(|d| d.parse::<T>().map_err(|_| ()))
            .collect(),
    )
}

/// The header text and the data bytes of a `.npy` file, or `None` when it
/// does not start like one.
fn split_header(bytes: &[u8]) -> Option<(String, &[u8])> {
    let (len, prefix) = match bytes.get(..12)? {
        [0x93, b'N', b'U', b'M', b'P', b'Y', 1, _, a, b, ..] => {
            (usize::from(u16::from_le_bytes([*a, *b])), 10usize)
        }
        [0x93, b'N', b'U', b'M', b'P', b'Y', _, _, a, b, c, d] => {
            (u32::from_le_bytes([*a, *b, *c, *d]) as usize, 12)
        }
        _ => return None,
    };
    let end = len.checked_add(prefix)?;
    let header = bytes.get(prefix..end)?;
    Some((String::from_utf8_lossy(header).into_owned(), &bytes[end..]))
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
pub(crate) mod tests {
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

    /// A float64 `.npy` whose header declares `shape` (a tuple's text)
    /// over `data` zero bytes, whatever they hold.
    pub(crate) fn forged_npy(shape: &str, data: usize) -> Vec<u8> {
        let dict = format!("{{'descr': '<f8', 'fortran_order': False, 'shape': {shape}, }}");
        let pad = (64 - (10 + dict.len() + 1) % 64) % 64;
        let header = format!("{dict}{}\n", " ".repeat(pad));
        let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
        bytes.extend_from_slice(&(header.len() as u16).to_le_bytes());
        bytes.extend_from_slice(header.as_bytes());
        bytes.extend_from_slice(&vec![0u8; data]);
        bytes
    }

    /// A header may declare any shape: one whose point count overflows
    /// `usize`, exceeds [`MAX_POINTS`] or needs more data than the file
    /// holds is refused before anything is allocated (it once panicked on
    /// the multiplication).
    #[test]
    fn a_declared_shape_beyond_the_data_is_refused() {
        let huge = forged_npy("(4294967296, 4294967296)", 32);
        let err = npy_from_bytes(&huge, 1e-4, 1e-4).unwrap_err().to_string();
        assert!(err.contains("4294967296"), "{err}");
        let short = forged_npy("(3, 3)", 32);
        let err = npy_from_bytes(&short, 1e-4, 1e-4).unwrap_err().to_string();
        assert!(err.contains("9 points"), "{err}");
        assert!(npy_from_bytes(&forged_npy("(3, 3)", 72), 1e-4, 1e-4).is_ok());
    }

    /// Regression (adversarial run): a `(100, 100)` header over 200 × 200
    /// float64 values was read as the first 100 × 100 of them. Data past
    /// the declared array is refused, naming both byte counts; a float32
    /// array's size is its own.
    #[test]
    fn data_longer_than_the_header_declares_is_refused() {
        let long = forged_npy("(100, 100)", 200 * 200 * 8);
        let err = npy_from_bytes(&long, 1e-4, 1e-4).unwrap_err();
        assert!(matches!(
            err,
            TextureError::Format {
                format: "NumPy",
                ..
            }
        ));
        assert_eq!(
            err.to_string(),
            "malformed NumPy data: declared shape [100, 100] (10000 points, 80000 bytes) but \
             the file holds 320000 bytes of data: a wrong shape in the header, or data \
             appended after the array"
        );
        // One byte past the array is enough.
        let err = npy_from_bytes(&forged_npy("(3, 3)", 73), 1e-4, 1e-4).unwrap_err();
        assert!(
            err.to_string().contains("72 bytes) but the file holds 73"),
            "{err}"
        );
        let f4 = npy(&[2, 2], &[0.5f32, 1.5, 2.5, 3.5]);
        assert!(npy_from_bytes(&f4, 1e-4, 1e-4).is_ok());
        let mut f4_long = f4;
        f4_long.extend_from_slice(&[0u8; 4]);
        let err = npy_from_bytes(&f4_long, 1e-4, 1e-4).unwrap_err();
        assert!(
            err.to_string().contains("16 bytes) but the file holds 20"),
            "{err}"
        );
    }

    /// Regression (second adversarial run): a header length past the end
    /// of the file said only "failed to fill whole buffer".
    #[test]
    fn a_header_longer_than_its_file_is_said_to_be_cut_short() {
        let mut bytes = forged_npy("(3, 3)", 72);
        bytes[8..10].copy_from_slice(&60000u16.to_le_bytes());
        let err = npy_from_bytes(&bytes, 1e-4, 1e-4).unwrap_err().to_string();
        assert!(
            err.contains("header runs past the end of the file"),
            "{err}"
        );
        let err = npy_from_bytes(&bytes[..9], 1e-4, 1e-4)
            .unwrap_err()
            .to_string();
        assert!(err.contains("cut short"), "{err}");
    }

    /// NaN marks a missing point (the documented convention); an infinite
    /// height is no height at all and is refused, as X3P and the text
    /// formats refuse it.
    #[test]
    fn infinite_heights_are_refused_not_dropped() {
        let err = npy_from_bytes(&npy(&[1, 2], &[0.0f64, f64::INFINITY]), 1e-4, 1e-4)
            .unwrap_err()
            .to_string();
        assert!(err.contains("infinite"), "{err}");
        assert!(npy_from_bytes(&npy(&[1, 2], &[0.0f64, f64::NAN]), 1e-4, 1e-4).is_ok());
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

        // Regression (second adversarial run): an int64 spacing was
        // refused as "height maps are float64 or float32".
        let int_spacing = dir.join("i.npz");
        let mut zip = zip::ZipWriter::new(std::fs::File::create(&int_spacing).unwrap());
        zip.start_file("heights.npy", opts).unwrap();
        std::io::Write::write_all(&mut zip, &npy(&[2, 2], &[0.0f64, 1.0, 2.0, 3.0])).unwrap();
        zip.start_file("spacing.npy", opts).unwrap();
        std::io::Write::write_all(&mut zip, &npy(&[2], &[1i64, 1])).unwrap();
        zip.finish().unwrap();
        let err = super::super::read_any(&int_spacing)
            .unwrap_err()
            .to_string();
        assert!(
            err.contains("`spacing`") && err.contains("dtype <i8"),
            "{err}"
        );
        assert!(!err.contains("height maps"), "{err}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
