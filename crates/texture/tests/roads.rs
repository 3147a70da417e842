//! The hard road kinds deliver what their parameters promise: groove pitch
//! and depth, plateau fractions, skewness, joint spacing, a plausible MPD,
//! reproducibility from the seed, and named errors for bad parameters.
#![allow(clippy::unwrap_used)]

use tyreroad_texture::{
    BrushedConcrete, ExposedAggregate, HeightMap, Pave, PorousAsphalt, RoadGrid, TextureError,
    Tining, WornChipSeal, brushed_concrete, exposed_aggregate, mean_profile_depth, pave,
    porous_asphalt, tining, worn_chip_seal,
};

/// Mean of the profiles along x (`along_x`) or along y.
fn mean_profile(map: &HeightMap, along_x: bool) -> Vec<f64> {
    let (nx, ny, h) = (map.nx(), map.ny(), map.heights());
    if along_x {
        (0..nx)
            .map(|i| (0..ny).map(|j| h[j * nx + i]).sum::<f64>() / ny as f64)
            .collect()
    } else {
        (0..ny)
            .map(|j| h[j * nx..(j + 1) * nx].iter().sum::<f64>() / nx as f64)
            .collect()
    }
}

/// Normalised autocorrelation of a profile at lag `k` (samples).
fn autocorrelation(p: &[f64], k: usize) -> f64 {
    let m = p.iter().sum::<f64>() / p.len() as f64;
    let var = p.iter().map(|v| (v - m).powi(2)).sum::<f64>() / p.len() as f64;
    let n = p.len() - k;
    (0..n).map(|i| (p[i] - m) * (p[i + k] - m)).sum::<f64>() / n as f64 / var
}

/// The lag (samples) of the highest autocorrelation in `lo..=hi`.
fn best_lag(p: &[f64], lo: usize, hi: usize) -> usize {
    (lo..=hi)
        .max_by(|&a, &b| autocorrelation(p, a).total_cmp(&autocorrelation(p, b)))
        .unwrap()
}

fn median(mut v: Vec<f64>) -> f64 {
    v.sort_by(f64::total_cmp);
    v[v.len() / 2]
}

fn skewness(h: &[f64]) -> f64 {
    let n = h.len() as f64;
    let m = h.iter().sum::<f64>() / n;
    let m2 = h.iter().map(|v| (v - m).powi(2)).sum::<f64>() / n;
    let m3 = h.iter().map(|v| (v - m).powi(3)).sum::<f64>() / n;
    m3 / m2.powf(1.5)
}

/// Fraction of the points at the map's maximum (the wear plane).
fn plateau_fraction(map: &HeightMap) -> f64 {
    let (_, top) = map.min_max().unwrap();
    let h = map.heights();
    h.iter().filter(|&&v| v >= top - 1e-12).count() as f64 / h.len() as f64
}

fn mpd_mm(map: &HeightMap) -> f64 {
    mean_profile_depth(map, None).unwrap().mpd * 1e3
}

fn invalid_name(e: TextureError) -> &'static str {
    match e {
        TextureError::InvalidParameter { name, .. } => name,
        other => panic!("expected a named parameter error, got {other}"),
    }
}

#[test]
fn transverse_tining_has_its_pitch_depth_and_width() {
    // 200 × 10 mm at 0.25 mm: 16 grooves at 12.5 mm.
    let p = Tining::transverse(RoadGrid::square(800, 40, 0.25e-3), 7);
    let map = tining(&p).unwrap();
    let profile = mean_profile(&map, true);
    // Pitch: the autocorrelation peaks at 50 samples (12.5 mm), ±1 sample.
    let lag = best_lag(&profile, 25, 75);
    assert!(
        (lag as f64 * 0.25 - 12.5).abs() <= 0.25,
        "pitch {lag} samples"
    );
    // Depth: land and groove medians 4 mm apart, within 0.1 mm (mortar Sq
    // 0.05 mm).
    let h = map.heights();
    let (grooves, lands): (Vec<f64>, Vec<f64>) = h.iter().partition(|&&v| v < -2e-3);
    let depth = median(lands) - median(grooves.clone());
    assert!((depth - 4e-3).abs() < 0.1e-3, "depth {depth}");
    // Width: the grooved fraction is 3/12.5 = 0.24 within one grid column
    // per groove (0.25/12.5 = 0.02).
    let frac = grooves.len() as f64 / h.len() as f64;
    assert!((frac - 0.24).abs() <= 0.02, "grooved fraction {frac}");
    // MPD along x: the grooves dominate, about 1-2 mm for such tining.
    let mpd = mpd_mm(&map);
    assert!((0.8..2.0).contains(&mpd), "MPD {mpd} mm");
}

#[test]
fn random_tining_spaces_grooves_within_its_pitch_range() {
    let mut p = Tining::transverse(RoadGrid::square(1600, 8, 0.25e-3), 3);
    p.pitch = (12.5e-3, 25e-3);
    let map = tining(&p).unwrap();
    // Groove centres along one profile.
    let row = map.row(4);
    let mut centres = Vec::new();
    let mut start = None;
    for (i, &v) in row.iter().enumerate() {
        match (v < -2e-3, start) {
            (true, None) => start = Some(i),
            (false, Some(s)) => {
                centres.push(0.5 * (s + i - 1) as f64 * 0.25e-3);
                start = None;
            }
            _ => {}
        }
    }
    let gaps: Vec<f64> = centres.windows(2).map(|w| w[1] - w[0]).collect();
    assert!(gaps.len() >= 10, "{} grooves", centres.len());
    for g in &gaps {
        assert!(*g > 12.5e-3 - 0.3e-3 && *g < 25e-3 + 0.3e-3, "gap {g}");
    }
    let mean = gaps.iter().sum::<f64>() / gaps.len() as f64;
    assert!((mean - 18.75e-3).abs() < 3e-3, "mean pitch {mean}");
    // Not regular: the gaps spread over more than 5 mm.
    let (lo, hi) = gaps
        .iter()
        .fold((f64::MAX, f64::MIN), |(a, b), &g| (a.min(g), b.max(g)));
    assert!(hi - lo > 5e-3, "gaps {lo} to {hi}");
}

#[test]
fn longitudinal_tining_runs_along_x() {
    let p = Tining::longitudinal(RoadGrid::square(400, 800, 0.25e-3), 7);
    let map = tining(&p).unwrap();
    let across = mean_profile(&map, false);
    let lag = best_lag(&across, 25, 75);
    assert!(
        (lag as f64 * 0.25 - 12.5).abs() <= 0.25,
        "pitch {lag} samples"
    );
    // Along x each profile is a land or a groove bottom: only the mortar
    // is left for the MPD (well below 0.5 mm).
    let mpd = mpd_mm(&map);
    assert!(mpd < 0.5, "MPD {mpd} mm");
}

#[test]
fn brushed_concrete_striations_are_transverse() {
    let p = BrushedConcrete::new(RoadGrid::square(400, 400, 0.1e-3), 5);
    let map = brushed_concrete(&p).unwrap();
    // 1 mm apart, the heights still correlate along y (the striations' long
    // axis) but much less along x.
    let along_x = autocorrelation(map.row(200), 10);
    let col: Vec<f64> = (0..400).map(|j| map.heights()[j * 400 + 200]).collect();
    let along_y = autocorrelation(&col, 10);
    assert!(along_y > 0.7 && along_x < 0.5, "ρx {along_x}, ρy {along_y}");
    let sq = map.rms().unwrap();
    // Sq of striations (0.2 mm) and mortar (0.05 mm) in quadrature, ±5 %.
    let expected = (0.2e-3f64.powi(2) + 0.05e-3f64.powi(2)).sqrt();
    assert!((sq / expected - 1.0).abs() < 0.05, "Sq {sq}");
    let mpd = mpd_mm(&map);
    assert!((0.2..1.0).contains(&mpd), "MPD {mpd} mm");
}

#[test]
fn exposed_aggregate_stands_out_of_a_flat_mortar() {
    let p = ExposedAggregate::new(RoadGrid::square(400, 400, 0.1e-3), 11);
    let map = exposed_aggregate(&p).unwrap();
    let h = map.heights();
    // The mortar plane is most of the area: the median sits on it (within
    // its roughness).
    let med = median(h.to_vec());
    assert!(med.abs() < 0.1e-3, "median {med}");
    // Chippings 4-8 mm, 25-40 % exposed: summits 1-3 mm above the mortar.
    let (_, top) = map.min_max().unwrap();
    assert!(top > 1e-3 && top < 3.5e-3, "top {top}");
    let out = h.iter().filter(|&&v| v > 0.3e-3).count() as f64 / h.len() as f64;
    assert!((0.15..0.6).contains(&out), "chipping fraction {out}");
    let mpd = mpd_mm(&map);
    assert!((0.4..1.5).contains(&mpd), "MPD {mpd} mm");
}

#[test]
fn porous_asphalt_has_flat_tops_and_deep_pores() {
    let p = PorousAsphalt::new(RoadGrid::square(400, 400, 0.1e-3), 13);
    let map = porous_asphalt(&p).unwrap();
    let h = map.heights();
    let skew = skewness(h);
    assert!(skew < -0.3, "skewness {skew}");
    let plateau = plateau_fraction(&map);
    assert!((plateau - 0.2).abs() < 0.005, "plateau fraction {plateau}");
    // Pores at exactly −3 mm: about a fifth of the area.
    let pores = h.iter().filter(|&&v| v == -3e-3).count() as f64 / h.len() as f64;
    assert!((0.1..0.35).contains(&pores), "pore fraction {pores}");
    let mpd = mpd_mm(&map);
    assert!((1.0..4.0).contains(&mpd), "MPD {mpd} mm");
}

#[test]
fn worn_chip_seal_is_ground_flat_on_top() {
    let p = WornChipSeal::new(RoadGrid::square(400, 400, 0.1e-3), 17);
    let map = worn_chip_seal(&p).unwrap();
    let plateau = plateau_fraction(&map);
    assert!((plateau - 0.1).abs() < 0.005, "plateau fraction {plateau}");
    let mpd = mpd_mm(&map);
    assert!((1.0..3.0).contains(&mpd), "MPD {mpd} mm");
    let unworn = WornChipSeal {
        plateau_fraction: 0.0,
        ..p.clone()
    };
    let unworn = worn_chip_seal(&unworn).unwrap();
    assert!(plateau_fraction(&unworn) < 0.001);
    assert!(mpd_mm(&unworn) > mpd);
}

#[test]
fn pave_joints_repeat_at_the_block_pitch() {
    // 300 × 250 mm at 0.5 mm.
    let p = Pave::new(RoadGrid::square(600, 500, 0.5e-3), 19);
    let map = pave(&p).unwrap();
    // Along the profile at y = 50 mm (the middle of the first row of
    // blocks), joints (below −3 mm) every 110 mm, each 10 mm wide.
    let row = map.row(100);
    let mut runs = Vec::new();
    let mut start = None;
    for (i, &v) in row.iter().enumerate() {
        match (v < -3e-3, start) {
            (true, None) => start = Some(i),
            // A run cut by the map's edge has no centre.
            (false, Some(s)) if s > 0 => {
                runs.push((0.5 * (s + i - 1) as f64 * 0.5e-3, i - s));
                start = None;
            }
            (false, Some(_)) => {
                start = None;
            }
            _ => {}
        }
    }
    assert!(runs.len() >= 2, "{runs:?}");
    for w in runs.windows(2) {
        // Centres: the two edges cross −3 mm at up to ±0.25 mm from each
        // other (block tops ±0.5 mm), plus one sample.
        let spacing = w[1].0 - w[0].0;
        assert!((spacing - 110e-3).abs() <= 1e-3, "joint spacing {spacing}");
    }
    for &(_, len) in &runs {
        // The joint (10 mm) plus the rounded edges' last drop below −3 mm.
        let width = len as f64 * 0.5e-3;
        assert!((10e-3..16e-3).contains(&width), "joint width {width}");
    }
    // Joint floors at −4 mm (stone roughness 0.1 mm).
    let floor = median(row.iter().copied().filter(|&v| v < -3e-3).collect());
    assert!((floor + 4e-3).abs() < 0.3e-3, "joint floor {floor}");
    // Block tops within ±0.5 mm (spread 1 mm) plus roughness.
    let top = row[40];
    assert!(top.abs() < 0.9e-3, "block top {top}");
}

#[test]
fn every_kind_is_reproducible_and_seeded() {
    let g = RoadGrid::square(120, 100, 0.25e-3);
    type Make = fn(RoadGrid, u64) -> HeightMap;
    let kinds: [(&str, Make); 7] = [
        ("transverse", |g, s| {
            tining(&Tining::transverse(g, s)).unwrap()
        }),
        ("longitudinal", |g, s| {
            tining(&Tining::longitudinal(g, s)).unwrap()
        }),
        ("brushed", |g, s| {
            brushed_concrete(&BrushedConcrete::new(g, s)).unwrap()
        }),
        ("exposed", |g, s| {
            exposed_aggregate(&ExposedAggregate::new(g, s)).unwrap()
        }),
        ("porous", |g, s| {
            porous_asphalt(&PorousAsphalt::new(g, s)).unwrap()
        }),
        ("worn", |g, s| {
            worn_chip_seal(&WornChipSeal::new(g, s)).unwrap()
        }),
        ("pave", |g, s| {
            let mut p = Pave::new(g, s);
            p.block_length = 10e-3;
            p.block_width = 10e-3;
            p.joint_width = 2e-3;
            p.edge_radius = 1e-3;
            pave(&p).unwrap()
        }),
    ];
    for (name, make) in kinds {
        let a = make(g, 42);
        assert_eq!(a, make(g, 42), "{name}: same seed, same map");
        assert_ne!(a, make(g, 43), "{name}: another seed, another map");
    }
}

#[test]
fn bad_parameters_give_named_errors() {
    let g = RoadGrid::square(100, 100, 0.25e-3);
    let base = Tining::transverse(g, 1);
    let bad = |p: Tining| invalid_name(tining(&p).unwrap_err());
    assert_eq!(
        bad(Tining {
            groove_width: 0.1e-3,
            ..base
        }),
        "groove_width"
    );
    assert_eq!(
        bad(Tining {
            groove_width: 13e-3,
            ..base
        }),
        "groove_width"
    );
    assert_eq!(
        bad(Tining {
            groove_depth: f64::NAN,
            ..base
        }),
        "groove_depth"
    );
    assert_eq!(
        bad(Tining {
            pitch: (20e-3, 15e-3),
            ..base
        }),
        "pitch"
    );
    let mut rough = base;
    rough.mortar.rms = -1.0;
    assert_eq!(bad(rough), "microtexture rms");
    // Absurd sizes are refused before anything is allocated.
    let huge = Tining::transverse(RoadGrid::square(30_000_000, 30_000_000, 1e-4), 1);
    assert!(matches!(tining(&huge), Err(TextureError::InvalidMap(_))));
    let huge = Pave::new(RoadGrid::square(usize::MAX, 2, 1e-3), 1);
    assert!(matches!(pave(&huge), Err(TextureError::InvalidMap(_))));

    let mut b = BrushedConcrete::new(g, 1);
    b.elongation = 0.5;
    assert_eq!(
        invalid_name(brushed_concrete(&b).unwrap_err()),
        "elongation"
    );
    b.elongation = 20.0;
    b.striation_rms = 0.0;
    assert_eq!(
        invalid_name(brushed_concrete(&b).unwrap_err()),
        "striation_rms"
    );
    b.striation_rms = 0.2e-3;
    b.striation_short = 5e-3;
    assert_eq!(
        invalid_name(brushed_concrete(&b).unwrap_err()),
        "striation_short"
    );
    let mut e = ExposedAggregate::new(g, 1);
    e.exposure = (0.5, 0.2);
    assert_eq!(invalid_name(exposed_aggregate(&e).unwrap_err()), "exposure");
    e.exposure = (0.2, 0.5);
    e.coverage = -1.0;
    assert_eq!(invalid_name(exposed_aggregate(&e).unwrap_err()), "coverage");
    let mut pa = PorousAsphalt::new(g, 1);
    pa.plateau_fraction = 0.95;
    assert_eq!(
        invalid_name(porous_asphalt(&pa).unwrap_err()),
        "plateau_fraction"
    );
    pa.plateau_fraction = 0.1;
    pa.pore_depth = 0.0;
    assert_eq!(invalid_name(porous_asphalt(&pa).unwrap_err()), "pore_depth");
    let mut w = WornChipSeal::new(g, 1);
    w.plateau_fraction = -0.1;
    assert_eq!(
        invalid_name(worn_chip_seal(&w).unwrap_err()),
        "plateau_fraction"
    );
    let mut pv = Pave::new(g, 1);
    pv.edge_radius = 60e-3;
    assert_eq!(invalid_name(pave(&pv).unwrap_err()), "edge_radius");
    pv.edge_radius = 5e-3;
    pv.joint_width = 0.1e-3;
    assert_eq!(invalid_name(pave(&pv).unwrap_err()), "joint_width");
    pv.joint_width = 10e-3;
    pv.height_spread = -1.0;
    assert_eq!(invalid_name(pave(&pv).unwrap_err()), "height_spread");
}

#[test]
fn plateau_summits_sit_on_the_wear_plane_without_a_paraboloid() {
    use tyreroad_texture::{SegmentOptions, segment};
    let map = worn_chip_seal(&WornChipSeal::new(RoadGrid::square(200, 200, 0.2e-3), 2026)).unwrap();
    let (_, level) = map.min_max().unwrap();
    let seg = segment(
        &map,
        &SegmentOptions {
            min_prominence: 0.2e-3,
            min_area: 2e-6,
        },
    )
    .unwrap();
    let h = map.heights();
    let mut on_plateau = 0;
    for a in seg.asperities() {
        let flat = a.cells.iter().filter(|&&c| h[c] == level).count();
        if flat >= 9 {
            // A paraboloid through the plateau's edge would lift the summit
            // above the flat top and soften the law's onset.
            on_plateau += 1;
            assert!(a.fit.is_none(), "{:?}", a.summit_cell);
            assert_eq!(a.summit_height, level);
        }
    }
    assert!(on_plateau >= 3, "{on_plateau} plateaus");
}

/// Regression (adversarial run): the chipping kinds on 20 × 20 points at
/// 1 m drew ten million 4 mm chippings, none of them resolved, and hung.
/// A grid whose spacing is more than a quarter of the smallest chipping is
/// refused by the chipping, its size, the spacing and the bound; the bound
/// itself passes.
#[test]
fn a_coarse_spacing_that_cannot_draw_a_chipping_is_refused() {
    use tyreroad_texture::{Aggregate, MIN_CHIP_CELLS, aggregate};
    assert_eq!(MIN_CHIP_CELLS, 4.0);
    let coarse = RoadGrid::square(20, 20, 1.0);
    let unresolved = |r: Result<HeightMap, TextureError>| match r {
        Err(TextureError::Unresolved {
            what,
            size,
            spacing,
            min_cells,
        }) => (what, size, spacing, min_cells),
        other => panic!("expected an unresolved chipping, got {other:?}"),
    };
    // 6/10 mm: the smallest chipping is 4 mm; 4/6.3 mm: 2.8 mm.
    let six_ten = ("smallest chipping", 4e-3, 1.0, 4.0);
    let four_six = ("smallest chipping", 2.8e-3, 1.0, 4.0);
    assert_eq!(
        unresolved(porous_asphalt(&PorousAsphalt::new(coarse, 1))),
        six_ten
    );
    assert_eq!(
        unresolved(worn_chip_seal(&WornChipSeal::new(coarse, 1))),
        six_ten
    );
    assert_eq!(
        unresolved(exposed_aggregate(&ExposedAggregate::new(coarse, 1))),
        four_six
    );
    let chips = Aggregate::new(20, 20, 1.0, 1.0, Aggregate::grading_4_6(), 1);
    let e = aggregate(&chips).unwrap_err();
    assert_eq!(
        e.to_string(),
        "unresolved smallest chipping: 0.0028 m spans fewer than 4 grid spacings of 1.0 m \
         (refine the spacing to at most 1/4 of it)"
    );
    // The coarser spacing counts: 0.75 mm along y is too coarse for 2.8 mm.
    let aniso = Aggregate::new(40, 40, 0.5e-3, 0.75e-3, Aggregate::grading_4_6(), 1);
    assert_eq!(
        unresolved(aggregate(&aniso)),
        ("smallest chipping", 2.8e-3, 0.75e-3, 4.0)
    );
    // A grading whose first sizes share its first percentage draws nothing
    // below the last of them: (1 mm, 0 %), (4 mm, 0 %) draws from 4 mm.
    let flat_start = vec![(1e-3, 0.0), (4e-3, 0.0), (6e-3, 100.0)];
    let at_limit = Aggregate::new(40, 40, 0.99e-3, 0.99e-3, flat_start, 1);
    assert!(aggregate(&at_limit).is_ok());
    // Just inside the bound, each kind is drawn (4 mm over 4 × 0.999 mm).
    let fine = RoadGrid::square(40, 40, 0.999e-3);
    assert!(porous_asphalt(&PorousAsphalt::new(fine, 1)).is_ok());
    assert!(worn_chip_seal(&WornChipSeal::new(fine, 1)).is_ok());
    let fine = RoadGrid::square(40, 40, 0.699e-3);
    assert!(exposed_aggregate(&ExposedAggregate::new(fine, 1)).is_ok());
    let just_out = RoadGrid::square(40, 40, 1.001e-3);
    assert_eq!(
        unresolved(porous_asphalt(&PorousAsphalt::new(just_out, 1))).1,
        4e-3
    );
}

/// Regression (adversarial review, 2026-11-30): the generator stopped at
/// ten million chippings without a word, leaving a map that needed more
/// short of its coverage. Such a map (14 × 14 m at 0.7 mm, coverage 20:
/// some 143 million 4/6 chippings) is refused before anything is drawn or
/// its 400 million heights allocated, naming the count.
#[test]
fn a_map_needing_more_chippings_than_the_generator_draws_is_refused() {
    use tyreroad_texture::{Aggregate, MAX_CHIPS, aggregate};
    assert_eq!(MAX_CHIPS, 10_000_000);
    let mut huge = Aggregate::new(20_000, 20_000, 0.7e-3, 0.7e-3, Aggregate::grading_4_6(), 1);
    huge.coverage = 20.0;
    match aggregate(&huge) {
        Err(TextureError::InvalidParameter {
            name,
            value,
            requirement,
        }) => {
            assert!(name.starts_with("chippings to draw"), "{name}");
            assert!(value > 1e8 && value < 1e9, "{value}");
            assert!(
                requirement.starts_with("at most 10 million"),
                "{requirement}"
            );
        }
        other => panic!("expected the chippings refused, got {other:?}"),
    }
}
