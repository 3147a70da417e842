//! The contact law of one asperity during one viscoelastic time step: the
//! elastic law at the step's effective modulus, offset by the asperity's
//! memory and clipped at zero (complementarity on the real force).

use tyreroad_contact_law::{ContactLaw, LawPoint, LocalContact};

use crate::ting::BandLaw;

/// The law of one asperity in a rolling step: Lee–Radok's offset law or
/// Ting's depth bands ([`crate::Receding`]).
pub(crate) enum StepLaw<'a, L> {
    LeeRadok(MemoryLaw<'a, L>),
    Ting(BandLaw<'a, L>),
}

impl<L: ContactLaw> ContactLaw for StepLaw<'_, L> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        match self {
            Self::LeeRadok(law) => law.evaluate(depth),
            Self::Ting(law) => law.evaluate(depth),
        }
    }

    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        match self {
            Self::LeeRadok(law) => law.local_contact(force, depth),
            Self::Ting(law) => law.local_contact(force, depth),
        }
    }
}

/// `P(δ) = max(0, (E_eff/E_ref) P_ref(δ) + h)` with `h ≤ 0` the asperity's
/// memory force (docs/viscoelastic.md, "Rolling").
///
/// With `w = P_ref(δ)/E_ref` the elastic-equivalent force, the asperity is in
/// contact exactly when `E_eff w + h ≥ 0`: below that interpenetration the
/// tread's surface at the asperity is still recovering from earlier loading
/// and does not touch. Because `h ≤ 0` the law keeps the trait's rules
/// (`P = k = 0` for `δ ≤ 0`, continuous, non-decreasing); where `h < 0` its
/// slope jumps from 0 to `(E_eff/E_ref) k_ref` at the contact threshold, a
/// kink the solver's secant steps handle.
pub(crate) struct MemoryLaw<'a, L> {
    pub(crate) inner: &'a L,
    /// `E_eff / E_ref`.
    pub(crate) scale: f64,
    /// Memory force `h ≤ 0` (N).
    pub(crate) offset: f64,
}

impl<L: ContactLaw> ContactLaw for MemoryLaw<'_, L> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        let point = self.inner.evaluate(depth);
        let force = self.scale * point.force + self.offset;
        if force > 0.0 {
            LawPoint {
                force,
                stiffness: self.scale * point.stiffness,
            }
        } else {
            LawPoint {
                force: 0.0,
                stiffness: 0.0,
            }
        }
    }

    /// The patch follows the geometry (Lee–Radok: the contact radius is the
    /// elastic one at the same interpenetration), the force is the real one.
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if !(force > 0.0) {
            return LocalContact::NONE;
        }
        let elastic = self
            .inner
            .local_contact(self.inner.evaluate(depth).force, depth);
        LocalContact { force, ..elastic }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::MemoryLaw;
    use tyreroad_asperity::Sphere;
    use tyreroad_contact_law::{ContactLaw, Material, PotentialLaw};

    #[test]
    fn offset_law_is_zero_until_the_memory_is_overcome_then_scaled() {
        let rubber = Material::new(2e6, 0.5).unwrap();
        let inner = PotentialLaw::sphere(Sphere::new(5e-3).unwrap(), rubber);
        let p = |d: f64| inner.evaluate(d).force;
        let law = MemoryLaw {
            inner: &inner,
            scale: 3.0,
            offset: -3.0 * p(1e-4),
        };
        // Below the threshold δ* = 0.1 mm nothing touches.
        assert_eq!(law.evaluate(0.5e-4).force, 0.0);
        assert_eq!(law.evaluate(0.5e-4).stiffness, 0.0);
        assert_eq!(law.evaluate(-1.0).force, 0.0);
        // Above it, the scaled law minus the memory, slope scaled.
        let d = 2e-4;
        let expected = 3.0 * (p(d) - p(1e-4));
        assert!((law.evaluate(d).force - expected).abs() <= 1e-12 * expected);
        assert!(
            (law.evaluate(d).stiffness - 3.0 * inner.evaluate(d).stiffness).abs()
                <= 1e-12 * law.evaluate(d).stiffness
        );
        // The patch is the elastic one at the same depth, carrying the real force.
        let c = law.local_contact(law.evaluate(d).force, d);
        let e = inner.local_contact(p(d), d);
        assert_eq!(c.radius, e.radius);
        assert_eq!(c.force, law.evaluate(d).force);
        assert_eq!(law.local_contact(0.0, d).force, 0.0);
    }
}
