//! The disk cache of calibrated tables: one file per shape, named by the
//! [`super::Calibrator`]'s key (which hashes [`CACHE_VERSION`], the shape,
//! the grid, `δ_max`, `E*`, the options and whether the table keeps its
//! fields).
//!
//! - A table without fields: `calib-<key>.csv`, one line `δ, F, A` per
//!   knot, the border flag and the key in the header, and a last line
//!   `fnv1a=<hex>`, the FNV-1a of every byte before it (since cache
//!   version 4: a damaged or edited knot is refused, not read as a law).
//! - A table with fields: `calib-<key>.fields`, little-endian binary
//!   (bin records are too many for text):
//!
//!   ```text
//!   magic b"TYRCALF1" · key u64 · reached_border u8 · knots u64
//!   knots × (δ f64, F f64, A f64) · bin side f64
//!   knots × (bins u32 · bins × (index u32, force f64, moment_x f64, moment_y f64))
//!   FNV-1a u64 of every byte before it
//!   ```
//!
//! Values are written bit for bit (the CSV's shortest round-trip decimal
//! is exact too), so a table read back is the table written. A file that
//! cannot be read back whole — missing, truncated, another magic or key,
//! a count past the file's end, a checksum that does not match, a value
//! out of range or out of order (a depth not increasing from 0, a force or
//! area negative or decreasing: a table keeps them non-decreasing) — is
//! treated as absent: the table is
//! solved again and the file rewritten. Never a panic, never a table from
//! part of a file. Files are written beside and renamed, so a reader never
//! sees half a file.

use std::path::{Path, PathBuf};

use super::super::field::BinnedField;
use super::{CalibratedTable, FidelityError};

/// Hashed into every cache key: tables written by an earlier calibration
/// (before the windows and warm starts, version 1 unhashed; before fields
/// were cached, version 2; CSV tables without key and checksum, version 3)
/// are not read back as if solved the current way.
pub(super) const CACHE_VERSION: u64 = 4;

/// The first bytes of a table-with-fields file.
const MAGIC: &[u8; 8] = b"TYRCALF1";

/// 64-bit FNV-1a: stable across builds, so a disk cache survives a
/// toolchain change (std's hasher does not promise that).
pub(super) struct Fnv(pub(super) u64);

impl Fnv {
    pub(super) fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    pub(super) fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= u64::from(x);
            self.0 = self.0.wrapping_mul(0x0100_0000_01b3);
        }
    }
    pub(super) fn u64(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
    pub(super) fn quantised(&mut self, v: f64) {
        self.u64((v / super::HEIGHT_QUANTUM).round() as i64 as u64);
    }
}

/// The file of the table with `key` under `dir`.
pub(super) fn file_for(dir: &Path, key: u64, fields: bool) -> PathBuf {
    let extension = if fields { "fields" } else { "csv" };
    dir.join(format!("calib-{key:016x}.{extension}"))
}

/// Writes `t` to `file` (the binary format when it has fields).
///
/// # Errors
/// [`FidelityError::Cache`] when the folder or the file cannot be written.
pub(super) fn write_table(file: &Path, key: u64, t: &CalibratedTable) -> Result<(), FidelityError> {
    let io = |source| FidelityError::Cache {
        path: file.to_path_buf(),
        source,
    };
    if let Some(dir) = file.parent() {
        // Name the folder, not the table's file, when the folder is at fault.
        let folder = |source| FidelityError::Cache {
            path: dir.to_path_buf(),
            source,
        };
        if dir.exists() && !dir.is_dir() {
            return Err(folder(std::io::Error::new(
                std::io::ErrorKind::AlreadyExists,
                "it is a file, not a folder: the tables are kept in a folder there",
            )));
        }
        std::fs::create_dir_all(dir).map_err(folder)?;
    }
    let bytes = match t.field() {
        Some(field) => encode(t, field, key),
        None => csv_text(t, key).into_bytes(),
    };
    let partial = file.with_extension("partial");
    std::fs::write(&partial, bytes).map_err(io)?;
    std::fs::rename(&partial, file).map_err(io)
}

/// A cached table with fields when `fields`, or `None` if the file is
/// missing or cannot be read back whole (module docs).
pub(super) fn read_table(file: &Path, key: u64, fields: bool) -> Option<CalibratedTable> {
    if fields {
        decode(&std::fs::read(file).ok()?, key)
    } else {
        read_csv(&std::fs::read_to_string(file).ok()?, key)
    }
}

/// The trailer of a CSV table: its checksum.
const CSV_SUM: &str = "fnv1a=";

fn csv_text(t: &CalibratedTable, key: u64) -> String {
    let mut text = format!(
        "depth_m,force_n,area_m2,reached_border={},key={key:016x}\n",
        t.reached_border
    );
    for (d, f, a) in t.knots() {
        text.push_str(&format!("{d:e},{f:e},{a:e}\n"));
    }
    let mut h = Fnv::new();
    h.bytes(text.as_bytes());
    text.push_str(&format!("{CSV_SUM}{:016x}\n", h.0));
    text
}

fn read_csv(text: &str, key: u64) -> Option<CalibratedTable> {
    let body = text.strip_suffix('\n')?;
    let (body, sum) = body.rsplit_once('\n')?;
    let body = &text[..body.len() + 1];
    let mut h = Fnv::new();
    h.bytes(body.as_bytes());
    if sum.strip_prefix(CSV_SUM)? != format!("{:016x}", h.0) {
        return None;
    }
    let mut lines = body.lines();
    let header = lines.next()?;
    let (flags, written_key) = header.rsplit_once(",key=")?;
    if u64::from_str_radix(written_key, 16).ok()? != key {
        return None;
    }
    let reached_border = match flags.rsplit_once("reached_border=")?.1 {
        "true" => true,
        "false" => false,
        _ => return None,
    };
    let (mut d, mut f, mut a) = (Vec::new(), Vec::new(), Vec::new());
    for line in lines {
        let mut it = line.split(',').map(|s| s.parse::<f64>());
        let (Some(Ok(x)), Some(Ok(y)), Some(Ok(z)), None) =
            (it.next(), it.next(), it.next(), it.next())
        else {
            return None;
        };
        if !knot_ok((&d, &f, &a), x, y, z) {
            return None;
        }
        d.push(x);
        f.push(y);
        a.push(z);
    }
    (d.len() >= 2).then(|| CalibratedTable::from_knots(d, f, a, reached_border))
}

/// A knot `(x, y, z)` that may follow the knots `(d, f, a)`: finite, the
/// first at depth 0, deeper than the last, force and area non-negative and
/// not below the last (what [`CalibratedTable::from_knots`] keeps).
fn knot_ok((d, f, a): (&[f64], &[f64], &[f64]), x: f64, y: f64, z: f64) -> bool {
    let finite = x.is_finite() && y.is_finite() && z.is_finite();
    let after = match (d.last(), f.last(), a.last()) {
        (Some(&l), Some(&fl), Some(&al)) => x > l && y >= fl && z >= al,
        _ => x == 0.0,
    };
    finite && after && y >= 0.0 && z >= 0.0
}

fn encode(t: &CalibratedTable, field: &BinnedField, key: u64) -> Vec<u8> {
    let mut out = Vec::new();
    out.extend_from_slice(MAGIC);
    out.extend_from_slice(&key.to_le_bytes());
    out.push(u8::from(t.reached_border));
    out.extend_from_slice(&(t.depth.len() as u64).to_le_bytes());
    for (d, f, a) in t.knots() {
        for v in [d, f, a] {
            out.extend_from_slice(&v.to_le_bytes());
        }
    }
    out.extend_from_slice(&field.bin_size().to_le_bytes());
    for k in 0..field.knots() {
        let bins: Vec<_> = field.bins(k).collect();
        out.extend_from_slice(&(bins.len() as u32).to_le_bytes());
        for (index, force, moment) in bins {
            out.extend_from_slice(&index.to_le_bytes());
            for v in [force, moment[0], moment[1]] {
                out.extend_from_slice(&v.to_le_bytes());
            }
        }
    }
    let mut h = Fnv::new();
    h.bytes(&out);
    out.extend_from_slice(&h.0.to_le_bytes());
    out
}

/// Reads the bytes of a file front to back; `None` past its end.
struct Reader<'a> {
    bytes: &'a [u8],
}

impl<'a> Reader<'a> {
    fn take(&mut self, n: usize) -> Option<&'a [u8]> {
        if n > self.bytes.len() {
            return None;
        }
        let (head, rest) = self.bytes.split_at(n);
        self.bytes = rest;
        Some(head)
    }
    fn u8(&mut self) -> Option<u8> {
        Some(self.take(1)?[0])
    }
    fn u32(&mut self) -> Option<u32> {
        Some(u32::from_le_bytes(self.take(4)?.try_into().ok()?))
    }
    fn u64(&mut self) -> Option<u64> {
        Some(u64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    fn f64(&mut self) -> Option<f64> {
        Some(f64::from_le_bytes(self.take(8)?.try_into().ok()?))
    }
    /// A count of records of `size` bytes that the rest of the file can
    /// hold (a corrupt count must not size an allocation).
    fn count(&mut self, n: u64, size: usize) -> Option<usize> {
        let n = usize::try_from(n).ok()?;
        (n <= self.bytes.len() / size).then_some(n)
    }
}

fn decode(bytes: &[u8], key: u64) -> Option<CalibratedTable> {
    let (payload, sum) = bytes.split_at(bytes.len().checked_sub(8)?);
    let mut h = Fnv::new();
    h.bytes(payload);
    if h.0.to_le_bytes() != sum {
        return None;
    }
    let mut r = Reader { bytes: payload };
    if r.take(MAGIC.len())? != MAGIC || r.u64()? != key {
        return None;
    }
    let reached_border = match r.u8()? {
        0 => false,
        1 => true,
        _ => return None,
    };
    let n = r.u64()?;
    let n = r.count(n, 24)?;
    let (mut d, mut f, mut a) = (Vec::new(), Vec::new(), Vec::new());
    for _ in 0..n {
        let (x, y, z) = (r.f64()?, r.f64()?, r.f64()?);
        if !knot_ok((&d, &f, &a), x, y, z) {
            return None;
        }
        d.push(x);
        f.push(y);
        a.push(z);
    }
    let bin = r.f64()?;
    let mut knots = Vec::with_capacity(n);
    for _ in 0..n {
        let m = r.u32()?;
        let m = r.count(u64::from(m), 28)?;
        let mut bins = Vec::with_capacity(m);
        for _ in 0..m {
            bins.push((r.u32()?, r.f64()?, [r.f64()?, r.f64()?]));
        }
        knots.push(bins);
    }
    if !r.bytes.is_empty() || d.len() < 2 {
        return None;
    }
    let field = BinnedField::from_bins(bin, knots)?;
    let mut table = CalibratedTable::from_knots(d, f, a, reached_border);
    table.field = Some(field);
    Some(table)
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::super::{CacheCounts, CalibrationOptions, Calibrator, CapPatch};
    use super::*;
    use crate::contact_law::Material;

    fn material() -> Material {
        Material::new(6.54e6, 0.5).unwrap()
    }

    /// A paraboloid R = 5 mm on 0.1 mm cells: a few ms of BEM.
    fn cap() -> CapPatch {
        CapPatch::from_fn(21, 1e-4, |x, y| -(x * x + y * y) / 1e-2).unwrap()
    }

    const DEPTH: f64 = 0.1e-3;

    fn calibrator(dir: &Path, fields: bool) -> Calibrator {
        let c = Calibrator::new(material(), CalibrationOptions::default()).with_disk_cache(dir);
        if fields { c.with_fields() } else { c }
    }

    /// The knots and the fields: all of a table but its solve statistics
    /// (which a table read from disk does not have).
    fn same_table(a: &CalibratedTable, b: &CalibratedTable) -> bool {
        a.knots().eq(b.knots()) && a.field() == b.field() && a.reached_border == b.reached_border
    }

    fn the_fields_file(dir: &Path) -> PathBuf {
        let files: Vec<PathBuf> = std::fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "fields"))
            .collect();
        assert_eq!(files.len(), 1, "{files:?}");
        files[0].clone()
    }

    #[test]
    fn a_second_calibration_with_fields_reads_the_same_table_from_disk() {
        let dir = tempfile::tempdir().unwrap();
        let first = calibrator(dir.path(), true);
        let solved = first.law(&cap(), DEPTH).unwrap();
        assert_eq!(first.counts().solved, 1);
        assert!(solved.table().field().is_some_and(|f| f.knots() > 2));
        let second = calibrator(dir.path(), true);
        let read = second.law(&cap(), DEPTH).unwrap();
        assert_eq!(
            second.counts(),
            CacheCounts {
                solved: 0,
                memory_hits: 0,
                disk_hits: 1
            }
        );
        assert!(same_table(solved.table(), read.table()));
        // Bit for bit: the law and the field at a depth between knots.
        for d in [0.013e-3, 0.05e-3, 0.0999e-3] {
            assert_eq!(solved.table().force_at(d), read.table().force_at(d));
            assert_eq!(solved.unit_field(d), read.unit_field(d));
        }
        // Fields on or off is part of the key: a calibrator without fields
        // solves its own table (and one with fields never takes a
        // field-less file), each then found by its own kind.
        let plain = calibrator(dir.path(), false);
        let without = plain.law(&cap(), DEPTH).unwrap();
        assert_eq!(plain.counts().solved, 1);
        assert!(without.table().field().is_none());
        assert!(without.table().knots().eq(solved.table().knots()));
        let again = calibrator(dir.path(), false);
        again.law(&cap(), DEPTH).unwrap();
        assert_eq!(again.counts().disk_hits, 1);
        let with = calibrator(dir.path(), true);
        assert!(with.law(&cap(), DEPTH).unwrap().table().field().is_some());
        assert_eq!(with.counts().disk_hits, 1);
    }

    /// Regression (adversarial run, 2026-11-29): a cache path that is a
    /// file was reported under the first table's file name; the error now
    /// names the folder and what is wrong with it.
    #[test]
    fn a_cache_folder_that_is_a_file_is_named_as_the_folder() {
        let dir = tempfile::tempdir().unwrap();
        let cache = dir.path().join("calibration");
        std::fs::write(&cache, "not a folder").unwrap();
        let e = calibrator(&cache, false)
            .law(&cap(), DEPTH)
            .unwrap_err()
            .to_string();
        assert_eq!(
            e,
            format!(
                "calibration cache {}: it is a file, not a folder: the tables are kept in a \
                 folder there",
                cache.display()
            )
        );
    }

    #[test]
    fn a_truncated_or_corrupt_fields_file_is_solved_again_never_half_read() {
        let dir = tempfile::tempdir().unwrap();
        let reference = calibrator(dir.path(), true).law(&cap(), DEPTH).unwrap();
        let file = the_fields_file(dir.path());
        let good = std::fs::read(&file).unwrap();
        let key = u64::from_le_bytes(good[8..16].try_into().unwrap());
        // Every truncation and every flipped byte is refused, none panics.
        assert!(decode(&good, key).is_some());
        for n in 0..good.len() {
            assert!(decode(&good[..n], key).is_none(), "truncated to {n} bytes");
        }
        for at in 0..good.len() {
            let mut bad = good.clone();
            bad[at] ^= 0x20;
            assert!(decode(&bad, key).is_none(), "byte {at} flipped");
        }
        // Another table's file under this name (its key inside differs).
        assert!(decode(&good, key ^ 1).is_none());
        // Through the calibrator: each damage is a recompute, the table
        // the one solved first, and the file rewritten whole.
        let damages: [(&str, Vec<u8>); 4] = [
            ("empty", Vec::new()),
            ("half", good[..good.len() / 2].to_vec()),
            ("flipped", {
                let mut b = good.clone();
                b[good.len() / 3] ^= 1;
                b
            }),
            ("text", b"depth_m,force_n,area_m2\n1e-5,1,1\n".to_vec()),
        ];
        for (what, bytes) in damages {
            std::fs::write(&file, bytes).unwrap();
            let c = calibrator(dir.path(), true);
            let law = c.law(&cap(), DEPTH).unwrap();
            assert_eq!(c.counts().solved, 1, "{what}");
            assert_eq!(c.counts().disk_hits, 0, "{what}");
            assert!(same_table(law.table(), reference.table()), "{what}");
            assert!(decode(&std::fs::read(&file).unwrap(), key).is_some());
        }
    }

    #[test]
    fn a_damaged_or_edited_csv_table_is_solved_again_never_read_as_a_law() {
        let dir = tempfile::tempdir().unwrap();
        let reference = calibrator(dir.path(), false).law(&cap(), DEPTH).unwrap();
        let files: Vec<PathBuf> = std::fs::read_dir(dir.path())
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.extension().is_some_and(|e| e == "csv"))
            .collect();
        assert_eq!(files.len(), 1, "{files:?}");
        let file = &files[0];
        let good = std::fs::read_to_string(file).unwrap();
        let key = u64::from_str_radix(
            good.lines().next().unwrap().rsplit_once("key=").unwrap().1,
            16,
        )
        .unwrap();
        assert!(read_csv(&good, key).is_some());
        assert!(read_csv(&good, key ^ 1).is_none(), "another table's key");
        // Every truncation (at a line's end too) and every changed digit.
        for n in 0..good.len() {
            assert!(
                read_csv(&good[..n], key).is_none(),
                "truncated to {n} bytes"
            );
        }
        for (at, c) in good.char_indices().filter(|(_, c)| c.is_ascii_digit()) {
            let mut bad = good.clone();
            let other = if c == '1' { "2" } else { "1" };
            bad.replace_range(at..at + 1, other);
            assert!(read_csv(&bad, key).is_none(), "digit at {at} changed");
        }
        // An edit with its checksum made again: a force made negative or
        // decreasing, a table that does not start at depth 0.
        let resealed = |body: String| {
            let mut h = Fnv::new();
            h.bytes(body.as_bytes());
            format!("{body}{CSV_SUM}{:016x}\n", h.0)
        };
        let lines: Vec<&str> = good.lines().collect();
        let knots = &lines[1..lines.len() - 1];
        let edited = |k: usize, f: &dyn Fn(f64, f64, f64) -> (f64, f64, f64)| {
            let mut body = format!("{}\n", lines[0]);
            for (i, line) in knots.iter().enumerate() {
                let v: Vec<f64> = line.split(',').map(|x| x.parse().unwrap()).collect();
                let (d, fo, a) = if i == k {
                    f(v[0], v[1], v[2])
                } else {
                    (v[0], v[1], v[2])
                };
                body.push_str(&format!("{d:e},{fo:e},{a:e}\n"));
            }
            resealed(body)
        };
        assert!(read_csv(&edited(0, &|d, f, a| (d, f, a)), key).is_some());
        let last = knots.len() - 1;
        for (what, bad) in [
            ("negative force", edited(last, &|d, f, a| (d, -f, a))),
            ("decreasing force", edited(last, &|d, _, a| (d, 0.0, a))),
            ("decreasing area", edited(last, &|d, f, _| (d, f, 0.0))),
            ("first depth not 0", edited(0, &|_, f, a| (1e-9, f, a))),
        ] {
            assert!(read_csv(&bad, key).is_none(), "{what}");
        }
        // Through the calibrator: solved again, the reference table.
        std::fs::write(file, edited(last, &|d, f, a| (d, -f, a))).unwrap();
        let c = calibrator(dir.path(), false);
        let law = c.law(&cap(), DEPTH).unwrap();
        assert_eq!((c.counts().solved, c.counts().disk_hits), (1, 0));
        assert!(same_table(law.table(), reference.table()));
    }

    #[test]
    fn bins_out_of_order_or_not_finite_make_no_field() {
        let ok = vec![vec![(1, 1.0, [0.0, 0.0]), (3, 2.0, [1e-3, 0.0])]];
        assert!(BinnedField::from_bins(1e-4, ok.clone()).is_some());
        assert!(BinnedField::from_bins(0.0, ok.clone()).is_none());
        assert!(BinnedField::from_bins(f64::NAN, ok).is_none());
        for bad in [
            vec![(3, 1.0, [0.0, 0.0]), (1, 2.0, [0.0, 0.0])],
            vec![(1, 0.0, [0.0, 0.0])],
            vec![(1, 1.0, [f64::INFINITY, 0.0])],
        ] {
            assert!(BinnedField::from_bins(1e-4, vec![bad]).is_none());
        }
    }
}
