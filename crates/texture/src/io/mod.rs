//! Readers and writers: X3P, ASCII grid, xyz, Digital Surf `.sur`, NumPy
//! `.npy`/`.npz` (read only); [`window`]: a window of a large `.npy` map.

pub mod npy;
pub mod sur;
pub mod text;
pub mod window;
pub mod x3p;

use std::path::Path;

use crate::{HeightMap, TextureError};

/// Read a height map, choosing the format by the file extension: `.x3p`,
/// `.sur`, `.xyz`, `.npy` (spacing in a sidecar file) and `.npz`
/// ([`npy`]), and anything else as an ASCII grid (`.asc`, `.txt`, ...).
pub fn read_any(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let ext = path
        .extension()
        .map(|e| e.to_string_lossy().to_ascii_lowercase())
        .unwrap_or_default();
    match ext.as_str() {
        "x3p" => x3p::read_x3p(path),
        "sur" => sur::read_sur(path),
        "xyz" => text::read_xyz(path),
        "npy" => npy::read_npy_with_sidecar(path),
        "npz" => npy::read_npz(path),
        // An image's grey levels carry no height scale or spacing: refused
        // by name rather than read as a malformed ASCII grid.
        "png" | "tif" | "tiff" | "jpg" | "jpeg" | "bmp" | "gif" => Err(TextureError::Unsupported {
            format: "image",
            message: format!(
                "{}: a .{ext} image holds grey levels, not heights in metres with their \
                 spacing; export the height map as .x3p, .sur, .asc, .xyz, .npy (with a \
                 .spacing sidecar) or .npz",
                path.display()
            ),
        }),
        _ => text::read_ascii_grid(path),
    }
}
