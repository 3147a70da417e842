//! The `[rolling]` section of a scenario file (docs/rolling.md).

use serde::Deserialize;
use tyreroad_rolling as rolling;

use super::ScenarioError;
use super::units::{Force, Length, Speed};

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
    /// Where the tread touches each cap: `"profile"` (default: the
    /// undeformed profile's slope) or `"deformed"` (the profile's slope
    /// plus the other contacts' displacement slope; elastic treads only).
    pub contact_slope: Option<ContactSlopeSpec>,
    /// Welch segment length in samples (default: half the signal).
    pub segment: Option<usize>,
    /// How the sensors count each contact's force: `"run"` (default: as
    /// the run spreads it, its law's disc or its calibrated field) or
    /// `"caps"` (on its own cap, by a BEM solve of the cap under the tread
    /// at that step; an elastic tread on a `[texture]` read whole;
    /// docs/rolling.md, "Sensors counted on the caps").
    pub sensor_accounting: Option<SensorAccountingSpec>,
    /// A synthetic road of random spheres instead of the scenario's
    /// asperities.
    pub synthetic_road: Option<SyntheticRoadSpec>,
}

fn yes() -> bool {
    true
}

/// `[rolling] contact_slope`.
#[derive(Clone, Copy, Debug, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum ContactSlopeSpec {
    /// [`rolling::ContactSlope::Deformed`].
    Deformed,
    /// [`rolling::ContactSlope::Profile`].
    Profile,
}

/// `[rolling] sensor_accounting`.
#[derive(Clone, Copy, Debug, Default, Deserialize, PartialEq, Eq)]
#[serde(rename_all = "snake_case")]
pub enum SensorAccountingSpec {
    /// The run's own spread of each contact (its law's disc, or its
    /// calibrated field in the `calibrated_fields` rung).
    #[default]
    Run,
    /// Each contact's force placed by a BEM solve of its own cap under the
    /// tread (`crate::fidelity::cap_sensors`).
    Caps,
}

super::kind_tagged::deserialize_by_kind!(TreadSpec);

/// `[rolling.tread]`
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, remote = "Self")]
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
    /// Approach below the road's reference plane (fixed axle height): its
    /// highest summit, or a texture's highest point.
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
    /// Whether the sensors are recounted on the caps (`sensor_accounting
    /// = "caps"`).
    pub(super) fn sensors_on_caps(&self) -> bool {
        self.sensor_accounting == Some(SensorAccountingSpec::Caps)
    }

    /// The library configuration.
    pub fn config(&self) -> Result<rolling::RollingConfig, ScenarioError> {
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
            _ => {
                return Err(ScenarioError::Invalid(
                    "[rolling.control] needs exactly one of load, approach, tread_height".into(),
                ));
            }
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
        config.contact_slope = match self.contact_slope {
            Some(ContactSlopeSpec::Profile) | None => rolling::ContactSlope::Profile,
            Some(ContactSlopeSpec::Deformed) => rolling::ContactSlope::Deformed,
        };
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

/// The warning a rolling run on `config` is given before its first step
/// when its imposed approach is deeper than the tread's profile at the
/// edge of its selection window (`RollingConfig::approach_past_window`):
/// the contact then runs past the window at every step, and steps pressed
/// far past the road's shapes can take minutes. `None` otherwise.
pub fn approach_past_window_warning(config: &rolling::RollingConfig) -> Option<String> {
    config.approach_past_window().map(|(approach, boundary)| {
        format!(
            "the imposed approach ({:.3} mm) is deeper than the tread's profile at the edge \
             of its selection window ({:.3} mm): the contact runs past the window at every \
             step, whose answer is then no tread's, and steps pressed far past the road's \
             shapes can take long (a smaller approach, a longer footprint or a wider margin)",
            approach * 1e3,
            boundary * 1e3
        )
    })
}

/// The warning a rolling run is given when, at some step, its approach
/// passed the tread's profile at the edge of the selection window
/// (`min_clearance` ≤ 0, m: `RollingResult::min_clearance`): contacts
/// beyond the window were then left out. `None` otherwise.
pub fn clearance_warning(min_clearance: f64) -> Option<String> {
    (min_clearance <= 0.0).then(|| {
        format!(
            "at some steps the approach exceeds the tread profile at the selection \
             boundary (clearance {min_clearance:.3e} m): widen the footprint or the margin"
        )
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;
    use crate::scenario::Scenario;

    const FIXTURE: &str = include_str!("../../fixtures/rolling_tyre_dense_asphalt.toml");

    #[derive(Deserialize)]
    struct File {
        rolling: RollingSpec,
        #[allow(dead_code)]
        #[serde(flatten)]
        rest: toml::Table,
    }

    #[test]
    fn fixture_parses_with_units() -> Result<(), Box<dyn std::error::Error>> {
        let f: File = toml::from_str(FIXTURE)?;
        let c = f.rolling.config()?;
        assert!((c.speed - 50.0 / 3.6).abs() < 1e-12);
        assert!((c.step - 1e-3).abs() < 1e-15);
        assert!(matches!(c.tread, rolling::Tread::Tyre { .. }));
        // The road is the synthetic dense asphalt texture.
        assert!(f.rolling.synthetic_road.is_none());
        let s = Scenario::parse(FIXTURE, "fixture")?;
        let t = s.texture.as_ref().expect("[texture]");
        assert!(t.synth.is_some() && t.file.is_none());
        Ok(())
    }

    #[test]
    fn texture_and_synthetic_road_together_are_refused() {
        let both = format!("{FIXTURE}\n[rolling.synthetic_road]\nseed = 1\n");
        let e = Scenario::parse(&both, "both").expect_err("two roads");
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
    fn contact_slope_defaults_to_the_profile_and_names_its_values() {
        let with =
            |v: &str| FIXTURE.replace("[rolling]\n", &format!("[rolling]\ncontact_slope = {v}\n"));
        let slope = |text: &str| -> Result<rolling::ContactSlope, Box<dyn std::error::Error>> {
            Ok(Scenario::parse(text, "t")?.rolling_config()?.contact_slope)
        };
        assert_eq!(slope(FIXTURE).ok(), Some(rolling::ContactSlope::Profile));
        assert_eq!(
            slope(&with("\"deformed\"")).ok(),
            Some(rolling::ContactSlope::Deformed)
        );
        assert_eq!(
            slope(&with("\"profile\"")).ok(),
            Some(rolling::ContactSlope::Profile)
        );
        let e = Scenario::parse(&with("\"flat\""), "t").expect_err("unknown value");
        assert!(e.to_string().contains("deformed"), "{e}");
        // A viscoelastic tread has no deformed slope: asking for it is refused.
        let visco = format!(
            "{}\n[material.viscoelastic]\nlong_term = \"6.54 MPa\"\n[[material.viscoelastic.branch]]\nmodulus = \"10 MPa\"\nrelaxation_time = \"1 ms\"\n",
            with("\"deformed\"")
        );
        let e = Scenario::parse(&visco, "t")
            .and_then(|s| s.rolling_config())
            .expect_err("deformed on a viscoelastic tread");
        assert!(e.to_string().contains("contact_slope"), "{e}");
    }
}
