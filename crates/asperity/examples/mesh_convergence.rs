//! Convergence of sphere and cone meshes to the closed forms, and the cost of
//! one cap evaluation.
//!
//! `cargo run --release -p tyreroad-asperity --example mesh_convergence`

use std::f64::consts::PI;
use std::hint::black_box;
use std::time::Instant;

use tyreroad_asperity::{
    CapGeometry, Cone, GeometryError, MeshAsperity, MeshBuffers, Sphere, TabulatedCap,
};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Mean time of one `cap` call over `depths`, in ns.
fn time_caps(g: &impl CapGeometry, depths: &[f64]) -> f64 {
    let reps = 20;
    let start = Instant::now();
    let mut sink = 0.0;
    for _ in 0..reps {
        for &d in depths {
            sink += black_box(g).cap(black_box(d)).volume;
        }
    }
    black_box(sink);
    start.elapsed().as_secs_f64() * 1e9 / (reps * depths.len()) as f64
}

fn main() -> Result<(), GeometryError> {
    let r = 1.0;
    let sphere = Sphere::new(r)?;
    let ratios = [0.01, 0.1, 0.5];
    println!("Icosphere of radius R against the exact sphere: relative errors");
    println!("| n | triangles | edge/R | δ/R | Ω | Σ | Γ |");
    println!("|---|---|---|---|---|---|---|");
    for n in 1..=6 {
        let b = MeshBuffers::icosphere(r, n)?;
        let mesh = MeshAsperity::from_buffers(&b)?;
        let edge = 1.1071487177940904 / f64::from(1u32 << n); // icosahedron edge angle / 2ⁿ
        for &q in &ratios {
            let (m, s) = (mesh.cap(q * r), sphere.cap(q * r));
            println!(
                "| {n} | {} | {:.3} | {q} | {:.2e} | {:.2e} | {:.2e} |",
                mesh.num_triangles(),
                edge,
                rel(m.volume, s.volume),
                rel(m.base_area, s.base_area),
                rel(m.perimeter, s.perimeter)
            );
        }
    }

    let alpha = 1.2;
    let cone = Cone::new(alpha)?;
    println!("\nCone mesh (half-angle {alpha} rad) against the exact cone: relative errors");
    println!("(independent of δ: the section is the regular n-gon inscribed in the circle)");
    println!("| segments | Ω | Σ | Γ | exact n-gon Σ error |");
    println!("|---|---|---|---|---|");
    for seg in [8u32, 16, 32, 64, 128, 256] {
        let mesh = MeshAsperity::from_buffers(&MeshBuffers::cone(alpha, 1.0, seg)?)?;
        let d = 0.3;
        let (m, c) = (mesh.cap(d), cone.cap(d));
        let nf = f64::from(seg);
        let rr = d * alpha.tan();
        let polygon = 0.5 * nf * rr * rr * (2.0 * PI / nf).sin();
        println!(
            "| {seg} | {:.2e} | {:.2e} | {:.2e} | {:.1e} |",
            rel(m.volume, c.volume),
            rel(m.base_area, c.base_area),
            rel(m.perimeter, c.perimeter),
            rel(m.base_area, polygon)
        );
    }

    println!("\nCost of one cap evaluation (release build recommended)");
    println!("| asperity | triangles | cap() ns/call |");
    println!("|---|---|---|");
    let depths: Vec<f64> = (1..=200).map(|k| 0.5 * r * f64::from(k) / 200.0).collect();
    let small: Vec<f64> = (1..=200).map(|k| 0.02 * r * f64::from(k) / 200.0).collect();
    for n in [3u32, 5] {
        let mesh = MeshAsperity::from_buffers(&MeshBuffers::icosphere(r, n)?)?;
        println!(
            "| icosphere n={n}, δ ≤ 0.5R | {} | {:.0} |",
            mesh.num_triangles(),
            time_caps(&mesh, &depths)
        );
        println!(
            "| icosphere n={n}, δ ≤ 0.02R | {} | {:.0} |",
            mesh.num_triangles(),
            time_caps(&mesh, &small)
        );
    }
    let bumpy = MeshBuffers::height_field_rect([-1.0, 1.0], [-1.0, 1.0], 64, 64, -0.1, |x, y| {
        1.0 - 0.5 * (x * x + y * y) + 0.05 * (7.0 * x).sin() * (5.0 * y).cos()
    })?;
    let bumpy = MeshAsperity::from_buffers(&bumpy)?;
    let bd: Vec<f64> = (1..=200).map(|k| 0.3 * f64::from(k) / 200.0).collect();
    println!(
        "| height field 64×64, δ ≤ 0.3 | {} | {:.0} |",
        bumpy.num_triangles(),
        time_caps(&bumpy, &bd)
    );
    let table = TabulatedCap::from_geometry(&sphere, r, 200)?;
    println!(
        "| TabulatedCap, 200 nodes | — | {:.0} |",
        time_caps(&table, &depths)
    );
    let start = Instant::now();
    let mesh = MeshAsperity::from_buffers(&MeshBuffers::icosphere(r, 5)?)?;
    let built = start.elapsed().as_secs_f64() * 1e3;
    let start = Instant::now();
    let t = TabulatedCap::from_geometry(&mesh, 0.9 * r, 200)?;
    let tab = start.elapsed().as_secs_f64() * 1e3;
    println!(
        "\nicosphere n=5: build {built:.1} ms, tabulate 200 nodes {tab:.1} ms (volume mismatch {:.1e})",
        t.volume_mismatch()
    );
    Ok(())
}
