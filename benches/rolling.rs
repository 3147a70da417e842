//! Rolling on synthetic dense asphalt: ~1500 asperities under a 120 × 150 mm
//! tyre footprint, 1500 N, 1 mm steps. A 20-step path is timed (one cold
//! start per chunk plus warm-started steps); multiply by 50 for the
//! 1000-step target (< 60 s on the 2-core project machine). The full timed
//! run is `cargo run --release -p tyreroad-rolling --example rolling_dense_asphalt`.

use criterion::{Criterion, criterion_group, criterion_main};
use std::hint::black_box;
use tyreroad_contact_law::Material;
use tyreroad_rolling::{
    Par, RollingConfig, RollingControl, RunOptions, SyntheticRoad, Tread, roll,
};

fn rolling(c: &mut Criterion) {
    let rubber = Material::new(6.54e6, 0.5).expect("material");
    let road = SyntheticRoad {
        length: 0.16,
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
        [0.065, 0.084, 1e-3],
        50.0 / 3.6,
        RollingControl::Load(1500.0),
    );
    let mut group = c.benchmark_group("rolling");
    group.sample_size(10);
    for chunks in [1, 2] {
        let options = RunOptions {
            chunks: Some(chunks),
            par: Par::rayon(0),
            ..RunOptions::default()
        };
        group.bench_function(
            format!("dense_asphalt_1500_asperities_20_steps_{chunks}_chunks"),
            |b| b.iter(|| black_box(roll(&road, rubber, &config, &options).expect("roll"))),
        );
    }
    group.finish();
}

criterion_group!(benches, rolling);
criterion_main!(benches);
