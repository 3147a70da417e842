//! Rung 1: a contact law calibrated by a single-asperity BEM solve of the
//! asperity's own cap (docs/validation.md, "Fidelity on textures").
//!
//! A [`CapPatch`] is the rigid surface of one asperity on a small grid,
//! heights relative to the law's summit (so `δ` of the law is measured from
//! the summit, as the multipoint model measures it). The BEM
//! (`tyreroad-bem`) solves the patch alone against the half-space under
//! approach control at `n` depths `δ_k = δ_max (k/n)²` (dense near contact
//! onset, where `P ∝ δ^{3/2}` bends most), each warm-started from the
//! previous depths' pressures ([`WarmStart`]), and records the force `F_k`
//! and the contact area `A_k`. Each depth is solved on the window of the
//! patch that can touch at it (only cells within `δ_k` of the summit can
//! carry pressure, so the others change nothing but the FFT's size): the
//! same solution for less work, most at the shallow depths.
//! The law interpolates `F(δ)` and `A(δ)` by monotone cubic Hermite
//! interpolation (core PCHIP, Fritsch–Butland slopes), so that
//! `P = F(δ)` and `k = dF/dδ` are exactly the interpolant and its derivative,
//! and the local contact radius is `√(A(δ)/π)`. Beyond `δ_max` both continue
//! linearly with their last slope (continuous, non-decreasing; a range
//! chosen from the solve's own approach never needs it).
//!
//! Tables are cached by shape: the key hashes the quantised patch heights
//! (to [`HEIGHT_QUANTUM`]), the grid, `δ_max`, `E*`, the options (node
//! count, tolerance, warm start), whether the table keeps fields and a
//! format version, so identical caps (the same chipping repeated, a sphere
//! field) are solved once per [`Calibrator`]; optionally also on disk, one
//! small file per shape (`cache`: a CSV without fields, a checksummed
//! binary with them; a file that cannot be read back whole is solved
//! again, never half read).
//!
//! A calibrator [`Calibrator::with_fields`] also keeps, per knot, the BEM
//! pressure binned into a compact field ([`super::field`]) for the
//! `calibrated_fields` coupling.

use std::collections::HashMap;
use std::path::PathBuf;
use std::sync::{Arc, Mutex};

use tyreroad_contact_law::{ContactLaw, LawPoint, LocalContact, Material, PressureProfile};
use tyreroad_core::pchip::{PchipRule, pchip_slopes};

use super::FidelityError;
use super::field::{BinnedField, UnitField};

mod along;
mod cache;
mod stand_in;
mod sweep;
mod window;
pub use along::PathNode;
use cache::{CACHE_VERSION, Fnv};
pub(crate) use stand_in::stand_in_law;
pub use sweep::{JointTile, calibrate_joint};
use sweep::{Knot, sweep};

/// Heights are quantised to this step (m) before hashing: caps equal to
/// 1 nm share a table.
pub const HEIGHT_QUANTUM: f64 = 1e-9;

/// The rigid surface of one asperity: `nx × ny` cells of `dx × dy`,
/// row-major heights (m) relative to the law's summit (all `≤ 0`; the top
/// cell may sit below 0 when the summit was refined between cells), and
/// where cell `(0, 0)` is relative to the summit in plan.
#[derive(Clone, Debug, PartialEq)]
pub struct CapPatch {
    /// Cells along x.
    pub nx: usize,
    /// Cells along y.
    pub ny: usize,
    /// Cell size along x (m).
    pub dx: f64,
    /// Cell size along y (m).
    pub dy: f64,
    /// Heights (m), `ny` rows of `nx`, all finite and `≤ 0`.
    pub heights: Vec<f64>,
    /// Plan position (m) of the centre of cell `(0, 0)` relative to the
    /// summit (cell `(i, j)` at `origin + (i dx, j dy)`). Not part of the
    /// shape: equal caps anywhere share a table.
    pub origin: [f64; 2],
}

impl CapPatch {
    /// A patch sampled from `height(x, y)` (m, relative to the summit) at
    /// the centres of an `n × n` grid of cell `cell`, centred on the origin.
    ///
    /// # Errors
    /// As [`CapPatch::validate`].
    pub fn from_fn(
        n: usize,
        cell: f64,
        height: impl Fn(f64, f64) -> f64,
    ) -> Result<Self, FidelityError> {
        let c = 0.5 * (n as f64 - 1.0);
        let heights = (0..n * n)
            .map(|k| height(((k % n) as f64 - c) * cell, ((k / n) as f64 - c) * cell))
            .collect();
        let p = Self {
            nx: n,
            ny: n,
            dx: cell,
            dy: cell,
            heights,
            origin: [-c * cell, -c * cell],
        };
        p.validate()?;
        Ok(p)
    }

    /// Checks sizes and values.
    ///
    /// # Errors
    /// [`FidelityError::InvalidInput`] naming the value: fewer than 3 cells
    /// a side, a non-positive spacing, a height count that does not match,
    /// a non-finite or positive height.
    pub fn validate(&self) -> Result<(), FidelityError> {
        if self.nx < 3 || self.ny < 3 {
            return Err(FidelityError::invalid(
                "cap patch size",
                format!("{} × {}", self.nx, self.ny),
                "at least 3 × 3 cells",
            ));
        }
        for (name, v) in [("dx", self.dx), ("dy", self.dy)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(FidelityError::invalid(name, v, "finite and > 0 m"));
            }
        }
        if self.heights.len() != self.nx * self.ny {
            return Err(FidelityError::invalid(
                "cap patch heights",
                self.heights.len(),
                format!("{} values", self.nx * self.ny),
            ));
        }
        if let Some(h) = self.heights.iter().find(|h| !(h.is_finite() && **h <= 0.0)) {
            return Err(FidelityError::invalid(
                "cap patch height",
                h,
                "finite and <= 0 m (relative to the summit)",
            ));
        }
        Ok(())
    }

    /// Depth of the highest cell below the summit (m, ≥ 0).
    pub fn summit_offset(&self) -> f64 {
        -self
            .heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// How the calibration solves are run. The defaults are the measured
/// cheap choice (docs/performance.md, "Calibration cost"): the same 16
/// depths as [`CalibrationOptions::reference`], a tolerance matched to what
/// a law needs, and the extrapolated warm start; against the reference
/// their tables differ by under 0.02 % of the largest force and 0.9 % of the
/// largest area on the seven road kinds of `cargo xtask validate
/// --textures` (`cargo xtask calib-cost`).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CalibrationOptions {
    /// Number of BEM depths per table (≥ 4). Default 16 (8 or 10 move the
    /// interpolated force by up to 5 % and the area by up to 57 % on caps
    /// whose flat tops touch at once).
    pub nodes: usize,
    /// BEM tolerance (relative complementarity residual, docs/bem.md).
    /// Default 3e-4: a 0.3 µm gap error at a 1 mm approach, which moves a
    /// table's force by under 2e-4 of its largest and its area by under
    /// 1 % of its largest on the seven roads of `cargo xtask calib-cost`,
    /// and no figure of the rolling comparisons with the BEM by more than
    /// 0.01 % (docs/performance.md, "Calibration cost"); 1e-5 costs 1.4×
    /// more, 1e-8 2× more, for nothing the law can use.
    pub tolerance: f64,
    /// Where each depth's solve starts from. Default
    /// [`WarmStart::Extrapolated`].
    pub warm_start: WarmStart,
}

impl Default for CalibrationOptions {
    fn default() -> Self {
        Self {
            nodes: 16,
            tolerance: 3e-4,
            warm_start: WarmStart::Extrapolated,
        }
    }
}

impl CalibrationOptions {
    /// The first calibration's options (16 depths, tolerance 1e-8, warm
    /// start from the previous depth): the reference a cheaper choice is
    /// measured against (`cargo xtask calib-cost`).
    pub fn reference() -> Self {
        Self {
            nodes: 16,
            tolerance: 1e-8,
            warm_start: WarmStart::Previous,
        }
    }
}

/// The first pressure of each depth's BEM solve after the first.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum WarmStart {
    /// The previous depth's pressure.
    Previous,
    /// The previous two depths' pressures extrapolated linearly in depth
    /// (clamped at 0): 0–20 % fewer iterations than `Previous`.
    Extrapolated,
    /// The previous depth's pressure dilated about its centroid as a Hertz
    /// contact grows: radius and pressure scaled by `√(δ_k / δ_{k−1})`
    /// (depths from the summit). Measured 0–10 % more iterations than
    /// `Previous` on textures: kept to be measured, not used.
    Dilated,
}

/// A tabulated force–indentation law and contact area, from BEM solves.
#[derive(Clone, Debug, PartialEq)]
pub struct CalibratedTable {
    depth: Vec<f64>,
    force: Vec<f64>,
    force_slope: Vec<f64>,
    area: Vec<f64>,
    area_slope: Vec<f64>,
    /// Whether the BEM contact reached the patch's border at `δ_max` (the
    /// patch was too small for the range: the table is then stiffer than
    /// the real cap at the largest depths).
    pub reached_border: bool,
    /// The binned BEM pressure at each knot, when asked for
    /// ([`Calibrator::with_fields`]).
    field: Option<BinnedField>,
    /// What the solves cost (empty for a table read from disk).
    stats: CalibrationStats,
}

/// What one table's BEM solves cost: the measure the calibration's cost is
/// tuned by (docs/performance.md, "Calibration cost").
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct CalibrationStats {
    /// The patch's cells `[nx, ny]`.
    pub cells: [usize; 2],
    /// Conjugate-gradient iterations of each BEM solve, in depth order.
    pub iterations: Vec<usize>,
    /// The cells `[nx, ny]` each solve ran on: the window of the patch
    /// that can touch at its depth, grown to its FFT's size.
    pub windows: Vec<[usize; 2]>,
    /// BEM solvers built (one per window growth).
    pub solver_builds: usize,
}

impl CalibratedTable {
    fn from_knots(
        depth: Vec<f64>,
        mut force: Vec<f64>,
        mut area: Vec<f64>,
        reached_border: bool,
    ) -> Self {
        // The BEM's forces and areas grow with the approach up to its
        // tolerance; a running maximum removes the round-off so the law
        // keeps its invariant (non-decreasing).
        for v in [&mut force, &mut area] {
            for k in 1..v.len() {
                v[k] = v[k].max(v[k - 1]);
            }
        }
        let force_slope = pchip_slopes(&depth, &force, PchipRule::HarmonicMean);
        let area_slope = pchip_slopes(&depth, &area, PchipRule::HarmonicMean);
        Self {
            depth,
            force,
            force_slope,
            area,
            area_slope,
            reached_border,
            field: None,
            stats: CalibrationStats::default(),
        }
    }

    /// What the table's BEM solves cost (empty when read from disk).
    pub fn stats(&self) -> &CalibrationStats {
        &self.stats
    }

    /// The binned pressure fields, one per knot, if calibrated with them.
    pub fn field(&self) -> Option<&BinnedField> {
        self.field.as_ref()
    }

    /// The unit pressure field at `depth` (points relative to the patch's
    /// cell `(0, 0)` shifted by `origin`, weights summing to one): the knots'
    /// fields blended linearly in depth, the first loaded knot's below it,
    /// the last knot's beyond the table. `None` without fields.
    pub fn unit_field(&self, depth: f64, origin: [f64; 2]) -> Option<UnitField> {
        let field = self.field.as_ref()?;
        let n = self.depth.len();
        if n == 0 {
            return None;
        }
        let (k, t) = if !(depth > self.depth[0]) {
            (0, 0.0)
        } else if depth >= self.depth[n - 1] {
            (n - 1, 0.0)
        } else {
            let k = self.depth.partition_point(|&v| v <= depth) - 1;
            (
                k,
                (depth - self.depth[k]) / (self.depth[k + 1] - self.depth[k]),
            )
        };
        field.unit_field(k, t, origin)
    }

    /// The table's knots `(δ, F, A)`.
    pub fn knots(&self) -> impl Iterator<Item = (f64, f64, f64)> + '_ {
        (0..self.depth.len()).map(|k| (self.depth[k], self.force[k], self.area[k]))
    }

    /// The largest tabulated depth (m).
    pub fn max_depth(&self) -> f64 {
        self.depth.last().copied().unwrap_or(0.0)
    }

    /// Force (N) and its slope (N/m) at `depth`.
    pub fn force_at(&self, depth: f64) -> (f64, f64) {
        hermite(&self.depth, &self.force, &self.force_slope, depth)
    }

    /// Contact area (m²) at `depth`.
    pub fn area_at(&self, depth: f64) -> f64 {
        hermite(&self.depth, &self.area, &self.area_slope, depth).0
    }
}

/// The monotone cubic through the knots and its derivative at `x`; zero
/// below the first knot, linear with the last slope beyond the last.
fn hermite(xs: &[f64], ys: &[f64], ds: &[f64], x: f64) -> (f64, f64) {
    let n = xs.len();
    if n == 0 || !(x > xs[0]) {
        return (0.0, 0.0);
    }
    if x >= xs[n - 1] {
        return (ys[n - 1] + ds[n - 1] * (x - xs[n - 1]), ds[n - 1]);
    }
    let k = xs.partition_point(|&v| v <= x) - 1;
    let h = xs[k + 1] - xs[k];
    let t = (x - xs[k]) / h;
    let (t2, t3) = (t * t, t * t * t);
    let (h00, h10, h01, h11) = (
        2.0 * t3 - 3.0 * t2 + 1.0,
        t3 - 2.0 * t2 + t,
        -2.0 * t3 + 3.0 * t2,
        t3 - t2,
    );
    let value = h00 * ys[k] + h10 * h * ds[k] + h01 * ys[k + 1] + h11 * h * ds[k + 1];
    let (d00, d10, d01, d11) = (
        6.0 * t2 - 6.0 * t,
        3.0 * t2 - 4.0 * t + 1.0,
        -6.0 * t2 + 6.0 * t,
        3.0 * t2 - 2.0 * t,
    );
    let slope = (d00 * ys[k] + d01 * ys[k + 1]) / h + d10 * ds[k] + d11 * ds[k + 1];
    (value, slope)
}

/// A calibrated law: [`ContactLaw`] over a shared [`CalibratedTable`],
/// and where its patch lies relative to the summit (for the fields).
#[derive(Clone, Debug)]
pub struct CalibratedLaw {
    table: Arc<CalibratedTable>,
    origin: [f64; 2],
    /// Tables along the path, or the blend placed at one step (`along`).
    along: Option<along::Along>,
    /// The body this law's tile was calibrated with ([`calibrate_joint`]):
    /// laws of one body already hold their mutual coupling.
    body: Option<usize>,
}

impl CalibratedLaw {
    /// The law over `table`, its patch's cell `(0, 0)` at the summit.
    pub fn new(table: Arc<CalibratedTable>) -> Self {
        Self {
            table,
            origin: [0.0; 2],
            along: None,
            body: None,
        }
    }

    /// The law over `table` calibrated on a patch whose cell `(0, 0)` lies
    /// at `origin` (m) from the summit ([`CapPatch::origin`]).
    pub fn with_origin(table: Arc<CalibratedTable>, origin: [f64; 2]) -> Self {
        Self {
            table,
            origin,
            along: None,
            body: None,
        }
    }

    /// This law as a tile of body `body` (any id shared by the tiles of
    /// one [`calibrate_joint`] and no other): the multipoint coupling
    /// between laws of one body is then cancelled
    /// ([`super::joint::body_correction`]), since their tables hold it.
    pub fn in_body(self, body: usize) -> Self {
        Self {
            body: Some(body),
            ..self
        }
    }

    /// The body this law's tile was calibrated with, if any.
    pub fn body(&self) -> Option<usize> {
        self.body
    }

    /// The unit pressure field at `depth`, points relative to the summit
    /// ([`CalibratedTable::unit_field`]); `None` without fields.
    pub fn unit_field(&self, depth: f64) -> Option<UnitField> {
        if let Some(field) = self.with_parts(|p| along::unit_field(p, depth)) {
            return field;
        }
        self.table.unit_field(depth, self.origin)
    }

    /// Its table (along the path: the node nearest the footprint's
    /// centre, or the heavier of a placed blend's two).
    pub fn table(&self) -> &CalibratedTable {
        &self.table
    }

    /// The depth (m) at which the law carries `force` (bisection on the
    /// monotone interpolant), 0 for a force ≤ 0.
    pub fn depth_for(&self, force: f64) -> f64 {
        if let Some(depth) = self.with_parts(|p| along::depth_for(p, force)) {
            return depth;
        }
        depth_for_force(force, self.table.max_depth(), |d| self.table.force_at(d).0)
    }
}

/// The depth (m) at which a non-decreasing `force_at(δ)` reaches `force`:
/// bisection in a bracket grown by doubling from `start` (the table's end,
/// where most forces lie below); 0 for a force ≤ 0, NaN when not reached
/// within a metre.
fn depth_for_force(force: f64, start: f64, force_at: impl Fn(f64) -> f64) -> f64 {
    if !(force > 0.0) {
        return 0.0;
    }
    let (mut lo, mut hi) = (0.0, start.max(1e-12));
    while force_at(hi) < force {
        lo = hi;
        hi *= 2.0;
        if hi > 1.0 {
            return f64::NAN;
        }
    }
    for _ in 0..80 {
        let mid = 0.5 * (lo + hi);
        if force_at(mid) < force {
            lo = mid;
        } else {
            hi = mid;
        }
    }
    0.5 * (lo + hi)
}

impl ContactLaw for CalibratedLaw {
    fn evaluate(&self, depth: f64) -> LawPoint {
        if let Some(point) = self.with_parts(|p| along::evaluate(p, depth)) {
            return point;
        }
        if !(depth > 0.0) {
            return LawPoint::default();
        }
        let (force, stiffness) = self.table.force_at(depth);
        LawPoint {
            force: force.max(0.0),
            stiffness: stiffness.max(0.0),
        }
    }

    fn local_contact(&self, force: f64, depth: f64) -> LocalContact {
        if let Some(contact) = self.with_parts(|p| along::local_contact(p, force, depth)) {
            return contact;
        }
        if !(force > 0.0 && depth > 0.0) {
            return LocalContact::NONE;
        }
        LocalContact {
            force,
            radius: (self.table.area_at(depth).max(0.0) / std::f64::consts::PI).sqrt(),
            profile: PressureProfile::Hertz,
        }
    }
}

/// Solves the BEM on `patch` at depths up to `max_depth` (m, from the
/// summit) and tabulates the law.
///
/// # Errors
/// [`FidelityError::InvalidInput`] for an invalid patch, options, or a
/// `max_depth` not beyond the patch's [`CapPatch::summit_offset`];
/// [`FidelityError::Bem`] if a BEM solve fails.
pub fn calibrate(
    patch: &CapPatch,
    max_depth: f64,
    material: &Material,
    options: &CalibrationOptions,
) -> Result<CalibratedTable, FidelityError> {
    calibrate_table(patch, max_depth, material, options, false)
}

/// [`calibrate`], also keeping each knot's pressure binned
/// ([`CalibratedTable::field`]).
///
/// # Errors
/// As [`calibrate`].
pub fn calibrate_with_fields(
    patch: &CapPatch,
    max_depth: f64,
    material: &Material,
    options: &CalibrationOptions,
) -> Result<CalibratedTable, FidelityError> {
    calibrate_table(patch, max_depth, material, options, true)
}

fn calibrate_table(
    patch: &CapPatch,
    max_depth: f64,
    material: &Material,
    options: &CalibrationOptions,
    fields: bool,
) -> Result<CalibratedTable, FidelityError> {
    patch.validate()?;
    let mut depth = vec![0.0];
    let mut force = vec![0.0];
    let mut area = vec![0.0];
    let mut field = fields.then(|| BinnedField::new(patch.nx, patch.ny, patch.dx, patch.dy));
    if let Some(f) = &mut field {
        // The knot at δ = 0.
        f.push_knot(None, patch.nx, patch.dx, patch.dy);
    }
    let mut reached_border = false;
    let stats = sweep(patch, max_depth, material, options, |knot| {
        let Knot::Solved {
            depth: d,
            solution: sol,
            last,
        } = knot
        else {
            depth.push(patch.summit_offset());
            force.push(0.0);
            area.push(0.0);
            if let Some(f) = &mut field {
                f.push_knot(None, patch.nx, patch.dx, patch.dy);
            }
            return;
        };
        depth.push(d);
        force.push(sol.force);
        area.push(sol.contact_area);
        if last {
            reached_border = touches_border(&sol.pressure, patch.nx, patch.ny);
        }
        if let Some(f) = &mut field {
            f.push_knot(Some(&sol.pressure), patch.nx, patch.dx, patch.dy);
        }
    })?;
    let mut table = CalibratedTable::from_knots(depth, force, area, reached_border);
    table.field = field;
    table.stats = stats;
    Ok(table)
}

fn touches_border(pressure: &[f64], nx: usize, ny: usize) -> bool {
    (0..nx * ny).any(|c| {
        let (i, j) = (c % nx, c / nx);
        pressure[c] > 0.0 && (i == 0 || j == 0 || i == nx - 1 || j == ny - 1)
    })
}

type Slot = Arc<Mutex<Option<Arc<CalibratedTable>>>>;

/// Calibrates laws and caches their tables by shape.
#[derive(Debug)]
pub struct Calibrator {
    material: Material,
    options: CalibrationOptions,
    /// One slot per shape; a slot stays locked while its shape is being
    /// solved, so two workers asking for the same cap solve it once.
    memory: Mutex<HashMap<u64, Slot>>,
    disk: Option<PathBuf>,
    counts: Mutex<CacheCounts>,
    fields: bool,
}

/// How often the cache answered.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct CacheCounts {
    /// Tables solved by the BEM.
    pub solved: usize,
    /// Tables found in memory.
    pub memory_hits: usize,
    /// Tables read from the disk cache.
    pub disk_hits: usize,
}

impl Calibrator {
    /// A calibrator with an in-memory cache.
    pub fn new(material: Material, options: CalibrationOptions) -> Self {
        Self {
            material,
            options,
            memory: Mutex::new(HashMap::new()),
            disk: None,
            counts: Mutex::new(CacheCounts::default()),
            fields: false,
        }
    }

    /// Also keeps each table's binned pressure fields (for the
    /// `calibrated_fields` coupling); a disk cache then holds them too
    /// (their own files and keys: a table without fields never stands in
    /// for one with them).
    pub fn with_fields(mut self) -> Self {
        self.fields = true;
        self
    }

    /// Whether the tables carry fields.
    pub fn has_fields(&self) -> bool {
        self.fields
    }

    /// Also keeps tables on disk under `dir` (created on first write).
    pub fn with_disk_cache(mut self, dir: impl Into<PathBuf>) -> Self {
        self.disk = Some(dir.into());
        self
    }

    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }

    /// The options every table is solved with.
    pub fn options(&self) -> &CalibrationOptions {
        &self.options
    }

    /// The cache's counts so far.
    pub fn counts(&self) -> CacheCounts {
        *self.counts.lock().unwrap_or_else(|e| e.into_inner())
    }

    fn key(&self, patch: &CapPatch, max_depth: f64) -> u64 {
        let mut h = Fnv::new();
        h.u64(CACHE_VERSION);
        h.u64(self.options.warm_start as u64);
        h.u64(patch.nx as u64);
        h.u64(patch.ny as u64);
        h.u64(patch.dx.to_bits());
        h.u64(patch.dy.to_bits());
        h.quantised(max_depth);
        h.u64(self.material.reduced_modulus().to_bits());
        h.u64(self.options.nodes as u64);
        h.u64(self.options.tolerance.to_bits());
        h.u64(u64::from(self.fields));
        for &z in &patch.heights {
            h.quantised(z);
        }
        h.0
    }

    /// The law of `patch` over depths up to `max_depth` (m): from the cache
    /// when the same shape was calibrated before, else by [`calibrate`].
    ///
    /// # Errors
    /// As [`calibrate`]; [`FidelityError::Cache`] if the disk cache cannot
    /// be written (a file that cannot be read is solved again).
    pub fn law(&self, patch: &CapPatch, max_depth: f64) -> Result<CalibratedLaw, FidelityError> {
        patch.validate()?;
        let key = self.key(patch, max_depth);
        let slot: Slot = Arc::clone(
            self.memory
                .lock()
                .unwrap_or_else(|e| e.into_inner())
                .entry(key)
                .or_default(),
        );
        let mut slot = slot.lock().unwrap_or_else(|e| e.into_inner());
        if let Some(t) = slot.as_ref() {
            self.count(|c| c.memory_hits += 1);
            return Ok(CalibratedLaw::with_origin(Arc::clone(t), patch.origin));
        }
        let file = self
            .disk
            .as_ref()
            .map(|d| cache::file_for(d, key, self.fields));
        let table = match file
            .as_deref()
            .and_then(|f| cache::read_table(f, key, self.fields))
        {
            Some(t) => {
                self.count(|c| c.disk_hits += 1);
                t
            }
            None => {
                let t =
                    calibrate_table(patch, max_depth, &self.material, &self.options, self.fields)?;
                self.count(|c| c.solved += 1);
                if let Some(f) = &file {
                    cache::write_table(f, key, &t)?;
                }
                t
            }
        };
        let table = Arc::new(table);
        *slot = Some(Arc::clone(&table));
        Ok(CalibratedLaw::with_origin(table, patch.origin))
    }

    /// The tables of the tiles of one body ([`calibrate_joint`], with this
    /// calibrator's material, options and fields). Not cached: a body's
    /// tables are its tiles' only.
    ///
    /// # Errors
    /// As [`calibrate_joint`].
    pub fn joint_tables(
        &self,
        patch: &CapPatch,
        max_depth: f64,
        tiles: &[JointTile],
    ) -> Result<Vec<CalibratedTable>, FidelityError> {
        let tables = calibrate_joint(
            patch,
            max_depth,
            &self.material,
            &self.options,
            self.fields,
            tiles,
        )?;
        self.count(|c| c.solved += 1);
        Ok(tables)
    }

    fn count(&self, f: impl FnOnce(&mut CacheCounts)) {
        f(&mut self.counts.lock().unwrap_or_else(|e| e.into_inner()));
    }
}
