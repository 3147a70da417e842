//! Static multipoint runs of a scenario: solve at each load, tabulate,
//! write the CSV and the per-indenter charts.

use std::path::Path;
use std::time::Instant;

use anyhow::{Context, Result, bail};
use tyreroad_contact_law::{ContactLaw, LocalContact};
use tyreroad_multipoint::{Control, Problem, SolverOptions, overlapping_contacts, solve};

use crate::charts::{Series, line_chart};
use crate::output::Csv;
use crate::scenario::Scenario;

/// The CSV header every static run writes (and the film comparison reads).
pub const STATIC_CSV_HEADER: &str = "load_n,indenter,x_m,y_m,force_n,radius_m";

/// One asperity at one load.
#[derive(Clone, Debug, PartialEq)]
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
#[derive(Clone, Debug)]
pub struct LoadRun {
    /// Imposed load (N).
    pub load: f64,
    /// Σ P_i (N).
    pub total: f64,
    /// Approach δ0 (m).
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
}

/// Solves the scenario's `[static]` loads.
pub fn run_static(scenario: &Scenario) -> Result<(Vec<StaticRow>, Vec<LoadRun>)> {
    let Some(spec) = &scenario.static_case else {
        bail!("scenario {}: no [static] section to solve", scenario.name);
    };
    if spec.loads.is_empty() {
        bail!("scenario {}: [static] loads is empty", scenario.name);
    }
    let problem = scenario.problem()?;
    let loads: Vec<f64> = spec.loads.iter().map(|l| l.value()).collect();
    let (rows, runs, _) = run_static_problem(
        &scenario.name,
        &problem,
        &scenario.ids(),
        &loads,
        &scenario.solver_options(),
    )?;
    Ok((rows, runs))
}

/// Rows, per-load reports and per-load local contacts of a static run.
pub type StaticRuns = (Vec<StaticRow>, Vec<LoadRun>, Vec<Vec<LocalContact>>);

/// Solves a prepared problem at each of `loads`; `ids[k]` labels asperity
/// `k`. Also returns each load's local contacts (for pressure maps).
pub fn run_static_problem<L: ContactLaw + Sync>(
    name: &str,
    problem: &Problem<L>,
    ids: &[u32],
    loads: &[f64],
    options: &SolverOptions,
) -> Result<StaticRuns> {
    if ids.len() != problem.len() {
        bail!("{name}: {} ids for {} asperities", ids.len(), problem.len());
    }
    let (mut rows, mut runs, mut locals) = (Vec::new(), Vec::new(), Vec::new());
    for &load in loads {
        let start = Instant::now();
        let s = solve(problem, Control::Load(load), options)
            .with_context(|| format!("solving {name} at {load} N"))?;
        let seconds = start.elapsed().as_secs_f64();
        let contacts = s.local_contacts(problem);
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
            overlapping: overlapping_contacts(problem.positions(), &contacts).len(),
        });
        locals.push(contacts);
    }
    Ok((rows, runs, locals))
}

/// Writes `DIR/NAME.csv` and the charts `DIR/NAME_forces.svg`,
/// `DIR/NAME_radii.svg`; returns the paths written.
pub fn write_static_outputs(dir: &Path, name: &str, rows: &[StaticRow]) -> Result<Vec<String>> {
    let csv_path = dir.join(format!("{name}.csv"));
    write_static_csv(&csv_path, rows)?;
    let series = |value: fn(&StaticRow) -> f64| -> Vec<Series> {
        loads(rows)
            .into_iter()
            .map(|load| Series {
                label: format!("P = {load} N"),
                points: rows
                    .iter()
                    .filter(|r| r.load == load)
                    .map(|r| (f64::from(r.id), value(r)))
                    .collect(),
            })
            .collect()
    };
    let forces = dir.join(format!("{name}_forces.svg"));
    line_chart(
        &forces,
        "Contact force per indenter (multipoint model)",
        "indenter",
        "force (N)",
        &series(|r| r.force),
    )?;
    let radii = dir.join(format!("{name}_radii.svg"));
    line_chart(
        &radii,
        "Contact radius per indenter (multipoint model, Hertz rebuild)",
        "indenter",
        "radius (mm)",
        &series(|r| r.radius * 1e3),
    )?;
    Ok([csv_path, forces, radii]
        .iter()
        .map(|p| p.display().to_string())
        .collect())
}

/// Writes `rows` as a CSV with [`STATIC_CSV_HEADER`].
pub fn write_static_csv(path: &Path, rows: &[StaticRow]) -> Result<()> {
    let mut csv = Csv::new(STATIC_CSV_HEADER);
    for r in rows {
        csv.row(&[
            format!("{}", r.load),
            r.id.to_string(),
            format!("{:e}", r.x),
            format!("{:e}", r.y),
            format!("{:.9e}", r.force),
            format!("{:.9e}", r.radius),
        ]);
    }
    csv.write(path)
}

/// The distinct loads, in order of appearance.
pub fn loads(rows: &[StaticRow]) -> Vec<f64> {
    let mut out: Vec<f64> = Vec::new();
    for r in rows {
        if !out.contains(&r.load) {
            out.push(r.load);
        }
    }
    out
}

/// Prints forces and radii per asperity, a column pair per load.
pub fn print_table(rows: &[StaticRow]) {
    let loads = loads(rows);
    print!("{:>9} {:>7} {:>7} |", "indenter", "x (mm)", "y (mm)");
    for l in &loads {
        print!(" {:>8} {:>7} |", format!("P@{l:.0}N"), "a (mm)");
    }
    println!();
    let first: Vec<&StaticRow> = rows.iter().filter(|r| r.load == loads[0]).collect();
    for (k, r0) in first.iter().enumerate() {
        print!("{:>9} {:>7.1} {:>7.1} |", r0.id, r0.x * 1e3, r0.y * 1e3);
        for l in &loads {
            let r = rows.iter().filter(|r| r.load == *l).nth(k);
            if let Some(r) = r {
                print!(" {:>8.3} {:>7.3} |", r.force, r.radius * 1e3);
            }
        }
        println!();
    }
}
