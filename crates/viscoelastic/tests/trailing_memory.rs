//! What the multipoint rolling run keeps of an asperity the footprint window
//! has passed (`TrailingMemory`, docs/viscoelastic.md, "Where the memory
//! lives"). The viscoelastic rolling BEM forgets the rubber cells that leave
//! its window (the tread lifts off with its memory); the multipoint run must
//! do the same, or it carries the recovering depression of every asperity
//! passed along the path and sinks deeper than the BEM, by more the further
//! it rolls (docs/viscoelastic.md, "Rolling against the viscoelastic BEM":
//! 1.3 % growing to 3.0 % over 100 steps before, 1.0 % flat after).
//!
//! Reference: two spheres further apart than the window is long are never
//! under it together, so once the first has left the window the second
//! rolls exactly as it does alone on the road.

use tyreroad_contact_law::{HertzLaw, Material};
use tyreroad_multipoint::AsperitySet;
use tyreroad_rolling::{Road, RollingConfig, RollingControl, Tread};
use tyreroad_viscoelastic::{TrailingMemory, ViscoRollOptions, ViscoRolling, roll_viscoelastic};

use crate::support;
use support::tread;

const FIRST: f64 = 0.05;
const SECOND: f64 = 0.08;

/// Spheres of radius 5 mm with their summits at height 0, at `xs` (y = 0).
fn road(xs: &[f64], reference: Material) -> Road<HertzLaw> {
    let law = HertzLaw::new(5e-3, reference).expect("valid");
    let positions = xs.iter().map(|&x| [x, 0.0]).collect();
    let set = AsperitySet::new(positions, vec![0.0; xs.len()], vec![law; xs.len()]).expect("valid");
    Road::new(set)
}

/// A 20 × 20 mm tyre footprint (no margin) from 30 to 100 mm by 0.5 mm at
/// 10 m/s (a step is 50 µs, the window passes a point in 2 ms, about the
/// slow branch's time) at a fixed approach of 0.5 mm.
fn config() -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.3,
        length: 0.02,
        width: 0.02,
    };
    let mut config = RollingConfig::new(
        tyre,
        [0.03, 0.10, 5e-4],
        10.0,
        RollingControl::Approach(5e-4),
    );
    config.margin = 0.0;
    config
}

fn roll(xs: &[f64], trailing: TrailingMemory) -> ViscoRolling {
    let reference = Material::new(1e6, 0.5).expect("valid");
    let options = ViscoRollOptions {
        trailing,
        ..ViscoRollOptions::default()
    };
    roll_viscoelastic(
        &road(xs, reference),
        reference,
        &tread(),
        &config(),
        &options,
    )
    .expect("runs")
}

/// Worst difference, relative to its peak, of the second sphere's force in
/// `both` (its id is 1) from the same sphere's alone (id 0).
fn second_sphere_difference(both: &ViscoRolling, alone: &ViscoRolling) -> (f64, usize) {
    let force = |run: &ViscoRolling, id: usize| -> Vec<f64> {
        run.result
            .steps
            .iter()
            .map(|s| {
                s.contact_ids
                    .iter()
                    .position(|&i| i == id)
                    .map_or(0.0, |a| s.contact_forces[a])
            })
            .collect()
    };
    let (a, b) = (force(both, 1), force(alone, 0));
    let peak = b.iter().fold(0.0f64, |m, &p| m.max(p));
    assert!(peak > 0.0, "the second sphere is loaded");
    let loaded = b.iter().filter(|&&p| p > 0.0).count();
    let worst = a
        .iter()
        .zip(&b)
        .map(|(x, y)| (x - y).abs() / peak)
        .fold(0.0, f64::max);
    (worst, loaded)
}

#[test]
fn an_asperity_the_window_has_passed_no_longer_loads_the_footprint() {
    let (half, step) = (0.01, 5e-4);
    // Never under the window together: 30 mm apart, the window 20 mm long.
    assert!(SECOND - FIRST > 2.0 * half + step);
    let both = roll(&[FIRST, SECOND], TrailingMemory::LiftsOff);
    let alone = roll(&[SECOND], TrailingMemory::LiftsOff);
    let (worst, loaded) = second_sphere_difference(&both, &alone);
    assert!(loaded > 20, "{loaded} loaded steps");
    // The same problem step by step (warm starts differ: the solver's
    // tolerance is all that is left).
    assert!(worst < 1e-6, "second sphere off its lone run by {worst}");
    // Once the first sphere has left the window nothing remembers it.
    let config = config();
    for (k, &held) in both.memory.iter().enumerate() {
        if config.position(k) - half > FIRST + 1e-9 && config.position(k) + half < SECOND {
            assert_eq!(held, 0, "step {k}: {held} memories between the spheres");
        }
    }
    // Hunter's road-attached half-space keeps the first sphere's recovering
    // depression under the second (30 mm away, 1 ms later): the second
    // sphere then carries less (measured: 1.5 % of its peak). The check
    // above can fail.
    let kept = roll(&[FIRST, SECOND], TrailingMemory::Kept);
    let (hunter, _) = second_sphere_difference(&kept, &alone);
    eprintln!("lifts off: {worst:.1e}; kept: {hunter:.2e} of the peak");
    assert!(
        hunter > 5e-3,
        "kept memory changes the second sphere by {hunter}"
    );
}
