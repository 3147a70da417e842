//! The multipoint model against the full-grid BEM reference on random ball
//! sets (docs/validation.md): balls of random radius (2–6 mm) and summit
//! height (spread 0.5 mm) in a 40 × 40 mm square, at least 4.5 mm apart; two
//! loads each. Per-ball forces, approach, contact counts, and the two-scale
//! radii against the BEM's.
//!
//! `cargo run --release --example random_sets` (or without `--release`:
//! about four times slower).

use std::time::Instant;

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad::asperity::Sphere;
use tyreroad::bem::{self, BemOptions, Grid, nearest_labels, spherical_caps};
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};
use tyreroad::two_scale::{LocalShape, TwoScaleOptions, two_scale};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

/// BEM cell size (m), as in `cargo xtask validate`.
const CELL: f64 = 1e-4;

struct Ball {
    position: [f64; 2],
    radius: f64,
    height: f64,
}

fn random_set(n: usize, seed: u64) -> Res<Vec<Ball>> {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    let mut balls: Vec<Ball> = Vec::with_capacity(n);
    let side = 0.04;
    // Random sequential placement jams near 55 % cover: give up rather than
    // loop forever.
    let mut attempts = 0;
    while balls.len() < n {
        attempts += 1;
        if attempts > 1_000_000 {
            return Err(format!("cannot place {n} balls 4.5 mm apart").into());
        }
        let p = [
            (rng.random::<f64>() - 0.5) * side,
            (rng.random::<f64>() - 0.5) * side,
        ];
        let radius = 2e-3 + 4e-3 * rng.random::<f64>();
        let height = 5e-4 * rng.random::<f64>();
        if balls
            .iter()
            .all(|b| (b.position[0] - p[0]).hypot(b.position[1] - p[1]) >= 4.5e-3)
        {
            balls.push(Ball {
                position: p,
                radius,
                height,
            });
        }
    }
    Ok(balls)
}

fn main() -> Res<()> {
    let m = Material::new(6.54e6, 0.5)?;
    let bem_m = bem::Material::new(6.54e6, 0.5)?;
    for (seed, n, loads) in [(1u64, 40usize, [60.0, 250.0]), (2, 50, [100.0, 400.0])] {
        let balls = random_set(n, seed)?;
        let positions: Vec<[f64; 2]> = balls.iter().map(|b| b.position).collect();
        let heights: Vec<f64> = balls.iter().map(|b| b.height).collect();
        let laws = balls
            .iter()
            .map(|b| Ok(PotentialLaw::sphere(Sphere::new(b.radius)?, m)))
            .collect::<Res<Vec<_>>>()?;
        let problem = Problem::from_heights(positions.clone(), &heights, laws, m)?;

        // BEM grid: the square plus 3 mm (contact radii stay below ~2.5 mm),
        // odd cell count, the true spherical caps on a floor below them all.
        let half = 0.02 + 3e-3;
        let cells = 2 * (half / CELL).round() as usize + 1;
        let grid = Grid::centered(cells, cells, CELL, CELL)?;
        let spheres: Vec<bem::Sphere> = balls
            .iter()
            .map(|b| bem::Sphere {
                centre: b.position,
                radius: b.radius,
                summit: b.height,
            })
            .collect();
        let base = balls
            .iter()
            .map(|b| b.height - b.radius)
            .fold(f64::INFINITY, f64::min);
        let surface = spherical_caps(&grid, &spheres, base)?;
        let labels = nearest_labels(&grid, &positions);
        let mut solver = bem::Solver::new(&grid, &bem_m, &BemOptions::default())?;
        println!(
            "\n== set {seed}: {n} balls, R 2–6 mm, heights 0–0.5 mm, 40 × 40 mm; BEM {cells}² cells of {} mm",
            CELL * 1e3
        );
        let mut previous: Option<Vec<f64>> = None;
        for load in loads {
            let t = Instant::now();
            let sol = match &previous {
                Some(p) => solver.solve_from(&surface, bem::Control::Load(load), p)?,
                None => solver.solve(&surface, bem::Control::Load(load))?,
            };
            let bem_s = t.elapsed().as_secs_f64();
            let regions = sol.regions(&labels)?;
            let t = Instant::now();
            let mp = solve(&problem, Control::Load(load), &SolverOptions::default())?;
            let mp_s = t.elapsed().as_secs_f64();
            let shapes: Vec<LocalShape> = balls
                .iter()
                .map(|b| LocalShape::Sphere { radius: b.radius })
                .collect();
            let ts = two_scale(
                &positions,
                &mp.forces,
                &shapes,
                &m,
                &TwoScaleOptions::default(),
            )?;

            let mean = load / regions.iter().filter(|r| r.force > 0.0).count().max(1) as f64;
            let (mut max_abs, mut sum_abs, mut max_rel, mut arg) = (0.0f64, 0.0, 0.0f64, 0);
            let (mut both, mut only_mp, mut only_bem) = (0, 0, 0);
            let (mut max_da, mut sum_da, mut count_da) = (0.0f64, 0.0, 0);
            for (k, r) in regions.iter().enumerate() {
                let d = (mp.forces[k] - r.force).abs();
                max_abs = max_abs.max(d);
                sum_abs += d;
                // Relative differences on the balls carrying ≥ 10 % of the mean.
                if r.force >= 0.1 * mean {
                    let rel = d / r.force;
                    if rel > max_rel {
                        max_rel = rel;
                        arg = k;
                    }
                    let da = (ts.local[k].radius - r.equivalent_radius).abs() / r.equivalent_radius;
                    max_da = max_da.max(da);
                    sum_da += da;
                    count_da += 1;
                }
                match (mp.forces[k] > 0.0, r.force > 0.0) {
                    (true, true) => both += 1,
                    (true, false) => only_mp += 1,
                    (false, true) => only_bem += 1,
                    _ => {}
                }
            }
            // Small-force disagreements on contact (balls just touching).
            let edge: Vec<String> = regions
                .iter()
                .enumerate()
                .filter(|(k, r)| (mp.forces[*k] > 0.0) != (r.force > 0.0))
                .map(|(k, r)| format!("#{k}: model {:.3} N, BEM {:.3} N", mp.forces[k], r.force))
                .collect();
            println!(
                "  W = {load:>5} N: contacts model {} / BEM {} (both {both}, model only {only_mp}, BEM only {only_bem}); \
                 approach model {:.4} mm, BEM {:.4} mm ({:+.2} %)",
                mp.contact_count(),
                regions.iter().filter(|r| r.force > 0.0).count(),
                mp.approach * 1e3,
                sol.approach * 1e3,
                (mp.approach / sol.approach - 1.0) * 100.0
            );
            println!(
                "    forces: max |ΔP| = {:.3} N ({:.2} % of the mean force {:.2} N), mean |ΔP| = {:.3} N ({:.2} %); \
                 max |ΔP|/P_BEM on balls with P ≥ 10 % of the mean: {:.2} % (#{arg}: model {:.3} N, BEM {:.3} N)",
                max_abs,
                max_abs / mean * 100.0,
                mean,
                sum_abs / n as f64,
                sum_abs / n as f64 / mean * 100.0,
                max_rel * 100.0,
                mp.forces[arg],
                regions[arg].force,
            );
            let nearest = positions
                .iter()
                .enumerate()
                .filter(|(k, _)| *k != arg)
                .map(|(k, p)| {
                    let d = (p[0] - positions[arg][0]).hypot(p[1] - positions[arg][1]);
                    (d, k)
                })
                .fold((f64::INFINITY, 0), |a, b| if b.0 < a.0 { b } else { a });
            println!(
                "    ball #{arg}: R {:.2} mm, BEM a {:.2} mm; nearest ball #{} at {:.2} mm (R {:.2} mm, BEM a {:.2} mm, P {:.2} N)",
                balls[arg].radius * 1e3,
                regions[arg].equivalent_radius * 1e3,
                nearest.1,
                nearest.0 * 1e3,
                balls[nearest.1].radius * 1e3,
                regions[nearest.1].equivalent_radius * 1e3,
                regions[nearest.1].force
            );
            println!(
                "    two-scale radii vs BEM (same balls): max {:.2} %, mean {:.2} %; times: BEM {:.2} s ({} it.), multipoint {:.1} ms",
                max_da * 100.0,
                sum_da / count_da.max(1) as f64 * 100.0,
                bem_s,
                sol.iterations,
                mp_s * 1e3
            );
            if !edge.is_empty() {
                println!("    contact disagreements: {}", edge.join("; "));
            }
            previous = Some(sol.pressure);
        }
    }
    Ok(())
}
