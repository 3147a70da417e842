//! `cargo xtask calib-cost`: what a calibrated law's table costs and what a
//! cheaper calibration changes (issue 15; docs/performance.md,
//! "Calibration cost").
//!
//! On the seven road kinds of `cargo xtask validate --textures` (the same
//! maps, segmentation and range rule), every cap is calibrated twice, one
//! cap at a time on one thread (so the times are CPU times per table):
//! with [`CalibrationOptions::reference`] and with the options given. Per
//! road it prints the patch sizes, the BEM iterations per knot, the time
//! per table of both, and how far the candidate's table lands from the
//! reference's at 200 depths over its range: `max |ΔF| / F_max` and
//! `max |ΔA| / A_max`.
//!
//! The range: `APPROACH_MARGIN ×` the Wilke model's approach at the
//! largest load (the harness uses the BEM's; only the range's size matters
//! here).

use std::time::Instant;

use anyhow::{Context, Result, bail};
use tyreroad::fidelity::compare::APPROACH_MARGIN;
use tyreroad::fidelity::{
    CalibratedTable, CalibrationOptions, CapPatch, WarmStart, calibrate, cap_patch,
};
use tyreroad::multipoint::{Control, Problem, SolverOptions, solve};
use tyreroad::texture_road::{TextureRoadOptions, texture_road};

use crate::validate_textures::{KINDS, scenario};

/// Depths at which a candidate table is compared with the reference.
const PROBES: usize = 200;
/// The load (N) whose approach bounds the range (the harness's largest).
const LOAD: f64 = 300.0;

/// Options of `cargo xtask calib-cost`.
#[derive(Debug, clap::Args)]
pub struct CalibCostArgs {
    /// Cells per side of each texture (0.1 mm cells; 400 = the harness's
    /// 40 × 40 mm).
    #[arg(long, default_value_t = 400)]
    pub texture_cells: usize,
    /// Only this road (its label, e.g. "chip seal").
    #[arg(long)]
    pub kind: Option<String>,
    /// Candidate: BEM depths per table (default: the library's default).
    #[arg(long)]
    pub nodes: Option<usize>,
    /// Candidate: BEM tolerance (default: the library's default).
    #[arg(long)]
    pub tolerance: Option<f64>,
    /// Candidate: where each depth's solve starts (previous, extrapolated,
    /// dilated; default: the library's default).
    #[arg(long)]
    pub warm_start: Option<String>,
    /// Time only the candidate (no reference solves, no comparison).
    #[arg(long)]
    pub candidate_only: bool,
}

/// One road's caps and ranges.
struct Caps {
    label: &'static str,
    patches: Vec<(CapPatch, f64)>,
}

fn road_caps(label: &'static str, body: &str, cells: usize) -> Result<Caps> {
    let s = scenario(label, body, cells, 0.1)?;
    let map = s
        .texture
        .as_ref()
        .context("scenario without [texture]")?
        .height_map(std::path::Path::new("."))?;
    let material = s.material()?;
    let road = texture_road(&map, material, &TextureRoadOptions::new(0.2e-3, 2e-6))?;
    let problem = Problem::from_set(road.set.clone(), material)?;
    let wilke = solve(&problem, Control::Load(LOAD), &SolverOptions::default())?;
    let max_approach = APPROACH_MARGIN * wilke.approach;
    // The range rule of `fidelity::calibrated_set`.
    let top = road.set.top();
    let mut patches = Vec::new();
    for (i, &z) in road.set.heights().iter().enumerate() {
        let a = &road.segmentation.asperities()[road.asperity_index[i]];
        let depth = (max_approach - (top - z)).max(0.1 * max_approach);
        let patch = cap_patch(&map, a, depth)?;
        let depth = depth.max(2.0 * patch.summit_offset());
        patches.push((patch, depth));
    }
    Ok(Caps { label, patches })
}

/// `(max |ΔF| / F_max, max |ΔA| / A_max)` of `b` against `a` over `a`'s range.
fn table_distance(a: &CalibratedTable, b: &CalibratedTable) -> (f64, f64) {
    let top = a.max_depth();
    let (f_max, a_max) = (a.force_at(top).0, a.area_at(top));
    let (mut df, mut da) = (0.0f64, 0.0f64);
    for k in 1..=PROBES {
        let d = top * k as f64 / PROBES as f64;
        df = df.max((a.force_at(d).0 - b.force_at(d).0).abs());
        da = da.max((a.area_at(d) - b.area_at(d)).abs());
    }
    (
        df / f_max.max(f64::MIN_POSITIVE),
        da / a_max.max(f64::MIN_POSITIVE),
    )
}

/// Mean iterations per knot, knot by knot, over the tables.
fn iterations_per_knot(tables: &[CalibratedTable]) -> Vec<f64> {
    let n = tables
        .iter()
        .map(|t| t.stats().iterations.len())
        .max()
        .unwrap_or(0);
    (0..n)
        .map(|k| {
            let v: Vec<usize> = tables
                .iter()
                .filter_map(|t| t.stats().iterations.get(k).copied())
                .collect();
            v.iter().sum::<usize>() as f64 / v.len().max(1) as f64
        })
        .collect()
}

/// This thread's CPU time (s) from `/proc/thread-self/schedstat` (ns on
/// the CPU), or `None` where there is no such file.
fn thread_cpu_seconds() -> Option<f64> {
    let text = std::fs::read_to_string("/proc/thread-self/schedstat").ok()?;
    let ns: f64 = text.split_whitespace().next()?.parse().ok()?;
    Some(ns * 1e-9)
}

/// The BEM's work in a table, machine-independent: the sum over its solves
/// of the iterations times the padded FFT grid's cells (`≈ 4 nx ny`).
fn work(t: &CalibratedTable) -> f64 {
    let s = t.stats();
    s.iterations
        .iter()
        .zip(&s.windows)
        .map(|(&it, w)| it as f64 * 4.0 * (w[0] * w[1]) as f64)
        .sum()
}

/// [`work`] had every solve run on the whole patch (the first
/// calibration's way).
fn whole_patch_work(t: &CalibratedTable) -> f64 {
    let s = t.stats();
    let cells = 4.0 * (s.cells[0] * s.cells[1]) as f64;
    s.iterations.iter().map(|&it| it as f64 * cells).sum()
}

/// The tables and their CPU time (s; wall time where the CPU time cannot
/// be read).
fn run_all(
    caps: &Caps,
    material: &tyreroad::contact_law::Material,
    options: &CalibrationOptions,
) -> Result<(Vec<CalibratedTable>, f64)> {
    let (t, c) = (Instant::now(), thread_cpu_seconds());
    let tables = caps
        .patches
        .iter()
        .map(|(p, d)| calibrate(p, *d, material, options))
        .collect::<Result<Vec<_>, _>>()
        .with_context(|| format!("calibration of `{}`", caps.label))?;
    let seconds = match (c, thread_cpu_seconds()) {
        (Some(a), Some(b)) => b - a,
        _ => t.elapsed().as_secs_f64(),
    };
    Ok((tables, seconds))
}

fn knots_line(v: &[f64]) -> String {
    v.iter()
        .map(|x| format!("{x:.0}"))
        .collect::<Vec<_>>()
        .join(" ")
}

/// Runs the comparison; fails only if a road cannot be built or a table
/// cannot be solved.
pub fn run(args: &CalibCostArgs) -> Result<()> {
    if !(16..=2000).contains(&args.texture_cells) {
        bail!(
            "--texture-cells {}: expected 16 to 2000",
            args.texture_cells
        );
    }
    if let Some(kind) = &args.kind
        && !KINDS.iter().any(|(label, _)| label == kind)
    {
        let known: Vec<&str> = KINDS.iter().map(|k| k.0).collect();
        bail!("unknown --kind {kind:?} (known: {})", known.join(", "));
    }
    let reference = CalibrationOptions::reference();
    let mut candidate = CalibrationOptions::default();
    if let Some(n) = args.nodes {
        candidate.nodes = n;
    }
    if let Some(t) = args.tolerance {
        candidate.tolerance = t;
    }
    if let Some(w) = &args.warm_start {
        candidate.warm_start = match w.as_str() {
            "previous" => WarmStart::Previous,
            "extrapolated" => WarmStart::Extrapolated,
            "dilated" => WarmStart::Dilated,
            _ => bail!("--warm-start {w}: expected previous, extrapolated or dilated"),
        };
    }
    say!("reference: {reference:?}\ncandidate: {candidate:?}\n");
    say!(
        "| road | caps | patch cells (mean / max side) | reference CPU ms/table | candidate CPU ms/table | speed-up | work ratio | windows' gain | max ΔF/F_max | max ΔA/A_max | mean ΔF/F_max |"
    );
    say!("|---|---|---|---|---|---|---|---|---|---|---|");
    let material = tyreroad::contact_law::Material::new(6.54e6, 0.5)?;
    let (mut t_ref, mut t_cand, mut n_all) = (0.0, 0.0, 0usize);
    let mut knot_lines = Vec::new();
    for (label, body) in KINDS
        .iter()
        .filter(|(l, _)| args.kind.as_deref().is_none_or(|k| k == *l))
    {
        let caps = road_caps(label, body, args.texture_cells)?;
        let n = caps.patches.len();
        let side: Vec<f64> = caps
            .patches
            .iter()
            .map(|(p, _)| ((p.nx * p.ny) as f64).sqrt())
            .collect();
        let mean_side = side.iter().sum::<f64>() / n.max(1) as f64;
        let max_side = side.iter().copied().fold(0.0, f64::max);
        let (cand, tc) = run_all(&caps, &material, &candidate)?;
        let work_cand: f64 = cand.iter().map(work).sum();
        let (dist, tr, ref_knots, work_ref) = if args.candidate_only {
            (Vec::new(), f64::NAN, Vec::new(), f64::NAN)
        } else {
            let (refs, tr) = run_all(&caps, &material, &reference)?;
            let dist: Vec<(f64, f64)> = refs
                .iter()
                .zip(&cand)
                .map(|(a, b)| table_distance(a, b))
                .collect();
            let w: f64 = refs.iter().map(work).sum();
            (dist, tr, iterations_per_knot(&refs), w)
        };
        let worst_f = dist.iter().map(|d| d.0).fold(0.0, f64::max);
        let worst_a = dist.iter().map(|d| d.1).fold(0.0, f64::max);
        let mean_f = dist.iter().map(|d| d.0).sum::<f64>() / dist.len().max(1) as f64;
        say!(
            "| {label} | {n} | {mean_side:.0} / {max_side:.0} | {:.1} | {:.1} | {:.1}× | {:.2}× | {:.2}× | {:.3} % | {:.3} % | {:.3} % |",
            1e3 * tr / n as f64,
            1e3 * tc / n as f64,
            tr / tc,
            work_ref / work_cand,
            cand.iter().map(whole_patch_work).sum::<f64>() / work_cand,
            100.0 * worst_f,
            100.0 * worst_a,
            100.0 * mean_f
        );
        knot_lines.push(format!(
            "{label}: reference [{}] candidate [{}]",
            knots_line(&ref_knots),
            knots_line(&iterations_per_knot(&cand))
        ));
        t_ref += tr;
        t_cand += tc;
        n_all += n;
    }
    say!(
        "\nall roads: {n_all} tables, reference {:.1} ms/table, candidate {:.1} ms/table ({:.1}×)",
        1e3 * t_ref / n_all.max(1) as f64,
        1e3 * t_cand / n_all.max(1) as f64,
        t_ref / t_cand
    );
    say!("\nmean CG iterations per knot (depth order):");
    for l in knot_lines {
        say!("{l}");
    }
    Ok(())
}
