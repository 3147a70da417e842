//! What a BEM rolling reference was solved from ([`BemReference`]), so that
//! signals saved by one run are compared only with a run of the same
//! contact (`cargo xtask rolling-bem --bem-from` / `--bem-check`).
//!
//! A BEM step depends on the road's heights and grid, the material, the
//! tread, its lateral position, what is imposed (load or approach), the
//! selection margin (the BEM window), the sensors and the BEM's tolerance
//! and iteration limit; the footprint positions are checked step by step
//! apart from this ([`super::run_scenario_comparison_against`]). It does
//! not depend on the model's laws, fidelity, solver or segmentation, nor
//! on the speed (which only dates the samples): one BEM run serves every
//! model run of the same contact.
//!
//! The heights enter as a 64-bit FNV-1a digest of their bits and validity
//! mask (a changed height anywhere on the map changes it); every other
//! value as its shortest round-trip text, so that a saved file is plain to
//! read and two runs of one scenario write the same text.

use crate::rolling::RollingConfig;
use crate::shared::Material;
use crate::texture::HeightMap;

use super::{BemRollingError, BemRollingOptions};

/// The first line of a reference's text, which names what the file is.
const HEADER: &str = "# the contact this BEM rolling reference was solved for (tyreroad)";

/// The inputs of a BEM rolling run as named lines (`name = value`).
#[derive(Clone, Debug, PartialEq)]
pub struct BemReference {
    lines: Vec<(String, String)>,
}

/// 64-bit FNV-1a over the heights' bits and validity: a digest, not a
/// checksum against tampering.
fn heights_digest(map: &HeightMap) -> u64 {
    let mut hash: u64 = 0xcbf2_9ce4_8422_2325;
    let mut eat = |bytes: &[u8]| {
        for &b in bytes {
            hash ^= u64::from(b);
            hash = hash.wrapping_mul(0x0100_0000_01b3);
        }
    };
    for (&h, &valid) in map.heights().iter().zip(map.valid()) {
        // Missing points store NaN, whose bits need not be one pattern.
        let bits = if valid { h.to_bits() } else { u64::MAX };
        eat(&bits.to_le_bytes());
    }
    hash
}

impl BemReference {
    /// The reference of a BEM rolling run of `config` over `map` on
    /// `material` with `options` (its parallelism apart).
    pub fn of(
        map: &HeightMap,
        material: &Material,
        config: &RollingConfig,
        options: &BemRollingOptions,
    ) -> Self {
        let grid = map.grid();
        let entries = [
            (
                "grid",
                format!(
                    "{} x {} cells of {:?} x {:?} m from ({:?}, {:?}) m",
                    grid.nx(),
                    grid.ny(),
                    grid.dx(),
                    grid.dy(),
                    grid.origin()[0],
                    grid.origin()[1]
                ),
            ),
            ("heights", format!("fnv1a64 {:016x}", heights_digest(map))),
            (
                "material",
                format!(
                    "E = {:?} Pa, nu = {:?}",
                    material.youngs_modulus(),
                    material.poisson_ratio()
                ),
            ),
            ("tread", format!("{:?}", config.tread)),
            ("lateral", format!("{:?} m", config.lateral)),
            ("control", format!("{:?}", config.control)),
            ("margin", format!("{:?} m", config.margin)),
            ("sensors", format!("{:?}", config.sensors)),
            ("bem_tolerance", format!("{:?}", options.tolerance)),
            ("bem_max_iterations", options.max_iterations.to_string()),
        ];
        Self {
            lines: entries
                .into_iter()
                .map(|(k, v)| (k.to_string(), v))
                .collect(),
        }
    }

    /// The text written beside the saved signals: a header line, then one
    /// `name = value` line per input.
    pub fn to_text(&self) -> String {
        let mut text = format!("{HEADER}\n");
        for (k, v) in &self.lines {
            text.push_str(&format!("{k} = {v}\n"));
        }
        text
    }

    /// Reads [`BemReference::to_text`]'s text back.
    ///
    /// # Errors
    /// [`BemRollingError::InvalidInput`] when a line other than a comment
    /// or a blank one has no ` = `, or a name is given twice.
    pub fn parse(text: &str) -> Result<Self, BemRollingError> {
        let mut lines: Vec<(String, String)> = Vec::new();
        for (n, line) in text.lines().enumerate() {
            let line = line.trim();
            if line.is_empty() || line.starts_with('#') {
                continue;
            }
            let Some((k, v)) = line.split_once(" = ") else {
                return Err(BemRollingError::InvalidInput(format!(
                    "line {}: {line:?} is not `name = value`",
                    n + 1
                )));
            };
            if lines.iter().any(|(seen, _)| seen == k) {
                return Err(BemRollingError::InvalidInput(format!(
                    "line {}: {k} is given twice",
                    n + 1
                )));
            }
            lines.push((k.to_string(), v.to_string()));
        }
        Ok(Self { lines })
    }

    /// The reference without what a convergence check of the BEM varies:
    /// the grid and its heights, the window's margin, the BEM's tolerance
    /// and iteration limit. What stays (material, tread, lateral
    /// position, what is imposed, sensors) must be the same for two BEM
    /// runs to be two resolutions of one contact.
    pub fn without_discretisation(&self) -> Self {
        const VARIED: [&str; 5] = [
            "grid",
            "heights",
            "margin",
            "bem_tolerance",
            "bem_max_iterations",
        ];
        Self {
            lines: self
                .lines
                .iter()
                .filter(|(k, _)| !VARIED.contains(&k.as_str()))
                .cloned()
                .collect(),
        }
    }

    /// Each input where `saved` (the reference of saved signals) differs
    /// from `self` (this run's), as `name: saved …, this run …`; empty when
    /// they are the same contact.
    pub fn differences(&self, saved: &Self) -> Vec<String> {
        let value = |r: &Self, k: &str| {
            r.lines
                .iter()
                .find(|(name, _)| name == k)
                .map(|(_, v)| v.clone())
        };
        let mut names: Vec<&str> = self.lines.iter().map(|(k, _)| k.as_str()).collect();
        for (k, _) in &saved.lines {
            if !names.contains(&k.as_str()) {
                names.push(k);
            }
        }
        names
            .into_iter()
            .filter_map(|k| {
                let (a, b) = (value(saved, k), value(self, k));
                (a != b).then(|| {
                    let shown = |v: Option<String>| v.unwrap_or_else(|| "(not given)".into());
                    format!("{k}: saved {}, this run {}", shown(a), shown(b))
                })
            })
            .collect()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rolling::{RollingControl, Tread};

    fn map(bump: f64) -> HeightMap {
        HeightMap::from_fn(40, 30, 0.5e-3, 0.5e-3, move |x, y| {
            1e-4 * (x * 400.0).sin() * (y * 300.0).cos() + if x < 1e-3 { bump } else { 0.0 }
        })
        .expect("map")
    }

    fn config(load: f64) -> RollingConfig {
        let tread = Tread::Tyre {
            radius_x: 0.1,
            radius_y: 0.1,
            length: 5e-3,
            width: 5e-3,
        };
        RollingConfig::new(tread, [4e-3, 10e-3, 1e-3], 10.0, RollingControl::Load(load))
    }

    #[test]
    fn the_same_contact_reads_back_equal_and_another_names_what_changed() {
        let material = Material::new(6.54e6, 0.5).expect("material");
        let options = BemRollingOptions::default();
        let reference = BemReference::of(&map(0.0), &material, &config(30.0), &options);
        let text = reference.to_text();
        assert!(text.starts_with(HEADER), "{text}");
        let back = BemReference::parse(&text).expect("reads back");
        assert_eq!(back, reference);
        assert!(reference.differences(&back).is_empty());

        // Another path of the same contact is the same reference: the
        // positions are checked step by step apart from it.
        let mut moved = config(30.0);
        (moved.start, moved.end, moved.speed) = (5e-3, 9e-3, 20.0);
        assert_eq!(
            BemReference::of(&map(0.0), &material, &moved, &options),
            reference
        );

        let heavier = BemReference::of(&map(0.0), &material, &config(40.0), &options);
        let d = heavier.differences(&reference);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(
            d[0].starts_with("control: saved Load(30.0), this run Load(40.0)"),
            "{d:?}"
        );

        // One height changed by a nanometre changes the digest.
        let bumped = BemReference::of(&map(1e-9), &material, &config(30.0), &options);
        let d = bumped.differences(&reference);
        assert_eq!(d.len(), 1, "{d:?}");
        assert!(d[0].starts_with("heights: saved fnv1a64 "), "{d:?}");

        let softer = Material::new(3e6, 0.5).expect("material");
        let d =
            BemReference::of(&map(0.0), &softer, &config(30.0), &options).differences(&reference);
        assert!(d.len() == 1 && d[0].starts_with("material:"), "{d:?}");

        // A convergence check on another grid: the same contact.
        let coarse = HeightMap::from_fn(20, 15, 1e-3, 1e-3, |x, _| 1e-4 * x).expect("map");
        let coarse = BemReference::of(&coarse, &material, &config(30.0), &options);
        assert_eq!(coarse.differences(&reference).len(), 2);
        assert!(
            coarse
                .without_discretisation()
                .differences(&reference.without_discretisation())
                .is_empty()
        );
        assert_eq!(
            heavier
                .without_discretisation()
                .differences(&reference.without_discretisation())
                .len(),
            1
        );
    }

    #[test]
    fn a_reference_text_that_is_not_name_value_lines_is_refused_by_line() {
        let e = BemReference::parse("# c\ngrid = 1\nheights\n").expect_err("no ` = `");
        assert!(e.to_string().contains("line 3"), "{e}");
        let e = BemReference::parse("grid = 1\ngrid = 2\n").expect_err("twice");
        assert!(e.to_string().contains("grid is given twice"), "{e}");
    }
}
