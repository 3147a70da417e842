//! The multipoint model measured against the full-grid BEM reference on the
//! paper's case (docs/validation.md): the library's comparison
//! (`tyreroad::scenario::bem_comparison`) printed, checked and written.

use anyhow::{Context, Result};
use tyreroad::scenario::output::{OutputSet, pressure_field_npz};
use tyreroad::scenario::{
    BEM_CELL, MAX_FORCE_DIFFERENCE, Scenario, StaticResult, StaticRow, bem_comparison, differences,
};

use crate::statics::write_static_csv;

/// A pass/fail line of the validation.
pub struct BemCheck {
    /// What is checked.
    pub name: String,
    /// Whether it passed.
    pub passed: bool,
    /// Figures.
    pub detail: String,
}

/// Solves the scenario by the BEM at every load of `statics`, rebuilds the
/// two-scale radii, stages `NAME_bem.csv`, `NAME_two_scale.csv`,
/// `NAME_pressure_500N.png` and `NAME_pressure_500N.npz` (`pressure`, `x`,
/// `y`, `origin`, `spacing`), prints the differences and returns the checks.
pub fn run(
    statics: &StaticResult,
    scenario: &Scenario,
    set: &mut OutputSet,
) -> Result<Vec<BemCheck>> {
    let cmp = bem_comparison(scenario, statics)?;
    let ids = scenario.ids();
    let grid = &cmp.grid;
    say!(
        "\nBEM reference: true spherical caps, {}×{} cells of {} mm ({:.1} × {:.1} mm), \
         tolerance 1e-8, per-ball forces from the Voronoi regions of the summits; \
         set-up {:.2} s",
        grid.nx(),
        grid.ny(),
        BEM_CELL * 1e3,
        grid.size()[0] * 1e3,
        grid.size()[1] * 1e3,
        cmp.setup_seconds
    );
    let mut checks = Vec::new();
    let (mut bem_rows, mut two_rows) = (Vec::new(), Vec::new());
    say!("Multipoint model vs BEM, relative per-ball differences |Δ|/BEM (max at indenter, mean):");
    for l in &cmp.loads {
        let (load, b, ts) = (l.load, &l.bem, &l.two_scale);
        let mp = statics.at_load(load);
        let mp_forces: Vec<f64> = mp.iter().map(|r| r.force).collect();
        let mp_radii: Vec<f64> = mp.iter().map(|r| r.radius).collect();
        let ts_radii: Vec<f64> = ts.local.iter().map(|l| l.radius).collect();
        let (fmax, fmean, fk) = differences(&mp_forces, &b.forces);
        let (rmax, rmean, rk) = differences(&mp_radii, &b.radii);
        let (tmax, tmean, tk) = differences(&ts_radii, &b.radii);
        let mp_approach = l.model_approach;
        say!(
            "  {load:>5} N: BEM {} it. {:.2} s, δ {:.4} mm (model {:.4} mm, {:+.2} %) | \
             forces max {:.2} % (#{}) mean {:.2} % | radii, Hertz rebuild: max {:.2} % (#{}) mean {:.2} % | \
             radii, two-scale: max {:.2} % (#{}) mean {:.2} %",
            b.iterations,
            b.seconds,
            b.approach * 1e3,
            mp_approach * 1e3,
            (mp_approach / b.approach - 1.0) * 100.0,
            fmax * 100.0,
            ids[fk],
            fmean * 100.0,
            rmax * 100.0,
            ids[rk],
            rmean * 100.0,
            tmax * 100.0,
            ids[tk],
            tmean * 100.0,
        );
        checks.push(BemCheck {
            name: format!("model vs BEM forces at {load} N"),
            passed: fmax <= MAX_FORCE_DIFFERENCE,
            detail: format!(
                "max |ΔP|/P_BEM = {:.2} %, mean {:.2} % (≤ {} %)",
                fmax * 100.0,
                fmean * 100.0,
                MAX_FORCE_DIFFERENCE * 100.0
            ),
        });
        let bem_total: f64 = b.forces.iter().sum();
        let map_total = ts.map.as_ref().map_or(0.0, |m| m.integral());
        let balance = ((bem_total - load) / load)
            .abs()
            .max(((map_total - load) / load).abs());
        checks.push(BemCheck {
            name: format!("BEM Σ regions and two-scale map integral at {load} N"),
            passed: balance <= 1e-9,
            detail: format!("max |Σ − W| / W = {balance:.1e} (≤ 1e-9)"),
        });
        checks.push(BemCheck {
            name: format!("two-scale radii vs BEM at {load} N"),
            passed: tmax <= 0.05,
            detail: format!(
                "max |Δa|/a_BEM = {:.2} %, mean {:.2} % (≤ 5 %)",
                tmax * 100.0,
                tmean * 100.0
            ),
        });
        for (k, r) in mp.iter().enumerate() {
            bem_rows.push(StaticRow {
                force: b.forces[k],
                radius: b.radii[k],
                ..(*r).clone()
            });
            two_rows.push(StaticRow {
                radius: ts.local[k].radius,
                ..(*r).clone()
            });
        }
    }
    say!(
        "  two-scale local solves: {:.2} s for {} loads",
        cmp.two_scale_seconds,
        cmp.loads.len()
    );

    let shown = cmp.shown_load().context("no load")?;
    let load = shown.load;
    say!(
        "\nAt {load} N, per indenter: forces (N) and radii (mm): model (Hertz rebuild), two-scale, BEM"
    );
    say!(
        "{:>9} {:>8} {:>8} {:>8} | {:>7} {:>7} {:>7}",
        "indenter",
        "P model",
        "P BEM",
        "ΔP %",
        "a Hertz",
        "a 2-sc",
        "a BEM"
    );
    let (b, ts) = (&shown.bem, &shown.two_scale);
    for (k, r) in statics.at_load(load).iter().enumerate() {
        say!(
            "{:>9} {:>8.3} {:>8.3} {:>+8.2} | {:>7.3} {:>7.3} {:>7.3}",
            r.id,
            r.force,
            b.forces[k],
            (r.force / b.forces[k] - 1.0) * 100.0,
            r.radius * 1e3,
            ts.local[k].radius * 1e3,
            b.radii[k] * 1e3
        );
    }

    write_static_csv(set, &format!("{}_bem.csv", scenario.name), &bem_rows)?;
    write_static_csv(set, &format!("{}_two_scale.csv", scenario.name), &two_rows)?;
    if let Some(map) = &ts.map {
        let stem = format!("{}_pressure_{load:.0}N", scenario.name);
        crate::pressure_image::write_pressure_png(
            set,
            &format!("{stem}.png"),
            map,
            &format!("{load:.0} N"),
        )?;
        set.write(&format!("{stem}.npz"), &pressure_field_npz(map)?)?;
    }
    Ok(checks)
}
