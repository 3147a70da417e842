//! Where the tread touches each cap ([`crate::rolling::ContactSlope`])
//! against the BEM rolling reference: a field of spheres under a curved
//! tyre.

use super::*;
use crate::bem::{Sphere, spherical_caps};
use crate::contact_law::HertzLaw;
use crate::multipoint::AsperitySet;
use crate::rolling::{ContactSlope, Road, RunOptions, Tread, roll};

const E: f64 = 6.54e6;
const R: f64 = 5e-3;
const DX: f64 = 1e-4;
const PITCH: f64 = 3.5e-3;
const LOAD: f64 = 40.0;

fn material() -> Material {
    Material::new(E, 0.5).expect("valid material")
}

/// 13 × 5 spheres at 3.5 mm pitch, summits in three heights (0, −40 µm,
/// −80 µm in a fixed pattern) so that neighbours carry unequal loads.
fn summits() -> Vec<([f64; 2], f64)> {
    let mut s = Vec::new();
    for i in 0..13 {
        for j in 0..5 {
            let h = [0.0, -4e-5, -8e-5][(3 * i + 2 * j) % 3];
            s.push(([2e-3 + PITCH * i as f64, -7e-3 + PITCH * j as f64], h));
        }
    }
    s
}

fn road_map() -> Field {
    let grid = Grid::new(461, 181, DX, DX)
        .and_then(|g| g.with_origin([0.0, -9e-3]))
        .expect("valid grid");
    let spheres: Vec<Sphere> = summits()
        .iter()
        .map(|&(centre, summit)| Sphere {
            centre,
            radius: R,
            summit,
        })
        .collect();
    spherical_caps(&grid, &spheres, -R).expect("valid spheres")
}

/// A tyre of 60 mm radius along the path (flat across) centred on the
/// road, 40 N: three columns of spheres carry the load. Sensors: 3.5 mm strips across the road, one per column
/// of spheres, each strip's edges halfway between two columns.
fn config(slope: ContactSlope) -> RollingConfig {
    let tyre = Tread::Tyre {
        radius_x: 0.06,
        radius_y: 10.0,
        length: 40e-3,
        width: 16e-3,
    };
    let xc = 2e-3 + 6.0 * PITCH;
    let mut c = RollingConfig::new(tyre, [xc, xc, 1e-3], 10.0, RollingControl::Load(LOAD));
    c.contact_slope = slope;
    c.sensors = (0..13)
        .map(|i| {
            let x = 2e-3 + PITCH * i as f64;
            Sensor {
                name: format!("column {i}"),
                x: [x - 0.5 * PITCH, x + 0.5 * PITCH],
                y: [-1.0, 1.0],
            }
        })
        .collect();
    c
}

/// The two placements against the BEM on a field of spheres (Hertz laws,
/// point coupling within about 1 %), under a 60 mm tyre whose profile
/// slopes by 0.06 at the outer loaded columns. Measured: load on the wrong
/// column 0.18 % (profile) and 1.16 % (deformed: the neighbours' slope
/// takes 0.2 N from each outer column to the centre one, which the BEM
/// does not), approach 2.0 % and 1.5 % off (the tread's curvature added to
/// each sphere's, 8 %, is not in the Hertz law). The test holds both
/// within those figures, so a change to either placement shows; a solve
/// of the step by [`crate::rolling::settled_step`] is the run's step.
#[test]
fn both_contact_slopes_put_each_column_s_load_near_the_bem_s() {
    let bem = roll_bem(
        &road_map(),
        material(),
        &config(ContactSlope::Profile),
        &BemRollingOptions {
            tolerance: 1e-9,
            par: Par::Seq,
            ..BemRollingOptions::default()
        },
    )
    .expect("BEM run");
    let (positions, heights): (Vec<_>, Vec<_>) = summits().into_iter().unzip();
    let law = HertzLaw::new(R, material()).expect("Hertz law");
    let set = AsperitySet::new(positions.clone(), heights, vec![law; positions.len()])
        .expect("valid set");
    let road = Road::new(set)
        .with_summit_radii(vec![R; positions.len()])
        .expect("radii");
    let error = |slope| {
        let config = config(slope);
        let run = roll(&road, material(), &config, &RunOptions::default()).expect("run");
        let (m, b) = (&run.steps[0], &bem.steps[0]);
        assert!((m.total_force - LOAD).abs() < 1e-9 * LOAD);
        let columns: f64 = m.sensor_forces.iter().sum();
        assert!((columns - LOAD).abs() < 1e-6 * LOAD, "{columns}");
        let settled = crate::rolling::settled_step(
            &road,
            material(),
            &config,
            config.start,
            crate::multipoint::Control::Load(LOAD),
        )
        .expect("settled step")
        .expect("spheres under the footprint");
        for (&id, &force) in m.contact_ids.iter().zip(&m.contact_forces) {
            let a = settled.ids.iter().position(|&i| i == id).expect("selected");
            assert!(
                (settled.solution.forces[a] - force).abs() < 1e-6 * LOAD,
                "{slope:?}, sphere {id}: {} N settled, {force} N rolled",
                settled.solution.forces[a]
            );
        }
        let wrong = m
            .sensor_forces
            .iter()
            .zip(&b.sensor_forces)
            .map(|(m, b)| (m - b).abs())
            .sum::<f64>()
            / (2.0 * LOAD);
        (wrong, (m.approach - b.approach).abs() / b.approach)
    };
    let (profile, profile_approach) = error(ContactSlope::Profile);
    let (deformed, deformed_approach) = error(ContactSlope::Deformed);
    assert!(profile < 0.004, "profile: {profile}");
    assert!(deformed > 0.006 && deformed < 0.015, "deformed: {deformed}");
    assert!(profile_approach < 0.025, "{profile_approach}");
    assert!(deformed_approach < 0.02, "{deformed_approach}");
}

/// A lone loaded cap has no neighbour to tilt the tread: the deformed
/// placement is the profile's, to the last bit.
#[test]
fn a_lone_contact_is_placed_as_under_the_profile() {
    let law = HertzLaw::new(R, material()).expect("Hertz law");
    let set = AsperitySet::new(vec![[20e-3, 1e-3]], vec![0.0], vec![law]).expect("valid set");
    let road = Road::new(set).with_summit_radii(vec![R]).expect("radii");
    let run = |slope| {
        let mut c = config(slope);
        c.control = RollingControl::Load(5.0);
        roll(&road, material(), &c, &RunOptions::default()).expect("run")
    };
    let (p, d) = (run(ContactSlope::Profile), run(ContactSlope::Deformed));
    assert_eq!(p.steps[0].approach, d.steps[0].approach);
    assert_eq!(p.steps[0].sensor_forces, d.steps[0].sensor_forces);
}
