//! Digital Surf `.sur` files (read; a minimal writer for tests and export).

use std::path::Path;

use crate::error::{TextureError, write_atomic};
use crate::heightmap::{HeightMap, check_size};

const FMT: &str = "SUR";
const HEADER: usize = 512;

fn unit_factor(unit: &str) -> Result<f64, TextureError> {
    let u = unit.trim_matches(|c: char| c.is_whitespace() || c == '\0');
    Ok(match u {
        "m" => 1.0,
        "dm" => 1e-1,
        "cm" => 1e-2,
        "mm" => 1e-3,
        "\u{b5}m" | "um" | "\u{3bc}m" | "micron" => 1e-6,
        "nm" => 1e-9,
        "pm" => 1e-12,
        "A" | "Å" => 1e-10,
        "" => 1e-6,
        other => {
            return Err(TextureError::unsupported(
                FMT,
                format!("length unit {other:?}"),
            ));
        }
    })
}

fn latin1(b: &[u8]) -> String {
    // µ is 0xB5 in the files' Latin-1 (Windows-1252) encoding.
    b.iter().map(|&c| c as char).collect()
}

/// Read a `.sur` file (see [`sur_from_bytes`]).
pub fn read_sur(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let bytes = std::fs::read(path).map_err(|e| TextureError::io(path, e))?;
    sur_from_bytes(&bytes)
}

/// Read a Digital Surf `.sur` file from its bytes.
///
/// Supported: the classic uncompressed form (signature `DIGITAL SURF`), PC
/// byte order (format 0, little-endian), one object (the first is read) of
/// type surface (2) or profile (1), 16- or 32-bit signed integer points.
/// Header fields used (byte offsets): 98 bits per point (i16), 100 minimum
/// point (i32), 86 non-measured-points flag (i16), 108 points per line `nx`
/// (i32), 112 number of lines `ny` (i32), 120/124/128 spacings x/y/z (f32),
/// 180/196/212 units of the x/y/z steps (16 Latin-1 chars: m, mm, µm, nm,
/// ...), 334/336 comment and private-zone lengths (i16), 474 z offset (f32,
/// in the z step unit). Heights: `z = (raw · spacing_z + offset_z)` in that
/// unit, converted to metres; with the non-measured flag set, `raw =
/// minimum point − 2` marks a missing point. The data start at `512 +
/// comment + private` bytes, x fastest.
///
/// Not supported (a [`TextureError::Unsupported`]): compressed files
/// (`DSCOMPRESSED`), Macintosh byte order, float data, multi-layer or series
/// objects, RGB surfaces.
pub fn sur_from_bytes(b: &[u8]) -> Result<HeightMap, TextureError> {
    if b.len() < HEADER {
        return Err(TextureError::format(
            FMT,
            format!("{} bytes: shorter than the 512-byte header", b.len()),
        ));
    }
    let i16_at = |o: usize| i16::from_le_bytes([b[o], b[o + 1]]);
    let i32_at = |o: usize| i32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]);
    let f32_at = |o: usize| f32::from_le_bytes([b[o], b[o + 1], b[o + 2], b[o + 3]]) as f64;
    match &b[..12] {
        b"DIGITAL SURF" => {}
        b"DSCOMPRESSED" => {
            return Err(TextureError::unsupported(
                FMT,
                "compressed (DSCOMPRESSED) files",
            ));
        }
        _ => return Err(TextureError::format(FMT, "no DIGITAL SURF signature")),
    }
    if i16_at(12) != 0 {
        return Err(TextureError::unsupported(
            FMT,
            format!("format {} (only 0, PC byte order)", i16_at(12)),
        ));
    }
    let studiable = i16_at(18);
    if studiable != 1 && studiable != 2 {
        return Err(TextureError::unsupported(
            FMT,
            format!("object type {studiable} (1 profile and 2 surface are supported)"),
        ));
    }
    let bits = i16_at(98);
    let size = match bits {
        16 => 2,
        32 => 4,
        _ => {
            return Err(TextureError::unsupported(
                FMT,
                format!("{bits} bits per point (16 and 32 are supported)"),
            ));
        }
    };
    let non_measured = i16_at(86) != 0;
    let min_point = i32_at(100) as i64;
    let (nx, ny) = (i32_at(108), i32_at(112));
    if nx <= 0 || ny <= 0 {
        return Err(TextureError::format(FMT, format!("grid {nx} × {ny}")));
    }
    let (nx, ny) = (nx as usize, ny as usize);
    let n = check_size(nx, ny).map_err(|e| TextureError::format(FMT, e.to_string()))?;
    let ux = unit_factor(&latin1(&b[180..196]))?;
    let uy = unit_factor(&latin1(&b[196..212]))?;
    let uz = unit_factor(&latin1(&b[212..228]))?;
    let (sx, sy, sz) = (f32_at(120), f32_at(124), f32_at(128));
    let oz = f32_at(474);
    let (dx, dy) = (sx * ux, if ny == 1 { sx * ux } else { sy * uy });
    if !(dx.is_finite() && dx > 0.0 && dy.is_finite() && dy > 0.0) {
        return Err(TextureError::format(FMT, format!("spacings {sx}, {sy}")));
    }
    if !(sz.is_finite() && oz.is_finite()) {
        return Err(TextureError::format(
            FMT,
            format!("z scale {sz}, offset {oz}"),
        ));
    }
    let comment = i16_at(334).max(0) as usize;
    let private = i16_at(336).max(0) as usize;
    let start = HEADER + comment + private;
    let need = n as u64 * size as u64;
    let avail = b.len().saturating_sub(start) as u64;
    if avail < need {
        return Err(TextureError::format(
            FMT,
            format!("truncated: {nx} × {ny} points of {bits} bits need {need} bytes, {avail} left"),
        ));
    }
    let data = &b[start..start + need as usize];
    let mut h = Vec::with_capacity(n);
    for c in data.chunks_exact(size) {
        let raw = if size == 2 {
            i16::from_le_bytes([c[0], c[1]]) as i64
        } else {
            i32::from_le_bytes([c[0], c[1], c[2], c[3]]) as i64
        };
        h.push(if non_measured && raw == min_point - 2 {
            f64::NAN
        } else {
            (raw as f64 * sz + oz) * uz
        });
    }
    HeightMap::from_nan_heights(nx, ny, dx, dy, h)
        .map_err(|e| TextureError::format(FMT, e.to_string()))
}

/// The bytes of a classic `.sur` file holding `map`: 32-bit points, µm
/// units, f32 spacings (so spacings and the z step are rounded to f32).
pub fn sur_to_bytes(map: &HeightMap) -> Result<Vec<u8>, TextureError> {
    let (lo, hi) = map.min_max().unwrap_or((0.0, 0.0));
    let (lo_um, hi_um) = (lo * 1e6, hi * 1e6);
    let steps = (i32::MAX - 2) as f64;
    let sz = (((hi_um - lo_um) / 2.0 / steps) as f32).max(f32::MIN_POSITIVE);
    let oz = (0.5 * (hi_um + lo_um)) as f32;
    let min_point = -(i32::MAX - 1);
    let mut b = vec![0u8; HEADER];
    let put = |b: &mut Vec<u8>, o: usize, v: &[u8]| b[o..o + v.len()].copy_from_slice(v);
    put(&mut b, 0, b"DIGITAL SURF");
    put(&mut b, 14, &1i16.to_le_bytes());
    put(&mut b, 16, &1i16.to_le_bytes());
    put(&mut b, 18, &2i16.to_le_bytes());
    let any_invalid = map.valid().iter().any(|v| !v);
    put(&mut b, 86, &(any_invalid as i16).to_le_bytes());
    put(&mut b, 98, &32i16.to_le_bytes());
    put(&mut b, 100, &min_point.to_le_bytes());
    put(&mut b, 104, &(i32::MAX - 1).to_le_bytes());
    let (nx, ny) = (
        i32::try_from(map.nx()).map_err(|_| TextureError::unsupported(FMT, "nx > 2³¹"))?,
        i32::try_from(map.ny()).map_err(|_| TextureError::unsupported(FMT, "ny > 2³¹"))?,
    );
    put(&mut b, 108, &nx.to_le_bytes());
    put(&mut b, 112, &ny.to_le_bytes());
    put(&mut b, 116, &nx.wrapping_mul(ny).to_le_bytes());
    put(&mut b, 120, &((map.dx() * 1e6) as f32).to_le_bytes());
    put(&mut b, 124, &((map.dy() * 1e6) as f32).to_le_bytes());
    put(&mut b, 128, &sz.to_le_bytes());
    for o in [180, 196, 212, 228, 244, 260] {
        put(&mut b, o, &[0xB5, b'm']);
    }
    for o in [276, 280, 284] {
        put(&mut b, o, &1f32.to_le_bytes());
    }
    put(&mut b, 474, &oz.to_le_bytes());
    for (h, v) in map.heights().iter().zip(map.valid()) {
        let raw = if *v {
            (((h * 1e6) - oz as f64) / sz as f64).round() as i32
        } else {
            min_point - 2
        };
        b.extend_from_slice(&raw.to_le_bytes());
    }
    Ok(b)
}

/// Write a `.sur` file (whole or not at all; see [`sur_to_bytes`]).
pub fn write_sur(map: &HeightMap, path: impl AsRef<Path>) -> Result<(), TextureError> {
    write_atomic(path.as_ref(), &sur_to_bytes(map)?)
}
