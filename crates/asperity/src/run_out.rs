//! The C¹ run-out that continues a cap's `Σ` and `Γ` past the last depth
//! where its shape is described, into vertical walls.
//!
//! The potential law's force `P = U (2Σ/Ω + Γ'/(2Γ) − 7Σ'/(4Σ))` holds `Σ'`
//! and `Γ'`: walls started where those slopes are not 0 make `P` jump (by a
//! factor 2 at a pyramid's base), and a jump in an increasing law leaves
//! loads that no depth carries, which stalls the multipoint Newton solver.
//! Each measure therefore runs out along a monotone cubic to a slope of 0,
//! then stays constant; `Ω` stays the integral of `Σ`.

use crate::CapMeasures;

/// The C¹ run-out of an interpolant beyond the last node `x`: the Hermite
/// cubic from `(x, y, m)` to `(x + len, y + m·len/2, 0)`, then constant.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct RunOut {
    /// Length of the cubic piece (m).
    pub(crate) len: f64,
    y: f64,
    m: f64,
}

impl RunOut {
    /// The run-out from value `y` with slope `m` at the last node, over the
    /// last interval's width `h`; a falling run-out is shortened so that it
    /// loses at most half of `y` (a perimeter stays positive).
    pub(crate) fn new(y: f64, m: f64, h: f64) -> Self {
        let len = if m < 0.0 { h.min(y / -m) } else { h };
        Self { len, y, m }
    }

    /// Value, first and second derivatives at distance `t ≥ 0` past the
    /// last node.
    pub(crate) fn eval(&self, t: f64) -> [f64; 3] {
        if self.m == 0.0 || t >= self.len {
            return [self.y + 0.5 * self.m * self.len, 0.0, 0.0];
        }
        let u = t / self.len;
        let (m0, y1) = (self.m * self.len, self.y + 0.5 * self.m * self.len);
        let v = hermite(u, self.y, m0, y1, 0.0);
        [v[0], v[1] / self.len, v[2] / (self.len * self.len)]
    }

    /// `∫₀ᵗ` of the run-out.
    pub(crate) fn integral(&self, t: f64) -> f64 {
        let m0 = self.m * self.len;
        let y1 = self.y + 0.5 * m0;
        if self.m == 0.0 {
            return self.y * t;
        }
        if t >= self.len {
            return hermite_integral(1.0, self.len, self.y, m0, y1, 0.0) + y1 * (t - self.len);
        }
        hermite_integral(t / self.len, self.len, self.y, m0, y1, 0.0)
    }
}

/// `knots` (ending at the described shape's last depth) followed by the
/// depths where the run-outs of `Σ` and `Γ` reach their walls, in order,
/// each once: the breakpoints a law scans.
pub(crate) fn with_run_out_ends(
    mut knots: Vec<f64>,
    area: &RunOut,
    perimeter: &RunOut,
) -> Vec<f64> {
    let Some(&end) = knots.last() else {
        return knots;
    };
    let mut ends = [end + area.len, end + perimeter.len];
    ends.sort_by(f64::total_cmp);
    for e in ends {
        if knots.last().is_some_and(|&last| e > last) {
            knots.push(e);
        }
    }
    knots
}

/// The measures at distance `past ≥ 0` beyond the end of a described shape,
/// `volume` its `Ω` there, each of `Σ` and `Γ` along its run-out.
pub(crate) fn past_the_end(
    volume: f64,
    area: &RunOut,
    perimeter: &RunOut,
    past: f64,
) -> CapMeasures {
    let (sig, gam) = (area.eval(past), perimeter.eval(past));
    CapMeasures {
        volume: volume + area.integral(past),
        base_area: sig[0],
        perimeter: gam[0],
        d_base_area: sig[1],
        d_perimeter: gam[1],
        d2_base_area: sig[2],
        d2_perimeter: gam[2],
    }
}

/// Cubic Hermite on `u ∈ [0, 1]` with end values `y0`, `y1` and end slopes
/// `m0`, `m1` (per unit `u`): value and first two `u`-derivatives.
#[inline]
pub(crate) fn hermite(u: f64, y0: f64, m0: f64, y1: f64, m1: f64) -> [f64; 3] {
    let u2 = u * u;
    let u3 = u2 * u;
    let v = y0 * (2.0 * u3 - 3.0 * u2 + 1.0)
        + m0 * (u3 - 2.0 * u2 + u)
        + y1 * (3.0 * u2 - 2.0 * u3)
        + m1 * (u3 - u2);
    let d = y0 * (6.0 * u2 - 6.0 * u)
        + m0 * (3.0 * u2 - 4.0 * u + 1.0)
        + y1 * (6.0 * u - 6.0 * u2)
        + m1 * (3.0 * u2 - 2.0 * u);
    let dd =
        y0 * (12.0 * u - 6.0) + m0 * (6.0 * u - 4.0) + y1 * (6.0 - 12.0 * u) + m1 * (6.0 * u - 2.0);
    [v, d, dd]
}

/// `∫` of the cubic Hermite piece of width `h` (end slopes `m0`, `m1` per
/// unit `u`) from its start to `u ∈ [0, 1]`.
#[inline]
pub(crate) fn hermite_integral(u: f64, h: f64, y0: f64, m0: f64, y1: f64, m1: f64) -> f64 {
    let (u2, u3, u4) = (u * u, u * u * u, u * u * u * u);
    h * (y0 * (u4 / 2.0 - u3 + u)
        + m0 * (u4 / 4.0 - 2.0 * u3 / 3.0 + u2 / 2.0)
        + y1 * (u3 - u4 / 2.0)
        + m1 * (u4 / 4.0 - u3 / 3.0))
}
