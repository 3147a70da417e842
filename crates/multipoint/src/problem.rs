//! The multipoint contact problem: summits, initial gaps, laws, material.

use tyreroad_contact_law::{ContactLaw, Material};

use crate::{AsperitySet, SolveError};

/// N rigid asperities under one elastic half-space (docs/theory.md §3).
///
/// Invariants checked on construction: at least one asperity, as many
/// positions, gaps and laws, all coordinates and gaps finite, and no two
/// summits at the same horizontal position (the Boussinesq coefficient
/// `1/r` would be infinite).
#[derive(Clone, Debug)]
pub struct Problem<L> {
    positions: Vec<[f64; 2]>,
    gaps: Vec<f64>,
    laws: Vec<L>,
    material: Material,
}

impl<L: ContactLaw> Problem<L> {
    /// A problem from summit positions `(x_i, y_i)` (m), initial gaps `H_i`
    /// (m: the distance from the undeformed tread to summit `i` when the
    /// tread touches the reference plane `δ0 = 0`), one law per asperity, and
    /// the half-space's material (used by the Boussinesq coupling).
    pub fn new(
        positions: Vec<[f64; 2]>,
        gaps: Vec<f64>,
        laws: Vec<L>,
        material: Material,
    ) -> Result<Self, SolveError> {
        let n = positions.len();
        if n == 0 {
            return Err(SolveError::InvalidInput("no asperity".into()));
        }
        if gaps.len() != n || laws.len() != n {
            return Err(SolveError::InvalidInput(format!(
                "{n} positions but {} gaps and {} laws",
                gaps.len(),
                laws.len()
            )));
        }
        if let Some(i) = positions
            .iter()
            .position(|p| !(p[0].is_finite() && p[1].is_finite()))
        {
            return Err(SolveError::InvalidInput(format!(
                "asperity {i}: position {:?} is not finite",
                positions[i]
            )));
        }
        if let Some(i) = gaps.iter().position(|g| !g.is_finite()) {
            return Err(SolveError::InvalidInput(format!(
                "asperity {i}: gap {} is not finite",
                gaps[i]
            )));
        }
        if let Some((i, j)) = find_coincident(&positions) {
            return Err(SolveError::CoincidentSummits {
                first: i,
                second: j,
            });
        }
        Ok(Self {
            positions,
            gaps,
            laws,
            material,
        })
    }

    /// A problem from summit heights `z_i` (m, up towards the tread): the
    /// tread touches the highest summit at `δ0 = 0`, so `H_i = max z − z_i`.
    pub fn from_heights(
        positions: Vec<[f64; 2]>,
        heights: &[f64],
        laws: Vec<L>,
        material: Material,
    ) -> Result<Self, SolveError> {
        if let Some(i) = heights.iter().position(|z| !z.is_finite()) {
            return Err(SolveError::InvalidInput(format!(
                "asperity {i}: height {} is not finite",
                heights[i]
            )));
        }
        let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Self::new(
            positions,
            heights.iter().map(|z| top - z).collect(),
            laws,
            material,
        )
    }

    /// A problem from a set of asperities: the tread touches the highest
    /// summit at `δ0 = 0` (as [`Problem::from_heights`]).
    pub fn from_set(set: AsperitySet<L>, material: Material) -> Result<Self, SolveError> {
        let (positions, heights, laws) = set.into_parts();
        Self::from_heights(positions, &heights, laws, material)
    }

    /// Number of asperities N.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Always false: a problem holds at least one asperity.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Summit positions `(x_i, y_i)` (m).
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Initial gaps `H_i` (m).
    pub fn gaps(&self) -> &[f64] {
        &self.gaps
    }

    /// The contact laws.
    pub fn laws(&self) -> &[L] {
        &self.laws
    }

    /// The half-space's material.
    pub fn material(&self) -> &Material {
        &self.material
    }
}

/// Two summits closer than `10⁻¹²` of the layout's extent, if any. Sorting by
/// x keeps this O(N log N) for any sane layout.
fn find_coincident(positions: &[[f64; 2]]) -> Option<(usize, usize)> {
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for p in positions {
        for k in 0..2 {
            lo[k] = lo[k].min(p[k]);
            hi[k] = hi[k].max(p[k]);
        }
    }
    // Halved before the difference, which overflows for summits at ±1e308
    // (an infinite tolerance then took every pair for coincident).
    let half_extent = (0.5 * hi[0] - 0.5 * lo[0]).hypot(0.5 * hi[1] - 0.5 * lo[1]);
    // Relative to the layout, and never so small that the coupling's `r²`
    // underflows to 0 (summits 1e-302 m apart were taken as one point with
    // no coupling between them, neither refused nor coupled).
    let eps = (2e-12 * half_extent).max(1e-100);
    let mut order: Vec<usize> = (0..positions.len()).collect();
    order.sort_by(|&a, &b| positions[a][0].total_cmp(&positions[b][0]));
    for (k, &i) in order.iter().enumerate() {
        for &j in &order[k + 1..] {
            if positions[j][0] - positions[i][0] > eps {
                break;
            }
            if (positions[j][1] - positions[i][1]).abs() <= eps {
                return Some((i.min(j), i.max(j)));
            }
        }
    }
    None
}
