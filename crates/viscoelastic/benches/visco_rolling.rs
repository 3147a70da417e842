//! Viscoelastic rolling against elastic rolling on the same road and path
//! (docs/performance.md, "Viscoelastic rolling"): synthetic dense asphalt
//! (≈ 1500 asperities under a 120 × 150 mm tyre footprint), 1500 N, 1 mm
//! steps at 50 km/h, 40 steps, one thread each (the viscoelastic run is
//! sequential along the path; the elastic one runs as one chunk). The
//! tread is the five-branch compound of
//! `fixtures/rolling_tyre_dense_asphalt_visco.toml`. Target: the
//! viscoelastic run within 2× of the elastic one.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use tyreroad_contact_law::Material;
use tyreroad_rolling::{
    Par, RollingConfig, RollingControl, RunOptions, SyntheticRoad, Tread, roll,
};
use tyreroad_viscoelastic::{Branch, Prony, ViscoRollOptions, roll_viscoelastic};

fn rolling(c: &mut Criterion) {
    let rubber = Material::new(6.54e6, 0.5).expect("material");
    let road = SyntheticRoad {
        length: 0.2,
        ..SyntheticRoad::default()
    }
    .sphere_road(rubber)
    .expect("road");
    let tread = Tread::Tyre {
        radius_x: 0.3,
        radius_y: 0.5,
        length: 0.12,
        width: 0.15,
    };
    let config = RollingConfig::new(
        tread,
        [0.065, 0.104, 1e-3],
        50.0 / 3.6,
        RollingControl::Load(1500.0),
    );
    let branches = [
        (2e6, 1e-2),
        (3e6, 1e-3),
        (4e6, 1e-4),
        (6e6, 1e-5),
        (8e6, 1e-6),
    ]
    .map(|(modulus, relaxation_time)| Branch {
        modulus,
        relaxation_time,
    })
    .to_vec();
    let compound = Prony::new(4e6, branches, 0.5).expect("series");
    let mut group = c.benchmark_group("visco_rolling");
    group.sample_size(10);
    let options = RunOptions {
        chunks: Some(1),
        par: Par::Seq,
        ..RunOptions::default()
    };
    group.bench_function("elastic_dense_asphalt_40_steps", |b| {
        b.iter(|| black_box(roll(&road, rubber, &config, &options).expect("roll")))
    });
    let visco = ViscoRollOptions::default();
    group.bench_function("viscoelastic_dense_asphalt_40_steps", |b| {
        b.iter(|| {
            black_box(roll_viscoelastic(&road, rubber, &compound, &config, &visco).expect("roll"))
        })
    });
    group.finish();
}

criterion_group!(benches, rolling);
criterion_main!(benches);
