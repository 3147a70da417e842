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

use crate::error::positive;
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

    /// Reads a master curve from CSV text as a DMA machine exports it: three
    /// columns `frequency (Hz), E' (Pa), E'' (Pa)` separated by commas,
    /// semicolons or tabs. Blank lines and lines starting with `#` are
    /// skipped; a first row whose first field is not a number is a header.
    ///
    /// # Errors
    /// [`ViscoError::Csv`] naming the line, column and field of a missing or
    /// unreadable value, a non-positive frequency or storage modulus or a
    /// negative loss modulus; [`ViscoError::TooFewPoints`] under 2 rows.
    pub fn parse_csv(text: &str) -> Result<Self, ViscoError> {
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
                    && if column == 2 {
                        parsed >= 0.0
                    } else {
                        parsed > 0.0
                    };
                if !ok {
                    return Err(ViscoError::Csv {
                        line,
                        column: column + 1,
                        field,
                        message: format!(
                            "{parsed} is out of range (expected {})",
                            if column == 2 {
                                "finite and >= 0"
                            } else {
                                "finite and > 0"
                            }
                        ),
                    });
                }
                *value = parsed;
            }
            curve.frequency.push(values[0]);
            curve.storage.push(values[1]);
            curve.loss.push(values[2]);
        }
        if curve.frequency.len() < 2 {
            return Err(ViscoError::TooFewPoints {
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
        Ok(())
    }
}

/// Fits a Prony series to `curve` with `per_decade` relaxation times per
/// decade of frequency (2 is usual: more do not improve a smooth curve and
/// slow the fit), Poisson's ratio `poisson_ratio`.
///
/// # Errors
/// As [`fit_prony_with_times`]; [`ViscoError::InvalidValue`] for
/// `per_decade == 0`.
pub fn fit_prony(
    curve: &MasterCurve,
    per_decade: usize,
    poisson_ratio: f64,
) -> Result<Prony, ViscoError> {
    curve.check()?;
    if per_decade == 0 {
        return Err(ViscoError::InvalidValue {
            name: "relaxation times per decade",
            value: 0.0,
            expected: ">= 1",
        });
    }
    let (lo, hi) = curve
        .frequency
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(lo, hi), &f| {
            (lo.min(f), hi.max(f))
        });
    let tau_min = 1.0 / (2.0 * PI * hi) / 10f64.sqrt();
    let tau_max = 1.0 / (2.0 * PI * lo) * 10f64.sqrt();
    let decades = (tau_max / tau_min).log10();
    let count = ((decades * per_decade as f64).ceil() as usize).max(1) + 1;
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
            Err(ViscoError::TooFewPoints { found: 1, .. })
        ));
    }
}
