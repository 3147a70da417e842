//! Writes the small sample files of `fixtures/texture/` and prints the
//! figures quoted in `docs/texture.md`:
//! `cargo run --release -p tyreroad-texture --example texture_figures [OUT_DIR]`.

use std::path::PathBuf;

use tyreroad_texture::io::{text::write_ascii_grid, x3p::X3pDataType, x3p::write_x3p};
use tyreroad_texture::{
    Aggregate, ChipShape, HeightMap, SelfAffine, aggregate, mean_profile_depth, self_affine,
    third_octave_spectrum,
};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let out = std::env::args()
        .nth(1)
        .map(PathBuf::from)
        .unwrap_or_else(|| PathBuf::from("fixtures/texture"));
    std::fs::create_dir_all(&out)?;
    // Three 5 mm balls on a plane, 0.1 mm grid, 12 × 8 mm.
    let r = 5e-3;
    let balls = [
        (3.0e-3, 3.5e-3, 2.0e-3),
        (8.6e-3, 4.2e-3, 1.5e-3),
        (5.5e-3, 6.9e-3, 0.8e-3),
    ];
    let spheres = HeightMap::from_fn(120, 80, 1e-4, 1e-4, |x, y| {
        balls
            .iter()
            .map(|&(cx, cy, top)| {
                let d2 = (x - cx).powi(2) + (y - cy).powi(2);
                if d2 < r * r {
                    (r * r - d2).sqrt() - r + top
                } else {
                    0.0
                }
            })
            .fold(0.0, f64::max)
    })?;
    write_x3p(&spheres, out.join("spheres.x3p"), X3pDataType::F32)?;
    // A cosine profile, amplitude 0.5 mm, wavelength 12.5 mm, 0.5 mm steps.
    let dx = 0.5e-3;
    let sine = HeightMap::from_fn(400, 2, dx, 1e-3, |x, _| {
        0.5e-3 * (std::f64::consts::TAU * (x + 0.5 * dx) / 12.5e-3).cos()
    })?;
    write_ascii_grid(&sine, out.join("sine.asc"))?;
    let m = mean_profile_depth(&sine, None)?;
    println!(
        "sine.asc: MPD = {:.6} mm over {} segments",
        m.mpd * 1e3,
        m.segments
    );

    // Figures for the docs.
    let sa = self_affine(&SelfAffine {
        nx: 1024,
        ny: 512,
        dx: 0.25e-3,
        dy: 0.25e-3,
        rms: 0.5e-3,
        hurst: 0.8,
        lambda_long: 50e-3,
        lambda_short: 1e-3,
        seed: 1,
    })?;
    report("self-affine Sq 0.5 mm H 0.8 λ 1–50 mm", &sa)?;
    for (name, grading) in [
        ("4/6", Aggregate::grading_4_6()),
        ("6/10", Aggregate::grading_6_10()),
    ] {
        for shape in [
            ChipShape::Ellipsoid,
            ChipShape::Polyhedron {
                cuts: 6,
                rounding: 0.1,
            },
        ] {
            let mut p = Aggregate::new(1024, 256, 0.25e-3, 0.25e-3, grading.clone(), 1);
            p.shape = shape;
            let t = std::time::Instant::now();
            let map = aggregate(&p)?;
            let el = t.elapsed();
            report(&format!("aggregate {name} {shape:?} ({el:.2?})"), &map)?;
        }
    }
    Ok(())
}

fn report(name: &str, map: &HeightMap) -> Result<(), Box<dyn std::error::Error>> {
    let mpd = mean_profile_depth(map, None)?;
    let bands = third_octave_spectrum(map)?;
    let levels: Vec<String> = bands
        .iter()
        .filter(|b| [0, 5, 10, 15, 20].contains(&b.index))
        .map(|b| format!("{:.3} mm: {:.1} dB", b.centre * 1e3, b.level_db))
        .collect();
    println!(
        "{name}: Sq = {:.3} mm, MPD = {:.3} mm; {}",
        map.rms().unwrap_or(0.0) * 1e3,
        mpd.mpd * 1e3,
        levels.join(", ")
    );
    Ok(())
}
