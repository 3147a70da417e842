//! A master curve's values against what a passive tread can measure: a
//! storage modulus that falls with frequency (refused past
//! `MAX_STORAGE_FALL`, reported below it) and moduli outside a caller's
//! plausible range (refused by line and value), from an adversarial run
//! (docs/viscoelastic.md, "Fit from a master curve").
#![allow(clippy::unwrap_used)]

use tyreroad_viscoelastic::{
    MAX_STORAGE_FALL, MasterCurve, Prony, STORAGE_NOISE, StorageFall, ViscoError, fit_prony,
};

/// Regression: rows `1,9e6,1e5` / `10,5e6,5e5` / `100,1e6,1e6` (E' falls
/// ninefold over two decades) were fitted silently. The fall, from the
/// highest E' to the lowest after it, is refused by both points.
#[test]
fn a_storage_modulus_falling_with_frequency_is_refused() {
    assert_eq!(MAX_STORAGE_FALL, 0.2);
    let curve = MasterCurve::parse_csv("f,E1,E2\n1,9e6,1e5\n10,5e6,5e5\n100,1e6,1e6\n").unwrap();
    let fall = curve.storage_fall().unwrap();
    assert_eq!(
        fall,
        StorageFall {
            from: (1.0, 9e6),
            to: (100.0, 1e6)
        }
    );
    assert!((fall.fraction() - 8.0 / 9.0).abs() < 1e-15);
    let err = fit_prony(&curve, 3, 0.5).unwrap_err();
    assert_eq!(err, ViscoError::StorageModulusFalls { fall, max: 0.2 });
    assert_eq!(
        err.to_string(),
        "the storage modulus E' falls from 9e6 Pa at 1 Hz to 1e6 Pa at 100 Hz \
         (88.8889% lower): a passive tread's E' does not decrease with frequency, and falls \
         over 20% are not measurement noise (check the columns: frequency, E', E'')"
    );
    // Rows out of frequency order are taken in order: the same fall.
    let shuffled = MasterCurve::parse_csv("100,1e6,1e6\n1,9e6,1e5\n10,5e6,5e5\n").unwrap();
    assert_eq!(shuffled.storage_fall(), Some(fall));
}

/// A noisy curve's small dips are fitted (the series smooths them) and
/// measured for the caller to report; a fall just past the bound is not.
#[test]
fn a_small_dip_in_the_storage_modulus_is_fitted_and_measured() {
    // A 5 % dip at 10 Hz in a rising curve.
    let noisy =
        MasterCurve::parse_csv("1,2e6,1e5\n10,1.9e6,3e5\n100,4e6,1e6\n1000,8e6,2e6\n").unwrap();
    let fall = noisy.storage_fall().unwrap();
    assert_eq!(fall.from, (1.0, 2e6));
    assert_eq!(fall.to, (10.0, 1.9e6));
    assert!((fall.fraction() - 0.05).abs() < 1e-12);
    assert!(fall.fraction() > STORAGE_NOISE);
    let series = fit_prony(&noisy, 3, 0.5).unwrap();
    assert!(series.long_term() > 0.0);
    // 21 % is refused, 19 % fitted.
    let at = |e: f64| MasterCurve::parse_csv(&format!("1,2e6,1e5\n10,{e},3e5\n100,4e6,1e6\n"));
    assert!(matches!(
        fit_prony(&at(2e6 * 0.79).unwrap(), 3, 0.5),
        Err(ViscoError::StorageModulusFalls { .. })
    ));
    assert!(fit_prony(&at(2e6 * 0.81).unwrap(), 3, 0.5).is_ok());
    // A Prony series' own curve never falls.
    let own = Prony::new(1e6, vec![], 0.5).unwrap();
    let flat = MasterCurve::of(&own, &[1.0, 10.0, 100.0]);
    assert_eq!(flat.storage_fall(), None);
}

/// Regression: E' = E'' = 1e-3 Pa and 1e300 Pa were both refused as
/// "invalid long-term modulus E∞ (Pa): 0", a value no row held. Within a
/// caller's range, the row's own modulus is named by line and column.
#[test]
fn master_curve_moduli_out_of_range_are_named_by_line_and_value() {
    let range = [1e3, 1e12];
    let tiny = MasterCurve::parse_csv_within("f,E1,E2\n1,1e-3,1e-3\n10,2e-3,1e-3\n", range);
    assert_eq!(
        tiny.unwrap_err().to_string(),
        "master curve line 2, column 2 (storage modulus E' (Pa)): 0.001 is out of range \
         (expected within [1000, 1e12] Pa)"
    );
    let huge = MasterCurve::parse_csv_within("f,E1,E2\n1,2e6,1e5\n10,1e301,1e300\n", range);
    assert_eq!(
        huge.unwrap_err().to_string(),
        "master curve line 3, column 2 (storage modulus E' (Pa)): 1e301 is out of range \
         (expected within [1000, 1e12] Pa)"
    );
    let loss = MasterCurve::parse_csv_within("1,2e6,1e5\n10,3e6,5e12\n", range);
    assert!(
        matches!(&loss, Err(ViscoError::Csv { line: 2, column: 3, message, .. })
            if message == "5e12 is out of range (expected within [0, 1e12] Pa)"),
        "{loss:?}"
    );
    // The limits pass, and without a range only the sign is checked.
    assert!(MasterCurve::parse_csv_within("1,1e3,0\n10,1e12,1e12\n", range).is_ok());
    assert!(MasterCurve::parse_csv("1,1e-3,1e-3\n10,2e-3,1e-3\n").is_ok());
}

/// Regression (review, 2026-11-30): a curve built in code with one
/// frequency given twice at other moduli was fitted, and its "fall" was
/// reported at a single frequency. It is refused naming both rows; the
/// same row given twice is one point.
#[test]
fn a_frequency_given_twice_with_other_moduli_is_refused() {
    let curve = MasterCurve {
        frequency: vec![1.0, 10.0, 10.0, 100.0],
        storage: vec![2e6, 3e6, 2.5e6, 4e6],
        loss: vec![1e5, 2e5, 2e5, 3e5],
    };
    assert_eq!(
        fit_prony(&curve, 3, 0.5).unwrap_err(),
        ViscoError::ConflictingFrequency {
            first_line: 2,
            line: 3,
            frequency: 10.0
        }
    );
    let repeated = MasterCurve {
        storage: vec![2e6, 3e6, 3e6, 4e6],
        ..curve
    };
    assert!(fit_prony(&repeated, 3, 0.5).is_ok());
}
