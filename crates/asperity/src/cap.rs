//! The measures of an interpenetrated cap and the trait every shape implements.

/// Measures of the cap of an asperity cut by the horizontal plane lying `δ`
/// below its summit, with the derivatives a Newton solver needs.
///
/// All values are SI: `volume` in m³, `base_area` in m², `perimeter` in m,
/// derivatives with respect to `δ` (m). For `δ ≤ 0` every field is zero.
///
/// Invariants kept by every [`CapGeometry`]: `volume` and `base_area` never
/// decrease with `δ`, and `dΩ/dδ = Σ` (lowering the cutting plane adds a slab
/// of area `Σ`), which is why the volume carries no derivative field of its own.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CapMeasures {
    /// Ω(δ): volume of the cap above the cutting plane.
    pub volume: f64,
    /// Σ(δ): area of the cap's base (the section in the cutting plane).
    pub base_area: f64,
    /// Γ(δ): perimeter of the base, all loops of the section summed.
    pub perimeter: f64,
    /// dΣ/dδ.
    pub d_base_area: f64,
    /// dΓ/dδ.
    pub d_perimeter: f64,
    /// d²Σ/dδ².
    pub d2_base_area: f64,
    /// d²Γ/dδ².
    pub d2_perimeter: f64,
}

impl CapMeasures {
    /// The empty cap, returned for `δ ≤ 0`.
    pub const EMPTY: Self = Self {
        volume: 0.0,
        base_area: 0.0,
        perimeter: 0.0,
        d_base_area: 0.0,
        d_perimeter: 0.0,
        d2_base_area: 0.0,
        d2_perimeter: 0.0,
    };

    /// True when the cap has no base (the plane does not cut the asperity).
    pub fn is_empty(&self) -> bool {
        self.base_area <= 0.0
    }
}

/// A rigid asperity whose interpenetrated cap can be measured.
///
/// Implementations must return [`CapMeasures::EMPTY`] for `δ ≤ 0` (and for a
/// NaN `δ`), keep `Ω` and `Σ` non-decreasing, and satisfy `dΩ/dδ = Σ`.
pub trait CapGeometry {
    /// Measures of the cap at interpenetration `depth` = δ (m) below the summit.
    fn cap(&self, depth: f64) -> CapMeasures;

    /// The largest δ for which the shape is described (m); beyond it the
    /// measures are an extension documented by the implementation.
    fn max_depth(&self) -> f64 {
        f64::INFINITY
    }

    /// Depths at which the measures are pieced together (table nodes, the
    /// end of a run-out), increasing; empty for shapes given by one formula.
    /// Between two of them the measures are smooth, at them the second
    /// derivatives may jump. A law built on the shape scans these pieces,
    /// e.g. for intervals where its force would decrease.
    fn breakpoints(&self) -> Vec<f64> {
        Vec::new()
    }
}

impl<G: CapGeometry + ?Sized> CapGeometry for &G {
    fn cap(&self, depth: f64) -> CapMeasures {
        (**self).cap(depth)
    }
    fn max_depth(&self) -> f64 {
        (**self).max_depth()
    }
    fn breakpoints(&self) -> Vec<f64> {
        (**self).breakpoints()
    }
}

impl<G: CapGeometry + ?Sized> CapGeometry for std::sync::Arc<G> {
    fn cap(&self, depth: f64) -> CapMeasures {
        (**self).cap(depth)
    }
    fn max_depth(&self) -> f64 {
        (**self).max_depth()
    }
    fn breakpoints(&self) -> Vec<f64> {
        (**self).breakpoints()
    }
}
