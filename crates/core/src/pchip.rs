//! Slopes of monotone piecewise-cubic Hermite interpolation (PCHIP).
//!
//! Given knots `x_0 < … < x_{n−1}` and values `y_k`, with `h_k = x_{k+1} − x_k`
//! and secants `Δ_k = (y_{k+1} − y_k)/h_k`, [`pchip_slopes`] returns the
//! slopes `d_k` at the knots of a Hermite cubic that is monotone wherever the
//! data are. Two rules are in use in the workspace and both are kept, bit for
//! bit, behind [`PchipRule`]:
//!
//! - [`PchipRule::HarmonicMean`] (Fritsch & Butland 1984; MATLAB's and SciPy's
//!   `pchip`): `d_k = (w₁ + w₂) / (w₁/Δ_{k−1} + w₂/Δ_k)`,
//!   `w₁ = 2h_k + h_{k−1}`, `w₂ = h_k + 2h_{k−1}` where the secants share a
//!   sign (0 otherwise); the end slopes by the shape-preserving three-point
//!   rule. Two knots give the secant at both ends.
//! - [`PchipRule::PrescribedFirst`] (Fritsch & Carlson 1980): the first slope
//!   is given, the interior slopes are the weighted arithmetic means
//!   `(h_k Δ_{k−1} + h_{k−1} Δ_k)/(h_{k−1} + h_k)` (0 at a sign change), the
//!   last slope the three-point one-sided rule; then on every interval
//!   `(α, β) = (d_k/Δ_k, d_{k+1}/Δ_k)` are clipped to `≥ 0` and scaled into
//!   the circle `α² + β² ≤ 9` (flat intervals get zero slopes).
//!
//! Preconditions (the callers validate them): `x.len() == y.len()`, `x`
//! strictly increasing, all values finite. Fewer than two knots give zero
//! slopes.

/// Which slope rule [`pchip_slopes`] applies.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum PchipRule {
    /// Fritsch–Butland harmonic mean with shape-preserving three-point ends.
    HarmonicMean,
    /// Fritsch–Carlson with the slope at the first knot prescribed (before
    /// limiting).
    PrescribedFirst(f64),
}

/// The knot slopes of the monotone cubic through `(x_k, y_k)` (see the
/// [module documentation](self)).
pub fn pchip_slopes(x: &[f64], y: &[f64], rule: PchipRule) -> Vec<f64> {
    let n = x.len().min(y.len());
    if n < 2 {
        return vec![0.0; n];
    }
    let h: Vec<f64> = (0..n - 1).map(|k| x[k + 1] - x[k]).collect();
    let del: Vec<f64> = (0..n - 1).map(|k| (y[k + 1] - y[k]) / h[k]).collect();
    match rule {
        PchipRule::HarmonicMean => harmonic_mean_slopes(&h, &del),
        PchipRule::PrescribedFirst(first) => limited_slopes(&h, &del, first),
    }
}

fn harmonic_mean_slopes(h: &[f64], del: &[f64]) -> Vec<f64> {
    let n = h.len() + 1;
    let mut d = vec![0.0; n];
    if n == 2 {
        d[0] = del[0];
        d[1] = del[0];
        return d;
    }
    for k in 1..n - 1 {
        if del[k - 1] * del[k] > 0.0 {
            let w1 = 2.0 * h[k] + h[k - 1];
            let w2 = h[k] + 2.0 * h[k - 1];
            d[k] = (w1 + w2) / (w1 / del[k - 1] + w2 / del[k]);
        }
    }
    d[0] = end_slope(h[0], h[1], del[0], del[1]);
    d[n - 1] = end_slope(h[n - 2], h[n - 3], del[n - 2], del[n - 3]);
    d
}

/// The shape-preserving three-point end slope: the one-sided parabola's
/// slope, zeroed against the secant's sign, capped at three secants where
/// the data turn.
fn end_slope(h0: f64, h1: f64, m0: f64, m1: f64) -> f64 {
    let d = ((2.0 * h0 + h1) * m0 - h0 * m1) / (h0 + h1);
    if d.signum() != m0.signum() {
        0.0
    } else if m0.signum() != m1.signum() && d.abs() > 3.0 * m0.abs() {
        3.0 * m0
    } else {
        d
    }
}

fn limited_slopes(h: &[f64], del: &[f64], first: f64) -> Vec<f64> {
    let n = h.len() + 1;
    let mut m = vec![0.0; n];
    m[0] = first;
    for k in 1..n - 1 {
        m[k] = if del[k - 1] * del[k] <= 0.0 {
            0.0
        } else {
            (h[k] * del[k - 1] + h[k - 1] * del[k]) / (h[k - 1] + h[k])
        };
    }
    m[n - 1] = if n >= 3 {
        let (ha, hb) = (h[n - 3], h[n - 2]);
        let (da, db) = (del[n - 3], del[n - 2]);
        ((2.0 * hb + ha) * db - hb * da) / (ha + hb)
    } else {
        del[0]
    };
    for k in 0..n - 1 {
        let d = del[k];
        if d == 0.0 {
            m[k] = 0.0;
            m[k + 1] = 0.0;
            continue;
        }
        let mut a = m[k] / d;
        let mut b = m[k + 1] / d;
        if a < 0.0 {
            a = 0.0;
        }
        if b < 0.0 {
            b = 0.0;
        }
        let s = a * a + b * b;
        if s > 9.0 {
            let tau = 3.0 / s.sqrt();
            a *= tau;
            b *= tau;
        }
        m[k] = a * d;
        m[k + 1] = b * d;
    }
    m
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn linear_data_give_the_secant() {
        let x = [0.0, 1.0, 3.0, 4.0];
        let y = [1.0, 3.0, 7.0, 9.0];
        assert_eq!(pchip_slopes(&x, &y, PchipRule::HarmonicMean), vec![2.0; 4]);
        assert_eq!(
            pchip_slopes(&x, &y, PchipRule::PrescribedFirst(2.0)),
            vec![2.0; 4]
        );
    }

    #[test]
    fn extrema_get_zero_slopes_and_limits_hold() {
        let x = [0.0, 1.0, 2.0, 3.0];
        let y = [0.0, 1.0, 1.0, 0.0];
        let d = pchip_slopes(&x, &y, PchipRule::HarmonicMean);
        // End rule: (2·1 + 1)·1 − 1·0)/2 = 1.5; plateau interior slopes 0.
        assert_eq!(d, vec![1.5, 0.0, 0.0, -1.5]);
        // A steep prescribed first slope is pulled into α² + β² ≤ 9.
        let d = pchip_slopes(
            &[0.0, 1.0, 2.0],
            &[0.0, 1.0, 2.0],
            PchipRule::PrescribedFirst(10.0),
        );
        let tau = 3.0 / 101f64.sqrt();
        assert_eq!(d, vec![10.0 * tau, tau, 1.0]);
        assert!(pchip_slopes(&[0.0], &[1.0], PchipRule::HarmonicMean) == vec![0.0]);
    }
}
