//! `cargo xtask film`: analyse a pressure-film scan (Fuji Prescale) against
//! an indenter layout, optionally compare with a model run, and write a
//! per-print CSV and an annotated PNG. Also the synthetic Table 1 used by
//! `cargo xtask validate`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use tyreroad_film as film;

/// Arguments of `cargo xtask film`.
#[derive(Debug, Clone, clap::Args)]
pub struct FilmArgs {
    /// The scan: PNG or TIFF, 8 or 16 bit, grey or RGB (green channel of a
    /// colour scan).
    pub scan: PathBuf,
    /// Calibration: a CSV of pairs (header `density|grey|grey8|grey16,
    /// pressure_pa|pressure_mpa`) or `llw:A` … `llw:D` for the shipped LLW
    /// chart curve.
    #[arg(long)]
    pub calibration: String,
    /// Indenter layout: CSV with header `indenter,x_m,y_m`.
    #[arg(long)]
    pub layout: PathBuf,
    /// Model run to compare with: CSV with header
    /// `load_n,indenter,x_m,y_m,force_n,radius_m`.
    #[arg(long)]
    pub model: Option<PathBuf>,
    /// Load (N) of the model CSV to compare with (needed when it holds
    /// several loads).
    #[arg(long)]
    pub load: Option<f64>,
    /// Scan resolution in dots per inch (else read from the file).
    #[arg(long, conflicts_with = "pixel_size")]
    pub dpi: Option<f64>,
    /// Pixel size in metres (else from --dpi or the file).
    #[arg(long)]
    pub pixel_size: Option<f64>,
    /// Film origin in the scan as `COL,ROW` pixels (continuous, from the
    /// top-left corner); default: estimated from the prints' centroid.
    #[arg(long)]
    pub origin: Option<String>,
    /// Force and radius estimator: `mean-grey` (the paper's), `pixel-mean`
    /// or `hertz-fit`.
    #[arg(long, default_value = "mean-grey")]
    pub estimator: String,
    /// Grey threshold (0–1) instead of half-way to the calibration floor.
    #[arg(long)]
    pub threshold: Option<f64>,
    /// Scanner white reference (normalised grey of D = 0).
    #[arg(long, default_value_t = 1.0)]
    pub white: f64,
    /// Scanner black reference (normalised grey of no reflected light).
    #[arg(long, default_value_t = 0.0)]
    pub black: f64,
    /// Output directory.
    #[arg(long, default_value = "validation/film")]
    pub out: PathBuf,
}

fn parse_estimator(s: &str) -> Result<film::Estimator> {
    Ok(match s {
        "mean-grey" => film::Estimator::MeanGrey,
        "pixel-mean" => film::Estimator::PixelMean,
        "hertz-fit" => film::Estimator::HertzFit,
        other => bail!("unknown estimator {other:?} (mean-grey, pixel-mean, hertz-fit)"),
    })
}

fn load_calibration(spec: &str) -> Result<film::Calibration> {
    if let Some(curve) = spec.strip_prefix("llw:") {
        let curve: film::LlwCurve = curve.parse()?;
        return Ok(film::Calibration::llw(curve)?);
    }
    film::Calibration::read_csv(Path::new(spec))
        .with_context(|| format!("reading calibration {spec}"))
}

/// Runs `cargo xtask film`: writes `<out>/<scan>-prints.csv` and
/// `<out>/<scan>-annotated.png` (each written whole or not at all) and
/// prints a summary (with the Table 1 statistics when `--model` is given).
pub fn run(args: &FilmArgs) -> Result<()> {
    let estimator = parse_estimator(&args.estimator)?;
    let calibration = load_calibration(&args.calibration)?;
    let scanner = film::Scanner::new(args.white, args.black)?;
    let response = film::FilmResponse::new(calibration, scanner);
    let mut scan = film::Scan::open(&args.scan, film::Channel::Auto)?;
    if let Some(s) = args.pixel_size {
        scan = scan.with_pixel_size(s)?;
    } else if let Some(dpi) = args.dpi {
        scan = scan.with_dpi(dpi)?;
    }
    let layout = film::Layout::read_csv(&args.layout)?;
    let origin = match &args.origin {
        None => film::Origin::Centroid,
        Some(s) => {
            let v: Vec<f64> = s
                .split(',')
                .map(|t| t.trim().parse::<f64>())
                .collect::<std::result::Result<_, _>>()
                .with_context(|| format!("--origin {s:?}: expected COL,ROW"))?;
            let [col, row] = v[..] else {
                bail!("--origin {s:?}: expected COL,ROW");
            };
            film::Origin::Pixel { col, row }
        }
    };
    let mut options = film::AnalysisOptions::default();
    if let Some(t) = args.threshold {
        options.threshold = film::Threshold::Grey(t);
    }
    let det = film::analyse(&scan, &response, &options)
        .with_context(|| format!("analysing {}", args.scan.display()))?;
    let matching = film::match_layout(&det, &layout, origin, None).with_context(|| {
        format!(
            "matching prints of {} to {}",
            args.scan.display(),
            args.layout.display()
        )
    })?;
    let measured = film::measurements(&det, &matching, estimator)?;

    let comparison = match &args.model {
        None => None,
        Some(path) => {
            let rows = film::read_model_csv(path)?;
            let loads = film::loads(&rows);
            let load = match (args.load, loads.as_slice()) {
                (Some(l), _) => l,
                (None, [l]) => *l,
                (None, ls) => bail!(
                    "{} holds loads {ls:?} N: choose one with --load",
                    path.display()
                ),
            };
            let model = film::rows_at_load(&rows, load);
            if model.is_empty() {
                bail!(
                    "{} has no rows at load {load} N (loads: {loads:?})",
                    path.display()
                );
            }
            Some(film::compare(load, &measured, &model)?)
        }
    };

    // Per-print CSV.
    let mut csv = String::from(
        "indenter,x_m,y_m,pixels,area_m2,mean_grey,mean_grey_density,pressure_of_mean_grey_pa,\
         mean_grey_flag,mean_pixel_pressure_pa,force_n,radius_m,semi_major_m,semi_minor_m,\
         orientation_rad,hertz_force_n,hertz_radius_m,saturated_pixels,below_range_pixels,\
         touches_border,force_model_n,radius_model_m,eps_force,eps_radius\n",
    );
    for (m, &(number, force, radius)) in matching.matches.iter().zip(&measured) {
        let p = &det.prints[m.print];
        let (pm, flag) = match p.pressure_of_mean_grey {
            film::Calibrated::InRange(v) => (format!("{v:.6e}"), "in_range"),
            film::Calibrated::BelowRange => (String::new(), "below_range"),
            film::Calibrated::Saturated => (String::new(), "saturated"),
        };
        let (hf, hr) = p
            .hertz
            .map(|h| (format!("{:.6e}", h.force), format!("{:.6e}", h.radius)))
            .unwrap_or_default();
        let model = comparison
            .as_ref()
            .and_then(|c| c.indenters.iter().find(|i| i.indenter == number))
            .map(|i| {
                format!(
                    "{:.6e},{:.6e},{:.6},{:.6}",
                    i.force_model, i.radius_model, i.eps_force, i.eps_radius
                )
            })
            .unwrap_or_else(|| ",,,".into());
        writeln!(
            csv,
            "{number},{:.6e},{:.6e},{},{:.6e},{:.6},{:.6},{pm},{flag},{:.6e},{force:.6e},{radius:.6e},\
             {:.6e},{:.6e},{:.6},{hf},{hr},{},{},{},{model}",
            m.centroid.0,
            m.centroid.1,
            p.pixel_count,
            p.area,
            p.mean_grey,
            p.mean_grey_density,
            p.mean_pixel_pressure,
            p.ellipse.semi_major,
            p.ellipse.semi_minor,
            p.ellipse.orientation,
            p.saturated_pixels,
            p.below_range_pixels,
            p.touches_border,
        )?;
    }

    // Annotated PNG, encoded in memory.
    let png = film::annotated_png(&scan, &det, Some(&matching))?;

    let stem = args
        .scan
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scan".into());
    // Both files land together or not at all.
    let mut set = tyreroad::scenario::output::OutputSet::new(&args.out)?;
    set.write(&format!("{stem}-prints.csv"), csv.as_bytes())?;
    set.write(&format!("{stem}-annotated.png"), &png)?;
    let written = set.commit()?;

    println!(
        "{}: {} prints ({} matched, {} stray), threshold grey {:.4}, background {:.4}, pixel {:.3e} m",
        args.scan.display(),
        det.prints.len(),
        matching.matches.len(),
        matching.unmatched_prints.len(),
        det.threshold_grey,
        det.background_grey,
        det.pixel_size
    );
    let saturated: usize = det.prints.iter().map(|p| p.saturated_pixels).sum();
    if saturated > 0 {
        println!("warning: {saturated} saturated pixels: forces there are lower bounds");
    }
    if let Some(c) = &comparison {
        let t = &c.table1;
        println!(
            "load {} N, {} indenters ({:?}): mean |eps_P| = {:.1} % +- {:.1} %, mean |eps_a| = {:.1} % +- {:.1} %",
            t.load_n,
            t.indenters,
            estimator,
            100.0 * t.force.mean_abs,
            100.0 * t.force.std_abs,
            100.0 * t.radius.mean_abs,
            100.0 * t.radius.std_abs
        );
    }
    for w in &written {
        println!("wrote {}", w.display());
    }
    Ok(())
}

/// The synthetic Table 1 for `cargo xtask validate`: renders the model rows
/// (one per load and indenter, e.g. the static model's 25 balls at 289–500
/// N) as Hertzian prints on a synthetic LLW film, analyses them and
/// compares with the model. Returns the table as text, labelled synthetic.
/// With `options = None`, [`film::SyntheticOptions::llw_default`].
pub fn synthetic_table(
    rows: &[film::ModelRow],
    options: Option<&film::SyntheticOptions>,
) -> Result<String> {
    let default;
    let o = match options {
        Some(o) => o,
        None => {
            default = film::SyntheticOptions::llw_default()?;
            &default
        }
    };
    let res = film::synthetic_round_trip(rows, o)?;
    let mut s = String::new();
    writeln!(
        s,
        "Table 1 (SYNTHETIC film round trip: model forces/radii rendered as Hertz prints on LLW \
         film, grain {} D, blur {} px, {:.0} um pixels, then analysed)",
        o.render.grain_sigma,
        o.render.blur_sigma_px,
        o.pixel_size * 1e6
    )?;
    writeln!(
        s,
        "{:>8} | {:^27} | {:^27}",
        "", "paper's estimator (mean grey)", "Hertz-profile fit"
    )?;
    writeln!(
        s,
        "{:>8} | {:>12} {:>14} | {:>12} {:>14}",
        "P (N)", "eps_P (%)", "eps_a (%)", "eps_P (%)", "eps_a (%)"
    )?;
    for l in &res {
        let m = &l.mean_grey.table1;
        let h = &l.hertz_fit.table1;
        writeln!(
            s,
            "{:>8.0} | {:>5.1} +- {:<4.1} {:>6.1} +- {:<4.1} | {:>5.1} +- {:<4.1} {:>6.1} +- {:<4.1}",
            l.load_n,
            100.0 * m.force.mean_abs,
            100.0 * m.force.std_abs,
            100.0 * m.radius.mean_abs,
            100.0 * m.radius.std_abs,
            100.0 * h.force.mean_abs,
            100.0 * h.force.std_abs,
            100.0 * h.radius.mean_abs,
            100.0 * h.radius.std_abs,
        )?;
    }
    Ok(s)
}
