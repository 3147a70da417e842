//! `cargo xtask rolling-bem SCENARIO --viscoelastic E_INF,E1@TAU1,... [--speed V]`:
//! the viscoelastic rolling BEM reference (`tyreroad::bem_rolling::roll_visco_bem`)
//! over the scenario's stretch, beside the elastic rolling BEM with the
//! tread's two limit moduli `E∞` and `E∞ + Σ E_k` on the same stretch.
//! Prints the mean force, approach and total-force band levels of the three
//! runs and writes their steps, sensor forces and bands.
//!
//! A scenario with `[material.viscoelastic]` (and no `--viscoelastic`) is
//! rolled by both the viscoelastic multipoint model and the viscoelastic
//! BEM ([`run_comparison`]): the comparison table of the elastic runs,
//! per-step totals, approach and sensor forces side by side.

use std::path::Path;

use anyhow::{Context, Result, bail};
use serde::Serialize;
use tyreroad::bem_rolling::{
    BemRollingOptions, BemRollingResult, Stretch, ViscoBemRollingRun, roll_bem,
    roll_visco_bem_scenario, run_visco_scenario_comparison, texture_field, third_octave_policy,
};
use tyreroad::scenario::output::{OutputSet, fmt};
use tyreroad::scenario::{MODULUS_RANGE, Par, RELAXATION_TIME_RANGE, Scenario};
use tyreroad::shared::Material;
use tyreroad::viscoelastic::{Branch, Prony};

use crate::rolling_bem_args::{
    RollingBemArgs, compared_step_rows, print_report_header, print_report_row,
};

/// Rolls the scenario's viscoelastic tread over the stretch by the
/// multipoint model and by the viscoelastic BEM; prints the comparison,
/// writes the steps, sensors and bands of both.
pub fn run_comparison(args: &RollingBemArgs, scenario: Scenario) -> Result<()> {
    let name = scenario.name.clone();
    let base = args.scenario.parent().unwrap_or(Path::new("."));
    let options = BemRollingOptions {
        tolerance: args.tolerance,
        ..BemRollingOptions::default()
    };
    let stretch = Stretch {
        start: args.from,
        steps: Some(args.steps),
        segment: args.segment,
    };
    let run = run_visco_scenario_comparison(
        scenario,
        base,
        stretch,
        args.speed,
        Par::rayon(args.threads),
        &options,
    )?;
    print_comparison(&name, &run);
    let mut set = OutputSet::new(&args.out)?;
    write_comparison(&run, &mut set)?;
    for path in set.commit()? {
        say!("wrote {}", path.display());
    }
    Ok(())
}

fn print_comparison(name: &str, run: &ViscoBemRollingRun) {
    let c = &run.comparison;
    let config = &run.multipoint.config;
    let (nx, ny, dx) = run.road_grid;
    say!(
        "{name} (viscoelastic, E_inf {:.3} MPa, E_0 {:.3} MPa): {} steps at {} m/s (Δt = {:.3e} s); \
         texture {nx} × {ny} at {:.3} mm; BEM window {} × {} cells",
        run.tread.long_term() * 1e-6,
        run.tread.instantaneous() * 1e-6,
        c.steps,
        config.speed,
        config.step / config.speed,
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
        run.multipoint.result.status_counts()[2]
    );
    if let tyreroad::scenario::RoadSummary::Texture(t) = &run.multipoint.road
        && let Some(cal) = &t.calibration
    {
        say!(
            "calibrated laws: {} of the road's {} asperities, {} tables solved, to {:.3} mm approach, {:.1} s of the multipoint time (steps {:.1} s)",
            cal.asperities,
            t.asperities,
            cal.tables,
            cal.max_approach * 1e3,
            cal.time.as_secs_f64(),
            run.multipoint_time.saturating_sub(cal.time).as_secs_f64()
        );
        for warning in cal.warnings() {
            say!("warning: {warning}");
        }
    }
    say!(
        "mean approach: multipoint {:.5} mm, BEM {:.5} mm",
        1e3 * mean(&run.multipoint.result.approach()),
        1e3 * mean(&run.bem.approach())
    );
    print_report_header();
    print_report_row("total force", &c.total);
    print_report_row("approach", &c.approach);
    for s in &c.sensors {
        print_report_row(&format!("{} (fields)", s.name), s);
    }
    for s in &c.sensors_summit {
        print_report_row(&format!("{} (summits)", s.name), s);
    }
}

/// One sensor of both viscoelastic runs at one step.
#[derive(Serialize)]
struct ComparedSensor<'a> {
    step: usize,
    sensor: &'a str,
    #[serde(serialize_with = "fmt::sci9")]
    model_fields_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    bem_n: f64,
}

/// One band of one signal of both viscoelastic runs.
#[derive(Serialize)]
struct ComparedBand<'a> {
    signal: &'a str,
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

fn write_comparison(run: &ViscoBemRollingRun, set: &mut OutputSet) -> Result<()> {
    let mp = &run.multipoint.result;
    let steps = compared_step_rows(mp, &run.bem);
    set.write_csv("rolling_visco_compare_steps.csv", &steps)?;
    let mut sensors = Vec::new();
    for (k, s) in run.multipoint.config.sensors.iter().enumerate() {
        sensors.extend(
            mp.steps
                .iter()
                .zip(&run.bem.steps)
                .map(|(m, b)| ComparedSensor {
                    step: m.index,
                    sensor: &s.name,
                    model_fields_n: m.sensor_forces[k],
                    bem_n: b.sensor_forces[k],
                }),
        );
    }
    set.write_csv("rolling_visco_compare_sensors.csv", &sensors)?;
    let c = &run.comparison;
    let signals = [&c.total, &c.approach].into_iter().chain(&c.sensors);
    let bands: Vec<ComparedBand<'_>> = signals
        .flat_map(|s| {
            s.bands.iter().map(|b| ComparedBand {
                signal: &s.name,
                band_nominal_hz: b.nominal,
                model_db: b.model_db,
                bem_db: b.reference_db,
                difference_db: b.difference_db,
                error_db: b.error_db,
                resolved: b.resolved,
                spectrum: s.spectrum.name(),
            })
        })
        .collect();
    // A slow run's bands lie below 100 Hz: no table rather than an empty one.
    if !bands.is_empty() {
        set.write_csv("rolling_visco_compare_bands.csv", &bands)?;
    }
    Ok(())
}

/// The tread from `E_INF,E1@TAU1,E2@TAU2,...` (Pa and s), with the
/// scenario's Poisson's ratio.
pub fn parse_prony(text: &str, poisson_ratio: f64) -> Result<Prony> {
    let mut fields = text.split(',').map(str::trim);
    let number = |s: &str, what: &str| -> Result<f64> {
        s.parse::<f64>()
            .with_context(|| format!("--viscoelastic: {what} {s:?} is not a number (SI: Pa, s)"))
    };
    // The ranges a scenario's [material.viscoelastic] is held to.
    let within = |s: &str, what: &str, [lo, hi]: [f64; 2], unit: &str| -> Result<f64> {
        let v = number(s, what)?;
        if !(v >= lo && v <= hi) {
            bail!("--viscoelastic: {what} {s}: expected {lo:e} to {hi:e} {unit}");
        }
        Ok(v)
    };
    let long_term = within(fields.next().unwrap_or(""), "E_inf", MODULUS_RANGE, "Pa")?;
    let branches = fields
        .map(|branch| {
            let Some((modulus, time)) = branch.split_once('@') else {
                bail!("--viscoelastic: branch {branch:?} must be MODULUS@RELAXATION_TIME (Pa@s)");
            };
            Ok(Branch {
                modulus: within(modulus.trim(), "branch modulus", MODULUS_RANGE, "Pa")?,
                relaxation_time: within(
                    time.trim(),
                    "relaxation time",
                    RELAXATION_TIME_RANGE,
                    "s",
                )?,
            })
        })
        .collect::<Result<Vec<_>>>()?;
    if branches.is_empty() {
        bail!("--viscoelastic {text:?}: no branch E@TAU: that is an elastic tread");
    }
    Ok(Prony::new(long_term, branches, poisson_ratio)?)
}

/// Runs the viscoelastic BEM and the two elastic limits, prints, writes.
pub fn run(args: &RollingBemArgs, tread: &str) -> Result<()> {
    let scenario = Scenario::from_path(&args.scenario)?;
    let base = args.scenario.parent().unwrap_or(Path::new("."));
    let elastic = scenario.material()?;
    let material = parse_prony(tread, elastic.poisson_ratio())?;
    let options = BemRollingOptions {
        tolerance: args.tolerance,
        par: Par::rayon(args.threads),
        ..BemRollingOptions::default()
    };
    let stretch = Stretch {
        start: args.from,
        steps: Some(args.steps),
        segment: args.segment,
    };
    let clock = std::time::Instant::now();
    let visco = roll_visco_bem_scenario(
        &scenario,
        base,
        stretch,
        &material,
        args.speed,
        options.par,
        &options,
    )?;
    let visco_time = clock.elapsed().as_secs_f64();
    // The elastic limits on the same road, path and sensors.
    let Some(texture) = scenario.texture.as_ref() else {
        bail!("the scenario has no [texture]");
    };
    let road = texture_field(&texture.height_map(base)?)?;
    let config = {
        let Some(spec) = scenario.rolling.as_ref() else {
            bail!("the scenario has no [rolling] section");
        };
        let mut c = spec.config()?;
        c.start = visco.steps[0].position;
        c.end = visco.steps[visco.steps.len() - 1].position;
        if let Some(v) = args.speed {
            c.speed = v;
        }
        c
    };
    let limit = |modulus: f64| -> Result<BemRollingResult> {
        let m = Material::new(modulus, elastic.poisson_ratio())?;
        Ok(roll_bem(&road, m, &config, &options)?)
    };
    let relaxed = limit(material.long_term())?;
    let glassy = limit(material.instantaneous())?;
    let segment = args
        .segment
        .or(scenario.rolling.as_ref().and_then(|r| r.segment));
    let runs = [
        ("viscoelastic", &visco),
        ("E_inf", &relaxed),
        ("E_0", &glassy),
    ];
    say!(
        "{}: {} steps at {} m/s (Δt = {:.3e} s), BEM window {} × {} cells, viscoelastic run {visco_time:.1} s, {} failed steps",
        scenario.name,
        visco.steps.len(),
        config.speed,
        config.step / config.speed,
        visco.window.0,
        visco.window.1,
        visco.failed()
    );
    say!(
        "{:<14} {:>16} {:>16}",
        "run",
        "mean force (N)",
        "mean approach (mm)"
    );
    for (label, r) in runs {
        say!(
            "{label:<14} {:>16.4} {:>16.5}",
            mean(&r.total_force()),
            1e3 * mean(&r.approach())
        );
    }
    let mut set = OutputSet::new(&args.out)?;
    write_outputs(&runs, &config.sensors, segment, &mut set)?;
    for path in set.commit()? {
        say!("wrote {}", path.display());
    }
    Ok(())
}

fn mean(v: &[f64]) -> f64 {
    let finite: Vec<f64> = v.iter().copied().filter(|x| x.is_finite()).collect();
    finite.iter().sum::<f64>() / finite.len().max(1) as f64
}

/// One step of one run.
#[derive(Serialize)]
struct StepRow<'a> {
    run: &'a str,
    step: usize,
    #[serde(serialize_with = "fmt::sci9")]
    time_s: f64,
    #[serde(serialize_with = "fmt::sci9")]
    position_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    total_force_n: f64,
    #[serde(serialize_with = "fmt::sci9")]
    approach_m: f64,
    #[serde(serialize_with = "fmt::sci9")]
    contact_area_m2: f64,
}

/// One sensor of one run at one step.
#[derive(Serialize)]
struct SensorRow<'a> {
    run: &'a str,
    step: usize,
    sensor: &'a str,
    #[serde(serialize_with = "fmt::sci9")]
    force_n: f64,
}

/// One band of one signal of one run.
#[derive(Serialize)]
struct BandRow<'a> {
    run: &'a str,
    signal: &'a str,
    band_nominal_hz: f64,
    #[serde(serialize_with = "fmt::fixed3")]
    level_db: f64,
}

fn write_outputs(
    runs: &[(&str, &BemRollingResult)],
    sensors: &[tyreroad::rolling::Sensor],
    segment: Option<usize>,
    set: &mut OutputSet,
) -> Result<()> {
    let mut steps = Vec::new();
    let mut rows = Vec::new();
    let mut bands = Vec::new();
    for &(run, r) in runs {
        steps.extend(r.steps.iter().map(|s| StepRow {
            run,
            step: s.index,
            time_s: s.time,
            position_m: s.position,
            total_force_n: s.total_force,
            approach_m: s.approach,
            contact_area_m2: s.contact_area,
        }));
        for (k, sensor) in sensors.iter().enumerate() {
            rows.extend(r.steps.iter().map(|s| SensorRow {
                run,
                step: s.index,
                sensor: &sensor.name,
                force_n: s.sensor_forces[k],
            }));
        }
        let signals = std::iter::once(("total".to_string(), r.total_force()))
            .chain((0..sensors.len()).map(|k| (sensors[k].name.clone(), r.sensor(k))));
        for (signal, values) in signals {
            let levels = third_octave_policy(&values, r.sample_rate, 1.0, segment)?;
            for b in levels {
                bands.push((run, signal.clone(), b.band.nominal, b.level_db));
            }
        }
    }
    set.write_csv("rolling_visco_bem_steps.csv", &steps)?;
    set.write_csv("rolling_visco_bem_sensors.csv", &rows)?;
    let bands: Vec<BandRow<'_>> = bands
        .iter()
        .map(|(run, signal, nominal, level)| BandRow {
            run,
            signal,
            band_nominal_hz: *nominal,
            level_db: *level,
        })
        .collect();
    set.write_csv("rolling_visco_bem_bands.csv", &bands)?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_tread_is_parsed_and_bad_text_is_named() {
        let tread = parse_prony("2e6, 3e6@1e-3, 5e6@2e-5", 0.5).expect("valid");
        assert_eq!(tread.branches().len(), 2);
        assert!((tread.instantaneous() - 10e6).abs() < 1e-6);
        let error = parse_prony("2e6,3e6", 0.5).expect_err("no time");
        assert!(
            error.to_string().contains("MODULUS@RELAXATION_TIME"),
            "{error}"
        );
        let error = parse_prony("2 MPa", 0.5).expect_err("units");
        assert!(error.to_string().contains("E_inf"), "{error}");
        // Held to the scenario file's ranges (regression: `history
        // --viscoelastic 1e30` ran with an approach of 0 at every step).
        for (text, what) in [
            ("1e30,3e6@1e-3", "E_inf"),
            ("2e6,1e20@1e-3", "branch modulus"),
            ("2e6,3e6@1e300", "relaxation time"),
            ("2e6,3e6@1e-300", "relaxation time"),
        ] {
            let error = parse_prony(text, 0.5).expect_err(text).to_string();
            assert!(
                error.contains(what) && error.contains("expected"),
                "{error}"
            );
        }
        let error = parse_prony("2e6", 0.5).expect_err("no branch").to_string();
        assert!(error.contains("elastic tread"), "{error}");
    }
}
