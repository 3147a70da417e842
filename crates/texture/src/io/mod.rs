//! Readers and writers: X3P, ASCII grid, xyz, Digital Surf `.sur`.

pub mod sur;
pub mod text;
pub mod x3p;

use std::path::Path;

use crate::{HeightMap, TextureError};

/// Read a height map, choosing the format by the file extension: `.x3p`,
/// `.sur`, `.xyz`, and anything else as an ASCII grid (`.asc`, `.txt`, ...).
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
        _ => text::read_ascii_grid(path),
    }
}
