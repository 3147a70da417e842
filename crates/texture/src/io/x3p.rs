//! ISO 25178-72 (ISO 5436-2) X3P files: a zip holding `main.xml` and the
//! binary point data.

use std::io::{Cursor, Read, Write};
use std::path::Path;

use md5::{Digest, Md5};

use crate::error::{TextureError, write_atomic};
use crate::heightmap::{HeightMap, check_size};

const FMT: &str = "X3P";
/// Longest `main.xml` read (bytes).
const MAX_XML: u64 = 16 << 20;

/// The data type of the z axis of an X3P file (`CZ/DataType`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum X3pDataType {
    /// `I`: 16-bit signed integer, scaled by the axis increment and offset.
    I16,
    /// `L`: 32-bit signed integer, scaled by the axis increment and offset.
    I32,
    /// `F`: 32-bit IEEE float (NaN = invalid point).
    F32,
    /// `D`: 64-bit IEEE float (NaN = invalid point).
    F64,
}

impl X3pDataType {
    /// The one-letter code of ISO 5436-2 (`I`, `L`, `F`, `D`).
    pub fn code(self) -> &'static str {
        match self {
            Self::I16 => "I",
            Self::I32 => "L",
            Self::F32 => "F",
            Self::F64 => "D",
        }
    }
    /// Bytes per point.
    pub fn size(self) -> usize {
        match self {
            Self::I16 => 2,
            Self::I32 | Self::F32 => 4,
            Self::F64 => 8,
        }
    }
    fn from_code(code: &str) -> Result<Self, TextureError> {
        match code.trim() {
            "I" => Ok(Self::I16),
            "L" => Ok(Self::I32),
            "F" => Ok(Self::F32),
            "D" => Ok(Self::F64),
            other => Err(TextureError::format(
                FMT,
                format!("unknown z data type {other:?} (expected I, L, F or D)"),
            )),
        }
    }
}

/// Read an X3P file.
pub fn read_x3p(path: impl AsRef<Path>) -> Result<HeightMap, TextureError> {
    let path = path.as_ref();
    let bytes = tyreroad_core::read_input_file(path).map_err(|e| TextureError::io(path, e))?;
    x3p_from_bytes(&bytes)
}

/// Write an X3P file (whole or not at all: a temporary file, then a rename).
pub fn write_x3p(
    map: &HeightMap,
    path: impl AsRef<Path>,
    data_type: X3pDataType,
) -> Result<(), TextureError> {
    let bytes = x3p_to_bytes(map, data_type)?;
    write_atomic(path.as_ref(), &bytes)
}

fn hex(digest: &[u8]) -> String {
    digest.iter().map(|b| format!("{b:02x}")).collect()
}

/// MD5 of `bytes` as 32 lowercase hex digits.
pub(crate) fn md5_hex(bytes: &[u8]) -> String {
    hex(&Md5::digest(bytes))
}

fn read_entry<R: Read + std::io::Seek>(
    zip: &mut zip::ZipArchive<R>,
    name: &str,
    limit: u64,
) -> Result<Option<Vec<u8>>, TextureError> {
    let mut file = match zip.by_name(name) {
        Ok(f) => f,
        Err(zip::result::ZipError::FileNotFound) => return Ok(None),
        Err(e) => return Err(TextureError::format(FMT, format!("entry {name}: {e}"))),
    };
    let mut out = Vec::new();
    (&mut file)
        .take(limit + 1)
        .read_to_end(&mut out)
        .map_err(|e| TextureError::format(FMT, format!("entry {name}: {e}")))?;
    if out.len() as u64 > limit {
        return Err(TextureError::format(
            FMT,
            format!("entry {name} is larger than the {limit} bytes expected"),
        ));
    }
    Ok(Some(out))
}

/// The element `name` under `node`, if any. Every element this reader
/// takes is single-valued: a second one (two `SizeX`, say) is refused
/// rather than the first silently used.
fn child<'a, 'i>(
    node: roxmltree::Node<'a, 'i>,
    name: &str,
) -> Result<Option<roxmltree::Node<'a, 'i>>, TextureError> {
    let mut found = node
        .children()
        .filter(|c| c.is_element() && c.tag_name().name() == name);
    let first = found.next();
    if found.next().is_some() {
        return Err(TextureError::format(
            FMT,
            format!(
                "main.xml has {name} twice under {}: which one is meant?",
                node.tag_name().name()
            ),
        ));
    }
    Ok(first)
}

fn need<'a, 'i>(
    node: roxmltree::Node<'a, 'i>,
    path: &[&str],
) -> Result<roxmltree::Node<'a, 'i>, TextureError> {
    let mut n = node;
    for p in path {
        n = child(n, p)?.ok_or_else(|| {
            TextureError::format(FMT, format!("main.xml has no element {}", path.join("/")))
        })?;
    }
    Ok(n)
}

fn text<'a>(node: roxmltree::Node<'a, '_>) -> &'a str {
    node.text().unwrap_or("").trim()
}

fn number(node: roxmltree::Node<'_, '_>, what: &str) -> Result<f64, TextureError> {
    let t = text(node);
    t.parse::<f64>()
        .ok()
        .filter(|v| v.is_finite())
        .ok_or_else(|| TextureError::format(FMT, format!("{what} is {t:?}, not a finite number")))
}

fn size(node: roxmltree::Node<'_, '_>, what: &str) -> Result<usize, TextureError> {
    let t = text(node);
    t.parse::<usize>()
        .map_err(|_| TextureError::format(FMT, format!("{what} is {t:?}, not a size")))
}

struct Axis {
    axis_type: String,
    increment: f64,
    offset: f64,
}

fn axis(axes: roxmltree::Node<'_, '_>, name: &str) -> Result<Axis, TextureError> {
    let a = need(axes, &[name])?;
    let axis_type = child(a, "AxisType")?.map(text).unwrap_or("").to_string();
    let increment = match child(a, "Increment")? {
        Some(n) => number(n, &format!("{name}/Increment"))?,
        None => 1.0,
    };
    let offset = match child(a, "Offset")? {
        Some(n) => number(n, &format!("{name}/Offset"))?,
        None => 0.0,
    };
    Ok(Axis {
        axis_type,
        increment,
        offset,
    })
}

fn check_md5(what: &str, stored: &str, content: &[u8]) -> Result<(), TextureError> {
    let computed = md5_hex(content);
    let stored = stored.trim().to_ascii_lowercase();
    if stored != computed {
        return Err(TextureError::Checksum {
            what: what.to_string(),
            stored,
            computed,
        });
    }
    Ok(())
}

/// Read an X3P file from its bytes.
///
/// Supported: feature types `SUR` and `PRF` stored as a matrix
/// (`MatrixDimension`, `SizeZ = 1`) with incremental x and y axes
/// (`AxisType I`) and binary point data (`DataLink/PointDataLink`) of type
/// `I`, `L`, `F` or `D`, little-endian, x fastest. Heights are
/// `z = CZ/Offset + CZ/Increment · raw` (increment 1 and offset 0 when
/// absent), in metres. Invalid points: NaN (types `F`, `D`) and the
/// `ValidPointsLink` bit array when present (bit `k % 8` of byte `k / 8`,
/// least significant first, 1 = valid). Checked: the MD5 of the point data
/// (`MD5ChecksumPointData`), of the validity buffer
/// (`MD5ChecksumValidPoints`), and of `main.xml` against
/// `md5_checksum.hex`, each when present. Refused with a named error: an
/// infinite height (its index, column, row and byte offset), and point data
/// whose byte count disagrees with the matrix size times the declared type's
/// width (saying which type the bytes would fit).
///
/// Not supported (a [`TextureError::Unsupported`]): point lists, data
/// inside the XML (`DataList`), absolute x/y axes, `SizeZ > 1`.
pub fn x3p_from_bytes(bytes: &[u8]) -> Result<HeightMap, TextureError> {
    let mut zip = zip::ZipArchive::new(Cursor::new(bytes))
        .map_err(|e| TextureError::format(FMT, format!("not a readable zip archive: {e}")))?;
    let xml = read_entry(&mut zip, "main.xml", MAX_XML)?
        .ok_or_else(|| TextureError::format(FMT, "the archive has no main.xml"))?;
    if let Some(sum) = read_entry(&mut zip, "md5_checksum.hex", 4096)? {
        let sum = String::from_utf8_lossy(&sum);
        let stored = sum.split_whitespace().next().unwrap_or("");
        check_md5("main.xml", stored, &xml)?;
    }
    let xml = std::str::from_utf8(&xml)
        .map_err(|e| TextureError::format(FMT, format!("main.xml is not UTF-8: {e}")))?;
    let doc = roxmltree::Document::parse(xml)
        .map_err(|e| TextureError::format(FMT, format!("main.xml: {e}")))?;
    let root = doc.root_element();
    if root.tag_name().name() != "ISO5436_2" {
        return Err(TextureError::format(
            FMT,
            format!(
                "root element is {:?}, not ISO5436_2",
                root.tag_name().name()
            ),
        ));
    }
    let feature = text(need(root, &["Record1", "FeatureType"])?).to_string();
    if feature != "SUR" && feature != "PRF" {
        return Err(TextureError::unsupported(
            FMT,
            format!("feature type {feature:?} (SUR and PRF are supported)"),
        ));
    }
    let axes = need(root, &["Record1", "Axes"])?;
    let (cx, cy, cz) = (axis(axes, "CX")?, axis(axes, "CY")?, axis(axes, "CZ")?);
    for (name, a) in [("CX", &cx), ("CY", &cy)] {
        if a.axis_type != "I" {
            return Err(TextureError::unsupported(
                FMT,
                format!("{name} axis type {:?} (only incremental I)", a.axis_type),
            ));
        }
    }
    let ztype = X3pDataType::from_code(text(need(axes, &["CZ", "DataType"])?))?;
    let record3 = need(root, &["Record3"])?;
    let dims = child(record3, "MatrixDimension")?.ok_or_else(|| {
        TextureError::unsupported(FMT, "point list data (no Record3/MatrixDimension)")
    })?;
    let nx = size(need(dims, &["SizeX"])?, "SizeX")?;
    let ny = size(need(dims, &["SizeY"])?, "SizeY")?;
    let nz = size(need(dims, &["SizeZ"])?, "SizeZ")?;
    if nz != 1 {
        return Err(TextureError::unsupported(
            FMT,
            format!("SizeZ = {nz} (only 1 layer)"),
        ));
    }
    let n = check_size(nx, ny).map_err(|e| TextureError::format(FMT, e.to_string()))?;
    let link = child(record3, "DataLink")?.ok_or_else(|| {
        TextureError::unsupported(FMT, "point data inside main.xml (no Record3/DataLink)")
    })?;
    let data_name = text(need(link, &["PointDataLink"])?).to_string();
    let expected = (n as u64) * ztype.size() as u64;
    // Read up to the widest type's size so that a wrong declared type is
    // reported with the type the bytes would fit, not as a bare overflow.
    let widest = (n as u64) * X3pDataType::F64.size() as u64;
    let data = read_entry(&mut zip, &data_name, widest)?
        .ok_or_else(|| TextureError::format(FMT, format!("the archive has no {data_name}")))?;
    if data.len() as u64 != expected {
        let fits = [
            X3pDataType::I16,
            X3pDataType::I32,
            X3pDataType::F32,
            X3pDataType::F64,
        ]
        .into_iter()
        .filter(|t| (n as u64) * t.size() as u64 == data.len() as u64)
        .map(|t| t.code())
        .collect::<Vec<_>>();
        let hint = if fits.is_empty() {
            "the matrix size or the data is wrong".to_string()
        } else {
            format!(
                "the declared data type disagrees with the bytes, which fit type {}",
                fits.join(" or ")
            )
        };
        return Err(TextureError::format(
            FMT,
            format!(
                "{data_name} holds {} bytes, {nx} × {ny} points of declared type {} need \
                 {expected}: {hint}",
                data.len(),
                ztype.code()
            ),
        ));
    }
    if let Some(sum) = child(link, "MD5ChecksumPointData")? {
        check_md5(&data_name, text(sum), &data)?;
    }
    let mut valid = vec![true; n];
    if let Some(vlink) = child(link, "ValidPointsLink")? {
        let vname = text(vlink).to_string();
        if !vname.is_empty() {
            let vbytes = n.div_ceil(8);
            let buf = read_entry(&mut zip, &vname, vbytes as u64)?
                .ok_or_else(|| TextureError::format(FMT, format!("the archive has no {vname}")))?;
            if buf.len() != vbytes {
                return Err(TextureError::format(
                    FMT,
                    format!("{vname} holds {} bytes, expected {vbytes}", buf.len()),
                ));
            }
            if let Some(sum) = child(link, "MD5ChecksumValidPoints")? {
                check_md5(&vname, text(sum), &buf)?;
            }
            for (k, v) in valid.iter_mut().enumerate() {
                *v = buf[k / 8] >> (k % 8) & 1 == 1;
            }
        }
    }
    let (inc, off) = (cz.increment, cz.offset);
    // A zero (or negative, or non-finite) increment would read every
    // height as the offset, or upside down: refused, as the ASCII grid's
    // `z_scale` is.
    if !(inc.is_finite() && inc > 0.0 && off.is_finite()) {
        return Err(TextureError::format(
            FMT,
            format!(
                "CZ Increment {inc} and Offset {off}: the increment must be finite and > 0, the offset finite"
            ),
        ));
    }
    let mut heights = Vec::with_capacity(n);
    for (k, c) in data.chunks_exact(ztype.size()).enumerate() {
        let raw = match ztype {
            X3pDataType::I16 => i16::from_le_bytes([c[0], c[1]]) as f64,
            X3pDataType::I32 => i32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64,
            X3pDataType::F32 => f32::from_le_bytes([c[0], c[1], c[2], c[3]]) as f64,
            X3pDataType::F64 => {
                f64::from_le_bytes([c[0], c[1], c[2], c[3], c[4], c[5], c[6], c[7]])
            }
        };
        let z = off + inc * raw;
        // NaN is the X3P convention for a missing float point (no validity
        // buffer needed); an infinity is no height at all, so it is refused
        // rather than turned into a silent hole.
        if z.is_infinite() || (z.is_nan() && !raw.is_nan()) {
            return Err(TextureError::format(
                FMT,
                format!(
                    "{data_name}: point {k} (column {}, row {}, byte {}) is {z}, not a finite height",
                    k % nx,
                    k / nx,
                    k * ztype.size()
                ),
            ));
        }
        if z.is_nan() {
            valid[k] = false;
        }
        heights.push(z);
    }
    let (dx, dy) = (
        cx.increment,
        if ny == 1 { cx.increment } else { cy.increment },
    );
    if !(dx > 0.0 && dy > 0.0) {
        return Err(TextureError::format(
            FMT,
            format!("axis increments dx = {dx}, dy = {dy} must be > 0"),
        ));
    }
    HeightMap::with_mask(nx, ny, dx, dy, heights, valid)
}

/// The bytes of an X3P file holding `map`.
///
/// Types `F` and `D` store heights in metres (increment 1, offset 0) and
/// invalid points as NaN; `I` and `L` quantise `z = offset + increment · raw`
/// with the offset at the middle of the height range and the increment
/// spreading the range over ±(2¹⁵ − 2) or ±(2³¹ − 2) steps (quantisation
/// error ≤ increment/2). A validity buffer (`bindata/valid.bin`) is written
/// whenever a point is invalid. `md5_checksum.hex` holds the MD5 of
/// `main.xml`, and `main.xml` the MD5 of each binary entry.
pub fn x3p_to_bytes(map: &HeightMap, data_type: X3pDataType) -> Result<Vec<u8>, TextureError> {
    let n = map.nx() * map.ny();
    let (lo, hi) = map.min_max().unwrap_or((0.0, 0.0));
    let (inc, off) = match data_type {
        X3pDataType::F32 | X3pDataType::F64 => (1.0, 0.0),
        X3pDataType::I16 | X3pDataType::I32 => {
            let steps = if data_type == X3pDataType::I16 {
                (i16::MAX - 1) as f64
            } else {
                (i32::MAX - 1) as f64
            };
            let half = 0.5 * (hi - lo);
            let inc = if half > 0.0 { half / steps } else { 1e-9 };
            (inc, 0.5 * (hi + lo))
        }
    };
    let mut data = Vec::with_capacity(n * data_type.size());
    for (h, v) in map.heights().iter().zip(map.valid()) {
        let z = if *v { *h } else { f64::NAN };
        match data_type {
            X3pDataType::F64 => data.extend_from_slice(&z.to_le_bytes()),
            X3pDataType::F32 => data.extend_from_slice(&(z as f32).to_le_bytes()),
            X3pDataType::I16 => {
                let r = if *v {
                    ((z - off) / inc).round() as i16
                } else {
                    0
                };
                data.extend_from_slice(&r.to_le_bytes());
            }
            X3pDataType::I32 => {
                let r = if *v {
                    ((z - off) / inc).round() as i32
                } else {
                    0
                };
                data.extend_from_slice(&r.to_le_bytes());
            }
        }
    }
    let any_invalid = map.valid().iter().any(|v| !v);
    let valid_bin = any_invalid.then(|| {
        let mut buf = vec![0u8; n.div_ceil(8)];
        for (k, v) in map.valid().iter().enumerate() {
            if *v {
                buf[k / 8] |= 1 << (k % 8);
            }
        }
        buf
    });
    let valid_xml = valid_bin
        .as_ref()
        .map(|b| {
            format!(
                "\n      <ValidPointsLink>bindata/valid.bin</ValidPointsLink>\n      <MD5ChecksumValidPoints>{}</MD5ChecksumValidPoints>",
                md5_hex(b)
            )
        })
        .unwrap_or_default();
    let feature = if map.ny() == 1 { "PRF" } else { "SUR" };
    let xml = format!(
        r#"<?xml version="1.0" encoding="UTF-8" standalone="no" ?>
<p:ISO5436_2 xmlns:p="http://www.opengps.eu/2008/ISO5436_2" xmlns:xsi="http://www.w3.org/2001/XMLSchema-instance" xsi:schemaLocation="http://www.opengps.eu/2008/ISO5436_2 http://www.opengps.eu/2008/ISO5436_2/ISO5436_2_XML.xsd">
  <Record1>
    <Revision>ISO5436 - 2000</Revision>
    <FeatureType>{feature}</FeatureType>
    <Axes>
      <CX><AxisType>I</AxisType><DataType>D</DataType><Increment>{dx:e}</Increment><Offset>0</Offset></CX>
      <CY><AxisType>I</AxisType><DataType>D</DataType><Increment>{dy:e}</Increment><Offset>0</Offset></CY>
      <CZ><AxisType>A</AxisType><DataType>{code}</DataType><Increment>{inc:e}</Increment><Offset>{off:e}</Offset></CZ>
    </Axes>
  </Record1>
  <Record2>
    <Date>1970-01-01T00:00:00.0+00:00</Date>
    <Creator>tyreroad-texture</Creator>
    <Instrument><Manufacturer>tyreroad</Manufacturer><Model>tyreroad-texture</Model><Serial>none</Serial><Version>{version}</Version></Instrument>
    <CalibrationDate>1970-01-01T00:00:00.0+00:00</CalibrationDate>
    <ProbingSystem><Type>Software</Type><Identification>tyreroad-texture</Identification></ProbingSystem>
    <Comment>written by tyreroad-texture</Comment>
  </Record2>
  <Record3>
    <MatrixDimension><SizeX>{nx}</SizeX><SizeY>{ny}</SizeY><SizeZ>1</SizeZ></MatrixDimension>
    <DataLink>
      <PointDataLink>bindata/data.bin</PointDataLink>
      <MD5ChecksumPointData>{md5}</MD5ChecksumPointData>{valid_xml}
    </DataLink>
  </Record3>
  <Record4><ChecksumFile>md5_checksum.hex</ChecksumFile></Record4>
</p:ISO5436_2>
"#,
        dx = map.dx(),
        dy = map.dy(),
        code = data_type.code(),
        version = env!("CARGO_PKG_VERSION"),
        nx = map.nx(),
        ny = map.ny(),
        md5 = md5_hex(&data),
    );
    let zerr = |e: zip::result::ZipError| TextureError::format(FMT, format!("writing zip: {e}"));
    let ierr = |e: std::io::Error| TextureError::format(FMT, format!("writing zip: {e}"));
    let mut w = zip::ZipWriter::new(Cursor::new(Vec::new()));
    let opts = zip::write::SimpleFileOptions::default()
        .compression_method(zip::CompressionMethod::Deflated)
        .large_file(data.len() as u64 >= u32::MAX as u64);
    w.start_file("main.xml", opts).map_err(zerr)?;
    w.write_all(xml.as_bytes()).map_err(ierr)?;
    w.start_file("bindata/data.bin", opts).map_err(zerr)?;
    w.write_all(&data).map_err(ierr)?;
    if let Some(b) = &valid_bin {
        w.start_file("bindata/valid.bin", opts).map_err(zerr)?;
        w.write_all(b).map_err(ierr)?;
    }
    w.start_file("md5_checksum.hex", opts).map_err(zerr)?;
    w.write_all(format!("{} *main.xml\n", md5_hex(xml.as_bytes())).as_bytes())
        .map_err(ierr)?;
    Ok(w.finish().map_err(zerr)?.into_inner())
}
