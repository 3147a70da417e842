//! The window of a cap patch that one calibration depth solves on.
//!
//! At approach `a` below the patch's top, a cell of height `h` (from the
//! summit) is in contact only where its gap closes: `g = g0 + u − a = 0`
//! with `g0 = −offset − h` and `u ≥ 0` (the half-space only rises under a
//! pressure), so only cells with `h ≥ −(offset + a)` can carry pressure.
//! The others keep `p = 0` and `g > 0` whatever the solve does: dropping
//! them changes no pressure, force or contact area, only the FFT's size.
//! Each depth is therefore solved on the bounding box of its reachable
//! cells (small at the first, shallow depths), grown to the largest box
//! with the same FFT grid ([`tyreroad_bem::cells_at_same_fft_cost`]) so
//! that the following depths reuse its [`Solver`] until they outgrow it.

use tyreroad_bem::{
    BemOptions, Control, Grid, HeightMap, Material, Solver, cells_at_same_fft_cost,
};

use super::{CapPatch, FidelityError, WarmStart};

/// A rectangle of patch cells: `nx × ny` from cell `(i0, j0)`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct Window {
    i0: usize,
    j0: usize,
    nx: usize,
    ny: usize,
}

impl Window {
    /// The bounding box of the cells of `patch` within `depth` of the
    /// summit; `None` if there is none (not for a validated patch and a
    /// depth past its summit offset).
    fn reachable(patch: &CapPatch, depth: f64) -> Option<Self> {
        // Rounding of the caller's `offset + approach` must not drop the
        // top cell at the first depth.
        let floor = -depth * (1.0 + 1e-12);
        let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
        for (c, &h) in patch.heights.iter().enumerate() {
            if h >= floor {
                let (i, j) = (c % patch.nx, c / patch.nx);
                (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
            }
        }
        (i0 != usize::MAX).then(|| Self {
            i0,
            j0,
            nx: i1 - i0 + 1,
            ny: j1 - j0 + 1,
        })
    }

    fn contains(&self, other: &Self) -> bool {
        other.i0 >= self.i0
            && other.j0 >= self.j0
            && other.i0 + other.nx <= self.i0 + self.nx
            && other.j0 + other.ny <= self.j0 + self.ny
    }

    /// Grown about its centre, within the patch, to the largest size
    /// solved at the same FFT cost.
    fn grown(self, patch: &CapPatch) -> Self {
        let axis = |start: usize, n: usize, total: usize| {
            let m = cells_at_same_fft_cost(n).min(total);
            let extra = m - n;
            let start = start.saturating_sub(extra / 2).min(total - m);
            (start, m)
        };
        let (i0, nx) = axis(self.i0, self.nx, patch.nx);
        let (j0, ny) = axis(self.j0, self.ny, patch.ny);
        Self { i0, j0, nx, ny }
    }
}

/// The first pressure (whole patch) of the solve at `depth` (m from the
/// summit) from the last (at most two) depths' `(depth, pressure)`.
pub(super) fn warm_start(
    rule: WarmStart,
    previous: &[(f64, Vec<f64>)],
    depth: f64,
    patch: &CapPatch,
) -> Option<Vec<f64>> {
    let (d1, p1) = previous.last()?;
    match (rule, previous) {
        (WarmStart::Extrapolated, [(d0, p0), _]) if d1 > d0 => {
            let r = (depth - d1) / (d1 - d0);
            Some(
                p1.iter()
                    .zip(p0)
                    .map(|(a, b)| (a + r * (a - b)).max(0.0))
                    .collect(),
            )
        }
        (WarmStart::Dilated, _) if *d1 > 0.0 => Some(dilated(p1, (depth / d1).sqrt(), patch)),
        _ => Some(p1.clone()),
    }
}

/// `p` dilated by `s` about its centroid, bilinearly resampled, scaled by
/// `s` (Hertz: `a` and `p0` both grow as `√δ`).
fn dilated(p: &[f64], s: f64, patch: &CapPatch) -> Vec<f64> {
    let nx = patch.nx;
    let total: f64 = p.iter().sum();
    if !(total > 0.0) {
        return p.to_vec();
    }
    let (mut ci, mut cj) = (0.0, 0.0);
    for (c, &v) in p.iter().enumerate() {
        ci += v * (c % nx) as f64;
        cj += v * (c / nx) as f64;
    }
    let (ci, cj) = (ci / total, cj / total);
    let at = |i: isize, j: isize| -> f64 {
        if i < 0 || j < 0 || i as usize >= nx || j as usize >= patch.ny {
            0.0
        } else {
            p[j as usize * nx + i as usize]
        }
    };
    (0..p.len())
        .map(|c| {
            let x = ci + ((c % nx) as f64 - ci) / s;
            let y = cj + ((c / nx) as f64 - cj) / s;
            let (i, j) = (x.floor(), y.floor());
            let (tx, ty) = (x - i, y - j);
            let (i, j) = (i as isize, j as isize);
            let v = (1.0 - tx) * (1.0 - ty) * at(i, j)
                + tx * (1.0 - ty) * at(i + 1, j)
                + (1.0 - tx) * ty * at(i, j + 1)
                + tx * ty * at(i + 1, j + 1);
            s * v
        })
        .collect()
}

/// One depth's solution on the whole patch.
pub(super) struct KnotSolution {
    /// Force (N).
    pub force: f64,
    /// Contact area (m²).
    pub contact_area: f64,
    /// CG iterations.
    pub iterations: usize,
    /// Pressure on every patch cell (Pa), row-major, 0 outside the window.
    pub pressure: Vec<f64>,
    /// The window's cells `[nx, ny]`.
    pub window: [usize; 2],
}

/// Solves a patch depth by depth, each on its window.
pub(super) struct KnotSolver<'a> {
    patch: &'a CapPatch,
    material: &'a Material,
    options: BemOptions,
    current: Option<(Window, Solver, HeightMap)>,
    /// Solvers built so far (one per window growth).
    pub builds: usize,
}

impl<'a> KnotSolver<'a> {
    pub(super) fn new(patch: &'a CapPatch, material: &'a Material, options: BemOptions) -> Self {
        Self {
            patch,
            material,
            options,
            current: None,
            builds: 0,
        }
    }

    fn build(&mut self, w: Window) -> Result<(Window, Solver, HeightMap), FidelityError> {
        let patch = self.patch;
        let grid = Grid::new(w.nx, w.ny, patch.dx, patch.dy)
            .map_err(|e| FidelityError::invalid("cap patch grid", e, "a valid grid"))?;
        let heights = (0..w.ny)
            .flat_map(|j| {
                let row = (w.j0 + j) * patch.nx + w.i0;
                patch.heights[row..row + w.nx].iter().copied()
            })
            .collect();
        let surface = HeightMap::new(grid.clone(), heights)
            .map_err(|e| FidelityError::invalid("cap patch heights", e, "a valid field"))?;
        let solver = Solver::new(&grid, self.material, &self.options).map_err(|source| {
            FidelityError::Bem {
                context: "BEM set-up",
                source,
            }
        })?;
        self.builds += 1;
        Ok((w, solver, surface))
    }

    /// The solve at `approach` below the patch's top (`offset` below the
    /// summit), warm-started from `guess` (whole-patch pressure) if given.
    pub(super) fn solve(
        &mut self,
        offset: f64,
        approach: f64,
        guess: Option<&[f64]>,
    ) -> Result<KnotSolution, FidelityError> {
        let patch = self.patch;
        let need = Window::reachable(patch, offset + approach).ok_or_else(|| {
            FidelityError::invalid(
                "calibration depth",
                offset + approach,
                "a depth that reaches the patch's highest cell",
            )
        })?;
        let current = match self.current.take() {
            Some(c) if c.0.contains(&need) => c,
            _ => self.build(need.grown(patch))?,
        };
        let (w, solver, surface) = self.current.insert(current);
        let w = *w;
        let control = Control::Approach(approach);
        let sol = match guess {
            Some(full) => {
                let part: Vec<f64> = (0..w.ny)
                    .flat_map(|j| {
                        let row = (w.j0 + j) * patch.nx + w.i0;
                        full[row..row + w.nx].iter().copied()
                    })
                    .collect();
                solver.solve_from(surface, control, &part)
            }
            None => solver.solve(surface, control),
        }
        .map_err(|source| FidelityError::Bem {
            context: "BEM calibration solve",
            source,
        })?;
        let mut pressure = vec![0.0; patch.nx * patch.ny];
        for j in 0..w.ny {
            let row = (w.j0 + j) * patch.nx + w.i0;
            pressure[row..row + w.nx].copy_from_slice(&sol.pressure[j * w.nx..(j + 1) * w.nx]);
        }
        Ok(KnotSolution {
            force: sol.force,
            contact_area: sol.contact_area,
            iterations: sol.iterations,
            pressure,
            window: [w.nx, w.ny],
        })
    }
}

#[cfg(test)]
mod tests {
    #![allow(clippy::unwrap_used)]

    use super::*;
    use tyreroad_bem::Par;

    /// Two bumps on a wide floor: a paraboloid and, off-centre, a lower
    /// cone, so the reachable box grows unevenly and jumps when the cone's
    /// tip comes within reach.
    fn two_bumps() -> CapPatch {
        CapPatch::from_fn(71, 5e-5, |x, y| {
            let bowl = -(x * x + y * y) / (2.0 * 4e-3);
            let cone = -40e-6 - ((x - 1.1e-3).powi(2) + (y + 0.4e-3).powi(2)).sqrt() * 0.15;
            bowl.max(cone).max(-0.5e-3)
        })
        .unwrap()
    }

    /// The windowed solves against the BEM on the whole patch, depth by
    /// depth, both warm-started the same way: the same contact (cell for
    /// cell) and the same force to the solver's tolerance.
    #[test]
    fn windows_change_no_solution() {
        let m = Material::new(6.54e6, 0.5).unwrap();
        let patch = two_bumps();
        let options = BemOptions {
            tolerance: 1e-10,
            par: Par::Seq,
            ..BemOptions::default()
        };
        let grid = Grid::new(patch.nx, patch.ny, patch.dx, patch.dy).unwrap();
        let surface = HeightMap::new(grid.clone(), patch.heights.clone()).unwrap();
        let mut whole = Solver::new(&grid, &m, &options).unwrap();
        let mut windowed = KnotSolver::new(&patch, &m, options.clone());
        let offset = patch.summit_offset();
        let (mut prev_w, mut prev_f): (Option<Vec<f64>>, Option<Vec<f64>>) = (None, None);
        let mut sizes = Vec::new();
        for k in 1..=8 {
            let a = 0.12e-3 * (k as f64 / 8.0).powi(2);
            let w = windowed.solve(offset, a, prev_w.as_deref()).unwrap();
            let f = match &prev_f {
                Some(p) => whole.solve_from(&surface, Control::Approach(a), p),
                None => whole.solve(&surface, Control::Approach(a)),
            }
            .unwrap();
            assert!(
                (w.force - f.force).abs() <= 1e-8 * f.force,
                "δ = {a}: {} vs {}",
                w.force,
                f.force
            );
            let contact = |p: &[f64]| p.iter().map(|&v| v > 0.0).collect::<Vec<_>>();
            assert_eq!(contact(&w.pressure), contact(&f.pressure), "δ = {a}");
            assert_eq!(w.contact_area, f.contact_area);
            sizes.push(w.window[0] * w.window[1]);
            prev_w = Some(w.pressure);
            prev_f = Some(f.pressure);
        }
        // The windows grew, from well below the patch.
        assert!(sizes[0] * 4 < patch.nx * patch.ny, "{sizes:?}");
        assert!(sizes.windows(2).all(|s| s[0] <= s[1]), "{sizes:?}");
        assert!(windowed.builds <= 8);
    }

    #[test]
    fn a_window_is_grown_within_the_patch_to_its_fft_size() {
        let patch = two_bumps();
        let need = Window::reachable(&patch, 1e-6).unwrap();
        assert!(need.nx <= 3 && need.ny <= 3, "{need:?}");
        let grown = need.grown(&patch);
        assert!(grown.contains(&need));
        assert_eq!(grown.nx, cells_at_same_fft_cost(need.nx));
        let all = Window::reachable(&patch, 1.0).unwrap();
        assert_eq!((all.nx, all.ny), (patch.nx, patch.ny));
        assert_eq!(all.grown(&patch), all);
    }
}
