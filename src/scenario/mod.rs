//! The model as a library: scenario files read, run and written.
//!
//! A scenario (TOML, units written out: "5 mm", "6.54 MPa") names a tread
//! material and a road (an `[[asperity]]` list, a `[texture]` or a
//! `[rolling.synthetic_road]`) and what to solve: `[static]` loads or a
//! `[rolling]` run. [`Scenario::run`] dispatches on its sections and returns
//! typed results; nothing here prints. Files are written only through
//! [`output`], whose [`output::OutputSet`] stages a run's files in a
//! temporary directory and moves them into place together.
//!
//! ```no_run
//! use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
//! let scenario = Scenario::from_path("fixtures/paper_25_spheres.toml")?;
//! let options = RunOptions::new("fixtures");
//! if let ScenarioResult::Static(r) = scenario.run(&options)? {
//!     println!("{} rows", r.rows.len());
//! }
//! # Ok::<(), tyreroad::scenario::ScenarioError>(())
//! ```

mod bem;
mod check;
mod error;
mod height_checks;
mod history;
mod kind_tagged;
pub mod output;
mod ranges;
mod rolling;
mod rolling_calibrated;
mod rolling_caps;
mod rolling_fields;
mod rolling_inside;
mod rolling_npy;
mod rolling_spec;
mod rolling_stream;
mod shape_warnings;
mod spec;
mod statics;
mod texture;
pub mod units;
mod visco;
mod visco_curve;

use std::path::PathBuf;

pub use bem::{
    BEM_CELL, BemComparison, BemLoad, ComparedLoad, IMAGE_LOAD, MAP_CELL, MAX_FORCE_DIFFERENCE,
    bem_comparison, differences,
};
pub use error::ScenarioError;
pub use history::{
    DEFAULT_SEGMENT_STEPS, HistoryResult, HistorySpec, HistoryStep, MAX_HISTORY_STEPS,
    RecedingSpec, SEGMENT_DURATION_RANGE, SegmentSpec, run_load_history_scenario,
    write_history_csv,
};
pub use ranges::{
    LOAD_RANGE, MAX_MAP_POINTS, MIN_STATIC_LOAD, MODULUS_RANGE, SPEED_RANGE,
    THREAD_OVERSUBSCRIPTION, TOLERANCE_RANGE, check_name, check_threads,
};
pub use rolling::{RoadSummary, RollingRun, Spectra};
pub(crate) use rolling_fields::run_calibrated_fields;
pub use rolling_spec::{
    ContactSlopeSpec, ControlSpec, RollingSpec, SensorSpec, SyntheticRoadSpec, TreadSpec,
    approach_past_window_warning, clearance_warning,
};
pub use rolling_stream::StreamedRun;
pub use spec::{
    AsperitySpec, DynLaw, MaterialSpec, ModelSpec, RoadKindSpec, Scenario, ShapeSpec, SolverSpec,
    StaticSpec, SynthSpec, TextureSpec,
};
pub(crate) use statics::summits_inside_patches;
pub use statics::{
    LoadRun, StaticResult, StaticRow, StaticSolve, loads, run_static, run_static_problem,
    run_static_problem_with, static_loads,
};
pub use texture::{CalibrationSummary, TextureLoad, TextureResult, TextureSummary};
pub use tyreroad_multipoint::Par;
pub use tyreroad_rolling::{Progress, ProgressFn};
pub use visco::{
    ACTIVATION_ENERGY_RANGE, BranchSpec, MAX_TEMPERATURE, RELAXATION_TIME_RANGE, RelaxationTime,
    RelaxationTimeDim, ShiftSpec, Temperature, ViscoCase, ViscoSpec, WLF_C1_RANGE, WLF_C2_RANGE,
};

/// How to run a scenario (nothing here changes the results).
#[derive(Clone, Default)]
pub struct RunOptions<'a> {
    /// Directory against which relative paths of the scenario (a
    /// `[texture] file`) are resolved: usually the scenario file's own.
    pub base_dir: PathBuf,
    /// Parallelism of a rolling run: `None` takes `[rolling] threads`, or
    /// every core when that is unset.
    pub par: Option<Par>,
    /// Called after each rolling step, from the worker threads; return
    /// `ControlFlow::Break(())` to stop the run.
    pub progress: Option<ProgressFn<'a>>,
    /// Where a rolling run checkpoints and resumes from (when its
    /// `[rolling] checkpoint` is true); `None`: no checkpoint.
    pub checkpoint_dir: Option<PathBuf>,
}

impl RunOptions<'_> {
    /// Options resolving relative paths against `base_dir`, with no
    /// progress callback and no checkpoint.
    pub fn new(base_dir: impl Into<PathBuf>) -> Self {
        Self {
            base_dir: base_dir.into(),
            ..Self::default()
        }
    }

    /// The parallelism of a rolling run: the caller's, else `[rolling]
    /// threads` (0 or unset: every core).
    pub(crate) fn rolling_par(&self, spec: &RollingSpec) -> Par {
        self.par
            .unwrap_or_else(|| Par::rayon(spec.threads.unwrap_or(0)))
    }
}

/// What a scenario run produced.
#[derive(Clone, Debug)]
pub enum ScenarioResult {
    /// `[static]` loads on an `[[asperity]]` list.
    Static(StaticResult),
    /// `[static]` loads on a `[texture]`, with the two-scale rebuild.
    Texture(Box<TextureResult>),
    /// A `[rolling]` run.
    Rolling(Box<RollingRun>),
    /// A `[static.history]` run with a `[material.viscoelastic]` tread.
    History(HistoryResult),
}

impl ScenarioResult {
    /// What makes the run's answer no road's, in the words `cargo xtask run`
    /// prints as `warning:` lines: contacts pressed past their shapes or
    /// tables, summits inside each other's patch, a footprint off the map,
    /// an approach past the tread's profile at the selection window's edge.
    /// (The warning said before a rolling run's steps is
    /// [`approach_past_window_warning`]; caps that kept their Wilke law are
    /// listed by the calibration summary's `fallbacks`.)
    pub fn warnings(&self) -> Vec<String> {
        let past_tables = |t: &TextureSummary| {
            t.calibration
                .iter()
                .flat_map(|c| c.past_tables.warning())
                .collect::<Vec<_>>()
        };
        match self {
            Self::Static(r) => r.warnings.clone(),
            Self::Texture(r) => r
                .statics
                .warnings
                .iter()
                .chain(&r.texture.warnings)
                .cloned()
                .chain(past_tables(&r.texture))
                .collect(),
            Self::Rolling(r) => {
                let mut w = r.road.warnings().to_vec();
                if let RoadSummary::Texture(t) = &r.road {
                    w.extend(past_tables(t));
                }
                w.extend(clearance_warning(r.result.min_clearance()));
                w
            }
            Self::History(r) => r.warnings.clone(),
        }
    }
}

impl Scenario {
    /// Parses a scenario and checks every value (`check`): errors name the
    /// offending key (and its line, for TOML errors).
    ///
    /// `origin` (a path or a label) prefixes the messages.
    ///
    /// # Errors
    /// [`ScenarioError::Parse`] for malformed TOML or unknown keys,
    /// [`ScenarioError::Value`] for a value out of its range,
    /// [`ScenarioError::Invalid`] for inconsistent sections.
    pub fn parse(text: &str, origin: &str) -> Result<Self, ScenarioError> {
        let mut scenario: Scenario = toml::from_str(text).map_err(|e| ScenarioError::Parse {
            origin: origin.into(),
            message: e.to_string(),
        })?;
        scenario.origin = origin.into();
        check::check(&scenario).map_err(|e| match e {
            ScenarioError::Value {
                key,
                value,
                expected,
            } => ScenarioError::Value {
                key: format!("{origin}: {key}"),
                value,
                expected,
            },
            ScenarioError::Invalid(what) => {
                ScenarioError::Invalid(format!("scenario {origin}: {what}"))
            }
            other => other,
        })?;
        Ok(scenario)
    }

    /// Reads and parses a scenario file.
    ///
    /// # Errors
    /// [`ScenarioError::Io`] if the file cannot be read, else as
    /// [`Scenario::parse`].
    pub fn from_path(path: impl AsRef<std::path::Path>) -> Result<Self, ScenarioError> {
        let path = path.as_ref();
        let text = std::fs::read_to_string(path).map_err(ScenarioError::io("reading", path))?;
        Self::parse(&text, &path.display().to_string())
    }

    /// Runs the scenario: a `[rolling]` run when it has that section (on its
    /// texture, asperities or synthetic road), else its `[static]` loads on
    /// its `[texture]` or its `[[asperity]]` list.
    ///
    /// # Errors
    /// Any [`ScenarioError`]: a missing section, an invalid material or
    /// shape, an unreadable texture, a failed solve or run.
    pub fn run(&self, options: &RunOptions<'_>) -> Result<ScenarioResult, ScenarioError> {
        self.run_whole(options)
    }

    /// Rolls only the path's steps `steps` of the `[rolling]` section (one
    /// rank's part of a distributed run, docs/distributed.md), each chunk
    /// started `warmup` steps early ([`tyreroad_rolling::roll_range`]).
    /// The records of the parts, concatenated in order, finish into the
    /// run with [`Scenario::finish_rolling`].
    ///
    /// # Errors
    /// No `[rolling]` section, or as [`Scenario::run`].
    pub fn roll_part(
        &self,
        options: &RunOptions<'_>,
        steps: std::ops::Range<usize>,
        warmup: usize,
    ) -> Result<tyreroad_rolling::RollingResult, ScenarioError> {
        let spec = self.rolling_section()?;
        if self.material.viscoelastic.is_some() {
            return Err(ScenarioError::Invalid(
                "a viscoelastic rolling run carries each asperity's memory along the whole path: \
                 it is not split into parts"
                    .into(),
            ));
        }
        match rolling_calibrated::rolling_on_road(
            self,
            spec,
            options,
            rolling::What::Part { steps, warmup },
        )? {
            rolling::Rolled::Part(part) => Ok(part),
            _ => Err(ScenarioError::Invalid("a part gave a whole run".into())),
        }
    }

    /// The run made of records rolled elsewhere (every step of the path,
    /// in order): the road summary and the spectra as [`Scenario::run`]
    /// gives them, so the same writers write the same files.
    ///
    /// # Errors
    /// No `[rolling]` section, records that do not cover the path in order,
    /// or a spectrum that cannot be computed.
    pub fn finish_rolling(
        &self,
        options: &RunOptions<'_>,
        result: tyreroad_rolling::RollingResult,
    ) -> Result<RollingRun, ScenarioError> {
        let spec = self.rolling_section()?;
        match rolling_calibrated::rolling_on_road(
            self,
            spec,
            options,
            rolling::What::Gathered(result),
        )? {
            rolling::Rolled::Run(run) => Ok(*run),
            _ => Err(ScenarioError::Invalid("a whole run gave a part".into())),
        }
    }

    /// Steps on the `[rolling]` path.
    ///
    /// # Errors
    /// No `[rolling]` section or an invalid one.
    pub fn rolling_steps(&self) -> Result<usize, ScenarioError> {
        self.rolling_section()?;
        Ok(self.rolling_config()?.steps())
    }

    fn rolling_section(&self) -> Result<&RollingSpec, ScenarioError> {
        self.rolling
            .as_ref()
            .ok_or_else(|| ScenarioError::Invalid("the scenario has no [rolling] section".into()))
    }

    fn run_whole(&self, options: &RunOptions<'_>) -> Result<ScenarioResult, ScenarioError> {
        if self.rolling.is_some() && self.material.viscoelastic.is_some() {
            let mut runs = self.roll_viscoelastic(options, &[visco::ViscoCase::default()])?;
            return match runs.pop() {
                Some(run) => run.map(|r| ScenarioResult::Rolling(Box::new(r))),
                None => Err(ScenarioError::Invalid("no viscoelastic run".into())),
            };
        }
        if let Some(spec) = &self.rolling {
            return rolling_calibrated::run_rolling(self, spec, options)
                .map(|r| ScenarioResult::Rolling(Box::new(r)));
        }
        if self.texture.is_some() {
            return texture::run_texture_static(self, &options.base_dir)
                .map(|r| ScenarioResult::Texture(Box::new(r)));
        }
        if self
            .static_case
            .as_ref()
            .is_some_and(|s| s.history.is_some())
        {
            // An elastic `[material]` has no history: refused by name.
            let (tread, note) = self
                .viscoelastic_material_noted(&options.base_dir)?
                .ok_or_else(|| history::elastic_refusal(self))?;
            let mut result = run_load_history_scenario(self, Some(&tread))?;
            result.warnings.extend(note);
            return Ok(ScenarioResult::History(result));
        }
        run_static(self).map(ScenarioResult::Static)
    }
}
