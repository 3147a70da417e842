//! The synthetic road: a seeded dense-asphalt-like field of spherical
//! summits, one configuration of the multipoint crate's sphere-summit
//! generator (`tyreroad_multipoint::layouts`).

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::AsperitySet;
use tyreroad_multipoint::layouts::{DrawOrder, Heights, Placement, SphereSummitField};

use crate::{Road, RollingError};

/// Parameters of a synthetic road of spherical summits.
///
/// Summits are placed by random sequential addition (dart throwing) on the
/// rectangle `x ∈ [0, length)`, `y ∈ [−width/2, width/2)`: a candidate is
/// kept when no kept summit lies closer than `min_spacing`, until `density ·
/// length · width` summits are placed or `50 ×` that many candidates have
/// been tried. Radii are uniform in `[radius_min, radius_max]`; heights are
/// the mean of three uniforms on `[0, height_spread]` (bell-shaped, bounded,
/// mean `height_spread/2`, standard deviation `height_spread/6`). Everything
/// follows from `seed` (ChaCha8): the same parameters give the same road on
/// every platform.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SyntheticRoad {
    /// Seed of the generator.
    pub seed: u64,
    /// Extent along x (m).
    pub length: f64,
    /// Extent along y (m), centred on `y = 0`.
    pub width: f64,
    /// Target number of summits per m².
    pub density: f64,
    /// Smallest distance between two summits (m).
    pub min_spacing: f64,
    /// Smallest summit radius (m).
    pub radius_min: f64,
    /// Largest summit radius (m).
    pub radius_max: f64,
    /// Range of summit heights (m).
    pub height_spread: f64,
}

impl Default for SyntheticRoad {
    /// A dense-asphalt-like patch: 0.5 m × 0.15 m, 85 000 summits/m²
    /// (≈ 6 400 summits, mean spacing ≈ 3.4 mm), at least 2 mm apart, radii
    /// 2–5 mm, heights spread over 2 mm.
    fn default() -> Self {
        Self {
            seed: 2006,
            length: 0.5,
            width: 0.15,
            density: 85_000.0,
            min_spacing: 2e-3,
            radius_min: 2e-3,
            radius_max: 5e-3,
            height_spread: 2e-3,
        }
    }
}

impl SyntheticRoad {
    /// The road as a sphere-summit field (radii drawn before heights).
    pub fn field(&self) -> SphereSummitField {
        SphereSummitField {
            placement: Placement::DartThrowing {
                length: self.length,
                width: self.width,
                density: self.density,
                min_spacing: self.min_spacing,
            },
            heights: Heights::MeanOfThree {
                spread: self.height_spread,
            },
            radius_min: self.radius_min,
            radius_max: self.radius_max,
            draw_order: DrawOrder::RadiiThenHeights,
        }
    }

    /// The summits, each a sphere with the Wilke–Sameur law (paper's
    /// `c = 0.36`, Hertz local rule) on `material`.
    pub fn generate(
        &self,
        material: Material,
    ) -> Result<AsperitySet<PotentialLaw<Sphere>>, RollingError> {
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        self.field()
            .generate(material, || rng.random::<f64>())
            .map_err(|e| RollingError::InvalidInput(format!("synthetic road: {e}")))
    }

    /// The road of [`Self::generate`]'s summits.
    pub fn sphere_road(
        &self,
        material: Material,
    ) -> Result<Road<PotentialLaw<Sphere>>, RollingError> {
        Ok(Road::new(self.generate(material)?))
    }
}
