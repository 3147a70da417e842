//! The Lee–Radok closed form of a rigid sphere pressed at constant rate: the
//! independent reference of the hereditary recursion.
//!
//! While the contact grows, Lee & Radok (1960) replace the modulus of Hertz's
//! law by the hereditary operator:
//! `F(t) = 4√R / (3(1 − ν²)) ∫_0^t E(t − s) d(δ^{3/2})/ds ds`.
//! For `δ = v s` and one branch `E_k e^{−(t−s)/τ_k}`, with `x = t/τ_k`,
//! `∫_0^t e^{−(t−s)/τ} (3/2) v^{3/2} s^{1/2} ds = (3/2) (vτ)^{3/2} (√x − D(√x))`,
//! `D` being Dawson's integral `D(y) = e^{−y²} ∫_0^y e^{u²} du`.

use crate::error::{non_negative, positive};
use crate::{Prony, ViscoError};

/// Dawson's integral `D(x) = e^{−x²} ∫_0^x e^{u²} du` (Rybicki's method,
/// relative error below 2e-7; Press et al., Numerical Recipes §6.10).
pub fn dawson(x: f64) -> f64 {
    const H: f64 = 0.4;
    const TERMS: usize = 6;
    if x.abs() < 0.2 {
        let x2 = x * x;
        return x * (1.0 - 2.0 / 3.0 * x2 * (1.0 - 0.4 * x2 * (1.0 - 2.0 / 7.0 * x2)));
    }
    let xx = x.abs();
    let n0 = 2.0 * (0.5 * xx / H).round();
    let xp = xx - n0 * H;
    let mut e1 = (2.0 * xp * H).exp();
    let e2 = e1 * e1;
    let mut d1 = n0 + 1.0;
    let mut d2 = d1 - 2.0;
    let mut sum = 0.0;
    for i in 0..TERMS {
        let c = (-((2 * i + 1) as f64 * H).powi(2)).exp();
        sum += c * (e1 / d1 + 1.0 / (d2 * e1));
        d1 += 2.0;
        d2 -= 2.0;
        e1 *= e2;
    }
    x.signum() * (1.0 / std::f64::consts::PI.sqrt()) * (-xp * xp).exp() * sum
}

/// The Lee–Radok force (N) on a rigid sphere of radius `radius` (m) pressed
/// into `material` at constant approach rate `rate` (m/s), at time `time`
/// (s) after first contact; 0 at or before first contact (`time ≤ 0`).
///
/// # Errors
/// [`ViscoError::InvalidValue`] unless `radius` is finite and > 0, `rate`
/// finite and ≥ 0 (a withdrawing sphere recedes, where Lee–Radok does not
/// hold) and `time` finite, or when the force overflows (the approach
/// `rate · time` is named).
pub fn lee_radok_ramp_force(
    material: &Prony,
    radius: f64,
    rate: f64,
    time: f64,
) -> Result<f64, ViscoError> {
    positive("sphere radius (m)", radius)?;
    non_negative("approach rate (m/s)", rate)?;
    if !time.is_finite() {
        return Err(ViscoError::InvalidValue {
            name: "time (s)",
            value: time,
            expected: "finite",
        });
    }
    if time <= 0.0 {
        return Ok(0.0);
    }
    let nu = material.poisson_ratio();
    let prefactor = 4.0 * radius.sqrt() / (3.0 * (1.0 - nu * nu));
    let mut integral = material.long_term() * (rate * time).powf(1.5);
    for b in material.branches() {
        let x = time / b.relaxation_time;
        integral +=
            b.modulus * 1.5 * (rate * b.relaxation_time).powf(1.5) * (x.sqrt() - dawson(x.sqrt()));
    }
    let force = prefactor * integral;
    if !force.is_finite() {
        return Err(ViscoError::InvalidValue {
            name: "approach rate · time (m)",
            value: rate * time,
            expected: "small enough that the Lee–Radok force is finite",
        });
    }
    Ok(force)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Branch;

    #[test]
    fn dawson_matches_tabulated_values() {
        // The definition integrated by the midpoint rule (2e5 panels, 1e-10).
        for (x, d) in [
            (0.1, 0.099_335_992_4),
            (0.5, 0.424_436_38),
            (0.924_138_5, 0.541_044_25),
            (1.0, 0.538_079_51),
            (2.0, 0.301_340_39),
            (5.0, 0.102_134_074_2),
        ] {
            assert!(
                (dawson(x) - d).abs() / d < 1e-6,
                "D({x}) = {} vs {d}",
                dawson(x)
            );
            assert!((dawson(-x) + d).abs() / d < 1e-6);
        }
        // Large argument: D(x) → 1/(2x) (1 + 1/(2x²)).
        let x = 30.0;
        assert!((dawson(x) - (1.0 + 0.5 / (x * x)) / (2.0 * x)).abs() < 1e-7);
    }

    #[test]
    fn limits_of_the_closed_form_are_hertz() {
        let material = Prony::new(
            1e6,
            vec![Branch {
                modulus: 9e6,
                relaxation_time: 1e-3,
            }],
            0.5,
        )
        .expect("valid");
        let hertz = |e: f64, delta: f64| 4.0 / 3.0 * e / 0.75 * 0.01f64.sqrt() * delta.powf(1.5);
        let delta = 1e-4;
        // Slow (t = 10⁷ τ): the branch adds (3/2) E_k τ / (E∞ t) ≈ 1e-6.
        let slow = lee_radok_ramp_force(&material, 0.01, delta / 1e4, 1e4).expect("finite");
        assert!((slow / hertz(1e6, delta) - 1.0).abs() < 5e-3);
        let fast = lee_radok_ramp_force(&material, 0.01, delta / 1e-9, 1e-9).expect("finite");
        assert!((fast / hertz(10e6, delta) - 1.0).abs() < 5e-3);
    }

    /// Regression (adversarial run): a negative or NaN radius or a negative
    /// rate gave a NaN force, a NaN time 0 N and t = 1e300 s an infinite one.
    #[test]
    fn a_bad_radius_rate_or_time_is_refused_not_a_nan_or_infinite_force() {
        let branch = |modulus, relaxation_time| Branch {
            modulus,
            relaxation_time,
        };
        let material =
            Prony::new(2e6, vec![branch(3e6, 1e-3), branch(1e6, 1e-1)], 0.5).expect("valid");
        let name = |r: f64, v: f64, t: f64| match lee_radok_ramp_force(&material, r, v, t) {
            Err(ViscoError::InvalidValue { name, .. }) => name,
            other => panic!("R = {r}, rate = {v}, t = {t}: {other:?}"),
        };
        assert_eq!(name(-5e-3, 1e-3, 0.1), "sphere radius (m)");
        assert_eq!(name(f64::NAN, 1e-3, 0.1), "sphere radius (m)");
        assert_eq!(name(5e-3, -1e-3, 0.1), "approach rate (m/s)");
        assert_eq!(name(5e-3, 1e-3, f64::NAN), "time (s)");
        assert_eq!(name(5e-3, 1e-3, 1e300), "approach rate · time (m)");
        let e = lee_radok_ramp_force(&material, 5e-3, 1e-3, 1e300).expect_err("overflow");
        assert!(e.to_string().contains("1e297"), "{e}");
        // Before first contact the sphere carries nothing.
        assert_eq!(lee_radok_ramp_force(&material, 5e-3, 1e-3, -1.0), Ok(0.0));
        let f = lee_radok_ramp_force(&material, 5e-3, 1e-3, 0.1).expect("finite");
        assert!((f - 0.344_144_743_119_677_3).abs() < 1e-12, "{f}");
    }
}
