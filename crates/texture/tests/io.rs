//! Readers and writers: round trips, checksums, truncation, fuzzing.
#![allow(clippy::unwrap_used)]

use std::io::{Cursor, Read, Write};

use proptest::prelude::*;
use tyreroad_texture::io::npy::npy_from_bytes;
use tyreroad_texture::io::sur::{
    read_sur, sur_from_bytes, sur_to_bytes, sur_to_bytes_compressed, write_sur_compressed,
};
use tyreroad_texture::io::text::{
    ascii_grid_from_str, ascii_grid_to_string, xyz_from_str, xyz_to_string,
};
use tyreroad_texture::io::x3p::{X3pDataType, x3p_from_bytes, x3p_to_bytes};
use tyreroad_texture::{HeightMap, TextureError};

/// A 13 × 7 map with heights ±0.8 mm and two missing points.
fn sample() -> HeightMap {
    let (nx, ny) = (13, 7);
    let mut h: Vec<f64> = (0..nx * ny)
        .map(|k| 0.8e-3 * ((k as f64 * 0.37).sin()) + 1e-5 * (k % 5) as f64)
        .collect();
    h[5] = f64::NAN;
    h[40] = f64::NAN;
    HeightMap::from_nan_heights(nx, ny, 1.5e-4, 2.5e-4, h).unwrap()
}

fn max_diff(a: &HeightMap, b: &HeightMap) -> f64 {
    assert_eq!((a.nx(), a.ny()), (b.nx(), b.ny()));
    assert_eq!(a.valid(), b.valid());
    a.heights()
        .iter()
        .zip(b.heights())
        .filter(|(x, _)| x.is_finite())
        .map(|(x, y)| (x - y).abs())
        .fold(0.0, f64::max)
}

#[test]
fn x3p_round_trip_all_types() {
    let map = sample();
    let range = 1.6e-3 + 4e-5;
    for (t, tol) in [
        (X3pDataType::I16, range / 65532.0),
        (X3pDataType::I32, range / 4.29e9 + 1e-18),
        (X3pDataType::F32, 1e-3 * 6e-8),
        (X3pDataType::F64, 0.0),
    ] {
        let bytes = x3p_to_bytes(&map, t).unwrap();
        let back = x3p_from_bytes(&bytes).unwrap();
        assert_eq!(back.dx(), map.dx());
        assert_eq!(back.dy(), map.dy());
        let d = max_diff(&map, &back);
        assert!(d <= tol, "{t:?}: max error {d:e} > {tol:e}");
    }
}

#[test]
fn x3p_file_round_trip_and_read_any() {
    let dir = std::env::temp_dir().join(format!("tyreroad-texture-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("s.x3p");
    let map = sample();
    tyreroad_texture::io::x3p::write_x3p(&map, &path, X3pDataType::F64).unwrap();
    let back = tyreroad_texture::read_any(&path).unwrap();
    assert_eq!(max_diff(&map, &back), 0.0);
    let leftovers: Vec<_> = std::fs::read_dir(&dir).unwrap().collect();
    assert_eq!(leftovers.len(), 1, "no temporary file is left behind");
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Rebuild an X3P zip with one entry changed.
fn replace_entry(bytes: &[u8], name: &str, f: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    let mut zin = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
    let mut w = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let opts =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    for k in 0..zin.len() {
        let mut e = zin.by_index(k).unwrap();
        let n = e.name().unwrap().to_string();
        let mut buf = Vec::new();
        e.read_to_end(&mut buf).unwrap();
        if n == name {
            f(&mut buf);
        }
        w.start_file(n, opts).unwrap();
        w.write_all(&buf).unwrap();
    }
    w.finish().unwrap().into_inner()
}

#[test]
fn x3p_md5_mismatch_is_detected() {
    let bytes = x3p_to_bytes(&sample(), X3pDataType::F64).unwrap();
    // Untouched but re-zipped: still fine.
    assert!(x3p_from_bytes(&replace_entry(&bytes, "none", |_| ())).is_ok());
    let bad = replace_entry(&bytes, "bindata/data.bin", |b| b[17] ^= 0x40);
    match x3p_from_bytes(&bad) {
        Err(TextureError::Checksum { what, .. }) => assert_eq!(what, "bindata/data.bin"),
        other => panic!("expected a checksum error, got {other:?}"),
    }
    let bad = replace_entry(&bytes, "bindata/valid.bin", |b| b[0] ^= 1);
    assert!(matches!(
        x3p_from_bytes(&bad),
        Err(TextureError::Checksum { .. })
    ));
    let bad = replace_entry(&bytes, "main.xml", |b| {
        let s = String::from_utf8(b.clone())
            .unwrap()
            .replace("tyreroad-texture</Creator>", "someone else</Creator>");
        *b = s.into_bytes();
    });
    match x3p_from_bytes(&bad) {
        Err(TextureError::Checksum { what, .. }) => assert_eq!(what, "main.xml"),
        other => panic!("expected a checksum error, got {other:?}"),
    }
}

#[test]
fn x3p_validity_buffer_marks_missing_points_for_integer_types() {
    let map = sample();
    let back = x3p_from_bytes(&x3p_to_bytes(&map, X3pDataType::I16).unwrap()).unwrap();
    assert_eq!(back.valid_count(), map.nx() * map.ny() - 2);
    assert!(back.get(5, 0).is_none() && back.get(1, 3).is_none());
}

#[test]
fn truncated_files_give_errors() {
    let map = sample();
    let x3p = x3p_to_bytes(&map, X3pDataType::F32).unwrap();
    for cut in [
        0,
        1,
        10,
        22,
        x3p.len() / 3,
        x3p.len() / 2,
        x3p.len() - 23,
        x3p.len() - 1,
    ] {
        assert!(x3p_from_bytes(&x3p[..cut]).is_err(), "X3P cut at {cut}");
    }
    let sur = sur_to_bytes(&map).unwrap();
    for cut in [0, 100, 511, 512, sur.len() - 1] {
        assert!(sur_from_bytes(&sur[..cut]).is_err(), "SUR cut at {cut}");
    }
    let sur = sur_to_bytes_compressed(&map, 3).unwrap();
    // In the header, the stream count, a directory entry, a stream.
    for cut in [511, 512, 515, 520, 530, sur.len() - 30, sur.len() - 1] {
        assert!(
            sur_from_bytes(&sur[..cut]).is_err(),
            "compressed SUR cut at {cut}"
        );
    }
    let txt = ascii_grid_to_string(&map);
    // (A cut inside the last number of a text file cannot be seen.)
    for cut in [txt.len() / 2, txt.len() - 60] {
        assert!(
            ascii_grid_from_str(&txt[..cut]).is_err(),
            "ASCII cut at {cut}"
        );
    }
}

#[test]
fn sur_round_trip() {
    let map = sample();
    let back = sur_from_bytes(&sur_to_bytes(&map).unwrap()).unwrap();
    assert!((back.dx() / map.dx() - 1.0).abs() < 1e-7);
    let d = max_diff(&map, &back);
    assert!(d < 1e-9, "max error {d:e}"); // f32 offset and step, i32 points
}

/// Heights (bit for bit, NaN for missing points), mask and spacings equal.
fn assert_same(a: &HeightMap, b: &HeightMap) {
    assert_eq!(
        (a.nx(), a.ny(), a.dx(), a.dy()),
        (b.nx(), b.ny(), b.dx(), b.dy())
    );
    assert_eq!(a.valid(), b.valid());
    let bits = |m: &HeightMap| m.heights().iter().map(|h| h.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(a), bits(b));
}

#[test]
fn compressed_sur_reads_as_the_uncompressed_file() {
    let map = sample(); // 91 points: no stream count below divides it evenly
    let classic = sur_from_bytes(&sur_to_bytes(&map).unwrap()).unwrap();
    for streams in [1, 2, 3, 7, 8, 90, 91] {
        let bytes = sur_to_bytes_compressed(&map, streams).unwrap();
        assert_eq!(&bytes[..12], b"DSCOMPRESSED");
        // Offset 324: the size of the data block behind the header.
        let block = u32::from_le_bytes(bytes[324..328].try_into().unwrap()) as usize;
        assert_eq!(block, bytes.len() - 512, "{streams} streams");
        // Stream count: runs of ⌈91/s⌉ points (90 streams give 46 runs of 2
        // and none empty).
        let count = u32::from_le_bytes(bytes[512..516].try_into().unwrap()) as usize;
        assert_eq!(count, 91usize.div_ceil(91usize.div_ceil(streams)));
        assert_same(&sur_from_bytes(&bytes).unwrap(), &classic);
    }
    // A constant surface compresses well, and still reads back.
    let flat = HeightMap::from_fn(300, 200, 1e-4, 1e-4, |_, _| 1e-3).unwrap();
    let bytes = sur_to_bytes_compressed(&flat, 4).unwrap();
    assert!(bytes.len() < 512 + 300 * 200, "{}", bytes.len());
    assert_same(
        &sur_from_bytes(&bytes).unwrap(),
        &sur_from_bytes(&sur_to_bytes(&flat).unwrap()).unwrap(),
    );
    // Through a file, and `read_any` by the extension.
    let path = std::path::Path::new(env!("CARGO_TARGET_TMPDIR")).join("sample_compressed.sur");
    write_sur_compressed(&map, &path, 2).unwrap();
    assert_same(&read_sur(&path).unwrap(), &classic);
    assert_same(&tyreroad_texture::read_any(&path).unwrap(), &classic);
    assert!(sur_to_bytes_compressed(&map, 0).is_err());
    assert!(sur_to_bytes_compressed(&map, 92).is_err());
}

/// A compressed file of `sample()`'s header (13 × 7 points of 32 bits)
/// with the given data block.
fn compressed_with_block(block: &[u8]) -> Vec<u8> {
    let mut b = sur_to_bytes_compressed(&sample(), 1).unwrap()[..512].to_vec();
    b.extend_from_slice(block);
    b
}

fn zlib(data: &[u8]) -> Vec<u8> {
    let mut z = flate2::write::ZlibEncoder::new(Vec::new(), flate2::Compression::default());
    z.write_all(data).unwrap();
    z.finish().unwrap()
}

fn block(streams: &[(u32, &[u8])]) -> Vec<u8> {
    let mut b = (streams.len() as u32).to_le_bytes().to_vec();
    for (raw, zip) in streams {
        b.extend_from_slice(&raw.to_le_bytes());
        b.extend_from_slice(&(zip.len() as u32).to_le_bytes());
    }
    for (_, zip) in streams {
        b.extend_from_slice(zip);
    }
    b
}

fn sur_error(bytes: &[u8]) -> String {
    match sur_from_bytes(bytes) {
        Err(e @ TextureError::Format { .. }) => e.to_string(),
        other => panic!("expected a format error, got {other:?}"),
    }
}

#[test]
fn compressed_sur_sizes_are_checked_before_inflating() {
    let need = 13 * 7 * 4;
    let points = vec![7u8; need];
    // The well-formed block reads.
    assert!(
        sur_from_bytes(&compressed_with_block(&block(&[(
            need as u32,
            &zlib(&points)
        )])))
        .is_ok()
    );
    // A bomb: 1 MB of zeros announced as the 364 bytes the header asks for.
    // Inflation stops one byte past the announced size.
    let bomb = zlib(&vec![0u8; 1 << 20]);
    let e = sur_error(&compressed_with_block(&block(&[(need as u32, &bomb)])));
    assert!(e.contains("more than the 364 bytes"), "{e}");
    // A stream announcing more than zlib can give: refused unread.
    let tiny = zlib(&[0u8; 4]);
    let e = sur_error(&compressed_with_block(&block(&[(u32::MAX, &tiny)])));
    assert!(e.contains("announces"), "{e}");
    // Sizes that do not add up to the header's points.
    let half = zlib(&points[..need / 2]);
    let e = sur_error(&compressed_with_block(&block(&[(need as u32 / 2, &half)])));
    assert!(e.contains("take 364"), "{e}");
    // A stream shorter than announced, a corrupt stream.
    let e = sur_error(&compressed_with_block(&block(&[
        (need as u32 / 2, &half),
        (need as u32 / 2, &zlib(&points[..10])),
    ])));
    assert!(e.contains("inflates to 10 bytes"), "{e}");
    let mut bad = zlib(&points);
    bad[5] ^= 0xFF;
    bad[6] ^= 0xFF;
    assert!(sur_from_bytes(&compressed_with_block(&block(&[(need as u32, &bad)]))).is_err());
    // Directories: no stream, a count past the file, a stream past the file.
    assert!(
        sur_error(&compressed_with_block(&0u32.to_le_bytes())).contains("0 compressed streams")
    );
    assert!(
        sur_error(&compressed_with_block(&u32::MAX.to_le_bytes())).contains("compressed streams")
    );
    let mut past = block(&[(need as u32, &zlib(&points))]);
    past.truncate(past.len() - 1);
    assert!(sur_error(&compressed_with_block(&past)).contains("ends past the file"));
    // A header announcing 2³⁰ points behind 30 compressed bytes: refused by
    // the ratio check, nothing allocated for them.
    let mut huge = compressed_with_block(&block(&[(u32::MAX, &tiny)]));
    huge[108..112].copy_from_slice(&32768i32.to_le_bytes());
    huge[112..116].copy_from_slice(&32768i32.to_le_bytes());
    assert!(sur_from_bytes(&huge).is_err());
}

#[test]
fn ascii_and_xyz_round_trips() {
    let map = sample();
    let back = ascii_grid_from_str(&ascii_grid_to_string(&map)).unwrap();
    assert_eq!(max_diff(&map, &back), 0.0);
    assert_eq!((back.dx(), back.dy()), (map.dx(), map.dy()));
    let back = xyz_from_str(&xyz_to_string(&map)).unwrap();
    assert!(max_diff(&map, &back) == 0.0);
    assert!((back.dx() / map.dx() - 1.0).abs() < 1e-12);
    let text =
        "# demo\nnx 3\nny 2\ndx 0.1\ndy 0.2\nz_scale 1e-3\nxy_scale 1e-3\ndata\n1 2 3\n4 * nan\n";
    let m = ascii_grid_from_str(text).unwrap();
    assert_eq!((m.nx(), m.ny(), m.valid_count()), (3, 2, 4));
    assert!((m.dx() - 1e-4).abs() < 1e-18 && (m.get(2, 0).unwrap() - 3e-3).abs() < 1e-18);
}

#[test]
fn shipped_fixtures_read() {
    let dir = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../fixtures/texture");
    for name in ["spheres.x3p", "sine.asc"] {
        let p = dir.join(name);
        if p.exists() {
            let m = tyreroad_texture::read_any(&p).unwrap();
            assert!(m.valid_count() > 0, "{name}");
        }
    }
}

/// A valid 3 × 4 float64 `.npy` file (format 1.0), written by hand.
fn npy_sample() -> Vec<u8> {
    let mut header = "{'descr': '<f8', 'fortran_order': False, 'shape': (3, 4), }".to_string();
    while !(10 + header.len() + 1).is_multiple_of(16) {
        header.push(' ');
    }
    header.push('\n');
    let mut b = b"\x93NUMPY\x01\x00".to_vec();
    b.extend_from_slice(&(header.len() as u16).to_le_bytes());
    b.extend_from_slice(header.as_bytes());
    for k in 0..12 {
        b.extend_from_slice(&(f64::from(k) * 1e-4).to_le_bytes());
    }
    b
}

#[test]
fn hand_written_npy_reads_back() {
    let map = npy_from_bytes(&npy_sample(), 1e-4, 2e-4).unwrap();
    assert_eq!((map.nx(), map.ny()), (4, 3));
    assert!((map.dy() - 2e-4).abs() < 1e-18);
    assert!((map.heights()[11] - 11e-4).abs() < 1e-15);
}

/// Runs every reader on `bytes`: none may panic, and a map any of them
/// accepts has a finite height at every valid point (a non-finite value is
/// a named error or a missing point, never a valid one).
fn readers(bytes: &[u8]) {
    let s = String::from_utf8_lossy(bytes);
    for (reader, map) in [
        ("x3p", x3p_from_bytes(bytes)),
        ("sur", sur_from_bytes(bytes)),
        ("npy", npy_from_bytes(bytes, 1e-4, 1e-4)),
        ("ascii", ascii_grid_from_str(&s)),
        ("xyz", xyz_from_str(&s)),
    ] {
        if let Ok(map) = map {
            let bad = map
                .heights()
                .iter()
                .zip(map.valid())
                .position(|(h, v)| *v && !h.is_finite());
            assert_eq!(bad, None, "{reader}: a valid point is not finite");
            assert!(map.dx().is_finite() && map.dx() > 0.0, "{reader}: dx");
            assert!(map.dy().is_finite() && map.dy() > 0.0, "{reader}: dy");
        }
    }
}

proptest! {
    #![proptest_config(ProptestConfig { cases: 300, .. ProptestConfig::default() })]

    #[test]
    fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..2048)) {
        readers(&bytes);
    }

    #[test]
    fn mutated_files_never_panic(
        t in 0usize..4,
        cut in 0.0f64..1.0,
        flips in proptest::collection::vec((0.0f64..1.0, any::<u8>()), 0..6),
    ) {
        let map = sample();
        let ty = [X3pDataType::I16, X3pDataType::I32, X3pDataType::F32, X3pDataType::F64][t];
        for mut b in [
            x3p_to_bytes(&map, ty).unwrap(),
            replace_entry(&x3p_to_bytes(&map, ty).unwrap(), "none", |_| ()),
            sur_to_bytes(&map).unwrap(),
            sur_to_bytes_compressed(&map, 1 + t).unwrap(),
            ascii_grid_to_string(&map).into_bytes(),
            xyz_to_string(&map).into_bytes(),
            npy_sample(),
        ] {
            for (pos, v) in &flips {
                let k = ((pos * b.len() as f64) as usize).min(b.len() - 1);
                b[k] ^= v;
            }
            readers(&b);
            let n = (cut * b.len() as f64) as usize;
            readers(&b[..n]);
        }
    }

    #[test]
    fn mutated_sur_headers_never_panic(
        compressed in any::<bool>(),
        fields in proptest::collection::vec((0usize..512, any::<u8>()), 1..12),
    ) {
        let mut b = if compressed {
            sur_to_bytes_compressed(&sample(), 2).unwrap()
        } else {
            sur_to_bytes(&sample()).unwrap()
        };
        for (k, v) in fields {
            b[k] = v;
        }
        readers(&b);
    }

    #[test]
    fn arbitrary_compressed_data_never_panics(
        data in proptest::collection::vec(any::<u8>(), 0..1024),
        directory in proptest::collection::vec((0u32..2000, 0u32..2000), 0..4),
    ) {
        // Random bytes behind a valid header, and behind a plausible
        // directory (small sizes, so that the streams are reached).
        let _ = sur_from_bytes(&compressed_with_block(&data));
        let mut b = (directory.len() as u32).to_le_bytes().to_vec();
        for (raw, zip) in &directory {
            b.extend_from_slice(&raw.to_le_bytes());
            b.extend_from_slice(&zip.to_le_bytes());
        }
        b.extend_from_slice(&data);
        let _ = sur_from_bytes(&compressed_with_block(&b));
    }
}

/// An ASCII grid header that gives a key twice, or a zero or negative
/// scale, is refused (the last `nx` once won silently, and `z_scale 0`
/// flattened the map); an xyz file whose points share one (x, y) is no map
/// (it once became a 1 × 1 map at an invented 1 m spacing).
#[test]
fn ambiguous_text_headers_and_single_point_xyz_are_refused() {
    let grid = |header: &str| format!("{header}\ndata\n1 2\n3 4\n");
    let good = "nx 2\nny 2\ndx 1e-4\ndy 1e-4";
    assert!(ascii_grid_from_str(&grid(good)).is_ok());
    for (header, says) in [
        ("nx 2\nnx 2\nny 2\ndx 1e-4\ndy 1e-4", "given twice"),
        ("nx 2\nny 2\ndx 1e-4\ndy 1e-4\nz_scale 0", "z_scale"),
        ("nx 2\nny 2\ndx 1e-4\ndy 1e-4\nxy_scale -1", "xy_scale"),
    ] {
        let err = ascii_grid_from_str(&grid(header)).unwrap_err().to_string();
        assert!(err.contains(says), "{header}: {err}");
    }
    let err = xyz_from_str("0 0 1e-4\n").unwrap_err().to_string();
    assert!(err.contains("at least two grid points"), "{err}");
    assert!(xyz_from_str("0 0 1e-4\n1e-4 0 2e-4\n").is_ok());
}

/// Regression (adversarial run of the Python bindings, 2026-11-30): a PNG
/// height image was read as an ASCII grid ("malformed ASCII grid data: not
/// UTF-8 text") while the bindings' docs promised images. An image is
/// refused by name, saying which formats hold heights.
#[test]
fn an_image_file_is_refused_as_an_image_not_read_as_a_grid() {
    let dir = std::env::temp_dir().join(format!("tyreroad-texture-image-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    for ext in ["png", "TIF", "jpeg"] {
        let path = dir.join(format!("road.{ext}"));
        std::fs::write(&path, b"\x89PNG\r\n\x1a\n not a height map").unwrap();
        match tyreroad_texture::read_any(&path) {
            Err(e @ TextureError::Unsupported { .. }) => {
                let message = e.to_string();
                assert!(
                    message.contains("image") && message.contains(".x3p"),
                    "{message}"
                );
            }
            other => panic!("{ext}: {other:?}"),
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Regression (adversarial run of the texture comparison, 2026-11-30): a
/// missing `.npy` was reported as its missing `.npy.spacing` sidecar.
#[test]
fn a_missing_npy_is_named_not_its_sidecar() {
    let path = std::env::temp_dir().join(format!("tyreroad-no-such-{}.npy", std::process::id()));
    let message = tyreroad_texture::read_any(&path).unwrap_err().to_string();
    assert!(
        message.contains(&path.display().to_string()) && !message.contains(".spacing"),
        "{message}"
    );
}

/// Regression (adversarial run of the texture comparison, 2026-11-30): an
/// `.xyz` whose points sit 3 µm off a 0.1 mm grid was refused as "grid
/// 55682656 × 65038223 exceeds 1073741824 points". It is refused as points
/// off a regular grid; the same points on the grid are read.
#[test]
fn xyz_points_off_a_regular_grid_are_said_to_be_off_it() {
    let mut on = String::new();
    let mut off = String::new();
    for j in 0..20 {
        for i in 0..20 {
            let (x, y) = (i as f64 * 1e-4, j as f64 * 1e-4);
            let jitter = if (i + j) % 2 == 0 { 3e-6 } else { 0.0 };
            on.push_str(&format!("{x} {y} 0\n"));
            off.push_str(&format!("{} {} 0\n", x + jitter, y + jitter));
        }
    }
    let map = tyreroad_texture::io::text::xyz_from_str(&on).unwrap();
    assert_eq!((map.nx(), map.ny()), (20, 20));
    let message = tyreroad_texture::io::text::xyz_from_str(&off)
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("off a regular grid") && !message.contains("exceeds"),
        "{message}"
    );
}

/// Found by an adversarial run (2026-12-01): points in georeferenced
/// coordinates (x ≈ 412 345 m, y ≈ 5 612 345 m) at 0.1 mm were refused as
/// "every point is at one (x, y)": the gap tolerance was 1e-9 of the
/// coordinates' size, 0.4 mm there. It is now their rounding (a few ulps).
#[test]
fn georeferenced_xyz_points_keep_their_sub_millimetre_grid() {
    for step in [1e-4, 5e-4] {
        let mut text = String::new();
        for j in 0..40 {
            for i in 0..30 {
                let z = 1e-4 * ((i * 7 + j * 3) % 11) as f64;
                text.push_str(&format!(
                    "{:.4} {:.4} {z:e}\n",
                    412_345.0 + i as f64 * step,
                    5_612_345.0 + j as f64 * step
                ));
            }
        }
        let map = xyz_from_str(&text).unwrap();
        assert_eq!((map.nx(), map.ny()), (30, 40), "step {step}");
        assert!(
            (map.dx() / step - 1.0).abs() < 1e-6,
            "{} for {step}",
            map.dx()
        );
        assert!(
            (map.dy() / step - 1.0).abs() < 1e-6,
            "{} for {step}",
            map.dy()
        );
        let z = map.get(3, 5).unwrap();
        assert!(
            (z - 1e-4 * ((3 * 7 + 5 * 3) % 11) as f64).abs() < 1e-15,
            "{z}"
        );
    }
}
