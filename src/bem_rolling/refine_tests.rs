//! The grid refinement machinery: bilinear resampling keeps the coarse
//! nodes and reproduces bilinear surfaces, and on a sphere under a flat
//! block the refined BEM approaches Hertz.

use super::refine::{Refinement, grid_convergence, refine_bilinear};
use super::*;
use crate::bem::{Sphere, spherical_caps};
use crate::rolling::Tread;

const E: f64 = 6.54e6;
const NU: f64 = 0.5;
const R: f64 = 10e-3;
const LOAD: f64 = 1.0;

fn material() -> Material {
    Material::new(E, NU).expect("valid material")
}

/// A sphere of radius [`R`] with its summit on a node at (8 mm, 0) of a
/// 16 × 16 mm map of spacing `dx`.
fn sphere_map(dx: f64) -> Field {
    let n = (16e-3 / dx).round() as usize + 1;
    let grid = Grid::new(n, n, dx, dx)
        .and_then(|g| g.with_origin([0.0, -8e-3]))
        .expect("valid grid");
    let sphere = Sphere {
        centre: [8e-3, 0.0],
        radius: R,
        summit: 0.0,
    };
    spherical_caps(&grid, &[sphere], -R).expect("valid sphere")
}

/// A flat 6 × 6 mm block over the sphere, three steps of 0.4 mm, under
/// [`LOAD`].
fn config() -> RollingConfig {
    let block = Tread::Block {
        length: 6e-3,
        width: 6e-3,
    };
    RollingConfig::new(
        block,
        [7.6e-3, 8.4e-3, 0.4e-3],
        10.0,
        RollingControl::Load(LOAD),
    )
}

fn options() -> BemRollingOptions {
    BemRollingOptions {
        tolerance: 1e-9,
        par: Par::Seq,
        ..BemRollingOptions::default()
    }
}

/// Hertz's approach of a sphere of radius [`R`] on the half-space under
/// [`LOAD`]: `δ = (9 W² / (16 R E*²))^(1/3)`.
fn hertz_approach() -> f64 {
    let e_star = material().reduced_modulus();
    (9.0 * LOAD * LOAD / (16.0 * R * e_star * e_star)).cbrt()
}

#[test]
fn bilinear_refinement_keeps_the_nodes_and_reproduces_a_bilinear_surface() {
    let grid = Grid::new(5, 4, 1e-3, 2e-3)
        .and_then(|g| g.with_origin([1e-3, -3e-3]))
        .expect("valid grid");
    let surface = |x: f64, y: f64| 0.3 + 2.0 * x - 0.7 * y + 40.0 * x * y;
    let values = (0..grid.len())
        .map(|k| surface(grid.x(k % 5), grid.y(k / 5)))
        .collect();
    let field = Field::new(grid.clone(), values).expect("valid field");
    let fine = refine_bilinear(&field, 3).expect("refined");
    let g = fine.grid();
    assert_eq!((g.nx(), g.ny()), (13, 10));
    assert_eq!(g.origin(), grid.origin());
    for j in 0..g.ny() {
        for i in 0..g.nx() {
            let v = fine.values()[g.index(i, j)];
            assert!(
                (v - surface(g.x(i), g.y(j))).abs() < 1e-12,
                "({i}, {j}): {v}"
            );
            if i % 3 == 0 && j % 3 == 0 {
                assert_eq!(v, field.values()[grid.index(i / 3, j / 3)]);
            }
        }
    }
    assert!(refine_bilinear(&field, 0).is_err());
}

#[test]
fn refining_the_grid_brings_the_bem_closer_to_hertz_on_a_sphere() {
    let hertz = hertz_approach();
    let error = |r: &BemRollingResult| {
        assert_eq!(r.failed(), 0);
        r.approach()
            .iter()
            .map(|d| (d - hertz).abs() / hertz)
            .fold(0.0, f64::max)
    };
    // The same sphere sampled at 0.4 mm (contact ~5 cells across) and at
    // 0.2 mm: the synthesised refinement.
    let coarse = sphere_map(0.4e-3);
    let fine = sphere_map(0.2e-3);
    let run = grid_convergence(
        &coarse,
        &fine,
        Refinement::Synthesised,
        material(),
        &config(),
        &options(),
    )
    .expect("both runs");
    let (coarse_error, fine_error) = (error(&run.coarse), error(&run.fine));
    // Measured: 1.24 % at 0.4 mm, 0.08 % at 0.2 mm.
    assert!(
        fine_error < 0.5 * coarse_error,
        "{fine_error} vs {coarse_error}"
    );
    assert!(fine_error < 0.005, "{fine_error}");
    // The reported change is the runs' difference.
    let direct = run
        .coarse
        .approach()
        .iter()
        .zip(run.fine.approach())
        .map(|(c, f)| (f - c).abs())
        .fold(0.0, f64::max)
        / hertz;
    assert!(
        (run.approach_change() - direct).abs() < 0.05 * direct,
        "{direct}"
    );
    // The bilinear refinement of the coarse sphere: the BEM's
    // discretisation refined on the coarse grid's chordal surface.
    let bilinear = refine_bilinear(&coarse, 2).expect("refined");
    let resampled = roll_bem(&bilinear, material(), &config(), &options()).expect("BEM run");
    // Its facets lie below the sphere between the coarse nodes: measured
    // 1.75 % from Hertz, no nearer than the coarse run; what it isolates is
    // the BEM's own discretisation, not the texture's sampling.
    let resampled_error = error(&resampled);
    assert!(resampled_error < 0.03, "{resampled_error}");
    // One sphere, one load: every step carries it whole.
    for s in run.fine.steps.iter().chain(&resampled.steps) {
        assert!((s.total_force - LOAD).abs() < 1e-9, "{}", s.total_force);
    }
}

/// Regression (adversarial run, 2026-11-30): `rolling-bem --refine 100` on
/// a 200 × 120 map asked for 2.4e8 points and grew to 5 GB before anything
/// refused it. The factor is refused before the fine map is made, naming
/// the grid it would make; a factor within the limit is made.
#[test]
fn a_refinement_past_the_largest_map_is_refused_before_allocating() {
    let text = "name = \"r\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [texture]\nmin_prominence = \"0.1 mm\"\nmin_area = \"1 mm2\"\n\
                [texture.synth]\nkind = \"aggregate\"\ngrading = \"6/10\"\nnx = 200\nny = 120\n\
                spacing = \"0.25 mm\"\nseed = 3\n";
    let scenario = crate::scenario::Scenario::parse(text, "r").expect("scenario");
    let texture = scenario.texture.as_ref().expect("a texture");
    let e = super::refine::refined_texture_fields(texture, std::path::Path::new("."), 100)
        .expect_err("too fine")
        .to_string();
    assert!(
        e.contains("refinement factor 100 makes the 200 × 120 map 20000 × 12000 points"),
        "{e}"
    );
    let (coarse, fine, _) =
        super::refine::refined_texture_fields(texture, std::path::Path::new("."), 2)
            .expect("twice as fine");
    assert_eq!(fine.grid().nx(), 2 * coarse.grid().nx());
}
