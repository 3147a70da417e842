//! Caps tabulated on a grid of depths, interpolated smoothly and monotonically
//! for fast evaluation inside the Newton solver.

use crate::run_out::{RunOut, hermite, hermite_integral, past_the_end, with_run_out_ends};
use crate::{CapGeometry, CapMeasures, GeometryError};
use tyreroad_core::{PchipRule, pchip_slopes};

/// Samples of cap measures on an increasing grid of depths: the serialised
/// form of a [`TabulatedCap`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct CapTable {
    /// Depths `δₖ` (m), strictly increasing, `δ₀ > 0`.
    pub depth: Vec<f64>,
    /// `Ωₖ` (m³), positive, non-decreasing.
    pub volume: Vec<f64>,
    /// `Σₖ` (m²), positive, non-decreasing.
    pub base_area: Vec<f64>,
    /// `Γₖ` (m), positive (may decrease: patches merging, a crater closing).
    pub perimeter: Vec<f64>,
}

/// A cap tabulated on a grid `δ₀ < … < δₙ₋₁`, smoothly and monotonically
/// interpolated.
///
/// # Interpolation
///
/// - `Σ` and `Γ`: piecewise cubic Hermite with Fritsch–Carlson monotone
///   slopes (PCHIP): slopes from the parabola through three neighbouring
///   nodes (second-order accurate on any grid, so quadratics such as the
///   sphere's `Σ` are reproduced exactly), set to 0 at a local extremum of the
///   data and scaled into the Fritsch–Carlson region `α² + β² ≤ 9`. The
///   interpolant is C¹, never leaves the range of two neighbouring nodes and
///   is monotone wherever the data are: `Σ` is non-decreasing.
/// - `Ω` is the integral of the `Σ` interpolant, from `Ω(0) = 0`. So
///   `dΩ/dδ = Σ` holds exactly everywhere and `Ω` increases. Consequence: the
///   tabulated `Ωₖ` are not interpolated; only `Ω₀` is used (it fixes the
///   onset exponent, below), and the interpolant's `Ω(δₖ)` differs from the
///   table's `Ωₖ` by the quadrature error of the `Σ` interpolant, reported by
///   [`TabulatedCap::volume_mismatch`] (≈ 1e-9 relative or better at 200
///   nodes for the analytic shapes).
/// - `Σ'`, `Γ'`, `Σ''`, `Γ''` are the derivatives of the interpolants (`Σ''`,
///   `Γ''` are piecewise linear and jump at nodes).
///
/// # Contact onset (`0 < δ < δ₀`)
///
/// A power law reaching 0 at `δ = 0`: `Σ = Σ₀ (δ/δ₀)^p`,
/// `Ω = Σ δ/(p + 1)`, `Γ = Γ₀ (δ/δ₀)^q`, with
/// `p = Σ₀δ₀/Ω₀ − 1` (so `Ω(δ₀) = Ω₀` exactly; `p = 1` for a paraboloid,
/// → 1 for a sphere, `p = 2` for a cone or a mesh whose summit is a vertex)
/// and `q = ln(Γ₁/Γ₀)/ln(δ₁/δ₀)` (clamped to `q ≥ 0`). The Hermite slopes at
/// `δ₀` are those of the power laws, so `Σ` and `Γ` are C¹ at `δ₀`. When
/// the Fritsch–Carlson limiter has to reduce a slope there (data far from a
/// power law), the exponent is lowered to the limited slope instead, keeping
/// C¹; `Ω(δ₀)` then departs from `Ω₀`. `p = 0` is a flat
/// punch (`Σ` jumps to `Σ₀` at contact): still `Ω(0) = 0`, a law
/// `P ∝ Ω²Γ^½/Σ^(7/4)` then starts as `δ`.
///
/// # Beyond the last node (`δ > δₙ₋₁ = max_depth`)
///
/// A short C¹ run-out, then vertical walls. The potential law's force
/// `P = U (2Σ/Ω + Γ'/(2Γ) − 7Σ'/(4Σ))` contains `Σ'` and `Γ'`, so `Σ` and
/// `Γ` must be C¹ for `P` to be continuous: walls started right at the last
/// node, where the Hermite slopes are not 0, would make `P` jump there (by
/// 32 % on a segmented road asperity, enough to stall the multipoint Newton
/// solver). So each of `Σ` and `Γ` continues, over a length `ℓ`, along the
/// cubic Hermite piece from its last value `yₙ₋₁` and slope `mₙ₋₁` to the
/// value `yₙ₋₁ + mₙ₋₁ℓ/2` with slope 0 (monotone: Fritsch–Carlson
/// `α = 2, β = 0`), and is constant beyond. `ℓ` is the last interval's
/// width, shortened for a falling `Γ` so that it never drops below
/// `Γₙ₋₁/2`. `Ω` stays the integral of `Σ`: cubic then linear. A shape whose
/// slopes vanish at the last node (a sphere tabulated to its equator) gets
/// exact vertical walls. [`CapGeometry::max_depth`] returns `δₙ₋₁`.
///
/// # Cost
///
/// One binary search on the grid and a cubic per measure; no allocation.
///
/// # Example
///
/// ```
/// use tyreroad_asperity::{CapGeometry, Sphere, TabulatedCap};
///
/// let ball = Sphere::new(5e-3)?;
/// let table = TabulatedCap::from_geometry(&ball, 5e-3, 200)?;
/// let (exact, fast) = (ball.cap(0.1e-3), table.cap(0.1e-3));
/// assert!((fast.volume - exact.volume).abs() < 1e-6 * exact.volume);
/// assert!((fast.perimeter - exact.perimeter).abs() < 1e-4 * exact.perimeter);
/// # Ok::<(), tyreroad_asperity::GeometryError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TabulatedCap {
    table: CapTable,
    /// `Ω` of the interpolant at the nodes.
    omega: Vec<f64>,
    /// Hermite slopes of `Σ` at the nodes.
    d_area: Vec<f64>,
    /// Hermite slopes of `Γ` at the nodes.
    d_perimeter: Vec<f64>,
    /// Onset exponent of `Σ`.
    p: f64,
    /// Onset exponent of `Γ`.
    q: f64,
    /// Run-out of `Σ` beyond the last node.
    area_tail: RunOut,
    /// Run-out of `Γ` beyond the last node.
    perimeter_tail: RunOut,
}

impl TryFrom<CapTable> for TabulatedCap {
    type Error = GeometryError;
    fn try_from(table: CapTable) -> Result<Self, GeometryError> {
        Self::new(table)
    }
}

impl From<TabulatedCap> for CapTable {
    fn from(t: TabulatedCap) -> Self {
        t.table
    }
}

/// Relative tolerance under which a decrease of `Ω` or `Σ` between two nodes
/// is taken for rounding and flattened.
const ROUNDING: f64 = 1e-12;

impl TabulatedCap {
    /// The most nodes [`TabulatedCap::default_grid`] makes: 200 resolve a
    /// cap to 1e-5; more only costs memory (`nodes` near `usize::MAX` used
    /// to abort on "capacity overflow").
    pub const MAX_NODES: usize = 1_000_000;

    /// A tabulated cap from samples (see [`CapTable`] for the requirements).
    ///
    /// Refused with [`GeometryError::InvalidTable`]: fewer than 2 nodes,
    /// columns of different lengths, non-finite values, `δ₀ ≤ 0` or depths not
    /// strictly increasing, non-positive `Ω`, `Σ` or `Γ`, `Ω` or `Σ`
    /// decreasing (decreases within `1e-12` of the column's maximum are taken
    /// for rounding and flattened), or `Ω₀ > Σ₀δ₀` (impossible for a
    /// non-decreasing `Σ` starting from 0).
    pub fn new(mut table: CapTable) -> Result<Self, GeometryError> {
        let bad = |m: String| Err(GeometryError::InvalidTable(m));
        let n = table.depth.len();
        if n < 2 {
            return bad(format!("{n} node(s): at least 2 are needed"));
        }
        if table.volume.len() != n || table.base_area.len() != n || table.perimeter.len() != n {
            return bad(format!(
                "columns of different lengths: {n} depths, {} volumes, {} base areas, {} perimeters",
                table.volume.len(),
                table.base_area.len(),
                table.perimeter.len()
            ));
        }
        for (name, col) in [
            ("depth", &table.depth),
            ("volume", &table.volume),
            ("base area", &table.base_area),
            ("perimeter", &table.perimeter),
        ] {
            if let Some(k) = col.iter().position(|v| !(v.is_finite() && *v > 0.0)) {
                return bad(format!(
                    "{name} at node {k} is {}: must be finite and > 0",
                    col[k]
                ));
            }
        }
        if let Some(k) = (1..n).find(|&k| table.depth[k] <= table.depth[k - 1]) {
            return bad(format!(
                "depths must increase strictly: δ[{}] = {} ≥ δ[{k}] = {}",
                k - 1,
                table.depth[k - 1],
                table.depth[k]
            ));
        }
        for (name, col) in [
            ("volume", &mut table.volume),
            ("base area", &mut table.base_area),
        ] {
            let tol = ROUNDING * col.iter().fold(0.0f64, |m, v| m.max(*v));
            for k in 1..n {
                if col[k] < col[k - 1] {
                    if col[k - 1] - col[k] <= tol {
                        col[k] = col[k - 1];
                    } else {
                        return bad(format!(
                            "{name} decreases from node {} ({}) to node {k} ({})",
                            k - 1,
                            col[k - 1],
                            col[k]
                        ));
                    }
                }
            }
        }
        let (d0, s0, o0) = (table.depth[0], table.base_area[0], table.volume[0]);
        if o0 > s0 * d0 * (1.0 + 1e-9) {
            return bad(format!(
                "Ω₀ = {o0} > Σ₀δ₀ = {}: the base area cannot have grown from 0 to Σ₀",
                s0 * d0
            ));
        }
        let mut p = (s0 * d0 / o0 - 1.0).max(0.0);
        let (g0, g1, d1) = (table.perimeter[0], table.perimeter[1], table.depth[1]);
        let mut q = ((g1 / g0).ln() / (d1 / d0).ln()).max(0.0);
        let d_area = pchip_slopes(
            &table.depth,
            &table.base_area,
            PchipRule::PrescribedFirst(p * s0 / d0),
        );
        let d_perimeter = pchip_slopes(
            &table.depth,
            &table.perimeter,
            PchipRule::PrescribedFirst(q * g0 / d0),
        );
        // When the limiter lowered the slope at δ₀, lower the exponent to
        // match: the onset then stays C¹ (a law's force contains Σ' and Γ',
        // so a slope jump would be a force jump), at the price of Ω(δ₀)
        // departing from Ω₀ (reported by `volume_mismatch`).
        if d_area[0] != p * s0 / d0 {
            p = d_area[0] * d0 / s0;
        }
        if d_perimeter[0] != q * g0 / d0 {
            q = d_perimeter[0] * d0 / g0;
        }
        let mut omega = Vec::with_capacity(n);
        omega.push(s0 * d0 / (p + 1.0));
        for k in 0..n - 1 {
            let h = table.depth[k + 1] - table.depth[k];
            let (y0, y1) = (table.base_area[k], table.base_area[k + 1]);
            let (m0, m1) = (d_area[k], d_area[k + 1]);
            let inc = h * (0.5 * (y0 + y1) + h * (m0 - m1) / 12.0);
            omega.push(omega[k] + inc);
        }
        if !omega.iter().all(|v| v.is_finite()) {
            return bad("the integrated volume is not finite".into());
        }
        let h_last = table.depth[n - 1] - table.depth[n - 2];
        let area_tail = RunOut::new(table.base_area[n - 1], d_area[n - 1], h_last);
        let perimeter_tail = RunOut::new(table.perimeter[n - 1], d_perimeter[n - 1], h_last);
        Ok(Self {
            table,
            omega,
            d_area,
            d_perimeter,
            p,
            q,
            area_tail,
            perimeter_tail,
        })
    }

    /// Same as [`TabulatedCap::new`] from four columns.
    pub fn from_samples(
        depth: &[f64],
        volume: &[f64],
        base_area: &[f64],
        perimeter: &[f64],
    ) -> Result<Self, GeometryError> {
        Self::new(CapTable {
            depth: depth.to_vec(),
            volume: volume.to_vec(),
            base_area: base_area.to_vec(),
            perimeter: perimeter.to_vec(),
        })
    }

    /// Tabulate `geometry` on [`TabulatedCap::default_grid`]`(max_depth, nodes)`.
    ///
    /// Refused as [`TabulatedCap::default_grid`] refuses, and with
    /// [`GeometryError::InvalidTable`] when `max_depth` lies beyond the
    /// geometry's own [`CapGeometry::max_depth`] (by more than `1e-9` of it):
    /// the grid would then sample the shape's documented extension (a
    /// sphere's cylinder below its equator), and at a `max_depth` a million
    /// times the shape's its first node already lies there, so the table's
    /// onset is a flat punch instead of the shape. Past its last node a table
    /// continues into walls of its own.
    pub fn from_geometry(
        geometry: &(impl CapGeometry + ?Sized),
        max_depth: f64,
        nodes: usize,
    ) -> Result<Self, GeometryError> {
        let grid = Self::default_grid(max_depth, nodes)?;
        let own = geometry.max_depth();
        if max_depth > own * (1.0 + 1e-9) {
            return Err(GeometryError::InvalidTable(format!(
                "max_depth {max_depth:e} m lies beyond the geometry's own max_depth {own:e} m: \
                 tabulate at most to it"
            )));
        }
        Self::from_geometry_on_grid(geometry, &grid)
    }

    /// Tabulate `geometry` at the given depths (strictly increasing, > 0).
    pub fn from_geometry_on_grid(
        geometry: &(impl CapGeometry + ?Sized),
        depths: &[f64],
    ) -> Result<Self, GeometryError> {
        let caps: Vec<CapMeasures> = depths.iter().map(|&d| geometry.cap(d)).collect();
        Self::new(CapTable {
            depth: depths.to_vec(),
            volume: caps.iter().map(|c| c.volume).collect(),
            base_area: caps.iter().map(|c| c.base_area).collect(),
            perimeter: caps.iter().map(|c| c.perimeter).collect(),
        })
    }

    /// The default grid: `nodes ≥ 2` depths in geometric progression from
    /// `1e-6·max_depth` to `max_depth` (ratio ≈ 1.072 between nodes at 200
    /// nodes): the relative resolution is the same at every scale, which is
    /// what the `δ^(1/2)`, `δ`, `δ²` behaviours of caps near contact onset
    /// need, and below `1e-6·max_depth` the onset power law takes over.
    ///
    /// Refused with [`GeometryError::InvalidParameter`]: `max_depth` not
    /// finite or below `1e6` times the smallest normal float (≈ 2.2e-302 m,
    /// where the first node `1e-6·max_depth` would lose its precision or
    /// underflow to 0), and `nodes` outside `2..=`[`TabulatedCap::MAX_NODES`].
    pub fn default_grid(max_depth: f64, nodes: usize) -> Result<Vec<f64>, GeometryError> {
        if !(max_depth.is_finite() && max_depth > 0.0) {
            return Err(GeometryError::InvalidParameter {
                name: "table max_depth",
                value: max_depth,
                requirement: "> 0",
            });
        }
        if !(1e-6 * max_depth >= f64::MIN_POSITIVE) {
            return Err(GeometryError::InvalidParameter {
                name: "table max_depth",
                value: max_depth,
                requirement: "≥ 2.2251e-302 m: its first node, 1e-6·max_depth, must be a normal float",
            });
        }
        if !(2..=Self::MAX_NODES).contains(&nodes) {
            return Err(GeometryError::InvalidParameter {
                name: "table nodes",
                value: nodes as f64,
                requirement: "≥ 2 and ≤ TabulatedCap::MAX_NODES = 1e6",
            });
        }
        let min = 1e-6 * max_depth;
        let ratio = (max_depth / min).ln();
        let last = (nodes - 1) as f64;
        let mut grid: Vec<f64> = (0..nodes)
            .map(|k| min * (ratio * k as f64 / last).exp())
            .collect();
        grid[nodes - 1] = max_depth;
        Ok(grid)
    }

    /// The samples (after flattening rounding-level decreases).
    pub fn table(&self) -> &CapTable {
        &self.table
    }

    /// Number of nodes.
    pub fn len(&self) -> usize {
        self.table.depth.len()
    }

    /// Always false: a table has at least 2 nodes.
    pub fn is_empty(&self) -> bool {
        self.table.depth.is_empty()
    }

    /// Onset exponents `(p, q)`: `Σ ∝ δ^p`, `Γ ∝ δ^q` below the first node.
    pub fn onset_exponents(&self) -> (f64, f64) {
        (self.p, self.q)
    }

    /// Largest relative difference between the tabulated `Ωₖ` and the
    /// interpolant's `Ω(δₖ)` (the integral of the `Σ` interpolant): a check of
    /// the table's consistency and of the grid's density.
    pub fn volume_mismatch(&self) -> f64 {
        self.table
            .volume
            .iter()
            .zip(&self.omega)
            .map(|(t, o)| (t - o).abs() / t)
            .fold(0.0, f64::max)
    }
}

impl CapGeometry for TabulatedCap {
    fn cap(&self, depth: f64) -> CapMeasures {
        if depth.is_nan() || depth <= 0.0 {
            return CapMeasures::EMPTY;
        }
        let t = &self.table;
        let x = &t.depth;
        let n = x.len();
        if depth < x[0] {
            let r = depth / x[0];
            let s = t.base_area[0] * r.powf(self.p);
            let g = t.perimeter[0] * r.powf(self.q);
            let (p, q) = (self.p, self.q);
            return CapMeasures {
                volume: s * depth / (p + 1.0),
                base_area: s,
                perimeter: g,
                d_base_area: p * s / depth,
                d_perimeter: q * g / depth,
                d2_base_area: p * (p - 1.0) * s / (depth * depth),
                d2_perimeter: q * (q - 1.0) * g / (depth * depth),
            };
        }
        let last = n - 1;
        if depth > x[last] {
            let past = depth - x[last];
            return past_the_end(
                self.omega[last],
                &self.area_tail,
                &self.perimeter_tail,
                past,
            );
        }
        // x[k] ≤ depth < x[k+1], or k = last − 1 at depth = x[last].
        let k = (x.partition_point(|&v| v <= depth) - 1).min(last - 1);
        let h = x[k + 1] - x[k];
        let u = (depth - x[k]) / h;
        let (y0, y1) = (t.base_area[k], t.base_area[k + 1]);
        let (m0, m1) = (self.d_area[k] * h, self.d_area[k + 1] * h);
        let sig = hermite(u, y0, m0, y1, m1);
        let (g0, g1) = (t.perimeter[k], t.perimeter[k + 1]);
        let (n0, n1) = (self.d_perimeter[k] * h, self.d_perimeter[k + 1] * h);
        let gam = hermite(u, g0, n0, g1, n1);
        let vol = self.omega[k] + hermite_integral(u, h, y0, m0, y1, m1);
        CapMeasures {
            volume: vol,
            base_area: sig[0],
            perimeter: gam[0],
            d_base_area: sig[1] / h,
            d_perimeter: gam[1] / h,
            d2_base_area: sig[2] / (h * h),
            d2_perimeter: gam[2] / (h * h),
        }
    }

    fn max_depth(&self) -> f64 {
        self.table.depth[self.table.depth.len() - 1]
    }

    /// The nodes, then the ends of the run-outs of `Σ` and `Γ`.
    fn breakpoints(&self) -> Vec<f64> {
        with_run_out_ends(
            self.table.depth.clone(),
            &self.area_tail,
            &self.perimeter_tail,
        )
    }
}
