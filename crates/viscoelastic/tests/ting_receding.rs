//! Receding contact on one sphere: the hereditary multipoint model against
//! the viscoelastic BEM, which needs no assumption on growing contacts.
//! With Lee–Radok's recursion applied while the contact recedes the test pins
//! the size of that approximation: small while the unloading stays above a
//! fifth of the peak, large near separation. With Ting's treatment (the
//! default) the receding steps stay at the loading steps' offset
//! (docs/viscoelastic.md, "Receding contacts: Ting's treatment").

use tyreroad_viscoelastic::{
    Comparison, Receding, SphereField, compare_on_spheres_with, ramp_hold_unload,
};

use crate::support;
use support::tread;

/// One sphere, R = 20 mm, 0.25 mm BEM cells (the contact spans ~40 cells).
fn sphere() -> SphereField {
    SphereField {
        side: 1,
        radius: 0.02,
        pitch: 0.016,
        gaps: vec![0.0],
        cell: 2.5e-4,
    }
}

fn compare(floor: f64, receding: Receding) -> Comparison {
    // 20 N in 2 ms, held 2 ms, unloaded to `floor` in 2 ms; 10 steps each.
    let samples = ramp_hold_unload(20.0, floor, 2e-3, 2e-3, 10);
    compare_on_spheres_with(&sphere(), &tread(), receding, &samples).expect("both run")
}

/// Relative approach difference, model against BEM, per step.
fn approach_errors(c: &Comparison) -> Vec<f64> {
    c.model_approach
        .iter()
        .zip(&c.bem_approach)
        .map(|(m, b)| (m - b) / b)
        .collect()
}

/// `∫ W dδ0` over the history (trapezoids from rest): the work the load
/// did on the tread, most of it dissipated when the unloading ends near 0.
fn work(loads: &[f64], approach: &[f64]) -> f64 {
    let mut previous = (0.0, 0.0);
    let mut sum = 0.0;
    for (k, (&w, &d)) in loads.iter().zip(approach).enumerate() {
        if k > 0 {
            sum += 0.5 * (w + previous.0) * (d - previous.1);
        }
        previous = (w, d);
    }
    sum
}

#[test]
fn lee_radok_unloading_to_a_fifth_of_the_peak_stays_within_3_5_percent_of_the_bem() {
    let errors = approach_errors(&compare(4.0, Receding::LeeRadok));
    // Growing and held contact (Lee–Radok exact): the law's own offset
    // against the BEM, measured 0.27–0.90 %.
    for (k, e) in errors[..20].iter().enumerate() {
        assert!(e.abs() < 0.01, "loading step {k}: {e}");
    }
    // Receding: measured from −0.9 % to +2.9 % at 4 N.
    for (k, e) in errors[20..].iter().enumerate() {
        assert!(e.abs() < 0.035, "unloading step {k}: {e}");
    }
}

#[test]
fn near_separation_lee_radok_over_relaxes() {
    let errors = approach_errors(&compare(1.0, Receding::LeeRadok));
    let last = errors[errors.len() - 1];
    // At 1 N (5 % of the peak) the model's approach exceeds the BEM's by
    // 10.2 %: the force it keeps for a given approach relaxes too much,
    // the regime Ting's treatment is for.
    assert!(last > 0.05 && last < 0.15, "{last}");
}

#[test]
fn ting_follows_the_bem_down_to_one_percent_of_the_peak() {
    for floor in [1.0, 0.2] {
        let c = compare(floor, Receding::default());
        let errors = approach_errors(&c);
        // Ramp and hold: Lee–Radok exact (measured −0.10 % to −0.90 %).
        for (k, e) in errors[..20].iter().enumerate() {
            assert!(e.abs() < 0.01, "floor {floor} N, loading step {k}: {e}");
        }
        // Receding: measured −0.87 % to −0.68 % (1 N), to −0.73 % at 0.2 N,
        // against +10.2 % and +16.2 % with Lee–Radok's recursion.
        for (k, e) in errors[20..].iter().enumerate() {
            assert!(e.abs() < 0.015, "floor {floor} N, unloading step {k}: {e}");
        }
        // The work of the load over the cycle (mostly dissipated): the
        // BEM's within 1.5 % (measured −1.1 %; Lee–Radok +2.4 % to +2.7 %).
        let loads: Vec<f64> = ramp_hold_unload(20.0, floor, 2e-3, 2e-3, 10)
            .iter()
            .map(|s| s.1)
            .collect();
        let model = work(&loads, &c.model_approach);
        let bem = work(&loads, &c.bem_approach);
        assert!(
            (model - bem).abs() < 0.015 * bem,
            "floor {floor} N: {model} vs {bem}"
        );
    }
}
