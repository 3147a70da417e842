//! Rolling runs on the command line: a progress bar while the library runs
//! `[rolling]` (`tyreroad::scenario`), then the time signals, one-third-octave
//! spectra, per-sensor signals and charts written (docs/rolling.md).

use std::ops::ControlFlow;
use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use tyreroad::rolling;
use tyreroad::scenario::output::steps_stream::{StepSignals, StepStream};
use tyreroad::scenario::output::summits::{SummitRefs, SummitSource, write_road_npz_from};
use tyreroad::scenario::output::{OutputSet, csv_bytes, fmt};
use tyreroad::scenario::{
    RoadSummary, RollingRun, RunOptions, Scenario, ScenarioResult, Spectra, StreamedRun,
};

use crate::charts::{CHART_COLUMNS, CHART_POINTS, Series, line_chart, min_max_columns};
use crate::summary::Fallbacks;

/// Runs a `[rolling]` scenario with a progress bar; with `checkpoint = true`
/// a killed run resumes from `out/checkpoint/`. Writes into `out`:
/// `time_signals.csv`, `third_octave.csv` (`band_centre_hz,level_db`),
/// `third_octave_bands.csv` (exact centres and sensor levels; a band without
/// power, as at a sensor that never sees force, has an empty level, never
/// `-inf`), `sensors.csv`
/// (when sensors are defined), `road.npz` (the road's asperities: `ids`,
/// `positions` `(n, 2)`, `heights`), `steps.npz` (per step `time` and
/// `position`, the path's `lateral`, and the contact forces as COO triplets
/// `step`, `asperity`, `force`, and each step's `status`) and SVG/PNG
/// charts. Returns the steps that did not converge cleanly (stagnated or
/// failed), for the summary and `--strict`.
pub fn run_rolling(scenario: &Scenario, base_dir: &Path, out: &Path) -> Result<Fallbacks> {
    let bar = indicatif::ProgressBar::new(0);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} rolling [{elapsed_precise}] {wide_bar} {pos}/{len} steps (eta {eta})",
        )
        .context("progress bar template")?,
    );
    let progress = |p: rolling::Progress| {
        bar.set_length(p.total as u64);
        bar.set_position(p.done as u64);
        ControlFlow::Continue(())
    };
    let options = RunOptions {
        base_dir: base_dir.to_path_buf(),
        par: None,
        progress: Some(&progress),
        checkpoint_dir: Some(out.join("checkpoint")),
    };
    // A rung the user did not choose is named before the calibration's
    // seconds (an elastic rolling texture's default is no longer Wilke's).
    let fidelity = scenario.fidelity()?;
    if scenario.model.fidelity.is_none() && fidelity != tyreroad::fidelity::Fidelity::Wilke {
        say!(
            "model fidelity: {} (the default for this run; [model] fidelity = \"wilke\" for the paper's law)",
            fidelity.name()
        );
    }
    let config = scenario.rolling_config()?;
    if let Some(note) = end_off_the_step_grid(&config) {
        say!("note: {note}");
    }
    // Said before the steps: pressed this deep, a step can take minutes.
    if let Some(warning) = tyreroad::scenario::approach_past_window_warning(&config) {
        say!("warning: {warning}");
    }
    let result = scenario.run(&options);
    bar.finish();
    let ScenarioResult::Rolling(run) = result? else {
        anyhow::bail!("scenario {}: no [rolling] section", scenario.name);
    };
    report_rolling(&run, out)
}

/// A note when the path's `end` is not on the step grid from `start`
/// (beyond the rolling crate's `10⁻⁹ Δx`): the steps stop at the last
/// grid point before it, short of the end the scenario names.
fn end_off_the_step_grid(config: &rolling::RollingConfig) -> Option<String> {
    let n = config.steps();
    let last = config.position(n - 1);
    (config.end - last > 1e-6 * config.step).then(|| {
        format!(
            "[rolling] end = {:.6} m is not on the step grid from start = {:.6} m in steps of \
             {:.6} m: the last of the {n} steps is at x = {last:.6} m, {:.3} mm short of it",
            config.end,
            config.start,
            config.step,
            (config.end - last) * 1e3
        )
    })
}

/// Prints what a rolling run needs to be read right, and writes its files.
/// Returns the steps not `converged` (stagnated or failed).
pub fn report_rolling(run: &RollingRun, out: &Path) -> Result<Fallbacks> {
    let mut set = OutputSet::replacing(out, "rolling")?;
    let signals = stream_records(run, &mut set)?;
    let summits = SummitRefs {
        positions: &run.road_positions,
        heights: &run.road_heights,
    };
    report_ended(&Ended::of_run(run, &signals, &summits), set, out)
}

/// [`report_rolling`] for a run whose records were streamed into `set`
/// as they arrived (`mpi-run`'s rank 0): prints, writes the end-of-run
/// files into `set` and commits it.
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
pub fn report_streamed(run: &StreamedRun, set: OutputSet, out: &Path) -> Result<Fallbacks> {
    report_ended(&Ended::of_streamed(run), set, out)
}

/// What the end-of-run outputs and the summary read of a run, whole or
/// streamed.
struct Ended<'a> {
    road: &'a RoadSummary,
    summits: &'a dyn SummitSource,
    config: &'a rolling::RollingConfig,
    signals: &'a StepSignals,
    resumed: usize,
    sample_rate: f64,
    spectra: &'a Spectra,
}

impl<'a> Ended<'a> {
    fn of_run(run: &'a RollingRun, signals: &'a StepSignals, summits: &'a SummitRefs<'a>) -> Self {
        Self {
            road: &run.road,
            summits,
            config: &run.config,
            signals,
            resumed: run.result.resumed,
            sample_rate: run.result.sample_rate,
            spectra: &run.spectra,
        }
    }

    fn of_streamed(run: &'a StreamedRun) -> Self {
        Self {
            road: &run.road,
            summits: run.summits.as_ref(),
            config: &run.config,
            signals: &run.signals,
            resumed: run.resumed,
            sample_rate: run.config.sample_rate(),
            spectra: &run.spectra,
        }
    }
}

/// Writes the per-step files of a whole run through the same
/// [`StepStream`] as a streamed run, so both give the same bytes.
fn stream_records(run: &RollingRun, set: &mut OutputSet) -> Result<StepSignals> {
    let names: Vec<String> = run.config.sensors.iter().map(|s| s.name.clone()).collect();
    let mut stream = StepStream::new(set, &names)?;
    stream.reserve(run.result.steps.len());
    for s in &run.result.steps {
        stream.push(s)?;
    }
    Ok(stream.finish(set, run.config.lateral)?)
}

fn report_ended(run: &Ended<'_>, mut set: OutputSet, out: &Path) -> Result<Fallbacks> {
    match run.road {
        RoadSummary::Texture(t) => {
            say!(
                "texture road {:.1} mm × {:.1} mm at {}: Sq {:.3} mm, {} asperities ({} segmented)",
                t.extent.0 * 1e3,
                t.extent.1 * 1e3,
                spacing_text(t.spacing),
                t.rms * 1e3,
                t.asperities,
                t.segmented
            );
        }
        RoadSummary::Synthetic { count, .. } => {
            say!("synthetic road: {count} spherical summits");
        }
        RoadSummary::Asperities { .. } => {}
    }
    // Warned of here and listed again in the summary: `--strict` fails on
    // them as on a failed step.
    let mut warnings = run.road.warnings().to_vec();
    for warning in &warnings {
        say!("warning: {warning}");
    }
    if let RoadSummary::Texture(t) = &run.road
        && let Some(cal) = &t.calibration
    {
        say!(
            "calibrated laws: {} asperities the path can select, {} tables solved, {} read from disk, {:.1} s",
            cal.asperities,
            cal.tables,
            cal.from_disk,
            cal.time.as_secs_f64()
        );
        if let Some(note) = cal.depth_note() {
            say!("{note}");
        }
        if let Some(warning) = cal.past_tables.warning() {
            say!("warning: {warning}");
        }
    }
    let signals = run.signals;
    let total = signals.len();
    if run.resumed > 0 {
        say!(
            "resumed {} of {total} steps from {}",
            run.resumed,
            out.join("checkpoint").display()
        );
    }
    if let Some(warning) = tyreroad::scenario::clearance_warning(signals.min_clearance) {
        say!("warning: {warning}");
        warnings.push(warning);
    }
    let (overlapping_steps, most) = (signals.overlapping_steps, signals.most_overlapping);
    // The field rung couples overlapping patches through their calibrated
    // fields: the note is the point coupling's.
    let field_coupled = matches!(
        run.road,
        RoadSummary::Texture(t) if t.calibration.as_ref().is_some_and(|c| c.fields)
    );
    if overlapping_steps > 0 && !field_coupled {
        say!(
            "note: at {overlapping_steps} of {total} steps some contact patches overlap (up to \
             {most} pairs, column n_overlapping): the point-force coupling does not hold there"
        );
    }
    let [converged, stagnated, failed] = signals.status_counts();
    say!("steps: {converged} converged, {stagnated} stagnated, {failed} failed");
    let spectra = run.spectra;
    if failed > 0 {
        say!(
            "warning: {failed} of {total} steps failed (NaN in time_signals.csv, status \
             column; no contacts in steps.npz): the spectra bridge {} failed samples by \
             linear interpolation",
            spectra.interpolated_samples
        );
    }
    if spectra.has_unresolved_bands() {
        let fs = run.sample_rate;
        say!(
            "note: with {}-sample Welch segments (Δf = {:.1} Hz) the bands below \
             {:.0} Hz are not resolved: roll a longer path for them",
            spectra.segment,
            fs / spectra.segment as f64,
            spectra.resolved_from
        );
    }
    write_end(run, &mut set)?;
    if let Some(note) = set.landing_note() {
        say!("note: {note}");
    }
    set.commit()?;
    say!(
        "rolling: {} steps, fs = {:.1} Hz, written to {}",
        total,
        run.sample_rate,
        out.display()
    );
    let mut fallbacks = Fallbacks::from_rolling(&signals.not_converged);
    if let RoadSummary::Texture(t) = &run.road
        && let Some(cal) = &t.calibration
    {
        fallbacks.add_calibration(cal);
    }
    fallbacks.add_warnings(warnings);
    Ok(fallbacks)
}

#[derive(Serialize)]
struct BandRow {
    #[serde(rename = "band_centre_hz", serialize_with = "fmt::plain")]
    nominal: f64,
    #[serde(serialize_with = "fmt::level_db")]
    level_db: f64,
}

/// `band_centre_hz,exact_centre_hz,<sensor>_db...` (header written apart:
/// the sensor columns are named after the sensors).
#[derive(Serialize)]
struct BandDetailRow {
    #[serde(serialize_with = "fmt::plain")]
    nominal: f64,
    #[serde(serialize_with = "fmt::fixed3")]
    centre: f64,
    #[serde(serialize_with = "fmt::level_db_all")]
    sensors: Vec<f64>,
}

/// Writes every file of a whole run into `set` (not committed).
pub(crate) fn write_outputs(run: &RollingRun, set: &mut OutputSet) -> Result<()> {
    let signals = stream_records(run, set)?;
    let summits = SummitRefs {
        positions: &run.road_positions,
        heights: &run.road_heights,
    };
    write_end(&Ended::of_run(run, &signals, &summits), set)
}

/// The files written once every step is in: `road.npz`, the spectra
/// tables and the charts (the per-step files are [`StepStream`]'s).
fn write_end(run: &Ended<'_>, set: &mut OutputSet) -> Result<()> {
    let (config, signals, spectra) = (run.config, run.signals, run.spectra);
    write_road_npz_from(set, run.summits)?;

    // third_octave.csv keeps exactly the two columns noise models read; the
    // exact centres and the sensors' levels go beside it.
    let levels = &spectra.primary;
    let bands: Vec<BandRow> = levels
        .iter()
        .map(|l| BandRow {
            nominal: l.band.nominal,
            level_db: l.level_db,
        })
        .collect();
    let details: Vec<BandDetailRow> = levels
        .iter()
        .enumerate()
        .map(|(b, l)| BandDetailRow {
            nominal: l.band.nominal,
            centre: l.band.centre,
            sensors: spectra.sensors.iter().map(|s| s[b].level_db).collect(),
        })
        .collect();
    let mut header = vec!["band_centre_hz".to_string(), "exact_centre_hz".to_string()];
    header.extend(config.sensors.iter().map(|s| format!("{}_db", s.name)));
    if bands.is_empty() {
        set.write("third_octave.csv", b"band_centre_hz,level_db\n")?;
    } else {
        set.write_csv("third_octave.csv", &bands)?;
    }
    set.write(
        "third_octave_bands.csv",
        &csv_bytes(Some(&header), &details)?,
    )?;

    // Charts (x in ms for signals, band number k for spectra).
    let load_control = spectra.load_control;
    let reference = spectra.reference_force;
    let sensor_levels = &spectra.sensors;
    // A long run's signals are drawn as the smallest and largest value of
    // each of CHART_COLUMNS time columns (peaks stay visible, the files
    // stay small); up to CHART_POINTS steps every point is drawn, as ever.
    let steps = signals.len();
    let span = match (signals.time.first(), signals.time.last()) {
        (Some(&t0), Some(&t1)) => [t0 * 1e3, t1 * 1e3],
        _ => [0.0, 0.0],
    };
    let ms = |v: &mut dyn Iterator<Item = f64>| -> Vec<(f64, f64)> {
        let points = signals
            .time
            .iter()
            .zip(v)
            // A failed step's NaN is a gap in the chart, not a point.
            .filter(|(_, y)| y.is_finite())
            .map(|(t, y)| (t * 1e3, y));
        if steps <= CHART_POINTS {
            points.collect()
        } else {
            min_max_columns(points, CHART_COLUMNS, span)
        }
    };
    let (name, unit, main) = if load_control {
        (
            "approach",
            "approach (mm)",
            ms(&mut signals.approach.iter().map(|d| d * 1e3)),
        )
    } else {
        (
            "total force",
            "total force (N)",
            ms(&mut signals.total_force.iter().copied()),
        )
    };
    time_chart(
        set,
        "time_signals",
        &format!("{name} against time"),
        "time (ms)",
        unit,
        &[Series {
            label: name.into(),
            points: main,
        }],
    )?;
    time_chart(
        set,
        "contact_area",
        "contact area against time",
        "time (ms)",
        "contact area (mm²)",
        &[Series {
            label: "Σ π a²".into(),
            points: ms(&mut signals.contact_area.iter().map(|a| a * 1e6)),
        }],
    )?;
    if !config.sensors.is_empty() {
        let series: Vec<Series> = config
            .sensors
            .iter()
            .enumerate()
            .map(|(k, s)| Series {
                label: s.name.clone(),
                points: ms(&mut signals.sensors[k].iter().copied()),
            })
            .collect();
        time_chart(
            set,
            "sensors",
            "sensor forces",
            "time (ms)",
            "force (N)",
            &series,
        )?;
    }
    let band_points = |l: &[rolling::BandLevel]| -> Vec<(f64, f64)> {
        l.iter()
            .filter(|b| b.level_db.is_finite())
            .map(|b| (f64::from(b.band.index), b.level_db))
            .collect()
    };
    let mut series = vec![Series {
        label: if load_control {
            "approach (dB re 1 µm)".into()
        } else {
            format!("total force (dB re {reference} N)")
        },
        points: band_points(levels),
    }];
    for (s, l) in config.sensors.iter().zip(sensor_levels) {
        series.push(Series {
            label: format!("{} (dB re {reference} N)", s.name),
            points: band_points(l),
        });
    }
    // No band at all is the sample rate's doing, not the forces': at 1 mm/s
    // and 1 mm steps (fs = 1 Hz) no one-third-octave band fits, and the
    // notes below said "nothing touched" of a run carrying its load.
    if levels.is_empty() {
        say!(
            "note: no one-third-octave band fits this run's sample rate, fs = {:.3} Hz (speed \
             / step): the band tables are empty and third_octave.svg/png is not drawn; roll \
             faster or with shorter steps for spectra",
            config.sample_rate()
        );
        return Ok(());
    }
    // A band without power has no level (−∞ dB): its curve is left out, and
    // said so, rather than the whole chart failing for want of data.
    for s in series.iter().filter(|s| s.points.is_empty()) {
        say!(
            "note: {} has no power in any band (no force at all): its levels are empty in the \
             CSV files and it has no curve in third_octave.svg",
            s.label
        );
    }
    series.retain(|s| !s.points.is_empty());
    if series.is_empty() {
        say!("note: third_octave.svg/png not drawn: no band has power (nothing touched)");
        return Ok(());
    }
    line_chart(
        set,
        "third_octave",
        "one-third-octave spectra",
        "band k (centre 1000·10^(k/10) Hz; 0 = 1 kHz)",
        "level (dB)",
        &series,
    )?;
    Ok(())
}

/// A chart against time, or a note instead when no step has a finite
/// value to draw (every step failed): the run's files are written all the
/// same, and the failed steps are in them as NaN.
fn time_chart(
    set: &mut OutputSet,
    name: &str,
    title: &str,
    x_label: &str,
    y_label: &str,
    series: &[Series],
) -> Result<()> {
    if series.iter().all(|s| s.points.is_empty()) {
        say!("note: {name}.svg/png not drawn: no step has a finite value to draw");
        return Ok(());
    }
    line_chart(set, name, title, x_label, y_label, series)
}

/// A grid's spacing for a report: one figure when square, both when not.
fn spacing_text((dx, dy): (f64, f64)) -> String {
    if dx == dy {
        format!("{:.3} mm", dx * 1e3)
    } else {
        format!("{:.3} × {:.3} mm", dx * 1e3, dy * 1e3)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Regression (adversarial run, 2026-11-30): an `end` off the step
    /// grid ended the path a step short without a word.
    #[test]
    fn an_end_off_the_step_grid_is_noted_with_the_last_step() {
        let tread = rolling::Tread::Block {
            length: 0.05,
            width: 0.04,
        };
        let control = rolling::RollingControl::Load(50.0);
        let config = |end| rolling::RollingConfig::new(tread, [0.03, end, 1e-3], 10.0, control);
        let note = end_off_the_step_grid(&config(0.0605)).expect("off the grid");
        assert!(
            note.contains("the last of the 31 steps is at x = 0.060000 m, 0.500 mm short"),
            "{note}"
        );
        assert_eq!(end_off_the_step_grid(&config(0.06)), None);
        // A grid point reached to rounding is on the grid.
        assert_eq!(end_off_the_step_grid(&config(0.03 + 30.0 * 1e-3)), None);
    }

    #[test]
    fn small_run_writes_outputs() -> Result<()> {
        let text = r#"
            name = "small"
            [material]
            youngs_modulus = "6.54 MPa"
            poisson_ratio = 0.5
            [rolling]
            start = "30 mm"
            end = "60 mm"
            step = "1 mm"
            speed = "50 km/h"
            threads = 1
            checkpoint = true
            [rolling.tread]
            kind = "tyre"
            radius_x = "0.3 m"
            radius_y = "0.5 m"
            length = "50 mm"
            width = "40 mm"
            [rolling.control]
            load = "50 N"
            [[rolling.sensor]]
            name = "centre"
            x0 = "40 mm"
            x1 = "50 mm"
            y0 = "-10 mm"
            y1 = "10 mm"
            [rolling.synthetic_road]
            length = "0.1 m"
            width = "0.05 m"
            density = 40000
        "#;
        let scenario = Scenario::parse(text, "small")?;
        let out = std::env::temp_dir().join(format!("tyreroad-rolling-cmd-{}", std::process::id()));
        // Every step converges; the one summary item is the window's
        // warning (50 N presses this sparse road 0.7 mm past the tread's
        // profile at the footprint's edge).
        let summary = run_rolling(&scenario, Path::new("."), &out)?;
        assert_eq!(summary.len(), 1, "{:?}", summary.lines());
        assert!(summary.lines()[1].contains("warning: at some steps the approach exceeds"));
        let ts = std::fs::read_to_string(out.join("time_signals.csv"))?;
        assert!(
            ts.starts_with("time_s,position_m,total_force_n,approach_m,contact_area_m2,n_contacts")
        );
        assert_eq!(ts.lines().count(), 32);
        let header = ts.lines().next().unwrap_or_default();
        assert!(
            header.ends_with(",clearance_m,n_overlapping,status,recovery,residual"),
            "{header}"
        );
        assert!(
            ts.lines()
                .skip(1)
                .all(|l| l.split(',').nth(10) == Some("converged"))
        );
        let to = std::fs::read_to_string(out.join("third_octave.csv"))?;
        assert!(to.starts_with("band_centre_hz,level_db\n"));
        let bands = std::fs::read_to_string(out.join("third_octave_bands.csv"))?;
        assert!(bands.starts_with("band_centre_hz,exact_centre_hz,centre_db\n"));
        for f in [
            "road.npz",
            "steps.npz",
            "sensors.csv",
            "time_signals.svg",
            "contact_area.svg",
            "sensors.svg",
            "third_octave.svg",
            "time_signals.png",
            "contact_area.png",
            "sensors.png",
            "third_octave.png",
        ] {
            assert!(out.join(f).exists(), "{f}");
        }
        // A real PNG (signature), decodable, of the chart's size.
        let png = image::open(out.join("third_octave.png"))?;
        assert_eq!((png.width(), png.height()), (900, 520));
        // Second run: everything from the checkpoint.
        run_rolling(&scenario, Path::new("."), &out)?;
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }
    /// A run whose every step failed has no finite value to draw: its
    /// time charts are left out with a note, so the run still writes its
    /// files (they once ended with the chart's "no data" and nothing).
    #[test]
    fn a_time_chart_without_a_finite_point_is_a_note_not_an_error() -> Result<()> {
        let out = std::env::temp_dir().join(format!("tyreroad-nan-chart-{}", std::process::id()));
        let mut set = OutputSet::new(&out)?;
        let empty = [Series {
            label: "approach".into(),
            points: Vec::new(),
        }];
        time_chart(&mut set, "time_signals", "t", "x", "y", &empty)?;
        set.commit()?;
        assert!(!out.join("time_signals.svg").exists());
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }

    #[test]
    fn a_run_where_nothing_touches_writes_its_outputs_and_says_so() -> Result<()> {
        // The tread held 10 mm above the summits: no step has a contact, so
        // no band has power; the run must end with its files, not with a
        // chart's "no data".
        let text = r#"
            name = "nothing_touches"
            [material]
            youngs_modulus = "6.54 MPa"
            poisson_ratio = 0.5
            [rolling]
            start = "30 mm"
            end = "60 mm"
            step = "1 mm"
            speed = "50 km/h"
            threads = 1
            [rolling.tread]
            kind = "tyre"
            radius_x = "0.3 m"
            radius_y = "0.5 m"
            length = "50 mm"
            width = "40 mm"
            [rolling.control]
            approach = "-10 mm"
            [rolling.synthetic_road]
            length = "0.1 m"
            width = "0.05 m"
            density = 40000
        "#;
        let scenario = Scenario::parse(text, "nothing_touches")?;
        let out = std::env::temp_dir().join(format!("tyreroad-untouched-{}", std::process::id()));
        assert_eq!(run_rolling(&scenario, Path::new("."), &out)?.len(), 0);
        let ts = std::fs::read_to_string(out.join("time_signals.csv"))?;
        assert_eq!(ts.lines().count(), 32);
        assert!(ts.lines().skip(1).all(|l| l.split(',').nth(5) == Some("0")));
        assert!(out.join("third_octave.csv").exists());
        assert!(!out.join("third_octave.svg").exists());
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }

    #[test]
    fn a_sensor_that_never_sees_force_has_empty_levels_not_minus_infinity() -> Result<()> {
        let text = r#"
            name = "far_sensor"
            [material]
            youngs_modulus = "6.54 MPa"
            poisson_ratio = 0.5
            [rolling]
            start = "30 mm"
            end = "45 mm"
            step = "1 mm"
            speed = "50 km/h"
            threads = 1
            checkpoint = false
            [rolling.tread]
            kind = "tyre"
            radius_x = "0.3 m"
            radius_y = "0.5 m"
            length = "50 mm"
            width = "40 mm"
            [rolling.control]
            load = "50 N"
            [[rolling.sensor]]
            name = "centre"
            x0 = "0 mm"
            x1 = "100 mm"
            y0 = "-10 mm"
            y1 = "10 mm"
            [[rolling.sensor]]
            name = "far"
            x0 = "0 mm"
            x1 = "100 mm"
            y0 = "24 mm"
            y1 = "25 mm"
            [rolling.synthetic_road]
            length = "0.1 m"
            width = "0.05 m"
            density = 40000
        "#;
        let scenario = Scenario::parse(text, "far_sensor")?;
        let out = std::env::temp_dir().join(format!("tyreroad-far-sensor-{}", std::process::id()));
        run_rolling(&scenario, Path::new("."), &out)?;
        let sensors = std::fs::read_to_string(out.join("sensors.csv"))?;
        // The far sensor's force is zero at every step (the footprint reaches
        // y = ±20 mm), so its band powers are zero.
        assert!(
            sensors.lines().skip(1).all(|l| l
                .split(',')
                .nth(3)
                .and_then(|v| v.parse::<f64>().ok())
                == Some(0.0)),
            "{sensors}"
        );
        let bands = std::fs::read_to_string(out.join("third_octave_bands.csv"))?;
        assert!(!bands.to_ascii_lowercase().contains("inf"), "{bands}");
        let rows: Vec<&str> = bands.lines().skip(1).collect();
        assert!(!rows.is_empty());
        for row in rows {
            let cells: Vec<&str> = row.split(',').collect();
            assert_eq!(cells.len(), 4, "{row}");
            assert!(cells[2].parse::<f64>().is_ok_and(f64::is_finite), "{row}");
            assert_eq!(cells[3], "", "{row}");
        }
        assert!(out.join("third_octave.svg").exists());
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }
}
