//! A Prony series fitted to a measured master curve.
//!
//! The relaxation times are fixed on a log-spaced grid spanning the measured
//! frequencies (`τ = 1/ω` at each end, half a decade beyond), which makes the
//! moduli `E∞, E_k` enter linearly; they are found by non-negative least
//! squares (Lawson & Hanson 1974) on the storage and loss moduli together,
//! each row weighted by `1/|E*|` so every decade counts alike. Non-negative
//! moduli keep the material dissipative and the relaxation monotone, which an
//! unconstrained fit on a dense `τ` grid does not (it alternates signs).

use std::f64::consts::PI;

use crate::error::{positive, significant};
use crate::{Branch, Prony, ViscoError};

/// A master curve at its reference temperature: rows of frequency (Hz),
/// storage modulus `E'` (Pa) and loss modulus `E''` (Pa).
#[derive(Clone, Debug, PartialEq)]
pub struct MasterCurve {
    /// Frequencies (Hz), > 0.
    pub frequency: Vec<f64>,
    /// Storage moduli (Pa), > 0.
    pub storage: Vec<f64>,
    /// Loss moduli (Pa), ≥ 0.
    pub loss: Vec<f64>,
}

impl MasterCurve {
    /// The curve of `material` at `frequency` (Hz).
    pub fn of(material: &Prony, frequency: &[f64]) -> Self {
        let (storage, loss) = frequency
            .iter()
            .map(|f| material.complex_modulus(2.0 * PI * f))
            .unzip();
        Self {
            frequency: frequency.to_vec(),
            storage,
            loss,
        }
    }

    /// Reads a master curve from CSV text as a DMA machine exports it: exactly
    /// three columns `frequency (Hz), E' (Pa), E'' (Pa)` separated by commas,
    /// semicolons or tabs. Blank lines and lines starting with `#` are
    /// skipped; a first row whose first field is not a number is a header.
    /// A row repeating an earlier frequency with the same moduli is read once.
    ///
    /// # Errors
    /// [`ViscoError::Csv`] naming the line, column and field of a missing,
    /// extra or unreadable value (a fourth column is refused: a file laid out
    /// `f, |E*|, E', E''` would otherwise be misread), a non-positive
    /// frequency or storage modulus or a negative loss modulus;
    /// [`ViscoError::ConflictingFrequency`] naming both lines of a frequency
    /// given twice with different moduli; [`ViscoError::TooFewFrequencies`]
    /// under 2 distinct frequencies.
    pub fn parse_csv(text: &str) -> Result<Self, ViscoError> {
        Self::parse_csv_within(text, [0.0, f64::INFINITY])
    }

    /// [`Self::parse_csv`] with every storage modulus within `moduli`
    /// (Pa, `[lowest, highest]`) and every loss modulus at most the highest:
    /// a modulus out of the caller's plausible range is refused by its
    /// line and value, not fitted into a series that fails later for
    /// another reason (1e-3 Pa or 1e300 Pa once read as an invalid E∞ = 0).
    ///
    /// # Errors
    /// As [`Self::parse_csv`]; [`ViscoError::Csv`] naming the line, the
    /// column and the value of a modulus out of `moduli`.
    pub fn parse_csv_within(text: &str, moduli: [f64; 2]) -> Result<Self, ViscoError> {
        const FIELDS: [&str; 3] = [
            "frequency (Hz)",
            "storage modulus E' (Pa)",
            "loss modulus E'' (Pa)",
        ];
        let mut curve = Self {
            frequency: Vec::new(),
            storage: Vec::new(),
            loss: Vec::new(),
        };
        let mut seen_row = false;
        // The line of each row kept, to name both lines of a conflict.
        let mut lines: Vec<usize> = Vec::new();
        for (index, raw) in text.lines().enumerate() {
            let line = index + 1;
            let trimmed = raw.trim();
            if trimmed.is_empty() || trimmed.starts_with('#') {
                continue;
            }
            let fields: Vec<&str> = trimmed.split([',', ';', '\t']).map(str::trim).collect();
            let first_row = !seen_row;
            seen_row = true;
            if first_row && fields[0].parse::<f64>().is_err() {
                continue;
            }
            if fields.len() > FIELDS.len() {
                return Err(ViscoError::Csv {
                    line,
                    column: FIELDS.len() + 1,
                    field: "an extra column",
                    message: format!(
                        "{} columns found, 3 expected: frequency (Hz), E' (Pa), E'' (Pa)",
                        fields.len()
                    ),
                });
            }
            let mut values = [0.0; 3];
            for (column, (value, field)) in values.iter_mut().zip(FIELDS).enumerate() {
                let text = fields.get(column).ok_or_else(|| ViscoError::Csv {
                    line,
                    column: column + 1,
                    field,
                    message: format!("missing ({} columns found, 3 expected)", fields.len()),
                })?;
                let parsed: f64 = text.parse().map_err(|_| ViscoError::Csv {
                    line,
                    column: column + 1,
                    field,
                    message: format!("'{text}' is not a number"),
                })?;
                let ok = parsed.is_finite()
                    && match column {
                        0 => parsed > 0.0,
                        1 => parsed > 0.0 && parsed >= moduli[0] && parsed <= moduli[1],
                        _ => parsed >= 0.0 && parsed <= moduli[1],
                    };
                if !ok {
                    let expected = match column {
                        0 => "finite and > 0".to_string(),
                        1 if moduli[1].is_finite() => format!(
                            "within [{}, {}] Pa",
                            significant(moduli[0]),
                            significant(moduli[1])
                        ),
                        1 => "finite and > 0".to_string(),
                        _ if moduli[1].is_finite() => {
                            format!("within [0, {}] Pa", significant(moduli[1]))
                        }
                        _ => "finite and >= 0".to_string(),
                    };
                    return Err(ViscoError::Csv {
                        line,
                        column: column + 1,
                        field,
                        message: format!(
                            "{} is out of range (expected {expected})",
                            significant(parsed)
                        ),
                    });
                }
                *value = parsed;
            }
            let earlier = curve.frequency.iter().position(|&f| f == values[0]);
            if let Some(k) = earlier {
                if curve.storage[k] != values[1] || curve.loss[k] != values[2] {
                    return Err(ViscoError::ConflictingFrequency {
                        first_line: lines[k],
                        line,
                        frequency: values[0],
                    });
                }
                continue;
            }
            curve.frequency.push(values[0]);
            curve.storage.push(values[1]);
            curve.loss.push(values[2]);
            lines.push(line);
        }
        if curve.frequency.len() < 2 {
            return Err(ViscoError::TooFewFrequencies {
                found: curve.frequency.len(),
                needed: 2,
            });
        }
        Ok(curve)
    }

    fn check(&self) -> Result<(), ViscoError> {
        let n = self.frequency.len();
        for (name, len) in [
            ("storage moduli", self.storage.len()),
            ("loss moduli", self.loss.len()),
        ] {
            if len != n {
                return Err(ViscoError::LengthMismatch {
                    name,
                    found: len,
                    expected: n,
                });
            }
        }
        if n < 2 {
            return Err(ViscoError::TooFewPoints {
                found: n,
                needed: 2,
            });
        }
        for i in 0..n {
            positive("master-curve frequency (Hz)", self.frequency[i])?;
            positive("master-curve storage modulus (Pa)", self.storage[i])?;
            crate::error::non_negative("master-curve loss modulus (Pa)", self.loss[i])?;
        }
        // One frequency repeated spans no decade: the grid of relaxation
        // times would be empty.
        let first = self.frequency[0];
        if self.frequency.iter().all(|&f| f == first) {
            return Err(ViscoError::TooFewFrequencies {
                found: 1,
                needed: 2,
            });
        }
        // One frequency given twice with other moduli (a curve built in
        // code; the CSV reader refuses it by line): its "fall" would be at
        // a single frequency.
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&a, &b| {
            self.frequency[a]
                .total_cmp(&self.frequency[b])
                .then(a.cmp(&b))
        });
        for pair in order.windows(2) {
            let (a, b) = (pair[0], pair[1]);
            if self.frequency[a] == self.frequency[b]
                && (self.storage[a] != self.storage[b] || self.loss[a] != self.loss[b])
            {
                return Err(ViscoError::ConflictingFrequency {
                    first_line: a + 1,
                    line: b + 1,
                    frequency: self.frequency[a],
                });
            }
        }
        if let Some(fall) = self.storage_fall()
            && fall.fraction() > MAX_STORAGE_FALL
        {
            return Err(ViscoError::StorageModulusFalls {
                fall,
                max: MAX_STORAGE_FALL,
            });
        }
        Ok(())
    }

    /// The largest fall of the storage modulus with frequency: over the
    /// points in frequency order, the lowest `E'` relative to the highest
    /// at a lower frequency; `None` when `E'` never decreases.
    ///
    /// A passive linear viscoelastic solid's `E'(ω)` is non-decreasing (so
    /// is every Prony series with non-negative moduli, which is all
    /// [`fit_prony`] can return): a fall is measurement noise when small,
    /// a wrong column or unit when large.
    pub fn storage_fall(&self) -> Option<StorageFall> {
        let mut order: Vec<usize> = (0..self.frequency.len().min(self.storage.len())).collect();
        order.sort_by(|&a, &b| self.frequency[a].total_cmp(&self.frequency[b]));
        let mut peak: Option<(f64, f64)> = None;
        let mut worst: Option<StorageFall> = None;
        for k in order {
            let point = (self.frequency[k], self.storage[k]);
            match peak {
                Some(top) if point.1 < top.1 => {
                    let fall = StorageFall {
                        from: top,
                        to: point,
                    };
                    if worst.is_none_or(|w| fall.fraction() > w.fraction()) {
                        worst = Some(fall);
                    }
                }
                Some(top) if point.1 == top.1 => {}
                _ => peak = Some(point),
            }
        }
        worst
    }
}

/// Largest fall of a master curve's storage modulus with frequency that a
/// fit accepts, as a fraction of the highest `E'` below it: 20 %. A DMA's
/// repeatability is a few per cent, so a larger fall is not noise but a
/// wrong column, unit or curve; [`fit_prony`] refuses it. A smaller one is
/// smoothed by the fit (a Prony series cannot fall) and is for the caller
/// to report ([`MasterCurve::storage_fall`], [`STORAGE_NOISE`]).
pub const MAX_STORAGE_FALL: f64 = 0.2;

/// A fall of the storage modulus beyond which a caller should say so
/// (1 %): below it, any DMA's noise.
pub const STORAGE_NOISE: f64 = 0.01;

/// Where a master curve's storage modulus falls most with frequency
/// ([`MasterCurve::storage_fall`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct StorageFall {
    /// The highest `(frequency (Hz), E' (Pa))` before the fall.
    pub from: (f64, f64),
    /// The lowest point after it at a higher frequency.
    pub to: (f64, f64),
}

impl StorageFall {
    /// The fall as a fraction of `from`'s `E'`, in (0, 1).
    pub fn fraction(&self) -> f64 {
        1.0 - self.to.1 / self.from.1
    }
}

/// "the storage modulus E' falls from 2e6 Pa at 1 Hz to 1.9e6 Pa at 10 Hz
/// (5% lower)".
impl std::fmt::Display for StorageFall {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "the storage modulus E' falls from {} Pa at {} Hz to {} Pa at {} Hz ({}% lower)",
            significant(self.from.1),
            significant(self.from.0),
            significant(self.to.1),
            significant(self.to.0),
            significant(100.0 * self.fraction())
        )
    }
}

/// Most relaxation times per decade of a fit. A Prony fit with more than a
/// few terms per decade is ill-conditioned: neighbouring branches have
/// nearly the same response and the least-squares moduli only trade off
/// between them, so more buy nothing but time (the fit's cost grows as the
/// cube of the number of times).
pub const MAX_PER_DECADE: usize = 20;

/// Most relaxation times of a fit in all (`per_decade` times the decades
/// spanned, plus one): 20 decades at the largest `per_decade`, already
/// wider than any measured master curve.
pub const MAX_RELAXATION_TIMES: usize = 200;

/// Fits a Prony series to `curve` with `per_decade` relaxation times per
/// decade of frequency (2 is usual: more do not improve a smooth curve and
/// slow the fit), Poisson's ratio `poisson_ratio`.
///
/// # Errors
/// As [`fit_prony_with_times`]; [`ViscoError::InvalidValue`] for
/// `per_decade` outside `1..=`[`MAX_PER_DECADE`];
/// [`ViscoError::TooManyRelaxationTimes`] when the grid would hold more than
/// [`MAX_RELAXATION_TIMES`].
pub fn fit_prony(
    curve: &MasterCurve,
    per_decade: usize,
    poisson_ratio: f64,
) -> Result<Prony, ViscoError> {
    curve.check()?;
    if !(1..=MAX_PER_DECADE).contains(&per_decade) {
        return Err(ViscoError::InvalidValue {
            name: "relaxation times per decade (per_decade)",
            value: per_decade as f64,
            expected: "1 to 20: more make the Prony fit ill-conditioned",
        });
    }
    let (lo, hi) = curve
        .frequency
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &f| {
            (lo.min(f), hi.max(f))
        });
    // The cap is checked in logarithms: the ratio of the extreme times of a
    // curve spanning 1e-300 to 1e300 Hz overflows, its decades do not.
    let span = (hi.log10() - lo.log10()) + 1.0;
    let wanted = (span * per_decade as f64).ceil().max(1.0) + 1.0;
    if !(wanted <= MAX_RELAXATION_TIMES as f64) {
        return Err(ViscoError::TooManyRelaxationTimes {
            per_decade,
            decades: span,
            lowest: lo,
            highest: hi,
            count: wanted,
            max: MAX_RELAXATION_TIMES,
        });
    }
    let tau_min = 1.0 / (2.0 * PI * hi) / 10f64.sqrt();
    let tau_max = 1.0 / (2.0 * PI * lo) * 10f64.sqrt();
    let decades = (tau_max / tau_min).log10();
    // Within the cap `decades` is finite and at most ~200, so the count
    // cannot overflow; a time that underflows is refused by the fit below.
    let count = ((decades * per_decade as f64).ceil() as usize).clamp(1, MAX_RELAXATION_TIMES) + 1;
    let times: Vec<f64> = (0..count)
        .map(|j| tau_min * 10f64.powf(decades * j as f64 / (count - 1) as f64))
        .collect();
    fit_prony_with_times(curve, &times, poisson_ratio)
}

/// Fits the moduli of a Prony series with the given relaxation `times` (s)
/// to `curve`; branches whose modulus comes out zero are dropped.
///
/// # Errors
/// [`ViscoError::LengthMismatch`] / [`ViscoError::TooFewPoints`] /
/// [`ViscoError::InvalidValue`] for a malformed curve or times;
/// [`ViscoError::InvalidValue`] when the fitted `E∞` is zero (the curve does
/// not level off at low frequency); [`ViscoError::FitNotConverged`].
pub fn fit_prony_with_times(
    curve: &MasterCurve,
    times: &[f64],
    poisson_ratio: f64,
) -> Result<Prony, ViscoError> {
    curve.check()?;
    for &t in times {
        positive("relaxation time (s)", t)?;
    }
    let unknowns = times.len() + 1;
    let mut rows: Vec<(Vec<f64>, f64)> = Vec::with_capacity(2 * curve.frequency.len());
    for i in 0..curve.frequency.len() {
        let omega = 2.0 * PI * curve.frequency[i];
        let weight = 1.0 / curve.storage[i].hypot(curve.loss[i]);
        let mut storage_row = vec![weight; unknowns];
        let mut loss_row = vec![0.0; unknowns];
        for (k, &tau) in times.iter().enumerate() {
            let wt = omega * tau;
            let d = 1.0 + wt * wt;
            storage_row[k + 1] = weight * wt * wt / d;
            loss_row[k + 1] = weight * wt / d;
        }
        rows.push((storage_row, weight * curve.storage[i]));
        rows.push((loss_row, weight * curve.loss[i]));
    }
    let moduli = nnls(&rows, unknowns)?;
    let branches = times
        .iter()
        .zip(&moduli[1..])
        .filter(|(_, m)| **m > 0.0)
        .map(|(&relaxation_time, &modulus)| Branch {
            modulus,
            relaxation_time,
        })
        .collect();
    Prony::new(moduli[0], branches, poisson_ratio)
}

/// Lawson–Hanson non-negative least squares `min ‖A x − b‖, x ≥ 0` on the
/// normal equations of unit-norm columns (the systems are small: one unknown
/// per relaxation time).
fn nnls(rows: &[(Vec<f64>, f64)], n: usize) -> Result<Vec<f64>, ViscoError> {
    let mut scale = vec![0.0; n];
    for (row, _) in rows {
        for (s, a) in scale.iter_mut().zip(row) {
            *s += a * a;
        }
    }
    let scale: Vec<f64> = scale
        .iter()
        .map(|s| if *s > 0.0 { 1.0 / s.sqrt() } else { 0.0 })
        .collect();
    let mut gram = vec![vec![0.0; n]; n];
    let mut rhs = vec![0.0; n];
    for (row, b) in rows {
        for i in 0..n {
            let ai = row[i] * scale[i];
            rhs[i] += ai * b;
            for j in 0..n {
                gram[i][j] += ai * row[j] * scale[j];
            }
        }
    }
    let tolerance = 1e-13
        * rhs
            .iter()
            .fold(0.0f64, |m, v| m.max(v.abs()))
            .max(f64::MIN_POSITIVE);
    let mut x = vec![0.0; n];
    let mut passive = vec![false; n];
    let gradient = |x: &[f64]| -> Vec<f64> {
        (0..n)
            .map(|i| rhs[i] - (0..n).map(|j| gram[i][j] * x[j]).sum::<f64>())
            .collect()
    };
    let max_iterations = 30 * n + 30;
    let mut iterations = 0;
    loop {
        let w = gradient(&x);
        let candidate = (0..n)
            .filter(|&j| !passive[j] && w[j] > tolerance)
            .max_by(|&a, &b| w[a].total_cmp(&w[b]));
        let Some(j) = candidate else { break };
        passive[j] = true;
        loop {
            iterations += 1;
            if iterations > max_iterations {
                return Err(ViscoError::FitNotConverged { iterations });
            }
            let s = solve_passive(&gram, &rhs, &passive);
            if (0..n).all(|i| !passive[i] || s[i] > 0.0) {
                x = s;
                break;
            }
            let alpha = (0..n)
                .filter(|&i| passive[i] && s[i] <= 0.0)
                .map(|i| x[i] / (x[i] - s[i]))
                .fold(f64::INFINITY, f64::min);
            for i in 0..n {
                x[i] += alpha * (s[i] - x[i]);
                if passive[i] && x[i] <= 1e-15 {
                    passive[i] = false;
                    x[i] = 0.0;
                }
            }
        }
    }
    Ok(x.iter().zip(&scale).map(|(v, s)| v * s).collect())
}

/// The unconstrained least-squares solution on the passive set (zero
/// elsewhere): Gaussian elimination with partial pivoting on `G_PP`.
fn solve_passive(gram: &[Vec<f64>], rhs: &[f64], passive: &[bool]) -> Vec<f64> {
    let index: Vec<usize> = (0..passive.len()).filter(|&i| passive[i]).collect();
    let m = index.len();
    let mut a: Vec<Vec<f64>> = index
        .iter()
        .map(|&i| {
            let mut row: Vec<f64> = index.iter().map(|&j| gram[i][j]).collect();
            row.push(rhs[i]);
            row
        })
        .collect();
    for c in 0..m {
        let pivot = (c..m)
            .max_by(|&p, &q| a[p][c].abs().total_cmp(&a[q][c].abs()))
            .unwrap_or(c);
        a.swap(c, pivot);
        let d = a[c][c];
        if d.abs() < 1e-300 {
            continue;
        }
        let (upper, lower) = a.split_at_mut(c + 1);
        let pivot_row = &upper[c];
        for row in lower.iter_mut() {
            let f = row[c] / d;
            if f != 0.0 {
                for (x, p) in row[c..].iter_mut().zip(&pivot_row[c..]) {
                    *x -= f * p;
                }
            }
        }
    }
    let mut s = vec![0.0; m];
    for c in (0..m).rev() {
        let tail: f64 = (c + 1..m).map(|k| a[c][k] * s[k]).sum();
        s[c] = if a[c][c].abs() < 1e-300 {
            0.0
        } else {
            (a[c][m] - tail) / a[c][c]
        };
    }
    let mut full = vec![0.0; passive.len()];
    for (k, &i) in index.iter().enumerate() {
        full[i] = s[k];
    }
    full
}

#[cfg(test)]
mod tests {
    use super::*;

    fn known() -> Prony {
        let branches = [(4e6, 1e-2), (8e6, 1e-4), (20e6, 1e-6)]
            .map(|(modulus, relaxation_time)| Branch {
                modulus,
                relaxation_time,
            })
            .to_vec();
        Prony::new(3e6, branches, 0.5).expect("valid")
    }

    fn log_frequencies(lo: f64, hi: f64, n: usize) -> Vec<f64> {
        (0..n)
            .map(|i| lo * (hi / lo).powf(i as f64 / (n - 1) as f64))
            .collect()
    }

    #[test]
    fn a_known_series_is_recovered_from_its_own_curve() {
        let material = known();
        let curve = MasterCurve::of(&material, &log_frequencies(0.1, 1e8, 60));
        // The grid holds the true times among others (2 per decade).
        let times: Vec<f64> = (0..17).map(|j| 1e-8 * 10f64.powf(j as f64 * 0.5)).collect();
        let fitted = fit_prony_with_times(&curve, &times, 0.5).expect("fit");
        assert!((fitted.long_term() - 3e6).abs() / 3e6 < 1e-6, "{fitted:?}");
        let mut found = fitted.branches().to_vec();
        found.retain(|b| b.modulus > 1.0);
        assert_eq!(found.len(), 3, "{fitted:?}");
        for (b, t) in found.iter().zip(material.branches().iter().rev()) {
            assert!((b.relaxation_time / t.relaxation_time - 1.0).abs() < 1e-12);
            assert!(
                (b.modulus - t.modulus).abs() / t.modulus < 1e-6,
                "{b:?} vs {t:?}"
            );
        }
    }

    #[test]
    fn the_automatic_grid_reproduces_the_curve() {
        let material = known();
        let frequencies = log_frequencies(0.1, 1e7, 50);
        let curve = MasterCurve::of(&material, &frequencies);
        let fitted = fit_prony(&curve, 3, 0.5).expect("fit");
        for &f in &frequencies {
            let (a, b) = material.complex_modulus(2.0 * PI * f);
            let (c, d) = fitted.complex_modulus(2.0 * PI * f);
            let size = a.hypot(b);
            assert!(
                (a - c).abs() / size < 0.01 && (b - d).abs() / size < 0.01,
                "f = {f}: ({a}, {b}) vs ({c}, {d}); {fitted:?}"
            );
        }
        assert!(fitted.branches().iter().all(|b| b.modulus >= 0.0));
    }

    #[test]
    fn csv_reading_and_its_errors() {
        let text = "# DMA export\nfrequency_Hz;E_storage_Pa;E_loss_Pa\n1;2e6;1e5\n\n10;3e6;4e5\n";
        let curve = MasterCurve::parse_csv(text).expect("parses");
        assert_eq!(curve.frequency, vec![1.0, 10.0]);
        assert_eq!(curve.loss, vec![1e5, 4e5]);
        let bad = MasterCurve::parse_csv("1,2e6,1e5\n10,abc,4e5\n");
        assert!(
            matches!(&bad, Err(ViscoError::Csv { line: 2, column: 2, message, .. }) if message.contains("abc")),
            "{bad:?}"
        );
        let short = MasterCurve::parse_csv("1,2e6,1e5\n10,3e6\n");
        assert!(matches!(
            short,
            Err(ViscoError::Csv {
                line: 2,
                column: 3,
                ..
            })
        ));
        let negative = MasterCurve::parse_csv("1,2e6,1e5\n-10,3e6,1\n");
        assert!(matches!(
            negative,
            Err(ViscoError::Csv {
                line: 2,
                column: 1,
                ..
            })
        ));
        let few = MasterCurve::parse_csv("f,E1,E2\n1,2e6,1e5\n");
        assert!(matches!(
            few,
            Err(ViscoError::TooFewFrequencies { found: 1, .. })
        ));
    }

    /// The adversarial curve of 1e-300 to 1e300 Hz once overflowed the
    /// count of relaxation times (a panic); it spans 601 decades.
    #[test]
    fn a_curve_spanning_hundreds_of_decades_is_refused_by_the_cap() {
        let curve =
            MasterCurve::parse_csv("f,E1,E2\n1e-300,4e6,1e5\n1e300,5e6,1e5\n").expect("reads");
        let err = fit_prony(&curve, 3, 0.5).expect_err("over the cap");
        assert!(
            matches!(
                err,
                ViscoError::TooManyRelaxationTimes {
                    per_decade: 3,
                    max: MAX_RELAXATION_TIMES,
                    ..
                }
            ),
            "{err:?}"
        );
        let message = err.to_string();
        assert!(
            message.contains("per_decade = 3") && message.contains("601 decades"),
            "{message}"
        );
        // Just inside the cap: 65 decades at 3 per decade (197 times) fits.
        let wide = MasterCurve::of(&known(), &[1e-30, 1e-10, 1e10, 1e34]);
        assert!(fit_prony(&wide, 3, 0.5).is_ok());
        assert!(matches!(
            fit_prony(&wide, 4, 0.5),
            Err(ViscoError::TooManyRelaxationTimes { .. })
        ));
    }

    #[test]
    fn per_decade_above_twenty_is_refused_before_any_allocation() {
        let curve = MasterCurve::of(&known(), &log_frequencies(0.1, 1e3, 9));
        for per_decade in [0, MAX_PER_DECADE + 1, 10_000, 1_000_000, usize::MAX] {
            let err = fit_prony(&curve, per_decade, 0.5).expect_err("refused");
            assert!(
                err.to_string().contains("per_decade"),
                "{per_decade}: {err}"
            );
        }
        assert!(fit_prony(&curve, MAX_PER_DECADE, 0.5).is_ok());
    }

    #[test]
    fn a_fourth_column_is_refused_not_ignored() {
        let err = MasterCurve::parse_csv("f,E,E1,E2\n1,2e6,2e6,1e5\n10,3e6,3e6,4e5\n")
            .expect_err("four columns");
        assert!(
            matches!(&err, ViscoError::Csv { line: 2, column: 4, message, .. } if message.contains("4 columns")),
            "{err:?}"
        );
    }

    #[test]
    fn a_frequency_given_twice_with_other_moduli_names_both_lines() {
        let err = MasterCurve::parse_csv("# export\n1,2e6,1e5\n10,3e6,4e5\n1,2.5e6,1e5\n")
            .expect_err("conflict");
        assert_eq!(
            err,
            ViscoError::ConflictingFrequency {
                first_line: 2,
                line: 4,
                frequency: 1.0
            }
        );
        assert!(err.to_string().contains("lines 2 and 4"), "{err}");
        // The same row twice is read once.
        let curve = MasterCurve::parse_csv("1,2e6,1e5\n10,3e6,4e5\n1,2e6,1e5\n").expect("reads");
        assert_eq!(curve.frequency, vec![1.0, 10.0]);
    }

    #[test]
    fn one_distinct_frequency_is_too_few_to_fit() {
        let err = MasterCurve::parse_csv("5,2e6,1e5\n5,2e6,1e5\n").expect_err("one frequency");
        assert!(
            matches!(
                err,
                ViscoError::TooFewFrequencies {
                    found: 1,
                    needed: 2
                }
            ),
            "{err:?}"
        );
        let curve = MasterCurve {
            frequency: vec![5.0, 5.0],
            storage: vec![2e6, 3e6],
            loss: vec![1e5, 1e5],
        };
        assert!(matches!(
            fit_prony(&curve, 3, 0.5),
            Err(ViscoError::TooFewFrequencies { .. })
        ));
    }
}
