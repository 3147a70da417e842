//! `cargo xtask film`: analyse a pressure-film scan (Fuji Prescale) against
//! an indenter layout, optionally compare with a model run, and write a
//! per-print CSV and an annotated PNG. Also the synthetic Table 1 used by
//! `cargo xtask validate`.

use std::fmt::Write as _;
use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use serde::Serialize;
use tyreroad::film;
use tyreroad::scenario::output::{csv_bytes, fmt};

/// The columns of `<scan>-prints.csv`.
const PRINT_CSV_HEADER: &str = "indenter,x_m,y_m,pixels,area_m2,mean_grey,mean_grey_density,\
    pressure_of_mean_grey_pa,mean_grey_flag,mean_pixel_pressure_pa,force_n,radius_m,\
    semi_major_m,semi_minor_m,orientation_rad,hertz_force_n,hertz_radius_m,saturated_pixels,\
    below_range_pixels,touches_border,force_model_n,radius_model_m,eps_force,eps_radius";

/// One matched print (empty fields: no calibrated value, no Hertz fit, no
/// model to compare with).
#[derive(Serialize)]
struct PrintRow {
    indenter: u32,
    #[serde(rename = "x_m", serialize_with = "fmt::sci6")]
    x: f64,
    #[serde(rename = "y_m", serialize_with = "fmt::sci6")]
    y: f64,
    pixels: usize,
    #[serde(rename = "area_m2", serialize_with = "fmt::sci6")]
    area: f64,
    #[serde(serialize_with = "fmt::fixed6")]
    mean_grey: f64,
    #[serde(serialize_with = "fmt::fixed6")]
    mean_grey_density: f64,
    #[serde(rename = "pressure_of_mean_grey_pa", serialize_with = "fmt::opt_sci6")]
    pressure_of_mean_grey: Option<f64>,
    mean_grey_flag: &'static str,
    #[serde(rename = "mean_pixel_pressure_pa", serialize_with = "fmt::sci6")]
    mean_pixel_pressure: f64,
    #[serde(rename = "force_n", serialize_with = "fmt::sci6")]
    force: f64,
    #[serde(rename = "radius_m", serialize_with = "fmt::sci6")]
    radius: f64,
    #[serde(rename = "semi_major_m", serialize_with = "fmt::sci6")]
    semi_major: f64,
    #[serde(rename = "semi_minor_m", serialize_with = "fmt::sci6")]
    semi_minor: f64,
    #[serde(rename = "orientation_rad", serialize_with = "fmt::fixed6")]
    orientation: f64,
    #[serde(rename = "hertz_force_n", serialize_with = "fmt::opt_sci6")]
    hertz_force: Option<f64>,
    #[serde(rename = "hertz_radius_m", serialize_with = "fmt::opt_sci6")]
    hertz_radius: Option<f64>,
    saturated_pixels: usize,
    below_range_pixels: usize,
    touches_border: bool,
    #[serde(rename = "force_model_n", serialize_with = "fmt::opt_sci6")]
    force_model: Option<f64>,
    #[serde(rename = "radius_model_m", serialize_with = "fmt::opt_sci6")]
    radius_model: Option<f64>,
    #[serde(serialize_with = "fmt::opt_fixed6")]
    eps_force: Option<f64>,
    #[serde(serialize_with = "fmt::opt_fixed6")]
    eps_radius: Option<f64>,
}

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
    /// top-left corner); default: estimated from the prints' centroid
    /// (a one-indenter layout on a scan of several prints needs it given).
    #[arg(long)]
    pub origin: Option<String>,
    /// Force and radius estimator: `mean-grey` (the paper's), `pixel-mean`
    /// or `hertz-fit`.
    #[arg(long, default_value = "mean-grey")]
    pub estimator: String,
    /// Grey threshold (0–1) instead of half-way to the calibration floor.
    #[arg(long)]
    pub threshold: Option<f64>,
    /// Scanner white reference (normalised grey of D = 0), in (0, 1].
    #[arg(long, default_value_t = 1.0)]
    pub white: f64,
    /// Scanner black reference (normalised grey of no reflected light), in
    /// [0, 1) and below --white.
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
    let scanner = film::Scanner::new(args.white, args.black).with_context(|| {
        format!(
            "scanner references --white {} --black {}",
            args.white, args.black
        )
    })?;
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
            if !(col.is_finite() && row.is_finite()) {
                bail!("--origin {s:?}: expected finite pixel coordinates COL,ROW");
            }
            film::Origin::Pixel { col, row }
        }
    };
    let mut options = film::AnalysisOptions::default();
    if let Some(t) = args.threshold {
        options.threshold = film::Threshold::Grey(t);
    }
    let det = film::analyse(&scan, &response, &options)
        .with_context(|| format!("analysing {}", args.scan.display()))?;
    if let film::Origin::Pixel { col, row } = origin
        && !((0.0..=det.width as f64).contains(&col) && (0.0..=det.height as f64).contains(&row))
    {
        bail!(
            "--origin {col},{row}: outside the {} × {} pixel scan",
            det.width,
            det.height
        );
    }
    if args.load.is_some() && args.model.is_none() {
        bail!("--load chooses a load of the --model file: give --model too");
    }
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
            check_model_layout(&model, &layout, path)?;
            Some(film::compare(load, &measured, &model)?)
        }
    };

    // Per-print CSV.
    let mut rows = Vec::with_capacity(matching.matches.len());
    for (m, &(number, force, radius)) in matching.matches.iter().zip(&measured) {
        let p = &det.prints[m.print];
        let (pressure_of_mean_grey, flag) = match p.pressure_of_mean_grey {
            film::Calibrated::InRange(v) => (Some(v), "in_range"),
            film::Calibrated::BelowRange => (None, "below_range"),
            film::Calibrated::Saturated => (None, "saturated"),
        };
        let model = comparison
            .as_ref()
            .and_then(|c| c.indenters.iter().find(|i| i.indenter == number));
        rows.push(PrintRow {
            indenter: number,
            x: m.centroid.0,
            y: m.centroid.1,
            pixels: p.pixel_count,
            area: p.area,
            mean_grey: p.mean_grey,
            mean_grey_density: p.mean_grey_density,
            pressure_of_mean_grey,
            mean_grey_flag: flag,
            mean_pixel_pressure: p.mean_pixel_pressure,
            force,
            radius,
            semi_major: p.ellipse.semi_major,
            semi_minor: p.ellipse.semi_minor,
            orientation: p.ellipse.orientation,
            hertz_force: p.hertz.map(|h| h.force),
            hertz_radius: p.hertz.map(|h| h.radius),
            saturated_pixels: p.saturated_pixels,
            below_range_pixels: p.below_range_pixels,
            touches_border: p.touches_border,
            force_model: model.map(|i| i.force_model),
            radius_model: model.map(|i| i.radius_model),
            eps_force: model.map(|i| i.eps_force),
            eps_radius: model.map(|i| i.eps_radius),
        });
    }
    let csv = if rows.is_empty() {
        format!("{}\n", PRINT_CSV_HEADER).into_bytes()
    } else {
        csv_bytes(None, &rows)?
    };

    // Annotated PNG, encoded in memory.
    let png = film::annotated_png(&scan, &det, Some(&matching))?;

    let stem = args
        .scan
        .file_stem()
        .map(|s| s.to_string_lossy().into_owned())
        .unwrap_or_else(|| "scan".into());
    // Both files land together or not at all.
    let mut set = tyreroad::scenario::output::OutputSet::new(&args.out)?;
    set.write(&format!("{stem}-prints.csv"), &csv)?;
    set.write(&format!("{stem}-annotated.png"), &png)?;
    let written = set.commit()?;

    say!(
        "{}: {} prints ({} matched, {} stray), threshold grey {:.4}, background {:.4}, pixel {:.3e} m",
        args.scan.display(),
        det.prints.len(),
        matching.matches.len(),
        matching.unmatched_prints.len(),
        det.threshold_grey,
        det.background_grey,
        det.pixel_size
    );
    for warning in det.warnings() {
        say!("warning: {warning}");
    }
    let saturated: usize = det.prints.iter().map(|p| p.saturated_pixels).sum();
    if saturated > 0 {
        say!("warning: {saturated} saturated pixels: forces there are lower bounds");
    }
    if let Some(c) = &comparison {
        let t = &c.table1;
        say!(
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
        say!("wrote {}", w.display());
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

/// The model rows of a load against the film's layout: every model
/// indenter must be in the layout, at its position to within
/// [`MODEL_POSITION_TOLERANCE`] (the model of another layout, or of another
/// frame, would be compared print by print with the wrong indenters).
fn check_model_layout(model: &[film::ModelRow], layout: &film::Layout, path: &Path) -> Result<()> {
    for row in model {
        let Some(at) = layout.indenters().iter().find(|i| i.number == row.indenter) else {
            bail!(
                "{}: indenter {} of the model is not in the layout",
                path.display(),
                row.indenter
            );
        };
        let off = (row.x_m - at.x).hypot(row.y_m - at.y);
        if off > MODEL_POSITION_TOLERANCE {
            bail!(
                "{}: indenter {} of the model at ({}, {}) m lies {off:.3e} m from the layout's \
                 ({}, {}) m: the model of another layout or frame?",
                path.display(),
                row.indenter,
                row.x_m,
                row.y_m,
                at.x,
                at.y
            );
        }
    }
    Ok(())
}

/// How far a model indenter may lie from its layout position (m).
const MODEL_POSITION_TOLERANCE: f64 = 1e-3;

#[cfg(test)]
mod print_csv_tests {
    use super::*;

    /// Regression (adversarial run, 2026-11-29): a model 0.5 m off the
    /// layout, or of an indenter the layout lacks, was compared all the same.
    #[test]
    fn a_model_off_the_layout_is_refused() {
        let layout = film::Layout::new(vec![film::Indenter {
            number: 1,
            x: 0.01,
            y: 0.0,
        }])
        .expect("layout");
        let row = |indenter, x_m| film::ModelRow {
            load_n: 10.0,
            indenter,
            x_m,
            y_m: 0.0,
            force_n: 10.0,
            radius_m: 1e-3,
        };
        let path = Path::new("m.csv");
        assert!(check_model_layout(&[row(1, 0.0101)], &layout, path).is_ok());
        let far = check_model_layout(&[row(1, 0.5)], &layout, path).expect_err("far");
        assert!(far.to_string().contains("from the layout's"), "{far}");
        let absent = check_model_layout(&[row(2, 0.01)], &layout, path).expect_err("absent");
        assert!(absent.to_string().contains("not in the layout"), "{absent}");
    }

    fn row(model: bool) -> PrintRow {
        PrintRow {
            indenter: 7,
            x: 0.0123,
            y: -0.004,
            pixels: 321,
            area: 1.2e-5,
            mean_grey: 0.4,
            mean_grey_density: 0.75,
            pressure_of_mean_grey: model.then_some(1.5e6),
            mean_grey_flag: if model { "in_range" } else { "saturated" },
            mean_pixel_pressure: 1.4e6,
            force: 12.5,
            radius: 2.1e-3,
            semi_major: 2.2e-3,
            semi_minor: 2.0e-3,
            orientation: 0.3,
            hertz_force: model.then_some(12.0),
            hertz_radius: model.then_some(2.05e-3),
            saturated_pixels: 0,
            below_range_pixels: 3,
            touches_border: false,
            force_model: model.then_some(13.0),
            radius_model: model.then_some(2.0e-3),
            eps_force: model.then_some(-0.04),
            eps_radius: model.then_some(0.05),
        }
    }

    /// The line the hand-written CSV produced.
    fn by_hand(r: &PrintRow) -> String {
        let o6e = |v: Option<f64>| v.map(|v| format!("{v:.6e}")).unwrap_or_default();
        let o6 = |v: Option<f64>| v.map(|v| format!("{v:.6}")).unwrap_or_default();
        format!(
            "{},{:.6e},{:.6e},{},{:.6e},{:.6},{:.6},{},{},{:.6e},{:.6e},{:.6e},{:.6e},{:.6e},{:.6},{},{},{},{},{},{},{},{},{}",
            r.indenter,
            r.x,
            r.y,
            r.pixels,
            r.area,
            r.mean_grey,
            r.mean_grey_density,
            o6e(r.pressure_of_mean_grey),
            r.mean_grey_flag,
            r.mean_pixel_pressure,
            r.force,
            r.radius,
            r.semi_major,
            r.semi_minor,
            r.orientation,
            o6e(r.hertz_force),
            o6e(r.hertz_radius),
            r.saturated_pixels,
            r.below_range_pixels,
            r.touches_border,
            o6e(r.force_model),
            o6e(r.radius_model),
            o6(r.eps_force),
            o6(r.eps_radius),
        )
    }

    #[test]
    fn serde_rows_write_the_bytes_of_the_hand_written_csv() -> Result<()> {
        let rows = [row(true), row(false)];
        let text = String::from_utf8(csv_bytes(None, &rows)?)?;
        let expected = format!(
            "{PRINT_CSV_HEADER}\n{}\n{}\n",
            by_hand(&rows[0]),
            by_hand(&rows[1])
        );
        assert_eq!(text, expected);
        Ok(())
    }
}
