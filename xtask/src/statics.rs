//! Static runs on the command line: the per-asperity table printed, the
//! CSV and the per-indenter charts staged in an output set.

use anyhow::Result;
use serde::Serialize;
use tyreroad::scenario::output::{OutputSet, fmt};
use tyreroad::scenario::{LoadRun, StaticRow, loads};

use crate::charts::{Series, line_chart};

/// One line of a static CSV (`load_n,indenter,x_m,y_m,force_n,radius_m`,
/// the columns the film comparison reads).
#[derive(Serialize)]
struct StaticCsvRow {
    #[serde(rename = "load_n", serialize_with = "fmt::plain")]
    load: f64,
    indenter: u32,
    #[serde(rename = "x_m", serialize_with = "fmt::sci")]
    x: f64,
    #[serde(rename = "y_m", serialize_with = "fmt::sci")]
    y: f64,
    #[serde(rename = "force_n", serialize_with = "fmt::sci9")]
    force: f64,
    #[serde(rename = "radius_m", serialize_with = "fmt::sci9")]
    radius: f64,
}

/// Stages `NAME.csv` and the charts `NAME_forces.svg/.png`,
/// `NAME_radii.svg/.png`.
pub fn write_static_outputs(set: &mut OutputSet, name: &str, rows: &[StaticRow]) -> Result<()> {
    write_static_csv(set, &format!("{name}.csv"), rows)?;
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
    line_chart(
        set,
        &format!("{name}_forces"),
        "Contact force per indenter (multipoint model)",
        "indenter",
        "force (N)",
        &series(|r| r.force),
    )?;
    line_chart(
        set,
        &format!("{name}_radii"),
        "Contact radius per indenter (multipoint model, Hertz rebuild)",
        "indenter",
        "radius (mm)",
        &series(|r| r.radius * 1e3),
    )?;
    Ok(())
}

/// Stages `rows` as CSV file `file`.
pub fn write_static_csv(set: &mut OutputSet, file: &str, rows: &[StaticRow]) -> Result<()> {
    let rows: Vec<StaticCsvRow> = rows
        .iter()
        .map(|r| StaticCsvRow {
            load: r.load,
            indenter: r.id,
            x: r.x,
            y: r.y,
            force: r.force,
            radius: r.radius,
        })
        .collect();
    set.write_csv(file, &rows)?;
    Ok(())
}

/// Prints one line per load.
pub fn print_runs(runs: &[LoadRun]) {
    for r in runs {
        say!(
            "load {} N: Σ P = {:.9} N, δ0 = {:.6e} m, {} contacts, {} iterations",
            r.load,
            r.total,
            r.approach,
            r.contacts,
            r.iterations
        );
        if r.overlapping > 0 {
            say!(
                "  note: {} pairs of contacts overlap: the point-force coupling \
                 does not hold there",
                r.overlapping
            );
        }
    }
}

/// Prints the loads that did not converge; returns how many.
pub fn print_failed_loads(failed: &[(f64, String)]) -> usize {
    for (load, why) in failed {
        say!("load {load} N: FAILED, not written: {why}");
    }
    failed.len()
}

/// Prints the staged files' final paths.
pub fn print_written(written: &[std::path::PathBuf]) {
    for w in written {
        say!("written {}", w.display());
    }
}

/// Prints forces and radii per asperity, a column pair per load.
pub fn print_table(rows: &[StaticRow]) {
    let loads = loads(rows);
    let Some(&first_load) = loads.first() else {
        return;
    };
    say_part!("{:>9} {:>7} {:>7} |", "indenter", "x (mm)", "y (mm)");
    for l in &loads {
        say_part!(" {:>8} {:>7} |", format!("P@{l:.0}N"), "a (mm)");
    }
    say!();
    let first: Vec<&StaticRow> = rows.iter().filter(|r| r.load == first_load).collect();
    for (k, r0) in first.iter().enumerate() {
        say_part!("{:>9} {:>7.1} {:>7.1} |", r0.id, r0.x * 1e3, r0.y * 1e3);
        for l in &loads {
            let r = rows.iter().filter(|r| r.load == *l).nth(k);
            if let Some(r) = r {
                say_part!(" {:>8.3} {:>7.3} |", r.force, r.radius * 1e3);
            }
        }
        say!();
    }
}
