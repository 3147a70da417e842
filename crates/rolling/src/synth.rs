//! A deterministic synthetic road of random spheres (chipping-like), for
//! runs and tests while the texture crate is not available.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};

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

/// The generated summits.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereSummits {
    /// Summit positions `(x, y)` (m).
    pub positions: Vec<[f64; 2]>,
    /// Summit heights (m).
    pub heights: Vec<f64>,
    /// Sphere radii (m).
    pub radii: Vec<f64>,
}

impl SyntheticRoad {
    fn validate(&self) -> Result<(), RollingError> {
        let pos = |v: f64| v.is_finite() && v > 0.0;
        let ok = pos(self.length)
            && pos(self.width)
            && pos(self.density)
            && pos(self.min_spacing)
            && pos(self.radius_min)
            && self.radius_max.is_finite()
            && self.radius_max >= self.radius_min
            && self.height_spread.is_finite()
            && self.height_spread >= 0.0
            && self.density * self.length * self.width < 1e8;
        if ok {
            Ok(())
        } else {
            Err(RollingError::InvalidInput(format!(
                "synthetic road needs positive sizes, density, spacing and radii, \
                 radius_max ≥ radius_min, spread ≥ 0 and < 1e8 summits: {self:?}"
            )))
        }
    }

    /// The summits.
    pub fn generate(&self) -> Result<SphereSummits, RollingError> {
        self.validate()?;
        let mut rng = ChaCha8Rng::seed_from_u64(self.seed);
        let target = (self.density * self.length * self.width).round() as usize;
        let cell = self.min_spacing;
        let (nx, ny) = (
            (self.length / cell).ceil() as usize + 1,
            (self.width / cell).ceil() as usize + 1,
        );
        let mut grid: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
        let mut positions: Vec<[f64; 2]> = Vec::with_capacity(target);
        let d2 = self.min_spacing * self.min_spacing;
        let mut tries = 0;
        while positions.len() < target && tries < 50 * target {
            tries += 1;
            let x = rng.random::<f64>() * self.length;
            let y = (rng.random::<f64>() - 0.5) * self.width;
            let (cx, cy) = (
                (x / cell) as usize,
                ((y + 0.5 * self.width) / cell) as usize,
            );
            let mut free = true;
            'scan: for gx in cx.saturating_sub(1)..(cx + 2).min(nx) {
                for gy in cy.saturating_sub(1)..(cy + 2).min(ny) {
                    for &j in &grid[gx * ny + gy] {
                        let [px, py] = positions[j];
                        if (px - x).powi(2) + (py - y).powi(2) < d2 {
                            free = false;
                            break 'scan;
                        }
                    }
                }
            }
            if free {
                grid[cx.min(nx - 1) * ny + cy.min(ny - 1)].push(positions.len());
                positions.push([x, y]);
            }
        }
        let n = positions.len();
        let radii = (0..n)
            .map(|_| self.radius_min + rng.random::<f64>() * (self.radius_max - self.radius_min))
            .collect();
        let heights = (0..n)
            .map(|_| {
                let u: f64 = (0..3).map(|_| rng.random::<f64>()).sum();
                self.height_spread * u / 3.0
            })
            .collect();
        Ok(SphereSummits {
            positions,
            heights,
            radii,
        })
    }

    /// The road: each summit a sphere with the Wilke–Sameur law (paper's
    /// `c = 0.36`, Hertz local rule) on `material`.
    pub fn sphere_road(
        &self,
        material: Material,
    ) -> Result<Road<PotentialLaw<Sphere>>, RollingError> {
        let s = self.generate()?;
        let laws = s
            .radii
            .iter()
            .map(|&r| Sphere::new(r).map(|sp| PotentialLaw::sphere(sp, material)))
            .collect::<Result<Vec<_>, _>>()
            .map_err(|e| RollingError::InvalidInput(format!("sphere: {e}")))?;
        Road::new(s.positions, s.heights, laws)
    }
}
