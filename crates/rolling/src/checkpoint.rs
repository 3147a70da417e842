//! Checkpoint files: finished steps written atomically, keyed by a hash of
//! the inputs, loaded on start so that a killed run resumes.
//!
//! One file per chunk, `<hash as 16 hex>-<first>-<end>.ckpt` in the
//! checkpoint directory, rewritten whole (temporary file, `fsync`, rename)
//! with every finished step of that chunk. Floats are stored as the hex of
//! their bits, so a resumed run is bit-for-bit the same. Loading merges the
//! records of every file of the same hash, so a resume may use a different
//! chunking or thread count.
//!
//! A file ends with `checksum <FNV-1a of every byte before that line>`, and
//! every record is checked against the inputs when loaded (its position and
//! time, its clearance against its approach, its forces finite, positive and
//! summing to its total, its asperity ids on the road). A file that fails
//! any check is refused with [`RollingError::CheckpointRejected`] naming the
//! file and the reason, never resumed: the user deletes it (or the
//! directory) to recompute those steps.

use std::collections::HashMap;
use std::fmt::Write as _;
use std::fs;
use std::io::Write as _;
use std::path::Path;

use tyreroad_contact_law::{ContactLaw, Material};

use crate::step::Carry;
use crate::{
    CheckpointOptions, Recovery, Road, RollingConfig, RollingControl, RollingError, StepRecord,
    StepStatus, Tread, recovery_name,
};

// Version 2: sensors integrate each contact's pressure instead of counting
// summits, so version-1 records are not reused. Version 3: records carry the
// count of overlapping contacts. Version 4: records end with the contact
// forces by asperity id (`id:bits`), which older files lack. Version 5:
// records carry their status, recovery and residual; the file ends with a
// checksum.
const MAGIC: &str = "tyreroad-rolling-checkpoint 5";

/// 64-bit FNV-1a: stable across platforms and Rust versions (unlike std's
/// `DefaultHasher`).
#[derive(Debug)]
struct Fnv(u64);

impl Fnv {
    fn new() -> Self {
        Self(0xcbf2_9ce4_8422_2325)
    }
    fn bytes(&mut self, b: &[u8]) {
        for &x in b {
            self.0 ^= u64::from(x);
            self.0 = self.0.wrapping_mul(0x0000_0100_0000_01b3);
        }
    }
    fn f(&mut self, v: f64) {
        self.bytes(&v.to_bits().to_le_bytes());
    }
    fn u(&mut self, v: u64) {
        self.bytes(&v.to_le_bytes());
    }
}

/// Depths (m) at which each law is probed for the input hash.
const PROBES: [f64; 5] = [1e-7, 1e-6, 1e-5, 1e-4, 1e-3];

/// `hash` keyed further by `values` (a road's placed laws' probes).
pub(crate) fn mix(hash: u64, values: impl IntoIterator<Item = f64>) -> u64 {
    let mut h = Fnv(hash);
    h.u(0x91u64);
    for v in values {
        h.f(v);
    }
    h.0
}

/// `hash` (an [`input_hash`]) keyed further by a step coupling's key
/// ([`crate::StepCoupling::key`]).
pub(crate) fn with_coupling(hash: u64, key: u64) -> u64 {
    let mut h = Fnv(hash);
    h.u(0xc0u64);
    h.u(key);
    h.0
}

/// Hash of everything that determines a run's results: the road (positions,
/// heights, each law's fingerprint — force and stiffness at 0.1 µm to
/// 1 mm — and its reference plane [`Road::top`]), the material and the
/// configuration. Not the chunking nor the
/// threads: they do not change the results.
pub fn input_hash<L: ContactLaw>(
    road: &Road<L>,
    material: &Material,
    config: &RollingConfig,
) -> u64 {
    // The road's part, streamed in id order (a window carries its whole
    // road's), then the rest.
    let mut h = Fnv(road.digest());
    // The reference plane moves the approach (and, under approach or
    // tread-height control, the tread): a checkpoint of another plane is
    // another run.
    h.f(road.top());
    h.f(material.youngs_modulus());
    h.f(material.poisson_ratio());
    match config.tread {
        Tread::Block { length, width } => {
            h.u(1);
            h.f(length);
            h.f(width);
        }
        Tread::Tyre {
            radius_x,
            radius_y,
            length,
            width,
        } => {
            h.u(2);
            for v in [radius_x, radius_y, length, width] {
                h.f(v);
            }
        }
    }
    for v in [
        config.lateral,
        config.start,
        config.end,
        config.step,
        config.speed,
        config.margin,
        config.tolerance,
    ] {
        h.f(v);
    }
    h.u(config.max_iterations as u64);
    // Profile runs (the default) keep the keys they had before the option
    // existed.
    if config.contact_slope == crate::ContactSlope::Deformed {
        h.u(7);
    }
    let (tag, v) = match config.control {
        RollingControl::Load(w) => (1, w),
        RollingControl::Approach(d) => (2, d),
        RollingControl::TreadHeight(z) => (3, z),
    };
    h.u(tag);
    h.f(v);
    h.u(config.sensors.len() as u64);
    for s in &config.sensors {
        h.bytes(s.name.as_bytes());
        h.u(0xff);
        for v in s.x.iter().chain(&s.y) {
            h.f(*v);
        }
    }
    h.0
}

/// The road's part of [`input_hash`], fed one asperity at a time in id
/// order: a window of a road ([`Road::window_of`]) is given the digest of
/// its whole road, computed by whoever can stream the whole road's
/// asperities without holding them (the synthetic road's window builder).
///
/// The road's count is folded in last and the summit radii, when the road
/// has them, are hashed apart (their own FNV stream), so that a road can be
/// fed one asperity at a time in id order without knowing its count first
/// or holding its radii ([`RoadDigest::streamed`]): the digest is
/// `FNV(magic, asperities…, len[, 3, FNV(radii…)])`.
#[derive(Debug)]
pub struct RoadDigest {
    asperities: Fnv,
    /// The count given to [`RoadDigest::new`]; `None`: those pushed.
    len: Option<u64>,
    pushed: u64,
    radii: Option<Fnv>,
}

impl RoadDigest {
    /// A digest of a road of `len` asperities.
    pub fn new(len: usize) -> Self {
        Self {
            len: Some(len as u64),
            ..Self::streamed()
        }
    }

    /// A digest of a road whose count is that of the asperities pushed
    /// (the same digest as [`RoadDigest::new`] with that count).
    pub fn streamed() -> Self {
        let mut h = Fnv::new();
        h.bytes(MAGIC.as_bytes());
        Self {
            asperities: h,
            len: None,
            pushed: 0,
            radii: None,
        }
    }

    /// The next asperity (by id): summit position (m), height (m), law.
    pub fn push<L: ContactLaw>(&mut self, position: [f64; 2], height: f64, law: &L) {
        self.push_probed(position, height, &Self::probe(law));
    }

    /// What the digest reads of a law: force and stiffness at a few
    /// approaches, so that a road built piece by piece (a texture read by
    /// windows) can keep 80 B per asperity and fold them in id order later.
    pub fn probe<L: ContactLaw>(law: &L) -> [(f64, f64); PROBES.len()] {
        PROBES.map(|d| {
            let l = law.evaluate(d);
            (l.force, l.stiffness)
        })
    }

    /// [`RoadDigest::push`] with the law already probed
    /// ([`RoadDigest::probe`]).
    pub fn push_probed(
        &mut self,
        position: [f64; 2],
        height: f64,
        probed: &[(f64, f64); PROBES.len()],
    ) {
        self.pushed += 1;
        let h = &mut self.asperities;
        h.f(position[0]);
        h.f(position[1]);
        h.f(height);
        for &(force, stiffness) in probed {
            h.f(force);
            h.f(stiffness);
        }
    }

    /// Each asperity's summit curvature radius (m, by id), when the road
    /// has them (contact-point gaps): a road without them hashes as before.
    pub fn summit_radii(&mut self, radii: &[f64]) {
        for &r in radii {
            self.push_summit_radius(r);
        }
    }

    /// The next asperity's summit curvature radius (m, by id): as
    /// [`RoadDigest::summit_radii`], one at a time, interleaved with
    /// [`RoadDigest::push`] or not (the radii are hashed apart).
    pub fn push_summit_radius(&mut self, radius: f64) {
        self.radii.get_or_insert_with(Fnv::new).f(radius);
    }

    /// The digest, after every asperity (and radius) was pushed.
    pub fn finish(&self) -> u64 {
        let mut h = Fnv(self.asperities.0);
        h.u(self.len.unwrap_or(self.pushed));
        if let Some(radii) = &self.radii {
            h.u(3);
            h.u(radii.0);
        }
        h.0
    }
}

fn file_name(hash: u64, (a, b): (usize, usize)) -> String {
    format!("{hash:016x}-{a}-{b}.ckpt")
}

/// An I/O error on a checkpoint path, the two mistakes of kind said in
/// words rather than the system's "Not a directory (os error 20)".
fn io_error(path: &Path, e: std::io::Error) -> RollingError {
    let why = match e.kind() {
        std::io::ErrorKind::NotADirectory => {
            "a file stands where the checkpoint folder (or a folder above it) belongs: move \
             it, or set [rolling] checkpoint = false"
                .to_string()
        }
        std::io::ErrorKind::IsADirectory => {
            "a folder stands where a checkpoint file belongs: remove it".to_string()
        }
        _ => e.to_string(),
    };
    RollingError::Checkpoint(format!("{}: {why}", path.display()))
}

/// Writes the records of chunk `[a, b)` atomically.
pub(crate) fn save(
    ck: &CheckpointOptions,
    hash: u64,
    chunk: (usize, usize),
    sensors: usize,
    records: &[StepRecord],
    carry: Option<&Carry>,
) -> Result<(), RollingError> {
    fs::create_dir_all(&ck.dir).map_err(|e| io_error(&ck.dir, e))?;
    let mut text = format!("{MAGIC} {hash:016x} {sensors}\n");
    for r in records {
        let _ = write!(
            text,
            "{} {} {} {} {} {} {} {}",
            r.index,
            r.contacts,
            r.selected,
            r.iterations,
            r.overlapping,
            r.sensor_forces.len(),
            r.status.name(),
            recovery_name(r.recovery),
        );
        for v in [
            r.position,
            r.time,
            r.total_force,
            r.approach,
            r.contact_area,
            r.clearance,
            r.residual,
        ]
        .iter()
        .chain(&r.sensor_forces)
        {
            let _ = write!(text, " {:016x}", v.to_bits());
        }
        for (&i, &p) in r.contact_ids.iter().zip(&r.contact_forces) {
            let _ = write!(text, " {i}:{:016x}", p.to_bits());
        }
        text.push('\n');
    }
    // The warm-start state after the last step, so that a resumed chunk
    // continues exactly as an uninterrupted one would (non-zero forces only).
    if let (Some(c), Some(last)) = (carry, records.last()) {
        let _ = write!(text, "state {} {:016x}", last.index, c.approach.to_bits());
        for (&i, &p) in c.ids.iter().zip(&c.forces) {
            if p != 0.0 {
                let _ = write!(text, " {i}:{:016x}", p.to_bits());
            }
        }
        text.push('\n');
    }
    let _ = writeln!(text, "checksum {:016x}", checksum(text.as_bytes()));
    let path = ck.dir.join(file_name(hash, chunk));
    let tmp = ck.dir.join(format!(
        ".{}.tmp-{}",
        file_name(hash, chunk),
        std::process::id()
    ));
    let result = (|| -> std::io::Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(text.as_bytes())?;
        f.sync_all()?;
        fs::rename(&tmp, &path)
    })();
    if let Err(e) = result {
        let _ = fs::remove_file(&tmp);
        return Err(io_error(&path, e));
    }
    Ok(())
}

/// Removes the temporary files that killed runs left in a checkpoint
/// directory (written, never renamed, so never read). Call it only while no
/// other process writes there: [`crate::roll`] does, as the directory's sole
/// writer; a distributed job's coordinator does before its ranks start.
/// A missing directory holds nothing to remove.
///
/// # Errors
/// [`RollingError::Checkpoint`] when the directory exists but cannot be
/// listed.
pub fn remove_unfinished(dir: &Path) -> Result<(), RollingError> {
    let entries = match fs::read_dir(dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(io_error(dir, e)),
    };
    for entry in entries {
        let entry = entry.map_err(|e| io_error(dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if name.starts_with('.') && name.contains(".ckpt.tmp-") {
            let _ = fs::remove_file(entry.path());
        }
    }
    Ok(())
}

/// What a checkpoint directory holds for one input hash.
#[derive(Default)]
pub(crate) struct Loaded {
    /// Finished steps.
    pub records: Vec<StepRecord>,
    /// Warm-start states after some steps, by step index.
    pub states: HashMap<usize, Carry>,
}

/// FNV-1a of a file's bytes (its last line stores it).
pub(crate) fn checksum(bytes: &[u8]) -> u64 {
    let mut h = Fnv::new();
    h.bytes(bytes);
    h.0
}

/// What a loaded record must agree with: the run's inputs.
pub(crate) struct Expect<'c> {
    pub hash: u64,
    pub config: &'c RollingConfig,
    /// Asperities on the road (ids run below it).
    pub road_len: usize,
    /// `s` at the selection boundary (m): `clearance = boundary − approach`.
    pub boundary: f64,
}

/// Every record and state of every checkpoint file of `hash` in the
/// directory (none when the directory does not exist). Temporary files are
/// skipped, never removed here: the ranks of one job share the directory and
/// another rank may be writing one ([`remove_unfinished`] is the sole
/// writer's cleanup). A file that is damaged or disagrees with the inputs is refused
/// ([`RollingError::CheckpointRejected`]).
pub(crate) fn load(ck: &CheckpointOptions, expect: &Expect<'_>) -> Result<Loaded, RollingError> {
    let entries = match fs::read_dir(&ck.dir) {
        Ok(e) => e,
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(Loaded::default()),
        Err(e) => return Err(io_error(&ck.dir, e)),
    };
    let prefix = format!("{:016x}-", expect.hash);
    let mut out = Loaded::default();
    for entry in entries {
        let entry = entry.map_err(|e| io_error(&ck.dir, e))?;
        let name = entry.file_name().to_string_lossy().into_owned();
        if !(name.starts_with(&prefix) && name.ends_with(".ckpt")) {
            continue;
        }
        let path = entry.path();
        let bytes = fs::read(&path).map_err(|e| io_error(&path, e))?;
        parse(&bytes, expect, &mut out).map_err(|reason| RollingError::CheckpointRejected {
            file: path.display().to_string(),
            reason,
        })?;
    }
    Ok(out)
}

/// Checks the file's checksum, then parses and checks each line.
pub(crate) fn parse(bytes: &[u8], expect: &Expect<'_>, out: &mut Loaded) -> Result<(), String> {
    let text = std::str::from_utf8(bytes).map_err(|_| "not UTF-8 text".to_string())?;
    let body_end = text.trim_end_matches('\n').rfind('\n').map_or(0, |i| i + 1);
    let (body, last) = text.split_at(body_end);
    let stored = last
        .trim_end()
        .strip_prefix("checksum ")
        .and_then(|h| u64::from_str_radix(h, 16).ok())
        .ok_or("no checksum line at the end (truncated, or older than format 5)")?;
    let actual = checksum(body.as_bytes());
    if stored != actual {
        return Err(format!(
            "checksum mismatch (stored {stored:016x}, content {actual:016x}): the file was \
             damaged or edited"
        ));
    }
    let mut lines = body.lines();
    let sensors = expect.config.sensors.len();
    let header = format!("{MAGIC} {:016x} {sensors}", expect.hash);
    if lines.next() != Some(header.as_str()) {
        return Err("not a checkpoint of these inputs (header mismatch)".into());
    }
    for (n, line) in lines.enumerate() {
        let at = |why: &str| format!("line {}: {why}", n + 2);
        if let Some(rest) = line.strip_prefix("state ") {
            let (index, carry) = parse_state(rest).ok_or_else(|| at("malformed state"))?;
            check_state(&carry, expect).map_err(|why| at(&why))?;
            out.states.insert(index, carry);
            continue;
        }
        let record = parse_record(line, sensors).ok_or_else(|| at("malformed record"))?;
        check_record(&record, expect)
            .map_err(|why| at(&format!("step {}: {why}", record.index)))?;
        out.records.push(record);
    }
    Ok(())
}

fn parse_record(line: &str, sensors: usize) -> Option<StepRecord> {
    let mut it = line.split_ascii_whitespace();
    let mut int = || -> Option<usize> { it.next()?.parse().ok() };
    let (index, contacts, selected, iterations, overlapping, ns) =
        (int()?, int()?, int()?, int()?, int()?, int()?);
    if ns != sensors {
        return None;
    }
    let status = match it.next()? {
        "converged" => StepStatus::Converged,
        "stagnated" => StepStatus::Stagnated,
        "failed" => StepStatus::Failed,
        _ => return None,
    };
    let recovery_token = it.next()?;
    let recovery = RECOVERIES
        .into_iter()
        .find(|&r| recovery_name(r) == recovery_token)?;
    let floats: Vec<f64> = it
        .by_ref()
        .take(7 + ns)
        .map(|t| u64::from_str_radix(t, 16).map(f64::from_bits))
        .collect::<Result<_, _>>()
        .ok()?;
    if floats.len() != 7 + ns {
        return None;
    }
    let (contact_ids, contact_forces) = parse_forces(it)?;
    if contact_ids.len() != contacts {
        return None;
    }
    Some(StepRecord {
        index,
        position: floats[0],
        time: floats[1],
        total_force: floats[2],
        approach: floats[3],
        contact_area: floats[4],
        contacts,
        selected,
        iterations,
        status,
        recovery,
        residual: floats[6],
        clearance: floats[5],
        overlapping,
        sensor_forces: floats[7..].to_vec(),
        contact_ids,
        contact_forces,
    })
}

const RECOVERIES: [Recovery; 7] = [
    Recovery::None,
    Recovery::Continuation,
    Recovery::ColdRestart,
    Recovery::DenseFallback,
    Recovery::Regularized,
    Recovery::Clustered,
    Recovery::ProfileSlope,
];

/// What a record must satisfy to be resumed: it is the step it says it is,
/// and its values are those a solve produces (bit for bit where the runner
/// computes them from one another).
fn check_record(r: &StepRecord, e: &Expect<'_>) -> Result<(), String> {
    let config = e.config;
    if r.index >= config.steps() {
        return Err(format!("index beyond the path's {} steps", config.steps()));
    }
    let x = config.position(r.index);
    if r.position.to_bits() != x.to_bits() || r.time.to_bits() != (x / config.speed).to_bits() {
        return Err(format!(
            "position {} m / time {} s, the path puts it at {x} m",
            r.position, r.time
        ));
    }
    if let Some(&id) = r.contact_ids.iter().find(|&&id| id >= e.road_len) {
        return Err(format!(
            "asperity id {id} is not on the road ({} asperities)",
            e.road_len
        ));
    }
    if !(r.residual >= 0.0) {
        return Err(format!("residual {} is not ≥ 0", r.residual));
    }
    if r.status == StepStatus::Failed {
        let all_nan = [r.total_force, r.approach, r.contact_area, r.clearance]
            .iter()
            .chain(&r.sensor_forces)
            .all(|v| v.is_nan());
        if !all_nan || r.contacts != 0 {
            return Err("a failed step with values".into());
        }
        return Ok(());
    }
    if let Some(p) = r
        .contact_forces
        .iter()
        .find(|p| !(p.is_finite() && **p > 0.0))
    {
        return Err(format!("contact force {p} N is not finite and > 0"));
    }
    let sum: f64 = r.contact_forces.iter().sum();
    if sum.to_bits() != r.total_force.to_bits() {
        return Err(format!(
            "total force {} N is not the sum {sum} N of its contact forces",
            r.total_force
        ));
    }
    let finite = [r.approach, r.contact_area, r.residual]
        .iter()
        .chain(&r.sensor_forces)
        .all(|v| v.is_finite());
    // A step with no load and nothing under the footprint has approach −∞.
    let unloaded_and_empty = r.contacts == 0 && r.approach == f64::NEG_INFINITY;
    if !(finite || unloaded_and_empty) {
        return Err("a value is not finite".into());
    }
    if (e.boundary - r.approach).to_bits() != r.clearance.to_bits() {
        return Err(format!(
            "approach {} m disagrees with its clearance {} m",
            r.approach, r.clearance
        ));
    }
    Ok(())
}

fn check_state(c: &Carry, e: &Expect<'_>) -> Result<(), String> {
    if let Some(&id) = c.ids.iter().find(|&&id| id >= e.road_len) {
        return Err(format!(
            "state names asperity id {id}, not on the road ({} asperities)",
            e.road_len
        ));
    }
    if !c.approach.is_finite() || c.forces.iter().any(|p| !(p.is_finite() && *p >= 0.0)) {
        return Err("state holds a non-finite approach or force".into());
    }
    Ok(())
}
fn parse_state(rest: &str) -> Option<(usize, Carry)> {
    let mut it = rest.split_ascii_whitespace();
    let index = it.next()?.parse().ok()?;
    let approach = f64::from_bits(u64::from_str_radix(it.next()?, 16).ok()?);
    let (ids, forces) = parse_forces(it)?;
    Some((
        index,
        Carry {
            ids,
            forces,
            approach,
        },
    ))
}

/// `id:bits` tokens: asperity ids and their forces.
fn parse_forces<'t>(tokens: impl Iterator<Item = &'t str>) -> Option<(Vec<usize>, Vec<f64>)> {
    let (mut ids, mut forces) = (Vec::new(), Vec::new());
    for t in tokens {
        let (i, p) = t.split_once(':')?;
        ids.push(i.parse().ok()?);
        forces.push(f64::from_bits(u64::from_str_radix(p, 16).ok()?));
    }
    Some((ids, forces))
}
