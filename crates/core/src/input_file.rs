//! Input files are read only when they are files: a FIFO blocks a
//! reader forever and `/dev/zero` fills memory, both behind a name a
//! reader would take for a height map or a scan.

use std::io::{Error, ErrorKind, Read};
use std::path::Path;

/// The largest input file read whole (8 GiB): a map of [`crate::MAX_CELLS`]
/// heights as `f64`. Windowed readers stream larger ones.
pub const MAX_INPUT_BYTES: u64 = 8 << 30;

/// The length of `path` (symbolic links followed) if it is a regular file,
/// for readers that stream it rather than read it whole.
///
/// # Errors
/// The metadata's I/O error, or [`ErrorKind::InvalidInput`] naming what
/// the path is instead (a directory, a FIFO, a device).
pub fn check_input_file(path: &Path) -> Result<u64, Error> {
    let meta = std::fs::metadata(path)?;
    if meta.is_dir() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "a directory, not a file",
        ));
    }
    if !meta.is_file() {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            "not a regular file (a pipe, socket or device): give the path of a file",
        ));
    }
    Ok(meta.len())
}

/// The bytes of the regular file `path` ([`check_input_file`]), of at most
/// [`MAX_INPUT_BYTES`] (even if the file grows while it is read).
///
/// # Errors
/// As [`check_input_file`], [`ErrorKind::InvalidInput`] for a larger
/// file, and the read's I/O error.
pub fn read_input_file(path: &Path) -> Result<Vec<u8>, Error> {
    let len = check_input_file(path)?;
    if len > MAX_INPUT_BYTES {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("{len} bytes, past the {MAX_INPUT_BYTES} an input file read whole may hold"),
        ));
    }
    let mut bytes = Vec::with_capacity(usize::try_from(len).unwrap_or(0));
    std::fs::File::open(path)?
        .take(MAX_INPUT_BYTES + 1)
        .read_to_end(&mut bytes)?;
    if bytes.len() as u64 > MAX_INPUT_BYTES {
        return Err(Error::new(
            ErrorKind::InvalidInput,
            format!("grew past the {MAX_INPUT_BYTES} bytes an input file may hold while read"),
        ));
    }
    Ok(bytes)
}

/// The text of the regular file `path` ([`read_input_file`]).
///
/// # Errors
/// As [`read_input_file`], and [`ErrorKind::InvalidData`] naming the line
/// and byte where the text stops being UTF-8.
pub fn read_input_text(path: &Path) -> Result<String, Error> {
    String::from_utf8(read_input_file(path)?).map_err(|e| {
        let bytes = e.as_bytes();
        let at = e.utf8_error().valid_up_to();
        let line = 1 + bytes[..at].iter().filter(|&&b| b == b'\n').count();
        Error::new(
            ErrorKind::InvalidData,
            format!(
                "not UTF-8 text: line {line}, byte {at} (0x{:02x}); save the file as UTF-8",
                bytes[at]
            ),
        )
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn directories_and_devices_are_not_read_files_are() {
        let dir = std::env::temp_dir();
        let e = read_input_file(&dir).expect_err("a directory");
        assert_eq!(e.kind(), ErrorKind::InvalidInput);
        assert!(e.to_string().contains("directory"), "{e}");
        if Path::new("/dev/zero").exists() {
            let e = read_input_file(Path::new("/dev/zero")).expect_err("a device");
            assert!(e.to_string().contains("not a regular file"), "{e}");
        }
        let file = dir.join(format!("tyreroad-core-input-{}", std::process::id()));
        std::fs::write(&file, b"nx 1").expect("a temporary file");
        assert_eq!(read_input_file(&file).expect("a file"), b"nx 1");
        std::fs::write(&file, b"# caf\xe9\nnx 1").expect("a temporary file");
        let e = read_input_text(&file).expect_err("Latin-1");
        assert!(e.to_string().contains("line 1, byte 5 (0xe9)"), "{e}");
        std::fs::remove_file(&file).expect("removed");
        assert_eq!(
            read_input_file(&file).expect_err("gone").kind(),
            ErrorKind::NotFound
        );
    }
}
