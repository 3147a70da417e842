//! Receding contacts by the method of dimensionality reduction: each
//! asperity's elastic law cut into depth bands of independent springs, each
//! band with its own Prony internal variables, so a band can leave contact
//! (and recover) while the rest of the patch still carries load.
//!
//! # Why bands
//!
//! For an axisymmetric contact the method of dimensionality reduction (Popov
//! & Heß; Argatov & Popov 2016 for viscoelastic rebound) is exact, loading
//! and unloading: the half-space is replaced by a row of independent springs
//! `x ∈ [0, ∞)` pressed by a 1D profile `g(x)`, each spring a copy of the
//! material's rheology. In contact a spring's displacement is `δ − g(x)`; a
//! spring whose force would turn negative leaves contact and its free
//! displacement recovers through its own internal variables; it touches
//! again when `δ − g(x)` reaches it. That is Ting's (1966) solution: the
//! contact radius of a receding patch is where the spring force is zero.
//!
//! The profile comes from the asperity's own elastic law `f(δ)` (per unit
//! modulus, m²), whatever it is: the springs within `a(δ)` carry
//! `f(δ) = c ∫_0^{a(δ)} (δ − g) dx`, so `f'(δ) = c a(δ)` and the springs
//! inside the radius of depth `d` (i.e. `g ≤ d`) carry, at `δ ≥ d`, the
//! tangent of `f` at `d`:
//!
//! ```text
//! inner_d(δ) = f(δ)                       δ ≤ d
//!            = f(d) + f'(d) (δ − d)       δ > d
//! ```
//!
//! A band of springs between depth levels `lo < hi` carries
//! `f_b(δ) = inner_hi(δ) − inner_lo(δ)`: no profile `g` is needed, only `f`
//! and `f'` at the levels. For a convex law every band is non-negative and
//! non-decreasing, and `Σ_b f_b = f` exactly.
//!
//! # One step
//!
//! Each band follows the recursion of the hereditary step
//! (`p_b = E_eff φ_b + h_b`, `h_b ≤ 0` its memory), clipped at zero:
//!
//! ```text
//! p_b(δ) = max(0, E_eff f_b(δ) + h_b),   φ_b = (p_b − h_b)/E_eff
//! P_i(δ) = Σ_b p_b(δ),                   w_i = Σ_b φ_b
//! ```
//!
//! `w_i`, the asperity's elastic-equivalent force, drives the Boussinesq
//! coupling (`δ_i = δ0 − H_i − Σ_j K̃_ij w_j`): it is `∫ J dP_i`, the creep
//! displacement's driver. While every band stays in contact
//! `P_i = E_eff f(δ) + Σ_b h_b`, which is Lee–Radok's recursion term by term:
//! the two treatments agree to rounding while patches grow.
//!
//! Levels are geometric, `d_j = FLOOR · 10^{j/per_decade}`, `FLOOR` = 1 nm
//! (depths below it are one band), and a band holds state only once the
//! asperity has reached it: the springs deeper than any depth reached have no
//! history and are carried as one remainder `f(δ) − inner_top(δ)`.

use tyreroad_contact_law::{ContactLaw, LawPoint, LocalContact};

use crate::ViscoError;

/// The depth below which an asperity's springs form one band (m).
pub const BAND_FLOOR: f64 = 1e-9;

/// Default depth bands per decade of interpenetration.
pub const DEFAULT_BANDS_PER_DECADE: usize = 20;

/// Most bands per decade.
pub const MAX_BANDS_PER_DECADE: usize = 1000;

/// How the hereditary model treats a contact that recedes.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Receding {
    /// Lee–Radok's recursion on each asperity's whole force, also while it
    /// recedes: exact while patches grow, over-relaxes near separation.
    LeeRadok,
    /// Ting's treatment by the method of dimensionality reduction: each
    /// asperity's law cut into `per_decade` depth bands per decade, each with
    /// its own memory, leaving and re-entering contact on its own.
    Ting {
        /// Depth bands per decade of interpenetration (1 to
        /// [`MAX_BANDS_PER_DECADE`]).
        per_decade: usize,
    },
}

impl Default for Receding {
    fn default() -> Self {
        Self::Ting {
            per_decade: DEFAULT_BANDS_PER_DECADE,
        }
    }
}

impl Receding {
    /// Checks the band count.
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for `per_decade` outside
    /// `1..=MAX_BANDS_PER_DECADE`.
    pub fn check(self) -> Result<Self, ViscoError> {
        if let Self::Ting { per_decade } = self
            && !(1..=MAX_BANDS_PER_DECADE).contains(&per_decade)
        {
            return Err(ViscoError::InvalidValue {
                name: "Ting depth bands per decade",
                value: per_decade as f64,
                expected: "from 1 to 1000",
            });
        }
        Ok(self)
    }
}

/// A depth level: `(d, f(d), f'(d))` in unit-modulus terms.
#[derive(Clone, Copy, Debug, PartialEq)]
struct Level {
    depth: f64,
    force: f64,
    slope: f64,
}

impl Level {
    /// `inner_d(δ)` and its slope, given `f(δ)` and `f'(δ)`.
    #[inline]
    fn inner(&self, depth: f64, force: f64, slope: f64) -> (f64, f64) {
        if depth <= self.depth {
            (force, slope)
        } else {
            (self.force + self.slope * (depth - self.depth), self.slope)
        }
    }
}

/// One asperity's bands: the levels reached and, per band, `φ_b` and the
/// branch variables `q_bk`.
#[derive(Clone, Debug, Default)]
pub(crate) struct Bands {
    /// Upper levels of the bands held (band `b` spans `levels[b−1]` (or 0)
    /// to `levels[b]`).
    levels: Vec<Level>,
    /// `φ_b` (m²).
    unit: Vec<f64>,
    /// `q_bk` (N), band-major.
    branch: Vec<f64>,
    /// `h_b` of the current step (N, ≤ 0).
    history: Vec<f64>,
    /// Per band, a depth from which it surely touches in the current step
    /// (`E_eff f_b + h_b ≥ 0`; `−∞` without memory): only the bands short
    /// of theirs are looked at when the law is evaluated.
    touching: Vec<f64>,
    /// `Σ_b h_b` of the current step (N).
    history_sum: f64,
    /// Band levels looked at so far (kept or merged into the base band).
    reached: usize,
    /// Upper level of the base band after a slope drop (m); 0 while the
    /// law's slope has not fallen at any level.
    base: f64,
}

impl Bands {
    /// The asperity's memory force `Σ_b h_b` of the current step (N).
    pub(crate) fn history_total(&self) -> f64 {
        self.history_sum
    }

    /// The elastic-equivalent force `w = Σ φ_b` (m²).
    pub(crate) fn unit_total(&self) -> f64 {
        self.unit.iter().sum()
    }

    /// Sets every band's `h_b` for a step with `coefficients`
    /// (`(e^{−Δt/τ_k}, E_k γ_k)`); `h_b ≤ 0` while `φ ≥ 0`, so only rounding
    /// is clipped. Also the depth from which each band surely touches: past
    /// its upper level `f_b` is linear, so that depth is closed-form.
    pub(crate) fn prepare(&mut self, coefficients: &[(f64, f64)]) {
        let k = coefficients.len();
        for (b, h) in self.history.iter_mut().enumerate() {
            let value: f64 = coefficients
                .iter()
                .zip(&self.branch[b * k..(b + 1) * k])
                .map(|((decay, weight), q)| decay * q - weight * self.unit[b])
                .sum();
            *h = value.min(0.0);
        }
        self.history_sum = self.history.iter().sum();
    }

    /// The depths from which each band surely touches at `effective`
    /// (`E_eff`) for the step's memories.
    pub(crate) fn touching_depths(&mut self, effective: f64) {
        self.touching.clear();
        let mut lower: Option<Level> = None;
        for (level, &h) in self.levels.iter().zip(&self.history) {
            let depth = if h >= 0.0 {
                f64::NEG_INFINITY
            } else {
                // f_b at its upper level and its slope beyond.
                let (f_lo, s_lo) = lower.map_or((0.0, 0.0), |l| {
                    (l.force + l.slope * (level.depth - l.depth), l.slope)
                });
                let at_top = level.force - f_lo;
                let slope = level.slope - s_lo;
                let needed = -h / effective;
                if at_top >= needed {
                    level.depth
                } else if slope > 0.0 {
                    level.depth + (needed - at_top) / slope
                } else {
                    f64::INFINITY
                }
            };
            self.touching.push(depth);
            lower = Some(*level);
        }
    }

    /// A step whose forces are unknown: every `φ_b` held, the branches
    /// relax.
    pub(crate) fn hold(&mut self, coefficients: &[(f64, f64)]) {
        let k = coefficients.len();
        for b in 0..self.unit.len() {
            for ((decay, _), q) in coefficients
                .iter()
                .zip(&mut self.branch[b * k..(b + 1) * k])
            {
                *q *= decay;
            }
        }
    }

    /// Adds the bands down to `depth` (their springs have no history yet).
    fn reach<L: ContactLaw>(
        &mut self,
        depth: f64,
        law: &L,
        reference: f64,
        per_decade: usize,
        branches: usize,
    ) {
        if !depth.is_finite() {
            return;
        }
        while self.levels.last().is_none_or(|l| l.depth < depth) {
            let j = self.reached as f64;
            let level = BAND_FLOOR * 10f64.powf(j / per_decade as f64);
            self.reached += 1;
            let point = law.evaluate(level);
            let slope = point.stiffness / reference;
            let drop = self
                .levels
                .last()
                .is_some_and(|l| slope < l.slope * (1.0 - 1e-9));
            self.levels.push(Level {
                depth: level,
                force: point.force / reference,
                slope,
            });
            self.unit.push(0.0);
            self.history.push(0.0);
            self.touching.push(f64::NEG_INFINITY);
            self.branch.extend(std::iter::repeat_n(0.0, branches));
            if drop {
                self.merge_base(branches);
            }
        }
    }

    /// The law's slope fell at the level just added: every band up to it
    /// becomes one base band `[0, that level]` (the states add up: the
    /// recursion is linear). A base band is `f(δ)` up to its level and the
    /// tangent beyond, non-negative and non-decreasing whatever the law
    /// below it, so the bands above it keep their own memories. A tabulated
    /// law's slope dips inside its first interval (a monotone cubic from a
    /// zero slope), which would otherwise cost the whole asperity its bands;
    /// a law concave throughout keeps one band, Lee–Radok's recursion
    /// clipped at zero.
    fn merge_base(&mut self, branches: usize) {
        let top = self.levels.len() - 1;
        let k = branches.max(1);
        let mut branch = vec![0.0; branches];
        for q in self.branch.chunks(k).take(top + 1) {
            for (sum, v) in branch.iter_mut().zip(q) {
                *sum += v;
            }
        }
        let unit: f64 = self.unit[..=top].iter().sum();
        let history: f64 = self.history[..=top].iter().sum();
        self.levels.drain(..top);
        self.unit = vec![unit];
        self.history = vec![history];
        self.touching = vec![f64::NEG_INFINITY];
        self.branch = branch;
        self.base = self.levels[0].depth;
    }

    /// Ends a step at interpenetration `depth`: adds the bands reached,
    /// sets each band's `φ_b` from its clipped force and advances its branch
    /// variables. Returns the force carried (N).
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn advance<L: ContactLaw>(
        &mut self,
        depth: f64,
        law: &L,
        reference: f64,
        effective: f64,
        coefficients: &[(f64, f64)],
        per_decade: usize,
    ) -> f64 {
        let k = coefficients.len();
        self.reach(depth, law, reference, per_decade, k);
        let point = law.evaluate(depth);
        let (f, s) = (point.force / reference, point.stiffness / reference);
        let mut lower = (0.0, 0.0);
        let mut total = 0.0;
        for b in 0..self.levels.len() {
            let upper = self.levels[b].inner(depth, f, s);
            let p = (effective * (upper.0 - lower.0) + self.history[b]).max(0.0);
            total += p;
            let phi = (p - self.history[b]) / effective;
            let old = self.unit[b];
            for ((decay, weight), q) in coefficients
                .iter()
                .zip(&mut self.branch[b * k..(b + 1) * k])
            {
                *q = decay * *q + weight * (phi - old);
            }
            self.unit[b] = phi;
            lower = upper;
        }
        total
    }
}

/// The depth (m) up to which Ting's treatment keeps `law` as one base band
/// when its bands are built down to `depth` at `per_decade` bands a decade:
/// the deepest band level where the law's slope falls from the level
/// before (the rule [`Receding::Ting`] applies), zero for a law whose slope
/// never falls there. Below it the asperity follows Lee–Radok's recursion
/// clipped at zero; above it each band has its own memory. `reference` is
/// the modulus the law was built with (Pa).
pub fn base_band_depth<L: ContactLaw>(
    law: &L,
    reference: f64,
    per_decade: usize,
    depth: f64,
) -> f64 {
    let mut bands = Bands::default();
    bands.reach(depth, law, reference, per_decade.max(1), 0);
    bands.base
}

/// Whether Ting's treatment keeps all of `law`'s depth bands down to
/// `depth` (m) at `per_decade` bands a decade: the law's slope does not
/// fall from one band level to the next ([`base_band_depth`] is zero).
pub fn keeps_bands<L: ContactLaw>(law: &L, reference: f64, per_decade: usize, depth: f64) -> bool {
    base_band_depth(law, reference, per_decade, depth) == 0.0
}

/// The law of one asperity during one step under Ting's treatment:
/// `P(δ) = Σ_b max(0, E_eff f_b(δ) + h_b) + E_eff (f(δ) − inner_top(δ))`.
///
/// Non-decreasing and zero for `δ ≤ 0` (`f_b(δ ≤ 0) = 0`, `h_b ≤ 0`) for a
/// convex `f`, as the solver requires.
pub(crate) struct BandLaw<'a, L> {
    pub(crate) inner: &'a L,
    /// `E_ref`, the laws' modulus (divided out).
    pub(crate) reference: f64,
    /// `E_eff` of the step.
    pub(crate) effective: f64,
    pub(crate) bands: &'a Bands,
}

impl<L: ContactLaw> BandLaw<'_, L> {
    /// The force and its slope: `E_eff f + Σ h_b` less what the bands out of
    /// contact would pull, `Σ max(0, −(E_eff f_b + h_b))`, looked for only
    /// among the bands short of the depth from which they surely touch (so
    /// while every band touches, one law evaluation and a scan of that
    /// list: the cost of an elastic law).
    fn force_at(&self, depth: f64) -> (f64, f64) {
        let point = self.inner.evaluate(depth);
        let (f, s) = (
            point.force / self.reference,
            point.stiffness / self.reference,
        );
        let e = self.effective;
        let bands = self.bands;
        let mut force = e * f + bands.history_sum;
        let mut slope = e * s;
        for (b, &touching) in bands.touching.iter().enumerate() {
            if depth >= touching {
                continue;
            }
            let upper = bands.levels[b].inner(depth, f, s);
            let lower = if b == 0 {
                (0.0, 0.0)
            } else {
                bands.levels[b - 1].inner(depth, f, s)
            };
            let p = e * (upper.0 - lower.0) + bands.history[b];
            if p < 0.0 {
                force -= p;
                slope -= e * (upper.1 - lower.1);
            }
        }
        (force.max(0.0), slope.max(0.0))
    }

    /// The force, its slope, and the depth of the outermost band carrying.
    fn bands_at(&self, depth: f64) -> (f64, f64, f64) {
        let point = self.inner.evaluate(depth);
        let (f, s) = (
            point.force / self.reference,
            point.stiffness / self.reference,
        );
        let e = self.effective;
        let mut lower = (0.0, 0.0);
        let (mut force, mut slope, mut edge) = (0.0, 0.0, 0.0);
        for (level, h) in self.bands.levels.iter().zip(&self.bands.history) {
            let upper = level.inner(depth, f, s);
            let p = e * (upper.0 - lower.0) + h;
            if p > 0.0 {
                force += p;
                slope += e * (upper.1 - lower.1);
                edge = level.depth.min(depth);
            }
            lower = upper;
        }
        // The springs deeper than any level reached: no history.
        let rest = e * (f - lower.0);
        if rest > 0.0 {
            force += rest;
            slope += e * (s - lower.1);
            edge = depth;
        }
        (force, slope.max(0.0), edge)
    }
}

impl<L: ContactLaw> ContactLaw for BandLaw<'_, L> {
    fn evaluate(&self, depth: f64) -> LawPoint {
        if !(depth > 0.0) {
            return LawPoint {
                force: 0.0,
                stiffness: 0.0,
            };
        }
        let (force, stiffness) = self.force_at(depth);
        LawPoint { force, stiffness }
    }

    /// The patch reaches the outermost band in contact: the elastic patch at
    /// that band's depth, carrying the real force.
    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if !(force > 0.0 && depth > 0.0) {
            return LocalContact::NONE;
        }
        let (_, _, edge) = self.bands_at(depth);
        let elastic = self
            .inner
            .local_contact(self.inner.evaluate(edge).force, edge);
        LocalContact { force, ..elastic }
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use tyreroad_contact_law::{HertzLaw, Material};

    fn hertz() -> HertzLaw {
        HertzLaw::new(5e-3, Material::new(1e6, 0.5).unwrap()).unwrap()
    }

    #[test]
    fn bands_add_up_to_the_law_and_each_is_non_negative_and_non_decreasing() {
        let law = hertz();
        let mut bands = Bands::default();
        bands.reach(1e-4, &law, 1e6, 7, 0);
        let full = BandLaw {
            inner: &law,
            reference: 1e6,
            effective: 3e6,
            bands: &bands,
        };
        for depth in [1e-10, 3e-9, 2e-6, 5e-5, 1e-4, 3e-4] {
            let exact = 3.0 * law.evaluate(depth).force;
            let point = full.evaluate(depth);
            assert!((point.force - exact).abs() <= 1e-12 * exact, "{depth}");
            let k = 3.0 * law.evaluate(depth).stiffness;
            assert!((point.stiffness - k).abs() <= 1e-9 * k, "{depth}");
            // Each band alone: inner_hi − inner_lo ≥ 0, rising with depth.
            let (f, s) = (
                law.evaluate(depth).force / 1e6,
                law.evaluate(depth).stiffness / 1e6,
            );
            let mut lower = (0.0, 0.0);
            for level in &bands.levels {
                let upper = level.inner(depth, f, s);
                assert!(upper.0 - lower.0 >= -1e-24 && upper.1 - lower.1 >= -1e-18);
                lower = upper;
            }
        }
        assert_eq!(full.evaluate(0.0).force, 0.0);
        assert_eq!(full.evaluate(-1.0).stiffness, 0.0);
    }

    /// `P = E_ref √δ` (m² per unit modulus at δ in m): concave.
    struct Concave;

    impl ContactLaw for Concave {
        fn evaluate(&self, depth: f64) -> LawPoint {
            if depth > 0.0 {
                LawPoint {
                    force: 1e6 * depth.sqrt(),
                    stiffness: 0.5e6 / depth.sqrt(),
                }
            } else {
                LawPoint {
                    force: 0.0,
                    stiffness: 0.0,
                }
            }
        }
        fn local_contact(&self, force: f64, _depth: f64) -> LocalContact {
            LocalContact {
                force,
                ..LocalContact::NONE
            }
        }
    }

    #[test]
    fn a_law_that_is_not_convex_keeps_one_band_for_all_depths() {
        let mut bands = Bands::default();
        let coefficients = [(0.5, 2e6)];
        bands.prepare(&coefficients);
        bands.touching_depths(3e6);
        let p = bands.advance(1e-4, &Concave, 1e6, 3e6, &coefficients, 20);
        assert_eq!(bands.levels.len(), 1);
        assert!((p - 3e6 * 1e-2).abs() < 1e-9 * p, "{p}");
        // Next step: the whole law with the whole memory, Lee–Radok's
        // recursion clipped at zero.
        bands.prepare(&coefficients);
        bands.touching_depths(3e6);
        let h = bands.history_total();
        assert!(h < 0.0);
        let law = BandLaw {
            inner: &Concave,
            reference: 1e6,
            effective: 3e6,
            bands: &bands,
        };
        let depth: f64 = 0.5e-4;
        let expected = (3e6 * depth.sqrt() + h).max(0.0);
        assert!((law.evaluate(depth).force - expected).abs() <= 1e-9 * expected.max(1.0));
        assert_eq!(law.evaluate(1e-12).force, 0.0);
    }

    /// Hertz with a stiffer start, `+ k·min(δ, d0)`: the slope falls by
    /// `k` at `d0` and the law is convex on either side, as a tabulated
    /// law whose monotone cubic dips in its first interval.
    struct StiffStart {
        hertz: HertzLaw,
        stiffness: f64,
        knee: f64,
    }

    impl ContactLaw for StiffStart {
        fn evaluate(&self, depth: f64) -> LawPoint {
            let p = self.hertz.evaluate(depth);
            if !(depth > 0.0) {
                return p;
            }
            LawPoint {
                force: p.force + self.stiffness * depth.min(self.knee),
                stiffness: p.stiffness
                    + if depth < self.knee {
                        self.stiffness
                    } else {
                        0.0
                    },
            }
        }
        fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
            self.hertz.local_contact(force, depth)
        }
    }

    #[test]
    fn a_slope_drop_near_the_start_keeps_the_bands_above_it() {
        let law = StiffStart {
            hertz: hertz(),
            stiffness: 500.0,
            knee: 2e-6,
        };
        // The base band ends at the first level past the knee (20 a decade).
        let base = super::base_band_depth(&law, 1e6, 20, 1e-4);
        assert!(
            base > 2e-6 && base < 2e-6 * 10f64.powf(1.0 / 20.0),
            "{base}"
        );
        assert!(!super::keeps_bands(&law, 1e6, 20, 1e-4));
        let mut bands = Bands::default();
        bands.reach(1e-4, &law, 1e6, 20, 0);
        // The base band and the levels of the 1.7 decades above it, each
        // a band with its own memory (the rule before kept one band).
        assert!(bands.levels.len() > 30, "{}", bands.levels.len());
        assert_eq!(bands.levels[0].depth, base);
        let full = BandLaw {
            inner: &law,
            reference: 1e6,
            effective: 3e6,
            bands: &bands,
        };
        for depth in [1e-7, 2e-6, 3e-6, 5e-5, 1e-4, 3e-4] {
            let point = law.evaluate(depth);
            let exact = 3.0 * point.force;
            assert!(
                (full.evaluate(depth).force - exact).abs() <= 1e-12 * exact,
                "{depth}"
            );
            let (f, s) = (point.force / 1e6, point.stiffness / 1e6);
            let mut lower = (0.0, 0.0);
            for level in &bands.levels {
                let upper = level.inner(depth, f, s);
                assert!(upper.0 - lower.0 >= -1e-24 && upper.1 - lower.1 >= -1e-18);
                lower = upper;
            }
        }
    }

    #[test]
    fn a_convex_law_keeps_its_bands_and_a_concave_one_does_not() {
        assert!(super::keeps_bands(&hertz(), 1e6, 20, 1e-3));
        assert!(!super::keeps_bands(&Concave, 1e6, 20, 1e-3));
        // Above the floor there is one band only, whatever the law.
        assert!(super::keeps_bands(&Concave, 1e6, 20, 0.5 * BAND_FLOOR));
    }

    #[test]
    fn a_band_with_memory_leaves_contact_alone() {
        let law = hertz();
        let mut bands = Bands::default();
        bands.reach(1e-4, &law, 1e6, 5, 0);
        // The outermost band held away by its memory: it carries nothing
        // until its own springs are pressed past that memory.
        let last = bands.levels.len() - 1;
        bands.history[last] = -1e3;
        bands.history_sum = -1e3;
        bands.touching_depths(1e6);
        let law_now = BandLaw {
            inner: &law,
            reference: 1e6,
            effective: 1e6,
            bands: &bands,
        };
        let depth = 1e-4;
        let full = law.evaluate(depth).force;
        let p = law_now.evaluate(depth).force;
        assert!(p < full && p > 0.0);
        // Its edge is then the band below it.
        let c = law_now.local_contact(p, depth);
        assert!(c.radius < law.local_contact(full, depth).radius);
        assert!(Receding::Ting { per_decade: 0 }.check().is_err());
        assert!(Receding::default().check().is_ok());
    }
}
