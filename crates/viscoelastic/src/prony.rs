//! The generalized Maxwell material (Prony series) and its temperature shift.

use tyreroad_core::Material;

use crate::ViscoError;
use crate::error::{non_negative, positive, significant};

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
/// Invariant: `E∞ > 0`, every `E_k ≥ 0` and `τ_k > 0`, all finite, and
/// the instantaneous modulus `E∞ + Σ E_k` finite; `−1 < ν ≤ 0.5`.
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
    /// [`ViscoError::InvalidValue`] naming the first value out of range, or
    /// the instantaneous modulus `E∞ + Σ E_k` when the sum overflows.
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
        let material = Self {
            long_term,
            branches,
            poisson_ratio,
        };
        // Every modulus the series gives is at most this sum.
        let instantaneous = material.instantaneous();
        if !instantaneous.is_finite() {
            return Err(ViscoError::InvalidValue {
                name: "instantaneous modulus E∞ + Σ E_k (Pa)",
                value: instantaneous,
                expected: "finite (the moduli sum past floating point)",
            });
        }
        Ok(material)
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

    /// Relaxation modulus `E(t)` (Pa) at time `t ≥ 0` (s): from the
    /// instantaneous modulus at `t = 0` down to `E∞` as `t → ∞`.
    ///
    /// A time before the step (`t < 0`) reads as `t = 0`, the instantaneous
    /// modulus, not the growing exponentials' overflow; a NaN time gives NaN.
    pub fn relaxation(&self, t: f64) -> f64 {
        let t = if t < 0.0 { 0.0 } else { t };
        self.long_term
            + self
                .branches
                .iter()
                .map(|b| b.modulus * (-t / b.relaxation_time).exp())
                .sum::<f64>()
    }

    /// Storage and loss moduli `(E'(ω), E''(ω))` (Pa) at angular frequency
    /// `ω` (rad/s).
    ///
    /// Defined for every `ω` but NaN: the transform of a real kernel has an
    /// even `E'` and an odd `E''`, so a negative `ω` gives `E'(|ω|)` and
    /// `−E''(|ω|)` (the loss is positive for `ω > 0`). As `|ω| → ∞` (and at
    /// `ω = ±∞`) the moduli tend to the instantaneous modulus and `±0`.
    pub fn complex_modulus(&self, omega: f64) -> (f64, f64) {
        let mut storage = self.long_term;
        let mut loss = 0.0;
        for b in &self.branches {
            let wt = omega * b.relaxation_time;
            let d = 1.0 + wt * wt;
            if d.is_finite() {
                storage += b.modulus * wt * wt / d;
                loss += b.modulus * wt / d;
            } else {
                // (ωτ)² overflows: the glassy limit, where inf/inf is NaN.
                storage += b.modulus;
                loss += b.modulus / wt;
            }
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
    /// Temperatures are in kelvin: the errors of a temperature below 150 K
    /// say what it would be read as °C.
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for a non-positive temperature or bad
    /// constants; [`ViscoError::TemperatureShift`] for a WLF temperature at
    /// or below its pole `T_ref − C2`, or a factor that over- or underflows
    /// (naming the exponent and the inputs that make it).
    pub fn factor(&self, temperature: f64) -> Result<f64, ViscoError> {
        positive("temperature (K)", temperature)?;
        let refuse = |message: String| ViscoError::TemperatureShift {
            temperature,
            message: message + &celsius_hint(temperature),
        };
        let t = significant(temperature);
        match *self {
            Self::Wlf { c1, c2, reference } => {
                positive("WLF C1", c1)?;
                positive("WLF C2 (K)", c2)?;
                positive("reference temperature (K)", reference)?;
                let pole = reference - c2;
                let denominator = c2 + temperature - reference;
                if !(denominator > 0.0) {
                    return Err(refuse(format!(
                        "T = {t} K is at or below the WLF pole T_ref − C2 = {} K (expected a \
                         temperature above it)",
                        significant(pole)
                    )));
                }
                let exponent = -c1 * (temperature - reference) / denominator;
                let factor = 10f64.powf(exponent);
                if factor.is_finite() && factor > 0.0 {
                    return Ok(factor);
                }
                Err(refuse(format!(
                    "log10 a_T = −C1 (T − T_ref)/(C2 + T − T_ref) = {} puts a_T outside \
                     floating point (C1 = {}, C2 = {} K, T_ref = {} K; T = {t} K is {} K above \
                     the WLF pole {} K): a temperature farther from the pole or a smaller C1",
                    significant(exponent),
                    significant(c1),
                    significant(c2),
                    significant(reference),
                    significant(denominator),
                    significant(pole)
                )))
            }
            Self::Arrhenius {
                activation_energy,
                reference,
            } => {
                positive("activation energy (J/mol)", activation_energy)?;
                positive("reference temperature (K)", reference)?;
                let exponent =
                    activation_energy / GAS_CONSTANT * (1.0 / temperature - 1.0 / reference);
                let factor = exponent.exp();
                if factor.is_finite() && factor > 0.0 {
                    return Ok(factor);
                }
                Err(refuse(format!(
                    "ln a_T = E_a/R (1/T − 1/T_ref) = {} puts a_T outside floating point \
                     (E_a = {} J/mol, T = {t} K, T_ref = {} K): a smaller activation energy \
                     or a temperature closer to T_ref",
                    significant(exponent),
                    significant(activation_energy),
                    significant(reference)
                )))
            }
        }
    }
}

/// Temperatures (K) below which an error of [`TemperatureShift::factor`]
/// suspects a value meant in °C: no rubber tread is tested that cold.
const CELSIUS_SUSPECT: f64 = 150.0;

fn celsius_hint(temperature: f64) -> String {
    if temperature < CELSIUS_SUSPECT {
        format!(
            "; temperatures are in kelvin: {} °C would be {} K",
            significant(temperature),
            significant(temperature + 273.15)
        )
    } else {
        String::new()
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

    /// Regression (adversarial run): two branches of 1e308 Pa were accepted
    /// with an infinite instantaneous modulus.
    #[test]
    fn branch_moduli_summing_past_floating_point_are_refused() {
        let huge = |relaxation_time| Branch {
            modulus: 1e308,
            relaxation_time,
        };
        let e = Prony::new(2e6, vec![huge(1e-3), huge(1e-2)], 0.5).expect_err("inf sum");
        assert!(
            matches!(e, ViscoError::InvalidValue { name, .. } if name.contains("E∞ + Σ E_k")),
            "{e}"
        );
        assert!(Prony::new(2e6, vec![huge(1e-3)], 0.5).is_ok());
    }

    /// Regression (adversarial run): E(−1 s) was infinite, E'(∞) and E''(∞)
    /// NaN.
    #[test]
    fn moduli_are_defined_before_the_step_and_at_infinite_frequency() {
        let p = sample();
        assert_eq!(p.relaxation(-1.0), p.instantaneous());
        assert_eq!(p.relaxation(-1e300), p.instantaneous());
        assert!(p.relaxation(f64::NAN).is_nan());
        for omega in [f64::INFINITY, 1e200, 1e300] {
            let (storage, loss) = p.complex_modulus(omega);
            assert_eq!(storage, p.instantaneous(), "ω = {omega}");
            assert!((0.0..1e-150).contains(&loss), "ω = {omega}: {loss}");
        }
        // Finite (ωτ)² keeps the closed form to the last digit.
        let (storage, loss) = p.complex_modulus(1e12);
        let wt = [1e9, 1e7];
        let closed = 2e6
            + 3e6 * wt[0] * wt[0] / (1.0 + wt[0] * wt[0])
            + 5e6 * wt[1] * wt[1] / (1.0 + wt[1] * wt[1]);
        assert_eq!(storage, closed);
        assert!(loss > 0.0);
        // A real kernel: E' even, E'' odd in ω.
        let (s_pos, l_pos) = p.complex_modulus(300.0);
        let (s_neg, l_neg) = p.complex_modulus(-300.0);
        assert_eq!((s_neg, l_neg), (s_pos, -l_pos));
        let (s_inf, l_inf) = p.complex_modulus(f64::NEG_INFINITY);
        assert_eq!(s_inf, p.instantaneous());
        assert!(l_inf == 0.0);
    }

    /// Regression (adversarial run): a WLF temperature 1e-12 K above the pole
    /// and a huge activation energy said "invalid shift factor a_T: inf" as if
    /// a_T were given; 20 K (meant as 20 °C) gave no hint of kelvin.
    #[test]
    fn an_overflowing_shift_names_its_inputs_and_a_celsius_looking_temperature_is_hinted() {
        let wlf = TemperatureShift::Wlf {
            c1: 8.86,
            c2: 101.6,
            reference: 293.15,
        };
        let text = |r: Result<f64, ViscoError>| match r {
            Err(e @ ViscoError::TemperatureShift { .. }) => e.to_string(),
            other => panic!("{other:?}"),
        };
        let near_pole = text(wlf.factor(191.55 + 1e-12));
        assert!(
            near_pole.contains("log10 a_T")
                && near_pole.contains("C1 = 8.86")
                && near_pole.contains("WLF pole 191.55 K")
                && !near_pole.contains("kelvin")
                && near_pole.len() < 400,
            "{near_pole}"
        );
        let celsius = text(wlf.factor(20.0));
        assert!(
            celsius.contains("at or below the WLF pole T_ref − C2 = 191.55 K")
                && celsius.contains("20 °C would be 293.15 K"),
            "{celsius}"
        );
        let arrhenius = TemperatureShift::Arrhenius {
            activation_energy: 1e9,
            reference: 293.15,
        };
        let huge = text(arrhenius.factor(200.0));
        assert!(
            huge.contains("ln a_T") && huge.contains("E_a = 1e9 J/mol") && !huge.contains("kelvin"),
            "{huge}"
        );
        let tiny = TemperatureShift::Arrhenius {
            activation_energy: 1e5,
            reference: 293.15,
        };
        let cold = text(tiny.factor(1e-300));
        assert!(cold.contains("kelvin") && cold.contains("1e-300"), "{cold}");
        // A factor in range is unchanged.
        assert!((wlf.factor(263.15).expect("ok") - 5_155.734_001_273_99).abs() < 1e-6);
    }
}
