//! A viscoelastic tread fitted to a measured master curve
//! (`[material.viscoelastic] master_curve`, docs/viscoelastic.md "Fit from
//! a master curve"): the CSV read within the range of `[material]
//! youngs_modulus`, the Prony fit, and what a run should say of the curve.

use std::path::Path;

use tyreroad_viscoelastic::{MasterCurve, Prony, STORAGE_NOISE, fit_prony};

use super::ranges::MODULUS_RANGE;
use super::visco::visco_error;
use super::{Scenario, ScenarioError};

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
    let text = tyreroad_core::read_input_text(&path)
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

impl Scenario {
    /// [`Self::viscoelastic_material`], with what a run should say of its
    /// master curve (a storage modulus that dips with frequency, which the
    /// fit smooths over; as a rolling run's road summary says it).
    ///
    /// # Errors
    /// As [`Self::viscoelastic_material`].
    pub fn viscoelastic_material_noted(
        &self,
        base_dir: &Path,
    ) -> Result<Option<(Prony, Option<String>)>, ScenarioError> {
        let Some(spec) = &self.material.viscoelastic else {
            return Ok(None);
        };
        let (series, note) = spec
            .fitted(self.material.poisson_ratio, base_dir)
            .map_err(|e| self.located(e))?;
        spec.at(&series, None)
            .map(|series| Some((series, note)))
            .map_err(|e| self.located(e))
    }
}
