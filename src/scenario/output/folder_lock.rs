//! The lock a run holds on its output folder while it writes there: two
//! runs into one folder at once would remove each other's staging and swap
//! the folder over each other.

use std::fs;
use std::path::{Path, PathBuf};

use crate::scenario::ScenarioError;

/// The file that a run holds locked in its output folder while it writes
/// there (an advisory `flock`), removed when the run's sets are done.
pub const LOCK_FILE: &str = ".tyreroad-lock";

/// A held lock on an output folder: the file is unlinked before it is
/// closed, and a lock taken on a file that was unlinked meanwhile is taken
/// again ([`lock_folder`]), so no two runs ever hold one folder.
#[derive(Debug)]
pub(super) struct FolderLock {
    path: PathBuf,
    _file: fs::File,
}

impl Drop for FolderLock {
    fn drop(&mut self) {
        // Still held here: a run that opened this file before the unlink
        // finds it gone once it gets the lock, and opens the new one.
        let _ = fs::remove_file(&self.path);
    }
}

/// Whether `file` is still the one at `path` (not unlinked meanwhile).
fn still_linked(file: &fs::File, path: &Path) -> bool {
    #[cfg(unix)]
    {
        use std::os::unix::fs::MetadataExt;
        match (file.metadata(), fs::metadata(path)) {
            (Ok(a), Ok(b)) => (a.dev(), a.ino()) == (b.dev(), b.ino()),
            _ => false,
        }
    }
    #[cfg(not(unix))]
    {
        let _ = (file, path);
        true
    }
}

/// The lock on `dir` ([`LOCK_FILE`]). Two runs writing into one folder at
/// once removed each other's staging and swapped the folder over each
/// other (a run reported files written that were not there): the second
/// (another process, or another set of this one: a folder's rebuild
/// carries no other set's staging) is refused instead. A file system
/// without locks runs unlocked, as before.
pub(super) fn lock_folder(dir: &Path) -> Result<FolderLock, ScenarioError> {
    let path = dir.join(LOCK_FILE);
    let busy = || ScenarioError::Io {
        action: "writing outputs into",
        path: dir.to_path_buf(),
        source: std::io::Error::new(
            std::io::ErrorKind::ResourceBusy,
            "another run is writing into this folder: wait for it to end, or give another \
             output folder",
        ),
    };
    // A few rounds at most: each retry means another run unlinked the file
    // between this open and this lock, i.e. it just ended.
    for _ in 0..8 {
        let file = fs::OpenOptions::new()
            .create(true)
            .truncate(false)
            .write(true)
            .open(&path)
            .map_err(ScenarioError::io("opening the run's lock", &path))?;
        match file.try_lock() {
            Ok(()) if !still_linked(&file, &path) => continue,
            Ok(()) => {}
            Err(fs::TryLockError::WouldBlock) => return Err(busy()),
            Err(fs::TryLockError::Error(e)) if e.kind() == std::io::ErrorKind::Unsupported => {}
            Err(fs::TryLockError::Error(e)) => return Err(ScenarioError::io("locking", &path)(e)),
        }
        return Ok(FolderLock {
            path: path.clone(),
            _file: file,
        });
    }
    Err(busy())
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::scenario::output::OutputSet;

    /// Found by an adversarial run (2026-12-01): two runs into one folder
    /// at once removed each other's staging, and one said "written" of
    /// files that were not there. Another holder of the folder's lock
    /// (another process, or another set) is refused; the lock file goes
    /// with the set.
    #[test]
    fn a_second_run_into_a_folder_being_written_is_refused() {
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        fs::create_dir_all(&dir).unwrap();
        let other = fs::File::create(dir.join(LOCK_FILE)).unwrap();
        other.try_lock().unwrap();
        let e = OutputSet::new(&dir).unwrap_err().to_string();
        assert!(e.contains("another run is writing into this folder"), "{e}");
        drop(other);
        let mut first = OutputSet::new(&dir).unwrap();
        first.write("a.csv", b"one\n").unwrap();
        let e = OutputSet::new(&dir).unwrap_err().to_string();
        assert!(e.contains("another run is writing into this folder"), "{e}");
        // A new folder is locked from its creation.
        let fresh = parent.path().join("new");
        let held = OutputSet::new(&fresh).unwrap();
        assert!(OutputSet::new(&fresh).is_err());
        drop(held);
        first.commit().unwrap();
        let names: Vec<String> = fs::read_dir(&dir)
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        assert_eq!(names, ["a.csv"]);
        assert_eq!(fs::read_dir(&fresh).unwrap().count(), 0);
    }
}
