//! `.npz` archives written member by member into a staged file of an
//! [`OutputSet`]: what [`super::steps_stream`] (`steps.npz`) and
//! [`super::summits`] (`road.npz`) share.
//!
//! Invariant: a member's bytes are exactly those that
//! [`super::NpzBuilder`] writes for the same array, since both hand the
//! deflater pieces of [`super::DEFLATE_CHUNK`] bytes ([`Pieces`]).

use std::fs::File;
use std::io::{BufWriter, Write};
use std::path::PathBuf;

use super::{OutputSet, ScenarioError};

pub(crate) fn io(
    action: &'static str,
    path: &std::path::Path,
) -> impl Fn(std::io::Error) -> ScenarioError {
    let path = path.to_path_buf();
    move |source| ScenarioError::Io {
        action,
        path: path.clone(),
        source,
    }
}

pub(crate) fn npz_error(e: &dyn std::fmt::Display) -> ScenarioError {
    ScenarioError::Encode {
        what: ".npz".into(),
        message: e.to_string(),
    }
}

/// An `.npz` archive written member by member into a staged file, each
/// member's bytes handed to the deflater as [`super::NpzBuilder`] hands
/// them ([`Pieces`]).
pub(crate) struct NpzStream {
    path: PathBuf,
    zip: zip::ZipWriter<BufWriter<File>>,
}

impl NpzStream {
    pub(crate) fn create(set: &mut OutputSet, name: &str) -> Result<Self, ScenarioError> {
        let path = set.staging_path(name);
        let file = File::create(&path).map_err(io("creating", &path))?;
        Ok(Self {
            path,
            zip: zip::ZipWriter::new(BufWriter::new(file)),
        })
    }

    /// Member `name.npy` of `shape`, its data written by `body`.
    pub(crate) fn member(
        &mut self,
        name: &str,
        shape: &[usize],
        elem: Element,
        body: &mut dyn FnMut(&mut dyn Write) -> std::io::Result<()>,
    ) -> Result<(), ScenarioError> {
        let options = zip::write::SimpleFileOptions::default()
            .compression_method(zip::CompressionMethod::Deflated);
        self.zip
            .start_file(format!("{name}.npy"), options)
            .map_err(|e| npz_error(&e))?;
        let mut pieces = Pieces::new(&mut self.zip);
        npy_header(&mut pieces, shape, elem).map_err(|e| npz_error(&e))?;
        body(&mut pieces).map_err(|e| npz_error(&e))?;
        pieces.finish().map_err(io("writing", &self.path))
    }

    pub(crate) fn finish(self) -> Result<(), ScenarioError> {
        let file = self.zip.finish().map_err(|e| npz_error(&e))?;
        file.into_inner().map_err(|e| npz_error(&e))?;
        Ok(())
    }
}

/// Hands a member's bytes on in pieces of exactly
/// [`super::DEFLATE_CHUNK`] bytes (the last one shorter), as
/// [`super::NpzBuilder`] cuts them: deflate's output depends on the cut.
/// A `BufWriter` would not do: it hands on a part-full buffer when a write
/// does not fit.
struct Pieces<W: Write> {
    inner: W,
    piece: Vec<u8>,
}

impl<W: Write> Pieces<W> {
    fn new(inner: W) -> Self {
        Self {
            inner,
            piece: Vec::with_capacity(super::DEFLATE_CHUNK),
        }
    }

    /// Hands on the last piece. Not `flush`: the deflater's flush ends a
    /// block with a sync marker that the whole member's bytes do not have.
    fn finish(mut self) -> std::io::Result<()> {
        self.inner.write_all(&self.piece)
    }
}

impl<W: Write> Write for Pieces<W> {
    fn write(&mut self, bytes: &[u8]) -> std::io::Result<usize> {
        let room = super::DEFLATE_CHUNK - self.piece.len();
        let taken = room.min(bytes.len());
        self.piece.extend_from_slice(&bytes[..taken]);
        if self.piece.len() == super::DEFLATE_CHUNK {
            self.inner.write_all(&self.piece)?;
            self.piece.clear();
        }
        Ok(taken)
    }

    fn flush(&mut self) -> std::io::Result<()> {
        Ok(())
    }
}

/// The element types of `steps.npz`'s members.
#[derive(Clone, Copy)]
pub(crate) enum Element {
    F64,
    I64,
    U64,
}

/// The `.npy` header of an array of `shape` (C order), exactly as
/// [`super::npy_bytes`] writes it, for data that follows it.
fn npy_header(w: &mut dyn Write, shape: &[usize], elem: Element) -> std::io::Result<()> {
    use npyz::WriterBuilder;
    let shape: Vec<u64> = shape.iter().map(|&n| n as u64).collect();
    match elem {
        Element::F64 => npyz::WriteOptions::<f64>::new()
            .default_dtype()
            .shape(&shape)
            .writer(w)
            .write_header_only()
            .map(|_| ()),
        Element::I64 => npyz::WriteOptions::<i64>::new()
            .default_dtype()
            .shape(&shape)
            .writer(w)
            .write_header_only()
            .map(|_| ()),
        Element::U64 => npyz::WriteOptions::<u64>::new()
            .default_dtype()
            .shape(&shape)
            .writer(w)
            .write_header_only()
            .map(|_| ()),
    }
}

pub(crate) fn write_f64s(w: &mut dyn Write, values: &[f64]) -> std::io::Result<()> {
    values
        .iter()
        .try_for_each(|x| w.write_all(&x.to_le_bytes()))
}
