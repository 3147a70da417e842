//! The final summary of `cargo xtask run`: every item that did not get the
//! full-fidelity, converged result, with why; `--strict` turns any of them
//! into a non-zero exit, after the outputs are written.

use anyhow::Result;
use tyreroad::multipoint::Convergence;
use tyreroad::rolling::{Recovery, StepStatus};
use tyreroad::scenario::output::steps_stream::NotConverged;
use tyreroad::scenario::{CalibrationSummary, StaticResult, TextureResult};

/// Items listed one per line; beyond this many the rest are counted (each is
/// in the outputs' status columns).
const LISTED: usize = 20;

/// What fell back in one run, and why.
#[derive(Debug, Default)]
pub struct Fallbacks {
    items: Vec<String>,
}

impl Fallbacks {
    /// The loads of a static run that did not converge (not written) or
    /// stagnated (written, accepted above the tolerance).
    pub fn from_static(r: &StaticResult) -> Self {
        let mut f = Self::default();
        f.add_static(r);
        f
    }

    fn add_static(&mut self, r: &StaticResult) {
        for (load, why) in &r.failed_loads {
            self.items
                .push(format!("load {load} N: not solved, not written ({why})"));
        }
        self.items.extend(r.warnings.iter().cloned());
        for run in &r.runs {
            if let Convergence::Stagnated { residual } = run.convergence {
                self.items.push(format!(
                    "load {} N: the solve stagnated at a relative residual of {residual:.3e}, \
                     above the tolerance but within the acceptable one (written)",
                    run.load
                ));
            }
        }
    }

    /// As [`Fallbacks::from_static`], the texture's warnings, each asperity
    /// whose two-scale field is a lower-fidelity fallback, and each pressed
    /// past its cap table.
    pub fn from_texture(r: &TextureResult) -> Self {
        let mut f = Self::from_static(&r.statics);
        f.add_warnings(r.texture.warnings.iter().cloned());
        if let Some(cal) = &r.texture.calibration {
            f.add_calibration(cal);
        }
        let ids = r.ids();
        for (run, per_load) in r.statics.runs.iter().zip(&r.loads) {
            for (k, status) in per_load.two_scale.fallbacks() {
                let id = ids.get(k).copied().unwrap_or(k as u32 + 1);
                f.items.push(format!(
                    "load {} N, asperity {id}: two-scale field {status}",
                    run.load
                ));
            }
            for past in &per_load.past_caps {
                let id = ids
                    .get(past.index)
                    .copied()
                    .unwrap_or(past.index as u32 + 1);
                f.items
                    .push(format!("load {} N, asperity {id}: {past}", run.load));
            }
        }
        f
    }

    /// The rolling steps not `converged`: stagnated (kept, looser residual)
    /// or failed (NaN in the outputs, bridged in the spectra).
    pub fn from_rolling(not_converged: &[NotConverged]) -> Self {
        let mut f = Self::default();
        for s in not_converged {
            let what = match s.status {
                StepStatus::Converged => continue,
                StepStatus::Stagnated if s.recovery == Recovery::ProfileSlope => format!(
                    "the deformed tread's slopes did not settle (last move {:.3e} of the \
                     load): kept solved under the tread's profile slope",
                    s.residual
                ),
                StepStatus::Stagnated => format!(
                    "stagnated at a relative residual of {:.3e} (kept)",
                    s.residual
                ),
                StepStatus::Failed => "failed (NaN in time_signals.csv)".to_owned(),
            };
            f.items.push(format!(
                "step {} at x = {:.6} m: {what}",
                s.index, s.position
            ));
        }
        f
    }

    /// Each cap of a calibrated road whose calibration failed and that
    /// kept its Wilke law, and the contacts pressed past their tables
    /// (their laws extrapolated, not solved).
    pub fn add_calibration(&mut self, cal: &CalibrationSummary) {
        self.items.extend(cal.warnings());
    }

    /// Warnings printed with the run's report (a road pressed past its
    /// shapes, a footprint off the map, a window too narrow): each is an
    /// item, so that `--strict` does not pass a run whose answer they put
    /// in doubt.
    pub fn add_warnings(&mut self, warnings: impl IntoIterator<Item = String>) {
        self.items
            .extend(warnings.into_iter().map(|w| format!("warning: {w}")));
    }

    /// How many items fell back.
    pub fn len(&self) -> usize {
        self.items.len()
    }

    /// The summary lines: one per item (at most [`LISTED`], then a count).
    pub fn lines(&self) -> Vec<String> {
        if self.items.is_empty() {
            return vec!["summary: every item converged at full fidelity".to_owned()];
        }
        let mut lines = vec![format!(
            "summary: {} items fell back, did not converge or were warned of:",
            self.items.len()
        )];
        lines.extend(self.items.iter().take(LISTED).map(|i| format!("  - {i}")));
        if self.items.len() > LISTED {
            lines.push(format!(
                "  ... and {} more (see the status columns of the outputs)",
                self.items.len() - LISTED
            ));
        }
        lines
    }

    /// Prints the summary, then with `strict` fails when anything fell back.
    ///
    /// # Errors
    /// With `strict`, when any item fell back (the outputs are written).
    pub fn finish(&self, strict: bool) -> Result<()> {
        for line in self.lines() {
            say!("{line}");
        }
        if strict && self.len() > 0 {
            anyhow::bail!(
                "--strict: {} items fell back, did not converge or were warned of (outputs \
                 written; listed above)",
                self.len()
            );
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn strict_fails_on_any_item_and_lists_each_with_its_reason() {
        let mut f = Fallbacks::default();
        assert!(f.finish(true).is_ok());
        assert_eq!(f.lines().len(), 1);
        f.items.push("load 50 N: not solved".into());
        assert!(f.finish(false).is_ok());
        let e = f.finish(true).map_err(|e| e.to_string());
        assert!(e.is_err_and(|e| e.contains("--strict: 1 items")));
        f.items.extend((0..30).map(|k| format!("step {k}")));
        let lines = f.lines();
        assert_eq!(lines.len(), 1 + LISTED + 1);
        assert!(lines[1].contains("load 50 N: not solved"));
        assert!(lines.last().is_some_and(|l| l.contains("11 more")));
    }

    /// Regression (adversarial run, 2026-11-30): `--strict` passed a
    /// rolling run whose every contact was pressed past its cap, the
    /// warning printed but not counted.
    #[test]
    fn warnings_are_summary_items_that_strict_fails_on() {
        let mut f = Fallbacks::default();
        f.add_warnings(vec![
            "at 4 of 4 steps, 12 contacts were pressed past their caps".to_owned(),
        ]);
        assert_eq!(f.len(), 1);
        assert!(f.lines()[1].contains("warning: at 4 of 4 steps"));
        let e = f.finish(true).map_err(|e| e.to_string());
        assert!(e.is_err_and(|e| e.contains("were warned of")));
        assert!(f.finish(false).is_ok());
    }

    #[test]
    fn a_cap_that_kept_its_wilke_law_is_listed_with_why() {
        let cal = CalibrationSummary {
            asperities: 12,
            tables: 11,
            from_disk: 0,
            max_approach: 3e-3,
            bulk_sag: 0.0,
            deepened: 0,
            time: std::time::Duration::ZERO,
            past_tables: Default::default(),
            fallbacks: vec![tyreroad::fidelity::CapFallback {
                id: 7,
                summit: [12.5e-3, 3.25e-3],
                reason: "calibration BEM: not converged".into(),
            }],
            fields: false,
        };
        let mut f = Fallbacks::default();
        f.add_calibration(&cal);
        assert_eq!(f.len(), 1);
        let past = CalibrationSummary {
            past_tables: tyreroad::fidelity::rolling::PastTables {
                steps: 3,
                contacts: 4,
                worst_ratio: 1.36,
            },
            fallbacks: Vec::new(),
            ..cal.clone()
        };
        let mut g = Fallbacks::default();
        g.add_calibration(&past);
        assert_eq!(g.len(), 1);
        assert!(g.lines()[1].contains("pressed past their calibration tables"));
        assert!(f.lines()[1].contains(
            "asperity 7 (summit at x = 12.500 mm, y = 3.250 mm): calibration failed \
             (calibration BEM: not converged); its Wilke law kept"
        ));
        assert!(f.finish(true).is_err());
    }

    #[test]
    fn every_rolling_step_not_converged_is_listed_with_its_status() {
        let step = |index: usize, status: StepStatus| NotConverged {
            index,
            position: 0.001 * index as f64,
            status,
            residual: 2e-9,
            recovery: Recovery::None,
        };
        let on_profile = NotConverged {
            residual: 7e-3,
            recovery: Recovery::ProfileSlope,
            ..step(3, StepStatus::Stagnated)
        };
        let steps = [
            step(0, StepStatus::Converged),
            step(1, StepStatus::Stagnated),
            step(2, StepStatus::Failed),
            on_profile,
        ];
        let f = Fallbacks::from_rolling(&steps);
        assert_eq!(f.len(), 3);
        let lines = f.lines();
        assert!(
            lines[1]
                .contains("step 1 at x = 0.001000 m: stagnated at a relative residual of 2.000e-9")
        );
        assert!(lines[2].contains("step 2 at x = 0.002000 m: failed"));
        assert!(lines[3].contains(
            "step 3 at x = 0.003000 m: the deformed tread's slopes did not settle (last move \
             7.000e-3 of the load): kept solved under the tread's profile slope"
        ));
        assert!(f.finish(true).is_err());
    }
}
