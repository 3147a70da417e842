//! Reproducible asperity layouts for tests, examples and benchmarks.

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};

use crate::{Problem, SolveError};

/// Pitch of the road-like layout's grid (m).
const PITCH: f64 = 3e-3;

/// A road-like field of `n` spherical chippings: summits on a square grid
/// of 3 mm pitch, each jittered by up to ±1 mm in x and y (so no two summits
/// are closer than 1 mm: uniformly scattered summits can fall microns apart,
/// where the point-force coupling swamps the laws and the model itself
/// breaks down), summit heights uniform over 0.5 mm, radii uniform in
/// 1–5 mm, laws `PotentialLaw::sphere`.
///
/// `uniform` draws numbers in `[0, 1)`: the caller's generator, so that a
/// layout is reproducible from its seed. They are drawn in a fixed order:
/// the two jitters of every summit, then every height, then every radius.
///
/// # Errors
/// As [`Problem::from_heights`] (never, for `n ≥ 1` and draws in `[0, 1)`).
pub fn road_like_field(
    n: usize,
    material: Material,
    mut uniform: impl FnMut() -> f64,
) -> Result<Problem<PotentialLaw<Sphere>>, SolveError> {
    let columns = (n as f64).sqrt().ceil() as usize;
    let mut jitter = || PITCH * (uniform() - 0.5) * 2.0 / 3.0;
    let positions = (0..n)
        .map(|k| {
            let (i, j) = ((k % columns) as f64, (k / columns) as f64);
            [PITCH * (i + 0.5) + jitter(), PITCH * (j + 0.5) + jitter()]
        })
        .collect();
    let heights: Vec<f64> = (0..n).map(|_| uniform() * 5e-4).collect();
    let laws = (0..n)
        .map(|_| {
            let radius = 1e-3 + 4e-3 * uniform();
            Sphere::new(radius)
                .map(|s| PotentialLaw::sphere(s, material))
                .map_err(|e| SolveError::InvalidInput(format!("radius {radius}: {e}")))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Problem::from_heights(positions, &heights, laws, material)
}
