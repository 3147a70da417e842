//! Landing an output set whole: the folder is rebuilt beside itself and
//! swapped in.
//!
//! At commit a fresh sibling `PARENT/.tyreroad-next-NAME-XXXXXX` receives
//! hard links to everything in the folder that must survive (the files of
//! other producers and of the user, the `checkpoint/` tree, mirrored
//! directory by directory), then the staged files and the producer's
//! manifest. The two directories are then exchanged in one step
//! (`renameat2(RENAME_EXCHANGE)`, Linux) and the old tree, now at the
//! sibling's path, is removed. A reader that opened the folder reads one
//! set, old or new, never a mix; a failure before the exchange leaves the
//! folder untouched (the sibling is removed).
//!
//! Where the exchange is not available (another OS, a file system without
//! it) the old folder is first renamed aside, then the new one into place:
//! for that instant the folder is absent, never mixed, and a run killed in
//! that instant is undone by the next ([`prepare`] renames the old folder
//! back). Where no sibling can be made (the folder is a symbolic link, the
//! working directory or holds it, its parent is not writable, or a hard
//! link is refused) the files land one rename each, as before: each file
//! whole, the set not.
//!
//! Nothing a run of ours did not write is ever removed: the hard links
//! keep every foreign file, and a staged name that is a directory in the
//! folder is refused rather than replaced.

use std::fs;
use std::io;
use std::path::{Path, PathBuf};
use std::sync::Mutex;

use super::{MANIFEST_PREFIX, STAGING_PREFIX};
use crate::scenario::ScenarioError;

/// The name prefix of the sibling a commit builds (`NEXT_PREFIX` + the
/// folder's name + `-` + six random characters).
pub const NEXT_PREFIX: &str = ".tyreroad-next-";
/// The name prefix of the old folder moved aside where no exchange exists.
pub const OLD_PREFIX: &str = ".tyreroad-old-";
/// The random characters at the end of a sibling's name.
const RANDOM_CHARS: usize = 6;

/// Commits of this process one at a time: two sets landing in one folder
/// at once would each rebuild it without the other's files.
static LANDING: Mutex<()> = Mutex::new(());

fn lock() -> std::sync::MutexGuard<'static, ()> {
    // A panic while landing leaves nothing the lock protects half-done in
    // memory: the state is on disk, and `prepare` tidies it.
    LANDING
        .lock()
        .unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Where and how a folder can be swapped: its real path, its parent and its
/// name; `None` when it must be landed file by file.
fn swap_site(dir: &Path) -> Option<(PathBuf, PathBuf, String)> {
    if fs::symlink_metadata(dir).ok()?.file_type().is_symlink() {
        return None;
    }
    let real = fs::canonicalize(dir).ok()?;
    // Swapping the working directory (or one holding it) would leave this
    // process, and a shell started there, in the removed old tree.
    let cwd = std::env::current_dir().ok()?;
    let cwd = fs::canonicalize(cwd).unwrap_or_default();
    if cwd.starts_with(&real) {
        return None;
    }
    let name = real.file_name()?.to_str()?.to_owned();
    let parent = real.parent()?.to_path_buf();
    Some((real, parent, name))
}

/// Whether a set committed to `dir` lands whole (swapped in) rather than
/// file by file: `dir` can be swapped (not a symbolic link, not the working
/// directory nor holding it) and a sibling can be
/// made beside it (probed: one made and removed).
pub fn lands_whole(dir: &Path) -> bool {
    swap_site(dir).is_some_and(|(_, parent, name)| {
        tempfile::Builder::new()
            .prefix(&format!("{NEXT_PREFIX}{name}-"))
            .rand_bytes(RANDOM_CHARS)
            .tempdir_in(&parent)
            .is_ok()
    })
}

/// Whether `entry` is a sibling `prefix` + `name` + `-` + random characters.
fn is_sibling(entry: &str, prefix: &str, name: &str) -> bool {
    entry
        .strip_prefix(prefix)
        .and_then(|rest| rest.strip_prefix(name))
        .and_then(|rest| rest.strip_prefix('-'))
        .is_some_and(|tail| {
            tail.len() == RANDOM_CHARS && tail.chars().all(|c| c.is_ascii_alphanumeric())
        })
}

/// Tidies what a killed commit into `dir` left beside it: an old folder
/// moved aside while the new one was not yet in place is moved back (the
/// folder as it was before that run), and every other sibling is removed.
/// Called before the run stages anything.
pub fn prepare(dir: &Path) -> Result<(), ScenarioError> {
    let _landing = lock();
    let dir = fs::canonicalize(dir)
        .or_else(|_| std::path::absolute(dir))
        .map_err(ScenarioError::io("resolving", dir))?;
    let dir = dir.as_path();
    let Some(parent) = dir.parent() else {
        return Ok(());
    };
    let Some(name) = dir.file_name().and_then(|n| n.to_str()) else {
        return Ok(());
    };
    let Ok(entries) = fs::read_dir(parent) else {
        return Ok(());
    };
    let mut next = Vec::new();
    let mut old = Vec::new();
    for entry in entries.flatten() {
        let entry_name = entry.file_name().to_string_lossy().into_owned();
        if is_sibling(&entry_name, NEXT_PREFIX, name) {
            next.push(entry.path());
        } else if is_sibling(&entry_name, OLD_PREFIX, name) {
            old.push(entry.path());
        }
    }
    if !dir.exists()
        && let Some(aside) = old.pop()
    {
        fs::rename(&aside, dir).map_err(ScenarioError::io("moving back", &aside))?;
    }
    for stale in next.into_iter().chain(old) {
        fs::remove_dir_all(&stale).map_err(ScenarioError::io("removing stale", &stale))?;
    }
    Ok(())
}

/// What one commit lands: the staged files and the producer's manifest.
pub struct Landing<'a> {
    /// The output folder.
    pub dir: &'a Path,
    /// The staging directory inside it.
    pub staging: &'a Path,
    /// The staged names, in order.
    pub names: &'a [String],
    /// The producer's manifest file name, when the set replaces its last.
    pub manifest: Option<&'a str>,
}

impl Landing<'_> {
    /// Lands the set (see the module doc) and returns the final paths of the
    /// staged files, in order.
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if a staged name is a directory in the folder,
    /// or a file cannot be moved; the folder is then as it was (file by
    /// file: the files moved so far stay).
    pub fn land(&self) -> Result<Vec<PathBuf>, ScenarioError> {
        let _landing = lock();
        for name in self.names {
            let to = self.dir.join(name);
            if fs::symlink_metadata(&to).is_ok_and(|m| m.is_dir()) {
                return Err(ScenarioError::Io {
                    action: "replacing",
                    path: to,
                    source: io::Error::new(
                        io::ErrorKind::AlreadyExists,
                        "a directory not written by this run has the name of an output file",
                    ),
                });
            }
        }
        let stale = self.stale()?;
        if let Some((real, parent, name)) = swap_site(self.dir)
            && let Ok(next) = tempfile::Builder::new()
                .prefix(&format!("{NEXT_PREFIX}{name}-"))
                .rand_bytes(RANDOM_CHARS)
                .tempdir_in(&parent)
        {
            let keep = |entry: &str| {
                !entry.starts_with(STAGING_PREFIX)
                    && !entry.starts_with(NEXT_PREFIX)
                    && !entry.starts_with(OLD_PREFIX)
                    && Some(entry) != self.manifest
                    && !self.names.iter().any(|n| n == entry)
                    && !stale.iter().any(|n| n == entry)
            };
            if mirror(&real, next.path(), &keep).is_ok() {
                self.fill(next.path())?;
                let permissions = fs::metadata(&real)
                    .map_err(ScenarioError::io("reading", &real))?
                    .permissions();
                fs::set_permissions(next.path(), permissions)
                    .map_err(ScenarioError::io("setting permissions of", next.path()))?;
                swap(&real, next.path(), &parent, &name)?;
                // `next` now names the old tree: dropping it removes it.
                drop(next);
                return Ok(self.placed());
            }
        }
        self.land_file_by_file(&stale)
    }

    /// The names the producer's previous set listed that this one does not
    /// write, and that are files (a directory the user put there under
    /// such a name stays). The list is read as untrusted text: plain
    /// names only.
    fn stale(&self) -> Result<Vec<String>, ScenarioError> {
        let Some(manifest) = self.manifest else {
            return Ok(Vec::new());
        };
        let path = self.dir.join(manifest);
        let previous = match fs::read_to_string(&path) {
            Ok(text) => text,
            Err(e) if e.kind() == io::ErrorKind::NotFound => return Ok(Vec::new()),
            Err(e) => return Err(ScenarioError::io("reading", &path)(e)),
        };
        Ok(previous
            .lines()
            .filter(|old| {
                !old.is_empty()
                    && !old.contains(['/', '\\'])
                    && *old != ".."
                    && *old != "."
                    && !old.starts_with(MANIFEST_PREFIX)
                    && !self.names.iter().any(|n| n == old)
                    && fs::symlink_metadata(self.dir.join(old)).is_ok_and(|m| !m.is_dir())
            })
            .map(str::to_owned)
            .collect())
    }

    /// Moves the staged files into `into`, then writes the manifest there.
    fn fill(&self, into: &Path) -> Result<(), ScenarioError> {
        for name in self.names {
            let from = self.staging.join(name);
            if from.exists() {
                let to = into.join(name);
                fs::rename(&from, &to).map_err(ScenarioError::io("moving into place", &to))?;
            }
        }
        if let Some(manifest) = self.manifest {
            let list: String = self.names.iter().map(|n| format!("{n}\n")).collect();
            let path = into.join(manifest);
            fs::write(&path, list).map_err(ScenarioError::io("writing", &path))?;
        }
        Ok(())
    }

    /// The final paths of the files that were staged and landed.
    fn placed(&self) -> Vec<PathBuf> {
        self.names
            .iter()
            .map(|n| self.dir.join(n))
            .filter(|p| p.exists())
            .collect()
    }

    /// Each file by one rename (see the module doc): stale files first, the
    /// manifest last, so that it never names a file not yet in place.
    fn land_file_by_file(&self, stale: &[String]) -> Result<Vec<PathBuf>, ScenarioError> {
        for old in stale {
            let path = self.dir.join(old);
            match fs::remove_file(&path) {
                Ok(()) => {}
                Err(e) if e.kind() == io::ErrorKind::NotFound => {}
                Err(e) => return Err(ScenarioError::io("removing stale", &path)(e)),
            }
        }
        let mut written = Vec::with_capacity(self.names.len());
        for name in self.names {
            let from = self.staging.join(name);
            if !from.exists() {
                continue;
            }
            let to = self.dir.join(name);
            fs::rename(&from, &to).map_err(ScenarioError::io("moving into place", &to))?;
            written.push(to);
        }
        if let Some(manifest) = self.manifest {
            let list: String = self.names.iter().map(|n| format!("{n}\n")).collect();
            let from = self.staging.join(manifest);
            fs::write(&from, list).map_err(ScenarioError::io("writing", &from))?;
            let to = self.dir.join(manifest);
            fs::rename(&from, &to).map_err(ScenarioError::io("moving into place", &to))?;
        }
        Ok(written)
    }
}

/// Hard-links every entry of `from` that `keep` accepts into `to`,
/// directories recreated (with their permissions) and filled the same way
/// (every entry kept below the top). A hard link never follows a symbolic
/// link: a link stays a link.
fn mirror(from: &Path, to: &Path, keep: &dyn Fn(&str) -> bool) -> io::Result<()> {
    for entry in fs::read_dir(from)? {
        let entry = entry?;
        if !keep(&entry.file_name().to_string_lossy()) {
            continue;
        }
        let target = to.join(entry.file_name());
        if entry.file_type()?.is_dir() {
            fs::create_dir(&target)?;
            mirror(&entry.path(), &target, &|_| true)?;
            fs::set_permissions(&target, entry.metadata()?.permissions())?;
        } else {
            fs::hard_link(entry.path(), &target)?;
        }
    }
    Ok(())
}

/// Puts `next` at `real` and the old tree at `next`'s path.
fn swap(real: &Path, next: &Path, parent: &Path, name: &str) -> Result<(), ScenarioError> {
    #[cfg(target_os = "linux")]
    {
        use rustix::fs::{CWD, RenameFlags, renameat_with};
        match renameat_with(CWD, real, CWD, next, RenameFlags::EXCHANGE) {
            Ok(()) => return Ok(()),
            Err(e)
                if ![
                    rustix::io::Errno::INVAL,
                    rustix::io::Errno::NOSYS,
                    rustix::io::Errno::OPNOTSUPP,
                ]
                .contains(&e) =>
            {
                return Err(ScenarioError::io("swapping in", real)(e.into()));
            }
            Err(_) => {}
        }
    }
    // No exchange here: the old folder aside (onto an empty directory, which
    // a directory rename may replace), then the new one in.
    let aside = tempfile::Builder::new()
        .prefix(&format!("{OLD_PREFIX}{name}-"))
        .rand_bytes(RANDOM_CHARS)
        .tempdir_in(parent)
        .map_err(ScenarioError::io("creating a directory in", parent))?
        .keep();
    fs::rename(real, &aside).map_err(ScenarioError::io("moving aside", real))?;
    if let Err(e) = fs::rename(next, real) {
        fs::rename(&aside, real).map_err(ScenarioError::io("moving back", &aside))?;
        return Err(ScenarioError::io("moving into place", real)(e));
    }
    fs::rename(&aside, next).map_err(ScenarioError::io("moving", &aside))
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    #[test]
    fn siblings_are_told_apart_by_their_exact_name() {
        assert!(is_sibling(".tyreroad-next-out-a1B2c3", NEXT_PREFIX, "out"));
        assert!(!is_sibling(
            ".tyreroad-next-out-2-a1B2c3",
            NEXT_PREFIX,
            "out"
        ));
        assert!(!is_sibling(".tyreroad-next-out-a1B2c", NEXT_PREFIX, "out"));
        assert!(!is_sibling(".tyreroad-old-out-a1B2c3", NEXT_PREFIX, "out"));
    }

    #[test]
    fn a_folder_moved_aside_by_a_killed_commit_is_moved_back() {
        let parent = tempfile::tempdir().unwrap();
        let dir = parent.path().join("out");
        let aside = parent.path().join(format!("{OLD_PREFIX}out-abc123"));
        let next = parent.path().join(format!("{NEXT_PREFIX}out-xyz789"));
        fs::create_dir_all(&aside).unwrap();
        fs::write(aside.join("a.csv"), "old").unwrap();
        fs::create_dir_all(&next).unwrap();
        fs::write(next.join("a.csv"), "new").unwrap();
        prepare(&dir).unwrap();
        assert_eq!(fs::read_to_string(dir.join("a.csv")).unwrap(), "old");
        assert_eq!(fs::read_dir(parent.path()).unwrap().count(), 1);
    }

    #[cfg(unix)]
    #[test]
    fn a_mirror_links_files_and_rebuilds_directories() {
        let parent = tempfile::tempdir().unwrap();
        let (from, to) = (parent.path().join("a"), parent.path().join("b"));
        fs::create_dir_all(from.join("checkpoint")).unwrap();
        fs::create_dir_all(&to).unwrap();
        fs::write(from.join("checkpoint/0.ckpt"), "c").unwrap();
        fs::write(from.join("skip.csv"), "s").unwrap();
        fs::write(from.join("keep.txt"), "k").unwrap();
        mirror(&from, &to, &|n| n != "skip.csv").unwrap();
        assert_eq!(
            fs::read_to_string(to.join("checkpoint/0.ckpt")).unwrap(),
            "c"
        );
        assert_eq!(fs::read_to_string(to.join("keep.txt")).unwrap(), "k");
        assert!(!to.join("skip.csv").exists());
        // A link, not a copy: one inode, two names.
        use std::os::unix::fs::MetadataExt;
        assert_eq!(fs::metadata(to.join("keep.txt")).unwrap().nlink(), 2);
    }
}
