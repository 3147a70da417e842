//! Reproducible fields of spherical summits: the one generator behind the
//! road-like layout of tests, examples and benchmarks and the rolling
//! crate's synthetic road.
//!
//! A field is drawn from the caller's uniform numbers in `[0, 1)`, so that it
//! is reproducible from the caller's seed and generator. The draws come in a
//! fixed order: the placement's, then heights and radii in the field's
//! [`DrawOrder`].

use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};

use crate::{AsperitySet, Problem, SolveError};

/// Pitch of the road-like layout's grid (m).
const PITCH: f64 = 3e-3;

/// The most summits a field may hold (each placement's count, or a dart
/// throw's `density × length × width`): a count past it is a unit slip,
/// and would exhaust memory before any solve.
pub const MAX_SUMMITS: usize = 100_000_000;

/// Where the summits go.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Placement {
    /// `count` summits on a square grid of `pitch` (m), filled row by row in
    /// `⌈√count⌉` columns from `(pitch/2, pitch/2)`, each jittered by up to
    /// `±pitch/3` in x and y (two draws a summit, x first), so no two summits
    /// are closer than `pitch/3`.
    JitteredGrid {
        /// Number of summits.
        count: usize,
        /// Grid pitch (m).
        pitch: f64,
    },
    /// `count` summits scattered uniformly over the square `[0, side)²` (two
    /// draws a summit, x first). Nothing keeps them apart: two summits may
    /// fall microns apart, where the point-force coupling swamps the laws.
    Scattered {
        /// Number of summits.
        count: usize,
        /// Side of the square (m).
        side: f64,
    },
    /// Random sequential addition (dart throwing) on `x ∈ [0, length)`,
    /// `y ∈ [−width/2, width/2)`: a candidate (two draws, x first) is kept
    /// when no kept summit lies closer than `min_spacing`, until
    /// `density · length · width` summits are placed or `50 ×` that many
    /// candidates have been tried.
    DartThrowing {
        /// Extent along x (m).
        length: f64,
        /// Extent along y (m), centred on `y = 0`.
        width: f64,
        /// Target number of summits per m².
        density: f64,
        /// Smallest distance between two summits (m).
        min_spacing: f64,
    },
}

/// How summit heights are drawn, from 0 up to `spread` (m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Heights {
    /// One uniform draw a summit: `z = u · spread`.
    Uniform {
        /// Range of the heights (m).
        spread: f64,
    },
    /// The mean of three uniform draws, times `spread`: bell-shaped and
    /// bounded, mean `spread/2`, standard deviation `spread/6`.
    MeanOfThree {
        /// Range of the heights (m).
        spread: f64,
    },
}

/// Which of heights and radii are drawn first (after the placement): part
/// of a field's definition, since it decides which draws each gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum DrawOrder {
    /// Every height, then every radius.
    HeightsThenRadii,
    /// Every radius, then every height.
    RadiiThenHeights,
}

/// A field of spherical summits, each with the Wilke–Sameur law
/// (`PotentialLaw::sphere`) on the half-space's material.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SphereSummitField {
    /// Where the summits go.
    pub placement: Placement,
    /// How their heights are drawn.
    pub heights: Heights,
    /// Smallest sphere radius (m).
    pub radius_min: f64,
    /// Largest sphere radius (m); radii are uniform in
    /// `[radius_min, radius_max]`.
    pub radius_max: f64,
    /// The order of the height and radius draws.
    pub draw_order: DrawOrder,
}

impl SphereSummitField {
    /// The road-like layout of `n` spherical chippings: summits on a square
    /// grid of 3 mm pitch, each jittered by up to ±1 mm in x and y (so no two
    /// summits are closer than 1 mm: uniformly scattered summits can fall
    /// microns apart, where the point-force coupling swamps the laws and the
    /// model itself breaks down), heights uniform over 0.5 mm, radii uniform
    /// in 1–5 mm; heights drawn before radii.
    pub fn road_like(n: usize) -> Self {
        Self {
            placement: Placement::JitteredGrid {
                count: n,
                pitch: PITCH,
            },
            heights: Heights::Uniform { spread: 5e-4 },
            radius_min: 1e-3,
            radius_max: 5e-3,
            draw_order: DrawOrder::HeightsThenRadii,
        }
    }

    fn validate(&self) -> Result<(), SolveError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let placement_ok = match self.placement {
            Placement::JitteredGrid { count, pitch } => {
                (1..MAX_SUMMITS).contains(&count) && positive(pitch)
            }
            Placement::Scattered { count, side } => {
                (1..MAX_SUMMITS).contains(&count) && positive(side)
            }
            Placement::DartThrowing {
                length,
                width,
                density,
                min_spacing,
            } => {
                positive(length)
                    && positive(width)
                    && positive(density)
                    && positive(min_spacing)
                    && density * length * width < MAX_SUMMITS as f64
            }
        };
        let spread = match self.heights {
            Heights::Uniform { spread } | Heights::MeanOfThree { spread } => spread,
        };
        let ok = placement_ok
            && spread.is_finite()
            && spread >= 0.0
            && positive(self.radius_min)
            && self.radius_max.is_finite()
            && self.radius_max >= self.radius_min;
        if ok {
            Ok(())
        } else {
            Err(SolveError::InvalidInput(format!(
                "a sphere-summit field needs at least one summit, positive sizes, \
                 density, spacing and radii, radius_max ≥ radius_min, spread ≥ 0 and \
                 < 1e8 summits: {self:?}"
            )))
        }
    }

    /// The summits as a set of asperities, drawn from `uniform` (numbers in
    /// `[0, 1)`, in the order the module documents).
    ///
    /// # Errors
    /// [`SolveError::InvalidInput`] for a malformed field (see its fields),
    /// or when a dart-throwing placement keeps no summit.
    pub fn generate(
        &self,
        material: Material,
        mut uniform: impl FnMut() -> f64,
    ) -> Result<AsperitySet<PotentialLaw<Sphere>>, SolveError> {
        self.validate()?;
        let positions = match self.placement {
            Placement::JitteredGrid { count, pitch } => jittered_grid(count, pitch, &mut uniform),
            Placement::Scattered { count, side } => (0..count)
                .map(|_| [uniform() * side, uniform() * side])
                .collect(),
            Placement::DartThrowing {
                length,
                width,
                density,
                min_spacing,
            } => dart_throwing([length, width], density, min_spacing, &mut uniform),
        };
        let n = positions.len();
        let draw_heights = |uniform: &mut dyn FnMut() -> f64| -> Vec<f64> {
            (0..n)
                .map(|_| match self.heights {
                    Heights::Uniform { spread } => uniform() * spread,
                    Heights::MeanOfThree { spread } => {
                        let u: f64 = (0..3).map(|_| uniform()).sum();
                        spread * u / 3.0
                    }
                })
                .collect()
        };
        let (min, max) = (self.radius_min, self.radius_max);
        let draw_radii = |uniform: &mut dyn FnMut() -> f64| -> Vec<f64> {
            (0..n).map(|_| min + uniform() * (max - min)).collect()
        };
        let (heights, radii) = match self.draw_order {
            DrawOrder::HeightsThenRadii => {
                let heights = draw_heights(&mut uniform);
                (heights, draw_radii(&mut uniform))
            }
            DrawOrder::RadiiThenHeights => {
                let radii = draw_radii(&mut uniform);
                (draw_heights(&mut uniform), radii)
            }
        };
        let laws = radii
            .into_iter()
            .map(|radius| {
                Sphere::new(radius)
                    .map(|s| PotentialLaw::sphere(s, material))
                    .map_err(|e| SolveError::InvalidInput(format!("radius {radius}: {e}")))
            })
            .collect::<Result<Vec<_>, _>>()?;
        AsperitySet::new(positions, heights, laws)
    }
}

fn jittered_grid(n: usize, pitch: f64, uniform: &mut impl FnMut() -> f64) -> Vec<[f64; 2]> {
    let columns = (n as f64).sqrt().ceil() as usize;
    let mut jitter = || pitch * (uniform() - 0.5) * 2.0 / 3.0;
    (0..n)
        .map(|k| {
            let (i, j) = ((k % columns) as f64, (k / columns) as f64);
            [pitch * (i + 0.5) + jitter(), pitch * (j + 0.5) + jitter()]
        })
        .collect()
}

fn dart_throwing(
    [length, width]: [f64; 2],
    density: f64,
    min_spacing: f64,
    uniform: &mut impl FnMut() -> f64,
) -> Vec<[f64; 2]> {
    let target = (density * length * width).round() as usize;
    // A grid of cells at least one spacing wide: a candidate's neighbours
    // lie in the 3 × 3 cells around its own. A spacing far below the
    // summits' mean distance widens the cells to about that distance, so
    // the grid holds about one cell per summit, not (length / spacing)².
    let cell = min_spacing.max((length * width / target.max(1) as f64).sqrt());
    let (nx, ny) = (
        (length / cell).ceil() as usize + 1,
        (width / cell).ceil() as usize + 1,
    );
    let mut grid: Vec<Vec<usize>> = vec![Vec::new(); nx * ny];
    let mut positions: Vec<[f64; 2]> = Vec::with_capacity(target);
    let d2 = min_spacing * min_spacing;
    let mut tries = 0;
    while positions.len() < target && tries < 50 * target {
        tries += 1;
        let x = uniform() * length;
        let y = (uniform() - 0.5) * width;
        let (cx, cy) = ((x / cell) as usize, ((y + 0.5 * width) / cell) as usize);
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
    positions
}

/// The static problem on [`SphereSummitField::road_like`]`(n)`: the tread
/// touches the highest summit at `δ0 = 0`.
///
/// # Errors
/// As [`SphereSummitField::generate`] and [`Problem::from_set`] (never, for
/// `n ≥ 1` and draws in `[0, 1)`).
pub fn road_like_field(
    n: usize,
    material: Material,
    uniform: impl FnMut() -> f64,
) -> Result<Problem<PotentialLaw<Sphere>>, SolveError> {
    Problem::from_set(
        SphereSummitField::road_like(n).generate(material, uniform)?,
        material,
    )
}

/// 36 balls of R = 50 mm on a 6 × 6 grid of 1 mm pitch, each jittered by up
/// to ±0.15 mm in x and y, with initial gaps up to 20 µm (three draws a
/// ball: x, y, gap). Under about 100 N their Hertz radii (≈ 1.7 mm) exceed
/// the spacing, so the point-force coupling outweighs the laws'
/// compliances, `diag(1/k) + T` turns indefinite and the load path folds
/// before the load (docs/theory.md §3): the layout on which a solve must
/// fail cleanly, and short of the fold converge.
///
/// # Errors
/// As [`Problem::new`] (never, for draws in `[0, 1)`).
pub fn folding_field(
    material: Material,
    mut uniform: impl FnMut() -> f64,
) -> Result<Problem<PotentialLaw<Sphere>>, SolveError> {
    let (mut positions, mut gaps) = (Vec::new(), Vec::new());
    for j in 0..6 {
        for i in 0..6 {
            let x = (f64::from(i) + 0.3 * (uniform() - 0.5)) * 1e-3;
            let y = (f64::from(j) + 0.3 * (uniform() - 0.5)) * 1e-3;
            positions.push([x, y]);
            gaps.push(20e-6 * uniform());
        }
    }
    let ball = Sphere::new(50e-3).map_err(|e| SolveError::InvalidInput(e.to_string()))?;
    let law = PotentialLaw::sphere(ball, material);
    Problem::new(positions, gaps, vec![law; 36], material)
}

/// 400 balls on a 20 × 20 grid of 1.5 mm pitch, each jittered by up to
/// 0.2 mm, with gaps spread over 0.3 mm and radii over 0.5–2.5 mm: at a few
/// hundred newtons neighbouring patches come within their radii of each
/// other, many contacts enter during a solve. The draws, from `uniform`
/// (values in `[0, 1)`), are taken in a fixed order (positions, gaps, radii),
/// so a seeded generator gives the same layout everywhere.
///
/// # Errors
/// As [`Problem::from_heights`] (never, for draws in `[0, 1)`).
pub fn dense_sphere_grid(
    material: Material,
    mut uniform: impl FnMut() -> f64,
) -> Result<Problem<PotentialLaw<Sphere>>, SolveError> {
    let mut positions = Vec::with_capacity(400);
    for j in 0..20 {
        for i in 0..20 {
            let x = f64::from(i) * 1.5e-3 + 2e-4 * uniform();
            let y = f64::from(j) * 1.5e-3 + 2e-4 * uniform();
            positions.push([x, y]);
        }
    }
    let heights: Vec<f64> = (0..positions.len()).map(|_| 3e-4 * uniform()).collect();
    let laws = (0..positions.len())
        .map(|_| {
            Sphere::new(0.5e-3 + 2e-3 * uniform())
                .map(|ball| PotentialLaw::sphere(ball, material))
                .map_err(|e| SolveError::InvalidInput(e.to_string()))
        })
        .collect::<Result<Vec<_>, _>>()?;
    Problem::from_heights(positions, &heights, laws, material)
}
