//! Readers and writers: X3P, ASCII grid, xyz, Digital Surf `.sur`, NumPy
//! `.npy`/`.npz` (read only); [`window`]: a window of a large `.npy` map.

pub mod npy;
pub mod sur;
pub mod text;
pub mod window;
pub mod x3p;

use std::path::Path;

use crate::{HeightMap, TextureError};

/// The extensions [`read_any`] reads as ASCII grids by name; any other
/// unknown one is tried as an ASCII grid too, and a failure then says so.
const ASCII_GRID_EXTENSIONS: [&str; 3] = ["asc", "txt", ""];

/// Read a height map, choosing the format by the file extension: `.x3p`,
/// `.sur`, `.xyz`, `.npy` (spacing in a sidecar file) and `.npz`
/// ([`npy`]), and anything else as an ASCII grid (`.asc`, `.txt`, none,
/// ...). Images are refused by name. A file of another extension that is
/// not a valid ASCII grid is refused with a [`TextureError::Format`] saying
/// it was read as one because its extension is none of the known ones.
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
        e if ASCII_GRID_EXTENSIONS.contains(&e) => text::read_ascii_grid(path),
        // "malformed ASCII grid data" alone would leave the user of a
        // `.foo` file wondering why it was taken for one.
        _ => text::read_ascii_grid(path).map_err(|err| match err {
            TextureError::Format { format, message } => TextureError::Format {
                format,
                message: format!(
                    "{}: read as an ASCII grid because its extension .{ext} is none of the \
                     known ones (.x3p, .sur, .xyz, .npy, .npz, .asc, .txt): {message}",
                    path.display()
                ),
            },
            other => other,
        }),
    }
}
