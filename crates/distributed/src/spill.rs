//! A rank's own records held on disk, not in memory, and sent in bounded
//! chunks (docs/distributed.md, "Gather and write").
//!
//! A rank `r > 0` cannot send its records while it steps: rank 0 writes in
//! path order, so they would wait somewhere until the ranks before it are
//! written. They wait in a file instead: [`RecordSpill`] appends each
//! record, encoded as [`crate::wire`] sends it, to an unnamed spill file as
//! the rank rolls it; at the end the rank sends a head ([`encode_head`]:
//! the part's counts and the body's length) and then the body read back in
//! chunks of at most [`CHUNK`] bytes. Rank 0 decodes the chunks as they
//! come ([`RecordChunks`]), a record at a time, a record cut by a chunk
//! boundary being completed by the next chunk. So a rank holds one record
//! and one chunk, whatever its part's length.
//!
//! Invariants: the chunks concatenated are exactly
//! [`crate::wire::encode_records`]'s body (its bytes after the 4-word
//! head); the records come out in the order and bits they went in; a body
//! longer or shorter than its head says, or a record running past it, is a
//! [`DistributedError::Wire`].

use std::fs::File;
use std::io::{BufWriter, Read, Seek, SeekFrom, Write};
use std::path::{Path, PathBuf};

use tyreroad_rolling::{RollingResult, StepRecord};

use crate::DistributedError;
use crate::wire::{PartHead, Reader, Writer, decode_record, encode_record};

/// The largest chunk a rank sends at once (bytes).
pub const CHUNK: usize = 1 << 20;

/// Words of a record before its sensor count: 5 counts, 2 codes, 7 floats.
const FIXED_WORDS: usize = 14;

fn io_error(what: &str, path: &Path, e: &std::io::Error) -> DistributedError {
    DistributedError::Wire(format!("{what} spill file {}: {e}", path.display()))
}

/// A part's records, encoded, in a file removed when the spill is dropped.
pub struct RecordSpill {
    path: PathBuf,
    file: BufWriter<File>,
    head: PartHead,
    bytes: usize,
    record: Writer,
}

impl RecordSpill {
    /// An empty spill file for `rank` in `dir` (created if missing), named
    /// by rank and process so that ranks sharing a directory never share a
    /// file, and unlinked as soon as it is open (Unix).
    ///
    /// # Errors
    /// [`DistributedError::Wire`] when the file cannot be created.
    pub fn create(dir: &Path, rank: usize) -> Result<Self, DistributedError> {
        std::fs::create_dir_all(dir).map_err(|e| io_error("creating the folder of", dir, &e))?;
        let path = dir.join(format!(".records-rank{rank}-{}.spill", std::process::id()));
        let file = File::options()
            .read(true)
            .write(true)
            .create(true)
            .truncate(true)
            .open(&path)
            .map_err(|e| io_error("creating", &path, &e))?;
        // Unnamed at once where the system allows it (Unix): the open file
        // is still read and written, and nothing is left behind by a
        // killed rank; elsewhere the file is removed on drop.
        let _ = std::fs::remove_file(&path);
        Ok(Self {
            path,
            file: BufWriter::new(file),
            head: PartHead {
                sample_rate: 0.0,
                resumed: 0,
                input_hash: 0,
                steps: 0,
            },
            bytes: 0,
            record: Writer::default(),
        })
    }

    /// Appends a piece of the part (its records in path order), freeing
    /// each record once written.
    ///
    /// # Errors
    /// [`DistributedError::Wire`] when the file cannot be written.
    pub fn push(&mut self, piece: RollingResult) -> Result<(), DistributedError> {
        self.head.sample_rate = piece.sample_rate;
        self.head.input_hash = piece.input_hash;
        self.head.resumed += piece.resumed;
        for record in piece.steps {
            self.push_record(&record)?;
        }
        Ok(())
    }

    fn push_record(&mut self, record: &StepRecord) -> Result<(), DistributedError> {
        self.record.0.clear();
        encode_record(&mut self.record, record);
        self.file
            .write_all(&self.record.0)
            .map_err(|e| io_error("writing", &self.path, &e))?;
        self.bytes += self.record.0.len();
        self.head.steps += 1;
        Ok(())
    }

    /// What the head of the part's message says: counts and the body's
    /// length in bytes.
    pub fn head(&self) -> (PartHead, usize) {
        (self.head, self.bytes)
    }

    /// Hands the body to `send` in chunks of at most `chunk` bytes, in
    /// order, then removes the file.
    ///
    /// # Errors
    /// [`DistributedError::Wire`] when the file cannot be read back, or
    /// `send`'s error.
    pub fn send_chunks(
        mut self,
        chunk: usize,
        send: &mut dyn FnMut(&[u8]) -> Result<(), DistributedError>,
    ) -> Result<(), DistributedError> {
        self.file
            .flush()
            .map_err(|e| io_error("writing", &self.path, &e))?;
        let file = self.file.get_mut();
        file.seek(SeekFrom::Start(0))
            .map_err(|e| io_error("reading", &self.path, &e))?;
        let mut buffer = vec![0u8; chunk.clamp(1, self.bytes.max(1))];
        let mut left = self.bytes;
        while left > 0 {
            let n = left.min(buffer.len());
            file.read_exact(&mut buffer[..n])
                .map_err(|e| io_error("reading", &self.path, &e))?;
            send(&buffer[..n])?;
            left -= n;
        }
        Ok(())
    }
}

impl Drop for RecordSpill {
    fn drop(&mut self) {
        // Already gone on Unix (unlinked when opened); elsewhere this is
        // where it goes.
        let _ = std::fs::remove_file(&self.path);
    }
}

/// `lead` (a status byte) then the head of a spilled part: sample rate,
/// resumed steps, input hash, records and body bytes.
pub fn encode_head(lead: &[u8], head: &PartHead, body: usize) -> Vec<u8> {
    let mut w = Writer(lead.to_vec());
    w.f(head.sample_rate);
    w.u(head.resumed);
    w.u(head.input_hash as usize);
    w.u(head.steps);
    w.u(body);
    w.0
}

/// The inverse of [`encode_head`] (after its lead).
///
/// # Errors
/// [`DistributedError::Wire`] for a head of the wrong length.
pub fn decode_head(bytes: &[u8]) -> Result<(PartHead, usize), DistributedError> {
    let mut r = Reader::new(bytes);
    let head = PartHead {
        sample_rate: r.f()?,
        resumed: r.u()?,
        input_hash: r.u()? as u64,
        steps: r.u()?,
    };
    let body = r.u()?;
    r.finished()?;
    Ok((head, body))
}

/// Rank 0's side: a part's body decoded from its chunks as they arrive.
pub struct RecordChunks {
    pending: Vec<u8>,
    bytes_left: usize,
    records_left: usize,
}

impl RecordChunks {
    /// A body of `body` bytes holding `head.steps` records.
    pub fn new(head: &PartHead, body: usize) -> Self {
        Self {
            pending: Vec::new(),
            bytes_left: body,
            records_left: head.steps,
        }
    }

    /// Whether every byte the head announced has arrived.
    pub fn done(&self) -> bool {
        self.bytes_left == 0
    }

    /// Counts a chunk received but not decoded (after an error elsewhere:
    /// the sender must still be heard to its end).
    pub fn skip(&mut self, bytes: usize) {
        self.bytes_left = self.bytes_left.saturating_sub(bytes);
        self.pending.clear();
    }

    /// Takes the next chunk and hands every record it completes to `each`,
    /// in order.
    ///
    /// # Errors
    /// [`DistributedError::Wire`] for more bytes than announced, a damaged
    /// record, records left over or missing at the end; `each`'s error.
    pub fn push(
        &mut self,
        chunk: &[u8],
        each: &mut dyn FnMut(StepRecord) -> Result<(), DistributedError>,
    ) -> Result<(), DistributedError> {
        if chunk.len() > self.bytes_left {
            return Err(DistributedError::Wire(format!(
                "{} bytes more than the part's head announced",
                chunk.len() - self.bytes_left
            )));
        }
        self.bytes_left -= chunk.len();
        self.pending.extend_from_slice(chunk);
        let mut at = 0;
        while let Some(n) = self.record_len(&self.pending[at..])? {
            if self.records_left == 0 {
                return Err(DistributedError::Wire(
                    "more records than the part's head announced".into(),
                ));
            }
            let mut r = Reader::new(&self.pending[at..at + n]);
            let record = decode_record(&mut r)?;
            r.finished()?;
            at += n;
            self.records_left -= 1;
            each(record)?;
        }
        self.pending.drain(..at);
        if self.done() && (!self.pending.is_empty() || self.records_left > 0) {
            return Err(DistributedError::Wire(format!(
                "a part ends with {} bytes of a record and {} records missing",
                self.pending.len(),
                self.records_left
            )));
        }
        Ok(())
    }

    /// The length of the record `bytes` starts with, `None` when its
    /// counts have not all arrived yet or it is not whole yet.
    fn record_len(&self, bytes: &[u8]) -> Result<Option<usize>, DistributedError> {
        let word = |i: usize| -> Option<u64> {
            let b = bytes.get(8 * i..8 * i + 8)?;
            let mut w = [0u8; 8];
            w.copy_from_slice(b);
            Some(u64::from_le_bytes(w))
        };
        // What can still arrive bounds the counts: a damaged count must
        // not make rank 0 wait for (or allocate) more than the body.
        let reachable = (bytes.len() + self.bytes_left) as u64;
        let too_long = || DistributedError::Wire("a record runs past its part's body".into());
        let Some(sensors) = word(FIXED_WORDS) else {
            return Ok(None);
        };
        let to_count = (FIXED_WORDS as u64 + 2)
            .checked_add(sensors)
            .and_then(|w| w.checked_mul(8))
            .filter(|&b| b <= reachable)
            .ok_or_else(too_long)?;
        let Some(contacts) = word(to_count as usize / 8 - 1) else {
            return Ok(None);
        };
        let total = contacts
            .checked_mul(16)
            .and_then(|c| c.checked_add(to_count))
            .filter(|&b| b <= reachable)
            .ok_or_else(too_long)?;
        let total = total as usize;
        Ok((total <= bytes.len()).then_some(total))
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use tyreroad_rolling::StepStatus;

    use super::*;
    use crate::wire::encode_records;

    fn record(i: usize, contacts: usize) -> StepRecord {
        StepRecord {
            index: i,
            position: 0.05 + 1e-3 * i as f64,
            time: 7.2e-5 * i as f64,
            total_force: if i == 3 { f64::NAN } else { 30.0 + i as f64 },
            approach: 1e-4 / (1.0 + i as f64),
            contact_area: 1e-5,
            contacts,
            selected: 3 * contacts,
            iterations: 4,
            status: if i == 3 {
                StepStatus::Failed
            } else {
                StepStatus::Converged
            },
            recovery: tyreroad_rolling::Recovery::None,
            residual: 1e-13,
            clearance: 2e-4,
            overlapping: i % 2,
            sensor_forces: vec![1.0 / (1.0 + i as f64); i % 3],
            contact_ids: (0..contacts).map(|k| 7 * k + i).collect(),
            contact_forces: (0..contacts).map(|k| 0.1 * k as f64 + 1e-3).collect(),
        }
    }

    fn part(range: std::ops::Range<usize>) -> RollingResult {
        RollingResult {
            steps: range.map(|i| record(i, (i * 37) % 50)).collect(),
            sample_rate: 13_900.0,
            resumed: 1,
            input_hash: 0xdead_beef,
        }
    }

    /// A part spilled in pieces and sent in chunks of every size from 1
    /// byte (every record cut, counts cut inside their words) to more than
    /// the body arrives as the same records, bit for bit (compared through
    /// Debug, NaN included), and its body is `encode_records`'s.
    #[test]
    fn spilled_records_come_back_across_chunk_boundaries() {
        let whole = part(0..40);
        let dir = tempfile::tempdir().unwrap();
        for chunk in [1, 7, 8, 120, 1000, 1 << 20] {
            let mut spill = RecordSpill::create(dir.path(), 1).unwrap();
            spill.push(part(0..15)).unwrap();
            spill.push(part(15..40)).unwrap();
            let (head, body) = spill.head();
            assert_eq!((head.steps, head.resumed), (40, 2));
            let bytes = decode_head(&encode_head(&[], &head, body)).unwrap();
            assert_eq!(bytes, (head, body));
            let mut sent = Vec::new();
            let mut back = Vec::new();
            let mut chunks = RecordChunks::new(&head, body);
            spill
                .send_chunks(chunk, &mut |c| {
                    assert!(c.len() <= chunk);
                    sent.extend_from_slice(c);
                    chunks.push(c, &mut |r| {
                        back.push(r);
                        Ok(())
                    })
                })
                .unwrap();
            assert!(chunks.done());
            assert_eq!(sent, encode_records(&whole)[32..]);
            assert_eq!(format!("{back:?}"), format!("{:?}", whole.steps));
            // The spill file leaves no name behind.
            assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 0);
        }
    }

    /// A body shorter, longer or with a damaged count than its head says
    /// is refused, never waited for.
    #[test]
    fn damaged_bodies_are_refused() {
        let whole = part(0..5);
        let body = encode_records(&whole)[32..].to_vec();
        let head = PartHead {
            sample_rate: whole.sample_rate,
            resumed: 0,
            input_hash: 0,
            steps: 5,
        };
        let feed = |head: &PartHead, announced: usize, bytes: &[u8]| {
            let mut chunks = RecordChunks::new(head, announced);
            chunks.push(bytes, &mut |_| Ok(()))
        };
        assert!(feed(&head, body.len(), &body).is_ok());
        assert!(feed(&head, body.len() - 1, &body).is_err());
        assert!(feed(&head, body.len() + 8, &[body.clone(), vec![0; 8]].concat()).is_err());
        let fewer = PartHead { steps: 4, ..head };
        assert!(feed(&fewer, body.len(), &body).is_err());
        let more = PartHead { steps: 6, ..head };
        assert!(feed(&more, body.len(), &body).is_err());
        let mut damaged = body.clone();
        damaged[8 * FIXED_WORDS..8 * FIXED_WORDS + 8].copy_from_slice(&u64::MAX.to_le_bytes());
        assert!(feed(&head, body.len(), &damaged).is_err());
    }
}
