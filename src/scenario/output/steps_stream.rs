//! The per-step outputs of a rolling run written as the records arrive
//! (docs/distributed.md, "Gather and write"), so that the process writing
//! them holds a few signals per step instead of every record.
//!
//! A [`StepStream`] is opened on an [`OutputSet`] and given the records in
//! path order ([`StepStream::push`], which checks that step `k` is the
//! `k`-th record). Each record is appended at once to the staged
//! `time_signals.csv` and `sensors.csv` and its contacts to three spill
//! files of raw little-endian triplets (`step`, `asperity`, `force`),
//! then dropped. What is kept is [`StepSignals`]: per step the time,
//! position, total force, approach, contact area, status and sensor forces
//! (`41 B + 8 B` per sensor; what the spectra and the charts need), and
//! counters. [`StepStream::finish`] assembles `steps.npz` from the spill
//! files by streaming (the `.npy` header of a triplet member is written
//! once their count is known) and removes them.
//!
//! Invariant: the files are byte-identical to those written from the whole
//! [`RollingResult`](tyreroad_rolling::RollingResult) at once
//! ([`super::steps_npz`], [`super::csv_bytes`]); the staged set is still
//! moved into place whole at its commit ([`super::swap`]), never partly.

use std::fs::File;
use std::io::{BufReader, BufWriter, Write};
use std::path::PathBuf;

use serde::Serialize;
use tyreroad_rolling::{Recovery, StepRecord, StepStatus};

use super::npz_stream::{Element, NpzStream, io, npz_error, write_f64s};
use super::{OutputSet, ScenarioError, fmt};
use crate::texture_road::PastCapTally;

/// `time_signals.csv`'s row (its columns and number formats).
#[derive(Serialize)]
struct TimeSignalRow {
    #[serde(rename = "time_s", serialize_with = "fmt::sci9")]
    time: f64,
    #[serde(rename = "position_m", serialize_with = "fmt::sci9")]
    position: f64,
    #[serde(rename = "total_force_n", serialize_with = "fmt::sci12")]
    total_force: f64,
    #[serde(rename = "approach_m", serialize_with = "fmt::sci12")]
    approach: f64,
    #[serde(rename = "contact_area_m2", serialize_with = "fmt::sci9")]
    contact_area: f64,
    n_contacts: usize,
    n_selected: usize,
    iterations: usize,
    #[serde(rename = "clearance_m", serialize_with = "fmt::sci6")]
    clearance: f64,
    n_overlapping: usize,
    // Appended after the original columns, which keep their bytes; the
    // iteration count is already the `iterations` column above.
    status: &'static str,
    recovery: &'static str,
    #[serde(serialize_with = "fmt::sci6")]
    residual: f64,
}

impl TimeSignalRow {
    fn of(s: &StepRecord) -> Self {
        Self {
            time: s.time,
            position: s.position,
            total_force: s.total_force,
            approach: s.approach,
            contact_area: s.contact_area,
            n_contacts: s.contacts,
            n_selected: s.selected,
            iterations: s.iterations,
            clearance: s.clearance,
            n_overlapping: s.overlapping,
            status: s.status.name(),
            recovery: tyreroad_rolling::recovery_name(s.recovery),
            residual: s.residual,
        }
    }
}

/// `sensors.csv`'s row: `time_s,position_m,<sensor>_n...`.
#[derive(Serialize)]
struct SensorRow<'a> {
    #[serde(serialize_with = "fmt::sci9")]
    time: f64,
    #[serde(serialize_with = "fmt::sci9")]
    position: f64,
    #[serde(serialize_with = "fmt::sci9_all")]
    forces: &'a [f64],
}

/// A step that did not converge cleanly, for the run's summary.
#[derive(Clone, Debug, PartialEq)]
pub struct NotConverged {
    /// Step index on the path.
    pub index: usize,
    /// Footprint centre's x (m).
    pub position: f64,
    /// Stagnated or failed.
    pub status: StepStatus,
    /// Final relative residual.
    pub residual: f64,
    /// The attempt that produced the step (a kept step solved under the
    /// tread's profile slope: [`Recovery::ProfileSlope`]).
    pub recovery: Recovery,
}

/// What a run's end needs of its steps once their records are written:
/// the signals (one value per step, in path order) and counters.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StepSignals {
    /// Time of each step (s).
    pub time: Vec<f64>,
    /// Footprint centre's x (m).
    pub position: Vec<f64>,
    /// Total force (N; NaN at a failed step).
    pub total_force: Vec<f64>,
    /// Approach (m).
    pub approach: Vec<f64>,
    /// Contact area `Σ π a²` (m²).
    pub contact_area: Vec<f64>,
    /// Status of each step.
    pub status: Vec<StepStatus>,
    /// Force of each sensor (N), `sensors[k][step]`; a record without
    /// sensor `k` counts 0 N, as [`tyreroad_rolling::RollingResult::sensor`].
    pub sensors: Vec<Vec<f64>>,
    /// Smallest truncation clearance over the steps not failed (m).
    pub min_clearance: f64,
    /// Steps where some contact patches overlap.
    pub overlapping_steps: usize,
    /// Most overlapping pairs at one step.
    pub most_overlapping: usize,
    /// The steps not converged, in path order.
    pub not_converged: Vec<NotConverged>,
    /// What the run is told of contacts pressed past their caps, when the
    /// stream counted them ([`StepStream::count_past_caps`]) and some were.
    pub past_caps: Option<String>,
}

impl StepSignals {
    fn new(sensors: usize) -> Self {
        Self {
            sensors: vec![Vec::new(); sensors],
            min_clearance: f64::INFINITY,
            ..Self::default()
        }
    }

    fn push(&mut self, s: &StepRecord) {
        self.time.push(s.time);
        self.position.push(s.position);
        self.total_force.push(s.total_force);
        self.approach.push(s.approach);
        self.contact_area.push(s.contact_area);
        self.status.push(s.status);
        for (k, signal) in self.sensors.iter_mut().enumerate() {
            signal.push(s.sensor_forces.get(k).copied().unwrap_or(0.0));
        }
        if s.status != StepStatus::Failed {
            self.min_clearance = self.min_clearance.min(s.clearance);
        }
        if s.overlapping > 0 {
            self.overlapping_steps += 1;
        }
        self.most_overlapping = self.most_overlapping.max(s.overlapping);
        if s.status != StepStatus::Converged {
            self.not_converged.push(NotConverged {
                index: s.index,
                position: s.position,
                status: s.status,
                residual: s.residual,
                recovery: s.recovery,
            });
        }
    }

    /// Number of steps.
    pub fn len(&self) -> usize {
        self.time.len()
    }

    /// Whether there is no step.
    pub fn is_empty(&self) -> bool {
        self.time.is_empty()
    }

    /// Steps per status: `[converged, stagnated, failed]`.
    pub fn status_counts(&self) -> [usize; 3] {
        let mut n = [0; 3];
        for s in &self.status {
            n[status_code(*s) as usize] += 1;
        }
        n
    }
}

fn status_code(s: StepStatus) -> i64 {
    match s {
        StepStatus::Converged => 0,
        StepStatus::Stagnated => 1,
        StepStatus::Failed => 2,
    }
}

/// The three spill files of the contact triplets, in `steps.npz`'s
/// member order.
const TRIPLETS: [&str; 3] = ["step", "asperity", "force"];

/// Appends a rolling run's per-step outputs to an [`OutputSet`] as the
/// records arrive (module docs).
pub struct StepStream {
    time_signals: csv::Writer<BufWriter<File>>,
    sensors: Option<csv::Writer<BufWriter<File>>>,
    spill: Vec<(PathBuf, BufWriter<File>)>,
    nnz: usize,
    signals: StepSignals,
    past_caps: Option<PastCapTally>,
}

fn csv_error(e: csv::Error) -> ScenarioError {
    ScenarioError::Encode {
        what: "CSV".into(),
        message: e.to_string(),
    }
}

impl StepStream {
    /// Opens `time_signals.csv` (and `sensors.csv` when `sensor_names` is
    /// not empty) in `set`, and the spill files beside them.
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if a file cannot be created.
    pub fn new(set: &mut OutputSet, sensor_names: &[String]) -> Result<Self, ScenarioError> {
        let create = |path: PathBuf| -> Result<BufWriter<File>, ScenarioError> {
            File::create(&path)
                .map(BufWriter::new)
                .map_err(io("creating", &path))
        };
        let time_signals = csv::WriterBuilder::new()
            .terminator(csv::Terminator::Any(b'\n'))
            .from_writer(create(set.staging_path("time_signals.csv"))?);
        let sensors = if sensor_names.is_empty() {
            None
        } else {
            let mut w = csv::WriterBuilder::new()
                .has_headers(false)
                .terminator(csv::Terminator::Any(b'\n'))
                .from_writer(create(set.staging_path("sensors.csv"))?);
            let mut header = vec!["time_s".to_string(), "position_m".to_string()];
            header.extend(sensor_names.iter().map(|s| format!("{s}_n")));
            w.write_record(&header).map_err(csv_error)?;
            Some(w)
        };
        // Hidden names the commit would move in if they were left: `finish`
        // removes them (and a set dropped uncommitted removes its staging
        // directory whole).
        let mut spill = Vec::with_capacity(TRIPLETS.len());
        for name in TRIPLETS {
            let path = set.scratch_path(&format!(".steps-{name}.spill"));
            spill.push((path.clone(), create(path)?));
        }
        Ok(Self {
            time_signals,
            sensors,
            spill,
            nnz: 0,
            signals: StepSignals::new(sensor_names.len()),
            past_caps: None,
        })
    }

    /// Counts each record's contacts pressed past their caps on `tally`
    /// (a texture road's Wilke laws, `Scenario::past_cap_tally`), for
    /// [`StepSignals::past_caps`]: the records are not kept, so the count
    /// is made as they pass.
    pub fn count_past_caps(&mut self, tally: PastCapTally) {
        self.past_caps = Some(tally);
    }

    /// Steps written so far.
    pub fn len(&self) -> usize {
        self.signals.len()
    }

    /// Whether no step was written yet.
    pub fn is_empty(&self) -> bool {
        self.signals.is_empty()
    }

    /// Makes room for the signals of `steps` steps at once: a stream
    /// told the path's length holds its signals once, not up to twice
    /// while their vectors grow by doubling.
    pub fn reserve(&mut self, steps: usize) {
        let more = steps.saturating_sub(self.signals.len());
        let s = &mut self.signals;
        for column in [
            &mut s.time,
            &mut s.position,
            &mut s.total_force,
            &mut s.approach,
            &mut s.contact_area,
        ] {
            column.reserve_exact(more);
        }
        s.status.reserve_exact(more);
        s.sensors.iter_mut().for_each(|c| c.reserve_exact(more));
    }

    /// Appends one step's record; it must be the path's next step.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] for a record out of path order,
    /// [`ScenarioError::Io`] / [`ScenarioError::Encode`] if a file cannot
    /// be written.
    pub fn push(&mut self, s: &StepRecord) -> Result<(), ScenarioError> {
        let k = self.signals.len();
        if s.index != k {
            return Err(ScenarioError::Invalid(format!(
                "records out of path order: step {} arrived where step {k} was due",
                s.index
            )));
        }
        self.time_signals
            .serialize(TimeSignalRow::of(s))
            .map_err(csv_error)?;
        if let Some(w) = &mut self.sensors {
            w.serialize(SensorRow {
                time: s.time,
                position: s.position,
                forces: &s.sensor_forces,
            })
            .map_err(csv_error)?;
        }
        for (&id, &p) in s.contact_ids.iter().zip(&s.contact_forces) {
            // numpy indexes with int64; a run has far fewer than 2^63 steps
            // or asperities.
            let words = [
                (k as i64).to_le_bytes(),
                (id as i64).to_le_bytes(),
                p.to_le_bytes(),
            ];
            for ((path, w), word) in self.spill.iter_mut().zip(words) {
                w.write_all(&word).map_err(io("writing", path))?;
            }
            self.nnz += 1;
        }
        self.signals.push(s);
        if let Some(tally) = &mut self.past_caps {
            tally.count(s);
        }
        Ok(())
    }

    /// Writes `steps.npz` (with `lateral`, the path's y in m), closes the
    /// CSV files and removes the spill files; returns the kept signals.
    ///
    /// # Errors
    /// No step at all (a table needs a row), or a file that cannot be
    /// written or read back.
    pub fn finish(self, set: &mut OutputSet, lateral: f64) -> Result<StepSignals, ScenarioError> {
        let Self {
            time_signals,
            sensors,
            spill,
            nnz,
            mut signals,
            past_caps,
        } = self;
        signals.past_caps = past_caps.and_then(|t| t.warning());
        if signals.is_empty() {
            return Err(ScenarioError::Encode {
                what: "CSV".into(),
                message: "no rows to take the header from".into(),
            });
        }
        let flush = |w: csv::Writer<BufWriter<File>>| -> Result<(), ScenarioError> {
            let file = w.into_inner().map_err(|e| ScenarioError::Encode {
                what: "CSV".into(),
                message: e.to_string(),
            })?;
            file.into_inner().map(|_| ()).map_err(|e| npz_error(&e))
        };
        flush(time_signals)?;
        if let Some(w) = sensors {
            flush(w)?;
        }
        let mut paths = Vec::with_capacity(spill.len());
        for (path, w) in spill {
            w.into_inner().map_err(|e| npz_error(&e))?;
            paths.push(path);
        }
        let mut npz = NpzStream::create(set, "steps.npz")?;
        let mut member =
            |name: &str,
             shape: &[usize],
             elem: Element,
             body: &mut dyn FnMut(&mut dyn Write) -> std::io::Result<()>| {
                npz.member(name, shape, elem, body)
            };
        let n = signals.len();
        member("time", &[n], Element::F64, &mut |w| {
            write_f64s(w, &signals.time)
        })?;
        member("position", &[n], Element::F64, &mut |w| {
            write_f64s(w, &signals.position)
        })?;
        member("lateral", &[], Element::F64, &mut |w| {
            write_f64s(w, &[lateral])
        })?;
        for (name, path) in TRIPLETS.iter().zip(&paths) {
            let elem = if *name == "force" {
                Element::F64
            } else {
                Element::I64
            };
            let file = File::open(path).map_err(io("reading", path))?;
            let mut reader = BufReader::new(file);
            member(name, &[nnz], elem, &mut |w| {
                std::io::copy(&mut reader, w).map(|_| ())
            })?;
        }
        member("status", &[n], Element::I64, &mut |w| {
            signals
                .status
                .iter()
                .try_for_each(|s| w.write_all(&status_code(*s).to_le_bytes()))
        })?;
        npz.finish()?;
        for path in &paths {
            std::fs::remove_file(path).map_err(io("removing", path))?;
        }
        Ok(signals)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use tyreroad_rolling::{Recovery, RollingResult};

    use super::super::{csv_bytes, steps_npz};
    use super::*;

    /// Records of `n` steps with up to 40 contacts each (a deterministic
    /// scramble, so the deflated members span many deflate blocks), two
    /// sensors, a stagnated and a failed step (NaN values, no contacts).
    fn records(n: usize) -> RollingResult {
        let mut seed = 0x9e37_79b9_7f4a_7c15u64;
        let mut next = move || {
            seed ^= seed << 13;
            seed ^= seed >> 7;
            seed ^= seed << 17;
            seed
        };
        let steps = (0..n)
            .map(|k| {
                let m = (next() % 41) as usize;
                let contact_ids: Vec<usize> = (0..m).map(|_| (next() % 100_000) as usize).collect();
                let contact_forces: Vec<f64> =
                    (0..m).map(|_| (next() % 1_000_000) as f64 * 1e-6).collect();
                let failed = k == n / 2;
                let status = match k {
                    _ if failed => StepStatus::Failed,
                    3 => StepStatus::Stagnated,
                    _ => StepStatus::Converged,
                };
                let value = |v: f64| if failed { f64::NAN } else { v };
                StepRecord {
                    index: k,
                    position: 0.05 + k as f64 * 1e-3,
                    time: (0.05 + k as f64 * 1e-3) / 13.9,
                    total_force: value(contact_forces.iter().sum()),
                    approach: value(1e-4 + (next() % 1000) as f64 * 1e-9),
                    contact_area: value(m as f64 * 1e-7),
                    contacts: m,
                    selected: m + 7,
                    iterations: 4,
                    status,
                    recovery: if k == 3 {
                        Recovery::Continuation
                    } else {
                        Recovery::None
                    },
                    residual: 1e-13,
                    clearance: value(1e-3 - k as f64 * 1e-7),
                    overlapping: usize::from(k % 97 == 0),
                    sensor_forces: vec![value(0.5 * k as f64), value(1.0)],
                    contact_ids: if failed { vec![] } else { contact_ids },
                    contact_forces: if failed { vec![] } else { contact_forces },
                }
            })
            .collect();
        RollingResult {
            steps,
            sample_rate: 13.9 / 1e-3,
            resumed: 0,
            input_hash: 0,
        }
    }

    /// Streamed record by record, the files are byte for byte those
    /// written from the whole result at once (`steps_npz`, one CSV table),
    /// the kept signals are the result's, and no spill file is left.
    #[test]
    fn streamed_outputs_equal_the_whole_run_written_at_once() {
        let result = records(20_000);
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let mut set = OutputSet::new(&dir).unwrap();
        let names = ["a".to_string(), "b".to_string()];
        let mut stream = StepStream::new(&mut set, &names).unwrap();
        for s in &result.steps {
            stream.push(s).unwrap();
        }
        let signals = stream.finish(&mut set, 0.002).unwrap();
        set.commit().unwrap();

        let npz = std::fs::read(dir.join("steps.npz")).unwrap();
        let whole = steps_npz(&result, 0.002).unwrap();
        // Members of 3 MB: several deflate pieces (`DEFLATE_CHUNK`) each.
        assert!(
            npz.len() > 3_000_000,
            "{} bytes: too small a test",
            npz.len()
        );
        assert!(npz == whole, "steps.npz differs from steps_npz");

        let rows: Vec<TimeSignalRow> = result.steps.iter().map(TimeSignalRow::of).collect();
        let ts = std::fs::read(dir.join("time_signals.csv")).unwrap();
        assert!(ts == csv_bytes(None, &rows).unwrap());
        // The sensors table, formatted independently of the stream's rows.
        let mut expected = String::from("time_s,position_m,a_n,b_n\n");
        for s in &result.steps {
            let f = &s.sensor_forces;
            expected += &format!(
                "{:.9e},{:.9e},{:.9e},{:.9e}\n",
                s.time, s.position, f[0], f[1]
            );
        }
        assert_eq!(
            std::fs::read_to_string(dir.join("sensors.csv")).unwrap(),
            expected
        );

        let mut listed: Vec<String> = std::fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .filter(|n| !n.starts_with(".tyreroad"))
            .collect();
        listed.sort();
        assert_eq!(listed, ["sensors.csv", "steps.npz", "time_signals.csv"]);

        let same = |a: &[f64], b: &[f64]| {
            a.len() == b.len() && a.iter().zip(b).all(|(x, y)| x.to_bits() == y.to_bits())
        };
        assert!(same(&signals.time, &result.times()));
        assert!(same(&signals.total_force, &result.total_force()));
        assert!(same(&signals.approach, &result.approach()));
        assert!(same(&signals.contact_area, &result.contact_area()));
        assert!(same(&signals.sensors[1], &result.sensor(1)));
        assert_eq!(signals.status_counts(), result.status_counts());
        assert_eq!(
            signals.min_clearance.to_bits(),
            result.min_clearance().to_bits()
        );
        assert_eq!(signals.overlapping_steps, 20_000usize.div_ceil(97));
        let not_converged: Vec<usize> = signals.not_converged.iter().map(|s| s.index).collect();
        assert_eq!(not_converged, [3, 10_000]);
    }

    /// A record out of path order is refused, naming both steps; a stream
    /// without steps writes nothing (a table needs its header row).
    #[test]
    fn records_out_of_order_or_none_are_refused() {
        let result = records(5);
        let parent = tempfile::tempdir().unwrap();
        let mut set = OutputSet::new(parent.path().join("out")).unwrap();
        let mut stream = StepStream::new(&mut set, &[]).unwrap();
        stream.push(&result.steps[0]).unwrap();
        let err = stream.push(&result.steps[2]).unwrap_err().to_string();
        assert!(err.contains("step 2 arrived where step 1 was due"), "{err}");
        let empty = StepStream::new(&mut set, &[]).unwrap();
        assert!(empty.finish(&mut set, 0.0).is_err());
    }
}
