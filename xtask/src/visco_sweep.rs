//! `cargo xtask visco-sweep SCENARIO [--speeds 30..130] [--temperatures 0degC,20degC,40degC]`:
//! viscoelastic rolling runs of a scenario with `[material.viscoelastic]`
//! (docs/viscoelastic.md, "Rolling"), one per speed (at the scenario's
//! temperature) and one per temperature (at the scenario's speed), on one
//! road. Prints and writes a table of the overall and one-third-octave band
//! levels of the primary signal (total force, or the approach under load
//! control) and of each sensor, and charts of them against speed and
//! temperature.

use std::path::{Path, PathBuf};

use anyhow::{Context, Result, bail};
use clap::Args;
use tyreroad::scenario::output::OutputSet;
use tyreroad::scenario::{RollingRun, RunOptions, Scenario, Temperature, ViscoCase};
use tyreroad::shared::spectrum::BandLevel;
use tyreroad::viscoelastic::significant;

use crate::charts::{Series, line_chart};

/// `cargo xtask visco-sweep`'s arguments.
#[derive(Args)]
pub struct ViscoSweepArgs {
    /// The scenario (TOML) with `[rolling]` and `[material.viscoelastic]`.
    pub scenario: PathBuf,
    /// Speeds in km/h: a list `30,50,80` or a range `30..130` (split by
    /// `--speed-count`).
    #[arg(long, default_value = "30..130")]
    pub speeds: String,
    /// Points of a speed range (2 to 1000).
    #[arg(long, default_value_t = 6)]
    pub speed_count: usize,
    /// Tread temperatures, a list with units: `"0 °C,20 °C,40 °C"`,
    /// `0degC,20degC` or `273.15K,293.15K` (a bare number is refused: it
    /// means kelvin in a scenario file). Needs
    /// `[material.viscoelastic.shift]`. None: no temperature sweep.
    #[arg(long)]
    pub temperatures: Option<String>,
    /// Output directory.
    #[arg(long, default_value = "visco_sweep")]
    pub out: PathBuf,
}

/// Most runs of one sweep (speeds, and temperatures): each is a whole
/// rolling run, so a thousand is already hours; more is a typing slip.
const MAX_SWEEP_POINTS: usize = 1000;

/// The speeds (m/s) of `--speeds`, each in the range of `[rolling] speed`.
fn speeds(text: &str, count: usize) -> Result<Vec<f64>> {
    let [lo, hi] = ViscoCase::SPEED_RANGE;
    let kmh = |s: &str| -> Result<f64> {
        let v: f64 = s
            .trim()
            .trim_end_matches("km/h")
            .trim()
            .parse()
            .with_context(|| format!("--speeds: `{s}` is not a speed in km/h"))?;
        if !(v.is_finite() && (lo * 3.6..=hi * 3.6).contains(&v)) {
            bail!(
                "--speeds: {} km/h is outside the range of [rolling] speed ({} to {} km/h)",
                significant(v),
                significant(lo * 3.6),
                significant(hi * 3.6)
            );
        }
        Ok(v / 3.6)
    };
    let list = if let Some((a, b)) = text.split_once("..") {
        let (a, b) = (kmh(a)?, kmh(b)?);
        if !(2..=MAX_SWEEP_POINTS).contains(&count) || b <= a {
            bail!(
                "--speeds {text} with --speed-count {count}: a range needs its end above its \
                 start and --speed-count from 2 to {MAX_SWEEP_POINTS}"
            );
        }
        (0..count)
            .map(|j| a + (b - a) * j as f64 / (count - 1) as f64)
            .collect()
    } else {
        let count = text.split(',').count();
        if count > MAX_SWEEP_POINTS {
            bail!("--speeds: {count} speeds, at most {MAX_SWEEP_POINTS}");
        }
        text.split(',').map(kmh).collect::<Result<Vec<_>>>()?
    };
    Ok(list)
}

/// The temperatures (K) of `--temperatures`, each with its unit: a bare
/// number means kelvin in a scenario file and would read as °C to most
/// users here, so it is refused rather than guessed.
fn temperatures(text: &str) -> Result<Vec<f64>> {
    let count = text.split(',').count();
    if count > MAX_SWEEP_POINTS {
        bail!("--temperatures: {count} temperatures, at most {MAX_SWEEP_POINTS}");
    }
    text.split(',')
        .map(|t| {
            let t = t.trim();
            if t.parse::<f64>().is_ok() {
                bail!("--temperatures: `{t}` has no unit: write \"{t} °C\" ({t}degC) or \"{t} K\"");
            }
            Temperature::parse(t)
                .map(|t| t.0)
                .map_err(|e| anyhow::anyhow!("--temperatures: {e}"))
        })
        .collect()
}

/// One row of the table.
struct Row {
    sweep: &'static str,
    speed_kmh: f64,
    temperature_c: Option<f64>,
    /// Per signal (primary, then sensors): overall level and band levels.
    signals: Vec<(f64, Vec<BandLevel>)>,
}

/// Overall level (dB re the same reference) of a set of band levels: the
/// sum of the band powers.
fn overall(levels: &[BandLevel]) -> f64 {
    let power: f64 = levels
        .iter()
        .map(|b| 10f64.powf(b.level_db / 10.0))
        .filter(|p| p.is_finite())
        .sum();
    10.0 * power.log10()
}

fn row(sweep: &'static str, run: &RollingRun, temperature: Option<f64>) -> Row {
    let spectra = &run.spectra;
    let mut signals = vec![(overall(&spectra.primary), spectra.primary.clone())];
    for s in &spectra.sensors {
        signals.push((overall(s), s.clone()));
    }
    Row {
        sweep,
        speed_kmh: run.config.speed * 3.6,
        temperature_c: temperature.map(|t| t - 273.15),
        signals,
    }
}

/// `cargo xtask visco-sweep`.
pub fn run(args: &ViscoSweepArgs) -> Result<()> {
    let scenario = Scenario::from_path(&args.scenario)?;
    let base = args.scenario.parent().unwrap_or(Path::new("."));
    let options = RunOptions::new(base);
    let speeds = speeds(&args.speeds, args.speed_count)?;
    let temperatures = match &args.temperatures {
        Some(t) => temperatures(t)?,
        None => Vec::new(),
    };
    let mut cases: Vec<(&'static str, ViscoCase)> = speeds
        .iter()
        .map(|&v| {
            let case = ViscoCase {
                speed: Some(v),
                temperature: None,
            };
            ("speed", case)
        })
        .collect();
    cases.extend(temperatures.iter().map(|&t| {
        let case = ViscoCase {
            speed: None,
            temperature: Some(t),
        };
        ("temperature", case)
    }));
    let started = std::time::Instant::now();
    let list: Vec<ViscoCase> = cases.iter().map(|c| c.1).collect();
    let runs = scenario.roll_viscoelastic(&options, &list)?;
    let names = signal_names(&scenario);
    let mut rows = Vec::new();
    for ((sweep, case), run) in cases.iter().zip(runs) {
        match run {
            Ok(run) => rows.push(row(sweep, &run, case.temperature)),
            Err(e) => eprintln!("{sweep} run at {} failed: {e}", case_label(case)),
        }
    }
    if rows.is_empty() {
        bail!("every run failed");
    }
    print_table(&rows, &names);
    say!(
        "{} runs in {:.1} s",
        rows.len(),
        started.elapsed().as_secs_f64()
    );
    let mut set = OutputSet::new(&args.out)?;
    set.write("visco_sweep.csv", table_csv(&rows, &names).as_bytes())?;
    for sweep in ["speed", "temperature"] {
        charts(&mut set, &rows, &names, sweep)?;
    }
    let written = set.commit()?;
    say!("wrote {} files in {}", written.len(), args.out.display());
    Ok(())
}

/// "50 km/h", "20 °C (293.15 K)" or both: the values a case replaces.
fn case_label(case: &ViscoCase) -> String {
    let mut parts = Vec::new();
    if let Some(v) = case.speed {
        parts.push(format!("{} km/h", significant(v * 3.6)));
    }
    if let Some(t) = case.temperature {
        parts.push(format!(
            "{} °C ({} K)",
            significant(t - 273.15),
            significant(t)
        ));
    }
    if parts.is_empty() {
        "the scenario's speed and temperature".into()
    } else {
        parts.join(", ")
    }
}

fn signal_names(scenario: &Scenario) -> Vec<String> {
    let load = scenario
        .rolling
        .as_ref()
        .is_some_and(|r| r.control.load.is_some());
    let mut names = vec![if load { "approach" } else { "total_force" }.to_string()];
    if let Some(r) = &scenario.rolling {
        names.extend(r.sensors.iter().map(|s| s.name.clone()));
    }
    names
}

fn print_table(rows: &[Row], names: &[String]) {
    say_part!("{:<12} {:>9} {:>8}", "sweep", "km/h", "°C");
    for n in names {
        say_part!(" {:>14}", format!("{n} dB"));
    }
    say!();
    for r in rows {
        let t = r.temperature_c.map_or("-".into(), |t| format!("{t:.1}"));
        say_part!("{:<12} {:>9.1} {:>8}", r.sweep, r.speed_kmh, t);
        for (level, _) in &r.signals {
            say_part!(" {level:>14.2}");
        }
        say!();
    }
}

/// Long form: one line per run, signal and band (band `overall` for the sum).
fn table_csv(rows: &[Row], names: &[String]) -> String {
    let mut out = String::from("sweep,speed_kmh,temperature_c,signal,band_centre_hz,level_db\n");
    for r in rows {
        let t = r.temperature_c.map_or(String::new(), |t| format!("{t:.2}"));
        for (name, (level, bands)) in names.iter().zip(&r.signals) {
            let head = format!("{},{:.3},{t},{name}", r.sweep, r.speed_kmh);
            out.push_str(&format!("{head},overall,{level:.3}\n"));
            for b in bands {
                out.push_str(&format!("{head},{},{:.3}\n", b.band.nominal, b.level_db));
            }
        }
    }
    out
}

/// Charts of one sweep: overall levels of every signal, and the band levels
/// of each signal at up to five bands every run reports.
fn charts(set: &mut OutputSet, rows: &[Row], names: &[String], sweep: &str) -> Result<()> {
    let rows: Vec<&Row> = rows.iter().filter(|r| r.sweep == sweep).collect();
    if rows.len() < 2 {
        return Ok(());
    }
    let x = |r: &Row| {
        if sweep == "speed" {
            r.speed_kmh
        } else {
            r.temperature_c.unwrap_or(f64::NAN)
        }
    };
    let x_label = if sweep == "speed" {
        "speed (km/h)"
    } else {
        "tread temperature (°C)"
    };
    let overall: Vec<Series> = names
        .iter()
        .enumerate()
        .take(6)
        .map(|(s, name)| Series {
            label: name.clone(),
            points: rows
                .iter()
                .map(|r| (x(r), r.signals[s].0))
                .filter(|p| p.1.is_finite())
                .collect(),
        })
        .filter(|s| !s.points.is_empty())
        .collect();
    // A signal that stayed zero (a sensor the footprint missed) has no
    // finite level and no line.
    line_chart(
        set,
        &format!("{sweep}_overall"),
        &format!("Overall level against {sweep}"),
        x_label,
        "level (dB)",
        &overall,
    )?;
    for (s, name) in names.iter().enumerate() {
        // Bands every run reports (the slowest run's Nyquist bounds them).
        let common: Vec<f64> = rows[0].signals[s]
            .1
            .iter()
            .map(|b| b.band.nominal)
            .filter(|&f| {
                rows.iter()
                    .all(|r| r.signals[s].1.iter().any(|b| b.band.nominal == f))
            })
            .collect();
        let picked: Vec<f64> = common.iter().rev().step_by(3).take(5).copied().collect();
        let series: Vec<Series> = picked
            .iter()
            .map(|&f| Series {
                label: format!("{f} Hz"),
                points: rows
                    .iter()
                    .filter_map(|r| {
                        let b = r.signals[s].1.iter().find(|b| b.band.nominal == f)?;
                        b.level_db.is_finite().then_some((x(r), b.level_db))
                    })
                    .collect(),
            })
            .filter(|s| !s.points.is_empty())
            .collect();
        if !series.is_empty() {
            line_chart(
                set,
                &format!("{sweep}_bands_{name}"),
                &format!("{name}: one-third-octave band levels against {sweep}"),
                x_label,
                "level (dB)",
                &series,
            )?;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_runaway_speed_count_is_refused_before_allocating() {
        for count in [1, MAX_SWEEP_POINTS + 1, 100_000_000] {
            let err = speeds("30..130", count).expect_err("refused").to_string();
            assert!(err.contains("--speed-count"), "{count}: {err}");
        }
        assert_eq!(
            speeds("30..130", MAX_SWEEP_POINTS).expect("cap").len(),
            1000
        );
        let many = vec!["50"; MAX_SWEEP_POINTS + 1].join(",");
        assert!(speeds(&many, 6).is_err());
        let many = vec!["20 °C"; MAX_SWEEP_POINTS + 1].join(",");
        assert!(temperatures(&many).is_err());
    }

    #[test]
    fn speeds_outside_the_rolling_speed_range_are_refused() {
        for text in ["1e30", "30..1e30", "0", "-5", "0.001", "NaN", "inf"] {
            let err = speeds(text, 6).expect_err(text).to_string();
            assert!(
                err.contains("km/h") && err.contains("--speeds"),
                "{text}: {err}"
            );
        }
        let ok = speeds("30,50km/h,1800", 6).expect("in range");
        assert!((ok[2] - 500.0).abs() < 1e-9, "{ok:?}");
    }

    #[test]
    fn temperatures_need_their_unit() {
        let err = temperatures("25").expect_err("bare").to_string();
        assert!(
            err.contains("`25` has no unit") && err.contains("°C"),
            "{err}"
        );
        let kelvin = temperatures("25 °C, 298.15 K,25degC").expect("units");
        for t in kelvin {
            assert!((t - 298.15).abs() < 1e-9, "{t}");
        }
    }

    #[test]
    fn failed_cases_are_labelled_without_debug_output() {
        let case = ViscoCase {
            speed: None,
            temperature: Some(191.55 + 1e-13),
        };
        let label = case_label(&case);
        assert_eq!(label, "-81.6 °C (191.55 K)");
        let case = ViscoCase {
            speed: Some(50.0 / 3.6),
            temperature: None,
        };
        assert_eq!(case_label(&case), "50 km/h");
    }
}
