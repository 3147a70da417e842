//! Checkpoints that refuse anything else: a damaged or edited file is
//! refused with a named error, never resumed, and never panics.

use std::path::{Path, PathBuf};
use std::time::Duration;

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_rolling::{
    CheckpointOptions, Road, RollingConfig, RollingControl, RollingError, RollingResult,
    RunOptions, SyntheticRoad, Tread, roll,
};

type Law = PotentialLaw<Sphere>;
type TestResult = Result<(), Box<dyn std::error::Error>>;

fn rubber() -> Material {
    Material::new(6.54e6, 0.5).expect("material")
}

fn road() -> Road<Law> {
    SyntheticRoad {
        seed: 11,
        length: 0.12,
        width: 0.05,
        density: 30_000.0,
        ..SyntheticRoad::default()
    }
    .sphere_road(rubber())
    .expect("road")
}

fn config() -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.2,
        length: 0.06,
        width: 0.05,
    };
    RollingConfig::new(tyre, [0.03, 0.05, 2e-3], 13.9, RollingControl::Load(80.0))
}

fn run(road: &Road<Law>, dir: &Path) -> Result<RollingResult, RollingError> {
    let ck = CheckpointOptions {
        dir: dir.to_path_buf(),
        interval: Duration::ZERO,
    };
    roll(
        road,
        rubber(),
        &config(),
        &RunOptions {
            checkpoint: Some(&ck),
            ..RunOptions::default()
        },
    )
}

/// 64-bit FNV-1a, as the checkpoint's checksum line.
fn fnv1a(bytes: &[u8]) -> u64 {
    let mut h: u64 = 0xcbf2_9ce4_8422_2325;
    for &b in bytes {
        h ^= u64::from(b);
        h = h.wrapping_mul(0x0000_0100_0000_01b3);
    }
    h
}

/// The file's body (every line but the checksum) with a fresh checksum: an
/// edit made by someone who knows the format.
fn reseal(body: &str) -> String {
    format!("{body}checksum {:016x}\n", fnv1a(body.as_bytes()))
}

fn body(text: &str) -> &str {
    let end = text.trim_end_matches('\n').rfind('\n').map_or(0, |i| i + 1);
    &text[..end]
}

fn hex(v: f64) -> String {
    format!("{:016x}", v.to_bits())
}

fn unhex(t: &str) -> f64 {
    f64::from_bits(u64::from_str_radix(t, 16).expect("hex"))
}

/// Applies `edit` to the tokens of line `n` (0 = header) of `text`.
fn edit_line(text: &str, n: usize, edit: impl Fn(&mut Vec<String>)) -> String {
    text.lines()
        .enumerate()
        .map(|(i, l)| {
            if i == n {
                let mut tokens: Vec<String> = l.split(' ').map(str::to_string).collect();
                edit(&mut tokens);
                tokens.join(" ") + "\n"
            } else {
                format!("{l}\n")
            }
        })
        .collect()
}

// Record tokens (no sensor): 0 index … 6 status, 7 recovery, 8 position,
// 9 time, 10 total force, 11 approach, 12 area, 13 clearance, 14 residual,
// then `id:bits` contacts.
const POSITION: usize = 8;
const TOTAL: usize = 10;
const APPROACH: usize = 11;
const FIRST_CONTACT: usize = 15;

#[test]
fn damaged_or_edited_checkpoints_are_refused() -> TestResult {
    let road = road();
    let base: PathBuf =
        std::env::temp_dir().join(format!("tyreroad-ckpt-refusal-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    let good_dir = base.join("good");
    let clean = run(&road, &good_dir)?;
    let file = std::fs::read_dir(&good_dir)?
        .next()
        .ok_or("no checkpoint written")??
        .path();
    let name = file.file_name().ok_or("name")?.to_owned();
    let original = std::fs::read_to_string(&file)?;
    assert!(
        original
            .lines()
            .last()
            .is_some_and(|l| l.starts_with("checksum "))
    );
    assert!(original.lines().any(|l| l.starts_with("state ")));
    // Untouched, it resumes every step bit for bit.
    let again = run(&road, &good_dir)?;
    assert_eq!(again.resumed, clean.steps.len());
    assert_eq!(again.steps, clean.steps);

    let scaled =
        |k: usize, factor: f64| move |t: &mut Vec<String>| t[k] = hex(unhex(&t[k]) * factor);
    let edit_force = |t: &mut Vec<String>| {
        let (id, bits) = t[FIRST_CONTACT].split_once(':').expect("contact");
        t[FIRST_CONTACT] = format!("{id}:{}", hex(unhex(bits) * 1.01));
    };
    let unknown_id = |t: &mut Vec<String>| {
        let (_, bits) = t[FIRST_CONTACT].split_once(':').expect("contact");
        t[FIRST_CONTACT] = format!("999999999:{bits}");
    };
    let nan_total = |t: &mut Vec<String>| t[TOTAL] = hex(f64::NAN);
    let mut flipped = original.clone().into_bytes();
    let at = original.find('\n').ok_or("header")? + 3;
    flipped[at] ^= 0x01;
    let state_line = original
        .lines()
        .position(|l| l.starts_with("state "))
        .ok_or("state")?;
    // The state's first `id:bits` token (after "state", index, approach).
    let unknown_state_id = |t: &mut Vec<String>| {
        let (_, bits) = t[3].split_once(':').expect("state force");
        t[3] = format!("424242424:{bits}");
    };
    let cases: Vec<(&str, Vec<u8>, &str)> = vec![
        ("flipped bit", flipped, "checksum mismatch"),
        (
            "edited force",
            edit_line(&original, 1, edit_force).into_bytes(),
            "checksum mismatch",
        ),
        (
            "moved position",
            edit_line(&original, 1, scaled(POSITION, 1.5)).into_bytes(),
            "checksum mismatch",
        ),
        (
            "NaN",
            edit_line(&original, 1, nan_total).into_bytes(),
            "checksum mismatch",
        ),
        (
            "doubled approach",
            edit_line(&original, 1, scaled(APPROACH, 2.0)).into_bytes(),
            "checksum mismatch",
        ),
        (
            "truncated",
            body(&original).as_bytes().to_vec(),
            "no checksum line",
        ),
        // The same edits with the checksum recomputed: the records' own
        // checks refuse them.
        (
            "edited force, resealed",
            reseal(body(&edit_line(&original, 1, edit_force))).into_bytes(),
            "is not the sum",
        ),
        (
            "moved position, resealed",
            reseal(body(&edit_line(&original, 1, scaled(POSITION, 1.5)))).into_bytes(),
            "the path puts it",
        ),
        (
            "NaN, resealed",
            reseal(body(&edit_line(&original, 1, nan_total))).into_bytes(),
            "is not the sum",
        ),
        (
            "doubled approach, resealed",
            reseal(body(&edit_line(&original, 1, scaled(APPROACH, 2.0)))).into_bytes(),
            "disagrees with its clearance",
        ),
        (
            "unknown asperity id, resealed",
            reseal(body(&edit_line(&original, 1, unknown_id))).into_bytes(),
            "not on the road",
        ),
        (
            "unknown asperity id in the state, resealed",
            reseal(body(&edit_line(&original, state_line, unknown_state_id))).into_bytes(),
            "not on the road",
        ),
    ];
    for (k, (what, bytes, expected)) in cases.into_iter().enumerate() {
        let dir = base.join(format!("case-{k}"));
        std::fs::create_dir_all(&dir)?;
        std::fs::write(dir.join(&name), &bytes)?;
        match run(&road, &dir) {
            Err(RollingError::CheckpointRejected { file, reason }) => {
                assert!(file.ends_with(".ckpt"), "{what}: {file}");
                assert!(reason.contains(expected), "{what}: {reason}");
            }
            other => return Err(format!("{what}: expected a refusal, got {other:?}").into()),
        }
    }
    std::fs::remove_dir_all(&base)?;
    Ok(())
}

/// Regression (an MPI job's resume lost a rank's checkpoint): a rank's
/// `roll_range` must leave another writer's temporary file alone, since
/// that rank may rename it any moment; only the sole writer (`roll`)
/// removes the temporary files that killed runs left.
#[test]
fn a_part_leaves_other_writers_temporary_files_and_the_whole_run_removes_them() -> TestResult {
    let road = road();
    let base = std::env::temp_dir().join(format!("tyreroad-ckpt-shared-{}", std::process::id()));
    let _ = std::fs::remove_dir_all(&base);
    std::fs::create_dir_all(&base)?;
    let other = base.join(".00000000000000ab-0-9.ckpt.tmp-4242");
    std::fs::write(&other, "being written by another rank")?;
    let ck = CheckpointOptions {
        dir: base.clone(),
        interval: Duration::ZERO,
    };
    let options = RunOptions {
        checkpoint: Some(&ck),
        ..RunOptions::default()
    };
    let part = tyreroad_rolling::roll_range(&road, rubber(), &config(), 0..4, 0, &options)?;
    assert_eq!(part.steps.len(), 4);
    assert!(other.exists(), "a part removed another writer's file");
    run(&road, &base)?;
    assert!(!other.exists(), "the whole run left a killed run's file");
    std::fs::remove_dir_all(&base)?;
    Ok(())
}

/// Regression (adversarial run, 2026-11-30): a checkpoint folder that is a
/// file was reported as the system's "Not a directory (os error 20)". The
/// error now says what stands there and what to do, naming the path.
#[test]
fn a_file_where_the_checkpoint_folder_belongs_is_said_so() -> TestResult {
    let path = std::env::temp_dir().join(format!("tyreroad-ckpt-a-file-{}", std::process::id()));
    std::fs::write(&path, "not a folder")?;
    let message = run(&road(), &path)
        .expect_err("a file in the folder's place")
        .to_string();
    assert!(
        message.contains(&path.display().to_string())
            && message.contains("a file stands where the checkpoint folder")
            && message.contains("checkpoint = false"),
        "{message}"
    );
    std::fs::remove_file(&path)?;
    Ok(())
}
