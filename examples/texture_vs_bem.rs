//! Static contact of a flat rubber block (E = 6.54 MPa, ν = 0.5) on two
//! synthetic road textures (40 × 40 mm at 0.1 mm): the multipoint model on
//! the segmented asperities (tabulated caps, potential law c = 0.36,
//! half-section local rule, as `cargo xtask run` does for a `[texture]`)
//! against the full-grid BEM on the same height map (non-periodic). Per load:
//! approach, contacts, and per-asperity forces (BEM force per asperity =
//! pressure summed over its segmentation basin).
//!
//! `cargo run --release --example texture_vs_bem` (docs/validation.md).

use std::sync::Arc;
use std::time::Instant;

use tyreroad::bem::{self, BemOptions, Grid};
use tyreroad::contact_law::Material;
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};
use tyreroad::texture::{Aggregate, HeightMap, SelfAffine, UNLABELLED, aggregate, self_affine};
use tyreroad::texture_road::{CapDepth, TextureRoadOptions, texture_road};
use tyreroad::two_scale::{TwoScaleOptions, two_scale_solution};

type Res<T> = Result<T, Box<dyn std::error::Error>>;

const N: usize = 400;
const CELL: f64 = 1e-4;

fn compare(name: &str, map: &HeightMap, loads: &[f64], deep: bool) -> Res<()> {
    let m = Material::new(6.54e6, 0.5)?;
    let bem_m = bem::Material::new(6.54e6, 0.5)?;
    let mut options = TextureRoadOptions::new(0.2e-3, 2e-6);
    options.depth = if deep {
        CapDepth::BasinBottom
    } else {
        CapDepth::GridCapRange
    };
    let road = texture_road(map, m, &options)?;
    let n = road.len();
    let summit_top = road.set.top();
    let seg = &road.segmentation;
    let index = road.asperity_index.clone();
    // Each asperity's own surface, for the two-scale contact areas.
    let shapes = road.local_shapes(&Arc::new(map.clone()))?;
    let problem = Problem::from_set(road.set, m)?;

    // Labels for the BEM: segmentation index → multipoint index; missing
    // points and dropped asperities → the spare label n.
    let mut to_mp = vec![n; seg.asperities().len()];
    for (i, &k) in index.iter().enumerate() {
        to_mp[k] = i;
    }
    let labels: Vec<usize> = seg
        .labels()
        .iter()
        .map(|&l| {
            if l == UNLABELLED {
                n
            } else {
                to_mp[l as usize]
            }
        })
        .collect();
    let grid = Grid::new(map.nx(), map.ny(), map.dx(), map.dy())?;
    let surface = bem::HeightMap::new(grid.clone(), map.filled()?.heights().to_vec())?;
    let grid_top = surface.max();
    let mut solver = bem::Solver::new(&grid, &bem_m, &BemOptions::default())?;
    println!(
        "\n{name}, caps to {}: Sq = {:.3} mm, {} asperities ({} segmented), summit − grid top = {:.1} µm",
        if deep {
            "basin bottom"
        } else {
            "grid-cap range"
        },
        map.rms().unwrap_or(f64::NAN) * 1e3,
        n,
        seg.asperities().len(),
        (summit_top - grid_top) * 1e6
    );
    println!(
        "| load (N) | δ MP (µm) | δ MP from grid top (µm) | δ BEM (µm) | contacts MP / BEM | ½Σ|ΔF|/W | top-5 BEM forces (N) vs MP | BEM off-asperity (N) | contact area two-scale / half-section / BEM (mm²) | t MP / BEM (s) |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|");
    for &w in loads {
        let t0 = Instant::now();
        // Tabulated laws are only piecewise smooth: Newton may stall just
        // above the default 1e-11; retry at 1e-8 (marked *).
        let (mp, retried) = match solve(&problem, Control::Load(w), &SolverOptions::default()) {
            Ok(s) => (s, ""),
            Err(_) => {
                let loose = SolverOptions {
                    tolerance: 1e-8,
                    ..SolverOptions::default()
                };
                match solve(&problem, Control::Load(w), &loose) {
                    Ok(s) => (s, "*"),
                    Err(e) => {
                        println!("| {w:.0} | multipoint failed: {e} |");
                        continue;
                    }
                }
            }
        };
        let t_mp = t0.elapsed().as_secs_f64();
        let t0 = Instant::now();
        let b = solver.solve(&surface, bem::Control::Load(w))?;
        let t_bem = t0.elapsed().as_secs_f64();
        let regions = b.regions(&labels)?;
        let f_bem: Vec<f64> = (0..n)
            .map(|i| regions.get(i).map_or(0.0, |r| r.force))
            .collect();
        let off = regions.get(n).map_or(0.0, |r| r.force);
        let misallocated = 0.5
            * mp.forces
                .iter()
                .zip(&f_bem)
                .map(|(a, b)| (a - b).abs())
                .sum::<f64>()
            / w;
        let bem_contacts = f_bem.iter().filter(|&&f| f > 1e-9 * w).count();
        let mut order: Vec<usize> = (0..n).collect();
        order.sort_by(|&i, &j| f_bem[j].total_cmp(&f_bem[i]));
        let top: Vec<String> = order
            .iter()
            .take(5)
            .map(|&i| format!("{:.1}/{:.1}", f_bem[i], mp.forces[i]))
            .collect();
        // Contact areas: each asperity's force re-solved on its own surface
        // (two-scale), the law's half-section rule, and the full BEM.
        let half_section: f64 = mp.local_contacts(&problem).iter().map(|c| c.area()).sum();
        let two = two_scale_solution(
            &problem,
            &mp,
            &shapes,
            &TwoScaleOptions {
                map_cell: Some(CELL),
                ..TwoScaleOptions::default()
            },
        )
        .map(|t| {
            format!(
                "{:.1}",
                t.local.iter().map(|f| f.contact_area).sum::<f64>() * 1e6
            )
        })
        .unwrap_or_else(|e| format!("failed ({e})"));
        let areas = format!(
            "{two} / {:.1} / {:.1}",
            half_section * 1e6,
            b.contact_area * 1e6
        );
        // The multipoint approach is measured from the highest refined
        // summit, the BEM's from the highest grid point.
        let mp_from_grid = mp.approach - (summit_top - grid_top);
        println!(
            "| {w:.0}{retried} | {:.1} | {:.1} | {:.1} | {} / {} | {:.1} % | {} | {:.2} | {areas} | {:.3} / {:.1} |",
            mp.approach * 1e6,
            mp_from_grid * 1e6,
            b.approach * 1e6,
            mp.contact_count(),
            bem_contacts,
            misallocated * 100.0,
            top.join(", "),
            off,
            t_mp,
            t_bem
        );
    }
    Ok(())
}

fn main() -> Res<()> {
    let loads = [50.0, 150.0, 300.0];
    let agg = aggregate(&Aggregate::new(
        N,
        N,
        CELL,
        CELL,
        Aggregate::grading_4_6(),
        2026,
    ))?;
    for deep in [false, true] {
        compare("aggregate 4/6.3 ellipsoids, seed 2026", &agg, &loads, deep)?;
    }
    let sa = self_affine(&SelfAffine {
        nx: N,
        ny: N,
        dx: CELL,
        dy: CELL,
        rms: 0.5e-3,
        hurst: 0.8,
        lambda_long: 20e-3,
        lambda_short: 1e-3,
        seed: 1,
    })?;
    for deep in [false, true] {
        compare(
            "self-affine Sq 0.5 mm, H 0.8, λ 1–20 mm, seed 1",
            &sa,
            &loads,
            deep,
        )?;
    }
    Ok(())
}
