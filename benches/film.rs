//! Film post-processing: analysis of a synthetic 25-print scan of
//! 2000 × 2000 px (the paper's 25 balls at 419 N, LLW curve B, 22 µm pixels,
//! 16-bit, grain σ_D = 0.01, blur 1 px).

use std::hint::black_box;

use criterion::{Criterion, criterion_group, criterion_main};
use tyreroad_film::{
    AnalysisOptions, Calibration, FilmResponse, HertzPrint, Layout, LlwCurve, Origin,
    RenderOptions, Scanner, analyse, hertz_pressure_map, match_layout, paper_hertz_rows, render,
};

fn bench_film(c: &mut Criterion) {
    let film = FilmResponse::new(
        Calibration::llw(LlwCurve::B).expect("shipped LLW chart"),
        Scanner::default(),
    );
    let rows = paper_hertz_rows(&[419.0], 6.54e6, 0.5, 5e-3);
    let prints: Vec<HertzPrint> = rows
        .iter()
        .map(|r| HertzPrint {
            x: r.x_m,
            y: r.y_m,
            force: r.force_n,
            radius: r.radius_m,
        })
        .collect();
    let map = hertz_pressure_map(&prints, 2000, 2000, 22e-6).expect("map");
    let options = RenderOptions {
        grain_sigma: 0.01,
        blur_sigma_px: 1.0,
        ..RenderOptions::default()
    };
    let scan = render(&map, &film, &options).expect("render");
    let layout = Layout::paper_grid(10e-3);
    let mut g = c.benchmark_group("film");
    g.sample_size(10);
    g.bench_function("analyse_25_prints_2000x2000", |b| {
        b.iter(|| {
            let det =
                analyse(black_box(&scan), &film, &AnalysisOptions::default()).expect("analyse");
            let m = match_layout(&det, &layout, Origin::Centroid, None).expect("match");
            black_box(m.matches.len())
        })
    });
    g.finish();
}

criterion_group!(benches, bench_film);
criterion_main!(benches);
