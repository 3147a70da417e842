//! An output folder is swapped in whole (`tyreroad::scenario::output::swap`):
//! a reader that opens the folder while runs land in it reads one set,
//! never a mix of two; a failed commit leaves the old set as it was; the
//! user's files and the checkpoints survive every run.
#![cfg(target_os = "linux")]
#![allow(clippy::unwrap_used)]

use std::collections::BTreeSet;
use std::fs;
use std::os::fd::AsRawFd;
use std::os::unix::fs::MetadataExt;
use std::path::Path;
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};

use tyreroad::scenario::output::{MANIFEST_PREFIX, OutputSet};

/// The files every run writes; odd runs add `extra.csv`, so a stale file
/// left beside the next set would show too.
const FILES: [&str; 4] = ["a.csv", "b.csv", "c.npz", "d.svg"];
const RUNS: usize = 60;

fn run(dir: &Path, generation: usize) {
    let mut set = OutputSet::replacing(dir, "run").unwrap();
    for name in FILES {
        set.write(name, generation.to_string().as_bytes()).unwrap();
    }
    if generation % 2 == 1 {
        set.write("extra.csv", generation.to_string().as_bytes())
            .unwrap();
    }
    set.commit().unwrap();
}

/// What one look at the folder found.
struct Look {
    /// The generations of the run files read.
    generations: BTreeSet<usize>,
    /// Their names.
    names: BTreeSet<String>,
    /// The names the manifest lists.
    listed: BTreeSet<String>,
    /// Whether the folder read was the live one from start to end (else a
    /// swap happened meanwhile and the old tree was being removed under the
    /// reader: it may then see fewer files, never others).
    live: bool,
}

/// One look through a handle on the folder, as a careful reader reads a set;
/// `None` when a file went away under it.
fn look(dir: &Path) -> Option<Look> {
    let handle = fs::File::open(dir).ok()?;
    let inode = handle.metadata().ok()?.ino();
    let base = format!("/proc/self/fd/{}", handle.as_raw_fd());
    let base = Path::new(&base);
    let manifest = fs::read_to_string(base.join(format!("{MANIFEST_PREFIX}run"))).ok()?;
    let mut generations = BTreeSet::new();
    let mut names = BTreeSet::new();
    for entry in fs::read_dir(base).ok()? {
        let name = entry.ok()?.file_name().to_string_lossy().into_owned();
        if FILES.contains(&name.as_str()) || name == "extra.csv" {
            let text = fs::read_to_string(base.join(&name)).ok()?;
            generations.insert(text.parse().unwrap());
            names.insert(name);
        }
    }
    // The user's file and the checkpoints are in every set.
    assert_eq!(fs::read_to_string(base.join("notes.txt")).ok()?, "mine");
    assert_eq!(
        fs::read_to_string(base.join("checkpoint/0.ckpt")).ok()?,
        "state"
    );
    let live = fs::metadata(dir).ok()?.ino() == inode;
    Some(Look {
        generations,
        names,
        listed: manifest.lines().map(str::to_owned).collect(),
        live,
    })
}

#[test]
fn a_reader_polling_during_repeated_runs_never_sees_a_mix() {
    let parent = tempfile::tempdir().unwrap();
    let dir = parent.path().join("out");
    fs::create_dir_all(dir.join("checkpoint")).unwrap();
    fs::write(dir.join("notes.txt"), "mine").unwrap();
    fs::write(dir.join("checkpoint/0.ckpt"), "state").unwrap();
    run(&dir, 0);
    let done = AtomicBool::new(false);
    let (whole, torn) = (AtomicUsize::new(0), AtomicUsize::new(0));
    std::thread::scope(|s| {
        s.spawn(|| {
            while !done.load(Ordering::Acquire) {
                let Some(l) = look(&dir) else {
                    torn.fetch_add(1, Ordering::Relaxed);
                    continue;
                };
                assert!(l.generations.len() <= 1, "a mix: {:?}", l.generations);
                assert!(
                    l.names.is_subset(&l.listed),
                    "{:?} ⊄ {:?}",
                    l.names,
                    l.listed
                );
                if l.live {
                    let g = *l.generations.first().unwrap();
                    assert_eq!(l.names, l.listed, "run {g}: the manifest's files");
                    assert_eq!(l.names.contains("extra.csv"), g % 2 == 1, "run {g}");
                    whole.fetch_add(1, Ordering::Relaxed);
                } else {
                    torn.fetch_add(1, Ordering::Relaxed);
                }
            }
        });
        for generation in 1..=RUNS {
            run(&dir, generation);
        }
        done.store(true, Ordering::Release);
    });
    let (whole, torn) = (whole.into_inner(), torn.into_inner());
    eprintln!("{RUNS} runs: {whole} looks at a live set, {torn} cut short by a swap");
    assert!(whole > 0);
    let last = look(&dir).unwrap();
    assert!(last.live);
    assert_eq!(last.generations, BTreeSet::from([RUNS]));
    // Nothing is left beside the folder.
    let beside: Vec<_> = fs::read_dir(parent.path()).unwrap().collect();
    assert_eq!(beside.len(), 1);
}

#[test]
fn a_failed_commit_leaves_the_old_set_untouched() {
    let parent = tempfile::tempdir().unwrap();
    let dir = parent.path().join("out");
    run(&dir, 1);
    // The user made a directory of the name a run writes: replacing it
    // would delete their files, so the commit is refused.
    fs::create_dir_all(dir.join("e.csv")).unwrap();
    fs::write(dir.join("e.csv/keep.txt"), "mine").unwrap();
    let snapshot = |dir: &Path| -> Vec<(String, String)> {
        let mut files: Vec<_> = fs::read_dir(dir)
            .unwrap()
            .map(|e| e.unwrap().path())
            .filter(|p| p.is_file())
            .map(|p| {
                let text = fs::read_to_string(&p).unwrap();
                (p.file_name().unwrap().to_string_lossy().into_owned(), text)
            })
            .collect();
        files.sort();
        files
    };
    let before = snapshot(&dir);
    let mut set = OutputSet::replacing(&dir, "run").unwrap();
    set.write("a.csv", b"2").unwrap();
    set.write("e.csv", b"2").unwrap();
    let error = set.commit().unwrap_err().to_string();
    assert!(
        error.contains("e.csv") && error.contains("directory"),
        "{error}"
    );
    assert_eq!(snapshot(&dir), before);
    assert_eq!(
        fs::read_to_string(dir.join("e.csv/keep.txt")).unwrap(),
        "mine"
    );
    let beside: Vec<_> = fs::read_dir(parent.path()).unwrap().collect();
    assert_eq!(beside.len(), 1, "no sibling left");
    // The failed set's staging went with it.
    assert!(
        fs::read_dir(&dir).unwrap().all(|e| !e
            .unwrap()
            .file_name()
            .to_string_lossy()
            .contains("staging"))
    );
}

#[test]
fn a_folder_that_is_a_symbolic_link_lands_file_by_file_and_stays_a_link() {
    let parent = tempfile::tempdir().unwrap();
    let real = parent.path().join("real");
    fs::create_dir_all(&real).unwrap();
    let link = parent.path().join("out");
    std::os::unix::fs::symlink(&real, &link).unwrap();
    // Regression (adversarial run, 2026-11-29): such a folder was written
    // file by file without a word; the set says so before it lands, and a
    // plain folder does not.
    let note = OutputSet::new(&link).unwrap().landing_note();
    assert!(
        note.as_deref()
            .is_some_and(|n| n.contains("one file at a time") && n.contains("symbolic link")),
        "{note:?}"
    );
    assert_eq!(OutputSet::new(&real).unwrap().landing_note(), None);
    run(&link, 1);
    run(&link, 2);
    assert!(fs::symlink_metadata(&link).unwrap().is_symlink());
    assert_eq!(fs::read_to_string(real.join("a.csv")).unwrap(), "2");
    assert!(
        !real.join("extra.csv").exists(),
        "the stale file is removed"
    );
}
