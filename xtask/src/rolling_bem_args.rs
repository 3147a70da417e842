//! The arguments of `cargo xtask rolling-bem` and the row format of its
//! comparison tables, shared by the elastic (`rolling_bem_cmd`) and the
//! viscoelastic (`rolling_visco_bem_cmd`) runs so that neither command module
//! imports the other's internals.

use std::path::PathBuf;

use serde::Serialize;
use tyreroad::bem_rolling::{BemRollingResult, SignalComparison};
use tyreroad::rolling::RollingResult;
use tyreroad::scenario::output::fmt;

/// Arguments of `rolling-bem`.
#[derive(clap::Args)]
pub struct RollingBemArgs {
    /// A `[rolling]` scenario on a `[texture]`.
    pub scenario: PathBuf,
    /// Output directory.
    #[arg(long, default_value = "validation/rolling_bem")]
    pub out: PathBuf,
    /// First footprint centre, in metres (default: the path's start).
    #[arg(long)]
    pub from: Option<f64>,
    /// Steps from there (default 100; never beyond the path's end).
    #[arg(long, default_value_t = 100)]
    pub steps: usize,
    /// Welch segment of both runs' spectra, in samples (default: the
    /// scenario's `[rolling] segment`, else half the signal).
    #[arg(long)]
    pub segment: Option<usize>,
    /// Threads of both runs (0: every core).
    #[arg(long, default_value_t = 0, value_parser = crate::parse_threads)]
    pub threads: usize,
    /// Relative tolerance of each BEM step (within the range a scenario's
    /// `[solver] tolerance` accepts).
    #[arg(long, default_value_t = 1e-7, value_parser = parse_tolerance)]
    pub tolerance: f64,
    /// A viscoelastic tread `E_INF,E1@TAU1,E2@TAU2,...` (Pa, s): run the
    /// viscoelastic rolling BEM and the elastic one at its two limit
    /// moduli instead of the multipoint comparison.
    #[arg(long)]
    pub viscoelastic: Option<String>,
    /// Driving speed (m/s), instead of the scenario's (within the range
    /// `[rolling] speed` accepts).
    #[arg(long, value_parser = parse_speed)]
    pub speed: Option<f64>,
    /// Leave out the scenario's `[material.viscoelastic]`: compare the
    /// elastic runs with its `[material]` (the model's own error on the
    /// stretch of a viscoelastic comparison).
    #[arg(long, conflicts_with = "viscoelastic")]
    pub elastic: bool,
    /// Is the BEM reference converged? Solve the stretch by the BEM alone
    /// on the texture's grid and on one this many times finer
    /// (`rolling_bem_refine`), instead of the comparison.
    #[arg(long, conflicts_with = "viscoelastic", value_parser = parse_refinement)]
    pub refine: Option<usize>,
    /// The model's fidelity (`wilke`, `calibrated` or
    /// `calibrated_fields`), instead of the scenario's `[model] fidelity`.
    #[arg(long, conflicts_with = "viscoelastic")]
    pub fidelity: Option<String>,
    /// What the calibrated rungs' caps are calibrated under (`flat`,
    /// `tread` or `tread_slope`), instead of the scenario's `[model] calibrate_under`.
    #[arg(long, conflicts_with = "viscoelastic")]
    pub calibrate_under: Option<String>,
    /// Compare against the BEM signals an earlier `rolling-bem` run of the
    /// same stretch wrote to this directory instead of solving the BEM
    /// again.
    #[arg(long, conflicts_with = "viscoelastic")]
    pub bem_from: Option<PathBuf>,
    /// Is the reference converged in the bands compared? A second BEM run
    /// of the same stretch (another grid) that an earlier `rolling-bem`
    /// wrote to this directory, compared with this run's BEM as the model
    /// is (rows "BEM check"; docs/validation.md, "Where the bands miss").
    #[arg(long, conflicts_with = "viscoelastic")]
    pub bem_check: Option<PathBuf>,
}

/// One row of the comparison table: per-step and band errors of a signal.
pub(crate) fn print_report_row(label: &str, s: &SignalComparison) {
    say!("{}", report_row(label, s));
}

/// [`print_report_row`]'s line. A column over no band says `none`, not
/// the library's empty maxima (`0`, `−∞`), which read as agreement.
fn report_row(label: &str, s: &SignalComparison) -> String {
    let any = !s.bands.is_empty();
    let resolved = s.bands.iter().any(|b| b.resolved);
    let db = |show: bool, v: f64, digits: usize| {
        if show {
            format!("{v:.digits$}")
        } else {
            "none".to_owned()
        }
    };
    format!(
        "{:<22} {:>12.2} {:>12.2} {:>14} {:>14} {:>14} {:>10}",
        label,
        100.0 * s.max_error,
        100.0 * s.rms_error,
        db(any, s.max_band_db(), 2),
        db(resolved, s.max_resolved_band_db(), 2),
        db(resolved, s.max_resolved_error_db(), 1),
        s.spectrum.name()
    )
}

/// The header of [`print_report_row`]'s table, with what its last two
/// columns mean.
pub(crate) fn print_report_header() {
    say!(
        "bands: \"transient\" for a signal at rest at both ends of the stretch in both runs \
         (the whole record, no window: every band resolved), else \"welch\"; \
         err dB = the error signal's level re the BEM's in the band \
         (within 1 dB whatever its phase at or below {:.1} dB)",
        tyreroad::bem_rolling::ERROR_DB_FOR_1DB
    );
    say!(
        "{:<22} {:>12} {:>12} {:>14} {:>14} {:>14} {:>10}",
        "signal",
        "max err %",
        "rms err %",
        "max |ΔdB| all",
        "max |ΔdB| res.",
        "max err dB res.",
        "bands"
    );
}

/// `--tolerance`: a reference solved looser than the model it judges
/// would judge nothing; the same range as `[solver] tolerance`.
fn parse_tolerance(text: &str) -> Result<f64, String> {
    let [lo, hi] = tyreroad::scenario::TOLERANCE_RANGE;
    match text.trim().parse::<f64>() {
        Ok(t) if (lo..=hi).contains(&t) => Ok(t),
        _ => Err(format!(
            "`{text}`: expected a relative tolerance in [{lo:e}, {hi:e}]"
        )),
    }
}

/// `--speed V`: m/s, the range of `[rolling] speed` (1e300 m/s was
/// accepted, and gave a sample rate no band fits).
fn parse_speed(text: &str) -> Result<f64, String> {
    let [lo, hi] = tyreroad::scenario::SPEED_RANGE;
    match text.trim().parse::<f64>() {
        Ok(v) if (lo..=hi).contains(&v) => Ok(v),
        _ => Err(format!("`{text}`: expected a speed in [{lo:e}, {hi}] m/s")),
    }
}

/// `--refine F`: a grid F times finer, F ≥ 2 (1 would compare the grid
/// with itself, and print 0/0; a grid too large is the library's refusal).
fn parse_refinement(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(f) if f >= 2 => Ok(f),
        _ => Err(format!(
            "`{text}`: expected a refinement factor of 2 or more"
        )),
    }
}

/// One step of both runs (`rolling_bem_steps.csv`,
/// `rolling_visco_compare_steps.csv`: the same columns).
#[derive(Serialize)]
pub(crate) struct ComparedStepRow {
    step: usize,
    #[serde(serialize_with = "fmt::sci9")]
    time_s: f64,
    #[serde(serialize_with = "fmt::sci9")]
    position_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    total_force_model_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    total_force_bem_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    approach_model_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    approach_bem_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    contact_area_model_m2: f64,
    #[serde(serialize_with = "fmt::sci9")]
    contact_area_bem_m2: f64,
}

/// The per-step rows of a multipoint run beside the BEM's, step by step.
pub(crate) fn compared_step_rows(
    model: &RollingResult,
    bem: &BemRollingResult,
) -> Vec<ComparedStepRow> {
    model
        .steps
        .iter()
        .zip(&bem.steps)
        .map(|(m, b)| ComparedStepRow {
            step: m.index,
            time_s: m.time,
            position_m: m.position,
            total_force_model_n: m.total_force,
            total_force_bem_n: b.total_force,
            approach_model_m: m.approach,
            approach_bem_m: b.approach,
            contact_area_model_m2: m.contact_area,
            contact_area_bem_m2: b.contact_area,
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (adversarial run, 2026-11-30): a comparison whose bands
    /// were all unresolved printed `0.00` and `-inf` in the band columns,
    /// read as perfect agreement.
    #[test]
    fn a_signal_with_no_resolved_band_says_none_in_the_band_columns() {
        use tyreroad::bem_rolling::{BandComparison, SpectrumKind};
        let band = |resolved| BandComparison {
            nominal: 1000.0,
            model_db: 80.0,
            reference_db: 74.0,
            difference_db: 6.0,
            error_db: 1.5,
            resolved,
        };
        let mut s = SignalComparison {
            name: "centre".into(),
            scale: 1.0,
            max_error: 0.1,
            rms_error: 0.05,
            spectrum: SpectrumKind::Welch,
            bands: vec![band(false)],
        };
        let row = report_row("centre", &s);
        assert!(
            row.contains("6.00") && row.matches("none").count() == 2,
            "{row}"
        );
        s.bands = vec![band(true)];
        let row = report_row("centre", &s);
        assert!(!row.contains("none") && row.contains("1.5"), "{row}");
        s.bands.clear();
        assert_eq!(report_row("centre", &s).matches("none").count(), 3);
    }

    /// Regression (adversarial run, 2026-11-30): `--speed 1e300` and
    /// `1e-9` were accepted; the range is `[rolling] speed`'s.
    #[test]
    fn a_speed_outside_the_scenarios_range_is_refused() {
        assert_eq!(parse_speed("13.9"), Ok(13.9));
        for bad in ["1e300", "1e-9", "0", "-5", "nan", "fast"] {
            let e = parse_speed(bad).expect_err("refused");
            assert!(
                e.contains("expected a speed in [1e-3, 500] m/s"),
                "{bad}: {e}"
            );
        }
    }
}
