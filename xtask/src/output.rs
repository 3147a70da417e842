//! Outputs are written whole or not at all: to a temporary file beside the
//! target, then renamed over it.

use std::fs;
use std::io::Write;
use std::path::Path;

use anyhow::{Context, Result};

/// Writes `bytes` to `path` atomically (same-directory temporary + rename).
pub fn write_atomic(path: &Path, bytes: &[u8]) -> Result<()> {
    let dir = path
        .parent()
        .filter(|p| !p.as_os_str().is_empty())
        .unwrap_or(Path::new("."));
    fs::create_dir_all(dir).with_context(|| format!("creating {}", dir.display()))?;
    let name = path
        .file_name()
        .with_context(|| format!("{} has no file name", path.display()))?;
    let tmp = dir.join(format!(
        ".{}.tmp-{}",
        name.to_string_lossy(),
        std::process::id()
    ));
    let result = (|| -> Result<()> {
        let mut f = fs::File::create(&tmp)?;
        f.write_all(bytes)?;
        f.sync_all()?;
        fs::rename(&tmp, path)?;
        Ok(())
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result.with_context(|| format!("writing {}", path.display()))
}

/// A CSV table built in memory, then written atomically.
pub struct Csv {
    text: String,
}

impl Csv {
    /// A table with this header line (comma-separated names).
    pub fn new(header: &str) -> Self {
        Self {
            text: format!("{header}\n"),
        }
    }

    /// Appends a row of already-formatted fields.
    pub fn row(&mut self, fields: &[String]) {
        self.text.push_str(&fields.join(","));
        self.text.push('\n');
    }

    /// Writes the table.
    pub fn write(&self, path: &Path) -> Result<()> {
        write_atomic(path, self.text.as_bytes())
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn atomic_write_replaces_whole_and_leaves_no_temporary() -> Result<()> {
        let dir = std::env::temp_dir().join(format!("tyreroad-out-{}", std::process::id()));
        let path = dir.join("a.csv");
        write_atomic(&path, b"one\n")?;
        write_atomic(&path, b"two\n")?;
        assert_eq!(fs::read_to_string(&path)?, "two\n");
        let leftovers = fs::read_dir(&dir)?.filter(|e| {
            e.as_ref()
                .map(|e| e.file_name().to_string_lossy().contains(".tmp-"))
                .unwrap_or(false)
        });
        assert_eq!(leftovers.count(), 0);
        // A directory in the way: an error, no panic, no partial file.
        assert!(write_atomic(&dir, b"x").is_err());
        fs::remove_dir_all(&dir)?;
        Ok(())
    }
}
