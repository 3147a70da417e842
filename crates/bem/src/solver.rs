//! The constrained conjugate-gradient contact solver (Polonsky & Keer 1999).

use crate::influence::{Convolver, love_influence};
use tyreroad_core::{Par, is_parallel, run_at};

use crate::{BemError, Grid, HeightMap, Material};

/// Largest number of cells accepted along one axis (the non-periodic FFT
/// grid doubles it).
const MAX_CELLS_PER_AXIS: usize = 1 << 20;
/// Largest total number of cells accepted.
const MAX_CELLS: usize = 1 << 28;

/// What is imposed on the contact.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Control {
    /// Load control: the total normal force W (N, ≥ 0) is imposed; the
    /// approach is an output.
    Load(f64),
    /// Displacement control: the rigid approach δ (m) is imposed; the total
    /// force is an output.
    Approach(f64),
}

/// The loosest [`BemOptions::tolerance`]: the residual is the worst gap
/// error over the largest displacement, and at 1 or more the uniform
/// starting pressure already passes (a sphere "solved" in 0 iterations,
/// penetrating the tread).
pub const MAX_TOLERANCE: f64 = 0.1;

/// Options of the solver.
#[derive(Debug, Clone, PartialEq)]
pub struct BemOptions {
    /// Relative complementarity residual at which the iteration stops (see
    /// [`BemSolution::residual`]). Default `1e-8`, at most [`MAX_TOLERANCE`].
    pub tolerance: f64,
    /// Largest number of conjugate-gradient iterations. Default `5000`.
    pub max_iterations: usize,
    /// Periodic domain (the height map is one period in x and y) instead of
    /// the default isolated, non-periodic one. Default `false`.
    pub periodic: bool,
    /// Parallelism of the FFTs: [`Par::Seq`], or `Par::rayon(n)` for a rayon
    /// pool of `n` threads (the current pool when it has `n` threads).
    /// Default `Par::rayon(0)`: every thread of rayon's current pool.
    pub par: Par,
}

impl Default for BemOptions {
    fn default() -> Self {
        Self {
            tolerance: 1e-8,
            max_iterations: 5000,
            periodic: false,
            par: Par::rayon(0),
        }
    }
}

impl BemOptions {
    /// Checks the options.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] unless `tolerance` is in `(0,`
    /// [`MAX_TOLERANCE`]`]` and `max_iterations ≥ 1`.
    pub fn validate(&self) -> Result<(), BemError> {
        if !(self.tolerance > 0.0 && self.tolerance <= MAX_TOLERANCE) {
            return Err(BemError::invalid(format!(
                "tolerance must be in (0, {MAX_TOLERANCE}], got {:e}",
                self.tolerance
            )));
        }
        if self.max_iterations == 0 {
            return Err(BemError::invalid("max_iterations must be >= 1"));
        }
        Ok(())
    }
}

/// Result of a contact solve. All fields are row-major on [`BemSolution::grid`].
#[derive(Debug, Clone, PartialEq)]
pub struct BemSolution {
    /// The grid of the solved height map.
    pub grid: Grid,
    /// Contact pressure p ≥ 0 at each cell (Pa).
    pub pressure: Vec<f64>,
    /// Elastic surface displacement u = K p at each cell centre (m, positive
    /// into the elastic body, i.e. upward). Zero-mean in periodic mode.
    pub displacement: Vec<f64>,
    /// Gap g = (z_top − h) + u − δ at each cell centre (m); 0 in contact.
    pub gap: Vec<f64>,
    /// z_top = max h, the height of the undeformed elastic surface at zero
    /// approach (m). The undeformed surface lies at `z_top − approach`.
    pub reference_height: f64,
    /// Rigid approach δ (m): imposed under [`Control::Approach`], computed
    /// under [`Control::Load`].
    pub approach: f64,
    /// Total force Σ p · dx · dy (N).
    pub force: f64,
    /// Contact area: number of cells with p > 0 times dx · dy (m²).
    pub contact_area: f64,
    /// Number of cells with p > 0.
    pub contact_cells: usize,
    /// Conjugate-gradient iterations performed.
    pub iterations: usize,
    /// Final relative complementarity residual
    /// `max(max_{p>0} |g|, max_{p=0} max(−g, 0)) / max(max |u|, |δ|)`.
    pub residual: f64,
}

/// Contact statistics of one region of cells (see [`BemSolution::regions`]).
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct RegionContact {
    /// Force carried by the region Σ p · dx · dy (N).
    pub force: f64,
    /// Contact area of the region (cells with p > 0 times dx · dy, m²).
    pub contact_area: f64,
    /// Number of cells of the region in contact.
    pub contact_cells: usize,
    /// Radius of the disc of equal contact area √(A/π) (m).
    pub equivalent_radius: f64,
    /// Centroid of the contact area `[x, y]` (m); `[NaN, NaN]` without contact.
    pub centroid: [f64; 2],
    /// Semi-axes `[major, minor]` (m) of the ellipse with the same second
    /// moments of area as the contact area (each cell counted as a uniform
    /// rectangle): `2 √λ` for the eigenvalues λ of the area covariance. Equal
    /// to the radius for a disc.
    pub semi_axes: [f64; 2],
    /// Largest pressure in the region (Pa).
    pub max_pressure: f64,
}

impl BemSolution {
    /// Force Σ p · dx · dy carried by each region; `labels[k]` is the region
    /// of cell `k`, and the result has `max(labels) + 1` entries.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if `labels.len()` differs from the number of
    /// cells.
    pub fn force_per_region(&self, labels: &[usize]) -> Result<Vec<f64>, BemError> {
        Ok(self.regions(labels)?.iter().map(|r| r.force).collect())
    }

    /// Contact statistics (force, area, radii, centroid) of each region;
    /// `labels[k]` is the region of cell `k`, and the result has
    /// `max(labels) + 1` entries. [`crate::nearest_labels`] builds labels
    /// per asperity.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if `labels.len()` differs from the number of
    /// cells, or a label is not below `max(cells, 2^20)`.
    pub fn regions(&self, labels: &[usize]) -> Result<Vec<RegionContact>, BemError> {
        if labels.len() != self.pressure.len() {
            return Err(BemError::invalid(format!(
                "labels have {} entries, the grid has {} cells",
                labels.len(),
                self.pressure.len()
            )));
        }
        // One entry per label up to the largest: a label past every cell
        // (and past 2^20 regions) is an index gone wrong, whose table would
        // not fit in memory (and `usize::MAX + 1` wraps to 0).
        let most = self.pressure.len().max(1 << 20);
        let n = match labels.iter().max() {
            Some(&m) if m >= most => {
                return Err(BemError::invalid(format!(
                    "label {m} of a grid of {} cells: labels must be below {most}",
                    self.pressure.len()
                )));
            }
            Some(&m) => m + 1,
            None => 0,
        };
        // Sums: force, count, Σx, Σy, Σx², Σy², Σxy, max p.
        let mut acc = vec![[0.0f64; 8]; n];
        let g = &self.grid;
        for (k, (&p, &l)) in self.pressure.iter().zip(labels).enumerate() {
            if p > 0.0 {
                let (i, j) = g.cell(k);
                let (x, y) = (g.x(i), g.y(j));
                let a = &mut acc[l];
                a[0] += p;
                a[1] += 1.0;
                a[2] += x;
                a[3] += y;
                a[4] += x * x;
                a[5] += y * y;
                a[6] += x * y;
                a[7] = a[7].max(p);
            }
        }
        let cell = g.cell_area();
        Ok(acc
            .iter()
            .map(|a| {
                let c = a[1];
                if c == 0.0 {
                    return RegionContact {
                        centroid: [f64::NAN, f64::NAN],
                        ..RegionContact::default()
                    };
                }
                let (mx, my) = (a[2] / c, a[3] / c);
                let sxx = (a[4] / c - mx * mx).max(0.0) + g.dx() * g.dx() / 12.0;
                let syy = (a[5] / c - my * my).max(0.0) + g.dy() * g.dy() / 12.0;
                let sxy = a[6] / c - mx * my;
                let half_tr = 0.5 * (sxx + syy);
                let disc = (0.25 * (sxx - syy).powi(2) + sxy * sxy).sqrt();
                let l1 = half_tr + disc;
                let l2 = (half_tr - disc).max(0.0);
                let area = c * cell;
                RegionContact {
                    force: a[0] * cell,
                    contact_area: area,
                    contact_cells: c as usize,
                    equivalent_radius: (area / std::f64::consts::PI).sqrt(),
                    centroid: [mx, my],
                    semi_axes: [2.0 * l1.sqrt(), 2.0 * l2.sqrt()],
                    max_pressure: a[7],
                }
            })
            .collect())
    }

    /// Largest contact pressure (Pa).
    pub fn max_pressure(&self) -> f64 {
        self.pressure.iter().copied().fold(0.0, f64::max)
    }

    /// Radius of the disc of area equal to the whole contact area √(A/π) (m).
    pub fn equivalent_radius(&self) -> f64 {
        (self.contact_area / std::f64::consts::PI).sqrt()
    }
}

/// A reusable contact solver for one grid, material and set of options.
///
/// Construction computes the influence-coefficient spectrum (the costly,
/// reusable part) and allocates every work buffer; [`Solver::solve`] then
/// runs the constrained conjugate gradient without allocating (only the
/// returned [`BemSolution`] is allocated).
pub struct Solver {
    grid: Grid,
    material: Material,
    options: BemOptions,
    conv: Convolver,
    /// Centre value of the Love kernel (fallback step length).
    k00: f64,
    g0: Vec<f64>,
    p: Vec<f64>,
    u: Vec<f64>,
    g: Vec<f64>,
    t: Vec<f64>,
    r: Vec<f64>,
}

impl std::fmt::Debug for Solver {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("Solver")
            .field("grid", &self.grid)
            .field("material", &self.material)
            .field("options", &self.options)
            .finish_non_exhaustive()
    }
}

impl Solver {
    /// Precomputes the influence operator for `grid` and `material`.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if the options are invalid.
    pub fn new(grid: &Grid, material: &Material, options: &BemOptions) -> Result<Self, BemError> {
        options.validate()?;
        let (nx, ny) = (grid.nx(), grid.ny());
        if nx > MAX_CELLS_PER_AXIS || ny > MAX_CELLS_PER_AXIS || grid.len() > MAX_CELLS {
            return Err(BemError::invalid(format!(
                "grid too large: nx = {nx}, ny = {ny} (at most {MAX_CELLS_PER_AXIS} per axis and {MAX_CELLS} cells)"
            )));
        }
        let e_star = material.reduced_modulus();
        let parallel = is_parallel(options.par);
        let conv = run_at(options.par, || {
            Convolver::new(grid, e_star, options.periodic, parallel)
        })?;
        let n = grid.len();
        Ok(Self {
            grid: grid.clone(),
            material: *material,
            options: options.clone(),
            conv,
            k00: love_influence(0.0, 0.0, grid.dx(), grid.dy(), e_star),
            g0: vec![0.0; n],
            p: vec![0.0; n],
            u: vec![0.0; n],
            g: vec![0.0; n],
            t: vec![0.0; n],
            r: vec![0.0; n],
        })
    }

    /// The grid the solver was built for.
    pub fn grid(&self) -> &Grid {
        &self.grid
    }
    /// The material.
    pub fn material(&self) -> &Material {
        &self.material
    }
    /// The options.
    pub fn options(&self) -> &BemOptions {
        &self.options
    }

    /// Changes the tolerance and iteration limit (the influence operator
    /// does not depend on them).
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] as [`BemOptions::validate`].
    pub fn set_stopping(&mut self, tolerance: f64, max_iterations: usize) -> Result<(), BemError> {
        let o = BemOptions {
            tolerance,
            max_iterations,
            ..self.options.clone()
        };
        o.validate()?;
        self.options = o;
        Ok(())
    }

    /// Surface displacement `u = K p` (m) of a pressure field (Pa) on the grid.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] if `pressure` has the wrong length.
    pub fn displacement(&mut self, pressure: &[f64]) -> Result<Vec<f64>, BemError> {
        if pressure.len() != self.grid.len() {
            return Err(BemError::invalid(format!(
                "pressure has {} values, the grid has {} cells",
                pressure.len(),
                self.grid.len()
            )));
        }
        let mut u = vec![0.0; pressure.len()];
        let conv = &mut self.conv;
        run_at(self.options.par, || conv.apply(pressure, &mut u))?;
        Ok(u)
    }

    /// Solves the contact of the rigid surface `surface` (same grid sizes and
    /// spacings as the solver) under `control`.
    ///
    /// # Errors
    /// [`BemError::InvalidInput`] for a mismatched grid or an invalid control
    /// value; [`BemError::NotConverged`] if the tolerance is not reached within
    /// `max_iterations`.
    pub fn solve(
        &mut self,
        surface: &HeightMap,
        control: Control,
    ) -> Result<BemSolution, BemError> {
        self.run(surface, control, None)
    }

    /// As [`Solver::solve`], starting from the pressure field
    /// `initial_pressure` (a warm start, e.g. the solution at a nearby load).
    /// Under load control the guess is rescaled to the imposed load.
    ///
    /// # Errors
    /// As [`Solver::solve`], and [`BemError::InvalidInput`] if the guess has the
    /// wrong length or a negative or non-finite value.
    pub fn solve_from(
        &mut self,
        surface: &HeightMap,
        control: Control,
        initial_pressure: &[f64],
    ) -> Result<BemSolution, BemError> {
        if initial_pressure.len() != self.grid.len() {
            return Err(BemError::invalid(format!(
                "initial pressure has {} values, the grid has {} cells",
                initial_pressure.len(),
                self.grid.len()
            )));
        }
        if let Some(v) = initial_pressure
            .iter()
            .find(|v| !(v.is_finite() && **v >= 0.0))
        {
            return Err(BemError::invalid(format!(
                "initial pressure must be finite and >= 0, found {v}"
            )));
        }
        self.run(surface, control, Some(initial_pressure))
    }

    fn run(
        &mut self,
        surface: &HeightMap,
        control: Control,
        guess: Option<&[f64]>,
    ) -> Result<BemSolution, BemError> {
        if surface.valid_count() != surface.grid().len() {
            return Err(BemError::invalid(format!(
                "the height map has {} invalid cells: fill them first",
                surface.grid().len() - surface.valid_count()
            )));
        }
        run_at(self.options.par, || {
            self.run_at_par(surface, control, guess)
        })
        .and_then(|s| physical(s, control))
    }

    fn run_at_par(
        &mut self,
        surface: &HeightMap,
        control: Control,
        guess: Option<&[f64]>,
    ) -> Result<BemSolution, BemError> {
        let sg = surface.grid();
        if sg.nx() != self.grid.nx()
            || sg.ny() != self.grid.ny()
            || sg.dx() != self.grid.dx()
            || sg.dy() != self.grid.dy()
        {
            return Err(BemError::invalid(format!(
                "height map grid {}x{} (dx = {}, dy = {}) differs from the solver grid {}x{} (dx = {}, dy = {})",
                sg.nx(),
                sg.ny(),
                sg.dx(),
                sg.dy(),
                self.grid.nx(),
                self.grid.ny(),
                self.grid.dx(),
                self.grid.dy()
            )));
        }
        let n = self.grid.len();
        let cell = self.grid.cell_area();
        let z_top = surface.max();
        for (g0, h) in self.g0.iter_mut().zip(surface.values()) {
            *g0 = z_top - h;
        }
        let periodic = self.options.periodic;

        // Validate the control and handle the trivial no-contact cases.
        let load = match control {
            Control::Load(w) => {
                if !(w.is_finite() && w >= 0.0) {
                    return Err(BemError::invalid(format!(
                        "imposed load must be finite and >= 0, got {w}"
                    )));
                }
                if w == 0.0 {
                    return Ok(self.no_contact(sg, z_top, 0.0));
                }
                Some(w)
            }
            Control::Approach(d) => {
                if !d.is_finite() {
                    return Err(BemError::invalid(format!(
                        "imposed approach must be finite, got {d}"
                    )));
                }
                if d <= 0.0 {
                    return Ok(self.no_contact(sg, z_top, d));
                }
                if periodic {
                    let mean_gap = self.g0.iter().sum::<f64>() / n as f64;
                    if d >= mean_gap {
                        return Err(BemError::invalid(format!(
                            "periodic displacement control: approach {d:e} m closes the mean initial gap {mean_gap:e} m; no finite pressure satisfies it (use load control)"
                        )));
                    }
                }
                None
            }
        };
        let e_star = self.material.reduced_modulus();

        // Initial pressure.
        match (guess, load) {
            (Some(p0), _) => self.p.copy_from_slice(p0),
            (None, Some(w)) => self.p.fill(w / (n as f64 * cell)),
            (None, None) => self.p.fill(0.0),
        }
        if let Control::Approach(d) = control
            && self.p.iter().all(|&v| v == 0.0)
        {
            initial_from_interference(&mut self.p, &self.g0, d, e_star, cell);
        }
        if let Some(w) = load {
            let total: f64 = self.p.iter().sum::<f64>() * cell;
            if total > 0.0 {
                let s = w / total;
                self.p.iter_mut().for_each(|v| *v *= s);
            } else {
                self.p.fill(w / (n as f64 * cell));
            }
        }

        let tol = self.options.tolerance;
        let max_it = self.options.max_iterations;
        let mut g_old = 1.0;
        let mut conjugate = false;
        let mut iterations = 0;
        let mut approach;
        let mut residual;
        // `u` may be carried over from the previous iteration (see the end
        // of the loop) instead of recomputed; it is recomputed exactly at
        // least every EXACT_EVERY iterations and always before returning.
        let mut u_carried = false;
        let mut since_exact = 0usize;
        loop {
            let exact = !u_carried || since_exact >= EXACT_EVERY;
            if exact {
                self.conv.apply(&self.p, &mut self.u)?;
                since_exact = 0;
            } else {
                since_exact += 1;
            }
            // Gap before the approach shift, and contact-set statistics.
            let mut sum_c = 0.0;
            let mut n_c = 0usize;
            let mut u_max = 0.0f64;
            for i in 0..n {
                let gi = self.g0[i] + self.u[i];
                self.g[i] = gi;
                u_max = u_max.max(self.u[i].abs());
                if self.p[i] > 0.0 {
                    sum_c += gi;
                    n_c += 1;
                }
            }
            approach = match control {
                Control::Approach(d) => d,
                Control::Load(_) => {
                    if n_c > 0 {
                        sum_c / n_c as f64
                    } else {
                        0.0
                    }
                }
            };
            let mut big_g = 0.0;
            let mut worst = 0.0f64;
            for i in 0..n {
                let gi = self.g[i] - approach;
                self.g[i] = gi;
                if self.p[i] > 0.0 {
                    big_g += gi * gi;
                    worst = worst.max(gi.abs());
                } else {
                    worst = worst.max(-gi);
                }
            }
            let scale = u_max.max(approach.abs()).max(f64::MIN_POSITIVE);
            residual = worst / scale;
            if residual <= tol {
                if exact {
                    break;
                }
                // Confirm with the exact u = K p.
                u_carried = false;
                continue;
            }
            if iterations >= max_it {
                return Err(BemError::NotConverged {
                    iterations,
                    residual,
                    tolerance: tol,
                });
            }
            iterations += 1;

            if n_c == 0 {
                // Nothing in contact (only possible under displacement
                // control): restart from the interference.
                initial_from_interference(&mut self.p, &self.g, 0.0, e_star, cell);
                conjugate = false;
                g_old = 1.0;
                continue;
            }

            // Conjugate search direction on the contact set.
            let beta = if conjugate { big_g / g_old } else { 0.0 };
            for i in 0..n {
                self.t[i] = if self.p[i] > 0.0 {
                    self.g[i] + beta * self.t[i]
                } else {
                    0.0
                };
            }
            g_old = big_g;
            self.conv.apply(&self.t, &mut self.r)?;
            let rbar = if load.is_some() {
                let mut s = 0.0;
                for i in 0..n {
                    if self.p[i] > 0.0 {
                        s += self.r[i];
                    }
                }
                s / n_c as f64
            } else {
                0.0
            };
            let mut num = 0.0;
            let mut den = 0.0;
            for i in 0..n {
                if self.p[i] > 0.0 {
                    num += self.g[i] * self.t[i];
                    den += (self.r[i] - rbar) * self.t[i];
                }
            }
            let tau = if den > 0.0 && den.is_finite() {
                num / den
            } else {
                1.0 / self.k00
            };

            // Update, projection onto p ≥ 0, and the Polonsky–Keer
            // correction of inadmissible (penetrating, unloaded) points.
            let mut any_overlap = false;
            let mut any_clamped = false;
            for i in 0..n {
                let pi = self.p[i];
                if pi > 0.0 {
                    let v = pi - tau * self.t[i];
                    if v < 0.0 {
                        any_clamped = true;
                    }
                    self.p[i] = v.max(0.0);
                }
                if self.p[i] == 0.0 && pi == 0.0 && self.g[i] < 0.0 {
                    self.p[i] = -tau * self.g[i];
                    any_overlap = true;
                }
            }
            conjugate = !any_overlap;

            let mut rescale = 1.0;
            let mut linear = !(any_overlap || any_clamped);
            if let Some(w) = load {
                let total: f64 = self.p.iter().sum::<f64>() * cell;
                if total > 0.0 {
                    rescale = w / total;
                    self.p.iter_mut().for_each(|v| *v *= rescale);
                } else {
                    self.p.fill(w / (n as f64 * cell));
                    conjugate = false;
                    linear = false;
                }
            }
            // Without projection the update is linear, p ← s (p − τ t), and
            // so is u = K p: carry it over instead of another convolution.
            u_carried = linear;
            if linear {
                for (u, r) in self.u.iter_mut().zip(&self.r) {
                    *u = rescale * (*u - tau * r);
                }
            }
        }

        let force = self.p.iter().sum::<f64>() * cell;
        let contact_cells = self.p.iter().filter(|&&v| v > 0.0).count();
        Ok(BemSolution {
            grid: sg.clone(),
            pressure: self.p.clone(),
            displacement: self.u.clone(),
            gap: self.g.clone(),
            reference_height: z_top,
            approach,
            force,
            contact_area: contact_cells as f64 * cell,
            contact_cells,
            iterations,
            residual,
        })
    }

    fn no_contact(&self, grid: &Grid, z_top: f64, approach: f64) -> BemSolution {
        let n = self.grid.len();
        BemSolution {
            grid: grid.clone(),
            pressure: vec![0.0; n],
            displacement: vec![0.0; n],
            gap: self.g0.iter().map(|g| g - approach).collect(),
            reference_height: z_top,
            approach,
            force: 0.0,
            contact_area: 0.0,
            contact_cells: 0,
            iterations: 0,
            residual: 0.0,
        }
    }
}

/// Largest number of consecutive iterations that update `u = K p`
/// incrementally before it is recomputed by FFT (bounds rounding drift).
const EXACT_EVERY: usize = 8;

/// Initial guess under displacement control: a pressure proportional to the
/// rigid interference `max(δ − g0, 0)`, scaled as a punch of the same area
/// (p ≈ E* · interference / radius).
fn initial_from_interference(p: &mut [f64], g0: &[f64], d: f64, e_star: f64, cell: f64) {
    let n_pen = g0.iter().filter(|&&g| g < d).count().max(1);
    let radius = (n_pen as f64 * cell / std::f64::consts::PI).sqrt();
    let c = e_star / radius;
    for (pi, g) in p.iter_mut().zip(g0) {
        *pi = c * (d - g).max(0.0);
    }
}

/// `s`, or [`BemError::NotPhysical`] naming what no contact has: a value
/// that is not finite, a negative pressure, or (load control) a force
/// that is not the load to 1e-6 of it. The solver's own projection keeps
/// every pressure ≥ 0 and its load step rescales them to the load, so only
/// arithmetic past floating point's range gets here.
fn physical(s: BemSolution, control: Control) -> Result<BemSolution, BemError> {
    let what = if !s.force.is_finite() || !s.approach.is_finite() {
        Some(format!(
            "force {:e} N, approach {:e} m",
            s.force, s.approach
        ))
    } else if let Some((c, p)) = s
        .pressure
        .iter()
        .enumerate()
        .find(|(_, p)| !(p.is_finite() && **p >= 0.0))
    {
        Some(format!("pressure {p:e} Pa at cell {c}"))
    } else if let Control::Load(w) = control
        && (s.force - w).abs() > 1e-6 * w
    {
        Some(format!(
            "force {:e} N under an imposed load of {w:e} N",
            s.force
        ))
    } else {
        None
    };
    match what {
        Some(what) => Err(BemError::NotPhysical(what)),
        None => Ok(s),
    }
}

/// One-call convenience: builds a [`Solver`] and solves once.
///
/// Build a [`Solver`] instead to solve several loads or surfaces on the same
/// grid without recomputing the influence operator.
///
/// # Errors
/// As [`Solver::new`] and [`Solver::solve`].
pub fn solve(
    surface: &HeightMap,
    material: &Material,
    control: Control,
    options: &BemOptions,
) -> Result<BemSolution, BemError> {
    Solver::new(surface.grid(), material, options)?.solve(surface, control)
}
