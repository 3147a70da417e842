//! The one way the scenario layer writes files.
//!
//! An [`OutputSet`] stages a run's files in a fresh temporary directory
//! inside the output folder; when every one was written
//! ([`OutputSet::commit`]) the folder is rebuilt beside itself with them and
//! swapped in whole ([`swap`]), so a reader sees the old set or the new one,
//! never a mix; a failed or interrupted run leaves the folder as it was. CSV tables are serde rows ([`csv_bytes`]) whose
//! number columns keep their fixed formats ([`fmt`]); arrays go out as
//! NumPy `.npy` / `.npz` ([`npy_bytes`], [`NpzBuilder`]).

use std::fs;
use std::io::{Cursor, Write};
use std::path::{Path, PathBuf};

use serde::Serialize;

use super::ScenarioError;

mod folder_lock;
mod npz_stream;
pub mod steps_stream;
pub mod summits;
pub mod swap;

pub use folder_lock::LOCK_FILE;
use folder_lock::{FolderLock, lock_folder};

/// The name prefix of a set's staging directory inside its output folder.
pub const STAGING_PREFIX: &str = ".tyreroad-staging-";

/// Removes the staging directories a killed run left in `dir` (a run killed
/// before its commit never moved them in; they hold nothing a reader sees).
/// Called with the folder's lock held ([`lock_folder`]): a staging
/// directory here is then no live set's.
fn remove_stale_staging(dir: &Path) -> Result<(), ScenarioError> {
    let entries = fs::read_dir(dir).map_err(ScenarioError::io("reading", dir))?;
    for entry in entries.flatten() {
        if entry
            .file_name()
            .to_string_lossy()
            .starts_with(STAGING_PREFIX)
        {
            let path = entry.path();
            fs::remove_dir_all(&path).map_err(ScenarioError::io("removing stale", &path))?;
        }
    }
    Ok(())
}

/// Files staged for one output folder, moved in together.
#[derive(Debug)]
pub struct OutputSet {
    dir: PathBuf,
    staging: tempfile::TempDir,
    names: Vec<String>,
    /// The manifest of what this producer wrote last, when the set replaces
    /// it ([`OutputSet::replacing`]).
    manifest: Option<String>,
    /// The folder's lock, held until the set is committed or dropped.
    _lock: FolderLock,
}

impl OutputSet {
    /// A set that will land in `dir` (created when missing).
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if `dir` is a file system root, or `dir` or
    /// the staging directory cannot be created.
    pub fn new(dir: impl Into<PathBuf>) -> Result<Self, ScenarioError> {
        let dir = dir.into();
        // A run's folder is its own: `--out /` would scatter its files and
        // staging directories over the root of the file system.
        if std::path::absolute(&dir).is_ok_and(|d| d.parent().is_none()) {
            return Err(ScenarioError::Io {
                action: "writing outputs into",
                path: dir,
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    "a file system root is not an output folder: give a folder of its own",
                ),
            });
        }
        // An existing file in the folder's place: said so, not as the
        // system's "File exists" of the creation below.
        if dir.exists() && !dir.is_dir() {
            return Err(ScenarioError::Io {
                action: "writing outputs into",
                path: dir,
                source: std::io::Error::new(
                    std::io::ErrorKind::AlreadyExists,
                    "it is a file, not a folder: give a folder (new or existing) for the outputs",
                ),
            });
        }
        // Locked before anything is tidied: another run's staging and its
        // folder being rebuilt beside this one are not stale. A folder not
        // there yet is first put back from a swap a killed run left
        // half-done, then created and locked.
        let early = if dir.is_dir() {
            Some(lock_folder(&dir)?)
        } else {
            None
        };
        swap::prepare(&dir)?;
        fs::create_dir_all(&dir).map_err(ScenarioError::io("creating", &dir))?;
        let lock = match early {
            Some(lock) => lock,
            None => lock_folder(&dir)?,
        };
        remove_stale_staging(&dir)?;
        let staging = tempfile::Builder::new()
            .prefix(STAGING_PREFIX)
            .tempdir_in(&dir)
            .map_err(ScenarioError::io("creating a staging directory in", &dir))?;
        Ok(Self {
            dir,
            staging,
            names: Vec::new(),
            manifest: None,
            _lock: lock,
        })
    }

    /// A set that replaces what the same producer (`producer`, e.g. the
    /// scenario's name) last committed to `dir`: at commit, the files its
    /// previous set listed that this one does not write are removed, so an
    /// output of an older run (a pressure map at a load that now failed, the
    /// sensors of a scenario that no longer has any) never stays beside the
    /// new ones. The list is the hidden file `.tyreroad-outputs-PRODUCER`;
    /// files of other producers and of the user are never touched.
    ///
    /// # Errors
    /// As [`OutputSet::new`], and [`ScenarioError::Io`] naming `producer`
    /// when it is not a plain file-name part (empty, `/`, `\`, `..`).
    pub fn replacing(dir: impl Into<PathBuf>, producer: &str) -> Result<Self, ScenarioError> {
        let plain = !producer.is_empty()
            && !producer.contains(['/', '\\', '\n', '\0'])
            && !producer.contains("..");
        let dir = dir.into();
        if !plain {
            return Err(ScenarioError::Io {
                action: "naming the output list of",
                path: dir,
                source: std::io::Error::new(
                    std::io::ErrorKind::InvalidInput,
                    format!("producer {producer:?} is not a plain file-name part"),
                ),
            });
        }
        let mut set = Self::new(dir)?;
        set.manifest = Some(format!("{MANIFEST_PREFIX}{producer}"));
        Ok(set)
    }

    /// The folder the set lands in.
    pub fn dir(&self) -> &Path {
        &self.dir
    }

    /// What a run should tell its user when this set will not land whole
    /// ([`swap`]: the folder is a symbolic link, the working directory or
    /// holds it, or its parent is not writable): each file lands whole,
    /// the set one file at a time. `None` when it lands whole.
    pub fn landing_note(&self) -> Option<String> {
        (!swap::lands_whole(&self.dir)).then(|| {
            format!(
                "the outputs land in {} one file at a time (each file whole, not the set \
                 together): the folder is a symbolic link or the working directory (or \
                 holds it), or its parent is not writable",
                self.dir.display()
            )
        })
    }

    /// Where a writer that needs a path (a chart backend) puts file `name`;
    /// every file found in the staging directory at commit is moved in.
    pub fn staging_path(&mut self, name: &str) -> PathBuf {
        if !self.names.iter().any(|n| n == name) {
            self.names.push(name.into());
        }
        self.staging.path().join(name)
    }

    /// A path in the staging directory for a scratch file (such as
    /// [`steps_stream::StepStream`]'s spill files) that the caller removes
    /// before the commit: unlike [`OutputSet::staging_path`] the name is
    /// not listed, but a file left there would still be moved in.
    pub fn scratch_path(&self, name: &str) -> PathBuf {
        self.staging.path().join(name)
    }

    /// Stages `bytes` as file `name`.
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if the file cannot be written.
    pub fn write(&mut self, name: &str, bytes: &[u8]) -> Result<(), ScenarioError> {
        let path = self.staging_path(name);
        fs::write(&path, bytes).map_err(ScenarioError::io("writing", path))
    }

    /// Stages `rows` as CSV file `name` (header from the row type's fields).
    ///
    /// # Errors
    /// As [`csv_bytes`] and [`OutputSet::write`].
    pub fn write_csv<R: Serialize>(&mut self, name: &str, rows: &[R]) -> Result<(), ScenarioError> {
        let bytes = csv_bytes(None, rows)?;
        self.write(name, &bytes)
    }

    /// Lands every staged file in the folder (replacing files of the same
    /// name, and with [`OutputSet::replacing`] removing the producer's stale
    /// ones) and returns their final paths, in the order they were staged.
    ///
    /// The folder is rebuilt beside itself and swapped in whole (see
    /// [`swap`] for how, and for the cases that land file by file).
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if the staging directory cannot be read, a
    /// staged name is a directory in the folder, or a file cannot be moved;
    /// the folder then holds the previous set.
    pub fn commit(mut self) -> Result<Vec<PathBuf>, ScenarioError> {
        let staged = fs::read_dir(self.staging.path())
            .map_err(ScenarioError::io("reading", self.staging.path()))?;
        let mut extra = Vec::new();
        for entry in staged {
            let entry = entry.map_err(ScenarioError::io("reading", self.staging.path()))?;
            let name = entry.file_name().to_string_lossy().into_owned();
            if !self.names.contains(&name) {
                extra.push(name);
            }
        }
        extra.sort();
        self.names.extend(extra);
        let written = swap::Landing {
            dir: &self.dir,
            staging: self.staging.path(),
            names: &self.names,
            manifest: self.manifest.as_deref(),
        }
        .land()?;
        // After a swap the staging directory went with the old tree; after
        // a file-by-file landing it is empty. Either way it is gone or goes.
        let staging = self.staging.path().to_path_buf();
        if staging.exists() {
            self.staging
                .close()
                .map_err(ScenarioError::io("removing", staging))?;
        }
        Ok(written)
    }
}

/// The name prefix of the hidden list of what a producer last committed to
/// a folder ([`OutputSet::replacing`]).
pub const MANIFEST_PREFIX: &str = ".tyreroad-outputs-";

/// A CSV table: `header` (when given; else the row type's field names) then
/// one line per row, `\n`-terminated, fields quoted only where CSV needs it.
///
/// # Errors
/// [`ScenarioError::Encode`] if a row does not serialise to a record.
pub fn csv_bytes<R: Serialize>(
    header: Option<&[String]>,
    rows: &[R],
) -> Result<Vec<u8>, ScenarioError> {
    let encode = |e: csv::Error| ScenarioError::Encode {
        what: "CSV".into(),
        message: e.to_string(),
    };
    let mut w = csv::WriterBuilder::new()
        .has_headers(header.is_none())
        .terminator(csv::Terminator::Any(b'\n'))
        .from_writer(Vec::new());
    if let Some(h) = header {
        w.write_record(h).map_err(encode)?;
        if rows.is_empty() {
            // The header alone still makes a table.
        }
    } else if rows.is_empty() {
        return Err(ScenarioError::Encode {
            what: "CSV".into(),
            message: "no rows to take the header from".into(),
        });
    }
    for r in rows {
        w.serialize(r).map_err(encode)?;
    }
    w.into_inner().map_err(|e| ScenarioError::Encode {
        what: "CSV".into(),
        message: e.to_string(),
    })
}

pub mod fmt;

/// An element type of a NumPy array.
pub trait NpyElement: npyz::AutoSerialize + Copy {}
impl NpyElement for f64 {}
impl NpyElement for f32 {}
impl NpyElement for u32 {}
impl NpyElement for i64 {}
impl NpyElement for u64 {}

/// A `.npy` file (format 1.0, C order, little-endian) holding `data` with
/// `shape` (row-major; the product of `shape` must be `data.len()`).
///
/// # Errors
/// [`ScenarioError::Encode`] if the shape does not match the data.
pub fn npy_bytes<T: NpyElement>(shape: &[usize], data: &[T]) -> Result<Vec<u8>, ScenarioError> {
    use npyz::WriterBuilder;
    let count: usize = shape.iter().product();
    if count != data.len() {
        return Err(ScenarioError::Encode {
            what: ".npy".into(),
            message: format!("shape {shape:?} holds {count} values, not {}", data.len()),
        });
    }
    let encode = |e: std::io::Error| ScenarioError::Encode {
        what: ".npy".into(),
        message: e.to_string(),
    };
    let mut bytes = Vec::new();
    let shape: Vec<u64> = shape.iter().map(|&n| n as u64).collect();
    let mut w = npyz::WriteOptions::new()
        .default_dtype()
        .shape(&shape)
        .writer(&mut bytes)
        .begin_nd()
        .map_err(encode)?;
    w.extend(data.iter().copied()).map_err(encode)?;
    w.finish().map_err(encode)?;
    Ok(bytes)
}

/// Bytes of an `.npz` member handed to the deflater at once. Deflate's
/// output depends on how its input is cut (measured: a 3 MB member written
/// in 1 MiB pieces deflates to a few other bytes than written whole, and
/// 8-byte writes to others again), so every writer cuts members the same
/// way: [`NpzBuilder`] at once and [`steps_stream::StepStream`] streaming
/// give the same bytes. Members up to this size are one piece.
pub(crate) const DEFLATE_CHUNK: usize = 1 << 20;

/// A `.npz` archive (what `numpy.savez` writes): named `.npy` members in a
/// zip, read back by `numpy.load(path)["name"]`.
#[derive(Default)]
pub struct NpzBuilder {
    members: Vec<(String, Vec<u8>)>,
}

impl NpzBuilder {
    /// An empty archive.
    pub fn new() -> Self {
        Self::default()
    }

    /// Adds array `name` (stored as `name.npy`).
    ///
    /// # Errors
    /// As [`npy_bytes`].
    pub fn array<T: NpyElement>(
        &mut self,
        name: &str,
        shape: &[usize],
        data: &[T],
    ) -> Result<&mut Self, ScenarioError> {
        self.members
            .push((format!("{name}.npy"), npy_bytes(shape, data)?));
        Ok(self)
    }

    /// The archive's bytes (members deflated).
    ///
    /// # Errors
    /// [`ScenarioError::Encode`] if the zip cannot be written.
    pub fn finish(&self) -> Result<Vec<u8>, ScenarioError> {
        let encode = |e: &dyn std::fmt::Display| ScenarioError::Encode {
            what: ".npz".into(),
            message: e.to_string(),
        };
        let mut zip = zip::ZipWriter::new(Cursor::new(Vec::new()));
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        for (name, bytes) in &self.members {
            zip.start_file(name.as_str(), options)
                .map_err(|e| encode(&e))?;
            for piece in bytes.chunks(DEFLATE_CHUNK) {
                zip.write_all(piece).map_err(|e| encode(&e))?;
            }
        }
        Ok(zip.finish().map_err(|e| encode(&e))?.into_inner())
    }
}

/// A pressure field as `.npz`: `pressure` (Pa, shape `(ny, nx)`, so
/// `pressure[j, i]` is the cell at `x[i]`, `y[j]`), `x` and `y` (cell
/// centres, m), `origin` (`[x0, y0]`, the first cell's centre, m) and
/// `spacing` (`[dx, dy]`, m).
///
/// # Errors
/// As [`NpzBuilder`].
pub fn pressure_field_npz(
    field: &crate::two_scale::PressureField,
) -> Result<Vec<u8>, ScenarioError> {
    let g = field.grid();
    let x: Vec<f64> = (0..g.nx()).map(|i| g.x(i)).collect();
    let y: Vec<f64> = (0..g.ny()).map(|j| g.y(j)).collect();
    NpzBuilder::new()
        .array("pressure", &[g.ny(), g.nx()], field.values())?
        .array("x", &[g.nx()], &x)?
        .array("y", &[g.ny()], &y)?
        .array("origin", &[2], &g.origin())?
        .array("spacing", &[2], &[g.dx(), g.dy()])?
        .finish()
}

/// A height map as `.npz`: `heights` (m, shape `(ny, nx)`, NaN where not
/// measured; `heights[j, i]` is the point at `x = i·dx`, `y = j·dy`) and
/// `spacing` (`[dx, dy]`, m). The `heights` member alone, saved as `.npy`,
/// is what the texture reader takes back (`tyreroad_texture::io::npy`).
///
/// # Errors
/// As [`NpzBuilder`].
pub fn height_map_npz(map: &tyreroad_texture::HeightMap) -> Result<Vec<u8>, ScenarioError> {
    NpzBuilder::new()
        .array("heights", &[map.ny(), map.nx()], map.heights())?
        .array("spacing", &[2], &[map.dx(), map.dy()])?
        .finish()
}

/// The asperities of a rolled road as `.npz`: `ids` (the road's indices,
/// `uint64`, shape `(n,)`), `positions` (m, shape `(n, 2)`: `x`, `y`) and
/// `heights` (m, shape `(n,)`).
///
/// # Errors
/// As [`NpzBuilder`].
pub fn road_npz(positions: &[[f64; 2]], heights: &[f64]) -> Result<Vec<u8>, ScenarioError> {
    let ids: Vec<u64> = (0..positions.len() as u64).collect();
    let flat: Vec<f64> = positions.iter().flatten().copied().collect();
    NpzBuilder::new()
        .array("ids", &[ids.len()], &ids)?
        .array("positions", &[positions.len(), 2], &flat)?
        .array("heights", &[heights.len()], heights)?
        .finish()
}

/// The per-step outputs of a rolling run as `.npz`, beside [`road_npz`]:
/// per step `time` (s) and `position` (the footprint centre's x, m), both
/// shape `(n_steps,)`; `lateral` (the path's y, m, shape `()`); and the
/// contact forces as COO triplets of equal length `(nnz,)` — `step`
/// (`int64`, index into `time`), `asperity` (`int64`, id into `road.npz`'s
/// arrays) and `force` (`float64`, N, only contacts: `P > 0`). Summed per
/// step the forces give `time_signals.csv`'s `total_force_n`. And `status`
/// (`int64`, shape `(n_steps,)`): 0 converged, 1 stagnated, 2 failed — a
/// failed step has no triplets (its forces are unknown, not zero; its
/// `total_force_n` is NaN).
///
/// # Errors
/// As [`NpzBuilder`].
pub fn steps_npz(
    result: &tyreroad_rolling::RollingResult,
    lateral: f64,
) -> Result<Vec<u8>, ScenarioError> {
    let time = result.times();
    let position: Vec<f64> = result.steps.iter().map(|s| s.position).collect();
    let status: Vec<i64> = result
        .steps
        .iter()
        .map(|s| match s.status {
            tyreroad_rolling::StepStatus::Converged => 0,
            tyreroad_rolling::StepStatus::Stagnated => 1,
            tyreroad_rolling::StepStatus::Failed => 2,
        })
        .collect();
    let nnz: usize = result.steps.iter().map(|s| s.contact_ids.len()).sum();
    let (mut step, mut asperity, mut force) = (
        Vec::with_capacity(nnz),
        Vec::with_capacity(nnz),
        Vec::with_capacity(nnz),
    );
    for (k, id, p) in result.contact_triplets() {
        // numpy indexes with int64; a run has far fewer than 2^63 steps or
        // asperities.
        step.push(k as i64);
        asperity.push(id as i64);
        force.push(p);
    }
    NpzBuilder::new()
        .array("time", &[time.len()], &time)?
        .array("position", &[position.len()], &position)?
        .array("lateral", &[], &[lateral])?
        .array("step", &[nnz], &step)?
        .array("asperity", &[nnz], &asperity)?
        .array("force", &[nnz], &force)?
        .array("status", &[status.len()], &status)?
        .finish()
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[derive(Serialize)]
    struct Row {
        #[serde(rename = "load_n", serialize_with = "fmt::plain")]
        load: f64,
        name: String,
        #[serde(rename = "force_n", serialize_with = "fmt::sci9")]
        force: f64,
    }

    #[test]
    fn csv_rows_keep_their_formats_and_quote_names() {
        let rows = [Row {
            load: 50.0,
            name: "a,b".into(),
            force: 1.5,
        }];
        let text = String::from_utf8(csv_bytes(None, &rows).unwrap()).unwrap();
        assert_eq!(text, "load_n,name,force_n\n50,\"a,b\",1.500000000e0\n");
    }

    #[test]
    fn output_set_lands_whole_and_leaves_no_staging() {
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let mut set = OutputSet::new(&dir).unwrap();
        set.write("a.csv", b"one\n").unwrap();
        assert!(!dir.join("a.csv").exists(), "nothing visible before commit");
        let written = set.commit().unwrap();
        assert_eq!(written, vec![dir.join("a.csv")]);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "one\n");
        // A dropped set leaves the folder as it was.
        let mut set = OutputSet::new(&dir).unwrap();
        set.write("a.csv", b"two\n").unwrap();
        drop(set);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "one\n");
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 1);
    }

    #[test]
    fn a_replacing_set_removes_its_producers_stale_files_and_only_those() {
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        fs::create_dir_all(&dir).unwrap();
        fs::write(dir.join("notes.txt"), "the user's").unwrap();
        let mut other = OutputSet::replacing(&dir, "other").unwrap();
        other.write("other.csv", b"o\n").unwrap();
        other.commit().unwrap();
        let mut set = OutputSet::replacing(&dir, "run").unwrap();
        set.write("a.csv", b"1\n").unwrap();
        set.write("p_150N.npz", b"1\n").unwrap();
        set.commit().unwrap();
        // The next run of "run" no longer writes the 150 N map.
        let mut set = OutputSet::replacing(&dir, "run").unwrap();
        set.write("a.csv", b"2\n").unwrap();
        set.commit().unwrap();
        let mut names: Vec<String> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        assert_eq!(
            names,
            [
                ".tyreroad-outputs-other",
                ".tyreroad-outputs-run",
                "a.csv",
                "notes.txt",
                "other.csv"
            ]
        );
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "2\n");
        // A set dropped before its commit (a failed run) leaves the previous
        // run's files, all of them, as they were.
        let mut set = OutputSet::replacing(&dir, "run").unwrap();
        set.write("b.csv", b"3\n").unwrap();
        drop(set);
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "2\n");
        assert!(!dir.join("b.csv").exists());
        for bad in ["", "../x", "a/b"] {
            assert!(OutputSet::replacing(&dir, bad).is_err(), "{bad:?}");
        }
    }

    #[test]
    fn a_staging_directory_left_by_a_killed_run_is_removed_by_the_next() {
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let stale = dir.join(format!("{STAGING_PREFIX}killed"));
        fs::create_dir_all(&stale).unwrap();
        fs::write(stale.join("half.csv"), "1,").unwrap();
        let set = OutputSet::new(&dir).unwrap();
        assert!(!stale.exists());
        set.commit().unwrap();
        assert_eq!(fs::read_dir(&dir).unwrap().count(), 0);
    }

    #[test]
    fn npy_round_trips_through_npyz() {
        let bytes = npy_bytes(&[2, 3], &[1.0f64, 2.0, 3.0, 4.0, 5.0, 6.0]).unwrap();
        let file = npyz::NpyFile::new(&bytes[..]).unwrap();
        assert_eq!(file.shape(), &[2, 3]);
        assert_eq!(
            file.into_vec::<f64>().unwrap(),
            vec![1.0, 2.0, 3.0, 4.0, 5.0, 6.0]
        );
        assert!(npy_bytes(&[2, 2], &[1.0f64]).is_err());
        let npz = NpzBuilder::new()
            .array("x", &[1], &[0.5f64])
            .unwrap()
            .finish()
            .unwrap();
        let mut zip = zip::ZipArchive::new(Cursor::new(npz)).unwrap();
        assert!(zip.by_name("x.npy").is_ok());
    }

    #[test]
    fn steps_npz_holds_the_contacts_as_coo_triplets() {
        use std::io::Read;
        let step = |index: usize, ids: Vec<usize>, forces: Vec<f64>| tyreroad_rolling::StepRecord {
            index,
            position: 0.01 * index as f64,
            time: 0.001 * index as f64,
            total_force: forces.iter().sum(),
            approach: 1e-4,
            contact_area: 0.0,
            contacts: ids.len(),
            selected: 5,
            iterations: 3,
            status: tyreroad_rolling::StepStatus::Converged,
            recovery: tyreroad_rolling::Recovery::None,
            residual: 0.0,
            clearance: 1e-3,
            overlapping: 0,
            sensor_forces: Vec::new(),
            contact_ids: ids,
            contact_forces: forces,
        };
        let result = tyreroad_rolling::RollingResult {
            steps: vec![
                step(0, vec![4, 2], vec![1.5, 2.5]),
                step(1, vec![], vec![]),
                step(2, vec![7], vec![3.0]),
            ],
            sample_rate: 1000.0,
            resumed: 0,
            input_hash: 0,
        };
        let npz = steps_npz(&result, 0.002).unwrap();
        let mut zip = zip::ZipArchive::new(Cursor::new(npz)).unwrap();
        let mut member = |name: &str| {
            let mut bytes = Vec::new();
            zip.by_name(&format!("{name}.npy"))
                .unwrap()
                .read_to_end(&mut bytes)
                .unwrap();
            npyz::NpyFile::new(Cursor::new(bytes)).unwrap()
        };
        let lateral = member("lateral");
        assert!(lateral.shape().is_empty());
        assert_eq!(lateral.into_vec::<f64>().unwrap(), vec![0.002]);
        assert_eq!(
            member("time").into_vec::<f64>().unwrap(),
            vec![0.0, 0.001, 0.002]
        );
        assert_eq!(member("step").into_vec::<i64>().unwrap(), vec![0, 0, 2]);
        assert_eq!(member("asperity").into_vec::<i64>().unwrap(), vec![4, 2, 7]);
        assert_eq!(
            member("force").into_vec::<f64>().unwrap(),
            vec![1.5, 2.5, 3.0]
        );
        assert_eq!(member("status").into_vec::<i64>().unwrap(), vec![0, 0, 0]);
    }

    /// `--out /` is refused before anything is created (a run once wrote
    /// its files and manifest into the root of the file system).
    #[test]
    fn a_file_system_root_is_not_an_output_folder() {
        let err = OutputSet::new("/").err().map(|e| e.to_string());
        assert!(
            err.as_deref()
                .is_some_and(|e| e.contains("not an output folder")),
            "{err:?}"
        );
    }

    /// Regression (adversarial run, 2026-11-29): `--out FILE` said only
    /// "creating FILE: File exists"; it now says the path is a file, and
    /// the file is left as it was.
    #[test]
    fn an_output_path_that_is_a_file_is_refused_as_a_file() -> Result<(), ScenarioError> {
        let dir = tempfile::tempdir().map_err(ScenarioError::io("creating", "tempdir"))?;
        let file = dir.path().join("results");
        fs::write(&file, b"keep").map_err(ScenarioError::io("writing", &file))?;
        let err = OutputSet::new(&file).err().map(|e| e.to_string());
        assert!(
            err.as_deref()
                .is_some_and(|e| e.contains("it is a file, not a folder")),
            "{err:?}"
        );
        assert_eq!(
            fs::read(&file).map_err(ScenarioError::io("reading", &file))?,
            b"keep"
        );
        Ok(())
    }
}
