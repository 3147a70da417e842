//! Scenario files: TOML, units written out ("5 mm"), unknown keys refused
//! with their name and line.

use std::path::Path;

use serde::Deserialize;
use tyreroad_asperity::{Cone, EllipticParaboloid, Sphere};
use tyreroad_contact_law::{C_CONE, C_SPHERE, ContactLaw, LocalRule, Material, PotentialLaw};
use tyreroad_multipoint::{AsperitySet, Par, Problem, SolverOptions};
use tyreroad_texture::{Aggregate, ChipShape, HeightMap, SelfAffine, roads};

use super::ScenarioError;
use super::rolling_spec::RollingSpec;
use super::units::{Angle, Area, Force, Length, Pressure};
use crate::fidelity::Fidelity;
use crate::fidelity::under_tread::CalibrateUnder;
use crate::texture_road::TextureRoadOptions;

type Result<T, E = ScenarioError> = std::result::Result<T, E>;

/// A law usable in a mixed set of asperities.
pub type DynLaw = Box<dyn ContactLaw + Send + Sync>;

/// A scenario: a tread material, asperities, and what to solve.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name, used for output file names.
    pub name: String,
    /// One line for reports.
    #[serde(default)]
    pub description: String,
    /// The elastic half-space.
    pub material: MaterialSpec,
    /// Solver tuning.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Shape of every asperity that does not give its own.
    pub default_shape: Option<ShapeSpec>,
    /// A static contact at one or more loads.
    #[serde(rename = "static")]
    pub static_case: Option<StaticSpec>,
    /// A rolling run along a path (docs/rolling.md).
    pub rolling: Option<RollingSpec>,
    /// The asperities.
    #[serde(rename = "asperity", default)]
    pub asperities: Vec<AsperitySpec>,
    /// A road texture whose asperities replace the `[[asperity]]` list.
    pub texture: Option<TextureSpec>,
    /// `[model]`: which rung of the fidelity ladder runs.
    #[serde(default)]
    pub model: ModelSpec,
    /// Where the scenario was read from (the `origin` of
    /// [`Scenario::parse`]: a path or a label), which starts the run-time
    /// errors of its viscoelastic tread; not a key of the file.
    #[serde(skip)]
    pub origin: String,
}

/// `[model]`: the model's fidelity (`crate::fidelity`).
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ModelSpec {
    /// A rung of `crate::fidelity::RUNGS` by name: `"wilke"`,
    /// `"calibrated"`, `"distributed"`, `"clustered"` or
    /// `"calibrated_fields"`; when not given, the run's kind chooses
    /// ([`Scenario::default_fidelity`]).
    pub fidelity: Option<String>,
    /// What a rolling run's caps are calibrated under: `"flat"` (default,
    /// a flat punch), `"tread"` (the tread's local shape at each cap's
    /// lateral position, `crate::fidelity::under_tread`) or `"tread_slope"`
    /// (also at offsets along the path); for `calibrated` and
    /// `calibrated_fields` in a `[rolling]` run on a `[texture]`.
    pub calibrate_under: Option<String>,
}

impl ModelSpec {
    /// The rung asked for, `None` when not given (the run's kind then
    /// chooses, [`Scenario::fidelity`]).
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming `[model] fidelity` for an unknown name.
    pub fn fidelity(&self) -> Result<Option<Fidelity>> {
        self.fidelity
            .as_ref()
            .map(|name| {
                name.parse().map_err(|_| ScenarioError::Value {
                    key: "[model] fidelity".into(),
                    value: format!("{name:?}"),
                    expected: crate::fidelity::one_of(crate::fidelity::RUNGS.map(Fidelity::name)),
                })
            })
            .transpose()
    }

    /// What caps are calibrated under, [`CalibrateUnder::Flat`] when not
    /// given.
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming `[model] calibrate_under` for an
    /// unknown name.
    pub fn calibrate_under(&self) -> Result<CalibrateUnder> {
        match &self.calibrate_under {
            None => Ok(CalibrateUnder::Flat),
            Some(name) => name.parse().map_err(|_| ScenarioError::Value {
                key: "[model] calibrate_under".into(),
                value: format!("{name:?}"),
                expected: crate::fidelity::one_of(CalibrateUnder::ALL.map(CalibrateUnder::name)),
            }),
        }
    }
}

/// `[texture]`: a height map, read (`file`) or synthesised (`[texture.synth]`),
/// and how it is split into asperities.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct TextureSpec {
    /// A height-map file (X3P, ASCII grid, xyz, `.sur`), relative to the
    /// scenario file's directory.
    pub file: Option<String>,
    /// A synthetic surface.
    pub synth: Option<SynthSpec>,
    /// Smallest prominence of an asperity (summit − key saddle), e.g. "0.2 mm".
    pub min_prominence: Length,
    /// Smallest basin area of an asperity, e.g. "2 mm2".
    pub min_area: Area,
    /// Shape constant c of the potential law (default 0.36).
    pub constant: Option<f64>,
    /// Split basins whose top is wider than this into tiles no wider, one
    /// asperity each, e.g. "8 mm" (`tyreroad_texture::split_wide_tops`;
    /// absent: basins kept whole).
    pub max_cap_width: Option<Length>,
}

/// The grid and seed of a hard road kind (`tyreroad_texture::roads`, with
/// that kind's documented defaults for everything else).
#[derive(Debug, Clone, Copy, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RoadKindSpec {
    /// Points along x.
    pub nx: usize,
    /// Points along y.
    pub ny: usize,
    /// Grid spacing (both directions).
    pub spacing: Length,
    /// Generator seed.
    pub seed: u64,
}

super::kind_tagged::deserialize_by_kind!(SynthSpec, ShapeSpec);

/// `[texture.synth]`: the generator, its grid and seed.
#[derive(Debug, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, remote = "Self")]
pub enum SynthSpec {
    /// Transverse tining: 3 mm grooves, 4 mm deep, at 12.5 mm, on mortar.
    TransverseTining(RoadKindSpec),
    /// Longitudinal tining (grooves along x), same defaults.
    LongitudinalTining(RoadKindSpec),
    /// Brushed concrete: fine transverse striations.
    BrushedConcrete(RoadKindSpec),
    /// Exposed-aggregate concrete.
    ExposedAggregate(RoadKindSpec),
    /// Porous (open-graded) asphalt: plateaus and deep pores.
    PorousAsphalt(RoadKindSpec),
    /// Worn chip seal: 6/10 chippings ground flat.
    WornChipSeal(RoadKindSpec),
    /// Pavé: setts with joints.
    Pave(RoadKindSpec),
    /// Chippings on a base plane (`tyreroad_texture::Aggregate::new`).
    Aggregate {
        /// Points along x.
        nx: usize,
        /// Points along y.
        ny: usize,
        /// Grid spacing (both directions).
        spacing: Length,
        /// Grading: "4/6" (4/6.3 mm) or "6/10".
        grading: String,
        /// Chipping shape: "ellipsoid" (default) or "polyhedron".
        shape: Option<String>,
        /// Summed plan area of the chippings over the map area (default 1.3).
        coverage: Option<f64>,
        /// Range `[min, max]` of the embedded fraction of each chipping's
        /// height (default `[0.3, 0.5]`, a surface dressing; a dense asphalt
        /// holds its chippings deeper in the mortar).
        embedding: Option<[f64; 2]>,
        /// Generator seed.
        seed: u64,
    },
    /// A self-affine Gaussian surface (`tyreroad_texture::SelfAffine`).
    SelfAffine {
        /// Points along x.
        nx: usize,
        /// Points along y.
        ny: usize,
        /// Grid spacing (both directions).
        spacing: Length,
        /// Sq.
        rms: Length,
        /// Hurst exponent H.
        hurst: f64,
        /// Roll-off wavelength.
        lambda_long: Length,
        /// Cut-off wavelength.
        lambda_short: Length,
        /// Generator seed.
        seed: u64,
    },
}

impl TextureSpec {
    /// The height map: `file` read relative to `base_dir`, or synthesised.
    /// A file's "no data" markers written as heights (−9999, 1e30:
    /// [`tyreroad_texture::find_sentinels`]) are read as missing points.
    pub fn height_map(&self, base_dir: &Path) -> Result<HeightMap> {
        self.height_map_and_notes(base_dir).map(|(map, _)| map)
    }

    /// [`TextureSpec::height_map`], and what reading it changed that a
    /// run's user should be told (the markers read as missing points).
    pub fn height_map_and_notes(&self, base_dir: &Path) -> Result<(HeightMap, Vec<String>)> {
        match (&self.file, &self.synth) {
            (Some(file), None) => {
                let path = base_dir.join(file);
                let texture_error = |source| ScenarioError::Texture {
                    context: format!("[texture] reading {}", path.display()),
                    source,
                };
                let map = tyreroad_texture::read_any(&path).map_err(texture_error)?;
                super::ranges::texture_file_spacing(&path, map.dx(), map.dy())?;
                super::height_checks::markers_as_missing(map).map_err(texture_error)
            }
            (None, Some(synth)) => synth.height_map().map(|map| (map, Vec::new())),
            (Some(_), Some(_)) => Err(ScenarioError::Invalid(
                "[texture]: give `file` or [texture.synth], not both".into(),
            )),
            (None, None) => Err(ScenarioError::Invalid(
                "[texture]: give `file` or [texture.synth]".into(),
            )),
        }
    }

    /// Segmentation thresholds and law constant.
    pub fn road_options(&self) -> TextureRoadOptions {
        let mut o = TextureRoadOptions::new(self.min_prominence.value(), self.min_area.value());
        o.constant = self.constant.unwrap_or(C_SPHERE);
        o.max_cap_width = self.max_cap_width.map(|w| w.value());
        o
    }
}

impl RoadKindSpec {
    fn grid(&self) -> roads::RoadGrid {
        roads::RoadGrid::square(self.nx, self.ny, self.spacing.value())
    }
}

impl SynthSpec {
    /// The synthetic height map.
    pub fn height_map(&self) -> Result<HeightMap> {
        let synthesised = match self {
            SynthSpec::Aggregate {
                nx,
                ny,
                spacing,
                grading,
                shape,
                coverage,
                embedding,
                seed,
            } => {
                let g = match grading.as_str() {
                    "4/6" | "4/6.3" => Aggregate::grading_4_6(),
                    "6/10" => Aggregate::grading_6_10(),
                    other => {
                        return Err(ScenarioError::Invalid(format!(
                            "[texture.synth]: unknown grading `{other}` (4/6, 6/10)"
                        )));
                    }
                };
                let h = spacing.value();
                let mut p = Aggregate::new(*nx, *ny, h, h, g, *seed);
                p.shape = match shape.as_deref() {
                    None | Some("ellipsoid") => ChipShape::Ellipsoid,
                    Some("polyhedron") => ChipShape::Polyhedron {
                        cuts: 6,
                        rounding: 0.1,
                    },
                    Some(other) => {
                        return Err(ScenarioError::Invalid(format!(
                            "[texture.synth]: unknown shape `{other}` (ellipsoid, polyhedron)"
                        )));
                    }
                };
                if let Some(c) = coverage {
                    p.coverage = *c;
                }
                if let Some([lo, hi]) = embedding {
                    p.embedding = (*lo, *hi);
                }
                tyreroad_texture::aggregate(&p)
            }
            SynthSpec::SelfAffine {
                nx,
                ny,
                spacing,
                rms,
                hurst,
                lambda_long,
                lambda_short,
                seed,
            } => tyreroad_texture::self_affine(&SelfAffine {
                nx: *nx,
                ny: *ny,
                dx: spacing.value(),
                dy: spacing.value(),
                rms: rms.value(),
                hurst: *hurst,
                lambda_long: lambda_long.value(),
                lambda_short: lambda_short.value(),
                seed: *seed,
            }),
            SynthSpec::TransverseTining(g) => {
                roads::tining(&roads::Tining::transverse(g.grid(), g.seed))
            }
            SynthSpec::LongitudinalTining(g) => {
                roads::tining(&roads::Tining::longitudinal(g.grid(), g.seed))
            }
            SynthSpec::BrushedConcrete(g) => {
                roads::brushed_concrete(&roads::BrushedConcrete::new(g.grid(), g.seed))
            }
            SynthSpec::ExposedAggregate(g) => {
                roads::exposed_aggregate(&roads::ExposedAggregate::new(g.grid(), g.seed))
            }
            SynthSpec::PorousAsphalt(g) => {
                roads::porous_asphalt(&roads::PorousAsphalt::new(g.grid(), g.seed))
            }
            SynthSpec::WornChipSeal(g) => {
                roads::worn_chip_seal(&roads::WornChipSeal::new(g.grid(), g.seed))
            }
            SynthSpec::Pave(g) => roads::pave(&roads::Pave::new(g.grid(), g.seed)),
        };
        synthesised.map_err(|source| ScenarioError::Texture {
            context: "[texture.synth]".into(),
            source,
        })
    }
}

/// `[material]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// E, e.g. "6.54 MPa".
    pub youngs_modulus: Pressure,
    /// ν.
    pub poisson_ratio: f64,
    /// A viscoelastic tread (`[material.viscoelastic]`, docs/viscoelastic.md):
    /// rolling runs then step it in time; `youngs_modulus` stays the laws'
    /// reference modulus.
    #[serde(default)]
    pub viscoelastic: Option<super::visco::ViscoSpec>,
}

/// `[solver]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Relative residual tolerance.
    pub tolerance: Option<f64>,
    /// Newton iterations per load step.
    pub max_iterations: Option<usize>,
}

/// A shape and its law constant.
#[derive(Debug, Clone, Deserialize)]
#[serde(rename_all = "snake_case", deny_unknown_fields, remote = "Self")]
pub enum ShapeSpec {
    /// A ball of radius `radius`.
    Sphere {
        /// R.
        radius: Length,
        /// c (default 0.36).
        constant: Option<f64>,
    },
    /// A cone of half-angle `half_angle`.
    Cone {
        /// α, e.g. "60 deg".
        half_angle: Angle,
        /// c (default 0.45).
        constant: Option<f64>,
    },
    /// An elliptic paraboloid with principal radii `radius_x`, `radius_y`.
    EllipticParaboloid {
        /// Rx.
        radius_x: Length,
        /// Ry.
        radius_y: Length,
        /// c (default 0.36).
        constant: Option<f64>,
    },
}

/// `[static]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticSpec {
    /// Total loads to solve at.
    #[serde(default)]
    pub loads: Vec<Force>,
    /// `[static.history]`: a loading history for a viscoelastic tread
    /// (`super::history`).
    pub history: Option<super::history::HistorySpec>,
}

/// `[[asperity]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AsperitySpec {
    /// Label in reports (defaults to the 1-based position in the file).
    pub id: Option<u32>,
    /// Summit x.
    pub x: Length,
    /// Summit y.
    pub y: Length,
    /// Summit height (up, towards the tread; default 0).
    pub height: Option<Length>,
    /// Shape, if not the default one.
    pub shape: Option<ShapeSpec>,
}

impl Scenario {
    /// The rung this scenario's run takes: `[model] fidelity` when given,
    /// else [`Scenario::default_fidelity`].
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming `[model] fidelity` for an unknown name.
    pub fn fidelity(&self) -> Result<Fidelity> {
        Ok(self
            .model
            .fidelity()?
            .unwrap_or_else(|| self.default_fidelity()))
    }

    /// `[model]`'s rung and what its caps are calibrated under, checked
    /// again against the rest of the scenario: for a runner that set them
    /// after the scenario was read (a command-line option), as
    /// [`Scenario::parse`] checks them.
    ///
    /// # Errors
    /// [`ScenarioError::Value`] naming the `[model]` key, as the parse would.
    pub fn check_model(&self) -> Result<()> {
        super::check::check_fidelity(self)
    }

    /// The rung a scenario takes without `[model] fidelity`: the best rung
    /// that keeps issue 15's cost targets for its kind of run.
    /// `calibrated` for an elastic `[rolling]` run on a `[texture]` (a first
    /// run within 2.5× of the Wilke run's time on the fixtures, the tables
    /// read back by a later run, and about a hundred times cheaper than the
    /// BEM rolling reference; docs/performance.md, "Tables as deep as the
    /// run presses"). `wilke` otherwise: a static texture's calibration
    /// costs more than its BEM solve, a viscoelastic run's calibrated cost
    /// is not measured, and the other roads have no caps to calibrate.
    pub fn default_fidelity(&self) -> Fidelity {
        if self.rolling.is_some() && self.texture.is_some() && self.material.viscoelastic.is_none()
        {
            Fidelity::Calibrated
        } else {
            Fidelity::Wilke
        }
    }

    /// The material, validated.
    pub fn material(&self) -> Result<Material> {
        Material::new(
            self.material.youngs_modulus.value(),
            self.material.poisson_ratio,
        )
        .map_err(|source| ScenarioError::Core {
            context: "[material]".into(),
            source,
        })
    }

    /// Solver options from `[solver]` over the defaults.
    pub fn solver_options(&self) -> SolverOptions {
        let mut o = SolverOptions::default();
        if let Some(t) = self.solver.tolerance {
            o.tolerance = t;
        }
        if let Some(m) = self.solver.max_iterations {
            o.max_iterations = m;
        }
        o
    }

    /// The `[rolling]` configuration, with `[solver]`'s tolerance and
    /// iteration limit when given (the run's steps are static solves).
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] without a `[rolling]` section, or any
    /// error of [`RollingSpec::config`].
    pub fn rolling_config(&self) -> Result<tyreroad_rolling::RollingConfig> {
        let spec = self
            .rolling
            .as_ref()
            .ok_or_else(|| ScenarioError::Invalid("no [rolling] section".into()))?;
        let mut config = spec.config()?;
        if spec.sensors_on_caps() {
            // Each cap is solved on the texture's own grid, elastically.
            let refusal = if self.texture.is_none() {
                Some("needs a [texture] (the caps are its segmentation's basins)")
            } else if self.material.viscoelastic.is_some() {
                Some("is for an elastic tread (each cap is solved elastically)")
            } else {
                None
            };
            if let Some(why) = refusal {
                return Err(ScenarioError::Invalid(format!(
                    "[rolling] sensor_accounting = \"caps\" {why}; use \"run\""
                )));
            }
        }
        if self.material.viscoelastic.is_some() {
            // The hereditary displacement's slope is not modelled.
            if spec.contact_slope == Some(super::rolling_spec::ContactSlopeSpec::Deformed) {
                return Err(ScenarioError::Invalid(
                    "[rolling] contact_slope = \"deformed\" is for an elastic tread; \
                     viscoelastic rolling places each contact under the undeformed \
                     profile (\"profile\")"
                        .into(),
                ));
            }
            config.contact_slope = tyreroad_rolling::ContactSlope::Profile;
        }
        if let Some(t) = self.solver.tolerance {
            config.tolerance = t;
        }
        if let Some(m) = self.solver.max_iterations {
            config.max_iterations = m;
        }
        Ok(config)
    }

    /// The `[texture]` road as rolling sees it (segmented, each asperity
    /// with its cap's law, y centred on the path, each gap taken at its cap's
    /// contact point through the summit radii): the road a rolling run on
    /// this scenario solves, built once for callers that roll it many times
    /// (`cargo xtask converge-sweep`). Relative paths resolve against
    /// `base_dir`.
    ///
    /// # Errors
    /// [`ScenarioError::Invalid`] without a `[texture]`, or any error of
    /// reading, synthesising or segmenting it.
    pub fn texture_rolling_road(
        &self,
        base_dir: &Path,
    ) -> Result<tyreroad_rolling::Road<crate::texture_road::TextureLaw>> {
        let texture = self
            .texture
            .as_ref()
            .ok_or_else(|| ScenarioError::Invalid("no [texture] section".into()))?;
        let material = self.material()?;
        let (set, summary, radii) =
            super::texture::rolling_texture_road_set(texture, base_dir, material, Par::Seq)?;
        Ok(crate::texture_road::rolling_road(set, radii, summary.top)?)
    }

    /// [`Scenario::texture_rolling_road`] on the `calibrated` rung: the
    /// asperities `config`'s path can select, each with its cap's
    /// BEM-calibrated law, calibrated once on `par`'s threads (tables kept
    /// in and read back from `cache` when given; docs/validation.md,
    /// "Calibrated laws in rolling"). For callers that time or roll the
    /// calibrated road apart from its calibration (`benches/fidelity.rs`).
    ///
    /// # Errors
    /// As [`Scenario::texture_rolling_road`], and any calibration error.
    pub fn calibrated_texture_rolling_road(
        &self,
        base_dir: &Path,
        config: &tyreroad_rolling::RollingConfig,
        par: tyreroad_multipoint::Par,
        cache: Option<&Path>,
    ) -> Result<tyreroad_rolling::Road<crate::fidelity::CalibratedLaw>> {
        let texture = self
            .texture
            .as_ref()
            .ok_or_else(|| ScenarioError::Invalid("no [texture] section".into()))?;
        let (set, summary, radii) = super::texture::calibrated_texture_road_set(
            texture,
            base_dir,
            self.material()?,
            config,
            par,
            cache,
            &crate::fidelity::table_depth::TablePlan::new(self.model.calibrate_under()?),
        )?;
        Ok(crate::fidelity::rolling::calibrated_rolling_road(
            set,
            radii,
            summary.top,
        )?)
    }

    /// Asperity labels, in file order.
    pub fn ids(&self) -> Vec<u32> {
        self.asperities
            .iter()
            .enumerate()
            .map(|(k, a)| a.id.unwrap_or(k as u32 + 1))
            .collect()
    }

    /// The multipoint problem: laws built, heights turned into gaps.
    pub fn problem(&self) -> Result<Problem<DynLaw>> {
        let material = self.material()?;
        Problem::from_set(self.asperity_set()?, material).map_err(|source| ScenarioError::Solve {
            context: "[[asperity]]".into(),
            source,
        })
    }

    /// The `[[asperity]]` list as a set: summit positions, heights and laws
    /// in file order.
    pub fn asperity_set(&self) -> Result<AsperitySet<DynLaw>> {
        let material = self.material()?;
        let mut positions = Vec::with_capacity(self.asperities.len());
        let mut heights = Vec::with_capacity(self.asperities.len());
        let mut laws = Vec::with_capacity(self.asperities.len());
        for (k, a) in self.asperities.iter().enumerate() {
            let shape = self.shape_of(k)?;
            positions.push([a.x.value(), a.y.value()]);
            heights.push(a.height.map_or(0.0, |h| h.value()));
            laws.push(build_law(shape, material, &format!("asperity #{}", k + 1))?);
        }
        AsperitySet::new(positions, heights, laws).map_err(|source| ScenarioError::Solve {
            context: "[[asperity]]".into(),
            source,
        })
    }

    /// Each `[[asperity]]`'s ball radius (m), NaN for one of another
    /// shape: the bound its law holds to (a ball's equator) and the patch
    /// its summit spreads (Hertz), for the runs' warnings.
    pub(crate) fn ball_radii(&self) -> Vec<f64> {
        (0..self.asperities.len())
            .map(|k| match self.shape_of(k) {
                Ok(ShapeSpec::Sphere { radius, .. }) => radius.value(),
                _ => f64::NAN,
            })
            .collect()
    }

    /// The shape of asperity `k` (0-based): its own or the default one.
    pub fn shape_of(&self, k: usize) -> Result<&ShapeSpec> {
        self.asperities
            .get(k)
            .and_then(|a| a.shape.as_ref())
            .or(self.default_shape.as_ref())
            .ok_or_else(|| {
                ScenarioError::Invalid(format!(
                    "asperity #{}: no shape, and no [default_shape]",
                    k + 1
                ))
            })
    }
}

fn build_law(shape: &ShapeSpec, material: Material, context: &str) -> Result<DynLaw> {
    let geometry = |source| ScenarioError::Geometry {
        context: context.into(),
        source,
    };
    let law = |source| ScenarioError::Law {
        context: context.into(),
        source,
    };
    Ok(match *shape {
        ShapeSpec::Sphere { radius, constant } => {
            let l = PotentialLaw::sphere(Sphere::new(radius.value()).map_err(geometry)?, material);
            Box::new(l.with_constant(constant.unwrap_or(C_SPHERE)).map_err(law)?)
        }
        ShapeSpec::Cone {
            half_angle,
            constant,
        } => {
            let l = PotentialLaw::cone(Cone::new(half_angle.value()).map_err(geometry)?, material);
            Box::new(l.with_constant(constant.unwrap_or(C_CONE)).map_err(law)?)
        }
        ShapeSpec::EllipticParaboloid {
            radius_x,
            radius_y,
            constant,
        } => {
            let g =
                EllipticParaboloid::new(radius_x.value(), radius_y.value()).map_err(geometry)?;
            let rule = LocalRule::Hertz {
                radius: (radius_x.value() * radius_y.value()).sqrt(),
            };
            Box::new(
                PotentialLaw::new(g, material, constant.unwrap_or(C_SPHERE), rule).map_err(law)?,
            )
        }
    })
}

#[cfg(test)]
#[path = "spec_tests.rs"]
mod tests;
