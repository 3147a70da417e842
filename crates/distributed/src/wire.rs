//! What ranks send each other: step records and sweep rows as flat byte
//! buffers (`u64` little-endian integers, `f64` as their bits, strings as
//! length + UTF-8), so that a record arrives bit for bit as it left.

use tyreroad_rolling::{Recovery, RollingResult, StepRecord, StepStatus};

use crate::DistributedError;

/// Appends values to a buffer.
#[derive(Default)]
pub(crate) struct Writer(pub(crate) Vec<u8>);

impl Writer {
    pub(crate) fn u(&mut self, v: usize) {
        self.0.extend_from_slice(&(v as u64).to_le_bytes());
    }
    pub(crate) fn f(&mut self, v: f64) {
        self.0.extend_from_slice(&v.to_bits().to_le_bytes());
    }
    pub(crate) fn s(&mut self, v: &str) {
        self.u(v.len());
        self.0.extend_from_slice(v.as_bytes());
    }
}

/// Reads values back; running off the end is a [`DistributedError::Wire`].
pub(crate) struct Reader<'b> {
    bytes: &'b [u8],
    at: usize,
}

impl<'b> Reader<'b> {
    pub(crate) fn new(bytes: &'b [u8]) -> Self {
        Self { bytes, at: 0 }
    }
    fn take(&mut self, n: usize) -> Result<&'b [u8], DistributedError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or_else(|| {
            DistributedError::Wire(format!("message truncated at byte {}", self.at))
        })?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }
    fn word(&mut self) -> Result<u64, DistributedError> {
        let mut b = [0u8; 8];
        b.copy_from_slice(self.take(8)?);
        Ok(u64::from_le_bytes(b))
    }
    pub(crate) fn u(&mut self) -> Result<usize, DistributedError> {
        let v = self.word()?;
        usize::try_from(v).map_err(|_| DistributedError::Wire(format!("count {v} too large")))
    }
    pub(crate) fn f(&mut self) -> Result<f64, DistributedError> {
        Ok(f64::from_bits(self.word()?))
    }
    pub(crate) fn s(&mut self) -> Result<String, DistributedError> {
        let n = self.u()?;
        String::from_utf8(self.take(n)?.to_vec())
            .map_err(|_| DistributedError::Wire("a string is not UTF-8".into()))
    }
    /// A count of items of at least `min_bytes` each, refused when the
    /// rest of the message cannot hold them (a damaged count must not
    /// allocate without bound).
    pub(crate) fn count(&mut self, min_bytes: usize) -> Result<usize, DistributedError> {
        let n = self.u()?;
        if n.saturating_mul(min_bytes.max(1)) > self.bytes.len() - self.at {
            return Err(DistributedError::Wire(format!(
                "count {n} exceeds the message"
            )));
        }
        Ok(n)
    }
    pub(crate) fn finished(&self) -> Result<(), DistributedError> {
        if self.at == self.bytes.len() {
            Ok(())
        } else {
            Err(DistributedError::Wire(format!(
                "{} bytes left over",
                self.bytes.len() - self.at
            )))
        }
    }
}

const STATUSES: [StepStatus; 3] = [
    StepStatus::Converged,
    StepStatus::Stagnated,
    StepStatus::Failed,
];
const RECOVERIES: [Recovery; 7] = [
    Recovery::None,
    Recovery::Continuation,
    Recovery::ColdRestart,
    Recovery::DenseFallback,
    Recovery::Regularized,
    Recovery::Clustered,
    Recovery::ProfileSlope,
];

fn code<T: PartialEq>(all: &[T], v: &T) -> usize {
    all.iter().position(|x| x == v).unwrap_or(usize::MAX)
}

fn decode_code<T: Copy>(all: &[T], code: usize, what: &str) -> Result<T, DistributedError> {
    all.get(code)
        .copied()
        .ok_or_else(|| DistributedError::Wire(format!("unknown {what} code {code}")))
}

/// The records of a part of a run, as sent to rank 0.
pub fn encode_records(result: &RollingResult) -> Vec<u8> {
    let mut w = header(&[], result);
    result.steps.iter().for_each(|r| encode_record(&mut w, r));
    w.0
}

/// `lead` (a message's own bytes, such as a status) then
/// [`encode_records`], taking the records and freeing each once encoded: a
/// rank holds its records and their message together only for one record
/// (and the message is allocated once, at its exact size).
pub fn encode_records_owned(lead: &[u8], result: RollingResult) -> Vec<u8> {
    let mut w = header(lead, &result);
    for r in result.steps {
        encode_record(&mut w, &r);
    }
    w.0
}

fn header(lead: &[u8], result: &RollingResult) -> Writer {
    // 4 header words; per record 16 words, a word per sensor, two per
    // contact.
    let size = lead.len()
        + 8 * (4 + result
            .steps
            .iter()
            .map(|r| 16 + r.sensor_forces.len() + 2 * r.contact_ids.len())
            .sum::<usize>());
    let mut w = Writer(Vec::with_capacity(size));
    w.0.extend_from_slice(lead);
    w.f(result.sample_rate);
    w.u(result.resumed);
    w.u(result.input_hash as usize);
    w.u(result.steps.len());
    w
}

pub(crate) fn encode_record(w: &mut Writer, r: &StepRecord) {
    for v in [r.index, r.contacts, r.selected, r.iterations, r.overlapping] {
        w.u(v);
    }
    w.u(code(&STATUSES, &r.status));
    w.u(code(&RECOVERIES, &r.recovery));
    for v in [
        r.position,
        r.time,
        r.total_force,
        r.approach,
        r.contact_area,
        r.residual,
        r.clearance,
    ] {
        w.f(v);
    }
    w.u(r.sensor_forces.len());
    r.sensor_forces.iter().for_each(|&v| w.f(v));
    w.u(r.contact_ids.len());
    for (&i, &p) in r.contact_ids.iter().zip(&r.contact_forces) {
        w.u(i);
        w.f(p);
    }
}

/// The inverse of [`encode_records`].
///
/// # Errors
/// [`DistributedError::Wire`] for a truncated or damaged message.
pub fn decode_records(bytes: &[u8]) -> Result<RollingResult, DistributedError> {
    let mut steps = Vec::new();
    let head = decode_records_each(bytes, &mut |record| {
        steps.push(record);
        Ok(())
    })?;
    Ok(RollingResult {
        steps,
        sample_rate: head.sample_rate,
        resumed: head.resumed,
        input_hash: head.input_hash,
    })
}

/// What a message of records says besides its records.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PartHead {
    /// Sampling rate `V/Δx` (Hz).
    pub sample_rate: f64,
    /// Steps of the part loaded from a checkpoint.
    pub resumed: usize,
    /// Hash of the inputs keying the checkpoint.
    pub input_hash: u64,
    /// Records in the message.
    pub steps: usize,
}

/// [`decode_records`] one record at a time: each is handed to `each` as
/// soon as it is decoded, so the receiver holds the message and one record,
/// not the message and its records. `each`'s first error stops the
/// decoding and is returned.
///
/// # Errors
/// [`DistributedError::Wire`] for a truncated or damaged message (found
/// where the damage is: the records before it were handed on), or `each`'s
/// error.
pub fn decode_records_each(
    bytes: &[u8],
    each: &mut dyn FnMut(StepRecord) -> Result<(), DistributedError>,
) -> Result<PartHead, DistributedError> {
    let mut r = Reader::new(bytes);
    let sample_rate = r.f()?;
    let resumed = r.u()?;
    let input_hash = r.u()? as u64;
    let n = r.count(15 * 8)?;
    for _ in 0..n {
        each(decode_record(&mut r)?)?;
    }
    r.finished()?;
    Ok(PartHead {
        sample_rate,
        resumed,
        input_hash,
        steps: n,
    })
}

pub(crate) fn decode_record(r: &mut Reader<'_>) -> Result<StepRecord, DistributedError> {
    let [index, contacts, selected, iterations, overlapping] =
        [r.u()?, r.u()?, r.u()?, r.u()?, r.u()?];
    let status = decode_code(&STATUSES, r.u()?, "status")?;
    let recovery = decode_code(&RECOVERIES, r.u()?, "recovery")?;
    let [
        position,
        time,
        total_force,
        approach,
        contact_area,
        residual,
        clearance,
    ] = [r.f()?, r.f()?, r.f()?, r.f()?, r.f()?, r.f()?, r.f()?];
    let sensors = r.count(8)?;
    let sensor_forces = (0..sensors).map(|_| r.f()).collect::<Result<_, _>>()?;
    let m = r.count(16)?;
    let (mut contact_ids, mut contact_forces) = (Vec::with_capacity(m), Vec::with_capacity(m));
    for _ in 0..m {
        contact_ids.push(r.u()?);
        contact_forces.push(r.f()?);
    }
    Ok(StepRecord {
        index,
        position,
        time,
        total_force,
        approach,
        contact_area,
        contacts,
        selected,
        iterations,
        status,
        recovery,
        residual,
        clearance,
        overlapping,
        sensor_forces,
        contact_ids,
        contact_forces,
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use tyreroad_rolling::{RollingConfig, RollingControl, RunOptions, SyntheticRoad, Tread, roll};

    use super::*;

    /// A rolled result (with a step made failed: NaN values) crosses the
    /// wire bit for bit (compared through the Debug text, NaN included);
    /// a truncated or padded message is refused.
    #[test]
    fn records_round_trip_bit_for_bit() {
        let rubber = tyreroad::contact_law::Material::new(6.54e6, 0.5).unwrap();
        let road = SyntheticRoad {
            length: 0.12,
            width: 0.06,
            ..SyntheticRoad::default()
        }
        .sphere_road(rubber)
        .unwrap();
        let tyre = Tread::Tyre {
            radius_x: 0.3,
            radius_y: 0.3,
            length: 0.05,
            width: 0.04,
        };
        let mut config =
            RollingConfig::new(tyre, [0.04, 0.05, 1e-3], 13.9, RollingControl::Load(30.0));
        config.sensors = vec![tyreroad_rolling::Sensor {
            name: "s".into(),
            x: [0.04, 0.05],
            y: [-0.01, 0.01],
        }];
        let mut result = roll(&road, rubber, &config, &RunOptions::default()).unwrap();
        result.steps[3].total_force = f64::NAN;
        result.steps[3].status = StepStatus::Failed;
        result.resumed = 2;
        let bytes = encode_records(&result);
        // Allocated at its exact size; the owned encoding is the same bytes.
        assert_eq!(bytes.capacity(), bytes.len());
        let owned = encode_records_owned(&[7], result.clone());
        assert_eq!((owned[0], &owned[1..]), (7, &bytes[..]));
        assert_eq!(owned.capacity(), owned.len());
        let back = decode_records(&bytes).unwrap();
        assert_eq!(format!("{back:?}"), format!("{result:?}"));
        // One record at a time: the same records, in order, and the head.
        let mut one_by_one = Vec::new();
        let head = decode_records_each(&bytes, &mut |s| {
            one_by_one.push(s);
            Ok(())
        })
        .unwrap();
        assert_eq!(format!("{one_by_one:?}"), format!("{:?}", result.steps));
        assert_eq!(
            (head.resumed, head.steps, head.sample_rate.to_bits()),
            (2, result.steps.len(), result.sample_rate.to_bits())
        );
        assert!(back.steps.iter().any(|s| !s.contact_ids.is_empty()));
        assert!(decode_records(&bytes[..bytes.len() - 1]).is_err());
        let mut longer = bytes.clone();
        longer.push(0);
        assert!(decode_records(&longer).is_err());
    }
}
