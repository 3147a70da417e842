//! A viscoelastic tread in a scenario (`[material.viscoelastic]`,
//! docs/viscoelastic.md): its Prony series, given directly or fitted to a
//! master-curve file, at a temperature through a WLF or Arrhenius shift; and
//! viscoelastic rolling runs of the `[rolling]` section, one or a sweep of
//! speeds and temperatures on one road.

use std::fmt;
use std::path::Path;

use serde::Deserialize;
use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_rolling as rolling;
use tyreroad_viscoelastic::{
    Branch, MAX_PER_DECADE, Prony, Receding, TemperatureShift, TrailingMemory, ViscoError,
    ViscoRollOptions, ViscoStart, roll_viscoelastic, roll_viscoelastic_coupled, significant,
};

use super::ranges::{MODULUS_RANGE, SPEED_RANGE, in_range};
use super::rolling::{RoadSummary, RollingRun, spectra};
use super::texture::{calibrated_texture_road_set_with, rolling_calibrator, texture_road_set};
use super::units::{Dimension, Pressure, Quantity};
use super::{RunOptions, Scenario, ScenarioError};
use crate::fidelity::rolling_fields::FieldRolling;
use crate::fidelity::{CalibratedLaw, Fidelity};
use crate::texture_road::{PastCapTally, PastShape, rolling_road};

/// The time dimension of relaxation times.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct RelaxationTimeDim;
impl Dimension for RelaxationTimeDim {
    const NAME: &'static str = "time";
    const UNITS: &'static [(&'static str, f64)] = &[
        ("s", 1.0),
        ("ms", 1e-3),
        ("us", 1e-6),
        ("µs", 1e-6),
        ("μs", 1e-6),
        ("ns", 1e-9),
        ("min", 60.0),
        ("h", 3600.0),
    ];
}
/// A relaxation time (s).
pub type RelaxationTime = Quantity<RelaxationTimeDim>;

/// Range (s) of a relaxation time `τ_k` written in a scenario: a picosecond
/// (faster than any rolling excitation) to about 30 000 years (slower than
/// any test); outside it a value is a unit slip, not rubber.
pub const RELAXATION_TIME_RANGE: [f64; 2] = [1e-12, 1e12];

/// Highest tread temperature a scenario or sweep takes (K).
pub const MAX_TEMPERATURE: f64 = 1000.0;

/// Range of the WLF constant `C1` (typical rubbers: 8 to 20).
pub const WLF_C1_RANGE: [f64; 2] = [0.0, 1e3];
/// Range (K) of the WLF constant `C2` (typical rubbers: 50 to 150 K).
pub const WLF_C2_RANGE: [f64; 2] = [0.0, 1e4];
/// Range (J/mol) of an Arrhenius activation energy (typical: 1e4 to 1e6).
pub const ACTIVATION_ENERGY_RANGE: [f64; 2] = [0.0, 1e8];

/// A temperature, held in kelvin: "20 °C", "20 degC", "293.15 K" or a bare
/// number (K).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Temperature(pub f64);

impl Temperature {
    /// Parses "20 °C", "20 C", "20 degC", "293.15 K" or "293.15".
    ///
    /// # Errors
    /// A message naming the text and the accepted units.
    pub fn parse(text: &str) -> Result<Self, String> {
        let t = text.trim();
        let (number, offset) = [("°C", 273.15), ("degC", 273.15), ("C", 273.15), ("K", 0.0)]
            .iter()
            .find_map(|&(unit, offset)| t.strip_suffix(unit).map(|n| (n.trim(), offset)))
            .unwrap_or((t, 0.0));
        let value: f64 = number.parse().map_err(|_| {
            format!(
                "`{text}` is not a temperature (expected \"20 °C\", \"20 degC\" or \"293.15 K\")"
            )
        })?;
        let kelvin = value + offset;
        if kelvin.is_finite() && kelvin > 0.0 {
            Ok(Self(kelvin))
        } else {
            Err(format!("`{text}` is not above absolute zero"))
        }
    }
}

impl<'de> Deserialize<'de> for Temperature {
    fn deserialize<D: serde::Deserializer<'de>>(deserializer: D) -> Result<Self, D::Error> {
        struct Visitor;
        impl serde::de::Visitor<'_> for Visitor {
            type Value = Temperature;
            fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
                write!(f, "a temperature (\"20 °C\", \"293.15 K\" or kelvin)")
            }
            fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<Temperature, E> {
                Temperature::parse(&v.to_string()).map_err(E::custom)
            }
            fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<Temperature, E> {
                self.visit_f64(v as f64)
            }
            fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<Temperature, E> {
                self.visit_f64(v as f64)
            }
            fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<Temperature, E> {
                Temperature::parse(v).map_err(E::custom)
            }
        }
        deserializer.deserialize_any(Visitor)
    }
}

/// `[material.viscoelastic]`: the tread's Prony series (docs/viscoelastic.md).
/// Either `long_term` with `[[material.viscoelastic.branch]]` entries, or a
/// `master_curve` CSV (frequency Hz, E' Pa, E'' Pa) to fit. The laws of the
/// road are built with `[material]`'s elastic modulus, which the
/// viscoelastic runs divide out; its Poisson's ratio is the tread's.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ViscoSpec {
    /// `E∞`, e.g. "2 MPa" (with `branch`).
    pub long_term: Option<Pressure>,
    /// The Maxwell branches (with `long_term`).
    #[serde(rename = "branch", default)]
    pub branches: Vec<BranchSpec>,
    /// A master-curve CSV, relative to the scenario's directory, fitted
    /// with `per_decade` relaxation times per decade (default 3).
    pub master_curve: Option<String>,
    /// Relaxation times per decade of the fit.
    pub per_decade: Option<usize>,
    /// The temperature shift of the series (measured at its reference).
    pub shift: Option<ShiftSpec>,
    /// The tread's temperature (default: the shift's reference).
    pub temperature: Option<Temperature>,
    /// `"fresh"` (default: the tread meets the road at the first step) or
    /// `"relaxed"` (it stood there long).
    pub start: Option<String>,
    /// In rolling, the memory of the asperities the footprint window has
    /// passed: `"lifts_off"` (default: the rubber leaves the road with its
    /// memory, as in the viscoelastic rolling BEM) or `"kept"` (Hunter's
    /// half-space attached to the road behind the footprint).
    pub trailing_memory: Option<String>,
    /// In rolling, a patch that shrinks while touching: `"ting"` (default:
    /// depth bands, 20 per decade) or `"lee_radok"` (the recursion on the
    /// whole force, which lifts a receding patch off early).
    pub receding: Option<String>,
}

/// `[[material.viscoelastic.branch]]`.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BranchSpec {
    /// `E_k`, e.g. "3 MPa".
    pub modulus: Pressure,
    /// `τ_k`, e.g. "1 ms".
    pub relaxation_time: RelaxationTime,
}

super::kind_tagged::deserialize_by_kind!(ShiftSpec);

/// `[material.viscoelastic.shift]`.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, remote = "Self")]
pub enum ShiftSpec {
    /// WLF: `log10 a_T = −C1 (T − T_ref)/(C2 + T − T_ref)`.
    Wlf {
        /// `C1`.
        c1: f64,
        /// `C2` (K), a temperature difference: a plain number or "101.6 K".
        #[serde(deserialize_with = "temperature_difference")]
        c2: f64,
        /// `T_ref`.
        reference: Temperature,
    },
    /// Arrhenius: `ln a_T = E_a/R (1/T − 1/T_ref)`.
    Arrhenius {
        /// `E_a` (J/mol).
        activation_energy: f64,
        /// `T_ref`.
        reference: Temperature,
    },
}

/// `C2` of a WLF shift: a temperature difference in kelvin, written as a
/// plain number or with its unit ("101.6 K"; a difference in °C is the same
/// number, but "°C" reads as a temperature and is refused).
fn temperature_difference<'de, D: serde::Deserializer<'de>>(d: D) -> Result<f64, D::Error> {
    struct Visitor;
    impl serde::de::Visitor<'_> for Visitor {
        type Value = f64;
        fn expecting(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
            write!(
                f,
                "`c2`, a temperature difference: a plain number (K) or \"101.6 K\""
            )
        }
        fn visit_f64<E: serde::de::Error>(self, v: f64) -> Result<f64, E> {
            Ok(v)
        }
        fn visit_i64<E: serde::de::Error>(self, v: i64) -> Result<f64, E> {
            Ok(v as f64)
        }
        fn visit_u64<E: serde::de::Error>(self, v: u64) -> Result<f64, E> {
            Ok(v as f64)
        }
        fn visit_str<E: serde::de::Error>(self, v: &str) -> Result<f64, E> {
            v.trim()
                .strip_suffix('K')
                .and_then(|n| n.trim().parse().ok())
                .ok_or_else(|| {
                    E::custom(format!(
                        "`c2` = \"{v}\": expected a temperature difference, a plain number \
                         (K) or \"101.6 K\""
                    ))
                })
        }
    }
    d.deserialize_any(Visitor)
}

pub(super) fn visco_error(key: &str) -> impl Fn(ViscoError) -> ScenarioError + '_ {
    move |e| ScenarioError::Invalid(format!("[material.viscoelastic] {key}: {e}"))
}

impl ViscoSpec {
    /// Every value against the range where it means something (called when
    /// the scenario is read, so the error names the file and the key): the
    /// moduli in [`MODULUS_RANGE`] as `[material] youngs_modulus`, the
    /// relaxation times in [`RELAXATION_TIME_RANGE`], `per_decade` in
    /// `1..=`[`MAX_PER_DECADE`], the shift's constants in their ranges and
    /// the temperature where the shift is defined.
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming the key, its value and the range.
    pub(super) fn check(&self) -> Result<(), ScenarioError> {
        const SECTION: &str = "[material.viscoelastic]";
        if let Some(e) = self.long_term {
            let key = format!("{SECTION} long_term");
            in_range(&key, e.value(), MODULUS_RANGE, false, "Pa")?;
        }
        for (k, b) in self.branches.iter().enumerate() {
            let key = |field: &str| format!("[[material.viscoelastic.branch]] #{} {field}", k + 1);
            in_range(
                &key("modulus"),
                b.modulus.value(),
                MODULUS_RANGE,
                false,
                "Pa",
            )?;
            let tau = b.relaxation_time.value();
            in_range(
                &key("relaxation_time"),
                tau,
                RELAXATION_TIME_RANGE,
                false,
                "s",
            )?;
        }
        if let Some(n) = self.per_decade
            && !(1..=MAX_PER_DECADE).contains(&n)
        {
            return Err(ScenarioError::Value {
                key: format!("{SECTION} per_decade"),
                value: n.to_string(),
                expected: format!(
                    "1 to {MAX_PER_DECADE} (a Prony fit with more than a few relaxation times \
                     per decade is ill-conditioned)"
                ),
            });
        }
        match self.shift {
            Some(ShiftSpec::Wlf { c1, c2, .. }) => {
                in_range(&format!("{SECTION}.shift c1"), c1, WLF_C1_RANGE, true, "")?;
                in_range(&format!("{SECTION}.shift c2"), c2, WLF_C2_RANGE, true, "K")?;
            }
            Some(ShiftSpec::Arrhenius {
                activation_energy, ..
            }) => in_range(
                &format!("{SECTION}.shift activation_energy"),
                activation_energy,
                ACTIVATION_ENERGY_RANGE,
                true,
                "J/mol",
            )?,
            None => {}
        }
        if let Some(t) = self.temperature {
            let key = format!("{SECTION} temperature");
            let kelvin = format!("{} K", significant(t.0));
            if !(t.0 > 0.0 && t.0 <= MAX_TEMPERATURE) {
                return Err(ScenarioError::Value {
                    key,
                    value: kelvin,
                    expected: format!(
                        "a temperature above absolute zero and at most {MAX_TEMPERATURE} K (no \
                         rubber tread outlives a few hundred degrees Celsius)"
                    ),
                });
            }
            let Some(shift) = self.shift() else {
                return Err(ScenarioError::Value {
                    key,
                    value: kelvin,
                    expected: "a [material.viscoelastic.shift] to move the series to it".into(),
                });
            };
            if shift.factor(t.0).is_err() {
                let expected = match shift {
                    TemperatureShift::Wlf { c2, reference, .. } if t.0 <= reference - c2 => {
                        format!(
                            "a temperature above the WLF pole T_ref − C2 = {} K ({} °C)",
                            significant(reference - c2),
                            significant(reference - c2 - 273.15)
                        )
                    }
                    TemperatureShift::Wlf { .. } => {
                        "a temperature where the WLF shift factor a_T is a finite number > 0 \
                         (there C1 makes it over- or underflow: closer to T_ref, or a smaller C1)"
                            .into()
                    }
                    _ => "a temperature where the Arrhenius shift factor is finite and > 0".into(),
                };
                return Err(ScenarioError::Value {
                    key,
                    value: kelvin,
                    expected,
                });
            }
        }
        Ok(())
    }

    /// The Prony series at the reference temperature.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] naming the key: both or neither of the
    /// series and `master_curve`, a value out of range, an unreadable or
    /// malformed curve, a fit that fails.
    pub fn series(&self, poisson_ratio: f64, base_dir: &Path) -> Result<Prony, ScenarioError> {
        self.fitted(poisson_ratio, base_dir)
            .map(|(series, _)| series)
    }

    /// [`Self::series`], and what a run should say of its master curve
    /// (`visco_curve::fit`).
    pub(super) fn fitted(
        &self,
        poisson_ratio: f64,
        base_dir: &Path,
    ) -> Result<(Prony, Option<String>), ScenarioError> {
        match (&self.master_curve, self.long_term) {
            (Some(file), None) if self.branches.is_empty() => {
                super::visco_curve::fit(file, base_dir, self.per_decade, poisson_ratio)
            }
            (None, Some(_)) if self.branches.is_empty() => Err(ScenarioError::Invalid(
                "[material.viscoelastic]: long_term without any [[material.viscoelastic.branch]] \
                 is an elastic tread: give its branches, or drop the section and keep \
                 [material] youngs_modulus"
                    .into(),
            )),
            (None, Some(long_term)) => {
                let branches = self
                    .branches
                    .iter()
                    .map(|b| Branch {
                        modulus: b.modulus.value(),
                        relaxation_time: b.relaxation_time.value(),
                    })
                    .collect();
                Prony::new(long_term.value(), branches, poisson_ratio)
                    .map(|series| (series, None))
                    .map_err(visco_error("long_term, branch"))
            }
            _ => Err(ScenarioError::Invalid(
                "[material.viscoelastic]: give either long_term with [[material.viscoelastic.branch]] \
                 entries, or master_curve"
                    .into(),
            )),
        }
    }

    /// The time–temperature shift, if any.
    pub fn shift(&self) -> Option<TemperatureShift> {
        self.shift.as_ref().map(|s| match *s {
            ShiftSpec::Wlf { c1, c2, reference } => TemperatureShift::Wlf {
                c1,
                c2,
                reference: reference.0,
            },
            ShiftSpec::Arrhenius {
                activation_energy,
                reference,
            } => TemperatureShift::Arrhenius {
                activation_energy,
                reference: reference.0,
            },
        })
    }

    /// The series at `temperature` (K; `None`: the spec's own temperature,
    /// else the reference).
    ///
    /// # Errors
    /// As [`ViscoSpec::series`]; a temperature without a `shift`, or one the
    /// shift refuses.
    pub fn at(&self, series: &Prony, temperature: Option<f64>) -> Result<Prony, ScenarioError> {
        let Some(t) = temperature.or(self.temperature.map(|t| t.0)) else {
            return Ok(series.clone());
        };
        let shift = self.shift().ok_or_else(|| {
            ScenarioError::Invalid(
                "[material.viscoelastic]: a temperature needs [material.viscoelastic.shift]".into(),
            )
        })?;
        let factor = shift.factor(t).map_err(visco_error("temperature"))?;
        series.shifted(factor).map_err(visco_error("temperature"))
    }

    fn start(&self) -> Result<ViscoStart, ScenarioError> {
        match self.start.as_deref() {
            None | Some("fresh") => Ok(ViscoStart::Fresh),
            Some("relaxed") => Ok(ViscoStart::Relaxed),
            Some(other) => Err(ScenarioError::Value {
                key: "[material.viscoelastic] start".into(),
                value: format!("{other:?}"),
                expected: "\"fresh\" or \"relaxed\"".into(),
            }),
        }
    }

    fn receding(&self) -> Result<Receding, ScenarioError> {
        match self.receding.as_deref() {
            Some("lee_radok") => Ok(Receding::LeeRadok),
            None | Some("ting") => Ok(Receding::default()),
            Some(other) => Err(ScenarioError::Value {
                key: "[material.viscoelastic] receding".into(),
                value: format!("{other:?}"),
                expected: "\"lee_radok\" or \"ting\"".into(),
            }),
        }
    }

    fn trailing(&self) -> Result<TrailingMemory, ScenarioError> {
        match self.trailing_memory.as_deref() {
            None | Some("lifts_off") => Ok(TrailingMemory::LiftsOff),
            Some("kept") => Ok(TrailingMemory::Kept),
            Some(other) => Err(ScenarioError::Value {
                key: "[material.viscoelastic] trailing_memory".into(),
                value: format!("{other:?}"),
                expected: "\"lifts_off\" or \"kept\"".into(),
            }),
        }
    }
}

/// One viscoelastic rolling run of a sweep: the `[rolling]` section with
/// its speed and the tread's temperature replaced where given.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct ViscoCase {
    /// Speed (m/s); `None`: `[rolling] speed`.
    pub speed: Option<f64>,
    /// Tread temperature (K); `None`: `[material.viscoelastic] temperature`.
    pub temperature: Option<f64>,
}

impl ViscoCase {
    /// Range (m/s) of `[rolling] speed`, which a command-line sweep keeps
    /// to. A case of the library may go beyond it (1e-6 or 1e6 m/s are the
    /// relaxed and glassy limits the tests roll at), not below zero.
    pub const SPEED_RANGE: [f64; 2] = SPEED_RANGE;

    /// The case's speed finite and > 0 and its temperature finite and above
    /// absolute zero.
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming the case's speed or temperature.
    pub fn check(&self) -> Result<(), ScenarioError> {
        if let Some(v) = self.speed
            && !(v.is_finite() && v > 0.0)
        {
            return Err(ScenarioError::Value {
                key: "sweep speed".into(),
                value: format!("{} m/s", significant(v)),
                expected: "a finite speed > 0".into(),
            });
        }
        if let Some(t) = self.temperature
            && !(t > 0.0 && t <= MAX_TEMPERATURE)
        {
            return Err(ScenarioError::Value {
                key: "sweep temperature".into(),
                value: format!("{} K", significant(t)),
                expected: format!(
                    "a temperature above absolute zero and at most {MAX_TEMPERATURE} K"
                ),
            });
        }
        Ok(())
    }
}

impl Scenario {
    /// The tread's Prony series at its temperature, when `[material]` has a
    /// `[material.viscoelastic]` section.
    ///
    /// # Errors
    /// As [`ViscoSpec::series`] and [`ViscoSpec::at`].
    pub fn viscoelastic_material(&self, base_dir: &Path) -> Result<Option<Prony>, ScenarioError> {
        Ok(self
            .viscoelastic_material_noted(base_dir)?
            .map(|(series, _)| series))
    }

    /// `error` starting with the scenario's origin (its file), as the errors
    /// of [`Scenario::parse`] do.
    pub(super) fn located(&self, error: ScenarioError) -> ScenarioError {
        if self.origin.is_empty() {
            return error;
        }
        match error {
            ScenarioError::Value {
                key,
                value,
                expected,
            } => ScenarioError::Value {
                key: format!("{}: {key}", self.origin),
                value,
                expected,
            },
            ScenarioError::Invalid(what) => {
                ScenarioError::Invalid(format!("scenario {}: {what}", self.origin))
            }
            other => other,
        }
    }

    /// Viscoelastic rolling runs of the `[rolling]` section on the
    /// scenario's road (built once), one per case; one case that fails is
    /// its own error, not the others'. Each run is sequential along its path
    /// (docs/viscoelastic.md, "Rolling"); `options.par` is not used.
    ///
    /// # Errors
    /// The whole call fails for no `[rolling]` or `[material.viscoelastic]`
    /// section, an invalid series or road.
    pub fn roll_viscoelastic(
        &self,
        options: &RunOptions<'_>,
        cases: &[ViscoCase],
    ) -> Result<Vec<Result<RollingRun, ScenarioError>>, ScenarioError> {
        let spec = self.rolling_section()?;
        let visco = self.material.viscoelastic.as_ref().ok_or_else(|| {
            self.located(ScenarioError::Invalid(
                "the scenario's [material] has no viscoelastic section".into(),
            ))
        })?;
        let (series, curve_warning) = visco
            .fitted(self.material.poisson_ratio, &options.base_dir)
            .map_err(|e| self.located(e))?;
        let material = self.material()?;
        let sweep = Sweep {
            scenario: self,
            visco,
            curve_warning: curve_warning.as_deref(),
            series: &series,
            material,
            options,
            cases,
        };
        if let Some(texture) = &self.texture {
            let fidelity = self.fidelity()?;
            if matches!(fidelity, Fidelity::Calibrated | Fidelity::CalibratedFields) {
                // Each cap's hereditary law takes the shape of its calibrated
                // elastic law (linear in the modulus, so the law per unit
                // modulus is F_cal(δ)/E_ref). The tables are built with E∞:
                // the softest tread sinks deepest, so the approach bound that
                // sizes them covers every speed and temperature. With
                // fields, the tables keep their binned pressures and every
                // step is coupled through them (a compliance correction
                // for E∞ that the hereditary step scales to its E_eff).
                let reference = series
                    .elastic(series.long_term())
                    .map_err(visco_error("long_term"))?;
                let config = self.rolling_config()?;
                let par = options.rolling_par(spec);
                let fields = fidelity == Fidelity::CalibratedFields;
                let under = self.model.calibrate_under()?;
                // The hereditary step solves each road law as it is: laws
                // along the path would stay at the footprint's centre.
                if under == crate::fidelity::under_tread::CalibrateUnder::TreadSlope {
                    return Err(ScenarioError::Invalid(
                        "[model] calibrate_under \"tread_slope\" is elastic only: use \"flat\" \
                         or \"tread\" on a viscoelastic tread"
                            .into(),
                    ));
                }
                let (set, summary, radii) = calibrated_texture_road_set_with(
                    texture,
                    &options.base_dir,
                    &config,
                    par,
                    &rolling_calibrator(reference, None, fields),
                    &crate::fidelity::table_depth::TablePlan::bound(under),
                )?;
                let road = rolling_road(set, radii, summary.top)?;
                let sweep = Sweep {
                    material: reference,
                    ..sweep
                };
                let coupling = if fields {
                    Some(FieldRolling::with_defaults(&reference)?)
                } else {
                    None
                };
                let coupling = coupling
                    .as_ref()
                    .map(|c| c as &dyn rolling::StepCoupling<CalibratedLaw>);
                return Ok(sweep.on(&road, RoadSummary::Texture(Box::new(summary)), coupling));
            }
            let (set, summary, radii) = texture_road_set(
                texture,
                &options.base_dir,
                material,
                options.rolling_par(spec),
            )?;
            // Gaps at each cap's contact point, as the elastic run takes them.
            let road = rolling_road(set, radii, summary.top)?;
            let mut runs = sweep.on(&road, RoadSummary::Texture(Box::new(summary)), None);
            sweep.warn_of_past_bounds(&mut runs, |stiffening| {
                PastCapTally::new(&road, stiffening, PastShape::Caps)
            });
            return Ok(runs);
        }
        match (self.asperities.is_empty(), &spec.synthetic_road) {
            (false, None) => {
                let set = self.asperity_set()?;
                let count = set.len();
                let balls = self.ball_radii();
                let road = rolling::Road::new(set);
                let mut runs = sweep.on(
                    &road,
                    RoadSummary::Asperities {
                        count,
                        warnings: self.steep_cone_warning().into_iter().collect(),
                    },
                    None,
                );
                sweep.warn_of_past_bounds(&mut runs, |stiffening| {
                    PastCapTally::at_equators(&balls, road.laws(), stiffening)
                });
                Ok(runs)
            }
            (true, Some(synth)) => {
                let road = synth.road().sphere_road(material)?;
                let count = road.len();
                let mut runs = sweep.on(
                    &road,
                    RoadSummary::Synthetic {
                        count,
                        warnings: Vec::new(),
                    },
                    None,
                );
                sweep.warn_of_past_bounds(&mut runs, |stiffening| {
                    PastCapTally::new(&road, stiffening, PastShape::Equators)
                });
                Ok(runs)
            }
            _ => Err(ScenarioError::Invalid(
                "no road, or two: give [[asperity]] entries or [rolling.synthetic_road]".into(),
            )),
        }
    }
}

struct Sweep<'a> {
    scenario: &'a Scenario,
    visco: &'a ViscoSpec,
    /// What every run says of the master curve (`ViscoSpec::fitted`).
    curve_warning: Option<&'a str>,
    series: &'a Prony,
    material: Material,
    options: &'a RunOptions<'a>,
    cases: &'a [ViscoCase],
}

impl Sweep<'_> {
    /// Each case's contacts pressed past their laws' bounds (caps,
    /// equators), counted on `tally(stiffening)` and warned of in its road
    /// summary. The laws are at `[material]`'s modulus and the tread at
    /// most its instantaneous modulus stiffer: `stiffening = E₀/E`
    /// (docs/viscoelastic.md). A case whose series does not shift to its
    /// temperature failed in its run already.
    fn warn_of_past_bounds(
        &self,
        runs: &mut [Result<RollingRun, ScenarioError>],
        tally: impl Fn(f64) -> PastCapTally,
    ) {
        for (run, case) in runs.iter_mut().zip(self.cases) {
            if let Ok(run) = run
                && let Ok(tread) = self.visco.at(self.series, case.temperature)
            {
                let stiffening = tread.instantaneous() / self.material.youngs_modulus();
                let warning = tally(stiffening).warning_over(&run.result.steps);
                run.road.warnings_mut().extend(warning);
            }
        }
    }

    /// One run per case on `road`, each step coupled by `coupling` when
    /// given.
    fn on<L: ContactLaw + Sync>(
        &self,
        road: &rolling::Road<L>,
        mut summary: RoadSummary,
        coupling: Option<&dyn rolling::StepCoupling<L>>,
    ) -> Vec<Result<RollingRun, ScenarioError>> {
        summary
            .warnings_mut()
            .extend(self.curve_warning.map(str::to_string));
        // A path the scenario cannot give fails in each case's run.
        if let (Ok(config), Some(spec)) = (self.scenario.rolling_config(), &self.scenario.rolling) {
            // The softest the tread gets: its long-term modulus.
            let modulus = self.series.long_term();
            summary.warn_of_path(&config, spec.synthetic_road.as_ref(), modulus);
        }
        self.cases
            .iter()
            .map(|case| {
                self.one((road, coupling), summary.clone(), case)
                    .map_err(|e| self.scenario.located(e))
            })
            .collect()
    }

    fn one<L: ContactLaw + Sync>(
        &self,
        (road, coupling): (&rolling::Road<L>, Option<&dyn rolling::StepCoupling<L>>),
        summary: RoadSummary,
        case: &ViscoCase,
    ) -> Result<RollingRun, ScenarioError> {
        case.check()?;
        let spec = self.scenario.rolling_section()?;
        let mut config = self.scenario.rolling_config()?;
        if let Some(speed) = case.speed {
            config.speed = speed;
        }
        let tread = self.visco.at(self.series, case.temperature)?;
        let options = ViscoRollOptions {
            start: self.visco.start()?,
            trailing: self.visco.trailing()?,
            receding: self.visco.receding()?,
            progress: self.options.progress,
            ..ViscoRollOptions::default()
        };
        let run = match coupling {
            None => roll_viscoelastic(road, self.material, &tread, &config, &options),
            Some(c) => roll_viscoelastic_coupled(road, self.material, &tread, &config, &options, c),
        }
        .map_err(|e| match e {
            ViscoError::Rolling { source } => ScenarioError::Rolling(source),
            other => ScenarioError::Invalid(format!("viscoelastic rolling: {other}")),
        })?;
        // The spectra are those of steady rolling: the first footprint
        // length, which still holds the start's loading, is left out (the
        // time signals keep every step).
        let mut steady = run.result.clone();
        if run.transient_steps + 8 < steady.steps.len() {
            steady.steps.drain(..run.transient_steps);
        }
        let spectra = spectra(&config, spec, &steady)?;
        Ok(RollingRun {
            road: summary,
            road_positions: road.positions().to_vec(),
            road_heights: road.heights().to_vec(),
            config,
            result: run.result,
            spectra,
        })
    }
}

#[cfg(test)]
#[path = "visco_tests.rs"]
mod tests;
