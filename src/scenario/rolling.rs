//! A `[rolling]` scenario: the road (a texture, the `[[asperity]]` list or a
//! synthetic road of spheres), the run, and the spectra of its signals
//! (docs/rolling.md).

use std::path::Path;
use std::time::Duration;

use tyreroad_contact_law::{ContactLaw, Material};
use tyreroad_multipoint::AsperitySet;
use tyreroad_rolling as rolling;

use super::output::summits::{SpilledSummits, SummitSlices, SummitSource};
use super::rolling_inside::InsidePatchTally;
use super::rolling_npy::{npy_file, npy_summary, npy_summits, npy_window_road};
use super::texture::{TextureSummary, footprint_off_road, rolling_texture_road_set};
use super::{RollingSpec, RunOptions, Scenario, ScenarioError, SyntheticRoadSpec};
use crate::texture_road::{PastCapTally, PastShape, rolling_road};

/// Where the rolled road came from.
#[derive(Clone, Debug, PartialEq)]
pub enum RoadSummary {
    /// The scenario's `[texture]`, split into asperities.
    Texture(Box<TextureSummary>),
    /// The scenario's `[[asperity]]` list.
    Asperities {
        /// Number of asperities.
        count: usize,
        /// What looks wrong with the run on them (balls pressed past
        /// their equators), for its report.
        warnings: Vec<String>,
    },
    /// `[rolling.synthetic_road]`'s random spheres.
    Synthetic {
        /// Number of spherical summits.
        count: usize,
        /// As [`RoadSummary::Asperities`]'s.
        warnings: Vec<String>,
    },
}

impl RoadSummary {
    /// What looks wrong with the road or the run on it, for its report.
    pub fn warnings(&self) -> &[String] {
        match self {
            Self::Texture(t) => &t.warnings,
            Self::Asperities { warnings, .. } | Self::Synthetic { warnings, .. } => warnings,
        }
    }

    /// [`RoadSummary::warnings`], to add to.
    pub(crate) fn warnings_mut(&mut self) -> &mut Vec<String> {
        match self {
            Self::Texture(t) => &mut t.warnings,
            Self::Asperities { warnings, .. } | Self::Synthetic { warnings, .. } => warnings,
        }
    }

    /// Warns of what `config`'s path misses on this road: a footprint
    /// reaching off the texture's map or the synthetic road (`synthetic`,
    /// its spec), each sensor no footprint covers (it reads nothing at any
    /// step: a sensor off the road, or beside the path), and a load whose
    /// nominal pressure over the footprint passes a tenth of the tread's
    /// `youngs_modulus` (Pa; a viscoelastic tread's long-term one).
    pub(crate) fn warn_of_path(
        &mut self,
        config: &rolling::RollingConfig,
        synthetic: Option<&SyntheticRoadSpec>,
        youngs_modulus: f64,
    ) {
        match self {
            Self::Texture(t) => t.warn_of_footprint_off_map(config),
            Self::Synthetic { warnings, .. } => {
                if let Some(synth) = synthetic {
                    let g = synth.road();
                    warnings.extend(footprint_off_road(
                        config,
                        ((g.length, g.width), (g.min_spacing, g.min_spacing)),
                        ("synthetic road", "give a longer or wider road"),
                    ));
                }
            }
            Self::Asperities { .. } => {}
        }
        // A tenth of the modulus: strains of that order are outside the
        // linear half-space the model (and its BEM) solves; a tyre's
        // footprint carries about 1 %.
        if let Some(p) = config
            .nominal_pressure()
            .filter(|&p| p > 0.1 * youngs_modulus)
        {
            self.warnings_mut().push(format!(
                "the load over the tread's footprint is {:.3} MPa, {:.0} % of the tread's \
                 Young's modulus ({:.3} MPa): strains this large lie outside the linear \
                 elastic half-space the model solves, and its forces and approach are no \
                 tread's (a smaller load or a larger footprint)",
                p * 1e-6,
                100.0 * p / youngs_modulus,
                youngs_modulus * 1e-6
            ));
        }
        let ([x0, x1], [y0, y1]) = config.swept_window();
        let mm = |v: f64| v * 1e3;
        for s in config.sensors_off_the_path() {
            self.warnings_mut().push(format!(
                "sensor {:?} (x = {:.1} … {:.1} mm, y = {:.1} … {:.1} mm) lies outside the \
                 region the path's footprints and their margins reach (x = {:.1} … {:.1} mm, \
                 y = {:.1} … {:.1} mm): it reads no force at any step (move the sensor onto \
                 the path)",
                s.name,
                mm(s.x[0]),
                mm(s.x[1]),
                mm(s.y[0]),
                mm(s.y[1]),
                mm(x0),
                mm(x1),
                mm(y0),
                mm(y1),
            ));
        }
    }
}

/// The one-third-octave spectra of a rolling run.
///
/// The primary signal is the total force under displacement control (dB re
/// the reference force) and the approach under load control (dB re 1 µm);
/// sensors are always in dB re the reference force.
#[derive(Clone, Debug, PartialEq)]
pub struct Spectra {
    /// Load control: the primary signal is the approach.
    pub load_control: bool,
    /// Reference force of the force levels (N).
    pub reference_force: f64,
    /// Reference of the primary signal (N or m).
    pub primary_reference: f64,
    /// Levels of the primary signal.
    pub primary: Vec<rolling::BandLevel>,
    /// Levels of each sensor's force, in sensor order.
    pub sensors: Vec<Vec<rolling::BandLevel>>,
    /// Welch segment length (samples).
    pub segment: usize,
    /// Lowest band centre (Hz) that the segment resolves: a Welch segment of
    /// L samples resolves Δf = fs/L, and a band narrower than two bins (width
    /// 0.23 f_c) holds leakage from its neighbours, not its own content.
    pub resolved_from: f64,
    /// Samples of failed steps (NaN) replaced by linear interpolation
    /// between their good neighbours before the spectra were computed
    /// ([`rolling::interpolate_failed`]); 0 when every step has values.
    pub interpolated_samples: usize,
}

impl Spectra {
    /// Whether the lowest band lies below [`Spectra::resolved_from`].
    pub fn has_unresolved_bands(&self) -> bool {
        self.primary
            .first()
            .is_some_and(|b| b.band.centre < self.resolved_from)
    }
}

/// A rolling run and what follows from it.
#[derive(Clone, Debug)]
pub struct RollingRun {
    /// The road rolled on.
    pub road: RoadSummary,
    /// Summit positions `(x, y)` (m) of the road's asperities, in the
    /// road's index order (the ids of the rolling crate).
    pub road_positions: Vec<[f64; 2]>,
    /// Summit heights (m), same order.
    pub road_heights: Vec<f64>,
    /// The configuration the spec described.
    pub config: rolling::RollingConfig,
    /// One record per step.
    pub result: rolling::RollingResult,
    /// The spectra of the signals.
    pub spectra: Spectra,
}

impl RollingRun {
    /// Steps per status: `[converged, stagnated, failed]`.
    pub fn status_counts(&self) -> [usize; 3] {
        self.result.status_counts()
    }

    /// Steps where some contact patches overlap, and the largest number of
    /// overlapping pairs at one step.
    pub fn overlapping_steps(&self) -> (usize, usize) {
        let steps = &self.result.steps;
        (
            steps.iter().filter(|s| s.overlapping > 0).count(),
            steps.iter().map(|s| s.overlapping).max().unwrap_or(0),
        )
    }
}

/// What [`run_on`] does with the road: roll the whole path, roll a part of
/// it (one rank of a distributed run), or take records rolled elsewhere
/// (gathered from the ranks) and finish them into a run.
pub(crate) enum What {
    Whole,
    Part {
        steps: std::ops::Range<usize>,
        warmup: usize,
    },
    Gathered(rolling::RollingResult),
    /// The road's summary and summits only: the records were written as
    /// they arrived (`super::rolling_stream`).
    Road,
}

/// What [`run_on`] gives back: a run, or a part's records.
pub(crate) enum Rolled {
    Run(Box<RollingRun>),
    Part(rolling::RollingResult),
    Road(RoadSummary, Box<dyn SummitSource>),
}

/// Builds the scenario's road on uncalibrated laws (the calibrated rungs
/// are `super::rolling_calibrated::rolling_on_road`'s) and does `what` on
/// it.
pub(crate) fn rolling_on_uncalibrated_road(
    scenario: &Scenario,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    what: What,
) -> Result<Rolled, ScenarioError> {
    let material = scenario.material()?;
    if let Some(texture) = &scenario.texture {
        // A rank's part on a `.npy` texture: windows of the file, the same
        // asperities by the same ids as the whole road's (other formats,
        // and calibrated laws above, are read whole: docs/distributed.md,
        // "Memory per rank").
        if let What::Part { steps, warmup } = &what
            && let Some(road) = npy_window_road(scenario, options, material)?
        {
            let summary = RoadSummary::Asperities {
                count: road.len(),
                warnings: Vec::new(),
            };
            return gather_part(steps.len(), |sink| {
                roll_part_on_windows(
                    scenario,
                    material,
                    spec,
                    options,
                    (steps.clone(), *warmup),
                    summary,
                    |range| Ok(road.window(range)?),
                    sink,
                )
            });
        }
        // Rank 0 finishing a run rolled elsewhere on a `.npy` texture: the
        // summary and the summits streamed from the file, a tile at a
        // time, never the whole road's laws.
        if matches!(what, What::Road | What::Gathered(_))
            && let Some(road) = npy_window_road(scenario, options, material)?
        {
            let mut summary = RoadSummary::Texture(Box::new(npy_summary(&road)));
            summary.warn_of_path(&scenario.rolling_config()?, None, material.youngs_modulus());
            return match what {
                What::Gathered(result) => {
                    let summits = npy_summits(&road)?;
                    finish(scenario.rolling_config()?, spec, summary, summits, result)
                }
                // Streamed, not held: the file is walked once into a
                // spill that `road.npz` reads once per member.
                _ => {
                    let path = npy_file(texture, options).unwrap_or_default();
                    let summits = SpilledSummits::from_source(&road)
                        .map_err(ScenarioError::io("spilling the summits of", path))?;
                    Ok(Rolled::Road(summary, Box::new(summits)))
                }
            };
        }
        let par = options.rolling_par(spec);
        let (set, summary, radii) =
            rolling_texture_road_set(texture, &options.base_dir, material, par)?;
        // Gaps at each cap's contact point, not its summit.
        let road = rolling_road(set, radii, summary.top)?;
        let mut rolled = roll_road(
            scenario,
            &road,
            RoadSummary::Texture(Box::new(summary)),
            material,
            spec,
            options,
            what,
        )?;
        warn_over(&mut rolled, |steps| {
            PastCapTally::new(&road, 1.0, PastShape::Caps).warning_over(steps)
        });
        return Ok(rolled);
    }
    match (scenario.asperities.is_empty(), &spec.synthetic_road) {
        (false, None) => {
            let set = scenario.asperity_set()?;
            let count = set.len();
            // The balls' bounds and summits, before the set moves into the
            // road.
            let balls = scenario.ball_radii();
            let past_equators = PastCapTally::at_equators(&balls, set.laws(), 1.0);
            let positions = set.positions().to_vec();
            let mut rolled = run_on(
                scenario,
                set,
                RoadSummary::Asperities {
                    count,
                    warnings: scenario.steep_cone_warning().into_iter().collect(),
                },
                material,
                spec,
                options,
                what,
            )?;
            warn_over(&mut rolled, |steps| past_equators.warning_over(steps));
            let name = |k: usize| format!("[[asperity]] #{}", k + 1);
            let inside =
                InsidePatchTally::new((&positions, &balls), material.reduced_modulus(), &name);
            warn_over(&mut rolled, |steps| inside.warning_over(steps));
            Ok(rolled)
        }
        (true, Some(synth)) => {
            let synth = synth.road();
            match what {
                // A rank's part: only the window of the road its steps
                // touch, the same summits by the same ids as the whole
                // road's (docs/distributed.md, "Memory per rank").
                What::Part { steps, warmup } => {
                    let windows = synth.windows(material)?;
                    let summary = RoadSummary::Synthetic {
                        count: windows.count(),
                        warnings: Vec::new(),
                    };
                    gather_part(steps.len(), |sink| {
                        roll_part_on_windows(
                            scenario,
                            material,
                            spec,
                            options,
                            (steps, warmup),
                            summary,
                            |range| Ok(windows.window(range)?),
                            sink,
                        )
                    })
                }
                // Streamed, not held: `road.npz` walks them once per
                // member (docs/distributed.md, "Memory per rank").
                What::Road => {
                    let summits = synth.summit_stream()?;
                    let count = summits.count();
                    Ok(Rolled::Road(
                        RoadSummary::Synthetic {
                            count,
                            warnings: Vec::new(),
                        },
                        Box::new(summits),
                    ))
                }
                // Records rolled elsewhere: the outputs need the summits'
                // positions and heights, not their laws.
                What::Gathered(result) => {
                    let (positions, heights) = synth.summits()?;
                    let config = scenario.rolling_config()?;
                    let summary = RoadSummary::Synthetic {
                        count: positions.len(),
                        warnings: Vec::new(),
                    };
                    finish(config, spec, summary, (positions, heights), result)
                }
                What::Whole => {
                    let road = synth.sphere_road(material)?;
                    let count = road.len();
                    let mut rolled = roll_road(
                        scenario,
                        &road,
                        RoadSummary::Synthetic {
                            count,
                            warnings: Vec::new(),
                        },
                        material,
                        spec,
                        options,
                        what,
                    )?;
                    warn_over(&mut rolled, |steps| {
                        PastCapTally::new(&road, 1.0, PastShape::Equators).warning_over(steps)
                    });
                    let balls: Vec<f64> = (0..count).map(|i| road.summit_radius(i)).collect();
                    let name = |k: usize| format!("summit {k} of the synthetic road");
                    let inside = InsidePatchTally::new(
                        (road.positions(), &balls),
                        material.reduced_modulus(),
                        &name,
                    );
                    warn_over(&mut rolled, |steps| inside.warning_over(steps));
                    Ok(rolled)
                }
            }
        }
        (false, Some(_)) => Err(ScenarioError::Invalid(
            "[rolling.synthetic_road] and [[asperity]] both given: choose one".into(),
        )),
        (true, None) => Err(ScenarioError::Invalid(
            "no road: give [[asperity]] entries or [rolling.synthetic_road]".into(),
        )),
    }
}

/// When `rolled` is a whole run: `warning(its steps)` (a tally of its
/// records, made only then), if any, added to its road's summary.
fn warn_over(rolled: &mut Rolled, warning: impl FnOnce(&[rolling::StepRecord]) -> Option<String>) {
    if let Rolled::Run(run) = rolled {
        let warning = warning(&run.result.steps);
        run.road.warnings_mut().extend(warning);
    }
}

fn run_on<L: ContactLaw + Sync>(
    scenario: &Scenario,
    set: AsperitySet<L>,
    summary: RoadSummary,
    material: Material,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    what: What,
) -> Result<Rolled, ScenarioError> {
    let road = rolling::Road::new(set);
    roll_road(scenario, &road, summary, material, spec, options, what)
}

pub(super) fn roll_road<L: ContactLaw + Sync>(
    scenario: &Scenario,
    road: &rolling::Road<L>,
    summary: RoadSummary,
    material: Material,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    what: What,
) -> Result<Rolled, ScenarioError> {
    roll_road_with(
        scenario,
        (road, None),
        summary,
        material,
        spec,
        options,
        what,
    )
}

/// [`roll_road`], each step coupled by `coupling` when given
/// ([`rolling::roll_coupled`]).
pub(super) fn roll_road_with<L: ContactLaw + Sync>(
    scenario: &Scenario,
    (road, coupling): (&rolling::Road<L>, Option<&dyn rolling::StepCoupling<L>>),
    mut summary: RoadSummary,
    material: Material,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    what: What,
) -> Result<Rolled, ScenarioError> {
    let config = scenario.rolling_config()?;
    summary.warn_of_path(
        &config,
        spec.synthetic_road.as_ref(),
        material.youngs_modulus(),
    );
    if let What::Road = what {
        let summits = SummitSlices {
            positions: road.positions().to_vec(),
            heights: road.heights().to_vec(),
        };
        return Ok(Rolled::Road(summary, Box::new(summits)));
    }
    let checkpoint = options
        .checkpoint_dir
        .as_deref()
        .filter(|_| spec.checkpoint)
        .map(|dir: &Path| rolling::CheckpointOptions {
            dir: dir.to_path_buf(),
            interval: checkpoint_interval(),
        });
    // The caller's parallelism, else the scenario's `threads` (0 or unset:
    // every core).
    let par = options.rolling_par(spec);
    let run_options = rolling::RunOptions {
        chunks: spec.chunks,
        checkpoint: checkpoint.as_ref(),
        progress: options.progress,
        par,
    };
    let off_road = |e: rolling::RollingError| match e {
        rolling::RollingError::NoSupport { position } => {
            ScenarioError::off_road(road.positions(), road.is_window(), config.lateral, position)
        }
        other => other.into(),
    };
    let result = match what {
        What::Whole => match coupling {
            None => rolling::roll(road, material, &config, &run_options),
            Some(c) => rolling::roll_coupled(road, material, &config, &run_options, c),
        }
        .map_err(off_road)?,
        What::Part { steps, warmup } => {
            let part = rolling::roll_range_coupled(
                road,
                material,
                &config,
                steps,
                warmup,
                &run_options,
                coupling,
            )
            .map_err(off_road)?;
            return Ok(Rolled::Part(part));
        }
        What::Gathered(result) => result,
        What::Road => return Err(ScenarioError::Invalid("no records to roll".into())),
    };
    let summits = (road.positions().to_vec(), road.heights().to_vec());
    finish(config, spec, summary, summits, result)
}

/// Path length (m) rolled on one window of a synthetic road by a rank:
/// the window is this plus a footprint and its margin, so a rank's memory
/// does not grow with its part (docs/distributed.md, "Memory per rank").
/// About 7 000 summits (1 MB) at road density; each window streams the
/// whole road's candidates once (about 1 ms per metre of road), so a longer
/// piece costs memory and a shorter one time.
const WINDOW_PATH: f64 = 1.0;

/// Where a part's pieces go as they are rolled, in path order.
pub(crate) type PieceSink<'s> = dyn FnMut(rolling::RollingResult) -> Result<(), ScenarioError> + 's;

/// Appends a piece to the part being gathered, with room for the whole
/// part (`steps`) made at the first piece (no doubling copies).
fn gather_piece(
    part: &mut Option<rolling::RollingResult>,
    rolled: rolling::RollingResult,
    steps: usize,
) {
    match part {
        None => {
            let mut first = rolled;
            first
                .steps
                .reserve_exact(steps.saturating_sub(first.steps.len()));
            *part = Some(first);
        }
        Some(all) => {
            all.steps.extend(rolled.steps);
            all.resumed += rolled.resumed;
        }
    }
}

/// Gathers the pieces that `roll` hands to its sink into one part of
/// `steps` steps.
fn gather_part(
    steps: usize,
    roll: impl FnOnce(&mut PieceSink<'_>) -> Result<(), ScenarioError>,
) -> Result<Rolled, ScenarioError> {
    let mut part: Option<rolling::RollingResult> = None;
    roll(&mut |rolled| {
        gather_piece(&mut part, rolled, steps);
        Ok(())
    })?;
    part.map(Rolled::Part)
        .ok_or_else(|| ScenarioError::Invalid("an empty part of the path".into()))
}

/// One rank's part on a road read by windows (a synthetic road, a `.npy`
/// texture): the part cut into pieces of [`WINDOW_PATH`], each rolled (with
/// its `warmup` steps) on the window of the road its footprints select
/// from; each piece's records go to `sink`, in path order. `summary` only
/// labels the pieces' runs: a part's records carry none.
#[allow(clippy::too_many_arguments)]
pub(super) fn roll_part_on_windows<L: ContactLaw + Sync>(
    scenario: &Scenario,
    material: Material,
    spec: &RollingSpec,
    options: &RunOptions<'_>,
    (steps, warmup): (std::ops::Range<usize>, usize),
    summary: RoadSummary,
    mut window: impl FnMut([f64; 2]) -> Result<rolling::Road<L>, ScenarioError>,
    sink: &mut PieceSink<'_>,
) -> Result<(), ScenarioError> {
    let config = scenario.rolling_config()?;
    let per_window = ((WINDOW_PATH / config.step).floor() as usize).max(1);
    if steps.is_empty() {
        return Err(ScenarioError::Invalid("an empty part of the path".into()));
    }
    let mut start = steps.start;
    while start < steps.end {
        let piece = start..(start + per_window).min(steps.end);
        start = piece.end;
        let road = window(part_window(&config, &piece, warmup))?;
        let what = What::Part {
            steps: piece,
            warmup,
        };
        let Rolled::Part(rolled) = roll_road(
            scenario,
            &road,
            summary.clone(),
            material,
            spec,
            options,
            what,
        )?
        else {
            return Err(ScenarioError::Invalid("a part gave a whole run".into()));
        };
        sink(rolled)?;
    }
    Ok(())
}

/// The x-range of the road that the steps `steps` and their `warmup`
/// steps select from: their footprints with the selection margin, and 1 mm
/// more (the selection compares coordinates, so a wider window selects the
/// same asperities; the pad only keeps rounding out of the question).
fn part_window(
    config: &rolling::RollingConfig,
    steps: &std::ops::Range<usize>,
    warmup: usize,
) -> [f64; 2] {
    let (hx, _) = config.tread.half_extents();
    let reach = hx + config.tread.effective_margin(config.margin) + 1e-3;
    let first = config.position(steps.start.saturating_sub(warmup));
    let last = config.position(steps.end.max(1) - 1);
    [first.min(last) - reach, first.max(last) + reach]
}

/// The run made of a path's records: checked to cover the path in order,
/// with the road's summits and the spectra.
fn finish(
    config: rolling::RollingConfig,
    spec: &RollingSpec,
    summary: RoadSummary,
    (road_positions, road_heights): (Vec<[f64; 2]>, Vec<f64>),
    result: rolling::RollingResult,
) -> Result<Rolled, ScenarioError> {
    if result.steps.len() != config.steps()
        || result.steps.iter().enumerate().any(|(k, s)| s.index != k)
    {
        return Err(ScenarioError::Invalid(format!(
            "gathered records do not cover the path's {} steps in order",
            config.steps()
        )));
    }
    let spectra = spectra(&config, spec, &result)?;
    Ok(Rolled::Run(Box::new(RollingRun {
        road: summary,
        road_positions,
        road_heights,
        config,
        result,
        spectra,
    })))
}

pub(super) fn spectra(
    config: &rolling::RollingConfig,
    spec: &RollingSpec,
    result: &rolling::RollingResult,
) -> Result<Spectra, ScenarioError> {
    let sensors: Vec<Vec<f64>> = (0..config.sensors.len())
        .map(|k| result.sensor(k))
        .collect();
    let signals = Signals {
        sample_rate: result.sample_rate,
        total_force: &result.total_force(),
        approach: &result.approach(),
        sensors: &sensors,
    };
    spectra_of(config, spec, &signals)
}

/// The signals the spectra are made of, one value per step.
pub(super) struct Signals<'a> {
    pub(super) sample_rate: f64,
    pub(super) total_force: &'a [f64],
    pub(super) approach: &'a [f64],
    /// `sensors[k][step]`, a sensor missing from a record counted 0 N.
    pub(super) sensors: &'a [Vec<f64>],
}

/// [`spectra`] of signals kept apart from their records.
pub(super) fn spectra_of(
    config: &rolling::RollingConfig,
    spec: &RollingSpec,
    signals: &Signals<'_>,
) -> Result<Spectra, ScenarioError> {
    let reference = spec.reference_force.map_or(1.0, |f| f.value());
    let load_control = matches!(config.control, rolling::RollingControl::Load(_));
    let (primary, primary_reference) = if load_control {
        (signals.approach, 1e-6)
    } else {
        (signals.total_force, reference)
    };
    let fs = signals.sample_rate;
    // A Welch periodogram needs every sample: failed steps are bridged by
    // linear interpolation, and their count reported with the spectra.
    let (primary, interpolated_samples) = rolling::interpolate_failed(primary);
    let third_octave = |signal: &[f64], r: f64| {
        rolling::third_octave(signal, fs, r, spec.segment).map_err(|source| ScenarioError::Core {
            context: "one-third-octave spectrum".into(),
            source,
        })
    };
    let spectrum = |signal: &[f64], r: f64| {
        let (signal, _) = rolling::interpolate_failed(signal);
        third_octave(&signal, r)
    };
    // Bridged already: a second copy would only repeat it.
    let levels = third_octave(&primary, primary_reference)?;
    let segment = rolling::effective_segment_len(primary.len(), spec.segment);
    let resolved_from = rolling::resolved_from(fs, segment);
    let sensors = (0..config.sensors.len())
        .map(|k| match signals.sensors.get(k) {
            Some(signal) => spectrum(signal, reference),
            None => spectrum(&vec![0.0; primary.len()], reference),
        })
        .collect::<Result<_, _>>()?;
    Ok(Spectra {
        load_control,
        reference_force: reference,
        primary_reference,
        primary: levels,
        sensors,
        segment,
        resolved_from,
        interpolated_samples,
    })
}

/// How often a chunk rewrites its checkpoint: every 2 s, or every
/// `TYREROAD_CHECKPOINT_INTERVAL` seconds when that variable holds a
/// non-negative number (0: every step; the SIGKILL-resume test uses it to
/// have checkpoints on a run of a second). The interval changes what a kill
/// loses, never the outputs, so it is not a scenario key.
fn checkpoint_interval() -> Duration {
    std::env::var("TYREROAD_CHECKPOINT_INTERVAL")
        .ok()
        .and_then(|v| v.trim().parse::<f64>().ok())
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .unwrap_or(Duration::from_secs(2))
}
