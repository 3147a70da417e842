//! The generalized Maxwell material (Prony series) and its temperature shift.

use tyreroad_core::Material;

use crate::ViscoError;
use crate::error::{non_negative, positive};

/// One Maxwell branch: a spring of modulus `E_k` in series with a dashpot of
/// relaxation time `τ_k`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Branch {
    /// Branch modulus `E_k` (Pa), ≥ 0.
    pub modulus: f64,
    /// Relaxation time `τ_k` (s), > 0.
    pub relaxation_time: f64,
}

/// A linear viscoelastic, isotropic tread: generalized Maxwell model with a
/// constant Poisson's ratio.
///
/// `E(t) = E∞ + Σ_k E_k e^{−t/τ_k}`,
/// `E'(ω) = E∞ + Σ_k E_k ω²τ_k² / (1 + ω²τ_k²)`,
/// `E''(ω) = Σ_k E_k ωτ_k / (1 + ω²τ_k²)`.
///
/// Invariant: `E∞ > 0`, every `E_k ≥ 0` and `τ_k > 0`, all finite;
/// `−1 < ν ≤ 0.5`.
#[derive(Clone, Debug, PartialEq)]
pub struct Prony {
    long_term: f64,
    branches: Vec<Branch>,
    poisson_ratio: f64,
}

impl Prony {
    /// A Prony series with long-term modulus `long_term` (Pa), `branches`
    /// and Poisson's ratio `poisson_ratio`.
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] naming the first value out of range.
    pub fn new(
        long_term: f64,
        branches: Vec<Branch>,
        poisson_ratio: f64,
    ) -> Result<Self, ViscoError> {
        positive("long-term modulus E∞ (Pa)", long_term)?;
        for b in &branches {
            non_negative("branch modulus E_k (Pa)", b.modulus)?;
            positive("branch relaxation time τ_k (s)", b.relaxation_time)?;
        }
        // The elastic material validates ν; its error is mapped to ours.
        if !(poisson_ratio.is_finite() && poisson_ratio > -1.0 && poisson_ratio <= 0.5) {
            return Err(ViscoError::InvalidValue {
                name: "Poisson's ratio",
                value: poisson_ratio,
                expected: "in (-1, 0.5]",
            });
        }
        Ok(Self {
            long_term,
            branches,
            poisson_ratio,
        })
    }

    /// Long-term (relaxed) modulus `E∞` (Pa).
    pub fn long_term(&self) -> f64 {
        self.long_term
    }

    /// Instantaneous (glassy) modulus `E∞ + Σ E_k` (Pa).
    pub fn instantaneous(&self) -> f64 {
        self.long_term + self.branches.iter().map(|b| b.modulus).sum::<f64>()
    }

    /// The Maxwell branches.
    pub fn branches(&self) -> &[Branch] {
        &self.branches
    }

    /// Poisson's ratio `ν`.
    pub fn poisson_ratio(&self) -> f64 {
        self.poisson_ratio
    }

    /// Relaxation modulus `E(t)` (Pa) at time `t ≥ 0` (s).
    pub fn relaxation(&self, t: f64) -> f64 {
        self.long_term
            + self
                .branches
                .iter()
                .map(|b| b.modulus * (-t / b.relaxation_time).exp())
                .sum::<f64>()
    }

    /// Storage and loss moduli `(E'(ω), E''(ω))` (Pa) at angular frequency
    /// `ω` (rad/s).
    pub fn complex_modulus(&self, omega: f64) -> (f64, f64) {
        let mut storage = self.long_term;
        let mut loss = 0.0;
        for b in &self.branches {
            let wt = omega * b.relaxation_time;
            let d = 1.0 + wt * wt;
            storage += b.modulus * wt * wt / d;
            loss += b.modulus * wt / d;
        }
        (storage, loss)
    }

    /// The same material at a temperature where every relaxation time is
    /// multiplied by the shift factor `a_T` (time–temperature superposition).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] unless `shift_factor` is finite and > 0.
    pub fn shifted(&self, shift_factor: f64) -> Result<Self, ViscoError> {
        positive("shift factor a_T", shift_factor)?;
        let branches = self
            .branches
            .iter()
            .map(|b| Branch {
                modulus: b.modulus,
                relaxation_time: b.relaxation_time * shift_factor,
            })
            .collect();
        Self::new(self.long_term, branches, self.poisson_ratio)
    }

    /// The elastic material of modulus `modulus` (Pa) with this Poisson's
    /// ratio (for the elastic limits and for unit-modulus solves).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] unless `modulus` is finite and > 0.
    pub fn elastic(&self, modulus: f64) -> Result<Material, ViscoError> {
        positive("elastic modulus (Pa)", modulus)?;
        Material::new(modulus, self.poisson_ratio).map_err(|_| ViscoError::InvalidValue {
            name: "Poisson's ratio",
            value: self.poisson_ratio,
            expected: "in (-1, 0.5]",
        })
    }
}

/// Gas constant (J/(mol·K)) of the Arrhenius shift.
pub const GAS_CONSTANT: f64 = 8.314_462_618;

/// Time–temperature shift of a master curve measured at a reference
/// temperature: at temperature `T` every relaxation time is `a_T` times its
/// reference value (a colder tread is slower, `a_T > 1`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TemperatureShift {
    /// Williams–Landel–Ferry: `log10 a_T = −C1 (T − T_ref) / (C2 + T − T_ref)`.
    Wlf {
        /// `C1` (dimensionless), e.g. 8.86.
        c1: f64,
        /// `C2` (K), e.g. 101.6.
        c2: f64,
        /// Reference temperature `T_ref` (K).
        reference: f64,
    },
    /// Arrhenius: `ln a_T = E_a / R · (1/T − 1/T_ref)`.
    Arrhenius {
        /// Activation energy `E_a` (J/mol).
        activation_energy: f64,
        /// Reference temperature `T_ref` (K).
        reference: f64,
    },
}

impl TemperatureShift {
    /// The shift factor `a_T` at temperature `temperature` (K).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for a non-positive temperature, bad
    /// constants, a WLF temperature at or below its pole `T_ref − C2`, or a
    /// factor that overflows.
    pub fn factor(&self, temperature: f64) -> Result<f64, ViscoError> {
        positive("temperature (K)", temperature)?;
        let factor = match *self {
            Self::Wlf { c1, c2, reference } => {
                positive("WLF C1", c1)?;
                positive("WLF C2 (K)", c2)?;
                positive("reference temperature (K)", reference)?;
                let denominator = c2 + temperature - reference;
                if !(denominator > 0.0) {
                    return Err(ViscoError::InvalidValue {
                        name: "temperature for the WLF shift (K)",
                        value: temperature,
                        expected: "above T_ref − C2 (the WLF pole)",
                    });
                }
                10f64.powf(-c1 * (temperature - reference) / denominator)
            }
            Self::Arrhenius {
                activation_energy,
                reference,
            } => {
                positive("activation energy (J/mol)", activation_energy)?;
                positive("reference temperature (K)", reference)?;
                (activation_energy / GAS_CONSTANT * (1.0 / temperature - 1.0 / reference)).exp()
            }
        };
        positive("shift factor a_T", factor)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> Prony {
        Prony::new(
            2e6,
            vec![
                Branch {
                    modulus: 3e6,
                    relaxation_time: 1e-3,
                },
                Branch {
                    modulus: 5e6,
                    relaxation_time: 1e-5,
                },
            ],
            0.5,
        )
        .expect("valid")
    }

    #[test]
    fn limits_of_the_moduli() {
        let p = sample();
        assert_eq!(p.relaxation(0.0), 10e6);
        assert!((p.relaxation(1.0) - 2e6).abs() < 1e-6);
        let (slow, slow_loss) = p.complex_modulus(1e-6);
        assert!((slow - 2e6).abs() / 2e6 < 1e-9 && slow_loss / 2e6 < 1e-8);
        let (fast, fast_loss) = p.complex_modulus(1e12);
        assert!((fast - 10e6).abs() / 10e6 < 1e-6 && fast_loss / 10e6 < 1e-6);
        // One branch alone peaks in loss at ωτ = 1 with E_k / 2.
        let one = Prony::new(
            1.0,
            vec![Branch {
                modulus: 4.0,
                relaxation_time: 0.5,
            }],
            0.3,
        )
        .expect("valid");
        assert!((one.complex_modulus(2.0).1 - 2.0).abs() < 1e-12);
        assert!((one.complex_modulus(2.0).0 - 3.0).abs() < 1e-12);
    }

    #[test]
    fn bad_values_are_named() {
        let bad = Prony::new(-1.0, vec![], 0.5);
        assert!(matches!(bad, Err(ViscoError::InvalidValue { name, .. }) if name.contains("E∞")));
        let bad_tau = Prony::new(
            1.0,
            vec![Branch {
                modulus: 1.0,
                relaxation_time: 0.0,
            }],
            0.5,
        );
        assert!(
            matches!(bad_tau, Err(ViscoError::InvalidValue { name, .. }) if name.contains("τ"))
        );
        assert!(Prony::new(1.0, vec![], 0.6).is_err());
    }

    #[test]
    fn temperature_shifts() {
        let wlf = TemperatureShift::Wlf {
            c1: 8.86,
            c2: 101.6,
            reference: 293.15,
        };
        assert!((wlf.factor(293.15).expect("ok") - 1.0).abs() < 1e-15);
        // 10 K warmer: log10 a_T = −88.6 / 111.6.
        let warm = wlf.factor(303.15).expect("ok");
        assert!((warm.log10() + 88.6 / 111.6).abs() < 1e-12);
        assert!(wlf.factor(293.15 - 101.6).is_err());
        let arr = TemperatureShift::Arrhenius {
            activation_energy: 1e5,
            reference: 300.0,
        };
        let cold = arr.factor(290.0).expect("ok");
        assert!((cold.ln() - 1e5 / GAS_CONSTANT * (1.0 / 290.0 - 1.0 / 300.0)).abs() < 1e-12);
        assert!(cold > 1.0);
        let p = sample().shifted(10.0).expect("ok");
        // A shifted material at frequency ω/a_T is the reference at ω.
        let (a, b) = sample().complex_modulus(300.0);
        let (c, d) = p.complex_modulus(30.0);
        assert!((a - c).abs() < 1e-6 && (b - d).abs() < 1e-6);
    }
}
