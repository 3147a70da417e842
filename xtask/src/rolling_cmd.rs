//! Rolling runs: the `[rolling]` section of a scenario file, run with a
//! progress bar and a checkpoint, written as time signals, one-third-octave
//! spectra, per-sensor signals and charts (docs/rolling.md).

use std::ops::ControlFlow;
use std::path::Path;
use std::time::Duration;

use anyhow::{Context, Result, bail};
use serde::Deserialize;
use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_rolling as rolling;

use tyreroad::texture_road::{TextureLaw, texture_road};

use crate::charts::{Series, line_chart};
use crate::output::Csv;
use crate::scenario::TextureSpec;
use crate::units::{Force, Length, Speed};

/// `[rolling]`: a tread rolled along the road.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RollingSpec {
    /// The tread's shape and footprint.
    pub tread: TreadSpec,
    /// First footprint centre x (m).
    pub start: Length,
    /// Last footprint centre x (m).
    pub end: Length,
    /// Space step Δx.
    pub step: Length,
    /// Lateral position y of the path (default 0).
    pub lateral: Option<Length>,
    /// Driving speed, e.g. "50 km/h".
    pub speed: Speed,
    /// What is imposed: exactly one of `load`, `approach`, `tread_height`.
    pub control: ControlSpec,
    /// Selection margin around a tyre's footprint (default 0).
    pub margin: Option<Length>,
    /// Virtual force sensors on the road.
    #[serde(default, rename = "sensor")]
    pub sensors: Vec<SensorSpec>,
    /// Reference of the force levels (default 1 N).
    pub reference_force: Option<Force>,
    /// Worker threads (default: rayon's, i.e. the cores).
    pub threads: Option<usize>,
    /// Chunks of the path solved in parallel (default: twice the threads).
    pub chunks: Option<usize>,
    /// Checkpoint in `OUT/checkpoint/` and resume from it (default true).
    #[serde(default = "yes")]
    pub checkpoint: bool,
    /// Solver tolerance (default 1e-12).
    pub tolerance: Option<f64>,
    /// Welch segment length in samples (default: half the signal).
    pub segment: Option<usize>,
    /// A synthetic road of random spheres instead of the scenario's
    /// asperities.
    pub synthetic_road: Option<SyntheticRoadSpec>,
}

fn yes() -> bool {
    true
}

/// `[rolling.tread]`
#[derive(Debug, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum TreadSpec {
    /// A flat rectangular block.
    Block {
        /// Along x.
        length: Length,
        /// Along y.
        width: Length,
    },
    /// A tyre envelope `s = x²/(2 Rx) + y²/(2 Ry)` over a footprint.
    Tyre {
        /// Longitudinal radius Rx.
        radius_x: Length,
        /// Transverse radius Ry.
        radius_y: Length,
        /// Footprint length along x.
        length: Length,
        /// Footprint width along y.
        width: Length,
    },
}

/// `[rolling.control]`: exactly one key.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ControlSpec {
    /// Wheel load (load control).
    pub load: Option<Force>,
    /// Approach below the road's highest summit (fixed axle height).
    pub approach: Option<Length>,
    /// Height of the tread's lowest point above z = 0 (fixed axle height).
    pub tread_height: Option<Length>,
}

/// `[[rolling.sensor]]`: a rectangle on the road.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SensorSpec {
    /// Name (CSV column).
    pub name: String,
    /// Lower x.
    pub x0: Length,
    /// Upper x.
    pub x1: Length,
    /// Lower y.
    pub y0: Length,
    /// Upper y.
    pub y1: Length,
}

/// `[rolling.synthetic_road]`: every key optional, defaults from
/// `tyreroad_rolling::SyntheticRoad::default()` (0.5 m × 0.15 m, 85 000
/// summits/m², ≥ 2 mm apart, radii 2–5 mm, heights over 2 mm, seed 2006).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SyntheticRoadSpec {
    /// Generator seed.
    pub seed: Option<u64>,
    /// Extent along x.
    pub length: Option<Length>,
    /// Extent along y (centred on y = 0).
    pub width: Option<Length>,
    /// Summits per m².
    pub density: Option<f64>,
    /// Smallest summit spacing.
    pub min_spacing: Option<Length>,
    /// Smallest radius.
    pub radius_min: Option<Length>,
    /// Largest radius.
    pub radius_max: Option<Length>,
    /// Range of summit heights.
    pub height_spread: Option<Length>,
}

impl SyntheticRoadSpec {
    /// The generator parameters.
    pub fn road(&self) -> rolling::SyntheticRoad {
        let d = rolling::SyntheticRoad::default();
        let l = |q: Option<Length>, v: f64| q.map_or(v, |q| q.value());
        rolling::SyntheticRoad {
            seed: self.seed.unwrap_or(d.seed),
            length: l(self.length, d.length),
            width: l(self.width, d.width),
            density: self.density.unwrap_or(d.density),
            min_spacing: l(self.min_spacing, d.min_spacing),
            radius_min: l(self.radius_min, d.radius_min),
            radius_max: l(self.radius_max, d.radius_max),
            height_spread: l(self.height_spread, d.height_spread),
        }
    }
}

impl RollingSpec {
    /// The library configuration.
    pub fn config(&self) -> Result<rolling::RollingConfig> {
        let tread = match self.tread {
            TreadSpec::Block { length, width } => rolling::Tread::Block {
                length: length.value(),
                width: width.value(),
            },
            TreadSpec::Tyre {
                radius_x,
                radius_y,
                length,
                width,
            } => rolling::Tread::Tyre {
                radius_x: radius_x.value(),
                radius_y: radius_y.value(),
                length: length.value(),
                width: width.value(),
            },
        };
        let c = &self.control;
        let control = match (c.load, c.approach, c.tread_height) {
            (Some(w), None, None) => rolling::RollingControl::Load(w.value()),
            (None, Some(d), None) => rolling::RollingControl::Approach(d.value()),
            (None, None, Some(h)) => rolling::RollingControl::TreadHeight(h.value()),
            _ => bail!("[rolling.control] needs exactly one of load, approach, tread_height"),
        };
        let mut config = rolling::RollingConfig::new(
            tread,
            [self.start.value(), self.end.value(), self.step.value()],
            self.speed.value(),
            control,
        );
        config.lateral = self.lateral.map_or(0.0, |q| q.value());
        config.margin = self.margin.map_or(0.0, |q| q.value());
        if let Some(t) = self.tolerance {
            config.tolerance = t;
        }
        config.sensors = self
            .sensors
            .iter()
            .map(|s| rolling::Sensor {
                name: s.name.clone(),
                x: [s.x0.value(), s.x1.value()],
                y: [s.y0.value(), s.y1.value()],
            })
            .collect();
        config.validate()?;
        Ok(config)
    }
}

/// The asperities of a scenario, by id order: positions (m), summit heights
/// (m) and one law each.
pub struct RoadParts<L> {
    /// Summit positions `(x, y)`.
    pub positions: Vec<[f64; 2]>,
    /// Summit heights `z`.
    pub heights: Vec<f64>,
    /// Contact laws.
    pub laws: Vec<L>,
}

/// The road of a `[texture]` scenario: the texture's asperities
/// (`tyreroad::texture_road`), with x along the map's x from its first column
/// and y centred on the map's mid-width, so a path at `lateral = 0` runs
/// down the middle of the texture.
pub fn texture_road_parts(
    texture: &TextureSpec,
    base_dir: &Path,
    material: Material,
) -> Result<RoadParts<TextureLaw>> {
    let map = texture.height_map(base_dir)?;
    let road = texture_road(&map, material, &texture.road_options())
        .context("turning the texture into asperities")?;
    let segmented = road.segmentation.asperities().len();
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    println!(
        "texture road {:.3} m × {:.3} m at {:.3} mm: Sq {:.3} mm, {} asperities ({} segmented)",
        map.length_x(),
        map.length_y(),
        map.dx() * 1e3,
        map.rms().unwrap_or(f64::NAN) * 1e3,
        road.len(),
        segmented
    );
    Ok(RoadParts {
        positions: road
            .positions
            .iter()
            .map(|&[x, y]| [x, y - y_mid])
            .collect(),
        heights: road.heights,
        laws: road.laws,
    })
}

/// Runs `[rolling]` on the scenario's asperities (`road`), or on
/// `spec.synthetic_road` when `road` is `None` (one of the two must be
/// given), and writes into `out`: `time_signals.csv`, `third_octave.csv`
/// (`band_centre_hz,level_db`), `third_octave_bands.csv` (exact centres and
/// sensor levels),
/// `sensors.csv` (when sensors are defined) and SVG charts. Shows a
/// progress bar; with `checkpoint = true` a killed run resumes from
/// `out/checkpoint/`.
pub fn run_rolling<L: ContactLaw + Sync>(
    material: Material,
    road: Option<RoadParts<L>>,
    spec: &RollingSpec,
    out: &Path,
) -> Result<()> {
    match (road, &spec.synthetic_road) {
        (Some(parts), None) => {
            let road = rolling::Road::new(tyreroad_multipoint::AsperitySet::new(
                parts.positions,
                parts.heights,
                parts.laws,
            )?);
            run_on(&road, material, spec, out)
        }
        (None, Some(synth)) => {
            let road = synth.road().sphere_road(material)?;
            println!("synthetic road: {} spherical summits", road.len());
            run_on(&road, material, spec, out)
        }
        (Some(_), Some(_)) => {
            bail!("[rolling.synthetic_road] and [[asperity]] both given: choose one")
        }
        (None, None) => bail!("no road: give [[asperity]] entries or [rolling.synthetic_road]"),
    }
}

fn run_on<L: ContactLaw + Sync>(
    road: &rolling::Road<L>,
    material: Material,
    spec: &RollingSpec,
    out: &Path,
) -> Result<()> {
    let config = spec.config()?;
    let total = config.steps();
    let bar = indicatif::ProgressBar::new(total as u64);
    bar.set_style(
        indicatif::ProgressStyle::with_template(
            "{spinner} rolling [{elapsed_precise}] {wide_bar} {pos}/{len} steps (eta {eta})",
        )
        .context("progress bar template")?,
    );
    let progress = |p: rolling::Progress| {
        bar.set_position(p.done as u64);
        ControlFlow::Continue(())
    };
    let checkpoint = rolling::CheckpointOptions {
        dir: out.join("checkpoint"),
        interval: Duration::from_secs(2),
    };
    let options = rolling::RunOptions {
        chunks: spec.chunks,
        par: rolling::Par::rayon(spec.threads.unwrap_or(0)),
        checkpoint: spec.checkpoint.then_some(&checkpoint),
        progress: Some(&progress),
    };
    let result = rolling::roll(road, material, &config, &options);
    bar.finish();
    let result = result?;
    if result.resumed > 0 {
        println!(
            "resumed {} of {total} steps from {}",
            result.resumed,
            checkpoint.dir.display()
        );
    }
    if result.min_clearance() <= 0.0 {
        println!(
            "warning: at some steps the approach exceeds the tread profile at the selection \
             boundary (clearance {:.3e} m): widen the footprint or the margin",
            result.min_clearance()
        );
    }
    write_outputs(&config, spec, &result, out)
}

fn write_outputs(
    config: &rolling::RollingConfig,
    spec: &RollingSpec,
    result: &rolling::RollingResult,
    out: &Path,
) -> Result<()> {
    let mut ts = Csv::new(
        "time_s,position_m,total_force_n,approach_m,contact_area_m2,n_contacts,n_selected,iterations,clearance_m,n_overlapping",
    );
    for s in &result.steps {
        ts.row(&[
            format!("{:.9e}", s.time),
            format!("{:.9e}", s.position),
            format!("{:.12e}", s.total_force),
            format!("{:.12e}", s.approach),
            format!("{:.9e}", s.contact_area),
            s.contacts.to_string(),
            s.selected.to_string(),
            s.iterations.to_string(),
            format!("{:.6e}", s.clearance),
            s.overlapping.to_string(),
        ]);
    }
    ts.write(&out.join("time_signals.csv"))?;
    let overlapping_steps = result.steps.iter().filter(|s| s.overlapping > 0).count();
    if overlapping_steps > 0 {
        println!(
            "note: at {overlapping_steps} of {} steps some contact patches overlap (up to {} \
             pairs, column n_overlapping): the point-force coupling does not hold there",
            result.steps.len(),
            result
                .steps
                .iter()
                .map(|s| s.overlapping)
                .max()
                .unwrap_or(0)
        );
    }

    // Spectra: the total force under displacement control (dB re the
    // reference force), the approach under load control (dB re 1 µm);
    // sensors always in dB re the reference force.
    let reference = spec.reference_force.map_or(1.0, |f| f.value());
    let load_control = matches!(config.control, rolling::RollingControl::Load(_));
    let (primary, primary_ref) = if load_control {
        (result.approach(), 1e-6)
    } else {
        (result.total_force(), reference)
    };
    let fs = result.sample_rate;
    let spectrum = |signal: &[f64], r: f64| rolling::third_octave(signal, fs, r, spec.segment);
    let levels = spectrum(&primary, primary_ref)?;
    // A Welch segment of L samples resolves Δf = fs/L; a band narrower than
    // two bins (width 0.23 f_c) holds leakage from its neighbours, not its
    // own content.
    let segment = spec
        .segment
        .unwrap_or_else(|| rolling::default_segment_len(primary.len()));
    let resolved_from = 2.0 * fs / segment as f64 / (10f64.powf(0.05) - 10f64.powf(-0.05));
    if levels
        .first()
        .is_some_and(|b| b.band.centre < resolved_from)
    {
        println!(
            "note: with {segment}-sample Welch segments (Δf = {:.1} Hz) the bands below \
             {resolved_from:.0} Hz are not resolved: roll a longer path for them",
            fs / segment as f64
        );
    }
    let sensor_levels: Vec<Vec<rolling::BandLevel>> = (0..config.sensors.len())
        .map(|k| spectrum(&result.sensor(k), reference))
        .collect::<Result<_, _>>()?;
    // third_octave.csv keeps exactly the two columns noise models read; the
    // exact centres and the sensors' levels go beside it.
    let mut to = Csv::new("band_centre_hz,level_db");
    let mut header = String::from("band_centre_hz,exact_centre_hz");
    for s in &config.sensors {
        header.push_str(&format!(",{}_db", s.name));
    }
    let mut detail = Csv::new(&header);
    for (b, level) in levels.iter().enumerate() {
        to.row(&[
            format!("{}", level.band.nominal),
            format!("{:.3}", level.level_db),
        ]);
        let mut row = vec![
            format!("{}", level.band.nominal),
            format!("{:.3}", level.band.centre),
        ];
        row.extend(
            sensor_levels
                .iter()
                .map(|l| format!("{:.3}", l[b].level_db)),
        );
        detail.row(&row);
    }
    to.write(&out.join("third_octave.csv"))?;
    detail.write(&out.join("third_octave_bands.csv"))?;

    if !config.sensors.is_empty() {
        let mut header = String::from("time_s,position_m");
        for s in &config.sensors {
            header.push_str(&format!(",{}_n", s.name));
        }
        let mut sc = Csv::new(&header);
        for s in &result.steps {
            let mut row = vec![format!("{:.9e}", s.time), format!("{:.9e}", s.position)];
            row.extend(s.sensor_forces.iter().map(|f| format!("{f:.9e}")));
            sc.row(&row);
        }
        sc.write(&out.join("sensors.csv"))?;
    }

    // Charts (x in ms for signals, band number k for spectra).
    let ms = |v: &[f64]| -> Vec<(f64, f64)> {
        result
            .steps
            .iter()
            .zip(v)
            .map(|(s, &y)| (s.time * 1e3, y))
            .collect()
    };
    let (name, unit, main) = if load_control {
        (
            "approach",
            "approach (mm)",
            result
                .approach()
                .iter()
                .map(|d| d * 1e3)
                .collect::<Vec<_>>(),
        )
    } else {
        ("total force", "total force (N)", result.total_force())
    };
    line_chart(
        &out.join("time_signals.svg"),
        &format!("{name} against time"),
        "time (ms)",
        unit,
        &[Series {
            label: name.into(),
            points: ms(&main),
        }],
    )?;
    let area_mm2: Vec<f64> = result.contact_area().iter().map(|a| a * 1e6).collect();
    line_chart(
        &out.join("contact_area.svg"),
        "contact area against time",
        "time (ms)",
        "contact area (mm²)",
        &[Series {
            label: "Σ π a²".into(),
            points: ms(&area_mm2),
        }],
    )?;
    if !config.sensors.is_empty() {
        let series: Vec<Series> = config
            .sensors
            .iter()
            .enumerate()
            .map(|(k, s)| Series {
                label: s.name.clone(),
                points: ms(&result.sensor(k)),
            })
            .collect();
        line_chart(
            &out.join("sensors.svg"),
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
        points: band_points(&levels),
    }];
    for (s, l) in config.sensors.iter().zip(&sensor_levels) {
        series.push(Series {
            label: format!("{} (dB re {reference} N)", s.name),
            points: band_points(l),
        });
    }
    line_chart(
        &out.join("third_octave.svg"),
        "one-third-octave spectra",
        "band k (centre 1000·10^(k/10) Hz; 0 = 1 kHz)",
        "level (dB)",
        &series,
    )?;
    println!(
        "rolling: {} steps, fs = {:.1} Hz, written to {}",
        result.steps.len(),
        fs,
        out.display()
    );
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    const FIXTURE: &str = include_str!("../../fixtures/rolling_tyre_dense_asphalt.toml");

    #[derive(Deserialize)]
    struct File {
        rolling: RollingSpec,
        #[allow(dead_code)]
        #[serde(flatten)]
        rest: toml::Table,
    }

    #[test]
    fn fixture_parses_with_units() -> Result<()> {
        let f: File = toml::from_str(FIXTURE)?;
        let c = f.rolling.config()?;
        assert!((c.speed - 50.0 / 3.6).abs() < 1e-12);
        assert!((c.step - 1e-3).abs() < 1e-15);
        assert!(matches!(c.tread, rolling::Tread::Tyre { .. }));
        // The road is the synthetic dense asphalt texture.
        assert!(f.rolling.synthetic_road.is_none());
        let s = crate::scenario::Scenario::parse(FIXTURE, "fixture")?;
        let t = s.texture.as_ref().expect("[texture]");
        assert!(t.synth.is_some() && t.file.is_none());
        Ok(())
    }

    #[test]
    fn texture_and_synthetic_road_together_are_refused() {
        let both = format!("{FIXTURE}\n[rolling.synthetic_road]\nseed = 1\n");
        let e = crate::scenario::Scenario::parse(&both, "both").expect_err("two roads");
        assert!(e.to_string().contains("choose one"), "{e}");
    }

    #[test]
    fn unknown_keys_and_double_controls_are_refused() {
        let bad = FIXTURE.replace("speed = ", "sped = ");
        assert!(toml::from_str::<File>(&bad).is_err());
        let double = FIXTURE.replace(
            "load = \"1500 N\"",
            "load = \"1500 N\"\napproach = \"1 mm\"",
        );
        let f: Result<File, _> = toml::from_str(&double);
        assert!(f.is_ok_and(|f| f.rolling.config().is_err()));
    }

    #[test]
    fn small_run_writes_outputs() -> Result<()> {
        let text = r#"
            start = "30 mm"
            end = "60 mm"
            step = "1 mm"
            speed = "50 km/h"
            threads = 1
            checkpoint = true
            [tread]
            kind = "tyre"
            radius_x = "0.3 m"
            radius_y = "0.5 m"
            length = "50 mm"
            width = "40 mm"
            [control]
            load = "50 N"
            [[sensor]]
            name = "centre"
            x0 = "40 mm"
            x1 = "50 mm"
            y0 = "-10 mm"
            y1 = "10 mm"
            [synthetic_road]
            length = "0.1 m"
            width = "0.05 m"
            density = 40000
        "#;
        let spec: RollingSpec = toml::from_str(text)?;
        let material = Material::new(6.54e6, 0.5)?;
        let out = std::env::temp_dir().join(format!("tyreroad-rolling-cmd-{}", std::process::id()));
        run_rolling::<&tyreroad_contact_law::HertzLaw>(material, None, &spec, &out)?;
        let ts = std::fs::read_to_string(out.join("time_signals.csv"))?;
        assert!(
            ts.starts_with("time_s,position_m,total_force_n,approach_m,contact_area_m2,n_contacts")
        );
        assert_eq!(ts.lines().count(), 32);
        let to = std::fs::read_to_string(out.join("third_octave.csv"))?;
        assert!(to.starts_with("band_centre_hz,level_db\n"));
        for f in [
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
        run_rolling::<&tyreroad_contact_law::HertzLaw>(material, None, &spec, &out)?;
        std::fs::remove_dir_all(&out)?;
        Ok(())
    }
}
