//! The error type of the texture layer.

use std::path::PathBuf;

/// What can go wrong when building, reading, writing or analysing a texture.
#[derive(Debug, thiserror::Error)]
pub enum TextureError {
    /// A file could not be read or written.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The underlying error.
        source: std::io::Error,
    },
    /// A height map's sizes, spacings or heights are inconsistent.
    #[error("invalid height map: {0}")]
    InvalidMap(String),
    /// A parameter is out of its range.
    #[error("invalid {name}: {value:?} (must be {requirement})")]
    InvalidParameter {
        /// Which parameter.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What it must satisfy.
        requirement: &'static str,
    },
    /// A feature of a synthetic texture is too small for its grid to draw:
    /// it would span fewer than `min_cells` grid spacings.
    #[error(
        "unresolved {what}: {size:?} m spans fewer than {min_cells} grid spacings of \
         {spacing:?} m (refine the spacing to at most 1/{min_cells} of it)"
    )]
    Unresolved {
        /// Which feature.
        what: &'static str,
        /// Its size (m).
        size: f64,
        /// The grid's coarser spacing (m).
        spacing: f64,
        /// The fewest grid spacings it must span.
        min_cells: f64,
    },
    /// A file is malformed or truncated.
    #[error("malformed {format} data: {message}")]
    Format {
        /// The file format (`X3P`, `ASCII grid`, `xyz`, `SUR`).
        format: &'static str,
        /// What is wrong.
        message: String,
    },
    /// A file uses a feature of its format that is not supported.
    #[error("unsupported {format} feature: {message}")]
    Unsupported {
        /// The file format.
        format: &'static str,
        /// What is not supported.
        message: String,
    },
    /// A checksum stored in a file does not match its content.
    #[error("MD5 checksum mismatch for {what}: stored {stored}, computed {computed}")]
    Checksum {
        /// Which part of the file.
        what: String,
        /// The stored checksum (hex).
        stored: String,
        /// The checksum of the content (hex).
        computed: String,
    },
    /// Building a cap table failed.
    #[error("cap geometry: {0}")]
    Geometry(#[from] tyreroad_asperity::GeometryError),
    /// An analysis has no data to work on (too few valid points, a map
    /// shorter than a needed length, an empty basin).
    #[error("not enough data: {0}")]
    NotEnoughData(String),
}

impl TextureError {
    pub(crate) fn format(format: &'static str, message: impl Into<String>) -> Self {
        Self::Format {
            format,
            message: message.into(),
        }
    }
    pub(crate) fn unsupported(format: &'static str, message: impl Into<String>) -> Self {
        Self::Unsupported {
            format,
            message: message.into(),
        }
    }
    pub(crate) fn io(path: &std::path::Path, source: std::io::Error) -> Self {
        Self::Io {
            path: path.to_path_buf(),
            source,
        }
    }
}

/// A core validator's error keeps its name, value and requirement (the
/// messages read as they did when the checks lived here); any other core
/// error concerns a map's grid or values.
impl From<tyreroad_core::CoreError> for TextureError {
    fn from(e: tyreroad_core::CoreError) -> Self {
        match e {
            tyreroad_core::CoreError::InvalidValue {
                name,
                value,
                expected,
            } => Self::InvalidParameter {
                name,
                value,
                requirement: expected,
            },
            other => Self::InvalidMap(other.to_string()),
        }
    }
}

/// Write `bytes` to `path` whole or not at all: a temporary file beside it,
/// then a rename.
pub(crate) fn write_atomic(path: &std::path::Path, bytes: &[u8]) -> Result<(), TextureError> {
    use std::io::Write as _;
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d.to_path_buf(),
        _ => PathBuf::from("."),
    };
    let name = path
        .file_name()
        .map(|n| n.to_string_lossy().into_owned())
        .unwrap_or_else(|| "out".into());
    let tmp = dir.join(format!(".{name}.tmp{}", std::process::id()));
    let result = (|| {
        let mut f = std::fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        std::fs::rename(&tmp, path)
    })();
    if let Err(e) = result {
        let _ = std::fs::remove_file(&tmp);
        return Err(TextureError::io(path, e));
    }
    Ok(())
}
