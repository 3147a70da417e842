//! A `[texture]` scenario: the height map split into asperities
//! ([`crate::texture_road`]), solved at the `[static]` loads, and each
//! load's contact rebuilt on the asperities' real surfaces
//! ([`crate::two_scale`]).

use std::path::Path;
use std::sync::Arc;

use tyreroad_contact_law::Material;
use tyreroad_multipoint::{AsperitySet, Control, Problem, Solution, SolveError, solve};
use tyreroad_texture::HeightMap;

use super::height_checks::height_warnings;
use super::statics::{StaticResult, run_static_problem, run_static_problem_with, static_loads};
use super::{Scenario, ScenarioError, TextureSpec};
use crate::fidelity::compare::APPROACH_MARGIN;
use crate::fidelity::coupling::{FieldCouplingOptions, solve_field_coupled};
use crate::fidelity::rolling::{PastTables, calibrate_rolling_road_under};
use crate::fidelity::table_depth::TablePlan;
use crate::fidelity::{
    CalibratedLaw, CalibrationOptions, Calibrator, CapFallback, Coupling, FidelityError, LawSource,
    calibrated_set_or_wilke, solve_calibrated,
};
use crate::texture_road::{
    PastCap, TextureLaw, TextureRoad, TextureRoadError, TextureRoadOptions, pressed_past_caps,
    rolling_road, texture_road,
};
use crate::two_scale::{TwoScale, TwoScaleError, TwoScaleOptions, two_scale};

/// What the segmentation made of a height map.
#[derive(Clone, Debug, PartialEq)]
pub struct TextureSummary {
    /// Points along x and y.
    pub size: (usize, usize),
    /// Grid spacing along x and y (m).
    pub spacing: (f64, f64),
    /// Extent along x and y (m).
    pub extent: (f64, f64),
    /// Sq (m), NaN when the map has no valid point.
    pub rms: f64,
    /// The map's highest valid point (m): the plane a static or rolling run
    /// on the texture measures its approach from
    /// ([`crate::texture_road::TextureRoad::top`]).
    pub top: f64,
    /// Asperities kept (with a depth range).
    pub asperities: usize,
    /// Asperities the segmentation found.
    pub segmented: usize,
    /// The calibration of a run on calibrated laws (`None` on the Wilke
    /// laws).
    pub calibration: Option<CalibrationSummary>,
    /// What looks wrong with the heights, for a run's report: cells far
    /// outside the rest (sentinel values, spikes) or a roughness no road
    /// has (heights in another unit than metres). The run goes on.
    pub warnings: Vec<String>,
}

impl TextureSummary {
    /// Warns when the tread's footprint, at some step of `config`'s path,
    /// reaches off the map (x from 0 to the extent, y centred on the map's
    /// mid-width, as a rolling road places it): no asperity lies there,
    /// so the part off the map carries nothing and the load rests on the
    /// rest, a footprint unlike the tyre's.
    pub(crate) fn warn_of_footprint_off_map(&mut self, config: &tyreroad_rolling::RollingConfig) {
        self.warnings.extend(footprint_off_road(
            config,
            (self.extent, self.spacing),
            ("map", "give a larger map"),
        ));
    }
}

/// The warning of a rolling path whose footprint reaches off a road of
/// `extent` (m; x from 0, y centred on 0) sampled every `cell` (m) —
/// `noun` names the road ("map"), `remedy` the user's third way out — or
/// `None` when it stays on. A sliver off the road is no matter (a 150 mm
/// tyre on a 149.75 mm map: its edges carry next to nothing); a tenth of
/// the footprint's half, or two cells, is.
pub(crate) fn footprint_off_road(
    config: &tyreroad_rolling::RollingConfig,
    ((ex, ey), (cx, cy)): ((f64, f64), (f64, f64)),
    (noun, remedy): (&str, &str),
) -> Option<String> {
    let (hx, hy) = config.tread.half_extents();
    let along = (
        config.start.min(config.end) - hx,
        config.start.max(config.end) + hx,
    );
    let across = (config.lateral - hy, config.lateral + hy);
    let (sx, sy) = ((0.1 * hx).max(2.0 * cx), (0.1 * hy).max(2.0 * cy));
    if along.0 >= -sx
        && along.1 <= ex + sx
        && across.0 >= -0.5 * ey - sy
        && across.1 <= 0.5 * ey + sy
    {
        return None;
    }
    let mm = |v: f64| v * 1e3;
    Some(format!(
        "the tread's footprint ({:.1} × {:.1} mm) reaches off the {noun} ({:.1} × {:.1} mm) \
         along the path: it covers x = {:.1} … {:.1} mm and y = {:.1} … {:.1} mm, the {noun} \
         x = 0 … {:.1} mm and y = {:.1} … {:.1} mm; no asperity lies off the {noun}, so the \
         load rests on the part that is on it (shorten the path, narrow the tread, or \
         {remedy})",
        mm(2.0 * hx),
        mm(2.0 * hy),
        mm(ex),
        mm(ey),
        mm(along.0),
        mm(along.1),
        mm(across.0),
        mm(across.1),
        mm(ex),
        mm(-0.5 * ey),
        mm(0.5 * ey),
    ))
}

/// What calibrating a texture's caps took: a static run's every cap, a
/// rolling run's caps its path can select (`crate::fidelity::rolling`).
#[derive(Clone, Debug, PartialEq)]
pub struct CalibrationSummary {
    /// Asperities given a calibrated law (or, failing that, their Wilke
    /// law: `fallbacks`).
    pub asperities: usize,
    /// Tables solved by the BEM (the rest were equal caps' tables or read
    /// from the disk cache).
    pub tables: usize,
    /// Tables read from the disk cache.
    pub from_disk: usize,
    /// Largest approach the tables cover (m; from the highest summit).
    pub max_approach: f64,
    /// The largest bulk sag taken off the tables' depths (m; 0 when every
    /// table reaches the bound, `crate::fidelity::table_depth`).
    pub bulk_sag: f64,
    /// Tables redone to the bound because a run pressed their caps past
    /// the estimated depth; the run was repeated on them (0: run once).
    pub deepened: usize,
    /// Wall time of the approach bound and the calibration (of every
    /// round, when a run was repeated).
    pub time: std::time::Duration,
    /// Contacts the run pressed past their tables (filled once a whole
    /// elastic run is rolled; not counted, so zero, for a part of a
    /// distributed run and for a viscoelastic run, whose forces are not
    /// its laws' at one depth, and for a static run).
    pub past_tables: PastTables,
    /// The caps whose calibration failed: each kept its Wilke law and the
    /// run went on (of the last round, when a run was repeated).
    pub fallbacks: Vec<CapFallback>,
    /// Whether the tables kept their pressure fields (`calibrated_fields`):
    /// near pairs are then coupled through them, not by point forces.
    pub fields: bool,
}

impl CalibrationSummary {
    /// What a run's user is warned of: the contacts pressed past their
    /// tables, then each cap that kept its Wilke law (empty when neither).
    pub fn warnings(&self) -> Vec<String> {
        self.past_tables
            .warning()
            .into_iter()
            .chain(self.fallbacks.iter().map(ToString::to_string))
            .collect()
    }

    /// How deep the tables reached, for a run's report: the bulk sag taken
    /// off them and the caps tabulated again to the bound (`None` when the
    /// tables reach the bound).
    pub fn depth_note(&self) -> Option<String> {
        (self.bulk_sag > 0.0).then(|| {
            let repeated = match self.deepened {
                0 => "no contact passed them".to_string(),
                n => format!(
                    "{n} cap(s) a run pressed past them tabulated again to the bound and the run repeated"
                ),
            };
            format!(
                "tables to each cap's estimated depth, the tread's bulk sag (up to {:.3} mm) \
                 taken off: {repeated}",
                self.bulk_sag * 1e3
            )
        })
    }
}

impl TextureSummary {
    /// The summary of `road` segmented from `map`; `read_notes` are what
    /// reading the map changed ([`TextureSpec::height_map_and_notes`]).
    fn new(map: &HeightMap, road: &TextureRoad, read_notes: Vec<String>) -> Self {
        Self {
            size: (map.nx(), map.ny()),
            spacing: (map.dx(), map.dy()),
            extent: (map.length_x(), map.length_y()),
            rms: map.rms().unwrap_or(f64::NAN),
            top: road.top,
            asperities: road.len(),
            segmented: road.segmentation.asperities().len(),
            calibration: None,
            warnings: read_notes.into_iter().chain(height_warnings(map)).collect(),
        }
    }
}

/// One load of a texture run: the two-scale rebuild of its contacts.
#[derive(Clone, Debug)]
pub struct TextureLoad {
    /// Imposed load (N).
    pub load: f64,
    /// Local fields (one per asperity, asperity order) and the assembled
    /// pressure map at the texture's grid spacing.
    pub two_scale: TwoScale,
    /// The asperities pressed past the depth their caps are tabulated to
    /// (whole basin in contact: the law's answer is an extrapolation).
    pub past_caps: Vec<PastCap>,
    /// What a reader of this load's outputs should know (a pressure map
    /// coarser than the texture's spacing).
    pub notes: Vec<String>,
}

/// A static run on a texture.
#[derive(Clone, Debug)]
pub struct TextureResult {
    /// The height map the asperities were taken from.
    pub map: Arc<HeightMap>,
    /// The texture and its segmentation.
    pub texture: TextureSummary,
    /// Multipoint rows (indenter = asperity index + 1, highest summit first;
    /// the radius is the half-section rule's) and per-load reports.
    pub statics: StaticResult,
    /// The two-scale rebuild of each load, in load order.
    pub loads: Vec<TextureLoad>,
}

impl TextureResult {
    /// Asperity labels, 1-based in the segmentation's order.
    pub fn ids(&self) -> Vec<u32> {
        (1..=self.texture.asperities as u32).collect()
    }
}

/// Runs a scenario's `[static]` loads on its `[texture]`; `base_dir` is
/// where `[texture] file` is resolved.
pub(crate) fn run_texture_static(
    scenario: &Scenario,
    base_dir: &Path,
) -> Result<TextureResult, ScenarioError> {
    let Some(texture) = &scenario.texture else {
        return Err(ScenarioError::Invalid(format!(
            "scenario {}: needs [texture] and [static]",
            scenario.name
        )));
    };
    let loads = static_loads(scenario)?;
    let (map, read_notes) = texture.height_map_and_notes(base_dir)?;
    let map = Arc::new(map);
    let material = scenario.material()?;
    let road = scenario_road(&map, material, texture, scenario.solver_options().par)?;
    let mut summary = TextureSummary::new(&map, &road, read_notes);
    let shapes = road.local_shapes(&map)?;
    let positions = road.set.positions().to_vec();
    // The solver measures its approach from the highest summit; a texture
    // run reports it from the map's highest point, as the BEM and a
    // rolling run on the same map do (`TextureRoad::top`).
    let plane_shift = road.top - road.set.top();
    let cap_depths = road.cap_depths();
    let ids: Vec<u32> = (1..=road.len() as u32).collect();
    let as_problem = |context: &str| {
        let context = context.to_string();
        move |source| ScenarioError::Solve { context, source }
    };
    let rung = scenario.fidelity()?.rung(&scenario.solver_options())?;
    let heights_said = summary.warnings.clone();
    let solved = match rung.laws {
        LawSource::Potential => {
            let problem = Problem::from_set(road.set, material)
                .map_err(as_problem("[texture] asperities"))?;
            run_static_problem(&scenario.name, &problem, &ids, &loads, &rung.solver)
                .map_err(|e| with_height_warnings(e, &heights_said))?
        }
        LawSource::Calibrated => {
            // The tables must cover the approaches in use: the Wilke
            // model's at the largest load, with a margin (beyond a table
            // the law continues linearly, so a deeper solve still works).
            let wilke = Problem::from_set(road.set.clone(), material)
                .map_err(as_problem("[texture] asperities"))?;
            let heaviest = loads.iter().copied().fold(0.0, f64::max);
            let approach = solve(&wilke, Control::Load(heaviest), &rung.solver)
                .map_err(as_problem(
                    "[model] fidelity: the approach range of the calibration",
                ))?
                .approach;
            let mut calibrator = Calibrator::new(material, CalibrationOptions::default());
            if rung.coupling == Coupling::Fields {
                calibrator = calibrator.with_fields();
            }
            let clock = std::time::Instant::now();
            let max_approach = APPROACH_MARGIN * approach;
            let (set, fallbacks) = calibrated_set_or_wilke(&road, &map, max_approach, &calibrator)?;
            let counts = calibrator.counts();
            summary.calibration = Some(CalibrationSummary {
                asperities: road.len(),
                tables: counts.solved,
                from_disk: counts.disk_hits,
                max_approach,
                bulk_sag: 0.0,
                deepened: 0,
                time: clock.elapsed(),
                past_tables: PastTables::default(),
                fallbacks,
                fields: calibrator.has_fields(),
            });
            let problem =
                Problem::from_set(set, material).map_err(as_problem("[texture] asperities"))?;
            match rung.coupling {
                // Tiles of one plateau are one body (crate::fidelity::joint):
                // the point kernel between them is cancelled.
                Coupling::Solver => {
                    run_static_problem_with(&scenario.name, &problem, &ids, &loads, |load| {
                        match solve_calibrated(&problem, Control::Load(load), &rung.solver, None) {
                            Ok(s) => Ok(Ok(s)),
                            Err(e @ FidelityError::Solve(SolveError::NotConverged { .. })) => {
                                Ok(Err(e.to_string()))
                            }
                            Err(e) => Err(ScenarioError::Invalid(format!(
                                "{}: solving at {load} N: {e}",
                                scenario.name
                            ))),
                        }
                    })
                    .map_err(|e| with_height_warnings(e, &heights_said))?
                }
                // Each load its own fixed point of the field coupling
                // (crate::fidelity::coupling), warm-started from the
                // previous load's solution.
                Coupling::Fields => {
                    let mut previous: Option<Solution> = None;
                    let coupling = FieldCouplingOptions::default();
                    run_static_problem_with(&scenario.name, &problem, &ids, &loads, |load| {
                        let solved = solve_field_coupled(
                            &problem,
                            Control::Load(load),
                            &rung.solver,
                            &coupling,
                            previous.as_ref(),
                        );
                        match solved {
                            Ok(f) => {
                                previous = Some(f.solution.clone());
                                Ok(Ok(f.solution))
                            }
                            Err(
                                e @ (FidelityError::FieldCoupling { .. }
                                | FidelityError::Solve(SolveError::NotConverged { .. })),
                            ) => Ok(Err(e.to_string())),
                            Err(e) => Err(ScenarioError::Invalid(format!(
                                "{}: solving at {load} N with the field coupling: {e}",
                                scenario.name
                            ))),
                        }
                    })
                    .map_err(|e| with_height_warnings(e, &heights_said))?
                }
            }
        }
    };
    let spacing = map.dx().min(map.dy());
    let options = TwoScaleOptions {
        map_cell: Some(spacing),
        ..TwoScaleOptions::default()
    };
    let mut statics = solved.result;
    for run in &mut statics.runs {
        run.approach += plane_shift;
    }
    let mut per_load = Vec::with_capacity(statics.runs.len());
    for (k, (r, depths)) in statics.runs.iter().zip(&solved.depths).enumerate() {
        let forces: Vec<f64> = statics.rows_of_run(k).iter().map(|row| row.force).collect();
        let as_scenario_error = |source| ScenarioError::TwoScale {
            context: format!("two-scale pressure map at {} N", r.load),
            source,
        };
        let mut notes = Vec::new();
        let ts = match two_scale(&positions, &forces, &shapes, &material, &options) {
            // A load whose contacts spread too far for a map at the
            // texture's spacing gets a coarser map, not the run's failure.
            Err(TwoScaleError::MapTooLarge { cells, limit }) => {
                let cell = spacing * (cells as f64 / limit as f64).sqrt() * 1.05;
                notes.push(format!(
                    "pressure map on {:.3} mm cells, not the texture's {:.3} mm: at its spacing \
                     the map would have {cells} cells, more than the limit {limit}",
                    cell * 1e3,
                    spacing * 1e3
                ));
                let coarser = TwoScaleOptions {
                    map_cell: Some(cell),
                    ..options.clone()
                };
                two_scale(&positions, &forces, &shapes, &material, &coarser)
                    .map_err(as_scenario_error)?
            }
            other => other.map_err(as_scenario_error)?,
        };
        per_load.push(TextureLoad {
            load: r.load,
            two_scale: ts,
            past_caps: pressed_past_caps(&cap_depths, depths),
            notes,
        });
    }
    Ok(TextureResult {
        map,
        texture: summary,
        statics,
        loads: per_load,
    })
}

/// A run's error with what looked wrong with the heights, when something
/// did: a run that fails outright (no load solved) never reaches the report
/// where those warnings are printed, and they are often its cause (heights
/// of 1e100 m fail the solver with a bare residual).
fn with_height_warnings(error: ScenarioError, warnings: &[String]) -> ScenarioError {
    if warnings.is_empty() {
        return error;
    }
    ScenarioError::Invalid(format!("{error} (the heights: {})", warnings.join("; ")))
}

/// The texture's asperities, with "no asperity" said in the scenario's
/// terms: which keys decide it and what the map was.
pub(super) fn scenario_road(
    map: &HeightMap,
    material: Material,
    texture: &TextureSpec,
    par: tyreroad_multipoint::Par,
) -> Result<TextureRoad, ScenarioError> {
    let options = TextureRoadOptions {
        par,
        ..texture.road_options()
    };
    texture_road(map, material, &options).map_err(|e| match e {
        TextureRoadError::NoAsperity { segmented } => ScenarioError::Value {
            key: "[texture] min_prominence, min_area (and the map's size)".into(),
            value: format!(
                "{} × {} points at {:e} × {:e} m: {segmented} segmented, none with a depth range",
                map.nx(),
                map.ny(),
                map.dx(),
                map.dy()
            ),
            expected: "a map large enough to hold asperities, or lower min_prominence / min_area"
                .into(),
        },
        other => other.into(),
    })
}

/// The road of a `[texture]` rolling scenario: the texture's asperities with
/// x along the map's x from its first column and y centred on the map's
/// mid-width, so a path at `lateral = 0` runs down the middle of the
/// texture; and each asperity's summit radius (m, set order), for the
/// contact-point gaps ([`tyreroad_rolling::Road::with_summit_radii`]).
pub(crate) fn texture_road_set(
    texture: &TextureSpec,
    base_dir: &Path,
    material: Material,
    par: tyreroad_multipoint::Par,
) -> Result<(AsperitySet<TextureLaw>, TextureSummary, Vec<f64>), ScenarioError> {
    let (map, read_notes) = texture.height_map_and_notes(base_dir)?;
    let road = scenario_road(&map, material, texture, par)?;
    let summary = TextureSummary::new(&map, &road, read_notes);
    let radii = road.summit_radii();
    Ok((centred_on_mid_width(road.set, &map)?, summary, radii))
}

/// `set` moved so that y is centred on the map's mid-width (x unchanged):
/// a rolling path at `lateral = 0` runs down the middle of the texture.
fn centred_on_mid_width<L>(
    set: AsperitySet<L>,
    map: &HeightMap,
) -> Result<AsperitySet<L>, ScenarioError> {
    let y_mid = 0.5 * (map.ny() - 1) as f64 * map.dy();
    set.translated([0.0, -y_mid])
        .map_err(|source| ScenarioError::Solve {
            context: "[texture] road".into(),
            source,
        })
}

/// [`texture_road_set`] with its asperities in the rolling order
/// ([`crate::texture_road::TextureRoad::rolling_order`]: by block of
/// columns, so that a `.npy` road read by windows gives the same ids,
/// docs/distributed.md, "Road windows").
pub(crate) fn rolling_texture_road_set(
    texture: &TextureSpec,
    base_dir: &Path,
    material: Material,
    par: tyreroad_multipoint::Par,
) -> Result<(AsperitySet<TextureLaw>, TextureSummary, Vec<f64>), ScenarioError> {
    let (map, read_notes) = texture.height_map_and_notes(base_dir)?;
    let road = scenario_road(&map, material, texture, par)?;
    let summary = TextureSummary::new(&map, &road, read_notes);
    let (set, radii) = road.rolling_set()?;
    Ok((centred_on_mid_width(set, &map)?, summary, radii))
}

/// [`texture_road_set`] with calibrated laws, for `[model] fidelity =
/// "calibrated"` in rolling: the asperities `config`'s path can select, in
/// the same frame and order, each with its cap's BEM-calibrated law,
/// calibrated once on `par`'s threads (`crate::fidelity::rolling`);
/// tables are kept in and read back from `cache` when given.
pub(crate) fn calibrated_texture_road_set(
    texture: &TextureSpec,
    base_dir: &Path,
    material: Material,
    config: &tyreroad_rolling::RollingConfig,
    par: tyreroad_multipoint::Par,
    cache: Option<&Path>,
    plan: &TablePlan,
) -> Result<(AsperitySet<CalibratedLaw>, TextureSummary, Vec<f64>), ScenarioError> {
    let calibrator = rolling_calibrator(material, cache, false);
    calibrated_texture_road_set_with(texture, base_dir, config, par, &calibrator, plan)
}

/// The calibrator of a rolling road's laws: the default options, the
/// tables keeping their binned pressure fields when `fields` (`[model]
/// fidelity = "calibrated_fields"`), kept in and read back from `cache`
/// when given.
pub(crate) fn rolling_calibrator(
    material: Material,
    cache: Option<&Path>,
    fields: bool,
) -> Calibrator {
    let mut calibrator = Calibrator::new(material, CalibrationOptions::default());
    if fields {
        calibrator = calibrator.with_fields();
    }
    if let Some(dir) = cache {
        calibrator = calibrator.with_disk_cache(dir);
    }
    calibrator
}

/// [`calibrated_texture_road_set`] by `calibrator` (on its material, with
/// fields when it keeps them, [`rolling_calibrator`]; a calibrator used
/// again solves only the tables it has not solved yet), each cap under and
/// as deep as `plan` says (`[model] calibrate_under`,
/// `crate::fidelity::under_tread`, `crate::fidelity::table_depth`).
pub(crate) fn calibrated_texture_road_set_with(
    texture: &TextureSpec,
    base_dir: &Path,
    config: &tyreroad_rolling::RollingConfig,
    par: tyreroad_multipoint::Par,
    calibrator: &Calibrator,
    plan: &TablePlan,
) -> Result<(AsperitySet<CalibratedLaw>, TextureSummary, Vec<f64>), ScenarioError> {
    let material = *calibrator.material();
    let (map, read_notes) = texture.height_map_and_notes(base_dir)?;
    let road = scenario_road(&map, material, texture, par)?;
    let mut summary = TextureSummary::new(&map, &road, read_notes);
    let radii = road.summit_radii();
    let set = centred_on_mid_width(road.set.clone(), &map)?;
    let wilke = rolling_road(set, radii.clone(), summary.top)?;
    let calibrated = calibrate_rolling_road_under(
        &road, &wilke, &map, config, calibrator, par, plan,
    )
    .map_err(|e| match e {
        // The Wilke run that bounds the tables met a step the road does
        // not reach: the path misses the road, as a Wilke run says.
        FidelityError::Rolling(tyreroad_rolling::RollingError::NoSupport { position }) => {
            ScenarioError::off_road(wilke.positions(), false, config.lateral, position)
        }
        other => other.into(),
    })?;
    let radii = calibrated.kept.iter().map(|&i| radii[i]).collect();
    summary.calibration = Some(CalibrationSummary {
        asperities: calibrated.kept.len(),
        tables: calibrated.counts.solved,
        from_disk: calibrated.counts.disk_hits,
        max_approach: calibrated.max_approach,
        bulk_sag: calibrated.bulk_sag,
        deepened: plan.deepen.len(),
        time: calibrated.time,
        past_tables: PastTables::default(),
        fallbacks: calibrated.fallbacks,
        fields: calibrator.has_fields(),
    });
    Ok((calibrated.set, summary, radii))
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The synthetic road kinds and the fixtures' texture files are roads:
    /// none is warned of (pores, grooves and joints lie within the span).
    #[test]
    fn no_road_the_project_makes_or_ships_is_warned_of() {
        let kinds = [
            "kind = \"aggregate\"\ngrading = \"4/6\"\n",
            "kind = \"self_affine\"\nrms = \"0.4 mm\"\nhurst = 0.7\nlambda_long = \"20 mm\"\n\
             lambda_short = \"0.5 mm\"\n",
            "kind = \"transverse_tining\"\n",
            "kind = \"longitudinal_tining\"\n",
            "kind = \"brushed_concrete\"\n",
            "kind = \"exposed_aggregate\"\n",
            "kind = \"porous_asphalt\"\n",
            "kind = \"worn_chip_seal\"\n",
            "kind = \"pave\"\n",
        ];
        let fixtures = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("fixtures");
        let textures = kinds
            .iter()
            .map(|k| {
                format!("[texture.synth]\n{k}nx = 400\nny = 300\nspacing = \"0.1 mm\"\nseed = 7\n")
            })
            .chain(["sine.asc", "spheres.x3p"].map(|f| format!("file = \"texture/{f}\"\n")));
        let mut checked = 0;
        for texture in textures {
            checked += 1;
            let text = format!(
                "name = \"t\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                 [static]\nloads = [\"50 N\"]\n[texture]\nmin_prominence = \"0.2 mm\"\n\
                 min_area = \"2 mm2\"\n{texture}"
            );
            let scenario = Scenario::parse(&text, "kind").expect("a valid scenario");
            let map = scenario
                .texture
                .as_ref()
                .expect("[texture]")
                .height_map(&fixtures)
                .expect("a map");
            assert!(
                height_warnings(&map).is_empty(),
                "{texture}: {:?}",
                height_warnings(&map)
            );
            // Their flat mortar, void bottoms and joints repeat one height
            // each, within reach of the rest: no "no data" marker.
            assert_eq!(tyreroad_texture::find_sentinels(&map), vec![], "{texture}");
        }
        assert_eq!(checked, 11);
    }
}
