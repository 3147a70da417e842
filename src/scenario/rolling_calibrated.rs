//! Which laws a `[rolling]` run takes, and a run on calibrated laws: the
//! road's tables calibrated as a [`TablePlan`] says, and a whole run
//! repeated while it presses caps past tables that stop at their estimated
//! depth (`crate::fidelity::table_depth`, docs/validation.md "Calibrated
//! laws in rolling"). The other roads are `super::rolling`'s; this module
//! calls into it, never the reverse.

use std::time::Duration;

use tyreroad_rolling as rolling;

use super::rolling::{
    PieceSink, RoadSummary, Rolled, RollingRun, What, roll_part_on_windows, roll_road,
    roll_road_with, rolling_on_uncalibrated_road,
};
use super::rolling_caps::CapRecount;
use super::rolling_npy::npy_window_road;
use super::texture::{calibrated_texture_road_set_with, rolling_calibrator};
use super::{RollingSpec, RunOptions, Scenario, ScenarioError, TextureSpec};
use crate::fidelity::rolling::caps_past_tables;
use crate::fidelity::rolling_fields::{FieldRolling, FieldRollingStats};
use crate::fidelity::table_depth::TablePlan;
use crate::fidelity::{CalibratedLaw, Calibrator, Fidelity};

/// Runs `[rolling]` on the scenario's road.
pub(crate) fn run_rolling(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
) -> Result<RollingRun, ScenarioError> {
    match rolling_on_road(scenario, spec, options, What::Whole)? {
        Rolled::Run(run) => Ok(*run),
        _ => Err(ScenarioError::Invalid("a whole run gave a part".into())),
    }
}

/// Builds the scenario's road and does `what` on it: on a texture, with
/// the calibrated rungs, here; otherwise
/// [`rolling_on_uncalibrated_road`].
/// A whole run's sensors are then counted as `[rolling]
/// sensor_accounting` says ([`CapRecount`]: once, after any repeated
/// calibrated round; its inputs checked before the run).
pub(crate) fn rolling_on_road(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    what: What,
) -> Result<Rolled, ScenarioError> {
    let caps = match what {
        What::Whole | What::Gathered(_) => CapRecount::prepare(scenario, spec, options)?,
        What::Part { .. } | What::Road => None,
    };
    match (caps, rolling_on_any_road(scenario, spec, options, what)?) {
        (Some(caps), Rolled::Run(mut run)) => {
            caps.recount(spec, &mut run)?;
            Ok(Rolled::Run(run))
        }
        (_, rolled) => Ok(rolled),
    }
}

/// [`rolling_on_road`] before the sensors are recounted.
fn rolling_on_any_road(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    what: What,
) -> Result<Rolled, ScenarioError> {
    let Some(texture) = &scenario.texture else {
        return rolling_on_uncalibrated_road(scenario, spec, options, what);
    };
    // `[model] fidelity = "calibrated"`: the same road with each
    // selectable cap's BEM-calibrated law (crate::fidelity::rolling);
    // "calibrated_fields": the same laws with their fields, each step
    // coupled through them (crate::fidelity::rolling_fields).
    match scenario.fidelity()? {
        Fidelity::Calibrated => {
            let material = scenario.material()?;
            let rolled = roll_calibrated(scenario, spec, options, texture, false, what, {
                |road, summary, what| {
                    let rolled = roll_road(scenario, road, summary, material, spec, options, what)?;
                    Ok((rolled, ()))
                }
            })?;
            Ok(rolled.0)
        }
        Fidelity::CalibratedFields => {
            Ok(roll_with_fields(scenario, spec, options, texture, what)?.0)
        }
        _ => rolling_on_uncalibrated_road(scenario, spec, options, what),
    }
}

/// Rolls the steps `steps` (a rank's part, each piece started `warmup`
/// steps early) and hands the records to `sink` in path order: piece by
/// piece on a synthetic road (so the caller need not hold the part), the
/// whole part at once on other roads.
pub(crate) fn roll_part_into(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    (steps, warmup): (std::ops::Range<usize>, usize),
    sink: &mut PieceSink<'_>,
) -> Result<(), ScenarioError> {
    let material = scenario.material()?;
    let part = (steps.clone(), warmup);
    if let (None, true, Some(synth)) = (
        &scenario.texture,
        scenario.asperities.is_empty(),
        &spec.synthetic_road,
    ) {
        let windows = synth.road().windows(material)?;
        let summary = RoadSummary::Synthetic {
            count: windows.count(),
            warnings: Vec::new(),
        };
        let window = |range| Ok(windows.window(range)?);
        return roll_part_on_windows(
            scenario, material, spec, options, part, summary, window, sink,
        );
    }
    if let Some(road) = npy_window_road(scenario, options, material)? {
        let summary = RoadSummary::Asperities {
            count: road.len(),
            warnings: Vec::new(),
        };
        let window = |range| Ok(road.window(range)?);
        return roll_part_on_windows(
            scenario, material, spec, options, part, summary, window, sink,
        );
    }
    match rolling_on_road(scenario, spec, options, What::Part { steps, warmup })? {
        Rolled::Part(part) => sink(part),
        _ => Err(ScenarioError::Invalid("a part gave a whole run".into())),
    }
}

/// The scenario's texture road with each selectable cap's law from
/// `calibrator`, tabulated as `plan` says, and its summary.
fn calibrated_road(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    texture: &TextureSpec,
    calibrator: &Calibrator,
    plan: &TablePlan,
) -> Result<(rolling::Road<CalibratedLaw>, RoadSummary), ScenarioError> {
    let config = scenario.rolling_config()?;
    let par = options.rolling_par(spec);
    let (set, summary, radii) = calibrated_texture_road_set_with(
        texture,
        &options.base_dir,
        &config,
        par,
        calibrator,
        plan,
    )?;
    let road = crate::fidelity::rolling::calibrated_rolling_road(set, radii, summary.top)?;
    Ok((road, RoadSummary::Texture(Box::new(summary))))
}

/// Rounds a whole run on calibrated laws may take: the first on tables to
/// their estimated depth, the next ones with the caps the previous round
/// pressed past them tabulated to the bound.
const CALIBRATED_ROUNDS: usize = 3;

/// Calibrates the scenario's road and rolls it by `roll` (the road, its
/// summary, what to do), on tables to their estimated depth
/// (`crate::fidelity::table_depth`). A whole run is repeated, its caps
/// that went past their tables tabulated to the bound, until none does (at
/// most [`CALIBRATED_ROUNDS`] runs; what still passes its table is counted
/// and reported). Every rank of a distributed run calibrates the same
/// tables as the whole run's first round, but a part cannot repeat alone:
/// rank 0 counts the gathered run's contacts past their tables and reports
/// them, and the run then differs from the single process's, which
/// repeated itself.
fn roll_calibrated<T>(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    texture: &TextureSpec,
    fields: bool,
    what: What,
    roll: impl FnMut(
        &rolling::Road<CalibratedLaw>,
        RoadSummary,
        What,
    ) -> Result<(Rolled, T), ScenarioError>,
) -> Result<(Rolled, rolling::Road<CalibratedLaw>, T), ScenarioError> {
    let plan = TablePlan::new(scenario.model.calibrate_under()?);
    roll_calibrated_from(plan, scenario, spec, options, (texture, fields), what, roll)
}

/// [`roll_calibrated`] from the first round's `plan`, on `texture` with
/// its fields when `fields`.
fn roll_calibrated_from<T>(
    mut plan: TablePlan,
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    (texture, fields): (&TextureSpec, bool),
    what: What,
    mut roll: impl FnMut(
        &rolling::Road<CalibratedLaw>,
        RoadSummary,
        What,
    ) -> Result<(Rolled, T), ScenarioError>,
) -> Result<(Rolled, rolling::Road<CalibratedLaw>, T), ScenarioError> {
    let whole = matches!(what, What::Whole);
    let mut what = Some(what);
    let mut spent = Duration::ZERO;
    // Tables are kept beside the checkpoints: a resumed or repeated run on
    // the same road does not calibrate it again. One calibrator for every
    // round: a repeated run solves only the deepened caps' tables.
    let cache = options
        .checkpoint_dir
        .as_deref()
        .filter(|_| spec.checkpoint)
        .map(|dir| dir.join("calibration"));
    let calibrator = rolling_calibrator(scenario.material()?, cache.as_deref(), fields);
    for round in 1.. {
        let (road, mut summary) =
            calibrated_road(scenario, spec, options, texture, &calibrator, &plan)?;
        if let RoadSummary::Texture(t) = &mut summary
            && let Some(cal) = &mut t.calibration
        {
            cal.time += spent;
            spent = cal.time;
        }
        let (rolled, extra) = roll(&road, summary, what.take().unwrap_or(What::Whole))?;
        let past = match &rolled {
            Rolled::Run(run) if whole && !plan.is_bound() && round < CALIBRATED_ROUNDS => {
                caps_past_tables(&road, &run.result)
            }
            _ => Vec::new(),
        };
        if past.is_empty() {
            return Ok((count_past_tables(rolled, &road), road, extra));
        }
        plan = plan.deepened(&past);
    }
    unreachable!("the rounds end by a return")
}

/// The scenario's road with calibrated laws and their fields, rolled with
/// each step coupled through the fields; the road and the coupling's
/// counts come back beside the result (for recounts of its sensors).
pub(super) fn roll_with_fields(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    texture: &TextureSpec,
    what: What,
) -> Result<(Rolled, rolling::Road<CalibratedLaw>, FieldRollingStats), ScenarioError> {
    let material = scenario.material()?;
    roll_calibrated(
        scenario,
        spec,
        options,
        texture,
        true,
        what,
        |road, summary, what| {
            let coupling = FieldRolling::with_defaults(&material)?;
            let rolled = roll_road_with(
                scenario,
                (road, Some(&coupling)),
                summary,
                material,
                spec,
                options,
                what,
            )?;
            Ok((rolled, coupling.stats()))
        },
    )
}

/// A whole run on calibrated laws says how many of its contacts went past
/// their tables ([`crate::fidelity::rolling::contacts_past_tables`]).
fn count_past_tables(rolled: Rolled, road: &rolling::Road<CalibratedLaw>) -> Rolled {
    let Rolled::Run(mut run) = rolled else {
        return rolled;
    };
    let past = crate::fidelity::rolling::contacts_past_tables(road, &run.result);
    if let RoadSummary::Texture(t) = &mut run.road
        && let Some(cal) = &mut t.calibration
    {
        cal.past_tables = past;
    }
    Rolled::Run(run)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fidelity::rolling::PastTables;
    use crate::fidelity::under_tread::CalibrateUnder;
    use crate::scenario::texture::CalibrationSummary;

    /// A tyre over a small aggregate texture, calibrated laws.
    fn tyre_scenario() -> Scenario {
        Scenario::parse(
            "name = \"r\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [model]\nfidelity = \"calibrated\"\n\
             [rolling]\nstart = \"24 mm\"\nend = \"36 mm\"\nstep = \"1 mm\"\nspeed = \"10 m/s\"\n\
             checkpoint = false\nthreads = 1\n\
             [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.1 m\"\nradius_y = \"0.1 m\"\n\
             length = \"30 mm\"\nwidth = \"24 mm\"\n\
             [rolling.control]\nload = \"150 N\"\n\
             [texture]\nmin_prominence = \"0.2 mm\"\nmin_area = \"2 mm2\"\n\
             [texture.synth]\nkind = \"aggregate\"\nnx = 300\nny = 200\nspacing = \"0.2 mm\"\n\
             grading = \"4/6\"\nseed = 2006\n",
            "tyre",
        )
        .expect("a valid scenario")
    }

    fn roll_from(
        plan: TablePlan,
    ) -> Result<(RollingRun, rolling::Road<CalibratedLaw>), ScenarioError> {
        let scenario = tyre_scenario();
        let spec = scenario.rolling.as_ref().expect("[rolling]");
        let texture = scenario.texture.as_ref().expect("[texture]");
        let options = RunOptions::new(".");
        let material = scenario.material()?;
        let (rolled, road, ()) = roll_calibrated_from(
            plan,
            &scenario,
            spec,
            &options,
            (texture, false),
            What::Whole,
            |road, summary, what| {
                let rolled = roll_road(&scenario, road, summary, material, spec, &options, what)?;
                Ok((rolled, ()))
            },
        )?;
        match rolled {
            Rolled::Run(run) => Ok((*run, road)),
            _ => Err(ScenarioError::Invalid("not a run".into())),
        }
    }

    /// `run`'s approach is `bound`'s within 0.2 % at every step: the same
    /// BEM laws sampled at other knots.
    fn rolls_as(run: &RollingRun, bound: &RollingRun) {
        assert_eq!(run.result.steps.len(), bound.result.steps.len());
        for (a, b) in run.result.steps.iter().zip(&bound.result.steps) {
            let (x, y) = (a.approach, b.approach);
            assert!((x - y).abs() < 2e-3 * y, "step {}: {x} vs {y}", a.index);
        }
    }

    fn calibration(run: &RollingRun) -> CalibrationSummary {
        match &run.road {
            RoadSummary::Texture(t) => t.calibration.clone().expect("calibrated"),
            _ => panic!("not a texture road"),
        }
    }

    /// Under a tyre the estimated tables stop well short of the bound
    /// (never past it), no contact passes them, and the run agrees with
    /// the one on tables to the bound.
    #[test]
    fn estimated_tables_stop_short_of_the_bound_and_roll_as_it_does() -> Result<(), ScenarioError> {
        let (run, road) = roll_from(TablePlan::new(CalibrateUnder::Flat))?;
        let (bound, bound_road) = roll_from(TablePlan::bound(CalibrateUnder::Flat))?;
        let cal = calibration(&run);
        assert!(cal.bulk_sag > 0.0, "{cal:?}");
        assert_eq!(cal.deepened, 0, "{cal:?}");
        assert_eq!(cal.past_tables, PastTables::default());
        let depths = |road: &rolling::Road<CalibratedLaw>| -> Vec<f64> {
            (0..road.len())
                .map(|i| road.law_at(i, 0.0).table().max_depth())
                .collect()
        };
        let (estimated, full) = (depths(&road), depths(&bound_road));
        assert_eq!(estimated.len(), full.len());
        let mut ratios: Vec<f64> = estimated.iter().zip(&full).map(|(e, f)| e / f).collect();
        assert!(ratios.iter().all(|&r| r <= 1.0 + 1e-12), "{ratios:?}");
        ratios.sort_by(f64::total_cmp);
        let median = ratios[ratios.len() / 2];
        // Measured: 0.63 (0.33 to 0.94).
        assert!(median < 0.8, "{ratios:?}");
        rolls_as(&run, &bound);
        Ok(())
    }

    /// Tables far too shallow (fifty times the bulk sag taken off): the
    /// first round presses caps past them, the next rounds tabulate those
    /// to the bound (solving no other table again), and the last run lies
    /// inside its tables and rolls as the run on tables to the bound does.
    #[test]
    fn a_run_past_its_estimated_tables_is_repeated_on_deeper_ones() -> Result<(), ScenarioError> {
        let shallow = TablePlan {
            sag: 50.0,
            ..TablePlan::new(CalibrateUnder::Flat)
        };
        let (run, road) = roll_from(shallow)?;
        let cal = calibration(&run);
        assert!(cal.deepened > 0, "{cal:?}");
        // One calibrator for every round: the later rounds solved only the
        // deepened caps' tables (each cap a table of its own here).
        assert!(
            cal.tables > cal.asperities && cal.tables <= cal.asperities + cal.deepened,
            "{cal:?}"
        );
        assert_eq!(cal.past_tables, PastTables::default(), "{cal:?}");
        assert!(caps_past_tables(&road, &run.result).is_empty());
        let (bound, _) = roll_from(TablePlan::bound(CalibrateUnder::Flat))?;
        assert_eq!(calibration(&bound).deepened, 0);
        assert_eq!(calibration(&bound).bulk_sag, 0.0);
        rolls_as(&run, &bound);
        Ok(())
    }
}
