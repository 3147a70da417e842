//! Each rung against the full BEM on one texture (docs/validation.md,
//! "Fidelity on textures"): the metrics of issue 15.
//!
//! Reference: the non-periodic BEM (`tyreroad-bem`) on the whole height map
//! (invalid points filled), loads ascending, each warm-started from the
//! previous pressure. Per load and rung:
//!
//! - load–approach error `(δ_model − δ_BEM)/δ_BEM`, both approaches from the
//!   map's highest grid point (the model's is shifted by the refined summit's
//!   height above it);
//! - total contact area error `(A_model − A_BEM)/A_BEM`, the model's area
//!   being each asperity's own single-asperity BEM area at its force: the
//!   two-scale rebuild for `wilke`, the calibrated table's `A(δ_i)` for
//!   `calibrated` (the same single-asperity solve, tabulated);
//! - load on the wrong asperity, 10 mm block and 5 mm block:
//!   `½ Σ |F_model − F_BEM| / W` over basins or square blocks from the map's
//!   origin (BEM: pressure summed over the cells; model: each asperity's
//!   force at its summit, and, as fields, each asperity's two-scale
//!   pressure, a BEM solve of its own cap under its force, summed over the
//!   blocks: [`field_blocks`]);
//! - cost: the model's solve time and the BEM's on the same grid.
//!
//! Beside the numbers, what they cannot say: a row's warnings (summits
//! inside each other's contact patch, where the point coupling is far too
//! stiff: [`RungLoad::warnings`]) and the reference's notes (missing
//! points filled, a contact pressed flat or unresolved, one asperity:
//! [`reference_notes`]). A table of small errors is no validation when
//! either says something.
//!
//! The law-only error: each asperity's BEM force is carried by the
//! calibrated law at depth `δ_i*`; the Wilke law at `δ_i*` gives a force;
//! `½ Σ |F_wilke(δ_i*) − F_BEM,i| / W` is what the law alone gets wrong
//! when the interaction is exact (the reverse of `calibrated`, which keeps
//! the point interaction with exact laws).

use std::time::Instant;

use crate::bem::{self, BemOptions, Grid, Solver};
use crate::contact_law::{ContactLaw, Material};
use crate::multipoint::{Control, Problem, Solution, SolverOptions, overlapping_contacts, solve};
use crate::texture::{HeightMap, UNLABELLED};
use crate::texture_road::{TextureRoad, TextureRoadOptions, texture_road};
use crate::two_scale::{LocalShape, TwoScale, TwoScaleOptions, two_scale_solution};

use super::coupling::{FieldCouplingOptions, solve_field_coupled};
pub use super::reference_notes::reference_notes;
use super::{
    CacheCounts, CalibrationOptions, Calibrator, Coupling, Fidelity, FidelityError, LawSource,
    calibrated_set, solve_calibrated,
};

/// Block sizes of the block metrics (m).
pub const BLOCKS: [f64; 2] = [10e-3, 5e-3];

/// The largest approach a calibration table covers, over the largest
/// approach seen (BEM or model): room for the model to land deeper.
pub const APPROACH_MARGIN: f64 = 1.3;

/// What to compare.
#[derive(Clone, Debug)]
pub struct CompareOptions {
    /// Loads (N), solved in increasing order, each once (a repeat is
    /// said in [`TextureComparison::notes`]).
    pub loads: Vec<f64>,
    /// Segmentation and Wilke law.
    pub road: TextureRoadOptions,
    /// Calibration solves.
    pub calibration: CalibrationOptions,
    /// Rungs to run, in order.
    pub rungs: Vec<Fidelity>,
    /// Base solver options of every rung.
    pub solver: SolverOptions,
    /// Passes of the two-scale rebuild (the block fields) that solve each
    /// cap again under its neighbours' displacement
    /// ([`TwoScaleOptions::neighbour_passes`]); 0: each cap alone.
    pub neighbour_passes: usize,
}

/// One load of the BEM reference.
#[derive(Clone, Debug)]
pub struct BemLoad {
    /// Load (N).
    pub load: f64,
    /// Approach from the highest grid point (m).
    pub approach: f64,
    /// Contact area (m²).
    pub contact_area: f64,
    /// Force per kept asperity's basin (N), asperity order.
    pub asperity_forces: Vec<f64>,
    /// Force on no kept asperity's basin (N).
    pub off_asperity: f64,
    /// Force on the map's missing points, filled for the BEM (N).
    pub on_missing: f64,
    /// Force per block of each size of [`BLOCKS`] (N).
    pub block_forces: [Vec<f64>; 2],
    /// CG iterations.
    pub iterations: usize,
    /// Solve time (s).
    pub seconds: f64,
}

/// One load of one rung against the BEM.
#[derive(Clone, Debug, PartialEq)]
pub struct RungLoad {
    /// Load (N).
    pub load: f64,
    /// `(δ_model − δ_BEM)/δ_BEM`.
    pub approach_error: f64,
    /// `(A_model − A_BEM)/A_BEM`.
    pub area_error: f64,
    /// Load on the wrong asperity (fraction of W).
    pub wrong_asperity: f64,
    /// Load on the wrong block, per size of [`BLOCKS`] (fraction of W),
    /// each asperity's force at its summit.
    pub wrong_block: [f64; 2],
    /// The same with the model's forces as fields: each asperity's
    /// two-scale pressure (a BEM solve of its own cap under its force,
    /// [`crate::two_scale`]) integrated over the blocks ([`field_blocks`]);
    /// NaN when the rung was run without shapes.
    pub field_block: [f64; 2],
    /// Model solve time (s).
    pub seconds: f64,
    /// Rounds of the field coupling's fixed point (0 for the other
    /// couplings).
    pub coupling_rounds: usize,
    /// The BEM's solve time at this load (s).
    pub bem_seconds: f64,
    /// What makes this load's answer no road's (summits inside each
    /// other's contact patch, where the point coupling is far too stiff).
    pub warnings: Vec<String>,
}

/// One rung on the texture.
#[derive(Clone, Debug)]
pub struct RungResult {
    /// The rung.
    pub fidelity: Fidelity,
    /// Building its laws (s): the calibration solves for `calibrated`.
    pub setup_seconds: f64,
    /// Per load: the metrics, or why it failed (that load's failure only).
    pub loads: Vec<Result<RungLoad, String>>,
    /// Why the rung did not run at all.
    pub unavailable: Option<String>,
}

/// Every rung on one texture.
#[derive(Clone, Debug)]
pub struct TextureComparison {
    /// Asperities kept.
    pub asperities: usize,
    /// BEM cells.
    pub bem_cells: usize,
    /// The reference, per load.
    pub bem: Vec<BemLoad>,
    /// One entry per rung asked for.
    pub rungs: Vec<RungResult>,
    /// Law-only wrong-asperity load per load (see the module docs); empty
    /// without the calibrated rung.
    pub law_only: Vec<f64>,
    /// The calibration cache's counts.
    pub cache: CacheCounts,
    /// What the reference itself cannot say ([`reference_notes`]).
    pub notes: Vec<String>,
}

/// Labels of the map's cells: the kept asperity's index, `n` elsewhere.
fn basin_labels(road: &TextureRoad) -> Vec<usize> {
    let n = road.len();
    let seg = &road.segmentation;
    let mut to_kept = vec![n; seg.asperities().len()];
    for (i, &k) in road.asperity_index.iter().enumerate() {
        to_kept[k] = i;
    }
    seg.labels()
        .iter()
        .map(|&l| {
            if l == UNLABELLED {
                n
            } else {
                to_kept[l as usize]
            }
        })
        .collect()
}

/// Block of a point: square blocks of `size` from the origin, row-major.
fn block_of(x: f64, y: f64, size: f64, per_row: usize) -> usize {
    // The small shift keeps a point on a block edge (a cell centre at an
    // exact multiple) in one block whatever the rounding of `i·dx`.
    let bx = (x / size + 1e-9).floor().max(0.0) as usize;
    let by = (y / size + 1e-9).floor().max(0.0) as usize;
    by * per_row + bx.min(per_row - 1)
}

fn blocks_per_row(map: &HeightMap, size: f64) -> (usize, usize) {
    let n = |len: f64| ((len / size - 1e-9).ceil() as usize).max(1);
    (n(map.nx() as f64 * map.dx()), n(map.ny() as f64 * map.dy()))
}

/// Half the summed absolute difference over the total load.
pub fn wrong_load(model: &[f64], reference: &[f64], load: f64) -> f64 {
    0.5 * model
        .iter()
        .zip(reference)
        .map(|(a, b)| (a - b).abs())
        .sum::<f64>()
        / load
}

fn point_blocks(positions: &[[f64; 2]], forces: &[f64], map: &HeightMap, size: f64) -> Vec<f64> {
    let (bx, by) = blocks_per_row(map, size);
    let mut out = vec![0.0; bx * by];
    for (p, f) in positions.iter().zip(forces) {
        out[block_of(p[0], p[1], size, bx).min(bx * by - 1)] += f;
    }
    out
}

/// Block forces (N) of a two-scale rebuild: every local pressure field
/// integrated over square blocks of `size` from the map's origin. Each
/// local cell (a fraction of the patch, finer than the map's) is counted
/// whole in the block of the map cell holding its centre, so that fields
/// and the BEM (whose map cells each fall in one block) split a patch at
/// the same line. A patch reaching past the map's edge is counted in the
/// edge block, as the point accounting does; the blocks sum to the forces
/// carried.
pub fn field_blocks(two: &TwoScale, map: &HeightMap, size: f64) -> Vec<f64> {
    let (bx, by) = blocks_per_row(map, size);
    let mut out = vec![0.0; bx * by];
    let block = |v: f64, cell: f64, n: usize| {
        let centre = (v / cell).round() * cell;
        ((centre / size + 1e-9).floor().max(0.0) as usize).min(n - 1)
    };
    for field in two.local.iter().filter_map(|l| l.field.as_ref()) {
        let g = field.grid();
        let cell = g.cell_area();
        for (k, &p) in field.values().iter().enumerate() {
            if p > 0.0 {
                let (i, j) = g.cell(k);
                let (ix, iy) = (block(g.x(i), map.dx(), bx), block(g.y(j), map.dy(), by));
                out[iy * bx + ix] += p * cell;
            }
        }
    }
    out
}

fn bem_reference(
    map: &HeightMap,
    road: &TextureRoad,
    material: &Material,
    loads: &[f64],
) -> Result<Vec<BemLoad>, FidelityError> {
    let err = |context: &'static str| move |source| FidelityError::Bem { context, source };
    let grid = Grid::new(map.nx(), map.ny(), map.dx(), map.dy())
        .map_err(|e| FidelityError::invalid("BEM grid", e, "a valid grid"))?;
    let filled = map
        .filled()
        .map_err(crate::texture_road::TextureRoadError::from)?;
    let surface = bem::HeightMap::new(grid.clone(), filled.heights().to_vec())
        .map_err(|e| FidelityError::invalid("BEM surface", e, "a valid field"))?;
    let labels = basin_labels(road);
    let n = road.len();
    let cell_blocks: Vec<Vec<usize>> = BLOCKS
        .iter()
        .map(|&size| {
            let (bx, _) = blocks_per_row(map, size);
            (0..grid.len())
                .map(|c| {
                    let (i, j) = (c % map.nx(), c / map.nx());
                    block_of(i as f64 * map.dx(), j as f64 * map.dy(), size, bx)
                })
                .collect()
        })
        .collect();
    let mut solver =
        Solver::new(&grid, material, &BemOptions::default()).map_err(err("BEM set-up"))?;
    let mut previous: Option<Vec<f64>> = None;
    let mut out = Vec::with_capacity(loads.len());
    for &load in loads {
        let t = Instant::now();
        let sol = match &previous {
            Some(p) => solver.solve_from(&surface, bem::Control::Load(load), p),
            None => solver.solve(&surface, bem::Control::Load(load)),
        }
        .map_err(err("BEM texture solve"))?;
        let seconds = t.elapsed().as_secs_f64();
        let mut per_label = vec![0.0; n + 1];
        let cell = grid.cell_area();
        let mut on_missing = 0.0;
        for (c, p) in sol.pressure.iter().enumerate() {
            per_label[labels[c]] += p * cell;
            if !map.valid()[c] {
                on_missing += p * cell;
            }
        }
        let block_forces = [0, 1].map(|b| {
            let (bx, by) = blocks_per_row(map, BLOCKS[b]);
            let mut f = vec![0.0; bx * by];
            for (c, p) in sol.pressure.iter().enumerate() {
                f[cell_blocks[b][c]] += p * cell;
            }
            f
        });
        out.push(BemLoad {
            load,
            approach: sol.approach,
            contact_area: sol.contact_area,
            off_asperity: per_label[n],
            on_missing,
            asperity_forces: per_label[..n].to_vec(),
            block_forces,
            iterations: sol.iterations,
            seconds,
        });
        previous = Some(sol.pressure);
    }
    Ok(out)
}

/// How a rung solves one load.
type SolveLoad<'a> = dyn Fn(Control) -> Result<(Solution, usize), String> + Sync + 'a;

/// Solves `problem` at every BEM load (by `solve_load`, or the solver's
/// `solve` with `solver`) and measures it; `area` gives the
/// model's total contact area of a solution. With `shapes` (the
/// asperities' real caps, [`TextureRoad::local_shapes`]) each solution is
/// also rebuilt by [`two_scale_solution`], its block forces integrated from
/// that pressure ([`field_blocks`]), and `area` sees the rebuild.
#[allow(clippy::too_many_arguments)]
fn run_rung<L: ContactLaw + Sync>(
    problem: &Problem<L>,
    solver: &SolverOptions,
    solve_load: Option<&SolveLoad<'_>>,
    bem: &[BemLoad],
    map: &HeightMap,
    summit_above_grid: f64,
    shapes: Option<&[LocalShape]>,
    rebuild: &TwoScaleOptions,
    area: impl Fn(&Solution, Option<&TwoScale>) -> Result<f64, String>,
) -> Vec<Result<RungLoad, String>> {
    bem.iter()
        .map(|b| {
            let t = Instant::now();
            let (s, coupling_rounds) = match solve_load {
                Some(f) => f(Control::Load(b.load))?,
                None => (
                    solve(problem, Control::Load(b.load), solver).map_err(|e| e.to_string())?,
                    0,
                ),
            };
            let seconds = t.elapsed().as_secs_f64();
            let two = shapes
                .map(|shapes| {
                    two_scale_solution(problem, &s, shapes, rebuild)
                        .map_err(|e| format!("two-scale rebuild: {e}"))
                })
                .transpose()?;
            let a = area(&s, two.as_ref())?;
            let wrong_block = [0, 1].map(|k| {
                let m = point_blocks(problem.positions(), &s.forces, map, BLOCKS[k]);
                wrong_load(&m, &b.block_forces[k], b.load)
            });
            let field_block = [0, 1].map(|k| {
                two.as_ref().map_or(f64::NAN, |two| {
                    let m = field_blocks(two, map, BLOCKS[k]);
                    wrong_load(&m, &b.block_forces[k], b.load)
                })
            });
            let contacts = s.local_contacts(problem);
            let overlapping = overlapping_contacts(problem.positions(), &contacts);
            let ids: Vec<u32> = (1..=problem.len() as u32).collect();
            let warnings = crate::scenario::summits_inside_patches(
                b.load,
                problem.positions(),
                &contacts,
                &overlapping,
                &ids,
            )
            .into_iter()
            .collect();
            let mut with_off = s.forces.clone();
            with_off.push(0.0);
            let mut reference = b.asperity_forces.clone();
            reference.push(b.off_asperity);
            Ok(RungLoad {
                load: b.load,
                approach_error: (s.approach - summit_above_grid - b.approach) / b.approach,
                area_error: (a - b.contact_area) / b.contact_area,
                wrong_asperity: wrong_load(&with_off, &reference, b.load),
                wrong_block,
                field_block,
                seconds,
                coupling_rounds,
                bem_seconds: b.seconds,
                warnings,
            })
        })
        .collect()
}

/// Runs every rung of `options` on `map` against the BEM (module docs).
///
/// # Errors
/// A texture that cannot be segmented, a failed BEM solve or calibration.
/// A rung's failed load is recorded in its [`RungResult`], not returned.
pub fn compare_texture(
    map: &HeightMap,
    material: Material,
    options: &CompareOptions,
) -> Result<TextureComparison, FidelityError> {
    // Increasing (the BEM warm-starts each load from the last), each once:
    // a load listed twice is the same contact.
    let mut loads = options.loads.clone();
    loads.sort_by(f64::total_cmp);
    loads.dedup();
    let repeated = options.loads.len() - loads.len();
    let road = texture_road(map, material, &options.road)?;
    let grid_top = map
        .filled()
        .map_err(crate::texture_road::TextureRoadError::from)?
        .heights()
        .iter()
        .copied()
        .fold(f64::NEG_INFINITY, f64::max);
    let summit_above_grid = road.set.top() - grid_top;
    let bem = bem_reference(map, &road, &material, &loads)?;
    let wilke = Problem::from_set(road.set.clone(), material)?;
    let max_approach = APPROACH_MARGIN
        * bem
            .iter()
            .map(|b| b.approach + summit_above_grid)
            .fold(0.0, f64::max);
    let shapes = road.local_shapes(&std::sync::Arc::new(map.clone()))?;
    // Fields cost only their binning; one calibrator serves every rung.
    let needs_fields = options.rungs.iter().any(|f| {
        f.rung(&options.solver)
            .is_ok_and(|r| r.coupling == Coupling::Fields)
    });
    let calibrator = Calibrator::new(material, options.calibration);
    let calibrator = if needs_fields {
        calibrator.with_fields()
    } else {
        calibrator
    };
    // The metrics read the local fields, never the assembled map: it is
    // assembled at the texture's spacing, as a static run's is, so a road of
    // 100 mm does not ask for a map of 6e7 cells at the local cell.
    let rebuild = TwoScaleOptions {
        neighbour_passes: options.neighbour_passes,
        map_cell: Some(map.dx().min(map.dy())),
        ..TwoScaleOptions::default()
    };
    let mut calibrated: Option<(Problem<super::CalibratedLaw>, f64)> = None;
    let mut rungs = Vec::new();
    for &fidelity in &options.rungs {
        let rung = match fidelity.rung(&options.solver) {
            Ok(r) => r,
            Err(e) => {
                rungs.push(RungResult {
                    fidelity,
                    setup_seconds: 0.0,
                    loads: Vec::new(),
                    unavailable: Some(e.to_string()),
                });
                continue;
            }
        };
        let (setup_seconds, results) = match rung.laws {
            LawSource::Potential => {
                let area = |_: &Solution, two: Option<&TwoScale>| {
                    two.map(|t| t.local.iter().map(|f| f.contact_area).sum())
                        .ok_or_else(|| "no two-scale rebuild".to_string())
                };
                let r = run_rung(
                    &wilke,
                    &rung.solver,
                    None,
                    &bem,
                    map,
                    summit_above_grid,
                    Some(&shapes),
                    &rebuild,
                    area,
                );
                (0.0, r)
            }
            LawSource::Calibrated => {
                let t = Instant::now();
                let set = calibrated_set(&road, map, max_approach, &calibrator)?;
                let problem = Problem::from_set(set, material)?;
                let setup = t.elapsed().as_secs_f64();
                let area = |s: &Solution, _: Option<&TwoScale>| {
                    Ok(s.local_contacts(&problem).iter().map(|c| c.area()).sum())
                };
                let fields = |control| {
                    solve_field_coupled(
                        &problem,
                        control,
                        &rung.solver,
                        &FieldCouplingOptions::default(),
                        None,
                    )
                    .map(|f| (f.solution, f.rounds))
                    .map_err(|e| e.to_string())
                };
                // Tiles of one plateau are one body (super::joint): the
                // point kernel between them is cancelled.
                let tiled = |control| {
                    solve_calibrated(&problem, control, &rung.solver, None)
                        .map(|s| (s, 0))
                        .map_err(|e| e.to_string())
                };
                let solve_load: Option<&SolveLoad<'_>> = match rung.coupling {
                    Coupling::Solver => Some(&tiled),
                    Coupling::Fields => Some(&fields),
                };
                let r = run_rung(
                    &problem,
                    &rung.solver,
                    solve_load,
                    &bem,
                    map,
                    summit_above_grid,
                    Some(&shapes),
                    &rebuild,
                    area,
                );
                calibrated = Some((problem, setup));
                (setup, r)
            }
        };
        rungs.push(RungResult {
            fidelity,
            setup_seconds,
            loads: results,
            unavailable: None,
        });
    }
    let law_only = match &calibrated {
        Some((problem, _)) => bem
            .iter()
            .map(|b| {
                let wilke_forces: Vec<f64> = problem
                    .laws()
                    .iter()
                    .zip(wilke.laws())
                    .zip(&b.asperity_forces)
                    .map(|((cal, w), &f)| w.force(cal.depth_for(f)))
                    .collect();
                wrong_load(&wilke_forces, &b.asperity_forces, b.load)
            })
            .collect(),
        None => Vec::new(),
    };
    Ok(TextureComparison {
        notes: (repeated > 0)
            .then(|| format!("{repeated} load(s) listed more than once are compared once"))
            .into_iter()
            .chain(reference_notes(map, road.len(), &bem))
            .collect(),
        asperities: road.len(),
        bem_cells: map.nx() * map.ny(),
        bem,
        rungs,
        law_only,
        cache: calibrator.counts(),
    })
}

/// One grid of [`bem_resolution`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ResolutionRow {
    /// Cell size `[dx, dy]` (m).
    pub cell: [f64; 2],
    /// Approach from the grid's highest point (m).
    pub approach: f64,
    /// Contact area (m²).
    pub contact_area: f64,
    /// Load on the wrong 10 mm block against the finest grid (fraction of
    /// the load).
    pub wrong_block: f64,
}

/// The BEM's own resolution convergence on `map` at `load`: the map as
/// given, every second point (twice the cell each way), and bilinearly
/// refined to half the cell each way. The cells need not be square.
///
/// # Errors
/// A BEM failure, or a map that cannot be filled.
pub fn bem_resolution(
    map: &HeightMap,
    material: &Material,
    load: f64,
) -> Result<Vec<ResolutionRow>, FidelityError> {
    let filled = map
        .filled()
        .map_err(crate::texture_road::TextureRoadError::from)?;
    let (nx, ny, dx, dy) = (filled.nx(), filled.ny(), filled.dx(), filled.dy());
    let z = |i: usize, j: usize| filled.heights()[filled.index(i.min(nx - 1), j.min(ny - 1))];
    let coarse: Vec<f64> = (0..ny.div_ceil(2))
        .flat_map(|j| (0..nx.div_ceil(2)).map(move |i| (2 * i, 2 * j)))
        .map(|(i, j)| z(i, j))
        .collect();
    let fine: Vec<f64> = (0..2 * ny - 1)
        .flat_map(|j| (0..2 * nx - 1).map(move |i| (i, j)))
        .map(|(i, j)| {
            0.25 * (z(i / 2, j / 2)
                + z(i.div_ceil(2), j / 2)
                + z(i / 2, j.div_ceil(2))
                + z(i.div_ceil(2), j.div_ceil(2)))
        })
        .collect();
    let cases = [
        (nx.div_ceil(2), ny.div_ceil(2), [2.0 * dx, 2.0 * dy], coarse),
        (nx, ny, [dx, dy], filled.heights().to_vec()),
        (2 * nx - 1, 2 * ny - 1, [0.5 * dx, 0.5 * dy], fine),
    ];
    let mut solved = Vec::new();
    for (cx, cy, cell, heights) in cases {
        let err = |source| FidelityError::Bem {
            context: "BEM resolution study",
            source,
        };
        let grid = Grid::new(cx, cy, cell[0], cell[1])
            .map_err(|e| FidelityError::invalid("BEM grid", e, "a valid grid"))?;
        let surface = bem::HeightMap::new(grid.clone(), heights)
            .map_err(|e| FidelityError::invalid("BEM surface", e, "a valid field"))?;
        let sol = Solver::new(&grid, material, &BemOptions::default())
            .map_err(err)?
            .solve(&surface, bem::Control::Load(load))
            .map_err(err)?;
        let (bx, by) = blocks_per_row(map, BLOCKS[0]);
        let mut blocks = vec![0.0; bx * by];
        for (c, p) in sol.pressure.iter().enumerate() {
            let (i, j) = (c % cx, c / cx);
            let b =
                block_of(i as f64 * cell[0], j as f64 * cell[1], BLOCKS[0], bx).min(bx * by - 1);
            blocks[b] += p * grid.cell_area();
        }
        solved.push((cell, sol.approach, sol.contact_area, blocks));
    }
    let finest = solved.last().map(|s| s.3.clone()).unwrap_or_default();
    Ok(solved
        .into_iter()
        .map(|(cell, approach, contact_area, b)| ResolutionRow {
            cell,
            approach,
            contact_area,
            wrong_block: wrong_load(&b, &finest, load),
        })
        .collect())
}
