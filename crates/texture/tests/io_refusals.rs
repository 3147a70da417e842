//! Readers refuse, with a named error, files whose numbers cannot be
//! heights or whose header disagrees with the data (issue #14: such files
//! used to be read anyway, as holes, sheared or rescaled surfaces).
#![allow(clippy::unwrap_used)]

use std::io::{Cursor, Read, Write};

use tyreroad_texture::HeightMap;
use tyreroad_texture::io::sur::{sur_from_bytes, sur_to_bytes};
use tyreroad_texture::io::x3p::{X3pDataType, x3p_from_bytes, x3p_to_bytes};

/// A 6 × 4 map of smooth heights (±0.5 mm), every point valid.
fn map() -> HeightMap {
    let h = (0..24).map(|k| 5e-4 * (k as f64 * 0.7).sin()).collect();
    HeightMap::from_nan_heights(6, 4, 1e-4, 1e-4, h).unwrap()
}

/// Rebuild an X3P zip: `edit` may change an entry and returns whether to
/// keep it.
fn rebuild(bytes: &[u8], edit: impl Fn(&str, &mut Vec<u8>) -> bool) -> Vec<u8> {
    let mut zin = zip::ZipArchive::new(Cursor::new(bytes)).unwrap();
    let mut w = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let opts =
        zip::write::SimpleFileOptions::default().compression_method(zip::CompressionMethod::Stored);
    for k in 0..zin.len() {
        let mut e = zin.by_index(k).unwrap();
        let name = e.name().unwrap().to_string();
        let mut buf = Vec::new();
        e.read_to_end(&mut buf).unwrap();
        if edit(&name, &mut buf) {
            w.start_file(name, opts).unwrap();
            w.write_all(&buf).unwrap();
        }
    }
    w.finish().unwrap().into_inner()
}

/// Edits main.xml with `f` and drops the checksums the edit invalidates, so
/// that the reader reaches the check under test.
fn edit_x3p(bytes: &[u8], f: impl Fn(String) -> String, data: impl Fn(&mut Vec<u8>)) -> Vec<u8> {
    rebuild(bytes, |name, buf| match name {
        "md5_checksum.hex" => false,
        "main.xml" => {
            let xml = String::from_utf8(buf.clone()).unwrap();
            let start = xml.find("<MD5ChecksumPointData>");
            let xml = match start {
                Some(s) => {
                    let end = xml[s..].find("</MD5ChecksumPointData>").unwrap() + s;
                    format!("{}{}", &xml[..s], &xml[end + 23..])
                }
                None => xml,
            };
            *buf = f(xml).into_bytes();
            true
        }
        "bindata/data.bin" => {
            data(buf);
            true
        }
        _ => true,
    })
}

#[test]
fn x3p_with_infinite_heights_is_refused_naming_the_point() {
    let bytes = x3p_to_bytes(&map(), X3pDataType::F64).unwrap();
    // Unedited but without checksums it still reads: the refusals below are
    // the infinities', not the rebuild's.
    assert!(x3p_from_bytes(&edit_x3p(&bytes, |x| x, |_| ())).is_ok());
    for (k, v) in [(9usize, f64::INFINITY), (23, f64::NEG_INFINITY)] {
        let bad = edit_x3p(
            &bytes,
            |x| x,
            |d| d[8 * k..8 * k + 8].copy_from_slice(&v.to_le_bytes()),
        );
        let e = x3p_from_bytes(&bad).unwrap_err().to_string();
        assert!(
            e.contains(&format!("point {k} (column {}, row {}", k % 6, k / 6)),
            "{e}"
        );
        assert!(
            e.contains(&format!("byte {}", 8 * k)) && e.contains("inf"),
            "{e}"
        );
    }
    let bytes = x3p_to_bytes(&map(), X3pDataType::F32).unwrap();
    let bad = edit_x3p(
        &bytes,
        |x| x,
        |d| d[4..8].copy_from_slice(&f32::INFINITY.to_le_bytes()),
    );
    let e = x3p_from_bytes(&bad).unwrap_err().to_string();
    assert!(
        e.contains("point 1 (column 1, row 0, byte 4) is inf"),
        "{e}"
    );
}

#[test]
fn x3p_whose_data_type_disagrees_with_its_bytes_is_refused() {
    let bytes = x3p_to_bytes(&map(), X3pDataType::F64).unwrap();
    let xml = {
        let mut z = zip::ZipArchive::new(Cursor::new(&bytes[..])).unwrap();
        let mut s = String::new();
        z.by_name("main.xml")
            .unwrap()
            .read_to_string(&mut s)
            .unwrap();
        s
    };
    assert!(xml.contains("<DataType>D</DataType>"), "{xml}");
    // 24 doubles declared as floats: twice the bytes type F needs.
    let bad = edit_x3p(
        &bytes,
        |x| x.replace("<DataType>D</DataType>", "<DataType>F</DataType>"),
        |_| (),
    );
    let e = x3p_from_bytes(&bad).unwrap_err().to_string();
    assert!(
        e.contains("holds 192 bytes") && e.contains("declared type F need 96"),
        "{e}"
    );
    assert!(e.contains("fit type D"), "{e}");
    // A byte count no type fits: the matrix size or the data is wrong.
    let bad = edit_x3p(&bytes, |x| x, |d| d.truncate(100));
    let e = x3p_from_bytes(&bad).unwrap_err().to_string();
    assert!(
        e.contains("holds 100 bytes") && e.contains("matrix size or the data"),
        "{e}"
    );
}

#[test]
fn sur_whose_header_disagrees_with_its_data_is_refused() {
    let good = sur_to_bytes(&map()).unwrap();
    assert!(sur_from_bytes(&good).is_ok());
    // Surplus bytes after the single object's points: the grid is wrong.
    let mut bad = good.clone();
    bad.extend_from_slice(&[0; 40]);
    let e = sur_from_bytes(&bad).unwrap_err().to_string();
    assert!(
        e.contains("6 × 4 points of 32 bits take 96 bytes from byte 512, the file holds 136"),
        "{e}"
    );
    // The header says 16 bits (min/max points set to fit) over 32-bit data:
    // the data are twice what 16 bits take.
    let mut bad = good.clone();
    bad[98..100].copy_from_slice(&16i16.to_le_bytes());
    bad[100..104].copy_from_slice(&(-32767i32).to_le_bytes());
    bad[104..108].copy_from_slice(&32767i32.to_le_bytes());
    let e = sur_from_bytes(&bad).unwrap_err().to_string();
    assert!(
        e.contains("fit 32 bits per point: the bit depth is wrong"),
        "{e}"
    );
    // 16 bits with 32-bit minimum/maximum points: the bit depth is wrong.
    let mut bad = good.clone();
    bad[98..100].copy_from_slice(&16i16.to_le_bytes());
    let e = sur_from_bytes(&bad).unwrap_err().to_string();
    assert!(
        e.contains("do not fit the header's 16 bits per point"),
        "{e}"
    );
    // A second object's header after the points is not surplus data.
    let mut two = good.clone();
    two[14..16].copy_from_slice(&2i16.to_le_bytes());
    two.extend_from_slice(&good);
    assert!(sur_from_bytes(&two).is_ok());
}

/// A z increment of 0 read every height as the offset (a flat map, "no
/// asperity" further on) without a word; a negative one reads the map
/// upside down. Both are refused, naming the increment.
#[test]
fn x3p_with_a_zero_or_negative_z_increment_is_refused() {
    let bytes = x3p_to_bytes(&map(), X3pDataType::I16).unwrap();
    let with_increment = |value: &'static str| {
        move |xml: String| {
            let cz = xml.find("<CZ>").unwrap();
            let start = xml[cz..].find("<Increment>").unwrap() + cz + "<Increment>".len();
            let end = xml[start..].find("</Increment>").unwrap() + start;
            format!("{}{value}{}", &xml[..start], &xml[end..])
        }
    };
    assert!(x3p_from_bytes(&edit_x3p(&bytes, with_increment("1e-6"), |_| ())).is_ok());
    for value in ["0", "-1e-6", "0e0"] {
        let bad = edit_x3p(&bytes, with_increment(value), |_| ());
        let e = x3p_from_bytes(&bad).unwrap_err().to_string();
        assert!(
            e.contains("CZ Increment") && e.contains("> 0"),
            "{value}: {e}"
        );
    }
}

/// Regression (adversarial run, 2026-11-29): an X3P whose `MatrixDimension`
/// held two `SizeX` was read with the first, whatever the second said.
/// A second copy of any element the reader takes is refused, naming it.
#[test]
fn x3p_with_an_element_given_twice_is_refused_naming_it() {
    let bytes = x3p_to_bytes(&map(), X3pDataType::I16).unwrap();
    let twice = |tag: &'static str| {
        move |xml: String| {
            let start = xml.find(&format!("<{tag}>")).unwrap();
            let end = xml[start..].find(&format!("</{tag}>")).unwrap() + start + tag.len() + 3;
            let element = xml[start..end].to_string();
            format!("{}{element}{}", &xml[..end], &xml[end..])
        }
    };
    for tag in ["SizeX", "Increment", "DataLink", "MatrixDimension"] {
        let bad = edit_x3p(&bytes, twice(tag), |_| ());
        let e = x3p_from_bytes(&bad).unwrap_err().to_string();
        assert!(e.contains(&format!("{tag} twice")), "{tag}: {e}");
    }
}

/// Regression (adversarial run, 2026-11-29): a text map saved with a UTF-8
/// byte-order mark was refused as 'unknown header key "\u{feff}#"'. The
/// mark is not data: the map reads as without it.
#[test]
fn text_maps_with_a_byte_order_mark_read_as_without_it() {
    use tyreroad_texture::io::text::{
        ascii_grid_from_str, ascii_grid_to_string, xyz_from_str, xyz_to_string,
    };
    let m = map();
    let grid = ascii_grid_to_string(&m);
    let plain = ascii_grid_from_str(&grid).unwrap();
    assert_eq!(
        ascii_grid_from_str(&format!("\u{feff}{grid}")).unwrap(),
        plain
    );
    let xyz = xyz_to_string(&m);
    let plain = xyz_from_str(&xyz).unwrap();
    assert_eq!(xyz_from_str(&format!("\u{feff}{xyz}")).unwrap(), plain);
}

/// Regression (adversarial run, 2026-11-29): a grid whose `data` line was
/// missing was refused as 'unknown header key "1.93e-06"'.
#[test]
fn a_grid_without_its_data_line_says_so() {
    use tyreroad_texture::io::text::{ascii_grid_from_str, ascii_grid_to_string};
    let grid = ascii_grid_to_string(&map()).replacen("data\n", "", 1);
    let e = ascii_grid_from_str(&grid).unwrap_err().to_string();
    assert!(e.contains("`data` line") && e.contains("missing"), "{e}");
}

/// Regression (adversarial run, adv6 U8): a `.foo` file was refused as
/// "malformed ASCII grid data: …", not saying why it was read as one. The
/// fallback stays (documented: unknown extensions are ASCII grids), and the
/// refusal names the extension and the known formats; a valid grid under
/// any extension is still read.
#[test]
fn a_file_of_unknown_extension_is_said_to_be_read_as_an_ascii_grid() {
    let dir = std::env::temp_dir().join(format!("tyreroad-texture-ext-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("road.foo");
    std::fs::write(&path, "1 2 3").unwrap();
    match tyreroad_texture::read_any(&path) {
        Err(e @ tyreroad_texture::TextureError::Format { .. }) => {
            let m = e.to_string();
            assert!(
                m.contains("read as an ASCII grid") && m.contains(".foo") && m.contains(".x3p"),
                "{m}"
            );
        }
        other => panic!("{other:?}"),
    }
    // Known extensions keep their own message.
    let asc = dir.join("road.asc");
    std::fs::write(&asc, "1 2 3").unwrap();
    let m = tyreroad_texture::read_any(&asc).unwrap_err().to_string();
    assert!(!m.contains("because its extension"), "{m}");
    let good = dir.join("road.dat");
    let text = tyreroad_texture::io::text::ascii_grid_to_string(&map());
    std::fs::write(&good, text).unwrap();
    let back = tyreroad_texture::read_any(&good).unwrap();
    assert_eq!((back.nx(), back.ny()), (6, 4));
    std::fs::remove_dir_all(&dir).unwrap();
}

/// An ASCII grid of `nx × ny` (declared) with `rows` data lines as given.
fn grid_text(header: &str, rows: &[Vec<f64>]) -> String {
    let mut s = format!("{header}\ndata\n");
    for r in rows {
        let line: Vec<String> = r.iter().map(|v| format!("{v:e}")).collect();
        s.push_str(&line.join(" "));
        s.push('\n');
    }
    s
}

/// Found by an adversarial run (2026-12-01): each of these was read as a
/// valid map, a thousand times too wide or scrambled, and solved.
#[test]
fn a_header_unit_and_rows_of_the_wrong_length_are_refused() {
    use tyreroad_texture::io::text::ascii_grid_from_str;
    let rows = |nx: usize, ny: usize| -> Vec<Vec<f64>> {
        (0..ny)
            .map(|j| (0..nx).map(|i| 1e-4 * ((i * 3 + j) % 7) as f64).collect())
            .collect()
    };
    // "dx 0.5 mm": the unit was dropped and the spacing read as 0.5 m.
    let e = ascii_grid_from_str(&grid_text("nx 4\nny 3\ndx 0.5 mm\ndy 0.0005", &rows(4, 3)))
        .unwrap_err()
        .to_string();
    assert!(e.contains("header dx") && e.contains("\"mm\""), "{e}");
    // 20 lines of 80 values under `nx 20`, `ny 80` (swapped).
    let e = ascii_grid_from_str(&grid_text("nx 20\nny 80\ndx 1e-4\ndy 1e-4", &rows(80, 20)))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("80 values but nx = 20") && e.contains("swapped"),
        "{e}"
    );
    // One value too many on line 3's row, one missing on a later row:
    // every row between shifted by one.
    let mut ragged = rows(5, 6);
    ragged[1].push(1e-4);
    ragged[4].pop();
    let e = ascii_grid_from_str(&grid_text("nx 5\nny 6\ndx 1e-4\ndy 1e-4", &ragged))
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("line 7 holds 6 values") && e.contains("nx = 5"),
        "{e}"
    );
    // Still read: rows of nx, and rows wrapped over lines of fewer values.
    let ok = ascii_grid_from_str(&grid_text("nx 6\nny 4\ndx 1e-4\ndy 1e-4", &rows(6, 4))).unwrap();
    let wrapped: Vec<Vec<f64>> = rows(6, 4).concat().chunks(4).map(<[f64]>::to_vec).collect();
    let back = ascii_grid_from_str(&grid_text("nx 6\nny 4\ndx 1e-4\ndy 1e-4", &wrapped)).unwrap();
    assert_eq!(ok, back);
}

/// Found by an adversarial run (2026-12-01): a grid whose lines end with
/// CR alone (classic Mac OS text) was one line, refused as "no `data` line
/// ends the header". It reads as the same grid with LF or CRLF; an xyz
/// file likewise.
#[test]
fn lines_ended_by_cr_alone_are_lines() {
    use tyreroad_texture::io::text::{ascii_grid_from_str, xyz_from_str, xyz_to_string};
    let lf = grid_text(
        "nx 5\nny 3\ndx 1e-4\ndy 2e-4",
        &[vec![1e-4; 5], vec![2e-4; 5], vec![3e-4; 5]],
    );
    let map = ascii_grid_from_str(&lf).unwrap();
    assert_eq!((map.nx(), map.ny(), map.heights()[10]), (5, 3, 3e-4));
    for ending in ["\r", "\r\n"] {
        assert_eq!(ascii_grid_from_str(&lf.replace('\n', ending)).unwrap(), map);
        let xyz = xyz_to_string(&map).replace('\n', ending);
        assert_eq!(xyz_from_str(&xyz).unwrap(), map);
    }
}

/// Found by an adversarial run (2026-12-01): a FIFO named as the texture
/// blocked the run forever, `/dev/zero` read until memory ran out.
#[test]
fn a_pipe_or_a_device_named_as_a_texture_is_refused_not_waited_on() {
    use tyreroad_texture::io::read_any;
    if std::path::Path::new("/dev/zero").exists() {
        let e = read_any("/dev/zero").unwrap_err().to_string();
        assert!(
            e.contains("/dev/zero") && e.contains("not a regular file"),
            "{e}"
        );
    }
    let dir = std::env::temp_dir().join(format!("tyreroad-fifo-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let fifo = dir.join("road.asc");
    let made = std::process::Command::new("mkfifo")
        .arg(&fifo)
        .status()
        .is_ok_and(|s| s.success());
    if made {
        let e = read_any(&fifo).unwrap_err().to_string();
        assert!(e.contains("not a regular file"), "{e}");
    }
    let e = read_any(&dir).unwrap_err().to_string();
    assert!(e.contains("a directory"), "{e}");
    std::fs::remove_dir_all(&dir).unwrap();
}
