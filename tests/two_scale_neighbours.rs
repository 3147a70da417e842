//! The two-scale rebuild under the neighbours' displacement
//! (`TwoScaleOptions::neighbour_passes`, src/two_scale/neighbours.rs)
//! against the full BEM of two close spheres: a cap alone keeps its pressure
//! centred on its summit; pressed beside a loaded neighbour its pressure
//! moves away from it, as the BEM's does.

use tyreroad::bem::{self, BemOptions, Grid, Sphere, spherical_caps};
use tyreroad::contact_law::Material;
use tyreroad::two_scale::{LocalShape, TwoScaleOptions, two_scale};

type TestResult = Result<(), Box<dyn std::error::Error>>;

/// Force-weighted x centroid and contact area of the cells with `x > 0`.
fn right_half(xs: impl Iterator<Item = (f64, f64)>, cell_area: f64) -> (f64, f64, f64) {
    let (mut f, mut fx, mut area) = (0.0, 0.0, 0.0);
    for (x, p) in xs.filter(|&(x, p)| x > 0.0 && p > 0.0) {
        f += p * cell_area;
        fx += p * cell_area * x;
        area += cell_area;
    }
    (f, fx / f, area)
}

#[test]
fn a_cap_beside_a_loaded_neighbour_moves_its_pressure_away_as_the_bem_does() -> TestResult {
    let m = Material::new(6.54e6, 0.5)?;
    let (radius, half_gap, load) = (5e-3, 1.75e-3, 10.0);
    let cell = 0.05e-3;
    let grid = Grid::centered(200, 140, cell, cell)?;
    let spheres: Vec<Sphere> = [-half_gap, half_gap]
        .iter()
        .map(|&x| Sphere {
            centre: [x, 0.0],
            radius,
            summit: 0.0,
        })
        .collect();
    let surface = spherical_caps(&grid, &spheres, -radius)?;
    let options = BemOptions {
        tolerance: 1e-9,
        ..BemOptions::default()
    };
    let sol = bem::solve(&surface, &m, bem::Control::Load(load), &options)?;
    let (nx, ny) = (grid.nx(), grid.ny());
    let cells = (0..nx * ny).map(|k| (grid.x(k % nx), sol.pressure[k]));
    let (bem_force, bem_centroid, bem_area) = right_half(cells, cell * cell);
    let bem_shift = bem_centroid - half_gap;

    let shapes = [LocalShape::Sphere { radius }];
    let positions = [[-half_gap, 0.0], [half_gap, 0.0]];
    let forces = [bem_force, load - bem_force];
    let rebuild = |passes: usize| -> Result<(f64, f64), Box<dyn std::error::Error>> {
        let options = TwoScaleOptions {
            neighbour_passes: passes,
            ..TwoScaleOptions::default()
        };
        let ts = two_scale(&positions, &forces, &shapes, &m, &options)?;
        let right = &ts.local[1];
        let field = right.field.as_ref().ok_or("no field")?;
        let g = field.grid();
        let (f, x, _) = right_half(
            (0..g.len()).map(|k| (g.x(k % g.nx()), field.values()[k])),
            g.dx() * g.dy(),
        );
        assert!((f - forces[1]).abs() < 1e-9 * load, "force {f}");
        Ok((x - half_gap, right.contact_area))
    };
    let (alone_shift, alone_area) = rebuild(0)?;
    let (one_shift, _) = rebuild(1)?;
    let (coupled_shift, coupled_area) = rebuild(2)?;
    let a = (3.0 * 5.0 * radius / (4.0 * m.reduced_modulus())).cbrt();
    println!(
        "two spheres R 5 mm, summits 3.5 mm apart, {load} N: right sphere's pressure centroid off its summit: \
         BEM {:.2} µm, alone {:.2} µm, one pass {:.2} µm, two passes {:.2} µm (Hertz a = {:.3} mm); \
         area BEM {:.4} mm², alone {:.4}, coupled {:.4}",
        bem_shift * 1e6,
        alone_shift * 1e6,
        one_shift * 1e6,
        coupled_shift * 1e6,
        a * 1e3,
        bem_area * 1e6,
        alone_area * 1e6,
        coupled_area * 1e6
    );
    // The BEM moves the pressure outwards by a measurable amount; the lone
    // cap cannot; the coupled rebuild follows the BEM.
    assert!(bem_shift > 0.01 * a, "BEM shift {bem_shift}");
    assert!(alone_shift.abs() < 0.1 * bem_shift, "alone {alone_shift}");
    assert!(
        (coupled_shift - bem_shift).abs() < 0.05 * bem_shift,
        "coupled {coupled_shift} against BEM {bem_shift}"
    );
    Ok(())
}

#[test]
fn a_lone_cap_is_rebuilt_the_same_with_or_without_neighbour_passes() -> TestResult {
    let m = Material::new(6.54e6, 0.5)?;
    let shapes = [LocalShape::Sphere { radius: 5e-3 }];
    let solve = |passes| {
        two_scale(
            &[[1e-3, -2e-3]],
            &[3.0],
            &shapes,
            &m,
            &TwoScaleOptions {
                neighbour_passes: passes,
                ..TwoScaleOptions::default()
            },
        )
    };
    assert_eq!(solve(0)?, solve(2)?);
    Ok(())
}
