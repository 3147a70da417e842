//! A road as a generic set of asperities, indexed by x for window queries.

use tyreroad_multipoint::AsperitySet;

use crate::RollingError;

/// A road surface reduced to asperities: an [`AsperitySet`] (summit
/// positions `(x_i, y_i)`, x along the driving direction, y across, m;
/// summit heights `z_i`, m, up towards the tread; one contact law each)
/// indexed along x.
///
/// An asperity's id is its index in the set given to [`Road::new`]; results
/// and warm starts refer to asperities by id. The asperities are also sorted
/// by x so that the ones under a footprint are found by binary search
/// (`O(log N + window)` per step). (Coincident summits are reported by the
/// solver when they fall under the same footprint.)
#[derive(Clone, Debug)]
pub struct Road<L> {
    set: AsperitySet<L>,
    /// Ids sorted by x (ties by id).
    by_x: Vec<usize>,
    /// `positions[by_x[k]][0]`.
    sorted_x: Vec<f64>,
    /// `set.top()`, read at every step.
    top: f64,
    /// Summit curvature radius per id (m), if known: the tread gap is then
    /// measured at the contact point ([`crate::Tread::contact_gap`]).
    summit_radii: Option<Vec<f64>>,
}

impl<L> Road<L> {
    /// The road on a set of asperities (ids are the set's indices). The set
    /// is already validated (non-empty, finite), so this cannot fail.
    pub fn new(set: AsperitySet<L>) -> Self {
        let positions = set.positions();
        let mut by_x: Vec<usize> = (0..set.len()).collect();
        by_x.sort_by(|&a, &b| positions[a][0].total_cmp(&positions[b][0]).then(a.cmp(&b)));
        let sorted_x = by_x.iter().map(|&i| positions[i][0]).collect();
        let top = set.top();
        Self {
            set,
            by_x,
            sorted_x,
            top,
            summit_radii: None,
        }
    }

    /// The same road with each asperity's summit curvature radius (m, by
    /// id), so that each step's gap is measured at the point of the cap
    /// closest to the tread, not at the summit ([`crate::Tread::contact_gap`];
    /// without radii the gaps are the summits').
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] if the count differs from the road's
    /// or a radius is not finite and positive.
    pub fn with_summit_radii(mut self, radii: Vec<f64>) -> Result<Self, RollingError> {
        if radii.len() != self.set.len() {
            return Err(RollingError::InvalidInput(format!(
                "summit radii: {} given for {} asperities",
                radii.len(),
                self.set.len()
            )));
        }
        if let Some((i, r)) = radii
            .iter()
            .enumerate()
            .find(|(_, r)| !(r.is_finite() && **r > 0.0))
        {
            return Err(RollingError::InvalidInput(format!(
                "summit radius of asperity {i}: expected finite and > 0 m, got {r}"
            )));
        }
        self.summit_radii = Some(radii);
        Ok(self)
    }

    /// The summit curvature radius of asperity `id` (m), infinite if the
    /// road has none.
    pub fn summit_radius(&self, id: usize) -> f64 {
        self.summit_radii
            .as_ref()
            .and_then(|r| r.get(id).copied())
            .unwrap_or(f64::INFINITY)
    }

    /// The road's asperities.
    pub fn set(&self) -> &AsperitySet<L> {
        &self.set
    }

    /// Number of asperities.
    pub fn len(&self) -> usize {
        self.set.len()
    }

    /// Always false: a road holds at least one asperity.
    pub fn is_empty(&self) -> bool {
        self.set.is_empty()
    }

    /// Summit positions `(x_i, y_i)` (m), by id.
    pub fn positions(&self) -> &[[f64; 2]] {
        self.set.positions()
    }

    /// Summit heights `z_i` (m), by id.
    pub fn heights(&self) -> &[f64] {
        self.set.heights()
    }

    /// Contact laws, by id.
    pub fn laws(&self) -> &[L] {
        self.set.laws()
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
                .filter(|&i| (y0..=y1).contains(&self.set.positions()[i][1])),
        );
    }
}
