//! MPI runs against the single process (feature `mpi`; needs `mpirun`, run
//! by `.ci/run`): `mpirun -np 1, 2, 3 xtask mpi-run` on a rolling fixture
//! gives the time signals of `xtask run` to 1e-9 relative and identical
//! spectra files, and the records written as they arrive give every file
//! of the records gathered first, to the byte; a rank's checkpoint is reused by a job on another number
//! of ranks; a sweep of 12 runs over 3 ranks writes the rayon run's table;
//! a `.npy` texture, read by windows on every rank, gives the single
//! process's signals on 2 and 3 ranks.
#![cfg(feature = "mpi")]
#![allow(clippy::unwrap_used)]

use std::path::{Path, PathBuf};
use std::process::Command;

const XTASK: &str = env!("CARGO_BIN_EXE_xtask");

fn fixtures() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../fixtures")
}

fn scratch(name: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("tyreroad-mpi-{name}-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).unwrap();
    dir
}

fn run(cmd: &mut Command) -> String {
    let out = cmd.output().unwrap();
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    assert!(
        out.status.success(),
        "{cmd:?}\n{text}\n{}",
        String::from_utf8_lossy(&out.stderr)
    );
    text
}

/// `mpirun` as CI runs it: as root allowed, more ranks than cores allowed.
fn mpirun(ranks: usize) -> Command {
    let mut c = Command::new("mpirun");
    c.args(["--oversubscribe", "-np", &ranks.to_string(), XTASK])
        .env("OMPI_ALLOW_RUN_AS_ROOT", "1")
        .env("OMPI_ALLOW_RUN_AS_ROOT_CONFIRM", "1");
    c
}

/// The CSV's columns by name.
fn columns(path: &Path) -> Vec<(String, Vec<String>)> {
    let text = std::fs::read_to_string(path).unwrap();
    let mut lines = text.lines();
    let head: Vec<String> = lines.next().unwrap().split(',').map(String::from).collect();
    let mut cols: Vec<(String, Vec<String>)> = head.into_iter().map(|h| (h, vec![])).collect();
    for line in lines {
        for (c, cell) in cols.iter_mut().zip(line.split(',')) {
            c.1.push(cell.to_string());
        }
    }
    cols
}

/// Every signal column equal to 1e-9 relative (plus half a unit in the last
/// printed digit: `*_force_n`/approach print 13 digits, the others 10).
fn assert_signals_equal(a: &Path, b: &Path, signal_columns: &[&str]) -> f64 {
    let (ca, cb) = (columns(a), columns(b));
    let mut worst = 0.0f64;
    for name in signal_columns {
        let col = |c: &[(String, Vec<String>)]| c.iter().find(|x| x.0 == *name).unwrap().1.clone();
        let (va, vb) = (col(&ca), col(&cb));
        assert_eq!(va.len(), vb.len(), "{name}");
        for (x, y) in va.iter().zip(&vb) {
            let (x, y): (f64, f64) = (x.parse().unwrap(), y.parse().unwrap());
            let scale = x.abs().max(y.abs());
            let printed = if name.ends_with("force_n") || name.starts_with("approach") {
                5e-13
            } else {
                5e-10
            };
            let rel = (x - y).abs() / scale.max(1e-300);
            worst = worst.max(rel);
            assert!(
                rel <= 1e-9 + printed,
                "{name}: {x} vs {y} in {}",
                b.display()
            );
        }
    }
    worst
}

/// The names in a folder, sorted (checkpoints left out).
fn names(dir: &Path) -> Vec<String> {
    let mut names: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .filter(|n| n != "checkpoint")
        .collect();
    names.sort();
    names
}

/// The same files in both folders, every one the same bytes.
fn assert_same_files(a: &Path, b: &Path) {
    assert_eq!(names(a), names(b));
    for name in names(a) {
        let same = std::fs::read(a.join(&name)).unwrap() == std::fs::read(b.join(&name)).unwrap();
        assert!(
            same,
            "{name} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
}

#[test]
fn rolling_on_1_2_3_ranks_equals_the_single_process() {
    let dir = scratch("roll");
    let scenario = fixtures().join("rolling_small.toml");
    let single = dir.join("single");
    run(Command::new(XTASK)
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(&single));
    for ranks in [1, 2, 3] {
        let out = dir.join(format!("np{ranks}"));
        run(mpirun(ranks)
            .arg("mpi-run")
            .arg(&scenario)
            .arg("--out")
            .arg(&out));
        let worst = assert_signals_equal(
            &single.join("time_signals.csv"),
            &out.join("time_signals.csv"),
            &[
                "time_s",
                "position_m",
                "total_force_n",
                "approach_m",
                "contact_area_m2",
                "n_contacts",
            ],
        );
        assert_signals_equal(
            &single.join("sensors.csv"),
            &out.join("sensors.csv"),
            &["centre_n"],
        );
        println!("{ranks} ranks: largest relative difference {worst:.2e}");
        for same in ["third_octave.csv", "third_octave_bands.csv", "road.npz"] {
            let same_bytes =
                std::fs::read(single.join(same)).unwrap() == std::fs::read(out.join(same)).unwrap();
            assert!(same_bytes, "{same} differs on {ranks} ranks");
        }
        // Rank 0 writes the records as they arrive; gathering them all
        // first (`--gather`, the same parts on the same ranks, so the same
        // records) writes every file, hidden ones included, to the byte.
        let gathered = dir.join(format!("np{ranks}_gathered"));
        run(mpirun(ranks)
            .arg("mpi-run")
            .arg(&scenario)
            .arg("--out")
            .arg(&gathered)
            .arg("--gather"));
        assert_same_files(&gathered, &out);
        assert_eq!(names(&single), names(&out), "{ranks} ranks");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Each rank checkpoints its own part: a job on 2 ranks, then one of its
/// files removed (as if that rank had been killed before writing) and the
/// job rerun on 3 ranks: the surviving part is resumed, the lost one
/// recomputed, and the outputs are the uninterrupted job's.
#[test]
fn a_job_resumes_from_its_ranks_checkpoints() {
    let dir = scratch("resume");
    let text = std::fs::read_to_string(fixtures().join("rolling_small.toml")).unwrap();
    let scenario = dir.join("rolling_ck.toml");
    std::fs::write(
        &scenario,
        text.replace("checkpoint = false", "checkpoint = true"),
    )
    .unwrap();
    let out = dir.join("out");
    run(mpirun(2)
        .arg("mpi-run")
        .arg(&scenario)
        .arg("--out")
        .arg(&out));
    let first = dir.join("first_time_signals.csv");
    std::fs::copy(out.join("time_signals.csv"), &first).unwrap();
    let mut files: Vec<PathBuf> = std::fs::read_dir(out.join("checkpoint"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ckpt"))
        .collect();
    files.sort();
    assert_eq!(files.len(), 2, "{files:?}");
    std::fs::remove_file(&files[1]).unwrap();
    let printed = run(mpirun(3)
        .arg("mpi-run")
        .arg(&scenario)
        .arg("--out")
        .arg(&out));
    assert!(printed.contains("resumed 20 of 40 steps"), "{printed}");
    assert_signals_equal(
        &first,
        &out.join("time_signals.csv"),
        &[
            "time_s",
            "total_force_n",
            "approach_m",
            "contact_area_m2",
            "n_contacts",
        ],
    );
    std::fs::remove_dir_all(&dir).unwrap();
}

#[test]
fn a_sweep_over_3_ranks_writes_the_rayon_table() {
    let dir = scratch("sweep");
    let sweep = fixtures().join("sweep_small.toml");
    let (local, ranks) = (dir.join("rayon"), dir.join("mpi"));
    run(Command::new(XTASK)
        .arg("sweep")
        .arg(&sweep)
        .arg("--out")
        .arg(&local)
        .args(["--threads", "2"]));
    run(mpirun(3)
        .arg("sweep")
        .arg(&sweep)
        .arg("--out")
        .arg(&ranks)
        .arg("--mpi"));
    let table = std::fs::read_to_string(local.join("sweep.csv")).unwrap();
    assert_eq!(table.lines().count(), 13, "{table}");
    assert!(
        table.lines().skip(1).all(|l| l.ends_with(',')),
        "a run failed:\n{table}"
    );
    assert_eq!(
        std::fs::read_to_string(ranks.join("sweep.csv")).unwrap(),
        table
    );
    for k in 0..12 {
        let name = format!("run_{k:04}/third_octave.csv");
        let same_bytes =
            std::fs::read(local.join(&name)).unwrap() == std::fs::read(ranks.join(&name)).unwrap();
        assert!(same_bytes, "{name} differs");
    }
    std::fs::remove_dir_all(&dir).unwrap();
}

/// Writes `map` as a float64 C-order `.npy` with its spacing sidecar.
fn write_npy(map: &tyreroad::texture::HeightMap, path: &Path) {
    use std::io::Write;
    let mut header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, {}), }}",
        map.ny(),
        map.nx()
    );
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut f = std::fs::File::create(path).unwrap();
    f.write_all(b"\x93NUMPY\x01\x00").unwrap();
    f.write_all(&(header.len() as u16).to_le_bytes()).unwrap();
    f.write_all(header.as_bytes()).unwrap();
    let bytes: Vec<u8> = map.heights().iter().flat_map(|v| v.to_le_bytes()).collect();
    f.write_all(&bytes).unwrap();
    let mut sidecar = path.as_os_str().to_os_string();
    sidecar.push(".spacing");
    std::fs::write(sidecar, format!("{:e} {:e}\n", map.dx(), map.dy())).unwrap();
}

/// A `[texture]` road given as a `.npy` is read by windows on every rank
/// (docs/distributed.md, "Road windows (texture roads, `.npy`)"): the MPI
/// job on 2 and 3 ranks gives the single process's signals to 1e-9 and
/// its spectra and road files byte for byte.
#[test]
fn a_npy_texture_on_2_and_3_ranks_equals_the_single_process() {
    use tyreroad::texture::{Aggregate, aggregate};
    let dir = scratch("texture");
    let mut synth = Aggregate::new(800, 160, 0.25e-3, 0.25e-3, Aggregate::grading_4_6(), 11);
    synth.coverage = 1.3;
    synth.embedding = (0.6, 0.8);
    write_npy(&aggregate(&synth).unwrap(), &dir.join("road.npy"));
    let scenario = dir.join("texture_mpi.toml");
    std::fs::write(
        &scenario,
        r#"
name = "texture_mpi"
[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5
# The Wilke laws: the rung that reads a .npy road by windows.
[model]
fidelity = "wilke"
[rolling]
start = "40 mm"
end = "160 mm"
step = "2 mm"
speed = "50 km/h"
margin = "0 mm"
reference_force = "1 N"
checkpoint = false
[rolling.tread]
kind = "tyre"
radius_x = "0.3 m"
radius_y = "0.5 m"
length = "60 mm"
width = "40 mm"
[rolling.control]
load = "300 N"
[[rolling.sensor]]
name = "centre"
x0 = "90 mm"
x1 = "110 mm"
y0 = "-10 mm"
y1 = "10 mm"
[texture]
file = "road.npy"
min_prominence = "0.1 mm"
min_area = "1 mm2"
"#,
    )
    .unwrap();
    let single = dir.join("single");
    run(Command::new(XTASK)
        .arg("run")
        .arg(&scenario)
        .arg("--out")
        .arg(&single));
    for ranks in [2, 3] {
        let out = dir.join(format!("np{ranks}"));
        run(mpirun(ranks)
            .arg("mpi-run")
            .arg(&scenario)
            .arg("--out")
            .arg(&out));
        let worst = assert_signals_equal(
            &single.join("time_signals.csv"),
            &out.join("time_signals.csv"),
            &[
                "total_force_n",
                "approach_m",
                "contact_area_m2",
                "n_contacts",
            ],
        );
        assert_signals_equal(
            &single.join("sensors.csv"),
            &out.join("sensors.csv"),
            &["centre_n"],
        );
        println!("texture, {ranks} ranks: largest relative difference {worst:.2e}");
        for same in ["third_octave.csv", "road.npz"] {
            let same_bytes =
                std::fs::read(single.join(same)).unwrap() == std::fs::read(out.join(same)).unwrap();
            assert!(same_bytes, "{same} differs on {ranks} ranks");
        }
    }
    std::fs::remove_dir_all(&dir).unwrap();
}
