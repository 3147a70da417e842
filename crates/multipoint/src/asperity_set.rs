//! The one form of a set of road asperities that every layer builds from.

use crate::SolveError;

/// N rigid asperities: summit positions `(x_i, y_i)` (m), summit heights
/// `z_i` (m, up towards the tread) and one contact law each, indexed alike.
///
/// This is what a scenario's `[[asperity]]` list, a segmented texture and a
/// rolling road all reduce to; [`Problem::from_set`](crate::Problem::from_set)
/// turns it into a static problem and the rolling crate's `Road` indexes it
/// along the path.
///
/// Invariants checked on construction: at least one asperity, as many
/// positions, heights and laws, every coordinate and height finite.
/// (Coincident summits are the solver's concern: a rolling road may hold two
/// summits that never share a footprint.)
#[derive(Clone, Debug)]
pub struct AsperitySet<L> {
    positions: Vec<[f64; 2]>,
    heights: Vec<f64>,
    laws: Vec<L>,
}

impl<L> AsperitySet<L> {
    /// A set from positions (m), heights (m) and laws, one each per asperity.
    ///
    /// # Errors
    /// [`SolveError::InvalidInput`] for an empty set, lengths that differ, or
    /// a non-finite coordinate or height (naming the asperity's index).
    pub fn new(
        positions: Vec<[f64; 2]>,
        heights: Vec<f64>,
        laws: Vec<L>,
    ) -> Result<Self, SolveError> {
        let n = positions.len();
        if n == 0 {
            return Err(SolveError::InvalidInput("no asperity".into()));
        }
        if heights.len() != n || laws.len() != n {
            return Err(SolveError::InvalidInput(format!(
                "{n} positions but {} heights and {} laws",
                heights.len(),
                laws.len()
            )));
        }
        if let Some(i) = (0..n).find(|&i| {
            !(positions[i][0].is_finite() && positions[i][1].is_finite() && heights[i].is_finite())
        }) {
            return Err(SolveError::InvalidInput(format!(
                "asperity {i}: position {:?} or height {} is not finite",
                positions[i], heights[i]
            )));
        }
        Ok(Self {
            positions,
            heights,
            laws,
        })
    }

    /// Number of asperities N.
    pub fn len(&self) -> usize {
        self.positions.len()
    }

    /// Always false: a set holds at least one asperity.
    pub fn is_empty(&self) -> bool {
        self.positions.is_empty()
    }

    /// Summit positions `(x_i, y_i)` (m).
    pub fn positions(&self) -> &[[f64; 2]] {
        &self.positions
    }

    /// Summit heights `z_i` (m).
    pub fn heights(&self) -> &[f64] {
        &self.heights
    }

    /// The contact laws.
    pub fn laws(&self) -> &[L] {
        &self.laws
    }

    /// The highest summit `max z_i` (m).
    pub fn top(&self) -> f64 {
        self.heights
            .iter()
            .copied()
            .fold(f64::NEG_INFINITY, f64::max)
    }

    /// The same set moved by `(dx, dy)` (m) in the horizontal plane.
    ///
    /// # Errors
    /// [`SolveError::InvalidInput`] if a moved coordinate is not finite.
    pub fn translated(self, [dx, dy]: [f64; 2]) -> Result<Self, SolveError> {
        let positions = self
            .positions
            .iter()
            .map(|&[x, y]| [x + dx, y + dy])
            .collect();
        Self::new(positions, self.heights, self.laws)
    }

    /// The parts, by index: positions, heights, laws.
    pub fn into_parts(self) -> (Vec<[f64; 2]>, Vec<f64>, Vec<L>) {
        (self.positions, self.heights, self.laws)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn refuses_empty_mismatched_and_non_finite_sets() {
        assert!(AsperitySet::<()>::new(vec![], vec![], vec![]).is_err());
        assert!(AsperitySet::new(vec![[0.0, 0.0]], vec![], vec![()]).is_err());
        let err = AsperitySet::new(
            vec![[0.0, 0.0], [1.0, f64::NAN]],
            vec![0.0, 0.0],
            vec![(), ()],
        )
        .expect_err("NaN y");
        assert!(err.to_string().contains("asperity 1"), "{err}");
        assert!(AsperitySet::new(vec![[0.0, 0.0]], vec![f64::INFINITY], vec![()]).is_err());
    }

    #[test]
    fn translation_moves_positions_and_keeps_heights() -> Result<(), SolveError> {
        let set = AsperitySet::new(vec![[1.0, 2.0], [3.0, 4.0]], vec![0.5, -0.5], vec![(), ()])?;
        assert_eq!(set.top(), 0.5);
        let moved = set.translated([-1.0, 0.5])?;
        assert_eq!(moved.positions(), &[[0.0, 2.5], [2.0, 4.5]]);
        assert_eq!(moved.heights(), &[0.5, -0.5]);
        Ok(())
    }
}
