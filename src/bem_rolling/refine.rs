//! Is the BEM reference converged in its grid? The same steps solved on the
//! texture's grid and on a grid `factor` times finer, and how far the
//! approach and the sensor forces move (docs/validation.md, "Is the rolling
//! reference converged?").
//!
//! The finer road is the same road, not a smoother one:
//!
//! - a synthetic `aggregate` texture (chippings placed from the seed in
//!   metres, each cell sampling the chippings' continuous surfaces, so the
//!   draw does not depend on the grid) is synthesised again with `factor ×`
//!   the points at `1/factor` the spacing: [`Refinement::Synthesised`];
//! - any other map (a measured file, an FFT-synthesised surface whose draw
//!   depends on its grid) is resampled bilinearly ([`refine_bilinear`]):
//!   [`Refinement::Bilinear`]. That surface has the coarse grid's slopes,
//!   so only the BEM's own discretisation is refined, not the texture.
//!
//! Both fields share the coarse map's road frame (x from its first column,
//! y centred on its middle row), so the fine grid's nodes `f·i` are the
//! coarse nodes `i`.

use std::path::Path;

use crate::rolling::RollingConfig;
use crate::scenario::units::Length;
use crate::scenario::{Scenario, SynthSpec, TextureSpec};
use crate::shared::{Field, Grid, Par};
use crate::texture::HeightMap;

use super::run_scenario::{cut_to_stretch, texture_of};
use super::{BemRollingError, BemRollingOptions, BemRollingResult, Stretch, roll_bem};

/// How the finer road was made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Refinement {
    /// The same synthetic road synthesised on the finer grid.
    Synthesised,
    /// The coarse map resampled bilinearly.
    Bilinear,
}

/// The same steps solved by the BEM on two grids.
#[derive(Clone, Debug)]
pub struct GridConvergence {
    /// On the texture's grid.
    pub coarse: BemRollingResult,
    /// On the refined grid.
    pub fine: BemRollingResult,
    /// Cell sizes (m) of the two grids.
    pub cells: (f64, f64),
    /// How the fine road was made.
    pub refinement: Refinement,
}

impl GridConvergence {
    /// Largest `|fine − coarse|` of the approach over the steps, over the
    /// coarse run's largest approach.
    pub fn approach_change(&self) -> f64 {
        largest_change(&self.coarse.approach(), &self.fine.approach())
    }

    /// Largest `|fine − coarse|` of sensor `k`'s force over the steps, over
    /// the coarse run's largest force on it (the per-step error measure of
    /// the rolling comparison, docs/validation.md).
    pub fn sensor_change(&self, k: usize) -> f64 {
        largest_change(&self.coarse.sensor(k), &self.fine.sensor(k))
    }
}

/// `max |b − a| / max |a|` (NaN when a step failed in either run or `a`
/// is all zero).
fn largest_change(a: &[f64], b: &[f64]) -> f64 {
    let peak = a.iter().fold(0.0_f64, |m, v| m.max(v.abs()));
    let diff = a.iter().zip(b).fold(0.0_f64, |m, (x, y)| {
        if (y - x).is_nan() {
            f64::NAN
        } else {
            m.max((y - x).abs())
        }
    });
    if peak > 0.0 { diff / peak } else { f64::NAN }
}

/// `field` resampled bilinearly on a grid `factor` times finer over the
/// same extent (`(n − 1)·factor + 1` nodes per axis, the same origin): the
/// coarse nodes keep their values, and a bilinear surface is reproduced
/// exactly.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for `factor` 0 or a grid too large.
pub fn refine_bilinear(field: &Field, factor: usize) -> Result<Field, BemRollingError> {
    if factor == 0 {
        return Err(BemRollingError::InvalidInput(
            "refinement factor must be >= 1, got 0".into(),
        ));
    }
    let g = field.grid();
    let (nx, ny) = (g.nx(), g.ny());
    let (fnx, fny) = ((nx - 1) * factor + 1, (ny - 1) * factor + 1);
    let f = factor as f64;
    let grid = Grid::new(fnx, fny, g.dx() / f, g.dy() / f)
        .and_then(|fine| fine.with_origin(g.origin()))
        .map_err(|e| BemRollingError::InvalidInput(format!("refined grid: {e}")))?;
    let v = field.values();
    let at = |i: usize, j: usize| v[g.index(i, j)];
    // Cell (i, j) of the coarse grid and the fraction across it.
    let split = |k: usize, n: usize| {
        let (c, r) = (k / factor, k % factor);
        if c + 1 >= n {
            (n.saturating_sub(2), if n > 1 { 1.0 } else { 0.0 })
        } else {
            (c, r as f64 / f)
        }
    };
    let mut values = Vec::with_capacity(fnx * fny);
    for j in 0..fny {
        let (cj, t) = split(j, ny);
        let cj1 = (cj + 1).min(ny - 1);
        for i in 0..fnx {
            let (ci, s) = split(i, nx);
            let ci1 = (ci + 1).min(nx - 1);
            let lower = (1.0 - s) * at(ci, cj) + s * at(ci1, cj);
            let upper = (1.0 - s) * at(ci, cj1) + s * at(ci1, cj1);
            values.push((1.0 - t) * lower + t * upper);
        }
    }
    Field::new(grid, values).map_err(|e| BemRollingError::InvalidInput(e.to_string()))
}

/// The texture's road field and the same road `factor` times finer, both in
/// the coarse map's road frame (see the module docs for which refinement).
///
/// # Errors
/// [`BemRollingError::InvalidInput`] for `factor` 0 or an incomplete map;
/// [`BemRollingError::Scenario`] when the texture cannot be read or made.
pub fn refined_texture_fields(
    texture: &TextureSpec,
    base_dir: &Path,
    factor: usize,
) -> Result<(Field, Field, Refinement), BemRollingError> {
    let map = texture.height_map(base_dir)?;
    // Before anything is allocated: a factor of 100 on a 200 × 120 map
    // asked for 2.4e8 points and some 5 GB before any refusal.
    let (fx, fy) = (
        map.nx().saturating_mul(factor),
        map.ny().saturating_mul(factor),
    );
    if fx as f64 * fy as f64 > crate::scenario::MAX_MAP_POINTS {
        return Err(BemRollingError::InvalidInput(format!(
            "refinement factor {factor} makes the {} × {} map {fx} × {fy} points, more than \
             the {:e} a map may hold: a smaller factor, or a shorter map",
            map.nx(),
            map.ny(),
            crate::scenario::MAX_MAP_POINTS
        )));
    }
    let coarse = super::texture_field(&map)?;
    let Some(SynthSpec::Aggregate {
        nx,
        ny,
        spacing,
        grading,
        shape,
        coverage,
        embedding,
        seed,
    }) = &texture.synth
    else {
        return Ok((
            coarse.clone(),
            refine_bilinear(&coarse, factor)?,
            Refinement::Bilinear,
        ));
    };
    if factor == 0 {
        return Err(BemRollingError::InvalidInput(
            "refinement factor must be >= 1, got 0".into(),
        ));
    }
    let finer = SynthSpec::Aggregate {
        nx: nx * factor,
        ny: ny * factor,
        spacing: Length::si(spacing.value() / factor as f64),
        grading: grading.clone(),
        shape: shape.clone(),
        coverage: *coverage,
        embedding: *embedding,
        seed: *seed,
    };
    let fine_map: HeightMap = finer.height_map()?;
    let fine = super::texture_field(&fine_map)?;
    // The coarse map's frame: its y_mid, not the fine map's (they differ
    // by half a coarse cell less a fine one).
    let grid = fine
        .grid()
        .clone()
        .with_origin(coarse.grid().origin())
        .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
    let fine = Field::new(grid, fine.values().to_vec())
        .map_err(|e| BemRollingError::InvalidInput(e.to_string()))?;
    Ok((coarse, fine, Refinement::Synthesised))
}

/// Solves `config`'s steps by the BEM on `coarse` and on `fine`.
///
/// # Errors
/// Those of [`roll_bem`].
pub fn grid_convergence(
    coarse: &Field,
    fine: &Field,
    refinement: Refinement,
    material: crate::shared::Material,
    config: &RollingConfig,
    options: &BemRollingOptions,
) -> Result<GridConvergence, BemRollingError> {
    Ok(GridConvergence {
        coarse: roll_bem(coarse, material, config, options)?,
        fine: roll_bem(fine, material, config, options)?,
        cells: (coarse.grid().dx(), fine.grid().dx()),
        refinement,
    })
}

/// [`grid_convergence`] on a `[rolling]` scenario's `[texture]` over
/// `stretch` (its Welch segment unused), the fine grid `factor` times finer.
///
/// # Errors
/// [`BemRollingError::InvalidInput`] without `[texture]` or `[rolling]`, or
/// for a stretch off the path; those of [`refined_texture_fields`] and
/// [`roll_bem`].
pub fn run_grid_convergence(
    mut scenario: Scenario,
    base_dir: &Path,
    stretch: Stretch,
    factor: usize,
    par: Par,
    options: &BemRollingOptions,
) -> Result<GridConvergence, BemRollingError> {
    let texture = texture_of(&scenario, "the grid convergence check")?;
    let (coarse, fine, refinement) = refined_texture_fields(texture, base_dir, factor)?;
    cut_to_stretch(&mut scenario, stretch)?;
    let config = scenario.rolling_config()?;
    grid_convergence(
        &coarse,
        &fine,
        refinement,
        scenario.material()?,
        &config,
        &BemRollingOptions {
            par,
            ..options.clone()
        },
    )
}
