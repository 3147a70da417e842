//! The calibrated law against the closed forms it must reproduce.
#![allow(clippy::unwrap_used)]

use super::*;
use crate::contact_law::{ContactLaw, HertzLaw, Material, SneddonLaw};

fn material() -> Material {
    Material::new(6.54e6, 0.5).unwrap()
}

/// A paraboloid (Hertz's geometry) R = 5 mm on 0.05 mm cells, tabulated to
/// 0.2 mm (contact radius 1 mm, 20 cells per radius).
fn paraboloid() -> CapPatch {
    let r = 5e-3;
    CapPatch::from_fn(61, 5e-5, |x, y| -(x * x + y * y) / (2.0 * r)).unwrap()
}

#[test]
fn a_paraboloid_cap_gives_hertz_to_the_bem_discretisation() {
    let m = material();
    let table = calibrate(&paraboloid(), 0.2e-3, &m, &CalibrationOptions::default()).unwrap();
    assert!(!table.reached_border);
    let law = CalibratedLaw::new(std::sync::Arc::new(table));
    let hertz = HertzLaw::new(5e-3, m).unwrap();
    // The BEM's force converges to ~0.3 % at 20 cells per radius
    // (docs/bem.md); between the knots the cubic adds < 0.5 %. The first
    // knot sits at 0.78 µm, where a cell or two is in contact: the
    // comparison starts at 20 µm (10 % of the range).
    for d in [20e-6, 37e-6, 80e-6, 123e-6, 0.2e-3] {
        let (p, h) = (law.force(d), hertz.force(d));
        assert!((p - h).abs() < 0.015 * h, "δ = {d}: {p} vs Hertz {h}");
        let a = law.local_contact(p, d).radius;
        let ah = (5e-3 * d).sqrt();
        // Cell-count radius: ±½ cell on 10–20 cells per radius.
        assert!((a - ah).abs() < 0.05 * ah, "δ = {d}: a = {a} vs {ah}");
    }
}

#[test]
fn a_cone_gives_sneddon_to_the_bem_discretisation() {
    let m = material();
    // Semi-angle 80° from the axis: faces at 10° to the plane.
    let alpha = 80f64.to_radians();
    let patch = CapPatch::from_fn(61, 5e-5, |x, y| -(x * x + y * y).sqrt() / alpha.tan()).unwrap();
    let table = calibrate(&patch, 0.15e-3, &m, &CalibrationOptions::default()).unwrap();
    assert!(!table.reached_border);
    let law = CalibratedLaw::new(std::sync::Arc::new(table));
    let sneddon = SneddonLaw::new(alpha, m).unwrap();
    // The apex's singular pressure sits on one cell: a few % at small
    // depths, less as the contact spreads over more cells.
    for (d, tol) in [(40e-6, 0.06), (80e-6, 0.04), (0.15e-3, 0.03)] {
        let (p, s) = (law.force(d), sneddon.force(d));
        assert!((p - s).abs() < tol * s, "δ = {d}: {p} vs Sneddon {s}");
    }
}

#[test]
fn the_law_is_monotone_zero_outside_contact_and_its_slope_is_its_derivative() {
    let m = material();
    let table = calibrate(&paraboloid(), 0.2e-3, &m, &CalibrationOptions::default()).unwrap();
    let law = CalibratedLaw::new(std::sync::Arc::new(table));
    for d in [0.0, -1e-5, f64::NAN] {
        assert_eq!(law.evaluate(d).force, 0.0);
        assert_eq!(law.evaluate(d).stiffness, 0.0);
    }
    assert_eq!(law.local_contact(1.0, 0.0).radius, 0.0);
    let mut last = 0.0;
    for k in 1..=300 {
        // Past the table's end too (linear continuation).
        let d = k as f64 * 0.25e-3 / 300.0;
        let p = law.evaluate(d);
        assert!(p.force >= last, "δ = {d}");
        last = p.force;
        let h = 1e-9;
        let fd = (law.force(d + h) - law.force(d - h)) / (2.0 * h);
        assert!(
            (fd - p.stiffness).abs() <= 1e-4 * p.stiffness + 1e-6,
            "δ = {d}: {fd} vs {}",
            p.stiffness
        );
        // The inverse is the inverse.
        assert!((law.depth_for(p.force) - d).abs() < 1e-9, "δ = {d}");
    }
}

#[test]
fn equal_caps_are_solved_once_and_the_disk_cache_round_trips() {
    let m = material();
    let dir = tempfile::tempdir().unwrap();
    let small = || CapPatch::from_fn(21, 1e-4, |x, y| -(x * x + y * y) / 1e-2).unwrap();
    let c = Calibrator::new(m, CalibrationOptions::default()).with_disk_cache(dir.path());
    let a = c.law(&small(), 0.1e-3).unwrap();
    let b = c.law(&small(), 0.1e-3).unwrap();
    assert_eq!(a.table(), b.table());
    assert_eq!(
        c.counts(),
        CacheCounts {
            solved: 1,
            memory_hits: 1,
            disk_hits: 0
        }
    );
    // Another range is another table.
    c.law(&small(), 0.05e-3).unwrap();
    assert_eq!(c.counts().solved, 2);
    // A new calibrator finds the first table on disk, knot for knot.
    let fresh = Calibrator::new(m, CalibrationOptions::default()).with_disk_cache(dir.path());
    let d = fresh.law(&small(), 0.1e-3).unwrap();
    assert_eq!(
        fresh.counts(),
        CacheCounts {
            solved: 0,
            memory_hits: 0,
            disk_hits: 1
        }
    );
    for ((d1, f1, a1), (d2, f2, a2)) in a.table().knots().zip(d.table().knots()) {
        assert!((d1 - d2).abs() <= 1e-15 * d1.abs() && (f1 - f2).abs() <= 1e-15 * f1.abs());
        assert!((a1 - a2).abs() <= 1e-15 * a1.abs());
    }
}

#[test]
fn bad_input_is_a_named_error() {
    let m = material();
    let o = CalibrationOptions::default();
    let mut p = paraboloid();
    p.heights[0] = 1e-3;
    assert!(matches!(
        calibrate(&p, 1e-4, &m, &o),
        Err(FidelityError::InvalidInput {
            key: "cap patch height",
            ..
        })
    ));
    let p = paraboloid();
    assert!(matches!(
        calibrate(&p, -1.0, &m, &o),
        Err(FidelityError::InvalidInput {
            key: "calibration depth",
            ..
        })
    ));
    // Regression (adversarial run, 2026-11-30): a billion nodes ran on,
    // and a tolerance of 10 gave NaN tables; both are refused by name.
    for nodes in [2, 1_000_000_000] {
        let bad = CalibrationOptions { nodes, ..o };
        assert!(matches!(
            calibrate(&p, 1e-4, &m, &bad),
            Err(FidelityError::InvalidInput {
                key: "calibration nodes",
                ..
            })
        ));
    }
    for tolerance in [10.0, 0.0, f64::NAN] {
        let bad = CalibrationOptions { tolerance, ..o };
        assert!(matches!(
            calibrate(&p, 1e-4, &m, &bad),
            Err(FidelityError::InvalidInput {
                key: "calibration tolerance",
                ..
            })
        ));
    }
}

#[test]
fn rungs_parse_by_name_and_map_to_their_laws_and_coupling() {
    for r in RUNGS {
        assert_eq!(r.name().parse::<Fidelity>().unwrap(), r);
    }
    assert!(matches!(
        "clusters".parse::<Fidelity>(),
        Err(FidelityError::UnknownFidelity(_))
    ));
    let base = crate::multipoint::SolverOptions::default();
    assert_eq!(
        Fidelity::Wilke.rung(&base).unwrap().laws,
        LawSource::Potential
    );
    assert_eq!(
        Fidelity::Calibrated.rung(&base).unwrap().laws,
        LawSource::Calibrated
    );
    let distributed = Fidelity::Distributed.rung(&base).unwrap();
    assert_eq!(distributed.laws, LawSource::Calibrated);
    assert_eq!(
        distributed.solver.interaction,
        crate::multipoint::Interaction::DISTRIBUTED
    );
    assert_eq!(
        Fidelity::Calibrated.rung(&base).unwrap().solver.interaction,
        crate::multipoint::Interaction::Point
    );
    let clustered = Fidelity::Clustered.rung(&base).unwrap();
    assert_eq!(clustered.laws, LawSource::Calibrated);
    assert_eq!(
        clustered.solver.interaction,
        crate::multipoint::Interaction::Point
    );
    assert_eq!(
        clustered.solver.clusters,
        crate::multipoint::Clusters::Always
    );
    // The other rungs keep the caller's choice.
    assert_eq!(
        Fidelity::Wilke.rung(&base).unwrap().solver.clusters,
        base.clusters
    );
    let fields = Fidelity::CalibratedFields.rung(&base).unwrap();
    assert_eq!(fields.laws, LawSource::Calibrated);
    assert_eq!(fields.coupling, Coupling::Fields);
    assert_eq!(
        fields.solver.interaction,
        crate::multipoint::Interaction::Point
    );
    assert!(
        RUNGS
            .iter()
            .filter(|r| **r != Fidelity::CalibratedFields)
            .all(|r| r.rung(&base).unwrap().coupling == Coupling::Solver)
    );
}

/// The binned field of a paraboloid against Hertz: centred on the summit
/// (so the patch's origin is carried), weights summing to one, and the
/// pressure's second moment `⟨ρ²⟩ = 2a²/5` (`p ∝ √(1 − ρ²/a²)`) within 3 %
/// once the bins' lost inner spread is allowed for (bins of 0.19 mm keep
/// first moments exactly and drop at most `b²/6` of the second).
#[test]
fn a_paraboloid_field_is_centred_and_has_the_hertz_spread() {
    let m = material();
    let patch = paraboloid();
    let table = calibrate_with_fields(&patch, 0.2e-3, &m, &CalibrationOptions::default()).unwrap();
    let law = CalibratedLaw::with_origin(std::sync::Arc::new(table), patch.origin);
    for d in [50e-6, 0.1e-3, 0.2e-3] {
        let field = law.unit_field(d).unwrap();
        assert!(field.len() <= field::MAX_BINS_PER_SIDE.pow(2));
        let total: f64 = field.iter().map(|p| p.1).sum();
        assert!((total - 1.0).abs() < 1e-12);
        let cx: f64 = field.iter().map(|p| p.1 * p.0[0]).sum();
        let cy: f64 = field.iter().map(|p| p.1 * p.0[1]).sum();
        assert!(cx.abs() < 1e-7 && cy.abs() < 1e-7, "centroid ({cx}, {cy})");
        let spread: f64 = field
            .iter()
            .map(|p| p.1 * (p.0[0].powi(2) + p.0[1].powi(2)))
            .sum();
        let hertz = 0.4 * 5e-3 * d;
        // Lumping a bin to its centroid drops its inner spread, at most
        // b²/6 (a full bin's): measured −5.9 % at a = 0.5 mm (b²/6 is
        // 6.1 % of ⟨ρ²⟩ there), −1.7 % at a = 1 mm.
        let bin = law.table().field().unwrap().bin_size();
        let lost = bin * bin / 6.0;
        assert!(
            spread > 0.97 * hertz - lost && spread < 1.03 * hertz,
            "δ = {d}: {spread:e} vs {hertz:e} (less at most {lost:e})"
        );
    }
    // A calibrator without fields gives laws without them.
    let plain = calibrate(&patch, 0.2e-3, &m, &CalibrationOptions::default()).unwrap();
    assert!(plain.field().is_none());
    assert!(
        CalibratedLaw::new(std::sync::Arc::new(plain))
            .unit_field(1e-4)
            .is_none()
    );
}

/// The default (cheap) options against the reference on the paraboloid:
/// the same knots, forces within 2e-4 of the largest, areas within a
/// cell; and a disk cache written under one set of options is not read
/// back under another (the key hashes them).
#[test]
fn the_default_options_give_the_reference_table_and_their_own_cache_entries() {
    let m = material();
    let reference = calibrate(&paraboloid(), 0.2e-3, &m, &CalibrationOptions::reference()).unwrap();
    let cheap = calibrate(&paraboloid(), 0.2e-3, &m, &CalibrationOptions::default()).unwrap();
    let f_max = reference.max_depth();
    let (f_top, cell) = (reference.force_at(f_max).0, 5e-5 * 5e-5);
    for ((d1, f1, a1), (d2, f2, a2)) in reference.knots().zip(cheap.knots()) {
        assert_eq!(d1, d2);
        assert!((f1 - f2).abs() <= 2e-4 * f_top, "δ = {d1}: {f1} vs {f2}");
        assert!((a1 - a2).abs() <= 1.5 * cell, "δ = {d1}: {a1} vs {a2}");
    }
    // The cheap table did less BEM work (iterations × cells).
    let work = |t: &CalibratedTable| -> usize {
        let s = t.stats();
        s.iterations
            .iter()
            .zip(&s.windows)
            .map(|(i, w)| i * w[0] * w[1])
            .sum()
    };
    assert!(2 * work(&cheap) < work(&reference));
    let dir = tempfile::tempdir().unwrap();
    let small = || CapPatch::from_fn(21, 1e-4, |x, y| -(x * x + y * y) / 1e-2).unwrap();
    Calibrator::new(m, CalibrationOptions::reference())
        .with_disk_cache(dir.path())
        .law(&small(), 0.1e-3)
        .unwrap();
    let other = Calibrator::new(m, CalibrationOptions::default()).with_disk_cache(dir.path());
    other.law(&small(), 0.1e-3).unwrap();
    assert_eq!(other.counts().solved, 1);
    assert_eq!(other.counts().disk_hits, 0);
}

/// A flat top tilted by 10 µm/mm along x (2.4 × 1.6 mm, falling away at
/// 0.2 mm/mm beyond it) on 0.05 mm cells, cut at x = 0 into a west tile
/// (its summit the patch's) and an east one (its summit 2.5 µm lower).
fn tilted_top_in_two() -> (CapPatch, Vec<JointTile>) {
    let top = |x: f64, y: f64| {
        let out = (x.abs() - 1.2e-3).max(0.0).max((y.abs() - 0.8e-3).max(0.0));
        (-0.01 * (x + 1.2e-3) - 0.2 * out).min(0.0)
    };
    let patch = CapPatch::from_fn(61, 5e-5, top).unwrap();
    let west: Vec<bool> = (0..61 * 61)
        .map(|k| ((k % 61) as f64 - 30.0) * 5e-5 < 0.0)
        .collect();
    let east: Vec<bool> = west.iter().map(|w| !w).collect();
    // The east tile's highest cell: the first cell of x >= 0.
    let below_east = -top(0.0, 0.0);
    (
        patch,
        vec![
            JointTile {
                cells: west,
                below: 0.0,
            },
            JointTile {
                cells: east,
                below: below_east,
            },
        ],
    )
}

/// Conservation: at every depth of the sweep the tiles' forces and areas,
/// each read in its own depth, sum to the whole cap's (the same BEM
/// solves, split by cells); each tile's law is zero up to its own summit.
#[test]
fn tiles_of_one_body_sum_to_the_whole_cap_at_every_depth() {
    let m = material();
    let options = CalibrationOptions::default();
    let (patch, tiles) = tilted_top_in_two();
    let whole = calibrate(&patch, 0.1e-3, &m, &options).unwrap();
    let parts = calibrate_joint(&patch, 0.1e-3, &m, &options, true, &tiles).unwrap();
    assert_eq!(parts.len(), 2);
    let mut checked = 0;
    for (d, f, a) in whole.knots().filter(|k| k.0 > tiles[1].below) {
        let sum_f: f64 = parts
            .iter()
            .zip(&tiles)
            .map(|(p, t)| p.force_at(d - t.below).0)
            .sum();
        let sum_a: f64 = parts
            .iter()
            .zip(&tiles)
            .map(|(p, t)| p.area_at(d - t.below))
            .sum();
        assert!((sum_f - f).abs() < 1e-9 * f, "δ = {d}: {sum_f} vs {f}");
        assert!((sum_a - a).abs() < 1e-9 * a, "δ = {d}: {sum_a} vs {a}");
        // Both halves carry load once the tilt is pressed flat.
        if d > 0.05e-3 {
            assert!(parts.iter().all(|p| p.force_at(d).0 > 0.05 * f));
        }
        checked += 1;
    }
    assert!(checked >= 10, "{checked} knots compared");
    for (p, t) in parts.iter().zip(&tiles) {
        let law = CalibratedLaw::new(std::sync::Arc::new(p.clone())).in_body(7);
        assert_eq!(law.body(), Some(7));
        assert_eq!(law.force(0.0), 0.0);
        assert_eq!(law.force(-1e-6), 0.0);
        assert!(p.field().is_some());
        // The lower tile's table ends deeper below its own summit by as
        // much as its summit lies below the body's.
        assert!((p.max_depth() + t.below - whole.max_depth()).abs() < 1e-15);
    }
}

#[test]
fn a_tile_that_is_not_the_patchs_size_or_lies_above_the_summit_is_refused() {
    let m = material();
    let options = CalibrationOptions::default();
    let (patch, mut tiles) = tilted_top_in_two();
    tiles[0].cells.pop();
    let e = calibrate_joint(&patch, 0.1e-3, &m, &options, false, &tiles).unwrap_err();
    assert!(e.to_string().contains("tile cells"), "{e}");
    let (patch, mut tiles) = tilted_top_in_two();
    tiles[1].below = -1e-6;
    let e = calibrate_joint(&patch, 0.1e-3, &m, &options, false, &tiles).unwrap_err();
    assert!(e.to_string().contains("tile summit depth"), "{e}");
}

/// The point kernel between tiles of one body is cancelled (their tables
/// hold that coupling) and kept to every other asperity: two tiles of one
/// body at a common height carry the load where their laws' sum does,
/// whatever their distance.
#[test]
fn tiles_of_one_body_are_not_coupled_again_and_others_are() {
    use crate::multipoint::{Control, Problem, SolverOptions};
    let m = material();
    let table = std::sync::Arc::new(
        calibrate(&paraboloid(), 0.2e-3, &m, &CalibrationOptions::default()).unwrap(),
    );
    let law = CalibratedLaw::new(std::sync::Arc::clone(&table));
    let laws = vec![law.clone().in_body(3), law.clone().in_body(3), law];
    let positions = vec![[0.0, 0.0], [4e-3, 0.0], [40e-3, 0.0]];
    let problem = Problem::new(positions, vec![0.0, 0.0, 1.0e-3], laws, m).unwrap();
    let c = body_correction(&problem).unwrap();
    let f = m.boussinesq_factor();
    assert_eq!(c.pairs(), &[(0, 1, -f / 4e-3)]);
    let s = solve_calibrated(
        &problem,
        Control::Load(2.0),
        &SolverOptions::default(),
        None,
    )
    .unwrap();
    // The third cap stands 1 mm lower: out of contact.
    assert_eq!(s.forces[2], 0.0);
    let one = CalibratedLaw::new(table);
    let want = one.depth_for(1.0);
    assert!((s.approach - want).abs() < 1e-9, "{} vs {want}", s.approach);
    // The rungs that a corrected solve cannot run are refused by name.
    let distributed = SolverOptions {
        interaction: crate::multipoint::Interaction::DISTRIBUTED,
        ..SolverOptions::default()
    };
    let e = solve_calibrated(&problem, Control::Load(2.0), &distributed, None).unwrap_err();
    assert!(e.to_string().contains("split into tiles"), "{e}");
}
