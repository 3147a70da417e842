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
fn beyond_the_table_a_c1_run_out_leads_into_vertical_walls() {
    let s = Sphere::new(1.0).unwrap();
    let t = TabulatedCap::from_geometry(&s, 0.5, 100).unwrap();
    let grid = TabulatedCap::default_grid(0.5, 100).unwrap();
    let h = grid[99] - grid[98];
    let end = t.cap(0.5); // the last piece's values at the last node
    let (y0, m0) = (end.base_area, end.d_base_area);
    assert!(m0 > 0.0);
    // The run-out is the Hermite cubic from (Σ, Σ') to (Σ + Σ'h/2, 0) over
    // the last interval's width h: at its middle (y0 + y1)/2 + h(m0 − m1)/8.
    let mid = t.cap(0.5 + 0.5 * h);
    assert!(rel(mid.base_area, y0 + 3.0 * m0 * h / 8.0) < 1e-13);
    // Then vertical walls: constant Σ, Γ, linear Ω, no derivatives.
    let (w, c) = (t.cap(0.5 + h), t.cap(0.7));
    assert!(rel(w.base_area, y0 + 0.5 * m0 * h) < 1e-14);
    assert_eq!((c.base_area, c.perimeter), (w.base_area, w.perimeter));
    assert!(rel(c.volume, w.volume + (0.7 - 0.5 - h) * w.base_area) < 1e-13);
    assert_eq!(
        (c.d_base_area, c.d_perimeter, c.d2_base_area, c.d2_perimeter),
        (0.0, 0.0, 0.0, 0.0)
    );
    // dΩ/dδ = Σ inside the run-out (central differences).
    for f in [0.1, 0.5, 0.9] {
        let d = 0.5 + f * h;
        let e = 1e-6 * h;
        let fd = (t.cap(d + e).volume - t.cap(d - e).volume) / (2.0 * e);
        assert!(rel(fd, t.cap(d).base_area) < 1e-9, "{f}");
        let fd = (t.cap(d + e).base_area - t.cap(d - e).base_area) / (2.0 * e);
        assert!(rel(fd, t.cap(d).d_base_area) < 1e-6, "{f}");
    }
    for d in [0.0, -1.0, f64::NAN] {
        assert_eq!(t.cap(d), CapMeasures::EMPTY);
    }
    // A sphere tabulated to its equator has Σ' = Γ' = 0 there (Σ is
    // quadratic, which the three-point end slope reproduces): exact walls,
    // the cylinder of `Sphere` itself.
    let t = TabulatedCap::from_geometry(&s, 1.0, 200).unwrap();
    for d in [1.0, 1.3] {
        let (a, b) = (t.cap(d), s.cap(d));
        assert!(rel(a.base_area, b.base_area) < 1e-12, "{d}");
        assert!(rel(a.perimeter, b.perimeter) < 1e-4, "{d}");
    }
    // The nodes, then the end of the run-outs (here both one interval long).
    let b = t.breakpoints();
    assert_eq!(&b[..200], &t.table().depth[..]);
    assert_eq!(b.len(), 201);
    assert!(rel(b[200] - 1.0, 1.0 - b[198]) < 1e-12);
}

/// `Σ`, `Γ` and their slopes one ulp on each side of `x`, relative to the
/// columns' maxima (slopes times `max_depth`): the law's force needs all
/// four continuous. The slopes' change over those two ulps, `Σ''·2ulp`, is
/// removed (a spike in the data can make `Γ''` 1e5 times its scale).
fn jump_at(t: &TabulatedCap, x: f64) -> [f64; 4] {
    let (lo, hi) = (x.next_down(), x.next_up());
    let (a, b) = (t.cap(lo), t.cap(hi));
    let s = t.table().base_area.iter().fold(0.0f64, |m, v| m.max(*v));
    let g = t.table().perimeter.iter().fold(0.0f64, |m, v| m.max(*v));
    let x_scale = t.max_depth();
    let curv = |u: f64, v: f64| (u.abs() + v.abs()) * (hi - lo);
    [
        (a.base_area - b.base_area).abs() / s,
        (a.perimeter - b.perimeter).abs() / g,
        ((a.d_base_area - b.d_base_area).abs() - curv(a.d2_base_area, b.d2_base_area)).max(0.0)
            * x_scale
            / s,
        ((a.d_perimeter - b.d_perimeter).abs() - curv(a.d2_perimeter, b.d2_perimeter)).max(0.0)
            * x_scale
            / g,
    ]
}

#[test]
fn tabulated_cap_is_c1_at_every_node_and_past_the_last() {
    let t = TabulatedCap::from_geometry(&Sphere::new(1.0).unwrap(), 0.5, 100).unwrap();
    for x in t.breakpoints() {
        let j = jump_at(&t, x);
        assert!(j.iter().all(|&v| v < 1e-9), "at {x}: {j:?}");
    }
}

#[test]
fn onset_stays_c1_when_the_limiter_lowers_the_first_slope() {
    // Ω₀ = Σ₀δ₀/4 asks for p = 3, a slope 3Σ₀/δ₀ four times the secant to
    // the next node: the Fritsch–Carlson limiter must cut it, and the onset
    // exponent follows.
    let t = TabulatedCap::new(CapTable {
        depth: vec![1.0, 2.0, 3.0],
        volume: vec![0.25, 1.5, 3.0],
        base_area: vec![1.0, 1.75, 2.0],
        perimeter: vec![1.0, 1.2, 1.3],
    })
    .unwrap();
    let (p, _) = t.onset_exponents();
    assert!(p < 3.0 && p > 0.0, "{p}");
    let j = jump_at(&t, 1.0);
    assert!(j.iter().all(|&v| v < 1e-12), "{j:?}");
    // Still Ω = Σδ/(p + 1) below δ₀ and dΩ/dδ = Σ.
    let c = t.cap(0.5);
    assert!(rel(c.volume, c.base_area * 0.5 / (p + 1.0)) < 1e-14);
    let e = 1e-7;
    assert!(
        rel(
            (t.cap(1.0 + e).volume - t.cap(1.0 - e).volume) / (2.0 * e),
            t.cap(1.0).base_area
        ) < 1e-6
    );
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
        if hi >= t.depth[0] && hi <= m {
            prop_assert!(ch.perimeter >= gmin * (1.0 - 1e-12) && ch.perimeter <= gmax * (1.0 + 1e-12));
        }
        // Past the table the run-out keeps Γ above half its last value.
        let last = t.perimeter[t.perimeter.len() - 1];
        prop_assert!(tab.cap(1.5 * m).perimeter >= 0.5 * last * (1.0 - 1e-12));
    }

    #[test]
    fn random_tables_are_c1_everywhere(t in random_table()) {
        let tab = TabulatedCap::new(t).unwrap();
        for x in tab.breakpoints() {
            let j = jump_at(&tab, x);
            prop_assert!(j.iter().all(|&v| v < 1e-9), "at {}: {:?}", x, j);
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

/// Regression (adversarial run, adv6 P2): `default_grid(1e-3, usize::MAX)`
/// aborted on "capacity overflow". The node count is bounded by
/// `TabulatedCap::MAX_NODES` and refused past it, naming the parameter.
#[test]
fn a_node_count_past_the_bound_is_refused_not_a_capacity_overflow() {
    let ball = Sphere::new(5e-3).unwrap();
    for n in [usize::MAX, TabulatedCap::MAX_NODES + 1] {
        for e in [
            TabulatedCap::default_grid(1e-3, n).unwrap_err(),
            TabulatedCap::from_geometry(&ball, 1e-3, n).unwrap_err(),
        ] {
            match e {
                GeometryError::InvalidParameter { name, value, .. } => {
                    assert_eq!((name, value), ("table nodes", n as f64));
                }
                other => panic!("{n}: {other:?}"),
            }
        }
    }
    let grid = TabulatedCap::default_grid(1e-3, TabulatedCap::MAX_NODES).unwrap();
    assert_eq!(grid.len(), TabulatedCap::MAX_NODES);
    assert!(grid.windows(2).all(|w| w[0] < w[1]));
}

/// Regression (adversarial run, adv6 S8): a sphere of R = 5 mm tabulated to
/// `max_depth = 1e308` was accepted with every node on its cylinder (first
/// node 1e302 m): `Σ(1 mm) = πR²` instead of 2.83e-5 m². A `max_depth`
/// beyond the shape's own is refused; up to it, tables build as before.
#[test]
fn a_max_depth_beyond_the_shapes_own_is_refused() {
    let r = 5e-3;
    let ball = Sphere::new(r).unwrap();
    for max in [1e308, 1e3, 1.01 * r] {
        match TabulatedCap::from_geometry(&ball, max, 10) {
            Err(GeometryError::InvalidTable(m)) => {
                assert!(m.contains("beyond") && m.contains("5e-3"), "{m}");
            }
            other => panic!("{max:e}: {other:?}"),
        }
    }
    let t = TabulatedCap::from_geometry(&ball, r, 200).unwrap();
    assert!(rel(t.cap(1e-3).base_area, ball.cap(1e-3).base_area) < 1e-6);
    // Shapes without a limit (a cone) take any finite max_depth.
    assert!(TabulatedCap::from_geometry(&Cone::new(1.2).unwrap(), 1e3, 50).is_ok());
}

/// Regression (adversarial run, adv6 U3): `max_depth = 1e-320` was refused
/// as "depth at node 0 is NaN". It is refused as the `max_depth` given.
#[test]
fn a_max_depth_too_small_for_its_grid_is_named() {
    let ball = Sphere::new(5e-3).unwrap();
    for max in [1e-320, 5e-324, 1e-303] {
        let e = TabulatedCap::from_geometry(&ball, max, 10).unwrap_err();
        match &e {
            GeometryError::InvalidParameter { name, value, .. } => {
                assert_eq!((*name, *value), ("table max_depth", max));
            }
            other => panic!("{max:e}: {other:?}"),
        }
        let m = e.to_string();
        assert!(m.contains(&format!("{max:e}")) && !m.contains("NaN"), "{m}");
    }
    assert!(TabulatedCap::default_grid(1e-300, 10).is_ok());
}
