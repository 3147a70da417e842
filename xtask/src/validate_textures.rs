//! `cargo xtask validate --textures`: every rung of the fidelity ladder
//! against the full BEM on seven road kinds at three loads
//! (`tyreroad::fidelity::compare`, docs/validation.md "Fidelity on
//! textures"), with the BEM's own resolution convergence shown once.
//!
//! The road kinds are data ([`KINDS`]): `[texture.synth]` text as a user
//! writes it, read through the scenario library, so the harness builds the
//! same surfaces as `cargo xtask run`. With `--scenario ROAD.toml` the
//! road is the user's own instead: its `[texture]` (a measured file or a
//! synthesis), its `[texture]` segmentation, its material and its
//! `[static]` loads.

use std::fmt::Write as _;
use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use tyreroad::fidelity::compare::{
    BLOCKS, CompareOptions, RungLoad, TextureComparison, bem_resolution, compare_texture,
};
use tyreroad::fidelity::segmentation::segmentation_spread;
use tyreroad::fidelity::{CalibrationOptions, Fidelity, RUNGS};
use tyreroad::multipoint::SolverOptions;
use tyreroad::scenario::Scenario;
use tyreroad::scenario::output::OutputSet;

/// Targets of issue 15 for the best rung: approach, area, 10 mm block,
/// 5 mm block (fractions), and the cost ratio.
const TARGETS: [f64; 4] = [0.02, 0.03, 0.03, 0.05];
const COST_TARGET: f64 = 100.0;

/// Loads (N) of every case (the issue's).
const LOADS: [f64; 3] = [50.0, 150.0, 300.0];

/// (label, `[texture.synth]` body without the grid: kind, seed, extras).
pub(crate) const KINDS: [(&str, &str); 7] = [
    (
        "self-affine H 0.6",
        "kind = \"self_affine\"\nseed = 6\nrms = \"0.4 mm\"\nhurst = 0.6\nlambda_long = \"20 mm\"\nlambda_short = \"0.5 mm\"\n",
    ),
    (
        "self-affine H 0.8",
        "kind = \"self_affine\"\nseed = 8\nrms = \"0.4 mm\"\nhurst = 0.8\nlambda_long = \"20 mm\"\nlambda_short = \"0.5 mm\"\n",
    ),
    ("chip seal", "kind = \"worn_chip_seal\"\nseed = 19\n"),
    (
        "dense asphalt",
        "kind = \"aggregate\"\nseed = 2006\ngrading = \"4/6\"\ncoverage = 1.3\nembedding = [0.6, 0.8]\n",
    ),
    ("porous asphalt", "kind = \"porous_asphalt\"\nseed = 18\n"),
    (
        "exposed aggregate",
        "kind = \"exposed_aggregate\"\nseed = 17\n",
    ),
    (
        "tined concrete",
        "kind = \"transverse_tining\"\nseed = 14\n",
    ),
];

/// The label of the kind whose BEM resolution convergence is shown.
const RESOLUTION_KIND: &str = "chip seal";

pub(crate) fn scenario(label: &str, body: &str, cells: usize, spacing_mm: f64) -> Result<Scenario> {
    let text = format!(
        "name = \"fidelity\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
         [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
         [texture.synth]\nnx = {cells}\nny = {cells}\nspacing = \"{spacing_mm} mm\"\n{body}"
    );
    Scenario::parse(&text, label).with_context(|| format!("road kind `{label}`"))
}

fn pct(v: f64) -> String {
    if v.is_finite() {
        format!("{:+.1} %", 100.0 * v)
    } else {
        "—".into()
    }
}

/// Options of `cargo xtask validate --textures`.
#[derive(Debug, clap::Args)]
pub struct TextureArgs {
    /// Instead: every fidelity rung against the BEM on seven road kinds at
    /// three loads (docs/validation.md, "Fidelity on textures").
    #[arg(long)]
    pub textures: bool,
    /// With `--textures`: cells per side of each texture (0.1 mm cells).
    #[arg(
        long,
        default_value_t = 400,
        requires = "textures",
        conflicts_with = "scenario"
    )]
    pub texture_cells: usize,
    /// With `--textures`: only this road (its label, e.g. "chip seal").
    #[arg(long, requires = "textures", conflicts_with = "scenario")]
    pub kind: Option<String>,
    /// With `--textures`: skip the BEM resolution study.
    #[arg(long, requires = "textures")]
    pub no_resolution: bool,
    /// With `--textures`: also segment each road a second way
    /// (`min_prominence` doubled) and measure how far one rung's outputs
    /// move (docs/validation.md, "Segmentation invariance").
    #[arg(long, requires = "textures")]
    pub segmentation: bool,
    /// With `--segmentation`: the rung measured (any name of
    /// `fidelity::RUNGS`).
    #[arg(long, default_value = "calibrated", requires = "segmentation")]
    pub segmentation_rung: String,
    /// With `--textures`: only these rungs, comma-separated names (e.g.
    /// "calibrated,calibrated_fields"); every rung of `fidelity::RUNGS`
    /// when absent.
    #[arg(long, value_delimiter = ',', requires = "textures")]
    pub rungs: Vec<String>,
    /// With `--textures`: passes of the block fields' two-scale rebuild
    /// that solve each cap again under its neighbours' displacement
    /// (docs/validation.md, "Caps rebuilt beside their neighbours"); 0
    /// rebuilds each cap alone (the tables measured before session 9).
    #[arg(long, default_value_t = 2, requires = "textures")]
    pub neighbour_passes: usize,
    /// With `--textures`: split each basin whose flat top is wider than this
    /// (mm) into tiles, one asperity each (`[texture] max_cap_width`,
    /// docs/texture.md "Wide tops split into tiles"); whole basins when
    /// absent.
    #[arg(long, requires = "textures", allow_negative_numbers = true)]
    pub max_cap_width: Option<f64>,
}

/// One road of the validation: its map, material and what to compare.
struct Road {
    label: String,
    map: tyreroad::texture::HeightMap,
    material: tyreroad::contact_law::Material,
    options: CompareOptions,
    /// Whether the BEM's resolution study runs on this road.
    resolution: bool,
    /// What the report says of the scenario before its tables (a
    /// viscoelastic tread compared elastically).
    notes: Vec<String>,
}

/// The most points a road of `--scenario` may have: as many as the largest
/// `--texture-cells` road (2000 × 2000).
const MAX_SCENARIO_POINTS: usize = 4_000_000;

/// The most points of the BEM resolution study's finest grid on a road of
/// `--scenario` (the map refined to half its cell, four times its points):
/// past it the study is skipped, with a note in the report.
const MAX_RESOLUTION_POINTS: usize = 4_000_000;

/// Runs the texture validation on the seven kinds, or on the road of
/// `scenario`; fails only if a case cannot be run at all (a rung's failed
/// load is a row that says so).
pub fn run(args: &TextureArgs, scenario: Option<&Path>, out: &Path) -> Result<()> {
    let rungs: Vec<Fidelity> = if args.rungs.is_empty() {
        RUNGS.to_vec()
    } else {
        args.rungs
            .iter()
            .map(|r| r.trim().parse::<Fidelity>())
            .collect::<Result<_, _>>()
            .context("--rungs")?
    };
    let max_cap_width = args
        .max_cap_width
        .map(|mm| {
            if mm.is_finite() && mm > 0.0 {
                Ok(1e-3 * mm)
            } else {
                Err(anyhow::anyhow!(
                    "--max-cap-width {mm}: expected a width > 0 in mm"
                ))
            }
        })
        .transpose()?;
    let segmentation_rung: Fidelity = args
        .segmentation_rung
        .trim()
        .parse()
        .context("--segmentation-rung")?;
    let base = CompareOptions {
        loads: LOADS.to_vec(),
        road: tyreroad::texture_road::TextureRoadOptions::new(0.2e-3, 2e-6),
        calibration: CalibrationOptions::default(),
        rungs: rungs.clone(),
        solver: SolverOptions::default(),
        neighbour_passes: args.neighbour_passes,
    };
    let roads = match scenario {
        Some(path) => vec![scenario_road(
            path,
            &base,
            max_cap_width,
            !args.no_resolution,
        )?],
        None => kind_roads(args, &base, max_cap_width)?,
    };
    // The output folder is checked before the comparison (minutes), not
    // after it; one this check made is removed again, so a run that fails
    // leaves no folder behind.
    let existed = out.exists();
    drop(OutputSet::new(out)?);
    if !existed {
        let _ = std::fs::remove_dir(out);
    }
    let grid = grid_label(&roads[0].map);
    let mut results = Vec::new();
    let mut report = String::new();
    if let Some(w) = roads[0].options.road.max_cap_width {
        writeln!(
            report,
            "Wide flat tops split into tiles of at most {} mm (`[texture] max_cap_width`).",
            w * 1e3
        )?;
        say!("{report}");
    }
    let segmentation_header = segmentation_header(segmentation_rung);
    let mut segmentation = String::new();
    if args.segmentation {
        say!("\n{segmentation_header}");
    }
    for road in &roads {
        let label = road.label.as_str();
        for n in &road.notes {
            writeln!(report, "Note ({label}): {n}.")?;
            say!("note: {n}");
        }
        eprintln!("validate --textures: {label} ...");
        let t = Instant::now();
        let c = compare_texture(&road.map, road.material, &road.options).with_context(|| {
            // The library says widths in metres; the option took mm.
            let width = road.options.road.max_cap_width.map_or(String::new(), |w| {
                format!(" (max_cap_width {} mm = {w} m)", w * 1e3)
            });
            format!("road `{label}`{width}")
        })?;
        eprintln!(
            "  {} asperities, {:.1} s",
            c.asperities,
            t.elapsed().as_secs_f64()
        );
        let refined = (2 * road.map.nx() - 1) * (2 * road.map.ny() - 1);
        if road.resolution && refined > MAX_RESOLUTION_POINTS {
            writeln!(
                report,
                "\nBEM resolution, {label}: not studied (the map refined to half its cell \
                 would hold {refined} points, more than {MAX_RESOLUTION_POINTS})."
            )?;
        } else if road.resolution {
            let loads = &road.options.loads;
            let load = loads[loads.len() / 2];
            let rows = bem_resolution(&road.map, &road.material, load)?;
            writeln!(report, "\nBEM resolution, {label}, {load} N:\n")?;
            writeln!(
                report,
                "| cell (mm) | approach (µm) | contact area (mm²) | wrong 10 mm block vs finest |"
            )?;
            writeln!(report, "|---|---|---|---|")?;
            for r in rows {
                writeln!(
                    report,
                    "| {} | {:.1} | {:.2} | {:.2} % |",
                    cell_label(r.cell),
                    r.approach * 1e6,
                    r.contact_area * 1e6,
                    100.0 * r.wrong_block
                )?;
            }
        }
        // Each road's rows as soon as they exist: a long run that is cut
        // short still leaves its finished roads on the terminal.
        say_part!("{}", tables(&[(label, c.clone())], &rungs, &grid)?);
        if args.segmentation {
            let rows = segmentation_rows(
                label,
                &road.map,
                road.material,
                &road.options,
                segmentation_rung,
            )?;
            say_part!("{rows}");
            segmentation.push_str(&rows);
        }
        results.push((label, c));
    }
    report.push_str(&tables(&results, &rungs, &grid)?);
    if args.segmentation {
        writeln!(report, "\n{segmentation_header}")?;
        report.push_str(&segmentation);
    }
    say!("\n== all roads ==");
    say_part!("{report}");
    let mut set = OutputSet::new(out)?;
    set.write("texture_fidelity.md", report.as_bytes())?;
    crate::statics::print_written(&set.commit()?);
    Ok(())
}

/// The seven kinds (or the one `--kind` names) on `--texture-cells` cells.
fn kind_roads(
    args: &TextureArgs,
    base: &CompareOptions,
    max_cap_width: Option<f64>,
) -> Result<Vec<Road>> {
    let cells = args.texture_cells;
    if !(16..=2000).contains(&cells) {
        bail!("--texture-cells {cells}: expected 16 to 2000");
    }
    let kinds: Vec<_> = KINDS
        .iter()
        .filter(|(label, _)| args.kind.as_deref().is_none_or(|k| k == *label))
        .collect();
    if kinds.is_empty() {
        let known: Vec<&str> = KINDS.iter().map(|k| k.0).collect();
        bail!("unknown --kind (known: {})", known.join(", "));
    }
    let mut options = base.clone();
    options.road.max_cap_width = max_cap_width;
    kinds
        .into_iter()
        .map(|(label, body)| {
            let s = scenario(label, body, cells, 0.1)?;
            Ok(Road {
                label: (*label).to_string(),
                map: s
                    .texture
                    .as_ref()
                    .context("scenario without [texture]")?
                    .height_map(Path::new("."))?,
                material: s.material()?,
                options: options.clone(),
                resolution: *label == RESOLUTION_KIND && !args.no_resolution,
                notes: Vec::new(),
            })
        })
        .collect()
}

/// The road of a user's scenario: its `[texture]` (a file read relative to
/// the scenario's folder, or a synthesis) and segmentation, its material,
/// its `[static]` loads in increasing order (the BEM warm-starts each load
/// from the last).
fn scenario_road(
    path: &Path,
    base: &CompareOptions,
    max_cap_width: Option<f64>,
    resolution: bool,
) -> Result<Road> {
    let s = Scenario::from_path(path)?;
    let Some(texture) = &s.texture else {
        bail!(
            "{}: `validate --textures --scenario` compares the model with the BEM on a \
             scenario's [texture]; this scenario has none (a scenario of [[asperity]] \
             shapes is checked by `validate --scenario` alone)",
            path.display()
        );
    };
    let mut loads = tyreroad::scenario::static_loads(&s).with_context(|| {
        format!(
            "{}: the comparison is solved at the scenario's [static] loads",
            path.display()
        )
    })?;
    // In order, for the resolution study's middle load; the comparison
    // itself orders them and says a repeat.
    loads.sort_by(f64::total_cmp);
    let mut notes = Vec::new();
    if s.material.viscoelastic.is_some() {
        notes.push(
            "[material.viscoelastic] is not used: the comparison is elastic, at \
             youngs_modulus"
                .into(),
        );
    }
    let base_dir = path.parent().unwrap_or(Path::new("."));
    let map = texture.height_map(base_dir)?;
    let points = map.nx() * map.ny();
    if points > MAX_SCENARIO_POINTS {
        bail!(
            "{}: the road's map is {} × {} points, more than the {MAX_SCENARIO_POINTS} the \
             full BEM of this comparison takes: compare a window of the texture, written as a \
             file of its own (400 × 400 points at 0.1 mm already hold 16 blocks of 10 mm)",
            path.display(),
            map.nx(),
            map.ny()
        );
    }
    let mut road = texture.road_options();
    if max_cap_width.is_some() {
        road.max_cap_width = max_cap_width;
    }
    Ok(Road {
        label: s.name.clone(),
        material: s.material()?,
        map,
        options: CompareOptions {
            loads,
            road,
            ..base.clone()
        },
        resolution,
        notes,
    })
}

/// "40 × 40 mm at 0.1 mm": a map's extent and cell.
fn grid_label(map: &tyreroad::texture::HeightMap) -> String {
    format!(
        "{:.0} × {:.0} mm at {} mm",
        map.nx() as f64 * map.dx() * 1e3,
        map.ny() as f64 * map.dy() * 1e3,
        cell_label([map.dx(), map.dy()])
    )
}

/// A cell in mm: "0.1", or "0.1 × 0.5" when it is not square.
fn cell_label(cell: [f64; 2]) -> String {
    let mm = |v: f64| format!("{}", (v * 1e7).round() / 1e4);
    if (cell[0] - cell[1]).abs() <= 1e-12 * cell[0].max(cell[1]) {
        mm(cell[0])
    } else {
        format!("{} × {}", mm(cell[0]), mm(cell[1]))
    }
}

fn segmentation_header(rung: Fidelity) -> String {
    format!(
        "Segmentation invariance (rung `{rung}`, forces as fields; \
         segmentation b = min_prominence doubled):\n\n\
         | road | W (N) | asperities a / b | approach b vs a | area b vs a | moved 10 mm block | moved 5 mm block |\n\
         |---|---|---|---|---|---|---|"
    )
}

/// The rows of one road: `rung` under the harness's segmentation and under
/// `min_prominence` doubled.
fn segmentation_rows(
    label: &str,
    map: &tyreroad::texture::HeightMap,
    material: tyreroad::contact_law::Material,
    options: &CompareOptions,
    rung: Fidelity,
) -> Result<String> {
    let doubled = tyreroad::texture_road::TextureRoadOptions {
        min_prominence: 2.0 * options.road.min_prominence,
        ..options.road
    };
    let calibrator = tyreroad::fidelity::Calibrator::new(material, options.calibration);
    // The field coupling reads each table's binned pressure field.
    let calibrator = if rung == Fidelity::CalibratedFields {
        calibrator.with_fields()
    } else {
        calibrator
    };
    let rebuild = tyreroad::two_scale::TwoScaleOptions {
        neighbour_passes: options.neighbour_passes,
        map_cell: Some(map.dx().min(map.dy())),
        ..Default::default()
    };
    let rows = segmentation_spread(
        map,
        material,
        &options.loads,
        [&options.road, &doubled],
        rung,
        &options.solver,
        &rebuild,
        &calibrator,
    )
    .with_context(|| format!("segmentation of `{label}`"))?;
    let mut out = String::new();
    for r in rows {
        writeln!(
            out,
            "| {label} | {:.0} | {} / {} | {} | {} | {:.1} % | {:.1} % |",
            r.load,
            r.asperities[0],
            r.asperities[1],
            pct(r.approach_change()),
            pct(r.area_change()),
            100.0 * r.block_moved[0],
            100.0 * r.block_moved[1]
        )?;
    }
    Ok(out)
}

fn tables(results: &[(&str, TextureComparison)], rungs: &[Fidelity], grid: &str) -> Result<String> {
    let mut out = String::new();
    for rung in rungs {
        writeln!(
            out,
            "\nRung `{rung}` ({grid}; targets: approach ±{:.1} %, \
             area ±{:.1} %, 10 mm block {:.1} %, 5 mm block {:.1} %, ≥ {COST_TARGET:.0}× cheaper):\n",
            100.0 * TARGETS[0],
            100.0 * TARGETS[1],
            100.0 * TARGETS[2],
            100.0 * TARGETS[3]
        )?;
        writeln!(
            out,
            "| road | N | W (N) | approach | area | wrong asperity | wrong {a:.0} mm block | wrong {b:.0} mm block | wrong {a:.0} mm block (fields) | wrong {b:.0} mm block (fields) | model s | BEM s | BEM/model | set-up s |",
            a = BLOCKS[0] * 1e3,
            b = BLOCKS[1] * 1e3
        )?;
        writeln!(
            out,
            "|---|---|---|---|---|---|---|---|---|---|---|---|---|---|"
        )?;
        for (label, c) in results {
            let Some(res) = c.rungs.iter().find(|r| r.fidelity == *rung) else {
                continue;
            };
            if let Some(why) = &res.unavailable {
                writeln!(out, "| {label} | {} | — | {why} |", c.asperities)?;
                continue;
            }
            for (k, l) in res.loads.iter().enumerate() {
                match l {
                    Ok(RungLoad {
                        load,
                        approach_error,
                        area_error,
                        wrong_asperity,
                        wrong_block,
                        field_block,
                        seconds,
                        bem_seconds,
                        ..
                    }) => writeln!(
                        out,
                        "| {label} | {} | {load} | {} | {} | {:.1} % | {:.1} % | {:.1} % | {:.1} % | {:.1} % | {seconds:.4} | {bem_seconds:.2} | {:.0} | {:.1} |",
                        c.asperities,
                        pct(*approach_error),
                        pct(*area_error),
                        100.0 * wrong_asperity,
                        100.0 * wrong_block[0],
                        100.0 * wrong_block[1],
                        100.0 * field_block[0],
                        100.0 * field_block[1],
                        bem_seconds / seconds.max(1e-9),
                        res.setup_seconds,
                    )?,
                    Err(e) => writeln!(
                        out,
                        "| {label} | {} | {} | failed: {e} |",
                        c.asperities,
                        c.bem.get(k).map_or("—".into(), |b| b.load.to_string())
                    )?,
                }
            }
        }
        let warned: Vec<&String> = results
            .iter()
            .filter_map(|(_, c)| c.rungs.iter().find(|r| r.fidelity == *rung))
            .flat_map(|r| r.loads.iter().flatten().flat_map(|l| &l.warnings))
            .collect();
        if !warned.is_empty() {
            writeln!(
                out,
                "\nWarnings, rung `{rung}` (rows whose answer is no road's):\n"
            )?;
            for w in warned {
                writeln!(out, "- {w}")?;
            }
        }
    }
    for (label, c) in results {
        if !c.notes.is_empty() {
            writeln!(out, "\nWhat the reference cannot say ({label}):\n")?;
            for n in &c.notes {
                writeln!(out, "- {n}")?;
            }
        }
    }
    let fields = Fidelity::CalibratedFields;
    if rungs.contains(&fields) {
        writeln!(
            out,
            "\nRung `{fields}`: rounds of the field coupling's fixed point (forces settled to \
             1e-6 of W), per load:\n"
        )?;
        writeln!(out, "| road | W (N) | rounds |\n|---|---|---|")?;
        for (label, c) in results {
            let Some(res) = c.rungs.iter().find(|r| r.fidelity == fields) else {
                continue;
            };
            for l in res.loads.iter().flatten() {
                writeln!(out, "| {label} | {:.0} | {} |", l.load, l.coupling_rounds)?;
            }
        }
    }
    writeln!(
        out,
        "\nWhere the error lives (load on the wrong asperity): `wilke` = Wilke laws + point \
         interaction; `calibrated` = exact laws + point interaction (the interaction's share); \
         law only = Wilke laws on the BEM's own load sharing (the law's share).\n"
    )?;
    writeln!(
        out,
        "| road | W (N) | wilke | calibrated | law only | calibration tables solved / reused |"
    )?;
    writeln!(out, "|---|---|---|---|---|---|")?;
    for (label, c) in results {
        for (k, b) in c.bem.iter().enumerate() {
            let at = |f: tyreroad::fidelity::Fidelity| {
                c.rungs
                    .iter()
                    .find(|r| r.fidelity == f)
                    .and_then(|r| r.loads.get(k))
                    .and_then(|l| l.as_ref().ok())
                    .map_or("—".to_string(), |l| {
                        format!("{:.1} %", 100.0 * l.wrong_asperity)
                    })
            };
            writeln!(
                out,
                "| {label} | {:.0} | {} | {} | {} | {} / {} |",
                b.load,
                at(tyreroad::fidelity::Fidelity::Wilke),
                at(tyreroad::fidelity::Fidelity::Calibrated),
                c.law_only
                    .get(k)
                    .map_or("—".into(), |v| format!("{:.1} %", 100.0 * v)),
                c.cache.solved,
                c.cache.memory_hits + c.cache.disk_hits,
            )?;
        }
    }
    Ok(out)
}
