//! `cargo xtask validate`: the paper's 25-ball experiment, solved, checked
//! against independent references, tabulated and charted.

use std::path::PathBuf;

use anyhow::{Context, Result, bail};
use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{C_HERTZ_EXACT, ContactLaw, HertzLaw, PotentialLaw};

use tyreroad::scenario::output::OutputSet;
use tyreroad::scenario::{Scenario, StaticRow, loads, run_static};

use crate::statics::{print_table, print_written, write_static_outputs};

/// The embedded default scenario: the paper's experiment (docs/validation.md).
pub const PAPER_SCENARIO: &str = include_str!("../../fixtures/paper_25_spheres.toml");

/// Options of `cargo xtask validate`.
#[derive(Debug, clap::Args)]
pub struct ValidateArgs {
    /// Output directory.
    #[arg(long, default_value = "validation")]
    pub out: PathBuf,
    /// Another static scenario to validate instead of the embedded paper
    /// case; with `--textures`, a scenario whose `[texture]` (your road) is
    /// compared with the BEM at its `[static]` loads.
    #[arg(long)]
    pub scenario: Option<PathBuf>,
    /// The texture validation's options (`--textures`).
    #[command(flatten)]
    pub textures: crate::validate_textures::TextureArgs,
}

struct Check {
    name: String,
    passed: bool,
    detail: String,
}

/// Runs the validation; fails if any check fails.
pub fn run(args: &ValidateArgs) -> Result<()> {
    if args.textures.textures {
        return crate::validate_textures::run(&args.textures, args.scenario.as_deref(), &args.out);
    }
    let (text, origin) = match &args.scenario {
        Some(p) => (
            std::fs::read_to_string(p).with_context(|| format!("reading {}", p.display()))?,
            p.display().to_string(),
        ),
        None => (
            PAPER_SCENARIO.to_string(),
            "embedded paper_25_spheres.toml".into(),
        ),
    };
    let scenario = Scenario::parse(&text, &origin)?;
    if scenario.texture.is_some() {
        bail!(
            "{origin}: a scenario with a [texture] is compared with the BEM by \
             `cargo xtask validate --textures --scenario {origin}` (every fidelity rung at its \
             [static] loads); `validate --scenario` alone checks a scenario of [[asperity]] shapes"
        );
    }
    say!("== {} — {}", scenario.name, scenario.description);
    let statics = run_static(&scenario)?;
    if let Some((load, why)) = statics.failed_loads.first() {
        bail!("validation: the load {load} N did not converge: {why}");
    }
    let (rows, runs) = (&statics.rows, &statics.runs);
    let mut checks = Vec::new();

    say!("\nMultipoint model, forces P (N) and Hertz contact radii a (mm), paper numbering:");
    print_table(rows);
    say!();
    for r in runs {
        say!(
            "load {:>6.1} N: Σ P = {:.12} N, approach δ0 = {:.4} mm, {} contacts, \
             {} Newton iterations, residual {:.1e}, {:.2} ms",
            r.load,
            r.total,
            r.approach * 1e3,
            r.contacts,
            r.iterations,
            r.residual,
            r.seconds * 1e3
        );
        let balance = (r.total - r.load).abs() / r.load;
        checks.push(Check {
            name: format!("load balance at {} N", r.load),
            passed: balance <= 1e-10,
            detail: format!("|Σ P − W| / W = {balance:.1e} (≤ 1e-10)"),
        });
    }

    checks.extend(symmetry_checks(rows));
    checks.push(hertz_check(&scenario)?);

    if args.scenario.is_none() {
        say!();
        say_part!(
            "{}",
            crate::film_cmd::synthetic_table(&film_rows(rows), None)?
        );
    }

    let mut set = OutputSet::new(&args.out)?;
    write_static_outputs(&mut set, &scenario.name, rows)?;
    if args.scenario.is_none() {
        // The model measured against the full-grid BEM reference.
        let bem = crate::bem_validation::run(&statics, &scenario, &mut set)?;
        checks.extend(bem.into_iter().map(|c| Check {
            name: c.name,
            passed: c.passed,
            detail: c.detail,
        }));
    }
    let written = set.commit()?;
    say!("\nChecks:");
    let mut failed = 0;
    for c in &checks {
        say!(
            "  [{}] {}: {}",
            if c.passed { "ok" } else { "FAIL" },
            c.name,
            c.detail
        );
        failed += usize::from(!c.passed);
    }
    say!("\nWritten:");
    print_written(&written);
    if failed > 0 {
        bail!("{failed} validation check(s) failed");
    }
    Ok(())
}

fn film_rows(rows: &[StaticRow]) -> Vec<tyreroad::film::ModelRow> {
    rows.iter()
        .map(|r| tyreroad::film::ModelRow {
            load_n: r.load,
            indenter: r.id,
            x_m: r.x,
            y_m: r.y,
            force_n: r.force,
            radius_m: r.radius,
        })
        .collect()
}

/// Forces must be invariant under every mirror of the layout that maps
/// summits onto summits (the paper's grid has the 8 symmetries of a square).
fn symmetry_checks(rows: &[StaticRow]) -> Vec<Check> {
    type Mirror = (&'static str, fn(f64, f64) -> (f64, f64));
    let maps: [Mirror; 4] = [
        ("x ↦ −x", |x, y| (-x, y)),
        ("y ↦ −y", |x, y| (x, -y)),
        ("x ↔ y", |x, y| (y, x)),
        ("x ↔ −y", |x, y| (-y, -x)),
    ];
    let mut out = Vec::new();
    for load in loads(rows) {
        let at_load: Vec<&StaticRow> = rows.iter().filter(|r| r.load == load).collect();
        let find = |x: f64, y: f64| {
            at_load
                .iter()
                .find(|r| (r.x - x).abs() < 1e-9 && (r.y - y).abs() < 1e-9)
        };
        for (name, map) in maps {
            let mut worst: Option<f64> = Some(0.0);
            for r in &at_load {
                let (mx, my) = map(r.x, r.y);
                worst = match (worst, find(mx, my)) {
                    (Some(w), Some(m)) => Some(w.max((r.force - m.force).abs() / load)),
                    _ => None,
                };
            }
            if let Some(w) = worst {
                out.push(Check {
                    name: format!("symmetry {name} at {load} N"),
                    passed: w <= 1e-9,
                    detail: format!("max |ΔP| / W = {w:.1e} (≤ 1e-9)"),
                });
            }
        }
    }
    out
}

/// The single-ball law against Hertz: with `c = 2/π^1.5` it is Hertz; the
/// paper's `c = 0.36` is 0.23 % stiffer.
fn hertz_check(scenario: &Scenario) -> Result<Check> {
    let material = scenario.material()?;
    let r = 5e-3;
    let law = PotentialLaw::sphere(Sphere::new(r)?, material).with_constant(C_HERTZ_EXACT)?;
    let hertz = HertzLaw::new(r, material)?;
    let d = 1e-9;
    let dev = (law.force(d) - hertz.force(d)).abs() / hertz.force(d);
    Ok(Check {
        name: "single ball: potential law with c = 2/π^1.5 vs Hertz (δ/R = 2e-7)".into(),
        passed: dev <= 1e-6,
        detail: format!("relative difference {dev:.1e} (≤ 1e-6)"),
    })
}
