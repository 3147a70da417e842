//! The Wilke–Sameur interaction-potential law (paper eq. 1).

use std::f64::consts::PI;

use tyreroad_asperity::{CapGeometry, CapMeasures, Cone, EllipticParaboloid, Sphere};

use crate::{ContactLaw, LawError, LawPoint, LocalContact, Material, PressureProfile};

/// `c` given by the paper for a sphere (Sameur 2004).
pub const C_SPHERE: f64 = 0.36;
/// `c` given by the paper for a cone (Sameur 2004).
pub const C_CONE: f64 = 0.45;
/// `c = 2 / π^(3/2)`: the value for which the sphere law is exactly Hertz as
/// `δ/R → 0`.
pub const C_HERTZ_EXACT: f64 = 0.359_174_244_250_333_1;
/// `c = 45 / (4 √2 π^(5/2))`: the value for which the cone law is exactly
/// Sneddon's.
pub const C_SNEDDON_EXACT: f64 = 0.454_739_670_621_523_9;

/// How the local contact (radius and pressure) is rebuilt from the force.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum LocalRule {
    /// Hertz with radius of curvature `R`: `a = (3 P R / (4 E*))^(1/3)`
    /// (independent of `δ`, how the paper computed its model radii).
    Hertz {
        /// Summit radius of curvature (m).
        radius: f64,
    },
    /// Sneddon's cone of half-angle `α`: `a = √(2 P tan α / (π E*))`
    /// (from `P = π/2 · E* a² cot α`), logarithmic pressure.
    Sneddon {
        /// Half-angle (rad).
        half_angle: f64,
    },
    /// Any shape: the contact area is half the cap's base area,
    /// `π a² = Σ(δ) / 2`, with a Hertzian pressure profile. Exact for every
    /// paraboloid in Hertz's limit (`π R δ = Σ/2`); for a cone it
    /// overestimates Sneddon's radius by 11 %. The two-scale BEM rebuild is the
    /// accurate alternative for real shapes.
    HalfSection,
}

impl LocalRule {
    /// The rule if its parameter is one the closed-form laws accept;
    /// otherwise every local contact would get a negative or NaN radius.
    pub fn validate(self) -> Result<Self, LawError> {
        match self {
            Self::Hertz { radius } if !(radius.is_finite() && radius > 0.0) => {
                Err(LawError::InvalidParameter {
                    name: "local rule Hertz radius (m)",
                    value: radius,
                })
            }
            Self::Sneddon { half_angle }
                if !(half_angle.is_finite() && half_angle > 0.0 && half_angle < PI / 2.0) =>
            {
                Err(LawError::InvalidParameter {
                    name: "local rule Sneddon half-angle (rad, in (0, π/2))",
                    value: half_angle,
                })
            }
            _ => Ok(self),
        }
    }
}

/// The interaction-potential law of Wilke and Sameur (docs/theory.md §1):
///
/// ```text
/// U(δ) = c · 8 π^(3/4) / 15 · E/(1 − ν²) · Ω² Γ^(1/2) / Σ^(7/4),   P = dU/dδ
/// ```
///
/// `P` and `k = dP/dδ` are computed analytically from the cap measures and
/// their derivatives through the logarithmic derivative
/// `g = U'/U = 2Σ/Ω + Γ'/(2Γ) − 7Σ'/(4Σ)` (using `Ω' = Σ`): `P = U g`,
/// `k = U (g² + g')`.
///
/// # Monotone envelope
///
/// `P = dU/dδ` increases for the closed-form shapes, but not for every cap:
/// when the section grows in a burst (the plane reaching a second summit of
/// a segmented road asperity), `Σ'` jumps, the `−7Σ'/(4Σ)` term pulls `P`
/// down, and `P` can lose most of its value, or even turn negative, before
/// rising again (below a basin's rim, where its section's perimeter
/// shrinks, more so). A
/// decreasing law breaks the [`ContactLaw`] contract the multipoint solver
/// relies on (it takes a contact with `k ≤ 0` for a free one, and its Newton
/// iteration then only converges linearly, or stalls). A law that merely
/// flattens is nearly as bad: near a local maximum `k → 0`, and a Newton
/// step `ΔP/k` throws the depth far off. So, for a shape with
/// [`CapGeometry::breakpoints`] (a [`tyreroad_asperity::TabulatedCap`]),
/// the law is scanned piece by piece when built, and wherever its stiffness
/// falls below [`MIN_STIFFNESS_RATIO`] `· P/δ` it is replaced by a ramp: from
/// the depth `a` where that happens, the law rises along the straight line
/// `P(a) + s (δ − a)`, `s = MIN_STIFFNESS_RATIO · P(a)/a`, to the depth `b`
/// where the raw law climbs back onto the line. The result is continuous,
/// strictly increasing, with `k ≥ s > 0` on every ramp, equal to the
/// potential law outside the ramps ([`PotentialLaw::ramps`]), and its `k` is
/// still `dP/dδ` (one-sided at the ramps' ends, as at a table's nodes).
/// [`PotentialLaw::potential`] stays the raw `U`. Shapes without breakpoints
/// (the closed forms) are left as they are.
#[derive(Clone, Debug, PartialEq)]
pub struct PotentialLaw<G> {
    geometry: G,
    material: Material,
    constant: f64,
    rule: LocalRule,
    /// Where the raw law is too flat or falls: sorted, disjoint ramps.
    ramps: Vec<Ramp>,
}

/// Smallest stiffness of a [`PotentialLaw`] on a tabulated cap, relative to
/// its secant `P/δ` (a sphere has `k δ/P = 3/2`, a cone 2, a flat punch 1):
/// below it, the law follows a [`Ramp`].
pub const MIN_STIFFNESS_RATIO: f64 = 0.1;

/// A depth range over which a [`PotentialLaw`] follows a straight ramp
/// because the raw potential law is too flat or dips there (see the type's
/// docs): `P = force + slope · (δ − start)` on `[start, end)`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Ramp {
    /// Depth where the raw law's stiffness falls below
    /// [`MIN_STIFFNESS_RATIO`] `· P/δ` and the ramp starts (m).
    pub start: f64,
    /// Depth where the raw law climbs back onto the ramp (m); infinite if
    /// it never does.
    pub end: f64,
    /// The raw law's force at `start` (N).
    pub force: f64,
    /// The ramp's stiffness, [`MIN_STIFFNESS_RATIO`] `· force/start` (N/m).
    pub slope: f64,
}

impl Ramp {
    /// The ramp's force at `depth` (N).
    pub fn force_at(&self, depth: f64) -> f64 {
        self.force + self.slope * (depth - self.start)
    }
}

/// Samples of the stiffness margin per piece between two breakpoints when
/// scanning for ramps.
const SCAN_SAMPLES: usize = 8;

/// The width, relative to the samples' spacing, below which the search for
/// a dip of the stiffness margin between two samples stops.
const MINIMUM_BRACKET: f64 = 1e-7;

impl<G: CapGeometry> PotentialLaw<G> {
    /// The law of `geometry` with shape constant `constant` (`c`) and the
    /// local rule `rule`.
    ///
    /// Refused: `c` not finite and > 0 ([`LawError::InvalidConstant`]); a
    /// rule whose parameter [`HertzLaw::new`](crate::HertzLaw::new) or
    /// [`SneddonLaw::new`](crate::SneddonLaw::new) would refuse, i.e. a
    /// [`LocalRule::Hertz`] radius not finite and > 0 or a
    /// [`LocalRule::Sneddon`] half-angle outside `(0, π/2)`
    /// ([`LawError::InvalidParameter`]).
    pub fn new(
        geometry: G,
        material: Material,
        constant: f64,
        rule: LocalRule,
    ) -> Result<Self, LawError> {
        if !(constant.is_finite() && constant > 0.0) {
            return Err(LawError::InvalidConstant(constant));
        }
        rule.validate()?;
        Ok(Self {
            geometry,
            material,
            constant,
            rule,
            ramps: Vec::new(),
        }
        .with_ramps())
    }

    /// The shape.
    pub fn geometry(&self) -> &G {
        &self.geometry
    }

    /// The half-space's material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The shape constant `c`.
    pub fn constant(&self) -> f64 {
        self.constant
    }

    /// The local-contact rule.
    pub fn rule(&self) -> LocalRule {
        self.rule
    }

    /// The same law with another shape constant `c`.
    pub fn with_constant(mut self, constant: f64) -> Result<Self, LawError> {
        if !(constant.is_finite() && constant > 0.0) {
            return Err(LawError::InvalidConstant(constant));
        }
        self.constant = constant;
        Ok(self.with_ramps())
    }

    /// The ramps that keep the law's stiffness at least
    /// [`MIN_STIFFNESS_RATIO`] `· P/δ` (empty when the raw potential law
    /// already is that stiff, and for shapes without breakpoints).
    pub fn ramps(&self) -> &[Ramp] {
        &self.ramps
    }

    /// How far below the smallest stiffness the raw law is at `depth`:
    /// `k − MIN_STIFFNESS_RATIO · P/δ` (negative where a ramp is needed).
    fn stiffness_margin(&self, depth: f64) -> f64 {
        let raw = self.raw(depth);
        raw.stiffness - MIN_STIFFNESS_RATIO * raw.force / depth
    }

    /// The raw potential law `P = dU/dδ`, `k = dP/dδ`, without ramps.
    ///
    /// Where `U` underflows to 0 (caps of a few 1e-130 m on rubber), `P` and
    /// `k` are 0, as at `δ = 0`.
    pub fn raw(&self, depth: f64) -> LawPoint {
        let cap = self.geometry.cap(depth);
        let (om, sg, gm) = (cap.volume, cap.base_area, cap.perimeter);
        if !(om > 0.0 && sg > 0.0 && gm > 0.0) {
            return LawPoint::default();
        }
        let log_u = self.log_potential(om, sg, gm);
        let u = log_u.exp();
        if u == 0.0 {
            return LawPoint::default();
        }
        let (ds, dg) = (cap.d_base_area, cap.d_perimeter);
        let g = 2.0 * sg / om + 0.5 * dg / gm - 1.75 * ds / sg;
        let dg_log = 2.0 * (ds / om - (sg / om).powi(2))
            + 0.5 * (cap.d2_perimeter / gm - (dg / gm).powi(2))
            - 1.75 * (cap.d2_base_area / sg - (ds / sg).powi(2));
        let point = LawPoint {
            force: u * g,
            stiffness: u * (g * g + dg_log),
        };
        // `U` past 1e308 J (a cap pressed absurdly deep) stays infinite: the
        // solvers refuse a force that is not finite, where a finite 1e165 N
        // from a 5 mm ball pressed 1e160 m would pass for an answer.
        if (point.force.is_finite() && point.stiffness.is_finite()) || !u.is_finite() {
            point
        } else {
            Self::scaled_raw(&cap, depth, log_u)
        }
    }

    /// [`Self::raw`] where `g² ∼ 1/δ²` overflows (δ below ~1e-154 m on a
    /// stiff material, `g² + g'` then reads `∞ − ∞`): every ratio scaled by `δ` to order 1 first (`G = δ g`,
    /// `G' = δ² g'`), the powers of `U` and `δ` taken in logarithms,
    /// `P = U/δ · G`, `k = U/δ² · (G² + G')`.
    fn scaled_raw(cap: &CapMeasures, depth: f64, log_u: f64) -> LawPoint {
        let (om, sg, gm) = (cap.volume, cap.base_area, cap.perimeter);
        let (ds, dg) = (cap.d_base_area, cap.d_perimeter);
        // Products first: `ds / om` alone overflows when `Ω` is subnormal.
        let a = sg * depth / om;
        let b = dg * depth / gm;
        let c = ds * depth / sg;
        let g = 2.0 * a + 0.5 * b - 1.75 * c;
        let dg_log = 2.0 * (ds * depth / om * depth - a * a)
            + 0.5 * (cap.d2_perimeter * depth * depth / gm - b * b)
            - 1.75 * (cap.d2_base_area * depth * depth / sg - c * c);
        let ln_d = depth.ln();
        let times = |log_scale: f64, x: f64| {
            if x == 0.0 {
                0.0
            } else {
                x.signum() * (log_scale + x.abs().ln()).exp()
            }
        };
        LawPoint {
            force: times(log_u - ln_d, g),
            stiffness: times(log_u - 2.0 * ln_d, g * g + dg_log),
        }
    }

    /// Scans the raw law over the geometry's pieces and records its ramps.
    ///
    /// The raw law is smooth between two breakpoints, so the depths where it
    /// is too flat (`k < MIN_STIFFNESS_RATIO · P/δ`, "soft") are found piece
    /// by piece: the margin sampled at [`SCAN_SAMPLES`] + 1 points of each
    /// piece, from just after its start to just before its end (the
    /// one-sided values at a node, where `k` may jump), plus the margin's
    /// minimum (golden section) around every sampled local minimum, every
    /// change of sign located by bisection. One more piece's width past the
    /// last breakpoint is scanned too. Each soft stretch then starts a ramp
    /// at its first depth `a`; the ramp ends in the first stiff stretch where
    /// `P` climbs back onto it (bisection), swallowing the soft stretches in
    /// between. Only a dip of the margin that leaves no local minimum among
    /// the samples can be missed; the law stays continuous.
    fn with_ramps(mut self) -> Self {
        self.ramps.clear();
        let knots = self.geometry.breakpoints();
        let n = knots.len();
        if n < 2 || !knots.iter().all(|d| d.is_finite() && *d > 0.0) {
            return self;
        }
        let width = knots[n - 1] - knots[n - 2];
        let mut ends = knots.clone();
        ends.push(knots[n - 1] + width);
        let soft = |d: f64| self.stiffness_margin(d) < 0.0;
        // Depth ranges where the raw law is soft: (start, end).
        let mut stretches: Vec<(f64, f64)> = Vec::new();
        let mut open: Option<f64> = None;
        for w in ends.windows(2) {
            let (x0, x1) = (w[0], w[1]);
            // The one-sided values at both ends: `cap` at a node may belong
            // to either piece (the last node to the piece before it).
            let mut ts: Vec<f64> = (0..=SCAN_SAMPLES)
                .map(|i| match i {
                    0 => x0.next_up(),
                    SCAN_SAMPLES => x1.next_down(),
                    _ => x0 + (x1 - x0) * i as f64 / SCAN_SAMPLES as f64,
                })
                .collect();
            let ms: Vec<f64> = ts.iter().map(|&t| self.stiffness_margin(t)).collect();
            // A dip of the margin between two samples that stay positive:
            // look for its minimum around every sampled local minimum, and
            // keep it as a sample when it is negative.
            let mut extra = Vec::new();
            for i in 0..ts.len() {
                let (a, b) = (i.saturating_sub(1), (i + 1).min(ts.len() - 1));
                if ms[i] >= 0.0 && ms[i] <= ms[a] && ms[i] <= ms[b] {
                    let t = self.margin_minimum(ts[a], ts[b]);
                    if self.stiffness_margin(t) < 0.0 {
                        extra.push(t);
                    }
                }
            }
            ts.extend(extra);
            ts.sort_by(f64::total_cmp);
            let mut prev = (ts[0], soft(ts[0]));
            match (open, prev.1) {
                (Some(start), false) => {
                    stretches.push((start, x0));
                    open = None;
                }
                (None, true) => open = Some(x0),
                _ => {}
            }
            for &t in &ts[1..] {
                let now = soft(t);
                if now != prev.1 {
                    let (lo, hi) = self.sign_change(prev.0, t, prev.1);
                    match open {
                        None => open = Some(lo),
                        Some(start) => {
                            stretches.push((start, hi));
                            open = None;
                        }
                    }
                }
                prev = (t, now);
            }
        }
        if let Some(start) = open {
            stretches.push((start, ends[ends.len() - 1]));
        }
        let mut ramps = Vec::new();
        let mut i = 0;
        while i < stretches.len() {
            let start = stretches[i].0;
            let force = self.raw(start).force;
            let mut ramp = Ramp {
                start,
                end: f64::INFINITY,
                force,
                slope: MIN_STIFFNESS_RATIO * force / start,
            };
            let mut j = i;
            ramp.end = loop {
                let low = stretches[j].1;
                match stretches.get(j + 1) {
                    Some(&(next, _)) if self.raw(next).force >= ramp.force_at(next) => {
                        break self.crossing(&ramp, low, next);
                    }
                    Some(_) => j += 1,
                    None => break self.climb_back(&ramp, low, width),
                }
            };
            ramps.push(ramp);
            i = j + 1;
        }
        self.ramps = ramps;
        self
    }

    /// The depth of the smallest stiffness margin in `[lo, hi]`, by
    /// golden-section search (enough for a dip between two samples). It
    /// stops at the first negative margin, or once the bracket is
    /// [`MINIMUM_BRACKET`] of its first width: a soft stretch narrower than
    /// that would carry a ramp of no consequence, and most searches are of
    /// pieces with no dip at all, where every further step is spent.
    fn margin_minimum(&self, mut lo: f64, mut hi: f64) -> f64 {
        const R: f64 = 0.618_033_988_749_895;
        let m = |t: f64| self.stiffness_margin(t);
        let smallest = MINIMUM_BRACKET * (hi - lo);
        let (mut c, mut d) = (hi - R * (hi - lo), lo + R * (hi - lo));
        let (mut mc, mut md) = (m(c), m(d));
        for _ in 0..60 {
            if mc < 0.0 || md < 0.0 || hi - lo < smallest {
                break;
            }
            if mc <= md {
                hi = d;
                (d, md) = (c, mc);
                c = hi - R * (hi - lo);
                mc = m(c);
            } else {
                lo = c;
                (c, mc) = (d, md);
                d = lo + R * (hi - lo);
                md = m(d);
            }
        }
        if mc <= md { c } else { d }
    }

    /// Brackets `[lo, hi]`, one ulp wide, of the change of sign of the
    /// stiffness margin between `lo` (soft or not, `lo_soft`) and `hi`.
    fn sign_change(&self, mut lo: f64, mut hi: f64, lo_soft: bool) -> (f64, f64) {
        loop {
            let mid = 0.5 * (lo + hi);
            if !(mid > lo && mid < hi) {
                return (lo, hi);
            }
            if (self.stiffness_margin(mid) < 0.0) == lo_soft {
                lo = mid;
            } else {
                hi = mid;
            }
        }
    }

    /// The first depth in `(lo, hi]` where `P` reaches the ramp, given
    /// `P(lo) < ramp(lo)` and `P(hi) ≥ ramp(hi)`: bisection.
    fn crossing(&self, ramp: &Ramp, mut lo: f64, mut hi: f64) -> f64 {
        loop {
            let mid = 0.5 * (lo + hi);
            if !(mid > lo && mid < hi) {
                return hi;
            }
            if self.raw(mid).force >= ramp.force_at(mid) {
                hi = mid;
            } else {
                lo = mid;
            }
        }
    }

    /// Past the scanned range: steps of doubling width until `P` reaches the
    /// ramp (beyond a table `Ω` grows linearly and `P` with it), then
    /// [`Self::crossing`]; infinite if `P` never gets there.
    fn climb_back(&self, ramp: &Ramp, from: f64, width: f64) -> f64 {
        let (mut lo, mut step) = (from, width.max(from * 1e-3));
        for _ in 0..64 {
            let hi = lo + step;
            if !hi.is_finite() {
                break;
            }
            if self.raw(hi).force >= ramp.force_at(hi) {
                return self.crossing(ramp, lo, hi);
            }
            lo = hi;
            step *= 2.0;
        }
        f64::INFINITY
    }

    /// The potential `U(δ)` (J).
    pub fn potential(&self, depth: f64) -> f64 {
        let cap = self.geometry.cap(depth);
        if !(cap.volume > 0.0 && cap.base_area > 0.0 && cap.perimeter > 0.0) {
            return 0.0;
        }
        self.log_potential(cap.volume, cap.base_area, cap.perimeter)
            .exp()
    }

    fn prefactor(&self) -> f64 {
        self.constant * 8.0 * PI.powf(0.75) / 15.0 * self.material.reduced_modulus()
    }

    // In logarithms: the powers of tiny caps under- and overflow separately.
    fn log_potential(&self, volume: f64, area: f64, perimeter: f64) -> f64 {
        self.prefactor().ln() + 2.0 * volume.ln() + 0.5 * perimeter.ln() - 1.75 * area.ln()
    }
}

impl PotentialLaw<Sphere> {
    /// The paper's sphere law: `c = 0.36`, Hertz local contacts.
    pub fn sphere(sphere: Sphere, material: Material) -> Self {
        let rule = LocalRule::Hertz {
            radius: sphere.radius(),
        };
        Self {
            geometry: sphere,
            material,
            constant: C_SPHERE,
            rule,
            ramps: Vec::new(),
        }
    }
}

impl PotentialLaw<Cone> {
    /// The paper's cone law: `c = 0.45`, Sneddon local contacts.
    pub fn cone(cone: Cone, material: Material) -> Self {
        let rule = LocalRule::Sneddon {
            half_angle: cone.half_angle(),
        };
        Self {
            geometry: cone,
            material,
            constant: C_CONE,
            rule,
            ramps: Vec::new(),
        }
    }
}

impl PotentialLaw<EllipticParaboloid> {
    /// An elliptic paraboloid with the sphere's constant `c = 0.36` and Hertz
    /// local contacts of the mean radius `√(Rx Ry)`.
    pub fn paraboloid(paraboloid: EllipticParaboloid, material: Material) -> Self {
        let (rx, ry) = paraboloid.radii();
        Self {
            geometry: paraboloid,
            material,
            constant: C_SPHERE,
            rule: LocalRule::Hertz {
                radius: (rx * ry).sqrt(),
            },
            ramps: Vec::new(),
        }
    }
}

impl<G: CapGeometry> ContactLaw for PotentialLaw<G> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        let i = self.ramps.partition_point(|r| r.start <= depth);
        if let Some(r) = i.checked_sub(1).map(|i| self.ramps[i])
            && depth < r.end
        {
            return LawPoint {
                force: r.force_at(depth),
                stiffness: r.slope,
            };
        }
        self.raw(depth)
    }

    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if !(force > 0.0) {
            return LocalContact::NONE;
        }
        let e_star = self.material.reduced_modulus();
        let (radius, profile) = match self.rule {
            LocalRule::Hertz { radius } => (
                (0.75 * force * radius / e_star).cbrt(),
                PressureProfile::Hertz,
            ),
            LocalRule::Sneddon { half_angle } => (
                (2.0 * force * half_angle.tan() / (PI * e_star)).sqrt(),
                PressureProfile::Cone,
            ),
            LocalRule::HalfSection => (
                (self.geometry.cap(depth).base_area / (2.0 * PI)).sqrt(),
                PressureProfile::Hertz,
            ),
        };
        LocalContact {
            force,
            radius,
            profile,
        }
    }
}
