//! The BEM sweep of one cap patch over its depths (module docs of
//! [`super`]), and the tables of a body's tiles from one sweep of the
//! whole body ([`calibrate_joint`]).

use tyreroad_bem::{BemOptions, Par};
use tyreroad_contact_law::Material;

use super::window::{self, KnotSolution, KnotSolver};
use super::{
    BinnedField, CalibratedTable, CalibrationOptions, CalibrationStats, CapPatch, FidelityError,
    touches_border,
};

/// One depth of a [`sweep`]: the patch's top cell touching (its summit
/// offset, no force yet), or a BEM solve at `depth` (m from the summit).
pub(super) enum Knot<'s> {
    Onset,
    Solved {
        depth: f64,
        solution: &'s KnotSolution,
        last: bool,
    },
}

/// Most depths a table is calibrated at.
const MAX_NODES: usize = 1024;

/// Loosest BEM tolerance a calibration accepts.
const MAX_TOLERANCE: f64 = 0.1;

/// The BEM solves of a table (module docs): checks the inputs, then hands
/// each depth to `on_knot` in increasing order (the onset first when the
/// summit stands above the top cell).
pub(super) fn sweep(
    patch: &CapPatch,
    max_depth: f64,
    material: &Material,
    options: &CalibrationOptions,
    mut on_knot: impl FnMut(Knot<'_>),
) -> Result<CalibrationStats, FidelityError> {
    patch.validate()?;
    // Each node is a BEM solve: a billion of them was accepted and ran on.
    if !(4..=MAX_NODES).contains(&options.nodes) {
        return Err(FidelityError::invalid(
            "calibration nodes",
            options.nodes,
            format!("4 to {MAX_NODES}"),
        ));
    }
    // A tolerance of 10 "solved" every depth at once, into NaN tables.
    if !(options.tolerance > 0.0 && options.tolerance <= MAX_TOLERANCE) {
        return Err(FidelityError::invalid(
            "calibration tolerance",
            options.tolerance,
            format!("in (0, {MAX_TOLERANCE}]: the BEM's relative residual"),
        ));
    }
    let offset = patch.summit_offset();
    if !(max_depth.is_finite() && max_depth > offset) {
        return Err(FidelityError::invalid(
            "calibration depth",
            max_depth,
            format!("finite and beyond the highest cell ({offset} m below the summit)"),
        ));
    }
    // One patch is small: its FFTs run serially, and callers calibrate many
    // patches in parallel.
    let bem_options = BemOptions {
        tolerance: options.tolerance,
        par: Par::Seq,
        ..BemOptions::default()
    };
    let mut solver = KnotSolver::new(patch, material, bem_options);
    let range = max_depth - offset;
    let n = options.nodes;
    if offset > 0.0 {
        on_knot(Knot::Onset);
    }
    let mut previous: Vec<(f64, Vec<f64>)> = Vec::new();
    let mut iterations = Vec::with_capacity(n);
    let mut windows = Vec::with_capacity(n);
    for k in 1..=n {
        let approach = range * (k as f64 / n as f64).powi(2);
        let guess = window::warm_start(options.warm_start, &previous, offset + approach, patch);
        let sol = solver.solve(offset, approach, guess.as_deref())?;
        iterations.push(sol.iterations);
        windows.push(sol.window);
        on_knot(Knot::Solved {
            depth: offset + approach,
            solution: &sol,
            last: k == n,
        });
        if previous.len() == 2 {
            previous.remove(0);
        }
        previous.push((offset + approach, sol.pressure));
    }
    Ok(CalibrationStats {
        cells: [patch.nx, patch.ny],
        iterations,
        windows,
        solver_builds: solver.builds,
    })
}

/// One tile of a body calibrated whole ([`calibrate_joint`]): which cells
/// of the body's patch are its own, and how far (m, ≥ 0) its summit lies
/// below the body's.
#[derive(Clone, Debug, PartialEq)]
pub struct JointTile {
    /// One flag per patch cell (row-major), `true` on the tile's cells.
    pub cells: Vec<bool>,
    /// Its summit's depth below the patch's summit (m, ≥ 0).
    pub below: f64,
}

/// The tables of tiles cut from one body, from BEM solves of the whole
/// body: the patch (the body's cap, heights from its summit) is pressed as
/// [`super::calibrate`] presses a cap, and each tile's force, contact area (and
/// field) at a body depth `δ` are the pressure and the contact cells on the
/// tile's own cells. Tile `t`'s table is in its own depth,
/// `δ_t = δ − below_t`, from `0` (its summit touching) up. At a common
/// depth the tables therefore hold the tiles' mutual coupling through the
/// half-space: the tiles of one body sum, at every depth, to the body's
/// own table (to rounding), and a multipoint solve must not couple them
/// again (docs/theory.md §3, "Tiles of one body").
///
/// # Errors
/// As [`super::calibrate`]; [`FidelityError::InvalidInput`] for a tile whose cell
/// flags are not the patch's size or whose `below` is not finite and ≥ 0.
pub fn calibrate_joint(
    patch: &CapPatch,
    max_depth: f64,
    material: &Material,
    options: &CalibrationOptions,
    fields: bool,
    tiles: &[JointTile],
) -> Result<Vec<CalibratedTable>, FidelityError> {
    patch.validate()?;
    for t in tiles {
        if t.cells.len() != patch.nx * patch.ny {
            return Err(FidelityError::invalid(
                "tile cells",
                t.cells.len(),
                format!("{} flags (the patch's cells)", patch.nx * patch.ny),
            ));
        }
        if !(t.below.is_finite() && t.below >= 0.0) {
            return Err(FidelityError::invalid(
                "tile summit depth",
                t.below,
                "finite and >= 0 m",
            ));
        }
    }
    struct Building {
        depth: Vec<f64>,
        force: Vec<f64>,
        area: Vec<f64>,
        field: Option<BinnedField>,
        reached_border: bool,
    }
    let cell = patch.dx * patch.dy;
    let mut building: Vec<Building> = tiles
        .iter()
        .map(|_| {
            let mut field =
                fields.then(|| BinnedField::new(patch.nx, patch.ny, patch.dx, patch.dy));
            if let Some(f) = &mut field {
                f.push_knot(None, patch.nx, patch.dx, patch.dy);
            }
            Building {
                depth: vec![0.0],
                force: vec![0.0],
                area: vec![0.0],
                field,
                reached_border: false,
            }
        })
        .collect();
    let mut own = vec![0.0; patch.nx * patch.ny];
    let stats = sweep(patch, max_depth, material, options, |knot| {
        let Knot::Solved {
            depth,
            solution,
            last,
        } = knot
        else {
            return;
        };
        for (t, b) in tiles.iter().zip(&mut building) {
            let d = depth - t.below;
            // Before its summit touches a tile carries nothing (to the
            // BEM's tolerance): its law starts at its own summit.
            if !(d > 0.0) {
                continue;
            }
            for ((o, &p), &mine) in own.iter_mut().zip(&solution.pressure).zip(&t.cells) {
                *o = if mine { p } else { 0.0 };
            }
            b.depth.push(d);
            b.force.push(own.iter().sum::<f64>() * cell);
            b.area
                .push(own.iter().filter(|&&p| p > 0.0).count() as f64 * cell);
            if last {
                b.reached_border = touches_border(&own, patch.nx, patch.ny);
            }
            if let Some(f) = &mut b.field {
                f.push_knot(Some(&own), patch.nx, patch.dx, patch.dy);
            }
        }
    })?;
    Ok(building
        .into_iter()
        .map(|b| {
            let mut table = CalibratedTable::from_knots(b.depth, b.force, b.area, b.reached_border);
            table.field = b.field;
            table.stats = stats.clone();
            table
        })
        .collect())
}
