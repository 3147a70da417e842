//! Ting's treatment of receding contacts (`Receding::Ting`) against its
//! independent references: Ting's closed form for a sphere pressed and
//! withdrawn at constant rate, Lee–Radok's recursion while every contact
//! grows, the elastic solutions with `E∞` and `E∞ + Σ E_k` for very slow and
//! very fast loading and unloading, and the load balance at every step
//! (docs/viscoelastic.md, "Receding contacts: Ting's treatment").

use tyreroad_contact_law::{HertzLaw, Material};
use tyreroad_multipoint::{Control, Problem, SolverOptions, solve};
use tyreroad_viscoelastic::{
    Hereditary, Prony, Receding, ViscoError, ramp_hold_unload, run_load_history_with,
};

use crate::support;
use support::{tread, twenty_five_balls};

const TING: Receding = Receding::Ting { per_decade: 20 };

/// `∫_a^b E(t − s) ds` in closed form.
fn relaxation_integral(material: &Prony, t: f64, a: f64, b: f64) -> f64 {
    material.long_term() * (b - a)
        + material
            .branches()
            .iter()
            .map(|k| {
                let tau = k.relaxation_time;
                k.modulus * tau * ((-(t - b) / tau).exp() - (-(t - a) / tau).exp())
            })
            .sum::<f64>()
}

/// Ting's (1966) force on a rigid sphere (Hertz, radius `radius`) pressed at
/// `rate` until `peak_time`, then withdrawn at the same rate: with `t1` the
/// loading time at which the contact radius had its present size, fixed by
/// `∫_{t1}^t E(t − s) dδ/ds ds = 0`, `P(t) = ∫_0^{t1} E(t − s) dP_e/ds ds`
/// (zero once no `t1` exists: the surface recovers slower than the sphere
/// withdraws). Integrated with `s = u²` (smooth) by Simpson's rule.
fn ting_force(material: &Prony, radius: f64, rate: f64, peak_time: f64, t: f64) -> f64 {
    let t1 = if t <= peak_time {
        t
    } else {
        let edge = |t1: f64| {
            relaxation_integral(material, t, t1, peak_time)
                - relaxation_integral(material, t, peak_time, t)
        };
        if edge(0.0) <= 0.0 {
            return 0.0;
        }
        let (mut lo, mut hi) = (0.0, peak_time);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if edge(mid) > 0.0 { lo = mid } else { hi = mid }
        }
        0.5 * (lo + hi)
    };
    // dP_e/ds = 2√R/(1 − ν²) (v s)^{1/2} v per unit modulus; s = u².
    let nu = material.poisson_ratio();
    let c = 2.0 * radius.sqrt() / (1.0 - nu * nu) * rate.powf(1.5);
    let top = t1.sqrt();
    let n = 4000;
    let h = top / n as f64;
    let g = |u: f64| material.relaxation(t - u * u) * u * 2.0 * u;
    let mut sum = g(0.0) + g(top);
    for j in 1..n {
        sum += if j % 2 == 1 { 4.0 } else { 2.0 } * g(j as f64 * h);
    }
    c * sum * h / 3.0
}

#[test]
fn a_sphere_pressed_and_withdrawn_follows_tings_closed_form() {
    let material = tread();
    let radius = 5e-3;
    let reference = Material::new(1e6, 0.5).expect("valid");
    let law = HertzLaw::new(radius, reference).expect("valid");
    let problem = Problem::new(vec![[0.0, 0.0]], vec![0.0], vec![law], reference).expect("valid");
    // 0.2 mm in 2 ms, withdrawn at the same rate: the slow branch (1 ms)
    // keeps the surface from following, so the contact recedes and is lost
    // before the sphere is back at its start.
    let (peak_time, rate) = (2e-3, 1e-4);
    let steps = 1600;
    let dt = 2.0 * peak_time / steps as f64;
    let run = |receding| {
        let mut solver = Hereditary::with_receding(
            &problem,
            material.clone(),
            SolverOptions::default(),
            receding,
        )
        .expect("valid");
        let peak_force = ting_force(&material, radius, rate, peak_time, peak_time);
        let mut worst = 0.0f64;
        let mut lost = None;
        for n in 1..=steps {
            let t = n as f64 * dt;
            let approach = rate
                * if t <= peak_time {
                    t
                } else {
                    2.0 * peak_time - t
                };
            let step = solver.step_approach(dt, approach).expect("solves");
            let exact = ting_force(&material, radius, rate, peak_time, t);
            if exact == 0.0 && lost.is_none() {
                lost = Some(n);
            }
            worst = worst.max((step.total_force() - exact).abs() / peak_force);
        }
        (worst, lost)
    };
    let (ting, lost) = run(TING);
    // Measured 8.4e-4 of the peak force (the first step of the ramp, f taken
    // linear over a step, and the depth bands of the receding edge).
    assert!(ting < 3e-3, "Ting: worst {ting} of the peak");
    // The closed form loses contact well before the end: the check covers
    // the receding patch and the separation.
    assert!(lost.is_some_and(|n| n < steps - 100), "{lost:?}");
    // Lee–Radok's recursion applied while receding misses it by far
    // (measured 25 % of the peak).
    let (lee, _) = run(Receding::LeeRadok);
    assert!(lee > 0.1, "Lee–Radok: worst {lee} of the peak");
}

fn worst_difference(a: &[f64], b: &[f64]) -> f64 {
    let scale = b.iter().fold(0.0f64, |m, v| m.max(v.abs()));
    a.iter()
        .zip(b)
        .map(|(x, y)| (x - y).abs() / scale)
        .fold(0.0, f64::max)
}

#[test]
fn while_every_contact_grows_ting_is_lee_radok() {
    let problem = twenty_five_balls();
    let samples: Vec<(f64, f64)> = (1..=20)
        .map(|j| (1e-4 * j as f64, 10.0 * j as f64))
        .collect();
    let options = SolverOptions::default();
    let lee = run_load_history_with(&problem, tread(), options, Receding::LeeRadok, &samples)
        .expect("Lee–Radok");
    let ting = run_load_history_with(&problem, tread(), options, TING, &samples).expect("Ting");
    for (k, (a, b)) in ting.iter().zip(&lee).enumerate() {
        assert_eq!(a.receding, 0);
        assert_eq!(b.receding, 0);
        // Measured: 6e-12 of the largest force, 1.5e-12 on the approach (the
        // two solves stop at the solver's tolerance, 1e-11).
        let forces = worst_difference(&a.forces, &b.forces);
        assert!(forces < 1e-9, "step {k}: forces {forces}");
        let approach = (a.approach - b.approach).abs() / b.approach;
        assert!(approach < 1e-9, "step {k}: approach {approach}");
    }
}

fn elastic_forces(problem: &Problem<HertzLaw>, modulus: f64, load: f64) -> Vec<f64> {
    let scale = modulus / problem.material().youngs_modulus();
    let solution = solve(
        problem,
        Control::Load(load / scale),
        &SolverOptions::default(),
    )
    .expect("elastic solve");
    solution.forces.iter().map(|f| f * scale).collect()
}

#[test]
fn slow_and_fast_loading_and_unloading_are_the_elastic_limits() {
    let problem = twenty_five_balls();
    let material = tread();
    // Up to 200 N and back down to 10 N: every ball recedes, several leave.
    let limit = |duration: f64, modulus: f64| {
        let samples = ramp_hold_unload(200.0, 10.0, duration, duration, 10);
        let steps = run_load_history_with(
            &problem,
            material.clone(),
            SolverOptions::default(),
            TING,
            &samples,
        )
        .expect("history");
        assert!(steps[20..].iter().any(|s| s.receding > 0));
        steps
            .iter()
            .zip(&samples)
            .map(|(s, (_, load))| {
                worst_difference(&s.forces, &elastic_forces(&problem, modulus, *load))
            })
            .fold(0.0, f64::max)
    };
    // Measured 1.7e-5 (slow) and 2.6e-5 (fast) of the largest force.
    let slow = limit(100.0, material.long_term());
    assert!(slow < 5e-3, "slow: {slow}");
    let fast = limit(1e-9, material.instantaneous());
    assert!(fast < 5e-3, "fast: {fast}");
    // The limits differ beyond the tolerance.
    let relaxed = elastic_forces(&problem, material.long_term(), 200.0);
    let glassy = elastic_forces(&problem, material.instantaneous(), 200.0);
    assert!(worst_difference(&relaxed, &glassy) > 0.02);
}

#[test]
fn the_load_is_carried_at_every_step_down_to_one_percent() {
    let problem = twenty_five_balls();
    let samples = ramp_hold_unload(200.0, 2.0, 1e-3, 1e-3, 10);
    let steps = run_load_history_with(&problem, tread(), SolverOptions::default(), TING, &samples)
        .expect("Ting does not separate");
    for (s, (_, load)) in steps.iter().zip(&samples) {
        assert!(
            (s.total_force() - load).abs() < 1e-8 * 200.0,
            "{} vs {load}",
            s.total_force()
        );
        assert!(s.forces.iter().all(|f| *f >= 0.0));
    }
    // Lee–Radok's recursion applied while receding pulls: near the end of
    // the unloading it gives some balls tension.
    let lee = run_load_history_with(
        &problem,
        tread(),
        SolverOptions::default(),
        Receding::LeeRadok,
        &samples,
    )
    .expect("Lee–Radok runs");
    let last = lee.last().expect("steps");
    assert!(last.forces.iter().any(|f| *f < -0.01), "{:?}", last.forces);
}

#[test]
fn a_band_count_out_of_range_is_refused() {
    let problem = twenty_five_balls();
    for per_decade in [0, 1001] {
        let r = Hereditary::with_receding(
            &problem,
            tread(),
            SolverOptions::default(),
            Receding::Ting { per_decade },
        );
        assert!(matches!(r, Err(ViscoError::InvalidValue { .. })));
    }
}

/// Hertz with a stiffer start, `+ k·min(δ, d0)`: a slope drop at `d0` with
/// the law convex on either side, as a calibrated texture law whose
/// monotone cubic dips inside its first interval.
struct StiffStart {
    hertz: HertzLaw,
    stiffness: f64,
    knee: f64,
}

impl tyreroad_contact_law::ContactLaw for StiffStart {
    fn evaluate(&self, depth: f64) -> tyreroad_contact_law::LawPoint {
        let p = self.hertz.evaluate(depth);
        if !(depth > 0.0) {
            return p;
        }
        tyreroad_contact_law::LawPoint {
            force: p.force + self.stiffness * depth.min(self.knee),
            stiffness: p.stiffness
                + if depth < self.knee {
                    self.stiffness
                } else {
                    0.0
                },
        }
    }
    fn local_contact(&self, force: f64, depth: f64) -> tyreroad_contact_law::LocalContact {
        self.hertz.local_contact(force, depth)
    }
}

/// A slope drop just above the floor (a calibrated law's first knot) used to
/// cost the asperity all its bands, leaving Lee–Radok's recursion clipped
/// at zero (5.7 % of the peak off Ting's closed form here). Now the
/// depths below the drop are one base band and the bands above it keep
/// their own memories: the sphere with a stiff start follows Ting's closed
/// form for the plain sphere, off by at most what the start adds.
#[test]
fn a_law_whose_slope_drops_near_the_start_still_follows_tings_closed_form() {
    use tyreroad_contact_law::ContactLaw;
    let material = tread();
    let radius = 5e-3;
    let reference = Material::new(1e6, 0.5).expect("valid");
    let hertz = HertzLaw::new(radius, reference).expect("valid");
    let (peak_time, rate) = (2e-3, 1e-4);
    // The knee at 1 % of the peak depth; the start's slope k is Hertz's at
    // the knee (the slope halves there), its force k·d0 = 1.5e-3 of the
    // peak's.
    let knee = 0.01 * rate * peak_time;
    let stiffness = hertz.evaluate(knee).stiffness;
    let extra = stiffness * knee / hertz.evaluate(rate * peak_time).force;
    assert!(extra > 1e-3 && extra < 2e-3, "{extra}");
    let law = StiffStart {
        hertz,
        stiffness,
        knee,
    };
    assert!(tyreroad_viscoelastic::base_band_depth(&law, 1e6, 20, rate * peak_time) > knee);
    let problem = Problem::new(vec![[0.0, 0.0]], vec![0.0], vec![law], reference).expect("valid");
    let steps = 1600;
    let dt = 2.0 * peak_time / steps as f64;
    let mut solver =
        Hereditary::with_receding(&problem, material.clone(), SolverOptions::default(), TING)
            .expect("valid");
    let peak_force = ting_force(&material, radius, rate, peak_time, peak_time);
    let mut worst = 0.0f64;
    for n in 1..=steps {
        let t = n as f64 * dt;
        let approach = rate
            * if t <= peak_time {
                t
            } else {
                2.0 * peak_time - t
            };
        let step = solver.step_approach(dt, approach).expect("solves");
        let exact = ting_force(&material, radius, rate, peak_time, t);
        worst = worst.max((step.total_force() - exact).abs() / peak_force);
    }
    // The plain sphere's 3e-3 plus the start's share: up to k·d0 at the
    // glassy modulus over the peak at the relaxed one, 1.5e-3 × E0/E∞.
    // Measured 3.4e-3; with the whole law one band at the drop (the rule
    // before) 5.7e-2.
    let bound = 3e-3 + extra * material.instantaneous() / material.long_term();
    assert!(worst < bound, "worst {worst} of the peak, bound {bound}");
}
