//! Influence coefficients (Love 1929) and their FFT convolution.

use std::f64::consts::PI;
use std::sync::Arc;

use rayon::prelude::*;
use realfft::num_complex::Complex;
use realfft::{ComplexToReal, RealFftPlanner, RealToComplex};
use rustfft::{Fft, FftPlanner};

use crate::{BemError, Grid};

/// Surface displacement (m, positive into the half-space) at `(x, y)` due to
/// a unit uniform pressure (1 Pa) on the rectangle `|x'| ≤ dx/2, |y'| ≤ dy/2`
/// of an elastic half-space of plane-strain modulus `e_star` (Love 1929).
///
/// `u(x, y) = 1/(π E*) · [F(x+a, y+b) − F(x+a, y−b) − F(x−a, y+b) + F(x−a, y−b)]`
/// with `a = dx/2`, `b = dy/2` and `F(ξ, η) = ξ·asinh(η/|ξ|) + η·asinh(ξ/|η|)`
/// (`F = 0` terms for a zero argument), the antiderivative of `1/r` written
/// without cancellation. At the centre of a square cell of side `s` it is
/// `4 ln(1 + √2) · s / (π E*) ≈ 1.1222 s / E*`; far away it tends to the
/// Boussinesq point load `dx·dy / (π E* r)`.
pub fn love_influence(x: f64, y: f64, dx: f64, dy: f64, e_star: f64) -> f64 {
    let a = 0.5 * dx;
    let b = 0.5 * dy;
    let s = f(x + a, y + b) - f(x + a, y - b) - f(x - a, y + b) + f(x - a, y - b);
    s / (PI * e_star)
}

/// The quadrant table `K(di, dj) = love_influence(di·dx, dj·dy, …)` for
/// `0 ≤ di < nx`, `0 ≤ dj < ny` (row-major), the kernel being even in both
/// offsets.
///
/// Neighbouring cells share the corners at which [`love_influence`]
/// evaluates its antiderivative `F`, so `F` is tabulated once at the
/// `(nx + 1) × (ny + 1)` corners `((k − ½)·dx, (l − ½)·dy)` and each
/// coefficient is the same four-corner difference: a quarter of the
/// `asinh` calls (the set-up cost of every small calibration solver).
/// `F` is odd in each argument, which gives the corners at `−dx/2`.
fn love_quadrant(nx: usize, ny: usize, dx: f64, dy: f64, e_star: f64, parallel: bool) -> Vec<f64> {
    let (a, b) = (0.5 * dx, 0.5 * dy);
    let corner = |k: usize, half: f64, step: f64| {
        if k == 0 {
            -half
        } else {
            (k - 1) as f64 * step + half
        }
    };
    let (cx, cy) = (nx + 1, ny + 1);
    let mut corners = vec![0.0; cx * cy];
    let fill_corners = |(l, row): (usize, &mut [f64])| {
        let eta = corner(l, b, dy);
        for (k, v) in row.iter_mut().enumerate() {
            *v = f(corner(k, a, dx), eta);
        }
    };
    if parallel {
        corners
            .par_chunks_mut(cx)
            .enumerate()
            .for_each(fill_corners);
    } else {
        corners.chunks_mut(cx).enumerate().for_each(fill_corners);
    }
    let scale = 1.0 / (PI * e_star);
    let mut quad = vec![0.0; nx * ny];
    for (dj, row) in quad.chunks_mut(nx).enumerate() {
        let (lo, hi) = (
            &corners[dj * cx..(dj + 1) * cx],
            &corners[(dj + 1) * cx..(dj + 2) * cx],
        );
        for (di, v) in row.iter_mut().enumerate() {
            *v = (hi[di + 1] - lo[di + 1] - hi[di] + lo[di]) * scale;
        }
    }
    quad
}

#[inline]
fn f(xi: f64, eta: f64) -> f64 {
    let t1 = if xi == 0.0 {
        0.0
    } else {
        xi * (eta / xi.abs()).asinh()
    };
    let t2 = if eta == 0.0 {
        0.0
    } else {
        eta * (xi / eta.abs()).asinh()
    };
    t1 + t2
}

/// Number of alias images `|m|, |n| ≤ PERIODIC_ALIASES` summed in the
/// periodic kernel.
pub(crate) const PERIODIC_ALIASES: i64 = 32;

/// Number of work chunks the rows and columns are split into (each with its
/// own preallocated FFT scratch).
const CHUNKS_PARALLEL: usize = 16;

/// A chunk of rows in the forward pass: (chunk index, ((real rows, spectra), scratch)).
type ForwardRows<'a> = (
    usize,
    (
        (&'a mut [f64], &'a mut [Complex<f64>]),
        &'a mut Vec<Complex<f64>>,
    ),
);
/// A chunk of columns: (chunk index, (columns, scratch)).
type Columns<'a> = (usize, (&'a mut [Complex<f64>], &'a mut Vec<Complex<f64>>));
/// A chunk of rows in the inverse pass: (chunk index, (((spectra, real rows), scratch), output)).
type InverseRows<'a> = (
    usize,
    (
        (
            (&'a mut [Complex<f64>], &'a mut [f64]),
            &'a mut Vec<Complex<f64>>,
        ),
        &'a mut [f64],
    ),
);

/// The influence operator `u = K p` on a grid, applied by FFT.
///
/// Non-periodic: the Love coefficients for all offsets are laid out on an
/// `mx × my` grid (`mx ≥ 2nx − 1`, wrap-around order) and the pressure is zero
/// padded to it,
/// so the circular convolution equals the linear one on the `nx × ny` block.
/// Periodic: the `nx × ny` grid is used directly with the spectrum of the
/// periodised Love kernel (see the crate documentation).
pub(crate) struct Convolver {
    nx: usize,
    ny: usize,
    /// FFT grid along x (≥ 2nx − 1, or nx when periodic).
    mx: usize,
    /// FFT grid along y (≥ 2ny − 1, or ny when periodic).
    my: usize,
    /// Number of complex columns `mx/2 + 1`.
    h: usize,
    r2c: Arc<dyn RealToComplex<f64>>,
    c2r: Arc<dyn ComplexToReal<f64>>,
    col_fwd: Arc<dyn Fft<f64>>,
    col_inv: Arc<dyn Fft<f64>>,
    /// Real kernel spectrum, column-major `c·my + j`, already divided by `mx·my`.
    khat: Vec<f64>,
    /// `ny` rows of `mx` reals.
    rows_real: Vec<f64>,
    /// `ny` rows of `h` complex values.
    rows_spec: Vec<Complex<f64>>,
    /// `h` columns of `my` complex values.
    spec: Vec<Complex<f64>>,
    rows_per_chunk: usize,
    cols_per_chunk: usize,
    row_scratch: Vec<Vec<Complex<f64>>>,
    col_scratch: Vec<Vec<Complex<f64>>>,
    parallel: bool,
}

impl Convolver {
    pub(crate) fn new(
        grid: &Grid,
        e_star: f64,
        periodic: bool,
        parallel: bool,
    ) -> Result<Self, BemError> {
        let (nx, ny) = (grid.nx(), grid.ny());
        let (mx, my) = if periodic {
            (nx, ny)
        } else {
            (padded_len(nx), padded_len(ny))
        };
        let h = mx / 2 + 1;
        let mut rplanner = RealFftPlanner::<f64>::new();
        let r2c = rplanner.plan_fft_forward(mx);
        let c2r = rplanner.plan_fft_inverse(mx);
        let mut planner = FftPlanner::<f64>::new();
        let col_fwd = planner.plan_fft_forward(my);
        let col_inv = planner.plan_fft_inverse(my);
        let chunks = if parallel { CHUNKS_PARALLEL } else { 1 };
        let rows_per_chunk = ny.div_ceil(chunks).max(1);
        let cols_per_chunk = h.div_ceil(chunks).max(1);
        let row_scratch_len = r2c.get_scratch_len().max(c2r.get_scratch_len());
        let col_scratch_len = col_fwd
            .get_inplace_scratch_len()
            .max(col_inv.get_inplace_scratch_len());
        let n_row_chunks = ny.div_ceil(rows_per_chunk);
        let n_col_chunks = h.div_ceil(cols_per_chunk);
        let zero = Complex::new(0.0, 0.0);
        let mut conv = Self {
            nx,
            ny,
            mx,
            my,
            h,
            r2c,
            c2r,
            col_fwd,
            col_inv,
            khat: Vec::new(),
            rows_real: vec![0.0; ny * mx],
            rows_spec: vec![zero; ny * h],
            spec: vec![zero; h * my],
            rows_per_chunk,
            cols_per_chunk,
            row_scratch: vec![vec![zero; row_scratch_len]; n_row_chunks],
            col_scratch: vec![vec![zero; col_scratch_len]; n_col_chunks],
            parallel,
        };
        let mut khat = if periodic {
            periodic_spectrum(grid, e_star, h, my, PERIODIC_ALIASES, parallel)
        } else {
            conv.padded_love_spectrum(grid, e_star)?
        };
        let scale = 1.0 / (mx as f64 * my as f64);
        khat.iter_mut().for_each(|k| *k *= scale);
        conv.khat = khat;
        Ok(conv)
    }

    /// Spectrum of the Love kernel laid out on the `mx × my` grid in
    /// wrap-around order (padding slots are zero).
    fn padded_love_spectrum(&mut self, grid: &Grid, e_star: f64) -> Result<Vec<f64>, BemError> {
        let (nx, ny, mx, my, h) = (self.nx, self.ny, self.mx, self.my, self.h);
        let (dx, dy) = (grid.dx(), grid.dy());
        let quad = love_quadrant(nx, ny, dx, dy, e_star, self.parallel);
        // Slot k of the FFT grid holds offset k (k < n) or −(m − k)
        // (k > m − n); the slots in between are padding.
        let offset = |k: usize, n: usize, m: usize| -> Option<usize> {
            if k < n {
                Some(k)
            } else if k > m - n {
                Some(m - k)
            } else {
                None
            }
        };
        // Row FFTs of all my rows of the padded kernel.
        let mut full = vec![Complex::new(0.0, 0.0); my * h];
        let mut row = vec![0.0; mx];
        let mut scratch = self.r2c.make_scratch_vec();
        for j in 0..my {
            match offset(j, ny, my) {
                None => row.fill(0.0),
                Some(dj) => {
                    for (i, v) in row.iter_mut().enumerate() {
                        *v = offset(i, nx, mx).map_or(0.0, |di| quad[dj * nx + di]);
                    }
                }
            }
            self.r2c
                .process_with_scratch(&mut row, &mut full[j * h..(j + 1) * h], &mut scratch)?;
        }
        // Column FFTs (transpose to column-major first).
        let mut cols = vec![Complex::new(0.0, 0.0); h * my];
        for j in 0..my {
            for c in 0..h {
                cols[c * my + j] = full[j * h + c];
            }
        }
        let mut cscratch = vec![Complex::new(0.0, 0.0); self.col_fwd.get_inplace_scratch_len()];
        self.col_fwd.process_with_scratch(&mut cols, &mut cscratch);
        // The kernel is real and even: its spectrum is real.
        Ok(cols.iter().map(|z| z.re).collect())
    }

    /// Number of cells of the physical grid.
    pub(crate) fn len(&self) -> usize {
        self.nx * self.ny
    }

    /// `output = K input` (both row-major `nx × ny`).
    pub(crate) fn apply(&mut self, input: &[f64], output: &mut [f64]) -> Result<(), BemError> {
        debug_assert_eq!(input.len(), self.len());
        debug_assert_eq!(output.len(), self.len());
        let (nx, mx, my, h) = (self.nx, self.mx, self.my, self.h);
        let rpc = self.rows_per_chunk;
        let cpc = self.cols_per_chunk;
        let parallel = self.parallel;

        // 1. Row r2c transforms of the zero-padded rows.
        {
            let r2c = &self.r2c;
            let job = |(ci, ((rr, rs), scr)): ForwardRows<'_>| -> Result<(), BemError> {
                for (k, (row, out)) in rr.chunks_mut(mx).zip(rs.chunks_mut(h)).enumerate() {
                    let j = ci * rpc + k;
                    row[..nx].copy_from_slice(&input[j * nx..(j + 1) * nx]);
                    row[nx..].fill(0.0);
                    r2c.process_with_scratch(row, out, scr)?;
                }
                Ok(())
            };
            if parallel {
                self.rows_real
                    .par_chunks_mut(rpc * mx)
                    .zip(self.rows_spec.par_chunks_mut(rpc * h))
                    .zip(self.row_scratch.par_iter_mut())
                    .enumerate()
                    .try_for_each(job)?;
            } else {
                self.rows_real
                    .chunks_mut(rpc * mx)
                    .zip(self.rows_spec.chunks_mut(rpc * h))
                    .zip(self.row_scratch.iter_mut())
                    .enumerate()
                    .try_for_each(job)?;
            }
        }

        // 2. Transpose to columns (zero padded), column FFT, multiply by the
        //    kernel spectrum, inverse column FFT.
        {
            let ny = self.ny;
            let rows_spec = &self.rows_spec;
            let khat = &self.khat;
            let (fwd, inv) = (&self.col_fwd, &self.col_inv);
            let job = |(ci, (cols, scr)): Columns<'_>| {
                let c0 = ci * cpc;
                let ncols = cols.len() / my;
                const B: usize = 16;
                let mut cb = 0;
                while cb < ncols {
                    let ce = (cb + B).min(ncols);
                    for j in 0..ny {
                        let src = &rows_spec[j * h + c0..j * h + c0 + ncols];
                        for c in cb..ce {
                            cols[c * my + j] = src[c];
                        }
                    }
                    cb = ce;
                }
                for col in cols.chunks_mut(my) {
                    col[ny..].fill(Complex::new(0.0, 0.0));
                }
                fwd.process_with_scratch(cols, scr);
                for (z, k) in cols.iter_mut().zip(&khat[c0 * my..(c0 + ncols) * my]) {
                    *z *= *k;
                }
                inv.process_with_scratch(cols, scr);
            };
            if parallel {
                self.spec
                    .par_chunks_mut(cpc * my)
                    .zip(self.col_scratch.par_iter_mut())
                    .enumerate()
                    .for_each(job);
            } else {
                self.spec
                    .chunks_mut(cpc * my)
                    .zip(self.col_scratch.iter_mut())
                    .enumerate()
                    .for_each(job);
            }
        }

        // 3. Transpose the first ny entries of each column back to rows,
        //    inverse row transforms, keep the first nx values.
        {
            let spec = &self.spec;
            let c2r = &self.c2r;
            let even = mx % 2 == 0;
            let job = |(ci, (((rs, rr), scr), out)): InverseRows<'_>| -> Result<(), BemError> {
                let j0 = ci * rpc;
                let nrows = rs.len() / h;
                for c in 0..h {
                    let col = &spec[c * my + j0..c * my + j0 + nrows];
                    for (k, z) in col.iter().enumerate() {
                        rs[k * h + c] = *z;
                    }
                }
                for ((srow, rrow), orow) in rs
                    .chunks_mut(h)
                    .zip(rr.chunks_mut(mx))
                    .zip(out.chunks_mut(nx))
                {
                    // The result is real: the imaginary parts of the zero and
                    // Nyquist frequencies are rounding noise.
                    srow[0].im = 0.0;
                    if even {
                        srow[h - 1].im = 0.0;
                    }
                    c2r.process_with_scratch(srow, rrow, scr)?;
                    orow.copy_from_slice(&rrow[..nx]);
                }
                Ok(())
            };
            if parallel {
                self.rows_spec
                    .par_chunks_mut(rpc * h)
                    .zip(self.rows_real.par_chunks_mut(rpc * mx))
                    .zip(self.row_scratch.par_iter_mut())
                    .zip(output.par_chunks_mut(rpc * nx))
                    .enumerate()
                    .try_for_each(job)?;
            } else {
                self.rows_spec
                    .chunks_mut(rpc * h)
                    .zip(self.rows_real.chunks_mut(rpc * mx))
                    .zip(self.row_scratch.iter_mut())
                    .zip(output.chunks_mut(rpc * nx))
                    .enumerate()
                    .try_for_each(job)?;
            }
        }
        Ok(())
    }
}

/// The largest number of cells along a non-periodic axis whose FFT grid is
/// the one of `n` cells (`padded_len(n) / 2`, `≥ n`): a grid grown to it
/// costs the same per product `K p`, so a caller solving a growing window
/// can grow it that far without building another [`crate::Solver`].
pub fn cells_at_same_fft_cost(n: usize) -> usize {
    (padded_len(n) / 2).max(n)
}

/// FFT length for a linear convolution of `n` cells: the smallest even
/// 7-smooth number (2^a 3^b 5^c 7^d) ≥ 2n − 1, on which the FFTs are fast.
pub(crate) fn padded_len(n: usize) -> usize {
    let min = (2 * n).saturating_sub(1).max(2);
    let mut m = min + (min % 2);
    loop {
        let mut r = m;
        for f in [2, 3, 5, 7] {
            while r.is_multiple_of(f) {
                r /= f;
            }
        }
        if r == 1 {
            return m;
        }
        m += 2;
    }
}

/// Spectrum of the periodised Love kernel on an `nx × ny` periodic grid,
/// column-major (`c·my + j`, `c ≤ nx/2`), not yet divided by `nx·ny`:
///
/// `K̂(q) = Σ_G 2 S(kx·dx/2) S(ky·dy/2) / (E* |k|)`, `k = q + G`,
/// `G = (2πm/dx, 2πn/dy)`, `S(t) = sin t / t`, with `K̂(0) = 0`.
fn periodic_spectrum(
    grid: &Grid,
    e_star: f64,
    h: usize,
    my: usize,
    aliases: i64,
    parallel: bool,
) -> Vec<f64> {
    let (nx, ny) = (grid.nx(), grid.ny());
    let (dx, dy) = (grid.dx(), grid.dy());
    let lx = nx as f64 * dx;
    let ly = ny as f64 * dy;
    let m = aliases;
    let nal = (2 * m + 1) as usize;
    let sinc = |t: f64| if t == 0.0 { 1.0 } else { t.sin() / t };
    // Separable tables: k and sinc factor for each (frequency, alias).
    let table = |n_freq: usize, n: usize, d: f64, l: f64| -> (Vec<f64>, Vec<f64>) {
        let mut k = vec![0.0; n_freq * nal];
        let mut s = vec![0.0; n_freq * nal];
        for fi in 0..n_freq {
            let f = if fi <= n / 2 {
                fi as f64
            } else {
                fi as f64 - n as f64
            };
            let q = 2.0 * PI * f / l;
            for (a, mm) in (-m..=m).enumerate() {
                let kk = q + 2.0 * PI * mm as f64 / d;
                // Half weight on the last alias: the average of the partial
                // sums up to M − 1 and M of the alternating series.
                let w = if mm.abs() == m { 0.5 } else { 1.0 };
                k[fi * nal + a] = kk;
                s[fi * nal + a] = w * sinc(0.5 * kk * d);
            }
        }
        (k, s)
    };
    let (kx, sx) = table(h, nx, dx, lx);
    let (ky, sy) = table(my, ny, dy, ly);
    let mut out = vec![0.0; h * my];
    let job = |(c, col): (usize, &mut [f64])| {
        for (j, v) in col.iter_mut().enumerate() {
            if c == 0 && j == 0 {
                *v = 0.0;
                continue;
            }
            let mut sum = 0.0;
            for a in 0..nal {
                let kxa = kx[c * nal + a];
                let sxa = sx[c * nal + a];
                if sxa == 0.0 {
                    continue;
                }
                let kx2 = kxa * kxa;
                let mut inner = 0.0;
                for b in 0..nal {
                    let kyb = ky[j * nal + b];
                    inner += sy[j * nal + b] / (kx2 + kyb * kyb).sqrt();
                }
                sum += sxa * inner;
            }
            *v = 2.0 * sum / e_star;
        }
    };
    if parallel {
        out.par_chunks_mut(my).enumerate().for_each(job);
    } else {
        out.chunks_mut(my).enumerate().for_each(job);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Direct O(N²) sum of Love coefficients.
    fn direct(grid: &Grid, e_star: f64, p: &[f64]) -> Vec<f64> {
        let (nx, ny) = (grid.nx(), grid.ny());
        let mut u = vec![0.0; nx * ny];
        for j in 0..ny {
            for i in 0..nx {
                let mut s = 0.0;
                for l in 0..ny {
                    for k in 0..nx {
                        let x = (i as f64 - k as f64) * grid.dx();
                        let y = (j as f64 - l as f64) * grid.dy();
                        s += love_influence(x, y, grid.dx(), grid.dy(), e_star) * p[l * nx + k];
                    }
                }
                u[j * nx + i] = s;
            }
        }
        u
    }

    /// The shared-corner quadrant against `love_influence` cell by cell,
    /// on a cell of unequal sides, out to offsets where the four-corner
    /// difference cancels most (1/r against F ~ r ln r).
    #[test]
    fn quadrant_from_shared_corners_matches_each_coefficient() {
        let (nx, ny, dx, dy, e_star) = (300, 7, 2.5e-4, 1.7e-4, 6.54e6 / 0.75);
        for parallel in [false, true] {
            let quad = love_quadrant(nx, ny, dx, dy, e_star, parallel);
            for dj in 0..ny {
                for di in 0..nx {
                    let direct = love_influence(di as f64 * dx, dj as f64 * dy, dx, dy, e_star);
                    let got = quad[dj * nx + di];
                    assert!(
                        (got - direct).abs() <= 1e-9 * direct,
                        "({di}, {dj}): {got:e} against {direct:e}"
                    );
                }
            }
        }
        // The centre's closed form, 4 ln(1 + √2) s / (π E*) for a square cell.
        let quad = love_quadrant(3, 3, 1e-3, 1e-3, 1.0, false);
        let centre = 4.0 * (1.0 + 2f64.sqrt()).ln() * 1e-3 / PI;
        assert!(
            (quad[0] - centre).abs() < 1e-15,
            "{} against {centre}",
            quad[0]
        );
    }

    #[test]
    fn periodic_alias_sum_is_converged() {
        let grid = Grid::new(16, 10, 1.0, 1.7).expect("grid");
        let (h, my) = (9, 10);
        let a = periodic_spectrum(&grid, 1.0, h, my, PERIODIC_ALIASES, false);
        let b = periodic_spectrum(&grid, 1.0, h, my, 8 * PERIODIC_ALIASES, false);
        let worst = a
            .iter()
            .zip(&b)
            .skip(1)
            .map(|(x, y)| (x - y).abs() / y)
            .fold(0.0f64, f64::max);
        println!("periodic alias truncation: {worst:e}");
        assert!(worst < 1e-6, "alias truncation {worst:e}");
        // Low frequencies: the continuum 2 / (E* |q|) dominates.
        let q = 2.0 * PI / 16.0;
        assert!((a[my] * q / 2.0 - 1.0).abs() < 0.01);
    }

    #[test]
    fn padded_lengths() {
        assert_eq!(padded_len(1), 2);
        assert_eq!(padded_len(512), 1024);
        assert_eq!(padded_len(513), 1050);
        assert_eq!(padded_len(7), 14);
        assert_eq!(padded_len(11), 24);
        // 24 = padded_len(11) is also 12 cells' length, and no more's.
        assert_eq!(cells_at_same_fft_cost(11), 12);
        for n in 1..300 {
            let m = cells_at_same_fft_cost(n);
            assert!(m >= n && padded_len(m) == padded_len(n), "n = {n}");
            assert!(padded_len(m + 1) > padded_len(n), "n = {n}");
        }
    }

    #[test]
    fn fft_matches_direct_sum() {
        for &(nx, ny, parallel) in &[
            (7usize, 5usize, false),
            (8, 9, true),
            (1, 6, true),
            (11, 12, false),
        ] {
            let grid = Grid::new(nx, ny, 0.3, 0.7).expect("grid");
            let p: Vec<f64> = (0..nx * ny).map(|k| ((k * 37 % 11) as f64) - 3.0).collect();
            let mut conv = Convolver::new(&grid, 2.0, false, parallel).expect("conv");
            let mut u = vec![0.0; nx * ny];
            conv.apply(&p, &mut u).expect("apply");
            let d = direct(&grid, 2.0, &p);
            let scale = d.iter().fold(0.0f64, |a, v| a.max(v.abs()));
            for (a, b) in u.iter().zip(&d) {
                assert!((a - b).abs() < 1e-13 * scale, "{a} vs {b}");
            }
        }
    }
}
