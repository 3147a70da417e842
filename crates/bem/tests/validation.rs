//! Validation of the BEM contact solver against closed forms.
//!
//! Run with `--nocapture` to see the measured figures.
#![allow(clippy::unwrap_used)]

use std::f64::consts::PI;

use tyreroad_bem::{
    BemError, BemOptions, BemSolution, Control, Grid, HeightMap, MAX_TOLERANCE, Material, Par,
    Solver, Sphere, love_influence, nearest_labels, solve, spherical_caps,
};

fn rel(a: f64, b: f64) -> f64 {
    (a - b).abs() / b.abs()
}

/// Checks p ≥ 0, g ≥ −tol·scale, |p·g| ≤ tol·p_max·scale; returns
/// (min gap / scale, max |p g| / (p_max scale)).
fn complementarity(s: &BemSolution, tol: f64) -> (f64, f64) {
    let scale = s
        .displacement
        .iter()
        .fold(s.approach.abs(), |a, v| a.max(v.abs()));
    let pmax = s.max_pressure();
    let mut min_gap = f64::INFINITY;
    let mut max_pg = 0.0f64;
    for (&p, &g) in s.pressure.iter().zip(&s.gap) {
        assert!(p >= 0.0, "negative pressure {p}");
        min_gap = min_gap.min(g / scale);
        max_pg = max_pg.max((p * g).abs() / (pmax * scale));
    }
    assert!(min_gap >= -tol, "penetration {min_gap:e}");
    assert!(max_pg <= tol, "p*g = {max_pg:e}");
    (min_gap, max_pg)
}

struct Hertz {
    e_star: f64,
    radius: f64,
    load: f64,
}

impl Hertz {
    fn a(&self) -> f64 {
        (3.0 * self.load * self.radius / (4.0 * self.e_star)).cbrt()
    }
    fn delta(&self) -> f64 {
        self.a().powi(2) / self.radius
    }
    fn p0(&self) -> f64 {
        3.0 * self.load / (2.0 * PI * self.a().powi(2))
    }
}

/// Paraboloid z = −r²/(2R) on 256² cells, summit on a cell centre, contact
/// radius ≈ 42 cells (diameter ≈ 1/3 of the domain).
fn hertz_case() -> (HeightMap, Material, Hertz) {
    let n = 256;
    let dx = 1e-5;
    let grid = Grid::new(n, n, dx, dx)
        .unwrap()
        .with_origin([-128.0 * dx, -128.0 * dx])
        .unwrap();
    let radius = 0.01;
    let material = Material::new(1e7, 0.3).unwrap();
    let a_target = 42.0 * dx;
    let load = 4.0 * material.reduced_modulus() * a_target.powi(3) / (3.0 * radius);
    let surface = HeightMap::from_fn(grid, |x, y| -(x * x + y * y) / (2.0 * radius)).unwrap();
    let hertz = Hertz {
        e_star: material.reduced_modulus(),
        radius,
        load,
    };
    (surface, material, hertz)
}

#[test]
fn hertz_paraboloid_load_and_displacement_control() {
    let (surface, material, hz) = hertz_case();
    let tol = 1e-10;
    let options = BemOptions {
        tolerance: tol,
        ..BemOptions::default()
    };
    let mut solver = Solver::new(surface.grid(), &material, &options).unwrap();
    let t0 = std::time::Instant::now();
    let s = solver.solve(&surface, Control::Load(hz.load)).unwrap();
    let t_load = t0.elapsed();
    // The summit is a cell centre at h = 0 = reference height, so the
    // approach is directly comparable with Hertz.
    assert_eq!(s.reference_height, 0.0);
    let a = s.equivalent_radius();
    let ea = rel(a, hz.a());
    let ed = rel(s.approach, hz.delta());
    let ep = rel(s.max_pressure(), hz.p0());
    let ef = rel(s.force, hz.load);
    let (min_gap, max_pg) = complementarity(&s, 10.0 * tol);
    println!(
        "Hertz 256²: a/a_H - 1 = {:+.3e}, delta/delta_H - 1 = {:+.3e}, p0 err = {:+.3e}, force err = {ef:.1e}, \
         iterations = {}, residual = {:.1e}, min gap = {min_gap:.1e}, max |pg| = {max_pg:.1e}, {t_load:?}",
        a / hz.a() - 1.0,
        s.approach / hz.delta() - 1.0,
        s.max_pressure() / hz.p0() - 1.0,
        s.iterations,
        s.residual
    );
    assert!(ea < 0.01, "contact radius error {ea}");
    assert!(ed < 0.002, "approach error {ed}");
    assert!(ep < 0.01, "peak pressure error {ep}");
    assert!(ef < 1e-12, "force balance {ef}");
    // Pressure profile inside the contact: p = p0 √(1 − r²/a²).
    let g = &s.grid;
    let mut worst = 0.0f64;
    for j in 0..g.ny() {
        for i in 0..g.nx() {
            let r = g.x(i).hypot(g.y(j));
            if r < 0.9 * hz.a() {
                let ph = hz.p0() * (1.0 - (r / hz.a()).powi(2)).sqrt();
                worst = worst.max((s.pressure[g.index(i, j)] - ph).abs() / hz.p0());
            }
        }
    }
    println!("Hertz 256²: max |p - p_H| / p0 for r < 0.9a = {worst:.2e}");
    assert!(worst < 0.01, "pressure profile {worst}");

    // Displacement control at the computed approach gives the same contact.
    let t0 = std::time::Instant::now();
    let sd = solver
        .solve(&surface, Control::Approach(s.approach))
        .unwrap();
    let t_disp = t0.elapsed();
    let ew = rel(sd.force, s.force);
    let dp = s
        .pressure
        .iter()
        .zip(&sd.pressure)
        .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()))
        / s.max_pressure();
    complementarity(&sd, 10.0 * tol);
    println!(
        "displacement control: force rel diff = {ew:.2e}, max |dp|/pmax = {dp:.2e}, contact cells {} vs {}, iterations = {}, {t_disp:?}",
        sd.contact_cells, s.contact_cells, sd.iterations
    );
    assert!(ew < 1e-8, "load/displacement control force mismatch {ew}");
    assert!(
        dp < 1e-7,
        "load/displacement control pressure mismatch {dp}"
    );
    assert_eq!(sd.contact_cells, s.contact_cells);
}

#[test]
fn symmetric_case_gives_symmetric_pressure() {
    let n = 64;
    let dx = 1e-5;
    let grid = Grid::centered(n, n, dx, dx).unwrap();
    let material = Material::new(2e6, 0.45).unwrap();
    let radius = 2e-3;
    let surface = HeightMap::from_fn(grid, |x, y| -(x * x + y * y) / (2.0 * radius)).unwrap();
    let options = BemOptions {
        tolerance: 1e-11,
        par: Par::Seq,
        ..BemOptions::default()
    };
    let s = solve(&surface, &material, Control::Load(2e-3), &options).unwrap();
    let g = &s.grid;
    let pmax = s.max_pressure();
    let mut worst = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let p = s.pressure[g.index(i, j)];
            for q in [
                s.pressure[g.index(n - 1 - i, j)],
                s.pressure[g.index(i, n - 1 - j)],
                s.pressure[g.index(j, i)],
            ] {
                worst = worst.max((p - q).abs() / pmax);
            }
        }
    }
    println!(
        "symmetry 64²: max asymmetry / pmax = {worst:.1e} ({} contact cells)",
        s.contact_cells
    );
    assert!(worst < 1e-9, "asymmetry {worst}");
}

#[test]
fn flat_circular_punch_stiffness() {
    // Flat punch of radius 40 cells on 160² cells, displacement control.
    let n = 160;
    let dx = 1e-5;
    let grid = Grid::centered(n, n, dx, dx).unwrap();
    let material = Material::new(1e7, 0.5).unwrap();
    let a = 40.0 * dx;
    let delta = 1e-6;
    let surface =
        HeightMap::from_fn(grid, |x, y| if x.hypot(y) <= a { 0.0 } else { -1e-3 }).unwrap();
    let n_in = surface.values().iter().filter(|&&h| h == 0.0).count();
    let a_eff = (n_in as f64 * dx * dx / PI).sqrt();
    let options = BemOptions {
        tolerance: 1e-10,
        ..BemOptions::default()
    };
    let s = solve(&surface, &material, Control::Approach(delta), &options).unwrap();
    let w_exact = 2.0 * material.reduced_modulus() * a_eff * delta;
    let err = s.force / w_exact - 1.0;
    complementarity(&s, 1e-9);
    println!(
        "flat punch a = 40 cells (a_eff/a = {:.5}): W/W_exact - 1 = {err:+.3e}, contact cells {} of {n_in}, iterations {}",
        a_eff / a,
        s.contact_cells,
        s.iterations
    );
    assert_eq!(s.contact_cells, n_in);
    assert!(err.abs() < 0.02, "punch stiffness error {err}");
}

/// Independent quadrature of the Love integral at an interior point:
/// ∫∫ dA / (π E* r) = 1/(π E*) ∮ R(θ) dθ, R the distance to the boundary.
fn love_by_quadrature(x: f64, y: f64, dx: f64, dy: f64, e_star: f64) -> f64 {
    let (a, b) = (0.5 * dx, 0.5 * dy);
    // Split at the corner angles so each piece is smooth.
    let mut cuts: Vec<f64> = [(a, b), (-a, b), (-a, -b), (a, -b)]
        .iter()
        .map(|(cx, cy)| (cy - y).atan2(cx - x).rem_euclid(2.0 * PI))
        .collect();
    cuts.push(0.0);
    cuts.push(2.0 * PI);
    cuts.sort_by(f64::total_cmp);
    let dist = |t: f64| {
        let (c, s) = (t.cos(), t.sin());
        let rx = if c > 0.0 {
            (a - x) / c
        } else if c < 0.0 {
            (-a - x) / c
        } else {
            f64::INFINITY
        };
        let ry = if s > 0.0 {
            (b - y) / s
        } else if s < 0.0 {
            (-b - y) / s
        } else {
            f64::INFINITY
        };
        rx.min(ry)
    };
    // 20-point Gauss–Legendre on each piece (via composite Simpson would be
    // slower): use composite Simpson with many points for simplicity.
    let mut total = 0.0;
    for w in cuts.windows(2) {
        let (t0, t1) = (w[0], w[1]);
        if t1 - t0 < 1e-15 {
            continue;
        }
        let m = 2000;
        let h = (t1 - t0) / m as f64;
        let mut s = dist(t0) + dist(t1);
        for k in 1..m {
            let t = t0 + k as f64 * h;
            s += if k % 2 == 1 { 4.0 } else { 2.0 } * dist(t);
        }
        total += s * h / 3.0;
    }
    total / (PI * e_star)
}

#[test]
fn love_influence_coefficient() {
    let e_star = 3.0e6;
    // Centre of a square of side s: 4 ln(1 + √2) s / (π E*).
    let s = 2e-4;
    let centre = love_influence(0.0, 0.0, s, s, e_star);
    let closed = 4.0 * (1.0 + 2f64.sqrt()).ln() * s / (PI * e_star);
    println!(
        "Love centre value: {:.3e} relative to closed form",
        rel(centre, closed)
    );
    assert!(rel(centre, closed) < 1e-14);
    // Rectangle, interior points, against an independent quadrature.
    let (dx, dy) = (1e-4, 3e-4);
    for &(x, y) in &[(0.0, 0.0), (2e-5, -1e-4), (3e-5, 1.2e-4)] {
        let u = love_influence(x, y, dx, dy, e_star);
        let q = love_by_quadrature(x, y, dx, dy, e_star);
        println!(
            "Love at ({x:e}, {y:e}): rel diff to quadrature {:.2e}",
            rel(u, q)
        );
        assert!(rel(u, q) < 1e-9, "{u} vs {q}");
    }
    // Far field: Boussinesq point load dx·dy / (π E* r), error O((dx/r)²).
    for &k in &[5.0, 20.0, 100.0] {
        let (x, y) = (k * dy * 0.6, k * dy * 0.8);
        let r = x.hypot(y);
        let u = love_influence(x, y, dx, dy, e_star);
        let b = dx * dy / (PI * e_star * r);
        let e = rel(u, b);
        println!("Love far field at r = {k} dy: rel diff to Boussinesq {e:.2e}");
        assert!(e < 0.3 * (dy / r).powi(2), "far field {e} at r = {r}");
    }
    // Symmetry.
    let u1 = love_influence(3e-4, 1e-4, dx, dy, e_star);
    let u2 = love_influence(-3e-4, -1e-4, dx, dy, e_star);
    assert!(rel(u1, u2) < 1e-15);
}

#[test]
fn periodic_sinusoid_full_contact() {
    // h = A cos(2π x / λ), one wavelength on 64 cells, pressed into full
    // contact: p = p̄ + E* k A / 2 · cos(k x) (Johnson 1985, §13.2).
    let (nx, ny) = (64, 8);
    let lambda = 1e-3;
    let dx = lambda / nx as f64;
    let grid = Grid::new(nx, ny, dx, dx).unwrap();
    let material = Material::new(1e7, 0.3).unwrap();
    let amp = 1e-6;
    let k = 2.0 * PI / lambda;
    let surface = HeightMap::from_fn(grid.clone(), |x, _| amp * (k * x).cos()).unwrap();
    let p_star = material.reduced_modulus() * k * amp / 2.0;
    let p_mean = 2.0 * p_star;
    let area = nx as f64 * ny as f64 * dx * dx;
    let options = BemOptions {
        tolerance: 1e-10,
        periodic: true,
        ..BemOptions::default()
    };
    let s = solve(&surface, &material, Control::Load(p_mean * area), &options).unwrap();
    assert_eq!(s.contact_cells, grid.len());
    let mut worst = 0.0f64;
    for j in 0..ny {
        for i in 0..nx {
            let exact = p_mean + p_star * (k * grid.x(i)).cos();
            worst = worst.max((s.pressure[grid.index(i, j)] - exact).abs() / p_star);
        }
    }
    // Full contact: gap 0 everywhere, so δ = mean initial gap = A (z_top = A).
    let ed = rel(s.approach, amp);
    println!(
        "periodic sinusoid, 64 cells/λ: max |p - p_exact| / p* = {worst:.2e}, approach err = {ed:.1e}, iterations {}",
        s.iterations
    );
    assert!(worst < 2e-3, "sinusoid pressure error {worst}");
    assert!(ed < 1e-9);

    // Partial contact, light load: Westergaard. Contact half-width a with
    // p̄ = p* sin²(π a / λ).
    let p_mean = 0.25 * p_star;
    let s = solve(&surface, &material, Control::Load(p_mean * area), &options).unwrap();
    let a_exact = lambda / PI * (p_mean / p_star).sqrt().asin();
    let a_num = s.contact_area / (ny as f64 * dx) / 2.0;
    let e = (a_num - a_exact) / dx;
    println!(
        "periodic Westergaard: half-width error = {e:+.2} cells (a = {:.1} cells)",
        a_exact / dx
    );
    assert!(e.abs() <= 1.0, "Westergaard half-width off by {e} cells");
}

#[test]
fn periodic_array_matches_one_cell() {
    // One sphere in a periodic cell versus 2 × 2 spheres in a doubled cell:
    // same force per sphere, same approach, same pressure pattern.
    let n = 48;
    let dx = 2e-5;
    let period = n as f64 * dx;
    let radius = 2e-3;
    let material = Material::new(5e6, 0.5).unwrap();
    let options = BemOptions {
        tolerance: 1e-10,
        periodic: true,
        ..BemOptions::default()
    };
    let one = Grid::centered(n, n, dx, dx).unwrap();
    let o = one.origin();
    let sph = |cx: f64, cy: f64| Sphere {
        centre: [cx, cy],
        radius,
        summit: 0.0,
    };
    let s1 = spherical_caps(&one, &[sph(0.0, 0.0)], -radius).unwrap();
    let two = Grid::new(2 * n, 2 * n, dx, dx)
        .unwrap()
        .with_origin(o)
        .unwrap();
    let c = [0.0, period];
    let balls: Vec<Sphere> = c
        .iter()
        .flat_map(|&x| c.iter().map(move |&y| sph(x, y)))
        .collect();
    let s2 = spherical_caps(&two, &balls, -radius).unwrap();
    let w = 0.05;
    let r1 = solve(&s1, &material, Control::Load(w), &options).unwrap();
    let r2 = solve(&s2, &material, Control::Load(4.0 * w), &options).unwrap();
    let labels = nearest_labels(&two, &balls.iter().map(|b| b.centre).collect::<Vec<_>>());
    let f = r2.force_per_region(&labels).unwrap();
    let mut worst = 0.0f64;
    for j in 0..n {
        for i in 0..n {
            let p1 = r1.pressure[one.index(i, j)];
            for (di, dj) in [(0, 0), (n, 0), (0, n), (n, n)] {
                let p2 = r2.pressure[two.index(i + di, j + dj)];
                worst = worst.max((p1 - p2).abs() / r1.max_pressure());
            }
        }
    }
    let ed = rel(r2.approach, r1.approach);
    println!(
        "periodic 1 vs 2x2 cells: forces {f:?} (expect {w}), approach rel diff {ed:.1e}, max |dp|/pmax {worst:.1e}"
    );
    for fi in f {
        assert!(rel(fi, w) < 1e-8);
    }
    assert!(ed < 1e-8);
    assert!(worst < 1e-8);
    // Periodic displacement control reproduces the load-controlled state.
    let rd = solve(&s1, &material, Control::Approach(r1.approach), &options).unwrap();
    println!(
        "periodic displacement control: force rel diff {:.1e}",
        rel(rd.force, w)
    );
    assert!(rel(rd.force, w) < 1e-7);
    // An approach closing the mean gap has no finite solution.
    let mean_gap = s1.values().iter().map(|h| s1.max() - h).sum::<f64>() / one.len() as f64;
    let e = solve(&s1, &material, Control::Approach(1.01 * mean_gap), &options);
    assert!(matches!(e, Err(BemError::InvalidInput(_))));
}

#[test]
fn twenty_five_balls_coarse_forces_are_symmetric() {
    // The 25-ball experiment of Cesbron et al. (2006, section 3) on a
    // coarse grid (0.5 mm cells).
    let dx = 5e-4;
    let grid = Grid::centered(108, 108, dx, dx).unwrap();
    let pos = [-0.02, -0.01, 0.0, 0.01, 0.02];
    let balls: Vec<Sphere> = pos
        .iter()
        .flat_map(|&y| {
            pos.iter().map(move |&x| Sphere {
                centre: [x, y],
                radius: 5e-3,
                summit: 0.0,
            })
        })
        .collect();
    let surface = spherical_caps(&grid, &balls, -5e-3).unwrap();
    let material = Material::new(6.54e6, 0.5).unwrap();
    let mut solver = Solver::new(&grid, &material, &BemOptions::default()).unwrap();
    let s = solver.solve(&surface, Control::Load(500.0)).unwrap();
    let centres: Vec<[f64; 2]> = balls.iter().map(|b| b.centre).collect();
    let labels = nearest_labels(&grid, &centres);
    let regions = s.regions(&labels).unwrap();
    let total: f64 = regions.iter().map(|r| r.force).sum();
    assert!(rel(total, 500.0) < 1e-12);
    let f = |k: usize| regions[k].force;
    // Ball k = 5·row + column. Symmetry classes of the 5 × 5 square.
    let classes: [&[usize]; 6] = [
        &[0, 4, 20, 24],
        &[1, 3, 5, 9, 15, 19, 21, 23],
        &[2, 10, 14, 22],
        &[6, 8, 16, 18],
        &[7, 11, 13, 17],
        &[12],
    ];
    for class in classes {
        for &k in class {
            assert!(rel(f(k), f(class[0])) < 1e-8, "ball {k} vs {}", class[0]);
        }
    }
    println!(
        "25 balls at 500 N, 0.5 mm cells: corner {:.3} N, edge {:.3} N, centre {:.3} N, {} iterations",
        f(0),
        f(2),
        f(12),
        s.iterations
    );
    // Hertz for 20 N per ball gives a ≈ 2.05 mm; check the centre ball's
    // radius is in that neighbourhood (coupling and the coarse grid).
    let h = Hertz {
        e_star: material.reduced_modulus(),
        radius: 5e-3,
        load: f(12),
    };
    let rc = regions[12];
    println!(
        "centre ball: equivalent radius {:.3} mm, semi-axes {:.3?} mm, Hertz a for its force {:.3} mm",
        rc.equivalent_radius * 1e3,
        rc.semi_axes.map(|v| v * 1e3),
        h.a() * 1e3
    );
    assert!(rel(rc.equivalent_radius, h.a()) < 0.1);
    assert!(rc.centroid[0].abs() < 1e-12 && rc.centroid[1].abs() < 1e-12);

    // Warm start from the 500 N solution at 450 N.
    let cold = solver.solve(&surface, Control::Load(450.0)).unwrap();
    let warm = solver
        .solve_from(&surface, Control::Load(450.0), &s.pressure)
        .unwrap();
    println!(
        "450 N: cold {} iterations, warm start {} iterations",
        cold.iterations, warm.iterations
    );
    assert!(rel(warm.approach, cold.approach) < 1e-6);
}

#[test]
fn bad_input_is_an_error_not_a_panic() {
    let grid = Grid::new(8, 8, 1e-4, 1e-4).unwrap();
    let material = Material::new(1e7, 0.3).unwrap();
    let surface = HeightMap::from_fn(grid.clone(), |x, y| -(x * x + y * y)).unwrap();
    let o = BemOptions::default();
    for c in [
        Control::Load(-1.0),
        Control::Load(f64::NAN),
        Control::Approach(f64::INFINITY),
    ] {
        assert!(matches!(
            solve(&surface, &material, c, &o),
            Err(BemError::InvalidInput(_))
        ));
    }
    let bad = BemOptions {
        tolerance: 0.0,
        ..o.clone()
    };
    assert!(Solver::new(&grid, &material, &bad).is_err());
    let bad = BemOptions {
        max_iterations: 0,
        ..o.clone()
    };
    assert!(Solver::new(&grid, &material, &bad).is_err());
    // Mismatched grids.
    let mut solver = Solver::new(&grid, &material, &o).unwrap();
    let other = HeightMap::new(Grid::new(8, 9, 1e-4, 1e-4).unwrap(), vec![0.0; 72]).unwrap();
    assert!(solver.solve(&other, Control::Load(1.0)).is_err());
    assert!(
        solver
            .solve_from(&surface, Control::Load(1.0), &[0.0; 3])
            .is_err()
    );
    assert!(
        solver
            .solve_from(&surface, Control::Load(1.0), &[-1.0; 64])
            .is_err()
    );
    let s = solver.solve(&surface, Control::Load(1.0)).unwrap();
    assert!(s.force_per_region(&[0; 5]).is_err());
    // Zero load and non-positive approach: no contact, no iteration.
    let s = solver.solve(&surface, Control::Load(0.0)).unwrap();
    assert_eq!((s.force, s.contact_cells, s.iterations), (0.0, 0, 0));
    let s = solver.solve(&surface, Control::Approach(-1e-6)).unwrap();
    assert_eq!(s.force, 0.0);
    assert!(s.gap.iter().all(|&g| g >= 1e-6));
    // Non-convergence is reported with its figures.
    solver.set_stopping(1e-14, 1).unwrap();
    let big = HeightMap::from_fn(grid, |x, y| -(x * x + y * y) * 10.0).unwrap();
    match solver.solve(&big, Control::Load(10.0)) {
        Err(BemError::NotConverged {
            iterations,
            residual,
            ..
        }) => {
            assert_eq!(iterations, 1);
            assert!(residual > 1e-14);
        }
        other => panic!("expected NotConverged, got {other:?}"),
    }
}

/// Small deterministic generator (no extra dependency).
struct Lcg(u64);
impl Lcg {
    fn next(&mut self) -> f64 {
        self.0 = self
            .0
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (self.0 >> 11) as f64 / (1u64 << 53) as f64
    }
}

#[test]
fn random_rough_surfaces_satisfy_the_contact_conditions() {
    // Random rough surfaces (white noise plus a bump), random loads, both
    // modes and both controls: complementarity and force balance hold.
    let mut rng = Lcg(42);
    let material = Material::new(5e6, 0.49).unwrap();
    for case in 0..12 {
        let periodic = case % 2 == 1;
        let (nx, ny) = (24 + case, 31 - case);
        let dx = 1e-5 * (0.5 + rng.next());
        let grid = Grid::centered(nx, ny, dx, 1.3 * dx).unwrap();
        let rough = 2e-6 * rng.next();
        let heights: Vec<f64> = (0..grid.len())
            .map(|k| {
                let (i, j) = grid.cell(k);
                let r2 = grid.x(i).powi(2) + grid.y(j).powi(2);
                -r2 / 2e-3 + rough * rng.next()
            })
            .collect();
        let surface = HeightMap::new(grid.clone(), heights).unwrap();
        let options = BemOptions {
            tolerance: 1e-9,
            periodic,
            par: if case % 3 == 0 {
                Par::rayon(0)
            } else {
                Par::Seq
            },
            ..BemOptions::default()
        };
        let mut solver = Solver::new(&grid, &material, &options).unwrap();
        let area = grid.len() as f64 * grid.cell_area();
        let load = area * 1e4 * (0.1 + rng.next());
        let s = solver.solve(&surface, Control::Load(load)).unwrap();
        assert!(rel(s.force, load) < 1e-12, "case {case}");
        complementarity(&s, 1e-8);
        let sd = solver
            .solve(&surface, Control::Approach(s.approach))
            .unwrap();
        complementarity(&sd, 1e-8);
        assert!(
            rel(sd.force, load) < 1e-5,
            "case {case}: {} vs {load}",
            sd.force
        );
    }
}

/// Regression (adversarial run of the Python bindings, 2026-11-30): a load
/// of 1e300 N came back as a contact carrying 0 N, an approach of 1e300 m
/// as an infinite force, cells of 1e-300 m with pressures of −6e297 Pa, all
/// without an error. A result no contact has is `NotPhysical` (or, past the
/// iteration's reach, `NotConverged`), never a solution; the same paraboloid
/// at a load it holds still solves, carrying its load.
#[test]
fn a_result_no_contact_has_is_an_error_not_a_solution() {
    let material = Material::new(6.54e6, 0.5).unwrap();
    let paraboloid = |dx: f64| {
        let grid = Grid::new(48, 32, dx, dx)
            .unwrap()
            .with_origin([-23.5 * dx, -15.5 * dx])
            .unwrap();
        HeightMap::from_fn(grid, |x, y| -(x * x + y * y) / 1e-2).unwrap()
    };
    // Cells of 1e-300 m (an area of 0 in floating point) are refused by
    // the grid itself since 2026-11-30.
    assert!(Grid::new(48, 32, 1e-300, 1e-300).is_err());
    let o = BemOptions::default();
    for (dx, control) in [
        (4e-5, Control::Load(1e300)),
        (4e-5, Control::Approach(1e300)),
    ] {
        match solve(&paraboloid(dx), &material, control, &o) {
            Err(BemError::NotPhysical(_) | BemError::NotConverged { .. }) => {}
            other => panic!("dx {dx}, {control:?}: {other:?}"),
        }
    }
    let s = solve(&paraboloid(4e-5), &material, Control::Load(1.0), &o).unwrap();
    assert!(rel(s.force, 1.0) < 1e-9, "{}", s.force);
}

/// Regression (adversarial run of the layer crates, 2026-11-30): a
/// tolerance of 10 returned the uniform starting pressure after 0
/// iterations, the sphere penetrating the tread; a region label of
/// `usize::MAX` panicked (`max + 1` wrapped to 0) and one of 1e7 allocated
/// 640 MB. Both are refused by name; the bounds themselves solve.
#[test]
fn a_tolerance_the_start_meets_and_a_label_past_every_cell_are_refused() {
    let material = Material::new(6.54e6, 0.5).unwrap();
    let grid = Grid::new(32, 32, 1e-4, 1e-4)
        .unwrap()
        .with_origin([-15.5e-4, -15.5e-4])
        .unwrap();
    let surface = HeightMap::from_fn(grid.clone(), |x, y| -(x * x + y * y) / 1e-2).unwrap();
    for tolerance in [10.0, 1.0, 0.2] {
        let o = BemOptions {
            tolerance,
            ..BemOptions::default()
        };
        match Solver::new(&grid, &material, &o) {
            Err(BemError::InvalidInput(m)) => assert!(m.contains("(0, 0.1]"), "{m}"),
            other => panic!("tolerance {tolerance}: {:?}", other.map(|_| ())),
        }
    }
    let loose = BemOptions {
        tolerance: MAX_TOLERANCE,
        ..BemOptions::default()
    };
    let s = solve(&surface, &material, Control::Load(1.0), &loose).unwrap();
    assert!(s.iterations > 0 && rel(s.force, 1.0) < 1e-9);
    assert!(s.residual <= MAX_TOLERANCE, "{}", s.residual);
    let mut labels = vec![0usize; 32 * 32];
    for bad in [usize::MAX, 10_000_000] {
        labels[5] = bad;
        match s.regions(&labels) {
            Err(BemError::InvalidInput(m)) => assert!(m.contains(&format!("label {bad}")), "{m}"),
            other => panic!("label {bad}: {other:?}"),
        }
    }
    labels[5] = 3;
    let regions = s.regions(&labels).unwrap();
    assert_eq!(regions.len(), 4);
    assert!(rel(regions.iter().map(|r| r.force).sum(), 1.0) < 1e-12);
}

/// Elastic contact has no length scale of its own: lengths × s and the load
/// × s² give the same pressures, and the approach and contact radius × s.
/// The solver keeps that from 1e-80 to 1e80 (measured: the same figures
/// to 1e-14 from 1e-90 to 1e100). Past that its conjugate-gradient step
/// (a sum of products of gaps, cubic in s) leaves floating point's range:
/// it must then say it did not converge, never answer otherwise.
#[test]
fn the_solution_scales_with_the_problem_and_says_where_it_cannot() {
    let solve_at = |s: f64| -> Result<BemSolution, BemError> {
        let grid = Grid::centered(65, 65, 4e-5 * s, 4e-5 * s)?;
        let ball = Sphere {
            centre: [0.0, 0.0],
            radius: 5e-3 * s,
            summit: 0.0,
        };
        let surface = spherical_caps(&grid, &[ball], -5e-3 * s)?;
        let material = Material::new(6.54e6, 0.5)?;
        // The unit case takes 32 iterations; those that cannot converge
        // stop at 200 rather than the default 5000.
        let options = BemOptions {
            max_iterations: 200,
            ..BemOptions::default()
        };
        solve(&surface, &material, Control::Load(s * s), &options)
    };
    let unit = solve_at(1.0).unwrap();
    for s in [1e-80, 1e-40, 1e-10, 1e10, 1e40, 1e80] {
        let scaled = solve_at(s).unwrap();
        assert_eq!(scaled.contact_cells, unit.contact_cells, "s = {s:e}");
        assert!(rel(scaled.approach / s, unit.approach) < 1e-9, "s = {s:e}");
        assert!(
            rel(scaled.equivalent_radius() / s, unit.equivalent_radius()) < 1e-9,
            "s = {s:e}"
        );
        assert!(
            rel(scaled.max_pressure(), unit.max_pressure()) < 1e-9,
            "s = {s:e}"
        );
    }
    for s in [1e-150, 1e150] {
        match solve_at(s) {
            Ok(scaled) => assert!(rel(scaled.approach / s, unit.approach) < 1e-9, "s = {s:e}"),
            Err(e) => assert!(matches!(e, BemError::NotConverged { .. }), "s = {s:e}: {e}"),
        }
    }
}
