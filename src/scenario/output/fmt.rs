//! The fixed number formats of the CSV columns, as serde `serialize_with`
//! functions: the outputs' bytes stay those of the formats they always had.

use serde::Serializer;

/// Rust's shortest round-trip `{}` (loads, band labels).
pub fn plain<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v}"))
}

/// Shortest round-trip scientific `{:e}` (coordinates).
pub fn sci<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:e}"))
}

/// Scientific, 6 decimals.
pub fn sci6<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.6e}"))
}

/// Fixed, 6 decimals.
pub fn fixed6<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.6}"))
}

/// Scientific with 6 decimals, or an empty field.
pub fn opt_sci6<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match v {
        Some(v) => sci6(v, s),
        None => s.serialize_str(""),
    }
}

/// Fixed with 6 decimals, or an empty field.
pub fn opt_fixed6<S: Serializer>(v: &Option<f64>, s: S) -> Result<S::Ok, S::Error> {
    match v {
        Some(v) => fixed6(v, s),
        None => s.serialize_str(""),
    }
}

/// Scientific, 9 decimals.
pub fn sci9<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.9e}"))
}

/// Scientific, 12 decimals.
pub fn sci12<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.12e}"))
}

/// Fixed, 3 decimals (levels in dB, band centres).
pub fn fixed3<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    s.collect_str(&format_args!("{v:.3}"))
}

/// A list of values, each scientific with 9 decimals (one column each).
pub fn sci9_all<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(|x| Sci9(*x)))
}

/// A level in dB, fixed with 3 decimals; a band without power (a sensor
/// that never sees force: `10 log10 0 = −∞`) is an empty field, which
/// CSV readers take as missing (NaN), never the text `-inf`.
pub fn level_db<S: Serializer>(v: &f64, s: S) -> Result<S::Ok, S::Error> {
    if v.is_finite() {
        fixed3(v, s)
    } else {
        s.serialize_str("")
    }
}

/// A list of levels, each as [`level_db`] (one column each).
pub fn level_db_all<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(|x| LevelDb(*x)))
}

struct LevelDb(f64);
impl serde::Serialize for LevelDb {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        level_db(&self.0, s)
    }
}

/// A list of values, each fixed with 3 decimals (one column each).
pub fn fixed3_all<S: Serializer>(v: &[f64], s: S) -> Result<S::Ok, S::Error> {
    s.collect_seq(v.iter().map(|x| Fixed3(*x)))
}

struct Sci9(f64);
impl serde::Serialize for Sci9 {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        sci9(&self.0, s)
    }
}
struct Fixed3(f64);
impl serde::Serialize for Fixed3 {
    fn serialize<S: Serializer>(&self, s: S) -> Result<S::Ok, S::Error> {
        fixed3(&self.0, s)
    }
}
