//! Grid convergence of the per-ball forces on the 25-ball experiment of
//! Cesbron et al. (2006, section 3: 25 steel balls R = 5 mm at 10 mm pitch,
//! coplanar summits, E = 6.54 MPa, ν = 0.5) at 500 N.
//!
//! ```text
//! cargo run --release -p tyreroad-bem --example grid_convergence [-- --fine]
//! ```
//!
//! Cells of 0.4, 0.2, 0.1 mm (and 0.05 mm with `--fine`) on a square domain
//! of about 51.3 mm (an odd number of cells, so that every summit is a cell
//! centre), which covers the contact zones (|x|, |y| ≤ 22.2 mm) with margin.

use std::time::Instant;

use tyreroad_bem::{
    BemError, BemOptions, Control, Grid, Material, Solver, Sphere, nearest_labels, spherical_caps,
};

fn main() -> Result<(), BemError> {
    let fine = std::env::args().any(|a| a == "--fine");
    let radius = 5e-3;
    let load = 500.0;
    let material = Material::new(6.54e6, 0.5)?;
    let pos = [-0.02, -0.01, 0.0, 0.01, 0.02];
    let balls: Vec<Sphere> = pos
        .iter()
        .flat_map(|&y| {
            pos.iter().map(move |&x| Sphere {
                centre: [x, y],
                radius,
                summit: 0.0,
            })
        })
        .collect();
    let centres: Vec<[f64; 2]> = balls.iter().map(|b| b.centre).collect();
    let hertz_a = (3.0 * load / 25.0 * radius / (4.0 * material.reduced_modulus())).cbrt();
    println!(
        "25 balls, W = {load} N, E* = {:.3} MPa; Hertz for W/25 = 20 N alone: a = {:.4} mm, delta = {:.4} mm",
        material.reduced_modulus() * 1e-6,
        hertz_a * 1e3,
        hertz_a * hertz_a / radius * 1e3
    );
    // Ball k = 5·row + column: 0 corner, 1 edge (next to a corner),
    // 2 edge (middle), 6 inner diagonal, 7 inner side, 12 centre.
    let show = [
        (0, "corner"),
        (1, "edge-1"),
        (2, "edge-mid"),
        (6, "inner-diag"),
        (7, "inner-side"),
        (12, "centre"),
    ];
    print!("| cell (mm) | cells | iters | time (s) | approach (mm) |");
    for (_, name) in show {
        print!(" {name} (N) |");
    }
    println!(" centre a_eq (mm) |");
    let mut cells_mm: Vec<f64> = vec![0.4, 0.2, 0.1];
    if fine {
        cells_mm.push(0.05);
    }
    let mut previous: Option<Vec<f64>> = None;
    for dx_mm in cells_mm {
        let dx = dx_mm * 1e-3;
        let n = 2 * (25.6 / dx_mm).round() as usize + 1;
        let grid = Grid::centered(n, n, dx, dx)?;
        let surface = spherical_caps(&grid, &balls, -radius)?;
        let labels = nearest_labels(&grid, &centres);
        let options = BemOptions {
            tolerance: 1e-8,
            ..BemOptions::default()
        };
        let t0 = Instant::now();
        let mut solver = Solver::new(&grid, &material, &options)?;
        let s = solver.solve(&surface, Control::Load(load))?;
        let time = t0.elapsed().as_secs_f64();
        let regions = s.regions(&labels)?;
        let forces: Vec<f64> = regions.iter().map(|r| r.force).collect();
        print!(
            "| {dx_mm} | {n}² | {} | {time:.2} | {:.5} |",
            s.iterations,
            s.approach * 1e3
        );
        for (k, _) in show {
            match &previous {
                Some(prev) => print!(
                    " {:.4} ({:+.2} %) |",
                    forces[k],
                    100.0 * (forces[k] / prev[k] - 1.0)
                ),
                None => print!(" {:.4} |", forces[k]),
            }
        }
        println!(" {:.4} |", regions[12].equivalent_radius * 1e3);
        previous = Some(forces);
    }
    println!("(in parentheses: change from the previous, coarser grid)");
    Ok(())
}
