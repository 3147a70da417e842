//! A viscoelastic tread fitted to a measured master curve
//! (`[material.viscoelastic] master_curve`, docs/viscoelastic.md "Fit from
//! a master curve"): the CSV read within the range of `[material]
//! youngs_modulus`, the Prony fit, and what a run should say of the curve.

use std::path::Path;

use tyreroad_viscoelastic::{MasterCurve, Prony, STORAGE_NOISE, fit_prony};

use super::ScenarioError;
use super::ranges::MODULUS_RANGE;
use super::visco::visco_error;

/// The series fitted to the master curve `file` (relative to `base_dir`)
/// with `per_decade` relaxation times per decade (3 if not given), and a
/// warning when its storage modulus dips with frequency by more than
/// [`STORAGE_NOISE`]: the fit smooths such a dip over, and a fall past
/// [`tyreroad_viscoelastic::MAX_STORAGE_FALL`] is the fit's error.
///
/// # Errors
/// [`ScenarioError::Io`] for an unreadable file; [`ScenarioError::Invalid`]
/// naming `master_curve` for a malformed curve, a modulus outside
/// [`MODULUS_RANGE`] (by its line and column) or a fit that fails.
pub(super) fn fit(
    file: &str,
    base_dir: &Path,
    per_decade: Option<usize>,
    poisson_ratio: f64,
) -> Result<(Prony, Option<String>), ScenarioError> {
    let path = base_dir.join(file);
    let text = std::fs::read_to_string(&path)
        .map_err(ScenarioError::io("reading the master curve", &path))?;
    let curve =
        MasterCurve::parse_csv_within(&text, MODULUS_RANGE).map_err(visco_error("master_curve"))?;
    let series = fit_prony(&curve, per_decade.unwrap_or(3), poisson_ratio)
        .map_err(visco_error("master_curve"))?;
    let warning = curve
        .storage_fall()
        .filter(|fall| fall.fraction() > STORAGE_NOISE)
        .map(|fall| {
            format!(
                "master curve {file}: {fall}; a passive tread's E' does not decrease with \
                 frequency, and the fitted series smooths the dip over: check the measurement"
            )
        });
    Ok((series, warning))
}
