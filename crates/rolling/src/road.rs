//! A road as a generic set of asperities, indexed by x for window queries.

use tyreroad_contact_law::ContactLaw;
use tyreroad_multipoint::AsperitySet;

use crate::RollingError;

/// A road surface reduced to asperities: summit positions `(x_i, y_i)`
/// (x along the driving direction, y across; m), summit heights `z_i` (m, up
/// towards the tread) and one contact law per asperity.
///
/// An asperity's id is its index in the vectors given to [`Road::new`];
/// results and warm starts refer to asperities by id. Internally the
/// asperities are also sorted by x so that the ones under a footprint are
/// found by binary search (`O(log N + window)` per step).
#[derive(Clone, Debug)]
pub struct Road<L> {
    positions: Vec<[f64; 2]>,
    heights: Vec<f64>,
    laws: Vec<L>,
    /// Ids sorted by x (ties by id).
    by_x: Vec<usize>,
    /// `positions[by_x[k]][0]`.
    sorted_x: Vec<f64>,
    top: f64,
}

impl<L: ContactLaw> Road<L> {
    /// A road from summit positions, heights and laws (one per asperity).
    ///
    /// Errors: no asperity, lengths that differ, or a coordinate or height
    /// that is not finite. (Coincident summits are reported by the solver
    /// when they fall under the same footprint.)
    pub fn new(
        positions: Vec<[f64; 2]>,
        heights: Vec<f64>,
        laws: Vec<L>,
    ) -> Result<Self, RollingError> {
        let n = positions.len();
        if n == 0 {
            return Err(RollingError::InvalidInput(
                "the road has no asperity".into(),
            ));
        }
        if heights.len() != n || laws.len() != n {
            return Err(RollingError::InvalidInput(format!(
                "{n} positions but {} heights and {} laws",
                heights.len(),
                laws.len()
            )));
        }
        if let Some(i) = (0..n).find(|&i| {
            !(positions[i][0].is_finite() && positions[i][1].is_finite() && heights[i].is_finite())
        }) {
            return Err(RollingError::InvalidInput(format!(
                "asperity {i}: position {:?} or height {} is not finite",
                positions[i], heights[i]
            )));
        }
        let mut by_x: Vec<usize> = (0..n).collect();
        by_x.sort_by(|&a, &b| positions[a][0].total_cmp(&positions[b][0]).then(a.cmp(&b)));
        let sorted_x = by_x.iter().map(|&i| positions[i][0]).collect();
        let top = heights.iter().copied().fold(f64::NEG_INFINITY, f64::max);
        Ok(Self {
            positions,
            heights,
            laws,
            by_x,
            sorted_x,
            top,
        })
    }
}

impl<L: ContactLaw> Road<L> {
    /// A road from a set of asperities (ids are the set's indices).
    pub fn from_set(set: AsperitySet<L>) -> Result<Self, RollingError> {
        let (positions, heights, laws) = set.into_parts();
        Self::new(positions, heights, laws)
    }
}

impl<L> Road<L> {
    /// Number of asperities.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Always false: a road holds at least one asperity.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Summit positions `(x_i, y_i)` (m), by id.
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Summit heights `z_i` (m), by id.
    pub fn heights(&self) -> &[f64] {
        &self.heights
    }

    /// Contact laws, by id.
    pub fn laws(&self) -> &[L] {
        &self.laws
    }

    /// The highest summit `z_max` (m): the reference plane of the gaps.
    pub fn top(&self) -> f64 {
        self.top
    }

    /// Extent `[x_min, x_max]` of the summits along x (m).
    pub fn x_range(&self) -> [f64; 2] {
        [
            self.sorted_x.first().copied().unwrap_or(0.0),
            self.sorted_x.last().copied().unwrap_or(0.0),
        ]
    }

    /// Ids of the asperities with `x0 ≤ x ≤ x1` and `y0 ≤ y ≤ y1`, in
    /// increasing x (ties by id): binary search on x, then a filter on y.
    pub fn window(&self, [x0, x1]: [f64; 2], [y0, y1]: [f64; 2], out: &mut Vec<usize>) {
        out.clear();
        let lo = self.sorted_x.partition_point(|&x| x < x0);
        let hi = self.sorted_x.partition_point(|&x| x <= x1);
        out.extend(
            self.by_x[lo..hi]
                .iter()
                .copied()
                .filter(|&i| (y0..=y1).contains(&self.positions[i][1])),
        );
    }
}
