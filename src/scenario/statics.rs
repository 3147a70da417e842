//! Static multipoint runs: a problem solved at each load of `[static]`.

use std::time::Instant;

use tyreroad_contact_law::{ContactLaw, LocalContact};
use tyreroad_multipoint::{
    Control, Problem, Solution, SolveError, SolverOptions, overlapping_contacts, solve,
};

use super::{Scenario, ScenarioError};

/// One asperity at one load.
#[derive(Clone, Debug, PartialEq, serde::Serialize)]
pub struct StaticRow {
    /// Imposed total load (N).
    pub load: f64,
    /// Asperity label.
    pub id: u32,
    /// Summit x (m).
    pub x: f64,
    /// Summit y (m).
    pub y: f64,
    /// Force (N).
    pub force: f64,
    /// Local contact radius (m).
    pub radius: f64,
}

/// What one load's solve reports.
#[derive(Clone, Debug, PartialEq)]
pub struct LoadRun {
    /// Imposed load (N).
    pub load: f64,
    /// Σ P_i (N).
    pub total: f64,
    /// Approach δ0 (m): from the highest summit on asperities, from the
    /// map's highest point on a texture (as the BEM measures it).
    pub approach: f64,
    /// Asperities in contact.
    pub contacts: usize,
    /// Newton iterations.
    pub iterations: usize,
    /// Final relative residual.
    pub residual: f64,
    /// Wall time of the solve (s).
    pub seconds: f64,
    /// Pairs of loaded asperities whose local contacts overlap, where the
    /// model's point-force coupling no longer holds
    /// (`tyreroad_multipoint::overlapping_contacts`).
    pub overlapping: usize,
    /// Whether the solve met the tolerance or stagnated within the
    /// acceptable one (what `--strict` counts as a fallback).
    pub convergence: tyreroad_multipoint::Convergence,
}

/// A static run: per-asperity rows (load-major, asperity order within a
/// load) and one report per load.
#[derive(Clone, Debug, PartialEq)]
pub struct StaticResult {
    /// The scenario's name.
    pub name: String,
    /// One row per asperity and load.
    pub rows: Vec<StaticRow>,
    /// One report per solved load, in the order of `[static] loads`.
    pub runs: Vec<LoadRun>,
    /// The loads whose solve did not converge (N) and why: each load is its
    /// own item, so the others are solved and written all the same.
    pub failed_loads: Vec<(f64, String)>,
    /// What looks wrong with a solved load's answer: an asperity pressed
    /// past the depth its shape describes (a ball past its equator).
    pub warnings: Vec<String>,
}

impl StaticResult {
    /// The distinct loads, in order of appearance.
    pub fn loads(&self) -> Vec<f64> {
        loads(&self.rows)
    }

    /// The rows at `load`, in asperity order: of the first run at it, when
    /// `[static] loads` lists it more than once (each is solved and
    /// reported; a second copy is the same contact).
    pub fn at_load(&self, load: f64) -> Vec<&StaticRow> {
        self.runs
            .iter()
            .position(|r| r.load == load)
            .map_or_else(Vec::new, |k| self.rows_of_run(k).iter().collect())
    }

    /// The rows of `runs[k]`, in asperity order (every solved load has one
    /// row per asperity, in the order of `runs`); empty past the last run.
    pub fn rows_of_run(&self, k: usize) -> &[StaticRow] {
        let per_run = self.rows.len().checked_div(self.runs.len()).unwrap_or(0);
        self.rows
            .get(k * per_run..(k + 1) * per_run)
            .unwrap_or_default()
    }
}

/// The `[static]` loads of a scenario (N), checked to be non-empty.
///
/// # Errors
/// No `[static]` section, or no load in it.
pub fn static_loads(scenario: &Scenario) -> Result<Vec<f64>, ScenarioError> {
    let Some(spec) = &scenario.static_case else {
        return Err(ScenarioError::Invalid(format!(
            "scenario {}: no [static] section to solve",
            scenario.name
        )));
    };
    if spec.loads.is_empty() {
        return Err(ScenarioError::Invalid(format!(
            "scenario {}: [static] loads is empty",
            scenario.name
        )));
    }
    Ok(spec.loads.iter().map(|l| l.value()).collect())
}

/// Solves the scenario's `[static]` loads on its `[[asperity]]` list.
///
/// # Errors
/// No `[static]` section or no load, an invalid material or shape, a failed
/// solve.
pub fn run_static(scenario: &Scenario) -> Result<StaticResult, ScenarioError> {
    let loads = static_loads(scenario)?;
    let problem = scenario.problem()?;
    let ids = scenario.ids();
    let solved = run_static_problem(
        &scenario.name,
        &problem,
        &ids,
        &loads,
        &scenario.solver_options(),
    )?;
    let mut result = solved.result;
    // A ball pressed past its equator (or given a contact wider than
    // itself by its law's local rule): its cap goes on as a cylinder, and
    // Hertz's small-contact picture ended long before.
    let radii = scenario.ball_radii();
    let extent = set_extent(problem.positions());
    // Each load's contact wider than the whole set, said after the shapes'.
    let mut too_wide = Vec::new();
    for (run, depths) in result.runs.iter().zip(&solved.depths) {
        let rows: Vec<_> = result
            .rows
            .iter()
            .filter(|row| row.load == run.load)
            .collect();
        for (((row, &id), &r), &depth) in rows.iter().zip(&ids).zip(&radii).zip(depths) {
            if r.is_finite() && (depth > r || row.radius > r) {
                result.warnings.push(format!(
                    "load {} N, asperity {id}: a ball of radius {:.3} mm pressed {:.3} mm deep, \
                     its contact radius {:.3} mm: a contact wider than the ball, or past its \
                     equator (where its law goes on as a cylinder), is no ball's; Hertz's \
                     small-contact picture ended well before",
                    run.load,
                    r * 1e3,
                    depth * 1e3,
                    row.radius * 1e3
                ));
            }
        }
        let widest = rows
            .iter()
            .zip(&ids)
            .max_by(|a, b| a.0.radius.total_cmp(&b.0.radius));
        if let Some((row, id)) = widest
            && row.radius > extent
        {
            too_wide.push(format!(
                "load {} N, asperity {id}: a contact radius of {:.4} mm, wider than the whole \
                 set of summits ({:.4} mm from end to end): one contact covering every other \
                 summit is no road's (a flatter shape than meant, or a much lighter load?)",
                run.load,
                row.radius * 1e3,
                extent * 1e3
            ));
        }
    }
    result.warnings.extend(scenario.steep_cone_warning());
    result.warnings.extend(too_wide);
    Ok(result)
}

/// The largest distance between two summits (m); infinite for fewer than
/// two, where no contact can be wider than the set.
///
/// The two farthest summits lie on the set's convex hull, so only the
/// hull's corners are paired: a list of a hundred thousand summits costs
/// a sort, not ten billion distances.
fn set_extent(positions: &[[f64; 2]]) -> f64 {
    if positions.len() < 2 {
        return f64::INFINITY;
    }
    let corners = hull_corners(positions);
    let mut widest = 0.0f64;
    for (k, a) in corners.iter().enumerate() {
        for b in &corners[k + 1..] {
            widest = widest.max((a[0] - b[0]).hypot(a[1] - b[1]));
        }
    }
    widest
}

/// The corners of the points' convex hull (Andrew's monotone chain),
/// collinear points dropped; all the points' extremes in any direction are
/// among them.
fn hull_corners(positions: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let mut sorted = positions.to_vec();
    sorted.sort_by(|a, b| a[0].total_cmp(&b[0]).then(a[1].total_cmp(&b[1])));
    sorted.dedup();
    if sorted.len() < 3 {
        return sorted;
    }
    let mut hull = half_hull(sorted.iter().copied());
    let upper = half_hull(sorted.iter().rev().copied());
    // Each chain ends where the other begins.
    hull.pop();
    hull.extend(&upper[..upper.len() - 1]);
    hull
}

/// One chain of the monotone-chain hull: the points, in order, that turn
/// left of the chain so far.
fn half_hull(points: impl Iterator<Item = [f64; 2]>) -> Vec<[f64; 2]> {
    let turn = |o: [f64; 2], a: [f64; 2], b: [f64; 2]| {
        (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
    };
    let mut chain: Vec<[f64; 2]> = Vec::new();
    for p in points {
        while chain.len() >= 2 && turn(chain[chain.len() - 2], chain[chain.len() - 1], p) <= 0.0 {
            chain.pop();
        }
        chain.push(p);
    }
    chain
}

/// A static run with each load's local contacts (for pressure maps).
#[derive(Clone, Debug)]
pub struct StaticSolve {
    /// Rows and per-load reports.
    pub result: StaticResult,
    /// Each load's local contacts, in asperity order.
    pub local_contacts: Vec<Vec<LocalContact>>,
    /// Each load's interpenetrations `δ_i` (m; negative out of contact), in
    /// asperity order.
    pub depths: Vec<Vec<f64>>,
}

/// The warning of one load whose `overlapping` contacts hold a pair where
/// one summit lies inside the other's contact patch (`r < max(a_i, a_j)`),
/// naming the closest such pair: the point
/// kernel `1/(π E* r)` between them then stands for a displacement that no
/// pressure spread over the patch gives (it grows without bound as `r → 0`,
/// where the patch's own displacement stays finite), so the pair's forces
/// and the approach are not physical. Two summits 1 µm apart under 50 N
/// carried almost nothing between them while a third took the load, with
/// only the overlap note. At most a few pairs are named.
pub(crate) fn summits_inside_patches(
    load: f64,
    positions: &[[f64; 2]],
    contacts: &[LocalContact],
    overlapping: &[(usize, usize)],
    ids: &[u32],
) -> Option<String> {
    const NAMED: usize = 3;
    let mut inside: Vec<(usize, usize, f64)> = overlapping
        .iter()
        .filter_map(|&(i, j)| {
            let r = (positions[i][0] - positions[j][0]).hypot(positions[i][1] - positions[j][1]);
            (r < contacts[i].radius.max(contacts[j].radius)).then_some((i, j, r))
        })
        .collect();
    inside.sort_by(|a, b| a.2.total_cmp(&b.2));
    let (i, j, r) = *inside.first()?;
    let more = if inside.len() > 1 {
        format!(
            " ({} pairs in all{})",
            inside.len(),
            if inside.len() > NAMED {
                String::new()
            } else {
                format!(
                    ": {}",
                    inside
                        .iter()
                        .map(|&(i, j, _)| format!("{} and {}", ids[i], ids[j]))
                        .collect::<Vec<_>>()
                        .join(", ")
                )
            }
        )
    } else {
        String::new()
    };
    Some(format!(
        "load {load} N: the summits of asperities {} and {} lie {:.4} mm apart, inside a contact \
         patch (radius {:.4} mm){more}: the point-force coupling 1/r between them is far too stiff \
         there, and this load's forces and approach are not physical; merge such asperities \
         (on a texture, [model] fidelity = \"clustered\" solves them as one body)",
        ids[i],
        ids[j],
        r * 1e3,
        contacts[i].radius.max(contacts[j].radius) * 1e3
    ))
}

/// Solves a prepared problem at each of `loads` (N); `ids[k]` labels
/// asperity `k`.
///
/// A load whose solve does not converge is recorded in
/// [`StaticResult::failed_loads`] and the next load is solved.
///
/// # Errors
/// As many ids as asperities are needed; an invalid problem or options, or
/// no load solved at all, is an error naming the load.
pub fn run_static_problem<L: ContactLaw + Sync>(
    name: &str,
    problem: &Problem<L>,
    ids: &[u32],
    loads: &[f64],
    options: &SolverOptions,
) -> Result<StaticSolve, ScenarioError> {
    run_static_problem_with(name, problem, ids, loads, |load| {
        match solve(problem, Control::Load(load), options) {
            Ok(s) => Ok(Ok(s)),
            Err(source @ SolveError::NotConverged { .. }) => Ok(Err(source.to_string())),
            Err(source) => Err(ScenarioError::Solve {
                context: format!("solving {name} at {load} N"),
                source,
            }),
        }
    })
}

/// [`run_static_problem`] with the solve of each load given: `solve(load)`
/// is `Ok(Ok(solution))`, `Ok(Err(why))` for that load's own failure
/// (recorded, the other loads go on) or `Err` for the run's.
///
/// # Errors
/// As [`run_static_problem`].
pub fn run_static_problem_with<L: ContactLaw + Sync>(
    name: &str,
    problem: &Problem<L>,
    ids: &[u32],
    loads: &[f64],
    mut solve_load: impl FnMut(f64) -> Result<Result<Solution, String>, ScenarioError>,
) -> Result<StaticSolve, ScenarioError> {
    if ids.len() != problem.len() {
        return Err(ScenarioError::Invalid(format!(
            "{name}: {} ids for {} asperities",
            ids.len(),
            problem.len()
        )));
    }
    let (mut rows, mut runs, mut locals) = (Vec::new(), Vec::new(), Vec::new());
    let mut depths = Vec::new();
    let (mut failed_loads, mut warnings) = (Vec::new(), Vec::new());
    for &load in loads {
        let start = Instant::now();
        let s = match solve_load(load)? {
            Ok(s) => s,
            Err(why) => {
                failed_loads.push((load, why));
                continue;
            }
        };
        let seconds = start.elapsed().as_secs_f64();
        let contacts = s.local_contacts(problem);
        let overlapping = overlapping_contacts(problem.positions(), &contacts);
        warnings.extend(summits_inside_patches(
            load,
            problem.positions(),
            &contacts,
            &overlapping,
            ids,
        ));
        for (k, (&[x, y], c)) in problem.positions().iter().zip(&contacts).enumerate() {
            rows.push(StaticRow {
                load,
                id: ids[k],
                x,
                y,
                force: s.forces[k],
                radius: c.radius,
            });
        }
        runs.push(LoadRun {
            load,
            total: s.total_force(),
            approach: s.approach,
            contacts: s.contact_count(),
            iterations: s.iterations,
            residual: s.residual,
            seconds,
            overlapping: overlapping.len(),
            convergence: s.convergence,
        });
        locals.push(contacts);
        depths.push(s.depths);
    }
    if runs.is_empty()
        && let Some((load, why)) = failed_loads.first()
    {
        return Err(ScenarioError::Invalid(format!(
            "{name}: no load solved; at {load} N: {why}"
        )));
    }
    Ok(StaticSolve {
        result: StaticResult {
            name: name.into(),
            rows,
            runs,
            failed_loads,
            warnings,
        },
        local_contacts: locals,
        depths,
    })
}

/// The distinct loads of `rows`, in order of appearance.
pub fn loads(rows: &[StaticRow]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for r in rows {
        if !out.contains(&r.load) {
            out.push(r.load);
        }
    }
    out
}

#[cfg(test)]
mod extent_tests {
    use super::set_extent;

    /// The brute-force diameter the hull must reproduce.
    fn widest_pair(positions: &[[f64; 2]]) -> f64 {
        let mut widest = 0.0f64;
        for (k, a) in positions.iter().enumerate() {
            for b in &positions[k + 1..] {
                widest = widest.max((a[0] - b[0]).hypot(a[1] - b[1]));
            }
        }
        widest
    }

    #[test]
    fn the_hull_finds_the_farthest_summits_of_every_set() {
        // A fixed pseudo-random sequence (no extra dependency): scattered
        // sets, sets on a line, grids with collinear edges, repeated points.
        let mut state = 0x2006_u64;
        let mut next = || {
            state = state
                .wrapping_mul(6_364_136_223_846_793_005)
                .wrapping_add(1_442_695_040_888_963_407);
            (state >> 11) as f64 / (1u64 << 53) as f64
        };
        for n in [2usize, 3, 4, 7, 40, 300] {
            let scattered: Vec<[f64; 2]> = (0..n).map(|_| [next() * 0.04, next() * 0.03]).collect();
            let on_a_line: Vec<[f64; 2]> = (0..n)
                .map(|k| [k as f64 * 1e-3, 2.0 * k as f64 * 1e-3])
                .collect();
            let side = (n as f64).sqrt().ceil() as usize;
            let grid: Vec<[f64; 2]> = (0..n)
                .map(|k| [(k % side) as f64 * 0.01, (k / side) as f64 * 0.01])
                .collect();
            let mut repeated = scattered.clone();
            repeated.extend_from_slice(&scattered);
            for set in [scattered, on_a_line, grid, repeated] {
                let brute = widest_pair(&set);
                assert!(
                    (set_extent(&set) - brute).abs() <= 1e-15,
                    "{n} points: hull {} against every pair {brute}",
                    set_extent(&set)
                );
            }
        }
        assert_eq!(set_extent(&[[0.0, 0.0]]), f64::INFINITY);
        assert_eq!(set_extent(&[[1e-3, 2e-3], [1e-3, 2e-3]]), 0.0);
    }
}
