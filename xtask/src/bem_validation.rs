//! The multipoint model measured against the full-grid BEM reference on the
//! paper's case (DESIGN §2.2–2.3, docs/validation.md): the same balls as
//! true spherical caps on a 0.1 mm grid, per-ball forces and radii from the
//! Voronoi regions of the summits; the two-scale radii (each ball's real
//! shape solved alone under its multipoint force); the 500 N pressure map.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use tyreroad::two_scale::{LocalShape, TwoScale, TwoScaleOptions, two_scale};
use tyreroad_bem::{BemOptions, Control, Grid, Solver, Sphere, nearest_labels, spherical_caps};
use tyreroad_multipoint::solve;

use crate::scenario::{Scenario, ShapeSpec};
use crate::statics::{StaticRow, loads, write_static_csv};

/// BEM cell size (m): per-ball forces change by < 0.05 % from 0.1 to
/// 0.05 mm on this case (docs/bem.md, grid convergence).
pub const BEM_CELL: f64 = 1e-4;

/// Largest relative per-ball force difference, model vs BEM, that passes.
pub const MAX_FORCE_DIFFERENCE: f64 = 0.05;

/// Cell of the two-scale pressure map (m), 1 pixel of the image.
pub const MAP_CELL: f64 = 8e-5;

/// The load whose pressure map is drawn (N), or the largest if absent.
pub const IMAGE_LOAD: f64 = 500.0;

/// A pass/fail line of the validation.
pub struct BemCheck {
    /// What is checked.
    pub name: String,
    /// Whether it passed.
    pub passed: bool,
    /// Figures.
    pub detail: String,
}

/// Checks and files of [`run`].
pub struct BemReport {
    /// Checks to add to the validation's.
    pub checks: Vec<BemCheck>,
    /// Paths written.
    pub written: Vec<String>,
}

/// One ball of the scenario, as the BEM sees it.
struct Ball {
    position: [f64; 2],
    summit: f64,
    radius: f64,
}

fn balls(scenario: &Scenario) -> Result<Vec<Ball>> {
    scenario
        .asperities
        .iter()
        .enumerate()
        .map(|(k, a)| {
            let shape = a
                .shape
                .as_ref()
                .or(scenario.default_shape.as_ref())
                .with_context(|| format!("asperity #{}: no shape", k + 1))?;
            let ShapeSpec::Sphere { radius, .. } = shape else {
                bail!(
                    "asperity #{}: the BEM comparison handles spheres only",
                    k + 1
                );
            };
            Ok(Ball {
                position: [a.x.value(), a.y.value()],
                summit: a.height.map_or(0.0, |h| h.value()),
                radius: radius.value(),
            })
        })
        .collect()
}

/// The BEM grid: square cells of `cell`, an odd count per axis centred on
/// the middle of the summits (so that summits on a pitch multiple of `cell`
/// are cell centres), covering every ball's footprint.
fn bem_grid(balls: &[Ball], cell: f64) -> Result<Grid> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for b in balls {
        for a in 0..2 {
            lo[a] = lo[a].min(b.position[a] - b.radius);
            hi[a] = hi[a].max(b.position[a] + b.radius);
        }
    }
    let centre = [0.5 * (lo[0] + hi[0]), 0.5 * (lo[1] + hi[1])];
    let n = |a: usize| 2 * ((0.5 * (hi[a] - lo[a]) / cell).ceil() as usize) + 1;
    let (nx, ny) = (n(0), n(1));
    Ok(Grid::new(nx, ny, cell, cell)?.with_origin([
        centre[0] - (nx / 2) as f64 * cell,
        centre[1] - (ny / 2) as f64 * cell,
    ])?)
}

/// One load of the BEM reference.
struct BemLoad {
    load: f64,
    forces: Vec<f64>,
    radii: Vec<f64>,
    approach: f64,
    iterations: usize,
    seconds: f64,
}

/// Max and mean of `|a − b| / b` over the entries with `b > 0`, and the
/// index of the max.
fn differences(a: &[f64], b: &[f64]) -> (f64, f64, usize) {
    let (mut max, mut sum, mut count, mut arg) = (0.0f64, 0.0, 0usize, 0);
    for (k, (x, y)) in a.iter().zip(b).enumerate() {
        if *y > 0.0 {
            let d = (x - y).abs() / y;
            if d > max {
                max = d;
                arg = k;
            }
            sum += d;
            count += 1;
        }
    }
    (max, sum / count.max(1) as f64, arg)
}

/// Solves the scenario by the BEM at every load of `rows` (the multipoint
/// results, in scenario order per load), rebuilds the two-scale radii,
/// writes `DIR/NAME_bem.csv`, `DIR/NAME_two_scale.csv` and
/// `DIR/NAME_pressure_500N.png`, prints the differences and returns the
/// checks.
pub fn run(rows: &[StaticRow], scenario: &Scenario, out: &Path) -> Result<BemReport> {
    let balls = balls(scenario)?;
    let material = scenario.material()?;
    let bem_material =
        tyreroad_bem::Material::new(material.youngs_modulus(), material.poisson_ratio())?;
    let positions: Vec<[f64; 2]> = balls.iter().map(|b| b.position).collect();
    let ids = scenario.ids();
    let load_list = loads(rows);
    let n = balls.len();
    let at_load =
        |load: f64| -> Vec<&StaticRow> { rows.iter().filter(|r| r.load == load).collect() };
    for &load in &load_list {
        if at_load(load).len() != n {
            bail!("{load} N: {} rows for {n} asperities", at_load(load).len());
        }
    }

    // --- BEM reference, loads in increasing order, warm-started.
    let start = Instant::now();
    let grid = bem_grid(&balls, BEM_CELL)?;
    let base = balls
        .iter()
        .map(|b| b.summit - b.radius)
        .fold(f64::INFINITY, f64::min);
    let spheres: Vec<Sphere> = balls
        .iter()
        .map(|b| Sphere {
            centre: b.position,
            radius: b.radius,
            summit: b.summit,
        })
        .collect();
    let surface = spherical_caps(&grid, &spheres, base)?;
    let labels = nearest_labels(&grid, &positions);
    let mut solver = Solver::new(&grid, &bem_material, &BemOptions::default())?;
    let setup = start.elapsed().as_secs_f64();
    let mut order = load_list.clone();
    order.sort_by(f64::total_cmp);
    let mut previous: Option<Vec<f64>> = None;
    let mut bem = Vec::new();
    for &load in &order {
        let t = Instant::now();
        let sol = match &previous {
            Some(p) => solver.solve_from(&surface, Control::Load(load), p),
            None => solver.solve(&surface, Control::Load(load)),
        }
        .with_context(|| format!("BEM solve at {load} N"))?;
        let regions = sol.regions(&labels)?;
        bem.push(BemLoad {
            load,
            forces: regions.iter().map(|r| r.force).collect(),
            radii: regions.iter().map(|r| r.equivalent_radius).collect(),
            approach: sol.approach,
            iterations: sol.iterations,
            seconds: t.elapsed().as_secs_f64(),
        });
        previous = Some(sol.pressure);
    }
    let bem_at = |load: f64| bem.iter().find(|b| b.load == load);

    // --- Two-scale radii from the multipoint forces.
    let shapes: Vec<LocalShape> = balls
        .iter()
        .map(|b| LocalShape::Sphere { radius: b.radius })
        .collect();
    let options = TwoScaleOptions {
        map_cell: Some(MAP_CELL),
        ..TwoScaleOptions::default()
    };
    let t = Instant::now();
    let mut two: Vec<(f64, TwoScale)> = Vec::new();
    for &load in &load_list {
        let forces: Vec<f64> = at_load(load).iter().map(|r| r.force).collect();
        let ts = two_scale(&positions, &forces, &shapes, &material, &options)
            .with_context(|| format!("two-scale at {load} N"))?;
        two.push((load, ts));
    }
    let two_seconds = t.elapsed().as_secs_f64();

    // --- Multipoint approaches, for the comparison (a solve is milliseconds).
    let problem = scenario.problem()?;
    let solver_options = scenario.solver_options();

    println!(
        "\nBEM reference: true spherical caps, {}×{} cells of {} mm ({:.1} × {:.1} mm), \
         tolerance 1e-8, per-ball forces from the Voronoi regions of the summits; \
         set-up {:.2} s",
        grid.nx(),
        grid.ny(),
        BEM_CELL * 1e3,
        grid.size()[0] * 1e3,
        grid.size()[1] * 1e3,
        setup
    );
    let mut checks = Vec::new();
    let (mut bem_rows, mut two_rows) = (Vec::new(), Vec::new());
    println!(
        "Multipoint model vs BEM, relative per-ball differences |Δ|/BEM (max at indenter, mean):"
    );
    for (&load, (_, ts)) in load_list.iter().zip(&two) {
        let b = bem_at(load).context("missing BEM load")?;
        let mp = at_load(load);
        let mp_forces: Vec<f64> = mp.iter().map(|r| r.force).collect();
        let mp_radii: Vec<f64> = mp.iter().map(|r| r.radius).collect();
        let ts_radii: Vec<f64> = ts.local.iter().map(|l| l.radius).collect();
        let (fmax, fmean, fk) = differences(&mp_forces, &b.forces);
        let (rmax, rmean, rk) = differences(&mp_radii, &b.radii);
        let (tmax, tmean, tk) = differences(&ts_radii, &b.radii);
        let mp_approach = solve(
            &problem,
            tyreroad_multipoint::Control::Load(load),
            &solver_options,
        )
        .map(|s| s.approach)
        .unwrap_or(f64::NAN);
        println!(
            "  {load:>5} N: BEM {} it. {:.2} s, δ {:.4} mm (model {:.4} mm, {:+.2} %) | \
             forces max {:.2} % (#{}) mean {:.2} % | radii, Hertz rebuild: max {:.2} % (#{}) mean {:.2} % | \
             radii, two-scale: max {:.2} % (#{}) mean {:.2} %",
            b.iterations,
            b.seconds,
            b.approach * 1e3,
            mp_approach * 1e3,
            (mp_approach / b.approach - 1.0) * 100.0,
            fmax * 100.0,
            ids[fk],
            fmean * 100.0,
            rmax * 100.0,
            ids[rk],
            rmean * 100.0,
            tmax * 100.0,
            ids[tk],
            tmean * 100.0,
        );
        checks.push(BemCheck {
            name: format!("model vs BEM forces at {load} N"),
            passed: fmax <= MAX_FORCE_DIFFERENCE,
            detail: format!(
                "max |ΔP|/P_BEM = {:.2} %, mean {:.2} % (≤ {} %)",
                fmax * 100.0,
                fmean * 100.0,
                MAX_FORCE_DIFFERENCE * 100.0
            ),
        });
        let bem_total: f64 = b.forces.iter().sum();
        let map_total = ts.map.as_ref().map_or(0.0, |m| m.integral());
        let balance = ((bem_total - load) / load)
            .abs()
            .max(((map_total - load) / load).abs());
        checks.push(BemCheck {
            name: format!("BEM Σ regions and two-scale map integral at {load} N"),
            passed: balance <= 1e-9,
            detail: format!("max |Σ − W| / W = {balance:.1e} (≤ 1e-9)"),
        });
        checks.push(BemCheck {
            name: format!("two-scale radii vs BEM at {load} N"),
            passed: tmax <= 0.05,
            detail: format!(
                "max |Δa|/a_BEM = {:.2} %, mean {:.2} % (≤ 5 %)",
                tmax * 100.0,
                tmean * 100.0
            ),
        });
        for (k, r) in mp.iter().enumerate() {
            bem_rows.push(StaticRow {
                force: b.forces[k],
                radius: b.radii[k],
                ..(*r).clone()
            });
            two_rows.push(StaticRow {
                radius: ts.local[k].radius,
                ..(*r).clone()
            });
        }
    }
    println!(
        "  two-scale local solves: {two_seconds:.2} s for {} loads",
        load_list.len()
    );

    // --- The per-ball table at the image load.
    let shown = if load_list.contains(&IMAGE_LOAD) {
        IMAGE_LOAD
    } else {
        order.last().copied().context("no load")?
    };
    if let (Some(b), Some((_, ts))) = (bem_at(shown), two.iter().find(|(l, _)| *l == shown)) {
        println!(
            "\nAt {shown} N, per indenter: forces (N) and radii (mm): model (Hertz rebuild), two-scale, BEM"
        );
        println!(
            "{:>9} {:>8} {:>8} {:>8} | {:>7} {:>7} {:>7}",
            "indenter", "P model", "P BEM", "ΔP %", "a Hertz", "a 2-sc", "a BEM"
        );
        for (k, r) in at_load(shown).iter().enumerate() {
            println!(
                "{:>9} {:>8.3} {:>8.3} {:>+8.2} | {:>7.3} {:>7.3} {:>7.3}",
                r.id,
                r.force,
                b.forces[k],
                (r.force / b.forces[k] - 1.0) * 100.0,
                r.radius * 1e3,
                ts.local[k].radius * 1e3,
                b.radii[k] * 1e3
            );
        }
    }

    let mut written = Vec::new();
    let bem_path = out.join(format!("{}_bem.csv", scenario.name));
    write_static_csv(&bem_path, &bem_rows)?;
    written.push(bem_path.display().to_string());
    let two_path = out.join(format!("{}_two_scale.csv", scenario.name));
    write_static_csv(&two_path, &two_rows)?;
    written.push(two_path.display().to_string());
    if let Some((_, ts)) = two.iter().find(|(l, _)| *l == shown)
        && let Some(map) = &ts.map
    {
        let png = out.join(format!("{}_pressure_{shown:.0}N.png", scenario.name));
        crate::pressure_image::write_pressure_png(&png, map, &format!("{shown:.0} N"))?;
        written.push(png.display().to_string());
    }
    Ok(BemReport { checks, written })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn differences_are_relative_to_the_reference() {
        let (max, mean, arg) = differences(&[1.1, 2.0, 5.0], &[1.0, 2.0, 0.0]);
        assert!((max - 0.1).abs() < 1e-12);
        assert!((mean - 0.05).abs() < 1e-12);
        assert_eq!(arg, 0);
    }
}
