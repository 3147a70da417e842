//! `road.npz` written from a stream of summits (docs/distributed.md,
//! "Memory per rank"): the process that finishes a run need not hold the
//! road's summits, only something that can list them, in id order, once
//! per member of the archive.
//!
//! A [`SummitSource`] says how many summits there are and walks them
//! ([`SummitSource::each`]); [`write_road_npz_from`] walks it once for
//! `positions` and once for `heights` (`ids` are `0..n`). Sources:
//! [`SummitSlices`] (summits already in memory), a synthetic road's
//! [`tyreroad_rolling::SummitStream`] (replays its kept candidates), and
//! any other road that can list its summits again (a texture read by
//! windows).
//!
//! Invariant: the file is byte-identical to
//! [`super::road_npz`]`(positions, heights)` of the summits listed; a source
//! that lists another number of summits than its `count` is refused (the
//! member's `.npy` header already announced `count`).

use std::io::Write;

use super::npz_stream::{Element, NpzStream, npz_error};
use super::{OutputSet, ScenarioError};

/// What a summit visitor returns: an I/O error stops the walk.
pub type Visit<'v> = dyn FnMut([f64; 2], f64) -> std::io::Result<()> + 'v;

/// A road's summits, listed on demand in id order.
pub trait SummitSource: std::fmt::Debug + Send + Sync {
    /// Summits on the road (the number [`SummitSource::each`] visits).
    fn count(&self) -> usize;

    /// Visits every summit in id order: its position `(x, y)` and height
    /// (m). Called once per member of `road.npz`, so it must list the same
    /// summits every time.
    ///
    /// # Errors
    /// `visit`'s first error (which stops the walk), or the source's own.
    fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()>;
}

/// Summits held in memory (a road built whole).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct SummitSlices {
    /// Summit positions `(x, y)` (m), in id order.
    pub positions: Vec<[f64; 2]>,
    /// Summit heights (m), same order.
    pub heights: Vec<f64>,
}

impl SummitSource for SummitSlices {
    fn count(&self) -> usize {
        self.positions.len()
    }

    fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()> {
        SummitRefs {
            positions: &self.positions,
            heights: &self.heights,
        }
        .each(visit)
    }
}

/// Summits borrowed from a road in memory.
#[derive(Clone, Copy, Debug)]
pub struct SummitRefs<'a> {
    /// Summit positions `(x, y)` (m), in id order.
    pub positions: &'a [[f64; 2]],
    /// Summit heights (m), same order.
    pub heights: &'a [f64],
}

impl SummitSource for SummitRefs<'_> {
    fn count(&self) -> usize {
        self.positions.len()
    }

    fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()> {
        if self.positions.len() != self.heights.len() {
            return Err(std::io::Error::other(format!(
                "{} summit positions but {} heights",
                self.positions.len(),
                self.heights.len()
            )));
        }
        self.positions
            .iter()
            .zip(self.heights)
            .try_for_each(|(&p, &z)| visit(p, z))
    }
}

impl SummitSource for tyreroad_rolling::SummitStream {
    fn count(&self) -> usize {
        tyreroad_rolling::SummitStream::count(self)
    }

    fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()> {
        // The stream cannot stop: after an error the rest is skipped.
        let mut outcome = Ok(());
        tyreroad_rolling::SummitStream::each(self, |p, z| {
            if outcome.is_ok() {
                outcome = visit(p, z);
            }
        });
        outcome
    }
}

impl SummitSource for crate::texture_road::window::NpyTextureRoad {
    fn count(&self) -> usize {
        self.len()
    }

    /// One streaming pass over the file per call (each tile's caps are
    /// rebuilt to know which asperities the road keeps).
    fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()> {
        let mut outcome = Ok(());
        self.summits(|_, p, z| {
            if outcome.is_ok() {
                outcome = visit(p, z);
            }
        })
        .map_err(std::io::Error::other)?;
        outcome
    }
}

/// Summits walked once from a costly source into an unnamed temporary file
/// (24 B each, removed by the system when dropped) and read back from it
/// for each member: a `.npy` texture road, whose walk rebuilds its caps
/// tile by tile, is walked once, and nothing of it stays in memory.
#[derive(Debug)]
pub struct SpilledSummits {
    file: std::sync::Mutex<std::fs::File>,
    count: usize,
}

/// Bytes of one spilled summit: `x`, `y`, `z`, little-endian `f64`.
const SPILLED: usize = 24;

impl SpilledSummits {
    /// Walks `source` once into a temporary file.
    ///
    /// # Errors
    /// The file cannot be created or written, or `source` fails.
    pub fn from_source(source: &dyn SummitSource) -> std::io::Result<Self> {
        let mut out = std::io::BufWriter::new(tempfile::tempfile()?);
        let mut count = 0usize;
        source.each(&mut |p, z| {
            count += 1;
            out.write_all(&p[0].to_le_bytes())?;
            out.write_all(&p[1].to_le_bytes())?;
            out.write_all(&z.to_le_bytes())
        })?;
        let file = out.into_inner().map_err(|e| e.into_error())?;
        Ok(Self {
            file: std::sync::Mutex::new(file),
            count,
        })
    }
}

impl SummitSource for SpilledSummits {
    fn count(&self) -> usize {
        self.count
    }

    fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()> {
        use std::io::{Read, Seek};
        let mut file = self
            .file
            .lock()
            .map_err(|_| std::io::Error::other("the summit spill's lock is poisoned"))?;
        file.rewind()?;
        let mut input = std::io::BufReader::new(&mut *file);
        let mut summit = [0u8; SPILLED];
        for _ in 0..self.count {
            input.read_exact(&mut summit)?;
            let f = |k: usize| {
                let mut b = [0u8; 8];
                b.copy_from_slice(&summit[8 * k..8 * k + 8]);
                f64::from_le_bytes(b)
            };
            visit([f(0), f(1)], f(2))?;
        }
        Ok(())
    }
}

/// Every summit of `source` in a `Vec`s (for tests and small roads).
///
/// # Errors
/// The source's error.
pub fn collect_summits(source: &dyn SummitSource) -> std::io::Result<SummitSlices> {
    let mut all = SummitSlices {
        positions: Vec::with_capacity(source.count()),
        heights: Vec::with_capacity(source.count()),
    };
    source.each(&mut |p, z| {
        all.positions.push(p);
        all.heights.push(z);
        Ok(())
    })?;
    Ok(all)
}

/// `road.npz` ([`super::road_npz`]'s bytes) written into `set` member by
/// member from `source`, walked once per member: memory of a deflate piece,
/// not of the summits.
///
/// # Errors
/// [`ScenarioError::Io`] / [`ScenarioError::Encode`] if the file cannot be
/// written, the source fails, or it lists another number of summits than
/// its count.
pub fn write_road_npz_from(
    set: &mut OutputSet,
    source: &dyn SummitSource,
) -> Result<(), ScenarioError> {
    let n = source.count();
    let mut npz = NpzStream::create(set, "road.npz")?;
    npz.member("ids", &[n], Element::U64, &mut |w| {
        (0..n as u64).try_for_each(|id| w.write_all(&id.to_le_bytes()))
    })?;
    npz.member("positions", &[n, 2], Element::F64, &mut |w| {
        walk(source, w, |p, _, w| {
            w.write_all(&p[0].to_le_bytes())?;
            w.write_all(&p[1].to_le_bytes())
        })
    })?;
    npz.member("heights", &[n], Element::F64, &mut |w| {
        walk(source, w, |_, z, w| w.write_all(&z.to_le_bytes()))
    })?;
    npz.finish()
}

/// `road.npz` ([`super::road_npz`]'s bytes) written into `set` member by
/// member from the summits ([`write_road_npz_from`] for a
/// road that lists its summits on demand).
///
/// # Errors
/// [`ScenarioError::Io`] / [`ScenarioError::Encode`] if the file cannot be
/// written, or the two lists differ in length.
pub fn write_road_npz(
    set: &mut OutputSet,
    positions: &[[f64; 2]],
    heights: &[f64],
) -> Result<(), ScenarioError> {
    if positions.len() != heights.len() {
        return Err(npz_error(&format!(
            "{} summit positions but {} heights",
            positions.len(),
            heights.len()
        )));
    }
    let source = SummitRefs { positions, heights };
    write_road_npz_from(set, &source)
}

/// What a member of `road.npz` writes of one summit.
type Field = fn([f64; 2], f64, &mut dyn Write) -> std::io::Result<()>;

/// Writes `field` of every summit of `source` to `w`: exactly
/// `source.count()` of them, since the member's header announced as many.
fn walk(source: &dyn SummitSource, w: &mut dyn Write, field: Field) -> std::io::Result<()> {
    let n = source.count();
    let mut seen = 0usize;
    source.each(&mut |p, z| {
        seen += 1;
        if seen > n {
            return Err(std::io::Error::other(format!(
                "the road lists more summits than its {n}"
            )));
        }
        field(p, z, w)
    })?;
    if seen == n {
        Ok(())
    } else {
        Err(std::io::Error::other(format!(
            "the road lists {seen} summits, not its {n}"
        )))
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// `road.npz` written member by member is `road_npz`'s bytes, on a
    /// road whose members span several deflate pieces; lists of unequal
    /// length are refused.
    #[test]
    fn streamed_road_npz_equals_the_whole_archive() {
        let n: usize = 70_000;
        let positions: Vec<[f64; 2]> = (0..n)
            .map(|i| [i as f64 * 1.3e-5, ((i * 7919) % 1000) as f64 * 8e-5])
            .collect();
        let heights: Vec<f64> = (0..n)
            .map(|i| ((i * 104_729) % 997) as f64 * 1e-6)
            .collect();
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let mut set = OutputSet::new(&dir).unwrap();
        write_road_npz(&mut set, &positions, &heights).unwrap();
        assert!(write_road_npz(&mut set, &positions, &heights[1..]).is_err());
        set.commit().unwrap();
        let whole = super::super::road_npz(&positions, &heights).unwrap();
        assert!(std::fs::read(dir.join("road.npz")).unwrap() == whole);
    }

    /// A source that says one count and lists another.
    #[derive(Debug)]
    struct Miscounted(SummitSlices, usize);

    impl SummitSource for Miscounted {
        fn count(&self) -> usize {
            self.1
        }
        fn each(&self, visit: &mut Visit<'_>) -> std::io::Result<()> {
            self.0.each(visit)
        }
    }

    /// A synthetic road's summit stream, walked once per member, writes
    /// the bytes of the archive built whole from its listed summits
    /// (`SyntheticRoad::summits`, an independent collection); a source
    /// whose walk disagrees with its count is refused.
    #[test]
    fn a_streamed_synthetic_road_writes_the_whole_archive() {
        let road = tyreroad_rolling::SyntheticRoad {
            length: 0.6,
            width: 0.05,
            ..tyreroad_rolling::SyntheticRoad::default()
        };
        let stream = road.summit_stream().unwrap();
        let (positions, heights) = road.summits().unwrap();
        assert!(positions.len() > 1000);
        assert_eq!(stream.count(), positions.len());
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let mut set = OutputSet::new(&dir).unwrap();
        write_road_npz_from(&mut set, &stream).unwrap();
        let listed = collect_summits(&stream).unwrap();
        assert_eq!((&listed.positions, &listed.heights), (&positions, &heights));
        for wrong in [positions.len() - 1, positions.len() + 1] {
            let bad = Miscounted(listed.clone(), wrong);
            let err = write_road_npz_from(&mut set, &bad).unwrap_err().to_string();
            assert!(err.contains("summits"), "{err}");
        }
        write_road_npz_from(&mut set, &stream).unwrap();
        set.commit().unwrap();
        let whole = super::super::road_npz(&positions, &heights).unwrap();
        assert!(std::fs::read(dir.join("road.npz")).unwrap() == whole);
    }

    /// A spill lists its source's summits bit for bit, every time it is
    /// walked, and a spilled road writes the archive built whole.
    #[test]
    fn spilled_summits_list_their_source_on_every_walk() {
        let source = SummitSlices {
            positions: (0..1000)
                .map(|k| [k as f64 * 1e-3, (k as f64).sin() * 1e-2])
                .collect(),
            heights: (0..1000).map(|k| -(k as f64).cos() * 1e-3).collect(),
        };
        let spill = SpilledSummits::from_source(&source).unwrap();
        assert_eq!(spill.count(), 1000);
        for _ in 0..2 {
            let listed = collect_summits(&spill).unwrap();
            assert_eq!(listed, source);
        }
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let mut set = OutputSet::new(&dir).unwrap();
        write_road_npz_from(&mut set, &spill).unwrap();
        set.commit().unwrap();
        let whole = super::super::road_npz(&source.positions, &source.heights).unwrap();
        assert!(std::fs::read(dir.join("road.npz")).unwrap() == whole);
    }
}
