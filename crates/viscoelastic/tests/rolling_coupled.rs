//! Viscoelastic rolling under a caller's pair correction
//! (`roll_viscoelastic_coupled`) against independent references:
//!
//! - a correction proportional to the point kernel on every pair,
//!   `C = α T`, is the uncoupled hereditary run of a tread and a reference
//!   modulus both divided by `1 + α` (the laws unchanged): then
//!   `w' = (1 + α) w`, the branch variables and `h` are unchanged, and the
//!   interaction `K̃ w'` is `(1 + α) K̃ w`. This holds at any speed, so it
//!   checks that the correction acts on the memory `h` as the point kernel
//!   does and that it is scaled by `E_ref/E_eff`;
//! - a depth-dependent correction (the fixed point takes rounds): slow
//!   rolling is the elastic coupled run (`tyreroad_rolling::roll_coupled`)
//!   with `E∞`, fast rolling the one with `E∞ + Σ E_k`, step by step,
//!   asperity by asperity and sensor by sensor (each contact counted on
//!   the coupling's spread);
//! - a fixed point that cannot settle is each step's recorded failure.

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::PairCorrection;
use tyreroad_rolling::{
    CouplingState, Road, RollingConfig, RollingControl, RollingResult, RunOptions, Sensor, Spread,
    StepCoupling, StepStatus, SyntheticRoad, Tread, roll_coupled,
};
use tyreroad_viscoelastic::{
    Prony, ViscoRollOptions, roll_viscoelastic, roll_viscoelastic_coupled,
};

use crate::support;
use support::tread;

type Law = PotentialLaw<Sphere>;

/// 0.15 × 0.05 m of random spherical summits, laws on `material`.
fn road(material: Material) -> Road<Law> {
    SyntheticRoad {
        seed: 18,
        length: 0.15,
        width: 0.05,
        ..SyntheticRoad::default()
    }
    .sphere_road(material)
    .expect("valid road")
}

/// A 40 × 40 mm tyre from 30 to 100 mm by 1 mm under 60 N, two sensors;
/// `margin` (m) beyond its box.
fn config(speed: f64, margin: f64) -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.3,
        length: 0.04,
        width: 0.04,
    };
    let mut config =
        RollingConfig::new(tyre, [0.03, 0.10, 1e-3], speed, RollingControl::Load(60.0));
    config.margin = margin;
    config.sensors = vec![
        Sensor {
            name: "centre".into(),
            x: [0.07, 0.08],
            y: [-0.005, 0.005],
        },
        Sensor {
            name: "side".into(),
            x: [0.07, 0.08],
            y: [0.005, 0.015],
        },
    ];
    config
}

/// A test correction for laws of modulus `modulus`: on every pair closer
/// than 15 mm, `C_ij = α f (1 + (δ_i⁺ + δ_j⁺)/depth) / r_ij` with
/// `f = (1 − ν²)/(π E)` (`depth = ∞`: `α T` on every pair, settled by the
/// fixed point's first round); with a finite depth each contact's force
/// is spread on two points 1 mm apart.
struct Toy {
    modulus: f64,
    alpha: f64,
    depth: f64,
    rounds: usize,
    tolerance: f64,
    spread: bool,
}

impl Toy {
    fn new(modulus: f64, alpha: f64, depth: f64) -> Self {
        Self {
            modulus,
            alpha,
            depth,
            rounds: 40,
            tolerance: 1e-10,
            spread: depth.is_finite(),
        }
    }
}

impl StepCoupling<Law> for Toy {
    fn correction(&self, state: &CouplingState<'_, '_, Law>) -> Result<PairCorrection, String> {
        let p = state.problem.positions();
        let f = (1.0 - 0.25) / (std::f64::consts::PI * self.modulus);
        let mut pairs = Vec::new();
        for i in 0..p.len() {
            for j in i + 1..p.len() {
                let r = (p[i][0] - p[j][0]).hypot(p[i][1] - p[j][1]);
                // Every pair for `α T`: the equivalence needs the whole kernel.
                if r < 0.015 || self.depth.is_infinite() {
                    let d = state.depths[i].max(0.0) + state.depths[j].max(0.0);
                    pairs.push((i, j, self.alpha * f * (1.0 + d / self.depth) / r));
                }
            }
        }
        PairCorrection::new(p.len(), pairs).map_err(|e| e.to_string())
    }
    fn tolerance(&self) -> f64 {
        self.tolerance
    }
    fn max_rounds(&self) -> usize {
        self.rounds
    }
    fn key(&self) -> u64 {
        0
    }
    fn spread(&self, _law: &Law, _depth: f64) -> Option<Spread> {
        self.spread.then(|| Spread {
            points: vec![([-5e-4, 0.0], 0.5), ([5e-4, 0.0], 0.5)],
            cell: 5e-4,
        })
    }
}

/// Worst per-step differences of `a` from `b`: approach (relative), and
/// each asperity's and sensor's force relative to the step's largest.
fn worst(a: &RollingResult, b: &RollingResult) -> (f64, f64) {
    let (mut approach, mut forces) = (0.0f64, 0.0f64);
    assert_eq!(a.steps.len(), b.steps.len());
    for (x, y) in a.steps.iter().zip(&b.steps) {
        approach = approach.max((x.approach / y.approach - 1.0).abs());
        let scale = y.contact_forces.iter().fold(0.0f64, |m, &p| m.max(p));
        let force = |s: &tyreroad_rolling::StepRecord, id: usize| {
            s.contact_ids
                .iter()
                .position(|&i| i == id)
                .map_or(0.0, |k| s.contact_forces[k])
        };
        for &id in x.contact_ids.iter().chain(&y.contact_ids) {
            forces = forces.max((force(x, id) - force(y, id)).abs() / scale);
        }
        for (p, q) in x.sensor_forces.iter().zip(&y.sensor_forces) {
            forces = forces.max((p - q).abs() / scale);
        }
    }
    (approach, forces)
}

fn coupled(tread: &Prony, config: &RollingConfig, coupling: &Toy) -> RollingResult {
    let reference = Material::new(coupling.modulus, 0.5).expect("valid");
    let run = roll_viscoelastic_coupled(
        &road(reference),
        reference,
        tread,
        config,
        &ViscoRollOptions::default(),
        coupling,
    )
    .expect("coupled viscoelastic run");
    assert!(
        run.result
            .steps
            .iter()
            .all(|s| s.status != StepStatus::Failed && s.contacts > 0)
    );
    run.result
}

#[test]
fn a_kernel_proportional_correction_is_a_softer_tread_at_any_speed() {
    let (alpha, reference) = (0.3, 1e6);
    let tread = tread();
    let scaled = Prony::new(
        tread.long_term() / (1.0 + alpha),
        tread
            .branches()
            .iter()
            .map(|b| tyreroad_viscoelastic::Branch {
                modulus: b.modulus / (1.0 + alpha),
                ..*b
            })
            .collect(),
        0.5,
    )
    .expect("valid");
    let laws = Material::new(reference, 0.5).expect("valid");
    let declared = Material::new(reference / (1.0 + alpha), 0.5).expect("valid");
    // 1 m/s: a step (1 ms) is the slow branch's τ (E_eff = 4.0 MPa against
    // E∞ = 2 MPa), so the memory matters; the 20 mm margin lets it fade
    // before an asperity leaves the window (the memory of an asperity no
    // longer selected acts through the point kernel only: at 10 m/s, where
    // it has not faded, this comparison is off by 6e-4).
    let config = config(1.0, 0.02);
    let with = coupled(&tread, &config, &Toy::new(reference, alpha, f64::INFINITY));
    let expected = roll_viscoelastic(
        &road(laws),
        declared,
        &scaled,
        &config,
        &ViscoRollOptions::default(),
    )
    .expect("reference run")
    .result;
    let plain = roll_viscoelastic(
        &road(laws),
        laws,
        &tread,
        &config,
        &ViscoRollOptions::default(),
    )
    .expect("uncoupled run")
    .result;
    let relaxed = coupled(
        &tread,
        &self::config(1e-5, 0.02),
        &Toy::new(reference, alpha, f64::INFINITY),
    );
    let (approach, forces) = worst(&with, &expected);
    let (apart, _) = worst(&plain, &expected);
    let (memory, _) = worst(&with, &relaxed);
    eprintln!(
        "approach {approach:.2e}, forces {forces:.2e}; uncoupled {apart:.2e}, relaxed {memory:.2e}"
    );
    assert!(approach < 1e-5, "approach off by {approach}");
    assert!(forces < 1e-5, "forces off by {forces}");
    // The correction and the memory both matter, so the checks can fail.
    assert!(apart > 0.02, "coupling invisible ({apart})");
    assert!(memory > 0.1, "memory invisible ({memory})");
}

#[test]
fn coupled_rolling_is_the_elastic_coupled_run_at_either_limit() {
    let tread = tread();
    // Reference laws at 1 MPa: the step scales the correction by 1/E_eff.
    let toy = Toy::new(1e6, 0.2, 1e-3);
    let mut limits = Vec::new();
    for (speed, modulus) in [(1e-5, tread.long_term()), (5e7, tread.instantaneous())] {
        let config = config(speed, 0.0);
        let visco = coupled(&tread, &config, &toy);
        let material = Material::new(modulus, 0.5).expect("valid");
        let elastic = roll_coupled(
            &road(material),
            material,
            &config,
            &RunOptions::default(),
            &Toy::new(modulus, 0.2, 1e-3),
        )
        .expect("elastic coupled run");
        let (approach, forces) = worst(&visco, &elastic);
        eprintln!("{speed} m/s: approach {approach:.2e}, forces {forces:.2e}");
        assert!(approach < 5e-3, "{speed} m/s: approach off by {approach}");
        assert!(forces < 5e-3, "{speed} m/s: forces off by {forces}");
        limits.push(visco);
    }
    // The two limits are far apart, so either check can fail.
    assert!(worst(&limits[0], &limits[1]).0 > 0.1);
}

#[test]
fn a_fixed_point_that_cannot_settle_is_each_steps_recorded_failure() {
    let reference = Material::new(1e6, 0.5).expect("valid");
    let toy = Toy {
        rounds: 1,
        tolerance: 1e-300,
        ..Toy::new(1e6, 0.2, 1e-3)
    };
    let config = config(10.0, 0.0);
    let run = roll_viscoelastic_coupled(
        &road(reference),
        reference,
        &tread(),
        &config,
        &ViscoRollOptions::default(),
        &toy,
    )
    .expect("the run goes on");
    assert_eq!(run.result.steps.len(), config.steps());
    for s in &run.result.steps {
        assert_eq!(s.status, StepStatus::Failed, "step {}", s.index);
        assert!(s.approach.is_nan() && s.total_force.is_nan());
        assert!(
            s.residual > 0.0 && s.residual.is_finite(),
            "step {}",
            s.index
        );
    }
}
