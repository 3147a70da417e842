//! What defines a rolling run's results: the tread, the path, the control,
//! the sensors and the solver tolerance; and where its checkpoints go.

use std::path::PathBuf;
use std::time::Duration;

use tyreroad_core::readable;
use tyreroad_multipoint::{MAX_TOLERANCE, MIN_LOAD};

use crate::{ContactSlope, RollingError, Sensor, Tread};

/// Most steps a path may have ([`RollingConfig::validate`]).
pub const MAX_STEPS: usize = 1_000_000;

/// What is imposed on the tread at every step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum RollingControl {
    /// Load control: the wheel load `W = Σ P_i` (N); the approach is an
    /// output.
    Load(f64),
    /// Displacement control at a fixed axle height, given as the approach
    /// `δ0` (m) of the tread's lowest point below the road's reference
    /// plane ([`Road::top`](crate::Road::top)); the total force is an output.
    Approach(f64),
    /// Displacement control at a fixed axle height, given as the height `h`
    /// (m) of the tread's lowest point above the road datum `z = 0`:
    /// `δ0 = z_max − h`.
    TreadHeight(f64),
}

/// Everything that defines a rolling run's results. Two runs with equal
/// configurations (and equal roads and material) give the same results to
/// the solver tolerance whatever the chunking and thread count.
#[derive(Clone, Debug, PartialEq)]
pub struct RollingConfig {
    /// The tread's shape.
    pub tread: Tread,
    /// Lateral position `y_c` of the footprint centre (m).
    pub lateral: f64,
    /// First footprint centre `x_c` (m).
    pub start: f64,
    /// Last footprint centre (m): steps run `x_k = start + k Δx` while
    /// `x_k ≤ end` (to `10⁻⁹ Δx`).
    pub end: f64,
    /// Space step `Δx` (m, > 0).
    pub step: f64,
    /// Driving speed `V` (m/s, > 0): `t = x / V`.
    pub speed: f64,
    /// What is imposed at each step.
    pub control: RollingControl,
    /// Selection margin (m) added around a tyre's footprint on every side.
    pub margin: f64,
    /// Virtual force sensors.
    pub sensors: Vec<Sensor>,
    /// Solver tolerance, relative to the force scale. Tight (default `1e-12`)
    /// so that a step's solution does not depend on its starting point.
    pub tolerance: f64,
    /// Newton iterations allowed per step (and load step).
    pub max_iterations: usize,
    /// Where the tread touches each cap: under the deformed tread (the
    /// default) or under its undeformed profile ([`ContactSlope`]).
    pub contact_slope: ContactSlope,
}

impl RollingConfig {
    /// A configuration with no sensor, no margin, tolerance `1e-12` and 60
    /// iterations.
    pub fn new(
        tread: Tread,
        [start, end, step]: [f64; 3],
        speed: f64,
        control: RollingControl,
    ) -> Self {
        Self {
            tread,
            lateral: 0.0,
            start,
            end,
            step,
            speed,
            control,
            margin: 0.0,
            sensors: Vec::new(),
            tolerance: 1e-12,
            max_iterations: 60,
            contact_slope: ContactSlope::default(),
        }
    }

    /// Checks the configuration: a finite path of at most `MAX_STEPS` steps,
    /// a speed and step whose sample rate and duration are finite, a
    /// tolerance in `(0, MAX_TOLERANCE]` (the multipoint solver's bound), a
    /// load of 0 or at least `MIN_LOAD`, finite sensors.
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] naming the value.
    pub fn validate(&self) -> Result<(), RollingError> {
        self.tread.validate()?;
        let bad = |what: &str, v: f64| {
            Err(RollingError::InvalidInput(format!(
                "{what}: got {}",
                readable(v)
            )))
        };
        for (what, v) in [
            ("lateral", self.lateral),
            ("start", self.start),
            ("end", self.end),
        ] {
            if !v.is_finite() {
                return bad(&format!("path {what} must be finite"), v);
            }
        }
        if !(self.step.is_finite() && self.step > 0.0) {
            return bad("step must be finite and > 0 m", self.step);
        }
        if self.end < self.start {
            return bad("path end must not precede start", self.end);
        }
        // Every step keeps a record in memory: a path of more steps is a
        // step given in the wrong unit, and would overflow the step count.
        let steps = (self.end - self.start) / self.step;
        if !(steps < MAX_STEPS as f64) {
            return Err(RollingError::InvalidInput(format!(
                "path of {steps:.3e} steps (from {} m to {} m by {} m): at most {MAX_STEPS} \
                 steps; is the step in the right unit?",
                readable(self.start),
                readable(self.end),
                readable(self.step)
            )));
        }
        if !(self.speed.is_finite() && self.speed > 0.0) {
            return bad("speed must be finite and > 0 m/s", self.speed);
        }
        // The signals' times are (x − start) / V and their sample rate
        // V / Δx: both must be numbers.
        let (rate, duration) = (self.speed / self.step, (self.end - self.start) / self.speed);
        if !(rate.is_finite() && rate > 0.0 && duration.is_finite()) {
            return Err(RollingError::InvalidInput(format!(
                "speed {} m/s over steps of {} m gives a sample rate of {} Hz and a duration \
                 of {} s: both must be finite (is the speed or the step in the right unit?)",
                readable(self.speed),
                readable(self.step),
                readable(rate),
                readable(duration)
            )));
        }
        if !(self.margin.is_finite() && self.margin >= 0.0) {
            return bad("margin must be finite and ≥ 0 m", self.margin);
        }
        if !(self.tolerance > 0.0 && self.tolerance <= MAX_TOLERANCE) || self.max_iterations == 0 {
            return bad(
                &format!("tolerance must be in (0, {MAX_TOLERANCE:e}] and max_iterations ≥ 1"),
                self.tolerance,
            );
        }
        match self.control {
            RollingControl::Load(w) if !(w.is_finite() && w >= 0.0) => {
                return bad("wheel load must be finite and ≥ 0 N", w);
            }
            RollingControl::Load(w) if w > 0.0 && w < MIN_LOAD => {
                return bad(
                    &format!("wheel load must be 0 or at least {MIN_LOAD:e} N"),
                    w,
                );
            }
            RollingControl::Approach(d) | RollingControl::TreadHeight(d) if !d.is_finite() => {
                return bad("imposed approach or height must be finite", d);
            }
            _ => {}
        }
        for s in &self.sensors {
            let ok = s.x.iter().chain(&s.y).all(|v| v.is_finite())
                && s.x[0] <= s.x[1]
                && s.y[0] <= s.y[1];
            if !ok {
                return Err(RollingError::InvalidInput(format!(
                    "sensor {:?}: needs finite x0 ≤ x1 and y0 ≤ y1, got x {:?}, y {:?}",
                    s.name, s.x, s.y
                )));
            }
        }
        Ok(())
    }

    /// Under [`RollingControl::Approach`] on a tyre, the imposed approach
    /// and the tread's profile height at the edge of its selection window
    /// ([`Tread::boundary_profile`]) when the approach is the deeper:
    /// asperities outside the window could then touch at every step, so
    /// the selection is not exact there (each step's `clearance` below
    /// zero). Known before any solve; `None` otherwise (under load control
    /// the approach is an output).
    pub fn approach_past_window(&self) -> Option<(f64, f64)> {
        let RollingControl::Approach(approach) = self.control else {
            return None;
        };
        let boundary = self
            .tread
            .boundary_profile(self.tread.effective_margin(self.margin));
        (approach > boundary).then_some((approach, boundary))
    }

    /// Under [`RollingControl::Load`], the load over the tread's box
    /// (`W / (L W_t)`, Pa): the nominal pressure the footprint carries.
    /// `None` under an imposed approach (the load is an output).
    pub fn nominal_pressure(&self) -> Option<f64> {
        let RollingControl::Load(load) = self.control else {
            return None;
        };
        let (hx, hy) = self.tread.half_extents();
        Some(load / (4.0 * hx * hy))
    }

    /// The rectangle `([x0, x1], [y0, y1])` (m) the path's selection windows
    /// sweep, from the first step to the last: the tread's box (`x_c ±
    /// L/2`, `lateral ± W/2`) grown by its effective margin, and by a tenth
    /// of its half extents more (a contact selected at the window's edge
    /// spreads its pressure a little past it). No force reaches a point
    /// outside it at any step.
    pub fn swept_window(&self) -> ([f64; 2], [f64; 2]) {
        let (hx, hy) = self.tread.half_extents();
        let m = self.tread.effective_margin(self.margin);
        let (gx, gy) = (hx + m + 0.1 * hx, hy + m + 0.1 * hy);
        let last = self.position(self.steps() - 1);
        (
            [self.start.min(last) - gx, self.start.max(last) + gx],
            [self.lateral - gy, self.lateral + gy],
        )
    }

    /// The sensors wholly outside [`Self::swept_window`]: they read no
    /// force at any step (a sensor off the road, or beside the path).
    pub fn sensors_off_the_path(&self) -> Vec<&Sensor> {
        let (along, across) = self.swept_window();
        let meets = |a: [f64; 2], b: [f64; 2]| a[0] <= b[1] && b[0] <= a[1];
        self.sensors
            .iter()
            .filter(|s| !(meets(s.x, along) && meets(s.y, across)))
            .collect()
    }

    /// Number of steps on the path ([`path_steps`], at least 1).
    pub fn steps(&self) -> usize {
        path_steps(self.start, self.end, self.step).max(1.0) as usize
    }

    /// Footprint centre `x_k = start + k Δx` of step `k` (m).
    pub fn position(&self, k: usize) -> f64 {
        self.start + k as f64 * self.step
    }

    /// Sampling rate `V / Δx` (Hz) of the time signals.
    pub fn sample_rate(&self) -> f64 {
        self.speed / self.step
    }
}

/// Where and how often to checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointOptions {
    /// Directory of the checkpoint files (created when missing).
    pub dir: PathBuf,
    /// Each chunk rewrites its file at most this often (and always at its
    /// end, on an error or on an interruption). `Duration::ZERO`: every step.
    pub interval: Duration,
}

/// Steps on a path from `start` to `end` by `step` (m):
/// `⌊(end − start)/step + 10⁻⁹⌋ + 1`, the last step within rounding of
/// `end`. A float, so that a scenario check can compare a path too long to
/// count, or one that ends before it starts, before any config is built.
pub fn path_steps(start: f64, end: f64, step: f64) -> f64 {
    ((end - start) / step + 1e-9).floor() + 1.0
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (adversarial run, 2026-11-30): `approach = "100 mm"` under
    /// a 50 × 40 mm tyre footprint rolled for minutes a step, warned of
    /// only after it ended. The approach past the window's edge is known
    /// before any solve.
    #[test]
    fn an_approach_deeper_than_the_window_edge_is_known_before_the_solve() {
        let tyre = Tread::Tyre {
            radius_x: 0.3,
            radius_y: 0.5,
            length: 0.05,
            width: 0.04,
        };
        let at = |control| {
            let mut c = RollingConfig::new(tyre, [0.04, 0.08, 1e-3], 13.9, control);
            c.margin = 0.01;
            c.approach_past_window()
        };
        // Edge of the window: (25 + 10)² / (2 · 300) = 2.04 mm along x,
        // (20 + 10)² / (2 · 500) = 0.9 mm across: the lower.
        let (approach, edge) = at(RollingControl::Approach(0.1)).expect("past the edge");
        assert_eq!(approach, 0.1);
        assert!((edge - 0.9e-3).abs() < 1e-12, "{edge}");
        assert_eq!(at(RollingControl::Approach(0.5e-3)), None);
        assert_eq!(at(RollingControl::Load(30.0)), None);
        let block = Tread::Block {
            length: 0.05,
            width: 0.04,
        };
        let c = RollingConfig::new(
            block,
            [0.04, 0.08, 1e-3],
            13.9,
            RollingControl::Approach(0.1),
        );
        assert_eq!(c.approach_past_window(), None);
    }
}
