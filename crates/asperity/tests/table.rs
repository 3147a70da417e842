//! Tabulated caps: accuracy against closed forms, invariants, validation.
#![allow(clippy::unwrap_used)]

use proptest::prelude::*;
use tyreroad_asperity::{
    CapGeometry, CapMeasures, CapTable, Cone, EllipticParaboloid, GeometryError, MeshAsperity,
    MeshBuffers, Sphere, TabulatedCap,
};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Largest relative errors (Ω, Σ, Γ, Σ', Γ') of `t` against `g` over depths
/// from 1e-12·max to max.
fn worst(g: &dyn CapGeometry, t: &TabulatedCap, max: f64) -> [f64; 5] {
    let mut e = [0.0f64; 5];
    for k in 0..=2400 {
        let d = max * 10f64.powf(-12.0 + 12.0 * f64::from(k) / 2400.0);
        let (a, b) = (t.cap(d), g.cap(d));
        for (i, (x, y)) in [
            (a.volume, b.volume),
            (a.base_area, b.base_area),
            (a.perimeter, b.perimeter),
            (a.d_base_area, b.d_base_area),
            (a.d_perimeter, b.d_perimeter),
        ]
        .into_iter()
        .enumerate()
        {
            if y.abs() > 1e-300 {
                e[i] = e[i].max(rel(x, y));
            }
        }
    }
    e
}

#[test]
fn tables_of_closed_forms_reproduce_them() {
    let r = 5e-3;
    let cases: [(&dyn CapGeometry, f64); 4] = [
        (&Sphere::new(r).unwrap(), 0.9 * r),
        (&Cone::new(1.3).unwrap(), 2e-3),
        (&EllipticParaboloid::new(2e-3, 7e-3).unwrap(), 1e-3),
        (&Sphere::new(r).unwrap(), r),
    ];
    for (g, max) in cases {
        let t = TabulatedCap::from_geometry(g, max, 200).unwrap();
        let e = worst(g, &t, max);
        // Measured: ≤ 4e-6 (the sphere's onset at δ = 1e-12·max, where the
        // power law's exponent is 1 − 3e-7 instead of 1), Γ ≤ 8e-6 (last
        // interval), Γ' ≤ 5.3e-3 (last node, one-sided slope).
        assert!(e[0] < 1e-5 && e[1] < 1e-5 && e[2] < 2e-5, "{e:?}");
        assert!(e[3] < 1e-5 && e[4] < 1e-2, "{e:?}");
        assert!(t.volume_mismatch() < 1e-9, "{}", t.volume_mismatch());
        assert_eq!(t.max_depth(), max);
        assert_eq!(t.len(), 200);
    }
    // Exact onsets: cone p = 2, q = 1; paraboloid p = 1, q = 1/2.
    let t = TabulatedCap::from_geometry(&Cone::new(0.8).unwrap(), 1e-3, 50).unwrap();
    let (p, q) = t.onset_exponents();
    assert!((p - 2.0).abs() < 1e-12 && (q - 1.0).abs() < 1e-12);
    let g = EllipticParaboloid::new(1e-3, 4e-3).unwrap();
    let t = TabulatedCap::from_geometry(&g, 1e-3, 50).unwrap();
    let (p, q) = t.onset_exponents();
    assert!((p - 1.0).abs() < 1e-12 && (q - 0.5).abs() < 1e-12);
    assert!(rel(t.cap(1e-15).perimeter, g.cap(1e-15).perimeter) < 1e-12);
}

#[test]
fn beyond_the_table_walls_are_vertical() {
    let s = Sphere::new(1.0).unwrap();
    let t = TabulatedCap::from_geometry(&s, 0.5, 100).unwrap();
    let end = t.cap(0.5);
    let c = t.cap(0.7);
    assert_eq!((c.base_area, c.perimeter), (end.base_area, end.perimeter));
    assert!(rel(c.volume, end.volume + 0.2 * end.base_area) < 1e-14);
    assert_eq!(
        (c.d_base_area, c.d_perimeter, c.d2_base_area),
        (0.0, 0.0, 0.0)
    );
    for d in [0.0, -1.0, f64::NAN] {
        assert_eq!(t.cap(d), CapMeasures::EMPTY);
    }
    // Continuous at every node, and at the onset.
    let grid = TabulatedCap::default_grid(0.5, 100).unwrap();
    for &x in &grid {
        let (a, b) = (t.cap(x * (1.0 - 1e-13)), t.cap(x * (1.0 + 1e-13)));
        assert!(rel(a.volume, b.volume) < 1e-11);
        assert!(rel(a.base_area, b.base_area) < 1e-11);
        assert!(rel(a.perimeter, b.perimeter) < 1e-11);
        if x < 0.5 {
            assert!(rel(a.d_base_area, b.d_base_area) < 1e-9, "C¹ at {x}");
        }
    }
}

#[test]
fn tables_of_meshes() {
    // A mesh's table: onset exponent 2 (the summit is a vertex), and the
    // table follows the mesh. Σ has kinks at every vertex height, so the
    // interpolation error is larger than for smooth shapes.
    let m = MeshAsperity::from_buffers(&MeshBuffers::icosphere(1.0, 4).unwrap()).unwrap();
    let t = TabulatedCap::from_geometry(&m, 0.9, 400).unwrap();
    let (p, q) = t.onset_exponents();
    assert!((p - 2.0).abs() < 1e-9 && (q - 1.0).abs() < 1e-9, "{p} {q}");
    let e = worst(&m, &t, 0.9);
    // Measured 1.1e-4, 3.2e-3, 2.5e-3; derivatives are not compared (the
    // mesh's jump at every vertex height).
    assert!(e[0] < 3e-4 && e[1] < 5e-3 && e[2] < 5e-3, "{e:?}");
    assert!(t.volume_mismatch() < 1e-3, "{}", t.volume_mismatch());
}

fn invalid(t: CapTable) -> String {
    match TabulatedCap::new(t) {
        Err(GeometryError::InvalidTable(m)) => m,
        other => panic!("expected InvalidTable, got {other:?}"),
    }
}

#[test]
fn bad_tables_are_refused() {
    let good = CapTable {
        depth: vec![1.0, 2.0, 3.0],
        volume: vec![0.5, 2.0, 4.5],
        base_area: vec![1.0, 2.0, 3.0],
        perimeter: vec![1.0, 1.5, 2.0],
    };
    assert!(TabulatedCap::new(good.clone()).is_ok());
    let with = |f: &dyn Fn(&mut CapTable)| {
        let mut t = good.clone();
        f(&mut t);
        invalid(t)
    };
    assert!(with(&|t| t.depth = vec![1.0, 2.0, 3.0, 4.0]).contains("different lengths"));
    assert!(with(&|t| t.depth[1] = 1.0).contains("increase strictly"));
    assert!(with(&|t| t.depth[0] = 0.0).contains("> 0"));
    assert!(with(&|t| t.volume[2] = f64::NAN).contains("finite"));
    assert!(with(&|t| t.perimeter[1] = f64::INFINITY).contains("finite"));
    assert!(with(&|t| t.base_area[2] = 1.5).contains("decreases"));
    assert!(with(&|t| t.volume[1] = 0.4).contains("decreases"));
    assert!(with(&|t| t.volume[0] = 1.5).contains("cannot have grown"));
    let one = CapTable {
        depth: vec![1.0],
        volume: vec![0.5],
        base_area: vec![1.0],
        perimeter: vec![1.0],
    };
    assert!(invalid(one).contains("at least 2"));
    assert!(invalid(CapTable::default()).contains("at least 2"));
    // Rounding-level decreases are flattened, perimeters may decrease.
    let mut t = good.clone();
    t.base_area[2] = 2.0 * (1.0 - 1e-15);
    t.perimeter[2] = 1.2;
    let t = TabulatedCap::new(t).unwrap();
    assert_eq!(t.table().base_area[2], 2.0);
    assert!(TabulatedCap::from_geometry(&Sphere::new(1.0).unwrap(), 0.0, 10).is_err());
    assert!(TabulatedCap::from_geometry(&Sphere::new(1.0).unwrap(), 1.0, 1).is_err());
    // A sphere mesh tabulated past its equator, where Σ decreases.
    let m = MeshAsperity::from_buffers(&MeshBuffers::icosphere(1.0, 2).unwrap())
        .unwrap()
        .with_max_depth(2.0)
        .unwrap();
    assert!(TabulatedCap::from_geometry(&m, 2.0, 50).is_err());
}

/// Random valid tables: positive increments of Σ, Ω consistent with Σ
/// (trapezoids), any positive Γ.
fn random_table() -> impl Strategy<Value = CapTable> {
    prop::collection::vec((0.01f64..1.0, 0.0f64..1.0, 0.1f64..2.0), 2..30).prop_map(|rows| {
        let mut t = CapTable::default();
        let (mut d, mut s, mut o) = (0.0, 0.0, 0.0);
        for (k, (dd, ds, g)) in rows.into_iter().enumerate() {
            let s_new = s + ds + if k == 0 { 0.1 } else { 0.0 };
            o += dd
                * if k == 0 {
                    0.5 * s_new
                } else {
                    0.5 * (s + s_new)
                };
            d += dd;
            s = s_new;
            t.depth.push(d);
            t.volume.push(o);
            t.base_area.push(s);
            t.perimeter.push(g);
        }
        t
    })
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(128))]

    #[test]
    fn interpolants_are_monotone(t in random_table(), a in 0.0f64..1.2, b in 0.0f64..1.2) {
        let tab = TabulatedCap::new(t).unwrap();
        let m = tab.max_depth();
        let (lo, hi) = if a < b { (a * m, b * m) } else { (b * m, a * m) };
        let (cl, ch) = (tab.cap(lo), tab.cap(hi));
        prop_assert!(ch.volume >= cl.volume);
        prop_assert!(ch.base_area >= cl.base_area);
        prop_assert!(cl.d_base_area >= 0.0 && ch.d_base_area >= 0.0);
        prop_assert!(cl.perimeter >= 0.0);
        // Never outside the data's range (no overshoot).
        let t = tab.table();
        let (gmin, gmax) = t.perimeter.iter().fold((f64::INFINITY, 0.0f64), |(x, y), &g| (x.min(g), y.max(g)));
        if hi >= t.depth[0] {
            prop_assert!(ch.perimeter >= gmin * (1.0 - 1e-12) && ch.perimeter <= gmax * (1.0 + 1e-12));
        }
    }

    #[test]
    fn volume_derivative_is_the_base_area(t in random_table(), a in 0.001f64..1.1) {
        let tab = TabulatedCap::new(t).unwrap();
        let d = a * tab.max_depth();
        let h = 1e-6 * d;
        let (lo, mid, hi) = (tab.cap(d - h), tab.cap(d), tab.cap(d + h));
        let scale = tab.table().base_area[tab.len() - 1];
        prop_assert!(((hi.volume - lo.volume) / (2.0 * h) - mid.base_area).abs() < 1e-6 * scale);
        // Σ' and Γ' are the slopes of Σ and Γ (one-sided at nodes: use the
        // right difference, the interpolant is C¹ so both agree to O(h)).
        let ds = (hi.base_area - mid.base_area) / h;
        prop_assert!((ds - mid.d_base_area).abs() < 1e-3 * (1.0 + mid.d_base_area.abs() + mid.d2_base_area.abs() * d));
    }
}
