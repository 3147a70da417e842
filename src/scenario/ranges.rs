//! The ranges where a scenario's numbers mean something, and the checks
//! that hold a value to one (docs/validation.md, "Bad input"): shared by the
//! whole-scenario check (`check.rs`) and by the parts that read their own
//! values (histories, viscoelastic treads, texture files, command lines).
//! A leaf: it knows the error type and nothing of the scenario's shape.
//!
//! The plausibility bounds are wide on purpose (soft gels to steel, a
//! fingertip to a truck): they catch typing errors and unit slips (a modulus
//! in Pa written as MPa, a step in µm written as m), not unusual physics.

use super::ScenarioError;

/// Young's modulus range (Pa): a soft gel to a hard metal.
pub const MODULUS_RANGE: [f64; 2] = [1e3, 1e12];
/// Load range (N) of a static load or a rolling wheel load.
pub const LOAD_RANGE: [f64; 2] = [0.0, 1e7];
/// Smallest static or rolling load (N): a nanonewton. Below it a load is a
/// unit gone wrong, not a contact (1e-300 N passed an open lower bound and
/// failed in the solver, printed with 300 digits; a rolling run failed
/// every step).
pub const MIN_STATIC_LOAD: f64 = 1e-9;
/// Length range (m) of a positive geometric size (radius, spacing, step,
/// tread size, road size).
pub const SIZE_RANGE: [f64; 2] = [1e-7, 1e3];
/// Largest magnitude (m) of a coordinate (positions, heights, path ends).
pub const MAX_COORDINATE: f64 = 1e4;
/// Speed range (m/s): walking pace to well above any road vehicle.
pub const SPEED_RANGE: [f64; 2] = [1e-3, 500.0];
/// Range of the relative solver tolerance.
pub const TOLERANCE_RANGE: [f64; 2] = [1e-15, 1e-3];
/// Largest number of Newton iterations per load step.
pub const MAX_ITERATIONS: usize = 100_000;
/// Range of a potential-law shape constant `c` (sphere 0.36, cone 0.45).
pub const CONSTANT_RANGE: [f64; 2] = [1e-3, 10.0];
/// Most points of a synthesised height map (8 bytes each, and a mask).
pub const MAX_MAP_POINTS: f64 = 2e8;
/// Most summits of a synthetic sphere road.
pub const MAX_SYNTHETIC_SUMMITS: f64 = 2e7;
/// Smallest reference force of the decibel levels (N): below, 1 N reads as
/// more than 240 dB.
pub const MIN_REFERENCE_FORCE: f64 = 1e-12;
/// Threads may exceed the machine's parallelism by this factor at most.
pub const THREAD_OVERSUBSCRIPTION: usize = 4;
/// Longest output name (characters).
pub const MAX_NAME_LEN: usize = 100;

/// An error naming `key`, its value and what it must be.
pub(super) fn bad(key: &str, value: impl std::fmt::Display, expected: &str) -> ScenarioError {
    ScenarioError::Value {
        key: key.into(),
        value: value.to_string(),
        expected: expected.into(),
    }
}

/// `value` must be finite and in `[lo, hi]` (`open_lo`: `> lo`).
pub(super) fn in_range(
    key: &str,
    value: f64,
    [lo, hi]: [f64; 2],
    open_lo: bool,
    unit: &str,
) -> Result<(), ScenarioError> {
    let above = if open_lo { value > lo } else { value >= lo };
    if value.is_finite() && above && value <= hi {
        Ok(())
    } else {
        let open = if open_lo { "(" } else { "[" };
        let unit = if unit.is_empty() {
            String::new()
        } else {
            format!(" {unit}")
        };
        Err(bad(
            key,
            format!("{}{unit}", number(value)),
            &format!(
                "a finite value in {open}{}, {}]{unit}",
                number(lo),
                number(hi)
            ),
        ))
    }
}

/// `x` in scientific notation, zero as `0` (not `0e0`).
pub(super) fn number(x: f64) -> String {
    if x == 0.0 {
        "0".into()
    } else {
        format!("{x:e}")
    }
}

pub(super) fn size(key: &str, value: f64) -> Result<(), ScenarioError> {
    in_range(key, value, SIZE_RANGE, false, "m")
}

pub(super) fn coordinate(key: &str, value: f64) -> Result<(), ScenarioError> {
    in_range(key, value, [-MAX_COORDINATE, MAX_COORDINATE], false, "m")
}

/// The grid spacing of a `[texture] file` (from its header, sidecar or
/// member), held to the range `[texture.synth] spacing` is: a file saying
/// 1e30 m per point otherwise fails much later as a solver that does not
/// converge.
pub(crate) fn texture_file_spacing(
    path: &std::path::Path,
    dx: f64,
    dy: f64,
) -> Result<(), ScenarioError> {
    for (axis, d) in [("dx", dx), ("dy", dy)] {
        size(
            &format!("[texture] file {} spacing {axis}", path.display()),
            d,
        )?;
    }
    Ok(())
}

/// Refuses a thread count above [`THREAD_OVERSUBSCRIPTION`] × the cores
/// (0 means every core): thousands of threads on a few cores only thrash,
/// and the count is read from files and command lines alike. `key` names
/// where it came from (`"[rolling] threads"`, `"--threads"`).
///
/// # Errors
/// [`ScenarioError::Invalid`] naming `key`, the value and the range.
pub fn check_threads(key: &str, n: usize) -> Result<usize, ScenarioError> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if n > THREAD_OVERSUBSCRIPTION * cores {
        return Err(bad(
            key,
            n,
            &format!(
                "0 (every core) to {} ({THREAD_OVERSUBSCRIPTION} × the {cores} cores)",
                THREAD_OVERSUBSCRIPTION * cores
            ),
        ));
    }
    Ok(n)
}

/// An output name must be a plain file name: it becomes the stem of files
/// inside the output folder and must not lead out of it.
pub fn check_name(name: &str) -> Result<(), ScenarioError> {
    let plain = !name.is_empty()
        && name.len() <= MAX_NAME_LEN
        && !name.starts_with('.')
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'));
    if plain {
        Ok(())
    } else {
        Err(bad(
            "name",
            format!("{name:?}"),
            "a plain file name: 1 to 100 of A-Z a-z 0-9 _ - . (not starting with a dot)",
        ))
    }
}
