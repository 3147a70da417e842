//! Windows of large height maps: the columns `i0..i1` (an x-range) of a
//! `.npy` map read without reading the rest of the file, so that a rank of
//! a distributed rolling run (docs/distributed.md) holds only the stretch
//! of road under its part of the path.
//!
//! Which formats support windows: **`.npy`** only (uncompressed, fixed-size
//! elements: the offset of `heights[j, i]` is `header + (j·nx + i)·size` in
//! C order, `header + (i·ny + j)·size` in Fortran order, so a window is one
//! seek and read per row in C order and a single contiguous read in Fortran
//! order). `.npz` and `.x3p` are zip archives (deflated members are read
//! from their start), `.sur`, ASCII grids and `.xyz` have variable or
//! unindexed records: those are read whole ([`super::read_any`]) and cut.
//!
//! Memory: `(i1 − i0)·ny` heights plus one row of file bytes.

use std::fs::File;
use std::io::{Read, Seek, SeekFrom};
use std::ops::Range;
use std::path::Path;

use tyreroad_core::validate;

use super::npy::{header_descr, header_shape, header_value};
use crate::{HeightMap, TextureError};

const NPY: &str = "NumPy";

/// What the header of a `.npy` height map says.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct NpyLayout {
    /// Points along x (the array's second axis).
    pub nx: usize,
    /// Points along y (the array's first axis).
    pub ny: usize,
    /// Bytes per element (8 for float64, 4 for float32).
    pub element: usize,
    /// Big-endian elements.
    pub big_endian: bool,
    /// Column-major (Fortran) order.
    pub fortran: bool,
    /// Bytes before the first element.
    pub data_offset: u64,
}

/// A window of a map: the columns `first_column..first_column + map.nx()`.
#[derive(Clone, Debug, PartialEq)]
pub struct MapWindow {
    /// The window as a map of its own (its point `(0, 0)` is the file's
    /// `(first_column, 0)`, at `x = first_column·dx`).
    pub map: HeightMap,
    /// The file's column of the window's first column.
    pub first_column: usize,
    /// The file's layout.
    pub layout: NpyLayout,
}

/// Reads only the header of a `.npy` height map (a 2-D float64 or float32
/// array, shape `(ny, nx)`).
///
/// # Errors
/// [`TextureError`] for an unreadable file, a header that is not NumPy's, a
/// dtype other than float64/float32 or a shape that is not 2-D.
pub fn npy_layout(path: impl AsRef<Path>) -> Result<NpyLayout, TextureError> {
    let path = path.as_ref();
    tyreroad_core::check_input_file(path).map_err(|e| TextureError::io(path, e))?;
    let mut file = File::open(path).map_err(|e| TextureError::io(path, e))?;
    layout_from(&mut file, path)
}

fn layout_from(file: &mut File, path: &Path) -> Result<NpyLayout, TextureError> {
    let bad = |m: &str| TextureError::format(NPY, format!("{}: {m}", path.display()));
    let mut lead = [0u8; 8];
    file.read_exact(&mut lead)
        .map_err(|_| bad("shorter than a NumPy header"))?;
    if &lead[..6] != b"\x93NUMPY" {
        return Err(bad("no NumPy magic string"));
    }
    let (len, prefix) = if lead[6] == 1 {
        let mut n = [0u8; 2];
        file.read_exact(&mut n)
            .map_err(|_| bad("truncated header"))?;
        (usize::from(u16::from_le_bytes(n)), 10)
    } else {
        let mut n = [0u8; 4];
        file.read_exact(&mut n)
            .map_err(|_| bad("truncated header"))?;
        let n = u32::from_le_bytes(n) as usize;
        if n > 1 << 20 {
            return Err(bad("header longer than 1 MiB"));
        }
        (n, 12)
    };
    let mut header = vec![0u8; len];
    file.read_exact(&mut header)
        .map_err(|_| bad("truncated header"))?;
    let header = String::from_utf8_lossy(&header);
    let descr = header_descr(&header).ok_or_else(|| bad("no descr"))?;
    let (big_endian, element) = match descr {
        "<f8" => (false, 8),
        "<f4" => (false, 4),
        ">f8" => (true, 8),
        ">f4" => (true, 4),
        other => {
            return Err(TextureError::unsupported(
                NPY,
                format!("dtype {other}: height maps are float64 or float32"),
            ));
        }
    };
    let fortran = header_value(&header, "fortran_order")
        .map(|v| v.starts_with("True"))
        .ok_or_else(|| bad("no fortran_order"))?;
    let shape: Vec<usize> = header_shape(&header)
        .ok_or_else(|| bad("no shape"))?
        .map_err(|()| bad("malformed shape"))?;
    let [ny, nx] = shape[..] else {
        return Err(TextureError::format(
            NPY,
            format!("a height map is a 2-D array, this one has shape {shape:?}"),
        ));
    };
    let data_offset = (prefix + len) as u64;
    // A window reads `ny` points per column: the declared shape must be
    // the file's, or a forged header would size the reads (and their
    // buffers) from nothing, and a shape short of the data would read
    // columns of a map that is not the file's.
    let stored = file
        .metadata()
        .map_err(|e| TextureError::io(path, e))?
        .len()
        .saturating_sub(data_offset);
    let needed = (nx as u128)
        .checked_mul(ny as u128)
        .and_then(|n| n.checked_mul(element as u128))
        .unwrap_or(u128::MAX);
    if ny > crate::MAX_POINTS || needed != u128::from(stored) {
        return Err(bad(&format!(
            "declared shape ({ny}, {nx}) needs {needed} bytes of data, the file holds {stored}"
        )));
    }
    Ok(NpyLayout {
        nx,
        ny,
        element,
        big_endian,
        fortran,
        data_offset,
    })
}

/// Reads the columns `columns` (x-indices, clamped to the map) of a `.npy`
/// height map with spacing `dx`, `dy` (m), without reading the others.
///
/// # Errors
/// As [`npy_layout`]; an empty window after clamping, a spacing that is not
/// > 0, or a file shorter than its header says.
pub fn read_npy_window(
    path: impl AsRef<Path>,
    dx: f64,
    dy: f64,
    columns: Range<usize>,
) -> Result<MapWindow, TextureError> {
    validate::positive("dx", dx)?;
    validate::positive("dy", dy)?;
    let path = path.as_ref();
    tyreroad_core::check_input_file(path).map_err(|e| TextureError::io(path, e))?;
    let mut file = File::open(path).map_err(|e| TextureError::io(path, e))?;
    let layout = layout_from(&mut file, path)?;
    let (i0, i1) = (columns.start.min(layout.nx), columns.end.min(layout.nx));
    if i0 >= i1 {
        return Err(TextureError::NotEnoughData(format!(
            "{}: columns {}..{} are outside the map's {} columns",
            path.display(),
            columns.start,
            columns.end,
            layout.nx
        )));
    }
    let (w, ny, size) = (i1 - i0, layout.ny, layout.element);
    let decode = |chunk: &[u8]| -> f64 {
        match (size, layout.big_endian) {
            (8, false) => f64::from_le_bytes(chunk.try_into().unwrap_or([0; 8])),
            (8, true) => f64::from_be_bytes(chunk.try_into().unwrap_or([0; 8])),
            (_, false) => f64::from(f32::from_le_bytes(chunk.try_into().unwrap_or([0; 4]))),
            (_, true) => f64::from(f32::from_be_bytes(chunk.try_into().unwrap_or([0; 4]))),
        }
    };
    let mut read_at = |offset: u64, buf: &mut [u8]| -> Result<(), TextureError> {
        file.seek(SeekFrom::Start(layout.data_offset + offset))
            .and_then(|_| file.read_exact(buf))
            .map_err(|e| TextureError::io(path, e))
    };
    let mut heights = vec![0.0; w * ny];
    if layout.fortran {
        // Columns are contiguous: one read of the window.
        let mut bytes = vec![0u8; w * ny * size];
        read_at((i0 * ny * size) as u64, &mut bytes)?;
        for (c, column) in bytes.chunks_exact(ny * size).enumerate() {
            for (j, v) in column.chunks_exact(size).enumerate() {
                heights[j * w + c] = decode(v);
            }
        }
    } else {
        let mut row = vec![0u8; w * size];
        for j in 0..ny {
            read_at(((j * layout.nx + i0) * size) as u64, &mut row)?;
            for (h, v) in heights[j * w..(j + 1) * w]
                .iter_mut()
                .zip(row.chunks_exact(size))
            {
                *h = decode(v);
            }
        }
    }
    Ok(MapWindow {
        map: HeightMap::from_nan_heights(w, ny, dx, dy, heights)?,
        first_column: i0,
        layout,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use npyz::WriterBuilder;

    fn write_npy<T: npyz::AutoSerialize + Copy>(
        path: &Path,
        shape: &[u64],
        data: &[T],
        order: npyz::Order,
    ) {
        let mut bytes = Vec::new();
        let mut w = npyz::WriteOptions::new()
            .default_dtype()
            .shape(shape)
            .order(order)
            .writer(&mut bytes)
            .begin_nd()
            .unwrap();
        w.extend(data.iter().copied()).unwrap();
        w.finish().unwrap();
        std::fs::write(path, bytes).unwrap();
    }

    /// A header that declares more data than the file holds is refused
    /// when the layout is read, before a window sizes its reads by it (a
    /// forged `(4294967296, 4294967296)` would otherwise ask for exabytes).
    #[test]
    fn a_declared_shape_beyond_the_file_is_refused() {
        let dir = std::env::temp_dir().join(format!("tyreroad-forged-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("forged.npy");
        for (shape, data, refused) in [
            ("(4294967296, 4294967296)", 32, true),
            ("(3, 3)", 64, true),
            ("(3, 3)", 72, false),
            // Data past the declared array (adversarial run: a (100, 100)
            // header over 200 × 200 values): refused as the whole reader
            // refuses it.
            ("(3, 3)", 80, true),
        ] {
            let bytes = crate::io::npy::tests::forged_npy(shape, data);
            std::fs::write(&path, bytes).unwrap();
            let layout = npy_layout(&path);
            assert_eq!(
                layout.is_err(),
                refused,
                "{shape} with {data} bytes: {layout:?}"
            );
            if refused {
                let err = layout.unwrap_err().to_string();
                assert!(err.contains("declared shape"), "{err}");
                assert!(err.contains(&format!("the file holds {data}")), "{err}");
                assert!(read_npy_window(&path, 1e-4, 1e-4, 0..2).is_err());
            }
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    /// Every window of C- and Fortran-ordered float64 and float32 maps is
    /// the same columns of the whole map read by the ordinary reader (an
    /// independent parser, `npyz`); windows past the edge are clamped or
    /// refused.
    #[test]
    fn windows_equal_the_columns_of_the_whole_map() {
        let dir = std::env::temp_dir().join(format!("tyreroad-window-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let (nx, ny) = (13usize, 5usize);
        let values: Vec<f64> = (0..nx * ny)
            .map(|k| {
                if k == 17 {
                    f64::NAN
                } else {
                    (k as f64 * 0.37).sin() * 1e-3
                }
            })
            .collect();
        for order in [npyz::Order::C, npyz::Order::Fortran] {
            let path = dir.join("h.npy");
            // The file holds heights[j, i] = values[j·nx + i] in either order.
            let data: Vec<f64> = match order {
                npyz::Order::C => values.clone(),
                npyz::Order::Fortran => (0..nx * ny)
                    .map(|k| values[(k % ny) * nx + k / ny])
                    .collect(),
            };
            write_npy(&path, &[ny as u64, nx as u64], &data, order);
            let whole = super::super::npy::read_npy(&path, 1e-4, 2e-4).unwrap();
            for (i0, i1) in [(0, nx), (0, 1), (4, 9), (12, 13), (10, 40)] {
                let win = read_npy_window(&path, 1e-4, 2e-4, i0..i1).unwrap();
                assert_eq!(win.first_column, i0);
                assert_eq!((win.map.nx(), win.map.ny()), (i1.min(nx) - i0, ny));
                for j in 0..ny {
                    for i in 0..win.map.nx() {
                        assert_eq!(win.map.get(i, j), whole.get(i0 + i, j), "{i0} {i} {j}");
                    }
                }
            }
            assert!(read_npy_window(&path, 1e-4, 2e-4, 13..20).is_err());
            let path32 = dir.join("h32.npy");
            let data32: Vec<f32> = data.iter().map(|&v| v as f32).collect();
            write_npy(&path32, &[ny as u64, nx as u64], &data32, order);
            let win = read_npy_window(&path32, 1e-4, 1e-4, 3..6).unwrap();
            assert_eq!(
                win.map.get(1, 2),
                Some(f64::from(values[2 * nx + 4] as f32))
            );
        }
        std::fs::write(dir.join("bad.npy"), b"not numpy at all").unwrap();
        assert!(npy_layout(dir.join("bad.npy")).is_err());
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
