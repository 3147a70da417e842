//! `cargo xtask rolling-bem SCENARIO --out DIR [--steps N]`: a rolling
//! scenario on a texture run over the same stretch by the multipoint model
//! and by the full-BEM reference (`tyreroad::bem_rolling`); prints the
//! comparison table and writes the signals, the band levels and the charts.
//! With `--viscoelastic` it runs the viscoelastic rolling BEM instead
//! (`rolling_visco_bem_cmd`); a scenario with `[material.viscoelastic]` is
//! rolled viscoelastically by both models and compared
//! (`rolling_visco_bem_cmd::run_comparison`), unless `--elastic`.

use std::path::Path;

use anyhow::{Context, Result};
use serde::Serialize;
use tyreroad::bem_rolling::{
    BemRollingOptions, BemRollingRun, SignalComparison, Stretch, compare_references,
    run_scenario_comparison_against, scenario_bem_reference,
};
use tyreroad::fidelity::Fidelity;
use tyreroad::scenario::output::{OutputSet, fmt};
use tyreroad::scenario::{Par, Scenario};

use crate::charts::{Series, line_chart};
use crate::rolling_bem_args::{
    RollingBemArgs, compared_step_rows, print_report_header, print_report_row,
};
use crate::rolling_bem_saved::SavedAs;

/// Runs both models, prints the table, writes the files.
pub fn run(args: &RollingBemArgs) -> Result<()> {
    if let Some(tread) = &args.viscoelastic {
        return crate::rolling_visco_bem_cmd::run(args, tread);
    }
    if let Some(factor) = args.refine {
        return crate::rolling_bem_refine::run(args, factor);
    }
    let mut scenario = Scenario::from_path(&args.scenario)?;
    // Before the viscoelastic branch: its multipoint run takes the rung too.
    if let Some(name) = &args.fidelity {
        let rolls = matches!(
            name.parse::<Fidelity>(),
            Ok(Fidelity::Wilke | Fidelity::Calibrated | Fidelity::CalibratedFields)
        );
        if !rolls {
            anyhow::bail!(
                "--fidelity {name:?}: rolling takes \"wilke\", \"calibrated\" or \"calibrated_fields\""
            );
        }
        scenario.model.fidelity = Some(name.clone());
    }
    if let Some(name) = &args.calibrate_under {
        scenario.model.calibrate_under = Some(name.clone());
    }
    if args.fidelity.is_some() || args.calibrate_under.is_some() {
        // The options checked together with the scenario as its own
        // `[model]` keys would be, before any solve (`--calibrate-under
        // tread` with `--fidelity wilke` is refused, not ignored).
        scenario
            .check_model()
            .context("--fidelity / --calibrate-under with this scenario")?;
    }
    if args.elastic {
        // The elastic runs of a viscoelastic comparison keep its rung (a
        // viscoelastic tread's default, not an elastic one's).
        if scenario.model.fidelity.is_none() {
            scenario.model.fidelity = Some(scenario.fidelity()?.name().to_string());
        }
        scenario.material.viscoelastic = None;
    } else if scenario.material.viscoelastic.is_some() {
        if let Some(dir) = &args.bem_from {
            // The viscoelastic BEM's signals are not saved in a form this
            // reads back: solving it again silently would hide the flag.
            anyhow::bail!(
                "--bem-from {}: reading the BEM back is for elastic comparisons; \
                 this scenario has [material.viscoelastic] (add --elastic, or drop --bem-from)",
                dir.display()
            );
        }
        return crate::rolling_visco_bem_cmd::run_comparison(args, scenario);
    }
    if let (Some(speed), Some(spec)) = (args.speed, scenario.rolling.as_mut()) {
        spec.speed = tyreroad::scenario::units::Speed::si(speed);
    }
    say!(
        "model fidelity: {}{}",
        scenario.fidelity()?,
        if args.bem_from.is_some() {
            "; BEM signals read back"
        } else {
            ""
        }
    );
    let base = args.scenario.parent().unwrap_or(Path::new("."));
    let options = BemRollingOptions {
        tolerance: args.tolerance,
        ..BemRollingOptions::default()
    };
    // Saved signals are checked against this scenario before anything is
    // solved: a BEM run of another road, load or tread is refused.
    let (saved, check) = if args.bem_from.is_some() || args.bem_check.is_some() {
        let reference = scenario_bem_reference(&scenario, base, &options)?;
        let read = |dir: Option<&Path>, saved_as| {
            dir.map(|dir| crate::rolling_bem_saved::read(dir, &scenario, (&reference, saved_as)))
                .transpose()
        };
        (
            read(args.bem_from.as_deref(), SavedAs::SameRun)?,
            read(args.bem_check.as_deref(), SavedAs::Check)?,
        )
    } else {
        (None, None)
    };
    let spectra = scenario.rolling.as_ref().map_or((args.segment, 1.0), |r| {
        (
            args.segment.or(r.segment),
            r.reference_force.map_or(1.0, |f| f.value()),
        )
    });
    let name = scenario.name.clone();
    let run = run_scenario_comparison_against(
        scenario,
        base,
        Stretch {
            start: args.from,
            steps: Some(args.steps),
            segment: args.segment,
        },
        Par::rayon(args.threads),
        &options,
        saved,
    )?;
    print_report(&name, &run);
    let checked = match check {
        Some(check) => {
            let (segment, reference_force) = spectra;
            let sensors = &run.multipoint.config.sensors;
            let c = compare_references(&check, &run.bem, sensors, reference_force, segment)?;
            say!("the second BEM run (--bem-check) against this one:");
            for s in &c {
                print_report_row(&format!("{} (BEM check)", s.name), s);
            }
            c
        }
        None => Vec::new(),
    };
    let mut set = OutputSet::new(&args.out)?;
    write_outputs(&run, &checked, &mut set)?;
    for path in set.commit()? {
        say!("wrote {}", path.display());
    }
    Ok(())
}

fn print_report(name: &str, run: &BemRollingRun) {
    let c = &run.comparison;
    let (nx, ny, dx) = run.road_grid;
    say!(
        "{name}: {} steps; texture {nx} × {ny} at {:.3} mm; BEM window {} × {} cells",
        c.steps,
        dx * 1e3,
        run.bem.window.0,
        run.bem.window.1
    );
    say!(
        "time: multipoint {:.1} s, BEM {:.1} s ({} CG iterations, {} failed steps); multipoint failed steps: {}",
        run.multipoint_time.as_secs_f64(),
        run.bem_time.as_secs_f64(),
        run.bem.iterations(),
        run.bem.failed(),
        run.multipoint.status_counts()[2]
    );
    if let tyreroad::scenario::RoadSummary::Texture(t) = &run.multipoint.road
        && let Some(cal) = &t.calibration
    {
        say!(
            "calibrated laws: {} of the road's {} asperities, {} tables solved ({} read from disk), approach bound {:.3} mm, {:.1} s (in the multipoint time)",
            cal.asperities,
            t.asperities,
            cal.tables,
            cal.from_disk,
            cal.max_approach * 1e3,
            cal.time.as_secs_f64()
        );
        if let Some(note) = cal.depth_note() {
            say!("{note}");
        }
        for warning in cal.warnings() {
            say!("warning: {warning}");
        }
    }
    if let Some(f) = &run.field_rung {
        let st = &f.stats;
        let calibration = match &run.multipoint.road {
            tyreroad::scenario::RoadSummary::Texture(t) => t.calibration.as_ref().map(|c| c.time),
            _ => None,
        }
        .unwrap_or_default();
        say!(
            "field coupling: {} settled steps, {} rounds ({:.2} a step, at most {}), {} double-sum and {} centroid pairs over all rounds; steps {:.1} s after the calibration; the run's own sensors on {}",
            st.steps,
            st.rounds,
            st.rounds as f64 / st.steps.max(1) as f64,
            st.max_rounds,
            st.field_pairs,
            st.centroid_pairs,
            run.multipoint_time
                .saturating_sub(calibration)
                .as_secs_f64(),
            match f.in_run {
                tyreroad::fidelity::rolling_fields::SensorAccounting::Fields =>
                    "the calibrated fields",
                tyreroad::fidelity::rolling_fields::SensorAccounting::Discs => "the discs",
            }
        );
    }
    say!(
        "bands from {:.0} Hz up are resolved by the Welch segment (unresolved bands marked *; a transient's bands all are)",
        c.resolved_from
    );
    print_report_header();
    let row = print_report_row;
    row("total force", &c.total);
    row("approach", &c.approach);
    for s in &c.sensors {
        row(&format!("{} (fields)", s.name), s);
    }
    for s in &c.sensors_summit {
        row(&format!("{} (summits)", s.name), s);
    }
    // Each contact's force spread as its own cap's BEM pressure.
    for s in &run.caps.1.sensors {
        row(&format!("{} (caps)", s.name), s);
    }
    // The calibrated_fields run recounted: on its calibrated fields, on
    // its laws' discs.
    if let Some(f) = &run.field_rung {
        for s in &f.fields.1.sensors {
            row(&format!("{} (cal. fields)", s.name), s);
        }
        for s in &f.discs.1.sensors {
            row(&format!("{} (discs)", s.name), s);
        }
    }
    // The model before the contact-point gaps, against the same BEM run.
    // (Not run on calibrated laws: it would calibrate the road again.)
    let g = run.summit_gaps.as_ref().map(|(_, c)| c);
    if let Some(g) = g {
        row("approach (summit gaps)", &g.approach);
        for s in &g.sensors {
            row(&format!("{} (summit gaps)", s.name), s);
        }
    }
    say!("band levels (dB), model fields / model summits / model summit gaps / BEM:");
    for (k, s) in c.sensors.iter().enumerate() {
        let summit = &c.sensors_summit[k];
        let gaps = g.map(|g| &g.sensors[k].bands);
        let cells: Vec<String> = s
            .bands
            .iter()
            .zip(&summit.bands)
            .enumerate()
            .map(|(i, (b, p))| {
                let q = gaps.and_then(|g| g.get(i)).map_or(f64::NAN, |q| q.model_db);
                format!(
                    "{}{:.0}: {:.1}/{:.1}/{:.1}/{:.1}",
                    if b.resolved { "" } else { "*" },
                    b.nominal,
                    b.model_db,
                    p.model_db,
                    q,
                    b.reference_db
                )
            })
            .collect();
        say!("  {}: {}", s.name, cells.join("  "));
    }
}

/// One sensor at one step.
#[derive(Serialize)]
struct SensorRow<'a> {
    step: usize,
    sensor: &'a str,
    #[serde(serialize_with = "fmt::sci9")]
    model_fields_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    model_summits_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    model_summit_gaps_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    bem_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    model_caps_n: f64,
    /// `calibrated_fields` only (NaN otherwise): the run's forces on its
    /// calibrated fields and on its laws' discs.
    #[serde(serialize_with = "fmt::sci9")]
    model_calibrated_fields_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    model_discs_n: f64,
}

/// One band of one signal.
#[derive(Serialize)]
struct BandRow<'a> {
    signal: &'a str,
    accounting: &'a str,
    band_nominal_hz: f64,
    #[serde(serialize_with = "fmt::fixed3")]
    model_db: f64,
    #[serde(serialize_with = "fmt::fixed3")]
    bem_db: f64,
    #[serde(serialize_with = "fmt::fixed3")]
    difference_db: f64,
    /// The error signal's level re the BEM's in the band.
    #[serde(serialize_with = "fmt::fixed3")]
    error_db: f64,
    resolved: bool,
    /// "welch" or "transient" (docs/validation.md, "Where the bands miss").
    spectrum: &'static str,
}

fn write_outputs(
    run: &BemRollingRun,
    checked: &[SignalComparison],
    set: &mut OutputSet,
) -> Result<()> {
    let mp = &run.multipoint.result;
    let steps = compared_step_rows(mp, &run.bem);
    set.write_csv("rolling_bem_steps.csv", &steps)?;
    set.write(
        crate::rolling_bem_saved::REFERENCE_FILE,
        run.bem_reference.to_text().as_bytes(),
    )?;
    let sensors = &run.multipoint.config.sensors;
    let summit =
        tyreroad::bem_rolling::summit_sensor_forces(mp, &run.multipoint.road_positions, sensors);
    let mut rows = Vec::new();
    let gap_steps: &[_] = run.summit_gaps.as_ref().map_or(&[], |(r, _)| &r.steps);
    for (k, s) in sensors.iter().enumerate() {
        for (i, (m, b)) in mp.steps.iter().zip(&run.bem.steps).enumerate() {
            rows.push(SensorRow {
                step: m.index,
                sensor: &s.name,
                model_fields_n: m.sensor_forces[k],
                model_summits_n: summit[k][i],
                model_summit_gaps_n: gap_steps.get(i).map_or(f64::NAN, |g| g.sensor_forces[k]),
                bem_n: b.sensor_forces[k],
                model_caps_n: run.caps.0[k][i],
                model_calibrated_fields_n: run
                    .field_rung
                    .as_ref()
                    .map_or(f64::NAN, |f| f.fields.0[k][i]),
                model_discs_n: run
                    .field_rung
                    .as_ref()
                    .map_or(f64::NAN, |f| f.discs.0[k][i]),
            });
        }
    }
    set.write_csv("rolling_bem_sensors.csv", &rows)?;
    let c = &run.comparison;
    let mut bands = Vec::new();
    let labelled = [
        ("total", "fields", &c.total),
        ("approach", "fields", &c.approach),
    ]
    .into_iter()
    .chain(c.sensors.iter().map(|s| (s.name.as_str(), "fields", s)))
    .chain(
        c.sensors_summit
            .iter()
            .map(|s| (s.name.as_str(), "summits", s)),
    )
    .chain(
        run.summit_gaps
            .iter()
            .flat_map(|(_, g)| g.sensors.iter())
            .map(|s| (s.name.as_str(), "summit gaps", s)),
    )
    .chain(
        run.caps
            .1
            .sensors
            .iter()
            .map(|s| (s.name.as_str(), "caps", s)),
    )
    .chain(
        run.field_rung
            .iter()
            .flat_map(|f| f.fields.1.sensors.iter())
            .map(|s| (s.name.as_str(), "calibrated fields", s)),
    )
    .chain(
        run.field_rung
            .iter()
            .flat_map(|f| f.discs.1.sensors.iter())
            .map(|s| (s.name.as_str(), "discs", s)),
    )
    .chain(checked.iter().map(|s| (s.name.as_str(), "bem check", s)));
    for (signal, accounting, s) in labelled {
        bands.extend(s.bands.iter().map(|b| BandRow {
            signal,
            accounting,
            band_nominal_hz: b.nominal,
            model_db: b.model_db,
            bem_db: b.reference_db,
            difference_db: b.difference_db,
            error_db: b.error_db,
            resolved: b.resolved,
            spectrum: s.spectrum.name(),
        }));
    }
    set.write_csv("rolling_bem_bands.csv", &bands)?;
    charts(run, &summit, set)
}

/// The sensors' forces per step and their band levels, model (fields and
/// summits) and BEM on one chart each.
fn charts(run: &BemRollingRun, summit: &[Vec<f64>], set: &mut OutputSet) -> Result<()> {
    let mp = &run.multipoint.result;
    let mut signals = Vec::new();
    let mut levels = Vec::new();
    for (k, s) in run.multipoint.config.sensors.iter().enumerate() {
        let pts = |v: &mut dyn Iterator<Item = f64>| -> Vec<(f64, f64)> {
            v.enumerate()
                .filter(|(_, y)| y.is_finite())
                .map(|(i, y)| (i as f64, y))
                .collect()
        };
        signals.push(Series {
            label: format!("{} multipoint", s.name),
            points: pts(&mut mp.steps.iter().map(|st| st.sensor_forces[k])),
        });
        signals.push(Series {
            label: format!("{} multipoint (summits)", s.name),
            points: pts(&mut summit[k].iter().copied()),
        });
        if let Some((gaps, _)) = &run.summit_gaps {
            signals.push(Series {
                label: format!("{} multipoint (summit gaps)", s.name),
                points: pts(&mut gaps.steps.iter().map(|st| st.sensor_forces[k])),
            });
        }
        signals.push(Series {
            label: format!("{} BEM", s.name),
            points: pts(&mut run.bem.steps.iter().map(|st| st.sensor_forces[k])),
        });
        let c = &run.comparison.sensors[k];
        let band_x = |nominal: f64| (10.0 * (nominal / 1000.0).log10()).round();
        let finite = |f: &dyn Fn(&tyreroad::bem_rolling::BandComparison) -> f64| {
            c.bands
                .iter()
                .filter(|b| f(b).is_finite())
                .map(|b| (band_x(b.nominal), f(b)))
                .collect::<Vec<_>>()
        };
        levels.push(Series {
            label: format!("{} multipoint", s.name),
            points: finite(&|b| b.model_db),
        });
        levels.push(Series {
            label: format!("{} BEM", s.name),
            points: finite(&|b| b.reference_db),
        });
    }
    if signals.iter().all(|s| s.points.is_empty()) {
        return Ok(());
    }
    line_chart(
        set,
        "rolling_bem_sensors",
        "Sensor forces: multipoint against the full BEM",
        "step",
        "force (N)",
        &signals,
    )?;
    if levels.iter().any(|s| !s.points.is_empty()) {
        line_chart(
            set,
            "rolling_bem_bands",
            "Sensor one-third-octave levels, 100 Hz to 2 kHz",
            "band k (centre 1 kHz · 10^(k/10))",
            "level (dB re reference force)",
            &levels,
        )?;
    }
    Ok(())
}
