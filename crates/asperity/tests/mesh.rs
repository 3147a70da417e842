//! Caps of triangle meshes: exactness, convergence, topology, validation.
#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;

use proptest::prelude::*;
use tyreroad_asperity::{
    CapGeometry, CapMeasures, Cone, GeometryError, MeshAsperity, MeshBuffers, Sphere,
};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

fn mesh(b: &MeshBuffers) -> MeshAsperity {
    MeshAsperity::from_buffers(b).unwrap()
}

/// Area and perimeter of the regular `n`-gon of circumradius `r`.
fn polygon(n: u32, r: f64) -> (f64, f64) {
    let n = f64::from(n);
    (
        0.5 * n * r * r * (2.0 * PI / n).sin(),
        2.0 * n * r * (PI / n).sin(),
    )
}

#[test]
fn cone_mesh_sections_are_exact_polygons() {
    let (alpha, height, seg) = (1.1, 2e-3, 48);
    let m = mesh(&MeshBuffers::cone(alpha, height, seg).unwrap());
    assert_eq!(m.max_depth(), height);
    assert!(
        rel(
            m.volume(),
            polygon(seg, height * alpha.tan()).0 * height / 3.0
        ) < 1e-13
    );
    for d in [1e-9, 1e-6, 3e-4, 1.5e-3, height] {
        let c = m.cap(d);
        let (area, perimeter) = polygon(seg, d * alpha.tan());
        assert!(rel(c.base_area, area) < 1e-12, "Σ at {d}");
        assert!(rel(c.perimeter, perimeter) < 1e-12, "Γ at {d}");
        assert!(rel(c.volume, area * d / 3.0) < 1e-12, "Ω at {d}");
        // Σ ∝ δ², Γ ∝ δ: exact derivatives.
        assert!(rel(c.d_base_area, 2.0 * area / d) < 1e-12);
        assert!(rel(c.d2_base_area, 2.0 * area / (d * d)) < 1e-12);
        assert!(rel(c.d_perimeter, perimeter / d) < 1e-12);
        assert_eq!(c.d2_perimeter, 0.0);
    }
}

#[test]
fn cone_mesh_converges_to_the_cone() {
    // Inscribed n-gon: relative error in Σ = 1 − sin(2π/n)/(2π/n) ≈ (2π/n)²/6.
    let cone = Cone::new(1.2).unwrap();
    for seg in [64, 256] {
        let m = mesh(&MeshBuffers::cone(1.2, 1.0, seg).unwrap());
        let x = 2.0 * PI / f64::from(seg);
        let tol = 1.01 * x * x / 6.0;
        for d in [0.01, 0.3, 0.9] {
            let (a, b) = (m.cap(d), cone.cap(d));
            assert!(rel(a.volume, b.volume) < tol);
            assert!(rel(a.base_area, b.base_area) < tol);
            assert!(rel(a.perimeter, b.perimeter) < tol / 4.0 * 1.01);
        }
    }
}

#[test]
fn icosphere_converges_to_the_sphere() {
    let r = 5e-3;
    let sphere = Sphere::new(r).unwrap();
    // Errors measured (docs/asperity.md); tolerances 1.2× the n = 5 values.
    let m5 = mesh(&MeshBuffers::icosphere(r, 5).unwrap());
    for (q, tol) in [
        (0.1, [4.3e-3, 2.2e-3, 9.1e-4]),
        (0.5, [1.04e-3, 5.5e-4, 2.3e-4]),
    ] {
        let (a, b) = (m5.cap(q * r), sphere.cap(q * r));
        assert!(rel(a.volume, b.volume) < tol[0], "Ω at δ/R = {q}");
        assert!(rel(a.base_area, b.base_area) < tol[1], "Σ at δ/R = {q}");
        assert!(rel(a.perimeter, b.perimeter) < tol[2], "Γ at δ/R = {q}");
        assert!(rel(a.d_base_area, b.d_base_area) < 2e-2, "Σ' at δ/R = {q}");
    }
    // Second order: refining once divides the error by about 4.
    let m4 = mesh(&MeshBuffers::icosphere(r, 4).unwrap());
    let e4 = rel(m4.cap(0.3 * r).volume, sphere.cap(0.3 * r).volume);
    let e5 = rel(m5.cap(0.3 * r).volume, sphere.cap(0.3 * r).volume);
    assert!(e4 / e5 > 3.5 && e4 / e5 < 4.5, "ratio {}", e4 / e5);
    // Inscribed: everything smaller than the sphere's.
    assert!(m5.volume() < 4.0 / 3.0 * PI * r.powi(3));
    // The first overhang is met near the equator: default max_depth ≈ R.
    assert!((m5.max_depth() - r).abs() < 0.05 * r, "{}", m5.max_depth());
    assert_eq!(m5.height(), 2.0 * r);
    assert_eq!(m5.summit(), [0.0, 0.0, r]);
}

#[test]
fn mesh_onset_is_a_pyramid() {
    // Above the first ring Ω ∝ δ³, Σ ∝ δ², Γ ∝ δ exactly.
    let m = mesh(&MeshBuffers::icosphere(1.0, 3).unwrap());
    let d1 = m.first_ring_depth();
    assert!(d1 > 0.0 && d1 < 0.02, "{d1}");
    let (a, b) = (m.cap(0.2 * d1), m.cap(0.8 * d1));
    assert!(rel(b.volume / a.volume, 64.0) < 1e-10);
    assert!(rel(b.base_area / a.base_area, 16.0) < 1e-10);
    assert!(rel(b.perimeter / a.perimeter, 4.0) < 1e-10);
}

/// A crater: floor at `zf` in the middle, rim at `zt` on ring `rr`, flank down
/// to `z = 0` at `rho`; linear in `r` between rings, so sections are exact
/// regular polygons.
fn crater(seg: u32) -> (MeshBuffers, [f64; 4]) {
    let (rho, rr, zf, zt) = (4.0, 2.0, 0.5, 1.0);
    let rings = 8; // rim on ring 4
    let f = move |x: f64, y: f64| {
        let r = x.hypot(y);
        if r <= rr {
            zf + (zt - zf) * r / rr
        } else {
            zt * (rho - r) / (rho - rr)
        }
    };
    let b = MeshBuffers::height_field_disc(rho, rings, seg, -0.5, f).unwrap();
    (b, [rho, rr, zf, zt])
}

#[test]
fn crater_gives_an_annulus() {
    let seg = 256;
    let (b, [rho, rr, zf, zt]) = crater(seg);
    let m = mesh(&b);
    // Cut at z = 0.8: between the floor (0.5) and the rim (1.0).
    let h = 0.8;
    let delta = zt - h;
    // Radii of the circles through the polygons' vertices.
    let ri = rr * (h - zf) / (zt - zf);
    let ro = rho - (rho - rr) * h / zt;
    let (ai, pi_) = polygon(seg, ri);
    let (ao, po) = polygon(seg, ro);
    let s = m.section(delta);
    assert!(rel(s.measures.base_area, ao - ai) < 1e-12);
    assert!(rel(s.measures.perimeter, po + pi_) < 1e-12);
    assert_eq!(s.loops, 2);
    assert_eq!(s.patches.len(), 1, "one patch bounded by two loops");
    assert_eq!(s.patches[0].loops, 2);
    assert!(rel(s.patches[0].base_area, ao - ai) < 1e-12);
    assert_eq!(s.measures, m.cap(delta));
    // And the circles, within the polygon error (2π/n)²/6 = 1.0e-4.
    let tol = 1.1e-4;
    assert!(rel(s.measures.base_area, PI * (ro * ro - ri * ri)) < tol);
    assert!(rel(s.measures.perimeter, 2.0 * PI * (ro + ri)) < tol / 4.0);
    // Below the floor: a disc.
    let s = m.section(zt - 0.3);
    let ro = rho - (rho - rr) * 0.3 / zt;
    assert_eq!((s.loops, s.patches.len()), (1, 1));
    assert!(rel(s.measures.base_area, polygon(seg, ro).0) < 1e-12);
    assert!(rel(s.measures.perimeter, polygon(seg, ro).1) < 1e-12);
    // The rim is a flat ring of vertices: at tiny δ a thin annulus already.
    let s = m.section(1e-9);
    assert_eq!((s.loops, s.patches.len()), (2, 1));
    assert!(m.is_valid_for_tests());
}

trait Valid {
    fn is_valid_for_tests(&self) -> bool;
}
impl Valid for MeshAsperity {
    fn is_valid_for_tests(&self) -> bool {
        self.trimesh().topology().is_some() && self.trimesh().pseudo_normals().is_some()
    }
}

/// Two "diamond" pyramids `H − (|x − c| + |y|)/s` with apexes on the grid, and
/// their crease on a grid line: exactly piecewise linear on the grid.
fn diamonds() -> (MeshAsperity, f64, f64) {
    let (hgt, s, c) = (1.0, 1.0, 1.0); // apexes at x = ±1, saddle at x = 0
    let f = move |x: f64, y: f64| {
        let a = hgt - ((x - c).abs() + y.abs()) / s;
        let b = hgt - ((x + c).abs() + y.abs()) / s;
        a.max(b)
    };
    let b = MeshBuffers::height_field_rect([-3.0, 3.0], [-2.0, 2.0], 24, 16, -4.0, f).unwrap();
    (mesh(&b), s, 2.0 * c)
}

#[test]
fn two_bumps_give_two_patches_then_merge() {
    let (m, s, dist) = diamonds();
    // Above the saddle (depth 1): two diamonds of L1 radius r = sδ.
    let d = 0.6;
    let r = s * d;
    let sec = m.section(d);
    assert_eq!(sec.loops, 2);
    assert_eq!(sec.patches.len(), 2);
    for p in &sec.patches {
        assert!(rel(p.base_area, 2.0 * r * r) < 1e-12);
        assert!(rel(p.perimeter, 4.0 * 2f64.sqrt() * r) < 1e-12);
        assert!(rel(p.volume, 2.0 * r * r * d / 3.0) < 1e-12);
        assert_eq!(p.loops, 1);
    }
    assert!(rel(sec.measures.base_area, 4.0 * r * r) < 1e-12);
    assert!(rel(sec.measures.perimeter, 8.0 * 2f64.sqrt() * r) < 1e-12);
    // Below the saddle: one patch, the union of two overlapping diamonds.
    let d = 1.4;
    let r = s * d;
    let sec = m.section(d);
    assert_eq!((sec.loops, sec.patches.len()), (1, 1));
    let overlap = r - dist / 2.0;
    let area = 4.0 * r * r - 2.0 * overlap * overlap;
    let perimeter = 4.0 * 2f64.sqrt() * r + 2.0 * 2f64.sqrt() * dist;
    assert!(rel(sec.measures.base_area, area) < 1e-12);
    assert!(rel(sec.measures.perimeter, perimeter) < 1e-12);
    // Volume below the saddle: Ω(1) + ∫₁^δ Σ.
    let at1 = 2.0 * 2.0 / 3.0; // two pyramids of base 2, height 1
    let vol = at1 + (4.0 * (d.powi(3) - 1.0) / 3.0 - 2.0 * (d - 1.0).powi(3) / 3.0);
    assert!(rel(sec.measures.volume, vol) < 1e-12);
}

#[test]
fn depth_outside_the_mesh() {
    let (m, _, _) = diamonds();
    for d in [0.0, -1.0, f64::NAN, f64::NEG_INFINITY] {
        assert_eq!(m.cap(d), CapMeasures::EMPTY);
        assert_eq!(m.section(d).patches.len(), 0);
    }
    // A terrain: max_depth is the whole height (top 1, bottom −4).
    assert_eq!(m.max_depth(), 5.0);
    let at = m.cap(5.0);
    // At the bottom the section is the whole rectangle.
    assert!(rel(at.base_area, 24.0) < 1e-12);
    assert!(rel(at.perimeter, 20.0) < 1e-12);
    assert!(rel(at.volume, m.volume()) < 1e-12);
    // Beyond: vertical walls.
    let beyond = m.cap(6.0);
    assert_eq!(beyond.base_area, at.base_area);
    assert_eq!(beyond.perimeter, at.perimeter);
    assert!(rel(beyond.volume, at.volume + at.base_area) < 1e-12);
    assert_eq!((beyond.d_base_area, beyond.d_perimeter), (0.0, 0.0));
    assert_eq!(m.cap(f64::INFINITY).base_area, at.base_area);
    // A sphere mesh continued below max_depth ≈ R, or below a chosen depth.
    let ball = mesh(&MeshBuffers::icosphere(1.0, 3).unwrap());
    // Past it, Σ runs out from its slope there (at most a tenth of the depth
    // long) and stays put.
    let c = ball.cap(3.0);
    let end = ball.cap(ball.max_depth());
    let run_out = 0.5 * end.d_base_area * 0.1 * ball.max_depth();
    assert!(c.base_area > 0.9 * PI && c.base_area >= end.base_area);
    assert!(c.base_area <= end.base_area + run_out + 1e-12);
    assert_eq!((c.d_base_area, c.d_perimeter), (0.0, 0.0));
    let ball = ball.with_max_depth(2.0).unwrap();
    assert!(
        ball.cap(2.0).base_area.abs() < 1e-12,
        "closed: no section at the bottom"
    );
    assert!(rel(ball.cap(3.0).volume, ball.volume()) < 1e-12);
    assert!(
        mesh(&MeshBuffers::icosphere(1.0, 1).unwrap())
            .with_max_depth(2.1)
            .is_err()
    );
}

fn invalid(v: &[[f64; 3]], i: &[[u32; 3]]) -> String {
    match MeshAsperity::new(v, i) {
        Err(GeometryError::InvalidMesh(m)) => m,
        other => panic!("expected InvalidMesh, got {other:?}"),
    }
}

#[test]
fn bad_meshes_are_refused() {
    let b = MeshBuffers::icosphere(1.0, 1).unwrap();
    let (v, i) = (&b.vertices, &b.indices);
    assert!(MeshAsperity::new(v, i).is_ok());
    // Open: a triangle removed.
    let msg = invalid(v, &i[1..]);
    assert!(msg.contains("not closed"), "{msg}");
    // One triangle flipped.
    let mut f = i.clone();
    f[7].swap(1, 2);
    let msg = invalid(v, &f);
    assert!(msg.contains("inconsistently oriented"), "{msg}");
    // All flipped: inwards.
    let all: Vec<[u32; 3]> = i.iter().map(|t| [t[0], t[2], t[1]]).collect();
    let msg = invalid(v, &all);
    assert!(msg.contains("oriented inwards"), "{msg}");
    // Repeated vertex.
    let mut d = i.clone();
    d[3][1] = d[3][0];
    let msg = invalid(v, &d);
    assert!(msg.contains("degenerate"), "{msg}");
    // Zero-area triangle: a tetrahedron with one vertex moved onto an edge of
    // a face makes that face collinear.
    let tv = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [2.0, 0.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let ti = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
    let msg = invalid(&tv, &ti);
    assert!(msg.contains("zero area"), "{msg}");
    // Non-finite coordinates, indices out of range, too few triangles.
    let mut nan = v.clone();
    nan[5][2] = f64::NAN;
    assert!(invalid(&nan, i).contains("non-finite"));
    let mut inf = v.clone();
    inf[0][0] = f64::INFINITY;
    assert!(invalid(&inf, i).contains("non-finite"));
    let mut oob = i.clone();
    oob[0][0] = 10_000;
    assert!(invalid(v, &oob).contains("only"));
    assert!(invalid(v, &i[..3]).contains("at least 4"));
    assert!(invalid(&[], &[]).contains("at least 4"));
    // Non-manifold: the same closed tetrahedron twice on the same vertices.
    let tet_v = [
        [0.0, 0.0, 0.0],
        [1.0, 0.0, 0.0],
        [0.0, 1.0, 0.0],
        [0.0, 0.0, 1.0],
    ];
    let tet_i = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
    assert!(MeshAsperity::new(&tet_v, &tet_i).is_ok());
    let twice: Vec<[u32; 3]> = tet_i.iter().chain(tet_i.iter()).copied().collect();
    assert!(invalid(&tet_v, &twice).contains("non-manifold"));
    // Huge coordinates overflow the measures.
    let big: Vec<[f64; 3]> = v.iter().map(|p| p.map(|c| c * 1e300)).collect();
    assert!(MeshAsperity::new(&big, i).is_err());
    // Height functions not above the bottom.
    assert!(MeshBuffers::height_field_disc(1.0, 2, 8, 0.0, |_, _| 0.0).is_err());
    assert!(
        MeshBuffers::height_field_rect([0.0, 1.0], [0.0, 1.0], 2, 2, 0.0, |_, _| f64::NAN).is_err()
    );
    assert!(MeshBuffers::cone(2.0, 1.0, 8).is_err());
    assert!(MeshBuffers::cone(1.0, 1.0, 2).is_err());
    assert!(MeshBuffers::icosphere(-1.0, 2).is_err());
}

#[test]
fn other_constructors_and_parry() {
    use nalgebra::Point3;
    let b = MeshBuffers::cone(0.7, 1.0, 12).unwrap();
    let m = mesh(&b);
    let pts: Vec<Point3<f64>> = b.vertices.iter().map(|p| Point3::from(*p)).collect();
    let m2 = MeshAsperity::from_points(&pts, &b.indices).unwrap();
    let m3 = MeshAsperity::from_trimesh(m.trimesh()).unwrap();
    assert_eq!(m.cap(0.4), m2.cap(0.4));
    assert_eq!(m.cap(0.4), m3.cap(0.4));
    assert_eq!(m.trimesh().num_triangles(), 24);
    // A triangle soup (STL-like) welds back into the same mesh.
    let mut soup = MeshBuffers::default();
    for t in &b.indices {
        let n = soup.vertices.len() as u32;
        soup.vertices.extend(t.map(|i| b.vertices[i as usize]));
        soup.indices.push([n, n + 1, n + 2]);
    }
    assert!(MeshAsperity::from_buffers(&soup).is_err());
    soup.merge_duplicate_vertices();
    assert_eq!(soup.vertices.len(), b.vertices.len());
    assert!(rel(mesh(&soup).cap(0.4).volume, m.cap(0.4).volume) < 1e-14);
    assert!(format!("{m:?}").contains("MeshAsperity"));
}

/// A random height field over a small grid (random heights in [0.1, 1]).
fn random_field() -> impl Strategy<Value = (u32, u32, Vec<f64>)> {
    (2u32..6, 2u32..6).prop_flat_map(|(nx, ny)| {
        let n = ((nx + 1) * (ny + 1)) as usize;
        (Just(nx), Just(ny), prop::collection::vec(0.1f64..1.0, n))
    })
}

fn field_mesh(nx: u32, ny: u32, z: &[f64]) -> MeshAsperity {
    let f = |x: f64, y: f64| {
        let i = (x * f64::from(nx)).round() as u32;
        let j = (y * f64::from(ny)).round() as u32;
        z[(j * (nx + 1) + i) as usize]
    };
    mesh(&MeshBuffers::height_field_rect([0.0, 1.0], [0.0, 1.0], nx, ny, 0.0, f).unwrap())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(64))]

    #[test]
    fn caps_of_random_terrains_are_monotone((nx, ny, z) in random_field(),
                                            a in 0.0f64..1.1, b in 0.0f64..1.1) {
        let m = field_mesh(nx, ny, &z);
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        let (cl, ch) = (m.cap(lo), m.cap(hi));
        prop_assert!(ch.volume >= cl.volume);
        prop_assert!(ch.base_area >= cl.base_area - 1e-15);
        prop_assert!(cl.d_base_area >= -1e-12 && ch.d_base_area >= -1e-12);
        prop_assert!(ch.base_area <= 1.0 + 1e-12);
    }

    #[test]
    fn derivatives_of_random_terrains((nx, ny, z) in random_field(), d in 0.01f64..0.89) {
        let m = field_mesh(nx, ny, &z);
        let top = z.iter().fold(0.0f64, |a, &b| a.max(b));
        // Stay away from vertex heights, where Σ' and Γ' jump.
        let h = 1e-6;
        prop_assume!(z.iter().all(|&zv| ((top - zv) - d).abs() > 10.0 * h));
        let (lo, mid, hi) = (m.cap(d - h), m.cap(d), m.cap(d + h));
        let fd = |f: fn(&CapMeasures) -> f64| (f(&hi) - f(&lo)) / (2.0 * h);
        // Rounding: Ω sums many tetrahedra, so its differences carry
        // about 1e3 ε |Ω| of noise, divided by 2h.
        let rounding = 1e3 * f64::EPSILON * (1.0 + hi.volume.abs()) / h;
        prop_assert!(
            (fd(|c| c.volume) - mid.base_area).abs() < 1e-9 + rounding,
            "dΩ/dδ = Σ: {} vs {}",
            fd(|c| c.volume),
            mid.base_area
        );
        prop_assert!((fd(|c| c.base_area) - mid.d_base_area).abs() < 1e-7 * (1.0 + mid.d_base_area.abs()));
        prop_assert!((fd(|c| c.perimeter) - mid.d_perimeter).abs() < 1e-7 * (1.0 + mid.d_perimeter.abs()));
        prop_assert!((fd(|c| c.d_base_area) - mid.d2_base_area).abs() < 1e-6 * (1.0 + mid.d2_base_area.abs()));
        // Across vertex heights too: Ω is C¹ and Σ continuous. Σ is
        // quadratic between vertex heights, so composite Simpson is exact
        // but for the kinks of Σ: one inside a panel of half-width w adds at
        // most 4 w² |jump of Σ'|, bounded by the change of Σ' across the
        // panel (a panel is narrow enough to hold one kink in most cases).
        let (k, panels) = (2e-3, 32);
        let w = k / f64::from(panels);
        let (mut simpson, mut kinks) = (0.0, 0.0);
        for p in 0..panels {
            let a = d - k + 2.0 * w * f64::from(p);
            let (ca, cm, cb) = (m.cap(a), m.cap(a + w), m.cap(a + 2.0 * w));
            simpson += w / 3.0 * (ca.base_area + 4.0 * cm.base_area + cb.base_area);
            kinks += 4.0 * w * w * (cb.d_base_area - ca.d_base_area).abs();
        }
        let (l2, h2) = (m.cap(d - k), m.cap(d + k));
        prop_assert!((h2.volume - l2.volume - simpson).abs() < 1e-9 + kinks);
    }

    #[test]
    fn sections_of_random_terrains_add_up((nx, ny, z) in random_field(), d in 0.0f64..1.0) {
        let m = field_mesh(nx, ny, &z);
        let s = m.section(d);
        let (v, a, p): (f64, f64, f64) = s.patches.iter().fold((0.0, 0.0, 0.0), |acc, q| {
            (acc.0 + q.volume, acc.1 + q.base_area, acc.2 + q.perimeter)
        });
        prop_assert!((v - s.measures.volume).abs() < 1e-12);
        prop_assert!((a - s.measures.base_area).abs() < 1e-12);
        prop_assert!((p - s.measures.perimeter).abs() < 1e-12);
        prop_assert_eq!(s.patches.iter().map(|q| q.loops).sum::<usize>(), s.loops);
        prop_assert!(s.patches.iter().all(|q| q.base_area > 0.0));
        if d > 0.0 {
            prop_assert!(!s.patches.is_empty());
        }
    }
}

#[test]
fn asperities_can_be_shared_between_threads() {
    fn check<T: Send + Sync + Clone>() {}
    check::<MeshAsperity>();
    check::<tyreroad_asperity::TabulatedCap>();
}

/// The unit cube `[0, 1]³`: a flat top and vertical walls.
fn cube() -> MeshAsperity {
    let v: Vec<[f64; 3]> = (0..8)
        .map(|k| [f64::from(k & 1), f64::from((k >> 1) & 1), f64::from(k >> 2)])
        .collect();
    let quads = [
        [0, 2, 3, 1], // bottom, facing down
        [4, 5, 7, 6], // top
        [0, 1, 5, 4], // y = 0
        [2, 6, 7, 3], // y = 1
        [0, 4, 6, 2], // x = 0
        [1, 3, 7, 5], // x = 1
    ];
    let i: Vec<[u32; 3]> = quads
        .iter()
        .flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]])
        .collect();
    MeshAsperity::new(&v, &i).unwrap()
}

/// The distinct depths of the mesh's vertices below its summit, in
/// `(0, max_depth]`; depths within rounding (1e-9 of the deepest) are one.
fn vertex_depths(m: &MeshAsperity) -> Vec<f64> {
    let top = m.summit()[2];
    let mut d: Vec<f64> = m
        .trimesh()
        .vertices()
        .iter()
        .map(|p| top - p.z)
        .filter(|&d| d > 0.0 && d <= m.max_depth())
        .collect();
    d.sort_by(f64::total_cmp);
    let close = 1e-9 * m.max_depth();
    d.dedup_by(|b, a| *b - *a <= close);
    d
}

/// Regression: at a depth where the plane passes exactly through a
/// triangle's lowest vertex, that triangle's cut segment has just shrunk to
/// nothing and added 0 to `Γ'`, so a cube's `Γ'` at its base came out as 4
/// instead of 0 (and a pyramid's as more than its own).
#[test]
fn slopes_at_vertex_heights_are_the_left_derivatives() {
    let meshes = [
        ("cube", cube()),
        (
            "tetrahedron",
            mesh(&MeshBuffers::cone(0.9, 1.0, 3).unwrap()),
        ),
        (
            "48-flank cone",
            mesh(&MeshBuffers::cone(1.1, 2e-3, 48).unwrap()),
        ),
        ("icosphere", mesh(&MeshBuffers::icosphere(1.0, 2).unwrap())),
        ("crater", mesh(&crater(12).0)),
        ("two bumps", diamonds().0),
    ];
    for (name, m) in &meshes {
        let depths = vertex_depths(m);
        let mut previous = 0.0;
        for &d in &depths {
            // Γ is affine and Σ quadratic between two vertex heights.
            let eps = 1e-3 * (d - previous);
            previous = d;
            let (at, before) = (m.cap(d), m.cap(d - eps));
            let gamma_left = (at.perimeter - before.perimeter) / eps;
            let sigma_left = (at.base_area - before.base_area) / eps;
            let scale = at.perimeter / d;
            assert!(
                (at.d_perimeter - gamma_left).abs() <= 1e-6 * scale,
                "{name}, δ = {d}: Γ' {} against the left difference {gamma_left}",
                at.d_perimeter
            );
            assert!(
                (at.d_base_area - sigma_left).abs()
                    <= 0.5 * at.d2_base_area.abs() * eps + 1e-6 * at.base_area / d,
                "{name}, δ = {d}: Σ' {} against the left difference {sigma_left}",
                at.d_base_area
            );
        }
    }
    let base = cube().cap(1.0);
    assert_eq!((base.d_base_area, base.d_perimeter), (0.0, 0.0));
}

/// Regression: past `max_depth` the mesh went on as walls at once, so its
/// `Σ'` fell from `2Σ/δ` to 0 at a pyramid's base and the potential law's
/// force jumped twofold there.
#[test]
fn past_its_depth_a_mesh_runs_out_without_a_jump() {
    for m in [
        mesh(&MeshBuffers::cone(0.9, 1.0, 3).unwrap()),
        mesh(&MeshBuffers::cone(1.1, 2e-3, 48).unwrap()),
        mesh(&MeshBuffers::icosphere(1.0, 2).unwrap()),
    ] {
        let h = m.max_depth();
        let (at, past) = (m.cap(h), m.cap(h * (1.0 + 1e-9)));
        for (a, b) in [
            (at.volume, past.volume),
            (at.base_area, past.base_area),
            (at.perimeter, past.perimeter),
        ] {
            assert!(rel(b, a) < 1e-7, "{a} then {b}");
        }
        assert!((past.d_base_area - at.d_base_area).abs() <= 1e-6 * at.base_area / h);
        assert!((past.d_perimeter - at.d_perimeter).abs() <= 1e-6 * at.perimeter / h);
        // Inside the run-out Ω' = Σ, Σ and Γ keep rising (or Γ falls by at
        // most half); a tenth of the depth on, walls.
        let d = h * 1.05;
        let eps = 1e-6 * h;
        let mid = m.cap(d);
        let omega_slope = (m.cap(d + eps).volume - m.cap(d - eps).volume) / (2.0 * eps);
        assert!(rel(omega_slope, mid.base_area) < 1e-6);
        assert!(mid.base_area >= at.base_area && mid.perimeter >= 0.5 * at.perimeter);
        let walls = m.cap(1.2 * h);
        assert_eq!((walls.d_base_area, walls.d_perimeter), (0.0, 0.0));
        let run_out = 0.5 * at.d_base_area * 0.1 * h;
        assert!(walls.base_area <= at.base_area + run_out * (1.0 + 1e-12));
        assert_eq!(m.breakpoints()[0], h);
    }
}

/// The unit-scaled tetrahedron `(0,0,0), (s,0,0), (0,s,0), (0,0,s)` shifted
/// by `o`, its vertex ids starting at `first`.
fn tetrahedron(s: f64, o: f64, first: u32) -> (Vec<[f64; 3]>, Vec<[u32; 3]>) {
    let v = vec![[o, o, o], [o + s, o, o], [o, o + s, o], [o, o, o + s]];
    let i = [[0, 2, 1], [0, 1, 3], [1, 2, 3], [2, 0, 3]];
    (v, i.iter().map(|t| t.map(|k| k + first)).collect())
}

/// Regression (adversarial run, adv6 S9): a mesh of two closed shells was
/// accepted and both counted as solid: the unit tetrahedron twice (volume
/// 1/3 instead of 1/6), a tetrahedron nested in another (1.5 instead of
/// 8/6). A mesh of more than one shell is refused, saying how many.
#[test]
fn a_mesh_of_several_closed_shells_is_refused() {
    let (v, i) = tetrahedron(1.0, 0.0, 0);
    assert!(rel(MeshAsperity::new(&v, &i).unwrap().volume(), 1.0 / 6.0) < 1e-15);
    for (name, (v2, i2)) in [
        ("twice", tetrahedron(1.0, 0.0, 4)),
        ("nested", tetrahedron(1.0, 0.1, 4)),
        ("apart", tetrahedron(1.0, 5.0, 4)),
    ] {
        let (mut vv, mut ii) = tetrahedron(if name == "nested" { 2.0 } else { 1.0 }, 0.0, 0);
        vv.extend(v2);
        ii.extend(i2);
        let msg = invalid(&vv, &ii);
        assert!(msg.contains("2 separate closed shells"), "{name}: {msg}");
    }
    // Three shells are counted as three.
    let (mut vv, mut ii) = tetrahedron(1.0, 0.0, 0);
    for k in 1..3 {
        let (v2, i2) = tetrahedron(1.0, 3.0 * k as f64, 4 * k);
        vv.extend(v2);
        ii.extend(i2);
    }
    assert!(invalid(&vv, &ii).contains("3 separate closed shells"));
}

/// Regression (adversarial run, adv6 S10): `height_field_rect` over
/// `x ∈ [−1e308, 1e308]` returned Ok with NaN vertices (the width overflows).
/// A range whose width is not finite is refused, naming the range.
#[test]
fn a_rectangle_of_infinite_width_is_refused() {
    let e = MeshBuffers::height_field_rect([-1e308, 1e308], [0.0, 1.0], 2, 2, 0.0, |_, _| 1.0)
        .unwrap_err();
    match &e {
        GeometryError::InvalidParameter { name, value, .. } => {
            assert_eq!((*name, *value), ("rectangle x range", f64::INFINITY));
        }
        other => panic!("{other:?}"),
    }
    assert!(
        MeshBuffers::height_field_rect([0.0, 1.0], [-1e308, 1e308], 2, 2, 0.0, |_, _| 1.0).is_err()
    );
    // Bounds near f64::MAX with a finite width: every vertex finite.
    let b = MeshBuffers::height_field_rect([1e308, 1.5e308], [0.0, 1.0], 2, 2, 0.0, |_, _| 1.0)
        .unwrap();
    assert!(b.vertices.iter().flatten().all(|c| c.is_finite()));
}
