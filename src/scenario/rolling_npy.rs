//! A `[rolling]` road on a `.npy` texture, read by windows (docs/distributed.md,
//! "Memory per rank"): whether the scenario's road is one, and its summary and
//! summits without the whole road's laws.

use std::path::PathBuf;

use tyreroad_contact_law::Material;

use super::texture::TextureSummary;
use super::{RunOptions, Scenario, ScenarioError};
use crate::fidelity::Fidelity;
use crate::texture_road::window::NpyTextureRoad;

/// The scenario's texture road, opened for reading by windows, when its
/// `[texture] file` is a `.npy` map rolled with the Wilke laws; `None` when
/// the road is read whole (other formats, no texture, calibrated laws).
pub(super) fn npy_window_road(
    scenario: &Scenario,
    options: &RunOptions<'_>,
    material: Material,
) -> Result<Option<NpyTextureRoad>, ScenarioError> {
    let Some(texture) = &scenario.texture else {
        return Ok(None);
    };
    if scenario.fidelity()? != Fidelity::Wilke {
        return Ok(None);
    }
    let Some(path) = npy_file(texture, options) else {
        return Ok(None);
    };
    if scenario
        .rolling
        .as_ref()
        .is_some_and(|r| r.sensors_on_caps())
    {
        return Err(ScenarioError::Invalid(format!(
            "[rolling] sensor_accounting = \"caps\" needs the whole map, and {} is read in \
             windows (a .npy road with the wilke rung); use \"run\"",
            path.display()
        )));
    }
    // Before the open pass over the whole file, which a spacing of 1e30 m
    // would only make slow and useless.
    let (dx, dy) = crate::texture::io::npy::sidecar_spacing(&path).map_err(|source| {
        ScenarioError::Texture {
            context: format!("[texture] reading {}", path.display()),
            source,
        }
    })?;
    super::ranges::texture_file_spacing(&path, dx, dy)?;
    Ok(Some(NpyTextureRoad::open(
        &path,
        material,
        &texture.road_options(),
    )?))
}

/// What the texture summary says of a `.npy` road opened by windows: the
/// whole build's counts; Sq summed tile by tile (equal to the whole map's
/// to rounding).
pub(super) fn npy_summary(road: &NpyTextureRoad) -> TextureSummary {
    let ((nx, ny), (dx, dy)) = (road.size(), road.spacing());
    let (valid, total) = road.valid_points();
    TextureSummary {
        size: (nx, ny),
        spacing: (dx, dy),
        extent: ((nx - 1) as f64 * dx, (ny - 1) as f64 * dy),
        rms: road.rms(),
        top: road.top(),
        asperities: road.len(),
        segmented: road.segmented(),
        calibration: None,
        // Sq, the spacing and the missing points only: the heights are
        // read tile by tile, never whole, so no percentiles for the
        // outliers' check.
        warnings: super::height_checks::missing_points_warning(valid, total)
            .into_iter()
            .chain(super::height_checks::roughness_warning(road.rms()))
            .chain(super::height_checks::spacing_warning(dx, dy))
            .collect(),
    }
}

/// The summits of a `.npy` road opened by windows, in id order, gathered
/// for `--gather`'s finish, which takes them whole (24 B a summit; the
/// streamed finish walks the road itself, as a [`SummitSource`]).
pub(super) fn npy_summits(
    road: &NpyTextureRoad,
) -> Result<(Vec<[f64; 2]>, Vec<f64>), ScenarioError> {
    let mut positions = Vec::with_capacity(road.len());
    let mut heights = Vec::with_capacity(road.len());
    road.summits(|_, p, z| {
        positions.push(p);
        heights.push(z);
    })?;
    Ok((positions, heights))
}

/// The `[texture] file` when it is a `.npy` map (read by windows), else
/// `None` (read whole).
pub(super) fn npy_file(texture: &super::TextureSpec, options: &RunOptions<'_>) -> Option<PathBuf> {
    let file = texture.file.as_ref()?;
    let path = options.base_dir.join(file);
    path.extension()
        .is_some_and(|e| e.eq_ignore_ascii_case("npy"))
        .then_some(path)
}
