//! A rolling run whose records were written as they arrived
//! ([`output::steps_stream`](super::output::steps_stream)): a distributed
//! run's rank 0 writes each rank's records in path order and keeps only
//! the signals, from which the run is finished here (road summary,
//! spectra), as [`Scenario::finish_rolling`] finishes whole records.

use tyreroad_rolling as rolling;

use super::output::steps_stream::StepSignals;
use super::output::summits::SummitSource;
use super::rolling::{Rolled, Signals, What, spectra_of};
use super::rolling_calibrated::{roll_part_into, rolling_on_road};
use super::{RoadSummary, RunOptions, Scenario, ScenarioError, Spectra};

/// A rolling run finished from its signals: what the end-of-run outputs
/// (spectra, charts, `road.npz`) and the summary need.
#[derive(Debug)]
pub struct StreamedRun {
    /// The road rolled on.
    pub road: RoadSummary,
    /// The road's summits, listed on demand (a synthetic road replays
    /// them rather than holding them; `road.npz` is written from this by
    /// [`write_road_npz_from`](super::output::summits::write_road_npz_from)).
    pub summits: Box<dyn SummitSource>,
    /// The configuration the spec described.
    pub config: rolling::RollingConfig,
    /// The steps' signals and counters.
    pub signals: StepSignals,
    /// Steps loaded from checkpoints instead of computed.
    pub resumed: usize,
    /// The spectra of the signals.
    pub spectra: Spectra,
}

impl Scenario {
    /// Rolls the path's steps `steps` as [`Scenario::roll_part`] does, but
    /// hands the records to `sink` in path order as they are made: piece by
    /// piece (1 m of path) on a synthetic road, so neither this process nor
    /// `sink` need hold the whole part; at once on other roads.
    ///
    /// # Errors
    /// As [`Scenario::roll_part`], and the first error of `sink` (which
    /// stops the rolling).
    pub fn roll_part_into(
        &self,
        options: &RunOptions<'_>,
        steps: std::ops::Range<usize>,
        warmup: usize,
        sink: &mut dyn FnMut(rolling::RollingResult) -> Result<(), ScenarioError>,
    ) -> Result<(), ScenarioError> {
        let spec = self.rolling_section()?;
        if self.material.viscoelastic.is_some() {
            // As roll_part says it.
            return self.roll_part(options, steps, warmup).map(|_| ());
        }
        roll_part_into(self, spec, options, (steps, warmup), sink)
    }

    /// Whether this scenario's run can be streamed (its records written as
    /// they arrive, [`Scenario::finish_streamed`]): not when its sensors
    /// are recounted on the caps at the end (`[rolling] sensor_accounting =
    /// "caps"`), which needs the whole records. A distributed runner asks
    /// before anything is rolled.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] naming the key and the gathered run.
    pub fn check_streamed(&self) -> Result<(), ScenarioError> {
        if self.rolling.as_ref().is_some_and(|r| r.sensors_on_caps()) {
            return Err(ScenarioError::Invalid(
                "[rolling] sensor_accounting = \"caps\" recounts the whole records at the \
                 end: gather them (`mpi-run --gather`) or use \"run\""
                    .into(),
            ));
        }
        Ok(())
    }

    /// A tally of the contacts pressed past their caps for a streamed run
    /// ([`StepStream::count_past_caps`](super::output::steps_stream::StepStream::count_past_caps)),
    /// when its road is a texture map read whole and rolled elastic on the
    /// Wilke laws (the road whose records a whole run counts on the same
    /// tally); `None` otherwise: calibrated laws count
    /// their own tables, a `.npy` road read by windows never holds its
    /// laws whole, and a viscoelastic run is not streamed. The road is
    /// built for it, once.
    ///
    /// # Errors
    /// As the road's build in a run.
    pub fn past_cap_tally(
        &self,
        options: &RunOptions<'_>,
    ) -> Result<Option<crate::texture_road::PastCapTally>, ScenarioError> {
        let Some(texture) = &self.texture else {
            return Ok(None);
        };
        if self.rolling.is_none()
            || self.material.viscoelastic.is_some()
            || self.fidelity()? != crate::fidelity::Fidelity::Wilke
            || super::rolling_npy::npy_file(texture, options).is_some()
        {
            return Ok(None);
        }
        let road = self.texture_rolling_road(&options.base_dir)?;
        Ok(Some(crate::texture_road::PastCapTally::new(
            &road,
            1.0,
            crate::texture_road::PastShape::Caps,
        )))
    }

    /// The run made of the signals of records written elsewhere as they
    /// arrived (every step of the path, in order): the road summary and the
    /// spectra exactly as [`Scenario::finish_rolling`] gives them from the
    /// records themselves.
    ///
    /// # Errors
    /// No `[rolling]` section, signals that do not cover the path, or a
    /// spectrum that cannot be computed.
    pub fn finish_streamed(
        &self,
        options: &RunOptions<'_>,
        signals: StepSignals,
        resumed: usize,
    ) -> Result<StreamedRun, ScenarioError> {
        let spec = self.rolling_section()?;
        let config = self.rolling_config()?;
        self.check_streamed()?;
        if signals.len() != config.steps() {
            return Err(ScenarioError::Invalid(format!(
                "gathered records do not cover the path's {} steps in order ({} written)",
                config.steps(),
                signals.len()
            )));
        }
        let Rolled::Road(mut road, summits) = rolling_on_road(self, spec, options, What::Road)?
        else {
            return Err(ScenarioError::Invalid("no road summary".into()));
        };
        road.warnings_mut().extend(signals.past_caps.clone());
        let spectra = spectra_of(
            &config,
            spec,
            &Signals {
                sample_rate: config.sample_rate(),
                total_force: &signals.total_force,
                approach: &signals.approach,
                sensors: &signals.sensors,
            },
        )?;
        Ok(StreamedRun {
            road,
            summits,
            config,
            signals,
            resumed,
            spectra,
        })
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use std::path::Path;

    use super::super::output::OutputSet;
    use super::super::output::steps_stream::StepStream;
    use super::super::output::summits::collect_summits;
    use super::super::{Par, ScenarioResult};
    use super::*;

    /// The fixture's path rolled as parts into a stream and finished from
    /// the kept signals gives the whole run's road and spectra: equal
    /// (every bit) with one part, and the signals to 1e-9 relative with the
    /// path split in two (each part warm-started, docs/distributed.md).
    #[test]
    fn a_streamed_run_finishes_as_the_whole_run() {
        let fixtures = Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
        let scenario = Scenario::from_path(fixtures.join("rolling_small.toml")).unwrap();
        let options = RunOptions {
            par: Some(Par::Seq),
            ..RunOptions::new(&fixtures)
        };
        let ScenarioResult::Rolling(whole) = scenario.run(&options).unwrap() else {
            panic!("not a rolling run");
        };
        let total = scenario.rolling_steps().unwrap();
        // The path cut at these steps: whole, then in two.
        for cuts in [vec![0, total], vec![0, total / 2, total]] {
            let parts: Vec<std::ops::Range<usize>> = cuts.windows(2).map(|w| w[0]..w[1]).collect();
            let parent = tempfile::tempdir().unwrap();
            let mut set = OutputSet::new(parent.path().join("out")).unwrap();
            let mut stream = StepStream::new(&mut set, &["centre".to_string()]).unwrap();
            let mut resumed = 0;
            for part in &parts {
                scenario
                    .roll_part_into(&options, part.clone(), 2, &mut |rolled| {
                        resumed += rolled.resumed;
                        rolled.steps.iter().try_for_each(|s| stream.push(s))
                    })
                    .unwrap();
            }
            let signals = stream.finish(&mut set, whole.config.lateral).unwrap();
            let run = scenario
                .finish_streamed(&options, signals, resumed)
                .unwrap();
            assert_eq!(run.road, whole.road);
            let summits = collect_summits(run.summits.as_ref()).unwrap();
            assert_eq!(summits.positions, whole.road_positions);
            assert_eq!(summits.heights, whole.road_heights);
            let approach = whole.result.approach();
            if parts.len() == 1 {
                assert_eq!(run.spectra, whole.spectra);
                assert!(
                    run.signals
                        .approach
                        .iter()
                        .zip(&approach)
                        .all(|(a, b)| a.to_bits() == b.to_bits())
                );
            } else {
                for (a, b) in run.signals.approach.iter().zip(&approach) {
                    assert!((a - b).abs() <= 1e-9 * b.abs(), "{a} vs {b}");
                }
                for (a, b) in run.spectra.primary.iter().zip(&whole.spectra.primary) {
                    assert!((a.level_db - b.level_db).abs() < 1e-6, "{a:?} vs {b:?}");
                }
            }
            assert_eq!(run.signals.len(), total);
        }
        // Signals that miss a step are refused.
        let short = StepSignals::default();
        assert!(scenario.finish_streamed(&options, short, 0).is_err());
    }
}
