//! How deep the base band of each of a rolling texture scenario's
//! asperities goes under Ting's treatment (the deepest band level where
//! its law's slope falls: the depths below it share one memory, the bands
//! above keep their own), and how many are one band down to the depth each
//! asperity can reach on the path (docs/viscoelastic.md,
//! "Ting's treatment on texture laws"):
//!
//! ```text
//! cargo run --release --example ting_bands -- fixtures/rolling_tyre_dense_asphalt.toml [calibrated]
//! ```
//!
//! The depth of asperity `i` is `A − (top − z_i)`, `A` the largest approach
//! of a Wilke rolling run along the path (the bound that sizes the
//! calibrated tables, before its margin); only asperities the path can
//! select and that reach a positive depth are counted. With `calibrated`
//! the laws are the BEM-calibrated ones (`[model] fidelity = "calibrated"`,
//! calibrated once, all threads). The modulus is `[material]`'s, or `E∞`
//! with `[material.viscoelastic]` (the tread the viscoelastic run
//! calibrates at); convexity does not depend on it.

use std::path::Path;

use tyreroad::fidelity::compare::APPROACH_MARGIN;
use tyreroad::fidelity::rolling::{approach_bound, calibrate_rolling_road, selectable};
use tyreroad::fidelity::{CalibrationOptions, Calibrator};
use tyreroad::scenario::Scenario;
use tyreroad::shared::Par;
use tyreroad::viscoelastic::{DEFAULT_BANDS_PER_DECADE, base_band_depth};

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut args = std::env::args().skip(1);
    let path = args
        .next()
        .unwrap_or_else(|| "fixtures/rolling_tyre_dense_asphalt.toml".into());
    let calibrated = args.next().as_deref() == Some("calibrated");
    let scenario = Scenario::from_path(&path)?;
    let base = Path::new(&path).parent().unwrap_or(Path::new("."));
    let mut material = scenario.material()?;
    if let Some(tread) = scenario.viscoelastic_material(base)? {
        material = tread.elastic(tread.long_term())?;
    }
    let config = scenario.rolling_config()?;
    let wilke = scenario.texture_rolling_road(base)?;
    let par = Par::rayon(0);
    let bound = approach_bound(&wilke, material, &config, par)?;
    let per_decade = DEFAULT_BANDS_PER_DECADE;
    let modulus = material.youngs_modulus();
    let (mut reached, mut one_band) = (0usize, 0usize);
    // The depth of each law's base band (the deepest level where its slope
    // falls), and that depth over the depth the asperity reaches.
    let (mut first_drop, mut share) = (Vec::new(), Vec::new());
    let mut count = |base: &dyn Fn(f64) -> f64, depth: f64| {
        if depth > 0.0 {
            reached += 1;
            let b = base(depth);
            if b > 0.0 {
                first_drop.push(b);
                share.push(b / depth);
                // Below the next level the whole reach is one band.
                if b >= depth {
                    one_band += 1;
                }
            }
        }
    };
    let top = wilke.top();
    if calibrated {
        let texture = scenario.texture.as_ref().ok_or("no [texture]")?;
        let map = texture.height_map(base)?;
        let troad = tyreroad::texture_road::texture_road(&map, material, &texture.road_options())?;
        let calibrator = Calibrator::new(material, CalibrationOptions::default());
        let cal = calibrate_rolling_road(&troad, &wilke, &map, &config, &calibrator, par)?;
        let set = &cal.set;
        for (law, z) in set.laws().iter().zip(set.heights()) {
            count(
                &|d| base_band_depth(law, modulus, per_decade, d),
                bound - (top - z),
            );
        }
    } else {
        let (laws, z) = (wilke.laws(), wilke.heights());
        for i in selectable(wilke.positions(), &config) {
            let law = &laws[i];
            count(
                &|d| base_band_depth(law, modulus, per_decade, d),
                bound - (top - z[i]),
            );
        }
    }
    println!(
        "{path}: {} laws, largest Wilke approach {:.3} mm (tables to {:.3} mm), {per_decade} bands a decade: \
         {reached} asperities reach a positive depth, {} have a base band ({:.1} %), {one_band} are one band down to their depth",
        if calibrated { "calibrated" } else { "Wilke" },
        bound * 1e3,
        APPROACH_MARGIN * bound * 1e3,
        first_drop.len(),
        100.0 * first_drop.len() as f64 / reached.max(1) as f64,
    );
    for (what, values, unit) in [
        ("base band depth (µm)", &mut first_drop, 1e6),
        ("base band over the depth reached", &mut share, 1.0),
    ] {
        if values.is_empty() {
            continue;
        }
        values.sort_by(f64::total_cmp);
        let q = |f: f64| values[((values.len() - 1) as f64 * f).round() as usize] * unit;
        println!(
            "  {what}: min {:.3}, quartiles {:.3} / {:.3} / {:.3}, max {:.3}",
            q(0.0),
            q(0.25),
            q(0.5),
            q(0.75),
            q(1.0)
        );
    }
    Ok(())
}
