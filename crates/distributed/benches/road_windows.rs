//! What a rank pays to build its road windows (docs/performance.md,
//! "Distributed rolling"): the keep pass over a whole synthetic road
//! (`SyntheticRoad::windows`, once per rank), one 0.3 m window of it, and
//! the whole road built at once (what every rank did before).

use criterion::{Criterion, criterion_group, criterion_main};
use tyreroad::contact_law::Material;
use tyreroad_rolling::SyntheticRoad;

fn road(length: f64) -> SyntheticRoad {
    // The road of crates/distributed/scripts/long_road.sh.
    SyntheticRoad {
        length,
        width: 0.08,
        ..SyntheticRoad::default()
    }
}

fn windows(c: &mut Criterion) {
    let rubber = Material::new(6.54e6, 0.5).expect("material");
    let mut g = c.benchmark_group("road_windows");
    g.sample_size(10);
    for length in [2.1, 10.1] {
        let road = road(length);
        g.bench_function(format!("keep_pass_{length}m"), |b| {
            b.iter(|| road.windows(rubber).expect("windows").count());
        });
        let windows = road.windows(rubber).expect("windows");
        g.bench_function(format!("one_0.3m_window_of_{length}m"), |b| {
            b.iter(|| windows.window([1.0, 1.3]).expect("window").len());
        });
        g.bench_function(format!("whole_road_{length}m"), |b| {
            b.iter(|| road.sphere_road(rubber).expect("road").len());
        });
    }
    g.finish();
}

criterion_group!(benches, windows);
criterion_main!(benches);
