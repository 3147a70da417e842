//! The contact-law interface and the local contact rebuilt from a force.

use std::f64::consts::PI;

/// A force and its derivative at one interpenetration.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct LawPoint {
    /// `P(δ)` (N).
    pub force: f64,
    /// `k(δ) = dP/dδ` (N/m).
    pub stiffness: f64,
}

/// The force–interpenetration law of one rigid asperity on the half-space.
///
/// Implementations keep: `P = k = 0` for `δ ≤ 0` (and NaN), `P` continuous
/// and non-decreasing, `k = dP/dδ`. A law knows nothing of the other
/// asperities or of any solver.
pub trait ContactLaw {
    /// `P(δ)` and `dP/dδ` at interpenetration `depth` = δ (m).
    fn evaluate(&self, depth: f64) -> LawPoint;

    /// `P(δ)` (N).
    fn force(&self, depth: f64) -> f64 {
        self.evaluate(depth).force
    }

    /// The local contact carrying `force` at interpenetration `depth`: its
    /// radius and pressure distribution (docs/theory.md §2).
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact;
}

impl<L: ContactLaw + ?Sized> ContactLaw for &L {
    fn evaluate(&self, depth: f64) -> LawPoint {
        (**self).evaluate(depth)
    }
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        (**self).local_contact(force, depth)
    }
}

impl<L: ContactLaw + ?Sized> ContactLaw for std::sync::Arc<L> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        (**self).evaluate(depth)
    }
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        (**self).local_contact(force, depth)
    }
}

/// Shape of the pressure distribution over a circular local contact of
/// radius `a` carrying force `P`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PressureProfile {
    /// Hertz: `p(r) = 3P / (2π a²) · √(1 − r²/a²)`.
    Hertz,
    /// Sneddon's cone: `p(r) = P / (π a²) · arcosh(a / r)` (integrable
    /// logarithmic singularity at the apex).
    Cone,
}

/// A local contact rebuilt from an asperity's force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalContact {
    /// Force carried (N).
    pub force: f64,
    /// Radius of the (equivalent) circular contact area (m).
    pub radius: f64,
    /// Shape of the pressure distribution.
    pub profile: PressureProfile,
}

impl LocalContact {
    /// No contact.
    pub const NONE: Self = Self {
        force: 0.0,
        radius: 0.0,
        profile: PressureProfile::Hertz,
    };

    /// Contact area `π a²` (m²).
    pub fn area(&self) -> f64 {
        PI * self.radius * self.radius
    }

    /// Mean pressure `P / (π a²)` (Pa), zero without contact.
    pub fn mean_pressure(&self) -> f64 {
        if self.radius > 0.0 {
            self.force / self.area()
        } else {
            0.0
        }
    }

    /// Pressure (Pa) at distance `r` (m) from the contact centre; zero outside
    /// (`|r| ≥ a`) and for a NaN `r`. A negative `r` is a signed coordinate
    /// along a line through the centre: its distance is `|r|`.
    /// The cone's apex value (`r = 0`) is infinite in theory; it is capped at
    /// its value at `r = a·10⁻⁶` so maps stay finite.
    pub fn pressure_at(&self, r: f64) -> f64 {
        let a = self.radius;
        let s = r.abs() / a;
        if !(a > 0.0) || !(s < 1.0) {
            return 0.0;
        }
        match self.profile {
            PressureProfile::Hertz => 1.5 * self.mean_pressure() * (1.0 - s * s).sqrt(),
            PressureProfile::Cone => self.mean_pressure() * (1.0 / s.max(1e-6)).acosh(),
        }
    }
}

impl<L: ContactLaw + ?Sized> ContactLaw for Box<L> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        (**self).evaluate(depth)
    }
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        (**self).local_contact(force, depth)
    }
}
