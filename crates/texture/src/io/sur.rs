//! Digital Surf `.sur` files (read; a minimal writer for tests and export).

use std::io::{Read, Write};
use std::path::Path;

use crate::error::{TextureError, write_atomic};
use crate::heightmap::{HeightMap, check_size};

const FMT: &str = "SUR";
const HEADER: usize = 512;
/// Header offset of the size of a compressed file's data block (u32).
const COMPRESSED_SIZE_AT: usize = 324;
/// zlib cannot inflate more than 1032 bytes per compressed byte (the
/// longest match, 258 bytes, coded in two bits at best); a stream that
/// announces more is refused before anything is inflated.
const MAX_INFLATE_RATIO: u64 = 1032;

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
    let bytes = tyreroad_core::read_input_file(path).map_err(|e| TextureError::io(path, e))?;
    sur_from_bytes(&bytes)
}

/// Read a Digital Surf `.sur` file from its bytes.
///
/// Supported: the classic uncompressed form (signature `DIGITAL SURF`) and
/// the compressed form (signature `DSCOMPRESSED`), PC
/// byte order (format 0, little-endian), one object (the first is read) of
/// type surface (2) or profile (1), 16- or 32-bit signed integer points.
/// Header fields used (byte offsets): 14 number of objects (i16), 98 bits
/// per point (i16), 100/104 minimum/maximum point (i32, must fit the bit
/// depth), 86 non-measured-points flag (i16), 108 points per line `nx`
/// (i32), 112 number of lines `ny` (i32), 120/124/128 spacings x/y/z (f32),
/// 180/196/212 units of the x/y/z steps (16 Latin-1 chars: m, mm, µm, nm,
/// ...), 334/336 comment and private-zone lengths (i16), 474 z offset (f32,
/// in the z step unit). Heights: `z = (raw · spacing_z + offset_z)` in that
/// unit, converted to metres; with the non-measured flag set, `raw =
/// minimum point − 2` marks a missing point. The data start at `512 +
/// comment + private` bytes, x fastest.
///
/// Compressed files have the same header; their data block is a directory,
/// a u32 stream count `m ≥ 1` then `m` pairs of u32 (inflated size,
/// compressed size), followed by the `m` zlib streams, whose inflated bytes,
/// concatenated, are the points of the classic form. (Header offset 324,
/// u32, holds the size of that block; it is not needed to read it.) Every
/// size is checked before use: the directory and the streams must lie in
/// the file, the inflated sizes must add up to the `nx·ny` points the
/// header announces, no stream may announce more than zlib's maximum ratio
/// (1032) times its compressed size, and each stream is inflated with a
/// limit of its announced size, which it must fill exactly. A decompression
/// bomb thus costs at most the memory of the announced surface, and only
/// once that much compressed data is present.
///
/// Refused with a named error: a classic file whose points do not end the
/// file (or, with several objects, are not followed by the next object's
/// signature) — the header's grid or bit depth disagrees with the data — and
/// a height that overflows to infinity (its index, column and row).
///
/// Not supported (a [`TextureError::Unsupported`]): Macintosh byte order,
/// float data, multi-layer or series objects, RGB surfaces.
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
    let compressed = match &b[..12] {
        b"DIGITAL SURF" => false,
        b"DSCOMPRESSED" => true,
        _ => {
            return Err(TextureError::format(
                FMT,
                "no DIGITAL SURF or DSCOMPRESSED signature",
            ));
        }
    };
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
    let (lo, hi) = if size == 2 {
        (i16::MIN as i64, i16::MAX as i64)
    } else {
        (i32::MIN as i64, i32::MAX as i64)
    };
    let max_point = i32_at(104) as i64;
    if non_measured && !(lo..=hi).contains(&min_point) || !(lo..=hi).contains(&max_point) {
        return Err(TextureError::format(
            FMT,
            format!(
                "minimum/maximum points {min_point}/{max_point} (bytes 100/104) do not fit the \
                 header's {bits} bits per point (byte 98): the bit depth is wrong"
            ),
        ));
    }
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
    let inflated;
    let data = if compressed {
        inflated = inflate_points(b.get(start..).unwrap_or_default(), need)?;
        &inflated[..]
    } else {
        let avail = b.len().saturating_sub(start) as u64;
        if avail < need {
            return Err(TextureError::format(
                FMT,
                format!(
                    "truncated: {nx} × {ny} points of {bits} bits need {need} bytes, {avail} left \
                     after byte {start}"
                ),
            ));
        }
        // A single-object file ends with its points, and in a multi-object
        // file the next object's header follows them: anything else means the
        // header's grid or bit depth does not describe the data (read as is,
        // they would give a sheared or rescaled surface).
        let objects = i16_at(14);
        let next = start + need as usize;
        let next_object = objects > 1 && b.get(next..next + 12) == Some(b"DIGITAL SURF");
        if avail > need && !next_object {
            let other = if bits == 16 { 32 } else { 16 };
            let hint = if avail * bits as u64 == need * other as u64 {
                format!(" (the data fit {other} bits per point: the bit depth is wrong)")
            } else {
                String::new()
            };
            return Err(TextureError::format(
                FMT,
                format!(
                    "the header's {nx} × {ny} points of {bits} bits take {need} bytes from byte \
                     {start}, the file holds {avail}{hint}"
                ),
            ));
        }
        &b[start..start + need as usize]
    };
    let mut h = Vec::with_capacity(n);
    for c in data.chunks_exact(size) {
        let raw = if size == 2 {
            i16::from_le_bytes([c[0], c[1]]) as i64
        } else {
            i32::from_le_bytes([c[0], c[1], c[2], c[3]]) as i64
        };
        let z = (raw as f64 * sz + oz) * uz;
        if non_measured && raw == min_point - 2 {
            h.push(f64::NAN);
        } else if z.is_finite() {
            h.push(z);
        } else {
            let k = h.len();
            return Err(TextureError::format(
                FMT,
                format!(
                    "point {k} (column {}, row {}) is {z}: the z scale {sz} and offset {oz} \
                     overflow",
                    k % nx,
                    k / nx
                ),
            ));
        }
    }
    HeightMap::from_nan_heights(nx, ny, dx, dy, h)
        .map_err(|e| TextureError::format(FMT, e.to_string()))
}

/// The points of a compressed file's data block `block` (directory, then
/// zlib streams), `need` bytes once inflated; see [`sur_from_bytes`].
fn inflate_points(block: &[u8], need: u64) -> Result<Vec<u8>, TextureError> {
    let u32_at = |o: usize| -> Result<u64, TextureError> {
        block
            .get(o..o + 4)
            .map(|v| u32::from_le_bytes([v[0], v[1], v[2], v[3]]) as u64)
            .ok_or_else(|| TextureError::format(FMT, "truncated stream directory"))
    };
    let count = u32_at(0)?;
    let dir_end = 4 + 8 * count;
    if count == 0 || dir_end > block.len() as u64 {
        return Err(TextureError::format(
            FMT,
            format!(
                "{count} compressed streams (need ≥ 1, directory within {} data bytes)",
                block.len()
            ),
        ));
    }
    let mut streams = Vec::with_capacity(count as usize);
    let (mut at, mut total) = (dir_end, 0u64);
    for k in 0..count as usize {
        let (raw, zip) = (u32_at(4 + 8 * k)?, u32_at(8 + 8 * k)?);
        if at + zip > block.len() as u64 {
            return Err(TextureError::format(
                FMT,
                format!("truncated: stream {k} of {zip} bytes ends past the file"),
            ));
        }
        if raw > MAX_INFLATE_RATIO * zip + 64 {
            return Err(TextureError::format(
                FMT,
                format!("stream {k} announces {raw} bytes from {zip} compressed ones"),
            ));
        }
        total += raw;
        streams.push((at as usize, zip as usize, raw));
        at += zip;
    }
    if total != need {
        return Err(TextureError::format(
            FMT,
            format!("the streams inflate to {total} bytes, the header's points take {need}"),
        ));
    }
    // Grown as inflated, never sized from the header alone.
    let mut out = Vec::new();
    for (k, &(at, zip, raw)) in streams.iter().enumerate() {
        let before = out.len() as u64;
        flate2::read::ZlibDecoder::new(&block[at..at + zip])
            .take(raw + 1)
            .read_to_end(&mut out)
            .map_err(|e| TextureError::format(FMT, format!("stream {k}: {e}")))?;
        let got = out.len() as u64 - before;
        if got > raw {
            return Err(TextureError::format(
                FMT,
                format!("stream {k} inflates to more than the {raw} bytes announced"),
            ));
        }
        if got < raw {
            return Err(TextureError::format(
                FMT,
                format!("stream {k} inflates to {got} bytes, {raw} announced"),
            ));
        }
    }
    Ok(out)
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

/// The bytes of a compressed (`DSCOMPRESSED`) `.sur` file holding `map`:
/// the header and points of [`sur_to_bytes`], the points split into
/// `streams` runs of whole points (the last one shorter), each compressed
/// into its own zlib stream.
///
/// Refused with [`TextureError::InvalidParameter`]: `streams` of 0 or more
/// than the number of points.
pub fn sur_to_bytes_compressed(map: &HeightMap, streams: usize) -> Result<Vec<u8>, TextureError> {
    let n = map.nx() * map.ny();
    if streams == 0 || streams > n {
        return Err(TextureError::InvalidParameter {
            name: "SUR compressed streams",
            value: streams as f64,
            requirement: "between 1 and the number of points",
        });
    }
    let classic = sur_to_bytes(map)?;
    let (header, points) = classic.split_at(HEADER);
    let per = n.div_ceil(streams) * 4;
    let mut dir = (streams as u32).to_le_bytes().to_vec();
    let mut body = Vec::new();
    for run in points.chunks(per) {
        let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
        let zip = z
            .write_all(run)
            .and_then(|()| z.finish())
            .map_err(|e| TextureError::format(FMT, format!("compressing: {e}")))?;
        dir.extend_from_slice(&(run.len() as u32).to_le_bytes());
        dir.extend_from_slice(&(zip.len() as u32).to_le_bytes());
        body.extend_from_slice(&zip);
    }
    // `chunks` gives fewer runs than asked when the last ones would be empty
    // (e.g. 5 points in 4 streams: runs of 2, 2, 1): write the true count.
    let count = (dir.len() - 4) / 8;
    dir[..4].copy_from_slice(&(count as u32).to_le_bytes());
    let block = dir.len() + body.len();
    let mut b = header.to_vec();
    b[..12].copy_from_slice(b"DSCOMPRESSED");
    let block = u32::try_from(block)
        .map_err(|_| TextureError::unsupported(FMT, "compressed data over 4 GiB"))?;
    b[COMPRESSED_SIZE_AT..COMPRESSED_SIZE_AT + 4].copy_from_slice(&block.to_le_bytes());
    b.extend_from_slice(&dir);
    b.extend_from_slice(&body);
    Ok(b)
}

/// Write a `.sur` file (whole or not at all; see [`sur_to_bytes`]).
pub fn write_sur(map: &HeightMap, path: impl AsRef<Path>) -> Result<(), TextureError> {
    write_atomic(path.as_ref(), &sur_to_bytes(map)?)
}

/// Write a compressed `.sur` file (whole or not at all; see
/// [`sur_to_bytes_compressed`]).
pub fn write_sur_compressed(
    map: &HeightMap,
    path: impl AsRef<Path>,
    streams: usize,
) -> Result<(), TextureError> {
    write_atomic(path.as_ref(), &sur_to_bytes_compressed(map, streams)?)
}
