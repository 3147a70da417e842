//! `cargo xtask run` for a `[texture]` scenario: the library's texture run
//! (`tyreroad::scenario`) printed and written.

use anyhow::Result;
use serde::Serialize;
use tyreroad::scenario::TextureResult;
use tyreroad::scenario::output::{OutputSet, fmt, height_map_npz, pressure_field_npz};

use crate::pressure_image::write_pressure_png;
use crate::statics::{print_table, write_static_outputs};

#[derive(Serialize)]
struct SummaryRow {
    #[serde(rename = "load_n", serialize_with = "fmt::plain")]
    load: f64,
    #[serde(rename = "total_n", serialize_with = "fmt::sci9")]
    total: f64,
    #[serde(rename = "approach_m", serialize_with = "fmt::sci9")]
    approach: f64,
    contacts: usize,
    asperities: usize,
    overlapping_pairs: usize,
}

#[derive(Serialize)]
struct TwoScaleRow {
    #[serde(rename = "load_n", serialize_with = "fmt::plain")]
    load: f64,
    indenter: u32,
    #[serde(rename = "force_n", serialize_with = "fmt::sci9")]
    force: f64,
    #[serde(rename = "contact_area_m2", serialize_with = "fmt::sci9")]
    contact_area: f64,
    #[serde(rename = "radius_m", serialize_with = "fmt::sci9")]
    radius: f64,
    #[serde(rename = "max_pressure_pa", serialize_with = "fmt::sci9")]
    max_pressure: f64,
    /// `complete`, `clipped` or `hertz` (`tyreroad::two_scale::LocalStatus`).
    local_field: &'static str,
}

/// Prints a texture run and stages into `set`:
/// - `NAME.csv` (indenter = asperity index + 1, highest summit first; the
///   radius column is the half-section rule's) and the force and radius
///   charts;
/// - `NAME_summary.csv`
///   (`load_n,total_n,approach_m,contacts,asperities,overlapping_pairs`:
///   pairs of contacts whose half-section radii overlap, where the model's
///   premise fails);
/// - `NAME_two_scale.csv`
///   (`load_n,indenter,force_n,contact_area_m2,radius_m,max_pressure_pa,local_field`):
///   each loaded asperity's contact rebuilt by a local BEM solve on its own
///   surface, and how (`complete`, or the fallback: `clipped`, `hertz`);
/// - per load, the two-scale pressure map as `NAME_pressure_<load>N.png`
///   and `NAME_pressure_<load>N.npz` (`pressure`, `x`, `y`, `origin`,
///   `spacing`);
/// - the height map as `NAME_height_map.npz` (`heights`, `spacing`).
///
/// Returns the number of asperity fields that fell back (each printed).
pub fn report_texture_static(name: &str, r: &TextureResult, set: &mut OutputSet) -> Result<usize> {
    let mut fallbacks = 0;
    let t = &r.texture;
    say!(
        "texture {} × {} at {:.3} × {:.3} mm: {} asperities ({} segmented, {} without depth range)",
        t.size.0,
        t.size.1,
        t.spacing.0 * 1e3,
        t.spacing.1 * 1e3,
        t.asperities,
        t.segmented,
        t.segmented - t.asperities
    );
    for warning in &t.warnings {
        say!("warning: {warning}");
    }
    let ids = r.ids();
    if ids.len() <= 40 {
        print_table(&r.statics.rows);
    }
    write_static_outputs(set, name, &r.statics.rows)?;
    let mut summary = Vec::new();
    let mut local = Vec::new();
    for (run, per_load) in r.statics.runs.iter().zip(&r.loads) {
        say!(
            "load {} N: Σ P = {:.9} N, δ0 = {:.6e} m, {} contacts of {}, {} iterations",
            run.load,
            run.total,
            run.approach,
            run.contacts,
            ids.len(),
            run.iterations
        );
        summary.push(SummaryRow {
            load: run.load,
            total: run.total,
            approach: run.approach,
            contacts: run.contacts,
            asperities: ids.len(),
            overlapping_pairs: run.overlapping,
        });
        if run.overlapping > 0 {
            say!(
                "  note: {} pairs of contacts overlap (a_i + a_j > spacing): the multipoint \
                 model's point-force coupling does not hold there (docs/validation.md)",
                run.overlapping
            );
        }
        let ts = &per_load.two_scale;
        for (k, f) in ts.local.iter().enumerate().filter(|(_, f)| f.force > 0.0) {
            local.push(TwoScaleRow {
                load: run.load,
                indenter: ids[k],
                force: f.force,
                contact_area: f.contact_area,
                radius: f.radius,
                max_pressure: f.max_pressure,
                local_field: f.status.name(),
            });
        }
        for (k, status) in ts.fallbacks() {
            fallbacks += 1;
            say!("  fallback: indenter {}: {status}", ids[k]);
        }
        for note in &per_load.notes {
            say!("  note: {note}");
        }
        for past in &per_load.past_caps {
            say!("  warning: indenter {}: {past}", ids[past.index]);
        }
        if let Some(field) = &ts.map {
            let area: f64 = ts.local.iter().map(|f| f.contact_area).sum();
            say!(
                "  two-scale: contact area {:.2} mm², peak {:.2} MPa, map Σ p dA = {:.6} N",
                area * 1e6,
                field.max() * 1e-6,
                field.integral()
            );
            let stem = format!("{name}_pressure_{}N", run.load);
            write_pressure_png(
                set,
                &format!("{stem}.png"),
                field,
                &format!("{} N", run.load),
            )?;
            set.write(&format!("{stem}.npz"), &pressure_field_npz(field)?)?;
        }
    }
    set.write_csv(&format!("{name}_summary.csv"), &summary)?;
    if local.is_empty() {
        let header =
            "load_n,indenter,force_n,contact_area_m2,radius_m,max_pressure_pa,local_field\n";
        set.write(&format!("{name}_two_scale.csv"), header.as_bytes())?;
    } else {
        set.write_csv(&format!("{name}_two_scale.csv"), &local)?;
    }
    set.write(&format!("{name}_height_map.npz"), &height_map_npz(&r.map)?)?;
    fallbacks += crate::statics::print_failed_loads(&r.statics.failed_loads);
    if fallbacks > 0 {
        say!(
            "summary: {fallbacks} asperity fields fell back to a lower-fidelity field (see \
             local_field in {name}_two_scale.csv)"
        );
    }
    Ok(fallbacks)
}
