//! A road as a generic set of asperities, indexed by x for window queries;
//! a whole road, or the window of one that a rank of a distributed run
//! rolls on (docs/distributed.md).

use std::sync::OnceLock;

use tyreroad_contact_law::ContactLaw;
use tyreroad_multipoint::AsperitySet;

use crate::RollingError;
use crate::checkpoint::RoadDigest;

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
///
/// A **window** ([`Road::window_of`]) holds only the asperities of a whole
/// road that lie in an x-range, with what the results need from the whole
/// road: each asperity's global id (records, checkpoints and outputs name
/// asperities by it), the whole road's reference plane ([`Road::top`]) and
/// its digest (the checkpoint key). Rolled on the steps whose
/// footprints lie inside the window, it gives the whole road's records bit
/// for bit: the selection at a step is the same asperities in the same
/// order, so the same sub-problem. Inside the crate asperities are indexed
/// locally (`0..len()`); [`Road::global_id`] maps them out.
#[derive(Clone, Debug)]
pub struct Road<L> {
    set: AsperitySet<L>,
    /// Local indices sorted by x (ties by index).
    by_x: Vec<usize>,
    /// `positions[by_x[k]][0]`.
    sorted_x: Vec<f64>,
    /// The plane the approach is measured from (m): the whole road's
    /// highest summit unless given ([`Road::with_top`]); read at every step.
    top: f64,
    /// A window's global ids by local index, increasing; `None`: the whole
    /// road (global id = local index).
    global_ids: Option<Vec<usize>>,
    /// Asperities on the whole road.
    global_len: usize,
    /// The whole road's part of the checkpoint key ([`RoadDigest`]).
    digest: OnceLock<u64>,
    /// Summit curvature radius per id (m), if known: the tread gap is then
    /// measured at the contact point ([`crate::Tread::contact_gap`]).
    summit_radii: Option<Vec<f64>>,
    /// How each law changes with the footprint's position over its cap
    /// ([`crate::Placement`]); `None`: one law for the whole run.
    placement: Option<crate::Placement<L>>,
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
        let global_len = set.len();
        Self {
            set,
            by_x,
            sorted_x,
            top,
            global_ids: None,
            global_len,
            digest: OnceLock::new(),
            summit_radii: None,
            placement: None,
        }
    }

    /// The window of a whole road: `set` holds the whole road's asperities
    /// `global_ids` (strictly increasing, below `global_len`), in that
    /// order; `top` is the whole road's reference plane ([`Road::top`]) and
    /// `digest` its [`RoadDigest`] (both are what the whole road has, so a
    /// window's records and checkpoints are the whole road's).
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] when the ids are not one per asperity,
    /// strictly increasing and below `global_len`, or `top` is not finite.
    pub fn window_of(
        set: AsperitySet<L>,
        global_ids: Vec<usize>,
        global_len: usize,
        top: f64,
        digest: u64,
    ) -> Result<Self, RollingError> {
        let increasing = global_ids.windows(2).all(|w| w[0] < w[1]);
        if global_ids.len() != set.len()
            || !increasing
            || global_ids.last().is_some_and(|&i| i >= global_len)
        {
            return Err(RollingError::InvalidInput(format!(
                "a road window needs one global id per asperity ({} for {}), strictly \
                 increasing and below the road's {global_len} asperities",
                global_ids.len(),
                set.len()
            )));
        }
        let mut road = Self::new(set).with_top(top)?;
        road.global_ids = Some(global_ids);
        road.global_len = global_len;
        road.digest = OnceLock::from(digest);
        Ok(road)
    }

    /// The whole road's id of local asperity `local`.
    pub fn global_id(&self, local: usize) -> usize {
        self.global_ids.as_ref().map_or(local, |ids| ids[local])
    }

    /// The local index of the whole road's asperity `global`, if this road
    /// holds it.
    pub fn local_id(&self, global: usize) -> Option<usize> {
        match &self.global_ids {
            None => (global < self.set.len()).then_some(global),
            Some(ids) => ids.binary_search(&global).ok(),
        }
    }

    /// Asperities on the whole road (`len()` for a whole road).
    pub fn global_len(&self) -> usize {
        self.global_len
    }

    /// Whether this is a window of a larger road.
    pub fn is_window(&self) -> bool {
        self.global_ids.is_some()
    }

    /// The same road with each asperity's summit curvature radius (m, by
    /// id), so that each step's gap is measured at the point of the cap
    /// closest to the tread, not at the summit ([`crate::Tread::contact_gap`];
    /// without radii the gaps are the summits').
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] if the count differs from the road's,
    /// a radius is not finite and non-negative (zero: a sharp summit, its gap
    /// the summit's), or the road is a window (its
    /// digest is the whole road's, given when it was cut, so the radii
    /// must be known then).
    pub fn with_summit_radii(mut self, radii: Vec<f64>) -> Result<Self, RollingError> {
        if self.is_window() {
            return Err(RollingError::InvalidInput(
                "summit radii on a road window: give them to the whole road".into(),
            ));
        }
        check_radii(&radii, self.set.len())?;
        self.summit_radii = Some(radii);
        // The radii change the gaps, so they are part of the checkpoint key.
        self.digest = OnceLock::new();
        Ok(self)
    }

    /// A window with each asperity's summit curvature radius (m, by local
    /// index): the window's digest, given when it was cut, already holds
    /// the whole road's radii ([`RoadDigest::summit_radii`]), so it is kept.
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] if this is not a window, the count
    /// differs from the window's, or a radius is not finite and non-negative.
    pub fn window_with_summit_radii(mut self, radii: Vec<f64>) -> Result<Self, RollingError> {
        if !self.is_window() {
            return Err(RollingError::InvalidInput(
                "window_with_summit_radii on a whole road: use with_summit_radii".into(),
            ));
        }
        check_radii(&radii, self.set.len())?;
        self.summit_radii = Some(radii);
        Ok(self)
    }

    /// The same road with each step's laws placed by `place` at the
    /// asperity's offset from the footprint's centre (docs/rolling.md,
    /// "Laws placed along the path").
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] on a window (its digest is the whole
    /// road's, given when it was cut without the placement).
    pub fn with_placement(mut self, place: crate::Placement<L>) -> Result<Self, RollingError> {
        if self.is_window() {
            return Err(RollingError::InvalidInput(
                "a law placement on a road window: give it to the whole road".into(),
            ));
        }
        self.placement = Some(place);
        // The placed laws are the run's: part of the checkpoint key.
        self.digest = OnceLock::new();
        Ok(self)
    }

    /// The road's [`crate::Placement`], if its laws move with the footprint.
    pub fn placement(&self) -> Option<crate::Placement<L>> {
        self.placement
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

    /// Number of asperities held (a window's, for a window).
    pub fn len(&self) -> usize {
        self.set.len()
    }

    /// Always false: a road holds at least one asperity.
    pub fn is_empty(&self) -> bool {
        self.set.is_empty()
    }

    /// Summit positions `(x_i, y_i)` (m), by local index.
    pub fn positions(&self) -> &[[f64; 2]] {
        self.set.positions()
    }

    /// Summit heights `z_i` (m), by local index.
    pub fn heights(&self) -> &[f64] {
        self.set.heights()
    }

    /// Contact laws, by local index.
    pub fn laws(&self) -> &[L] {
        self.set.laws()
    }

    /// The reference plane `z_max` (m) of the gaps `H_i = z_max − z_i + s`
    /// and of the approach `δ0`: the whole road's highest summit, or the
    /// height given to [`Road::with_top`].
    pub fn top(&self) -> f64 {
        self.top
    }

    /// The same road with its approach measured from `top` (m) instead of
    /// its highest summit.
    ///
    /// A road measured on a height map gives the map's highest point: the
    /// approach is then a property of the surface, as a full-grid BEM
    /// measures it, and does not change with the asperities a run keeps
    /// (the path's selectable ones, a stretch of the path) or with how far
    /// a fitted summit vertex stands above its grid point. A summit may
    /// stand above `top` (its gap is then negative at `s = 0`): the forces
    /// do not depend on the plane, only `δ0` under load control does, and
    /// under approach or tread-height control it fixes where the tread is.
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] if `top` is not finite.
    pub fn with_top(mut self, top: f64) -> Result<Self, RollingError> {
        if !top.is_finite() {
            return Err(RollingError::InvalidInput(format!(
                "a road's reference plane must be finite, got {top} m"
            )));
        }
        self.top = top;
        Ok(self)
    }

    /// Extent `[x_min, x_max]` of the summits along x (m).
    pub fn x_range(&self) -> [f64; 2] {
        [
            self.sorted_x.first().copied().unwrap_or(0.0),
            self.sorted_x.last().copied().unwrap_or(0.0),
        ]
    }

    /// Local indices of the asperities with `x0 ≤ x ≤ x1` and `y0 ≤ y ≤
    /// y1`, in increasing x (ties by index, so by global id in a window as
    /// in the whole road): binary search on x, then a filter on y.
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

/// One finite, non-negative radius per asperity. Zero is a sharp summit
/// (a spike, a one-cell peak): its first point of contact is its tip, so
/// its gap is the summit's ([`crate::Tread::contact_gap`]); refusing it
/// would lose the whole road to one asperity.
fn check_radii(radii: &[f64], len: usize) -> Result<(), RollingError> {
    if radii.len() != len {
        return Err(RollingError::InvalidInput(format!(
            "summit radii: {} given for {len} asperities",
            radii.len()
        )));
    }
    if let Some((i, r)) = radii
        .iter()
        .enumerate()
        .find(|(_, r)| !(r.is_finite() && **r >= 0.0))
    {
        return Err(RollingError::InvalidInput(format!(
            "summit radius of asperity {i}: expected finite and >= 0 m, got {r}"
        )));
    }
    Ok(())
}

impl<L: ContactLaw> Road<L> {
    /// The road's part of the checkpoint key: [`RoadDigest`] of the whole
    /// road's asperities in id order (computed once, on first use, for a
    /// whole road; given for a window).
    pub fn digest(&self) -> u64 {
        *self.digest.get_or_init(|| {
            let mut d = RoadDigest::new(self.set.len());
            for ((p, z), law) in self.positions().iter().zip(self.heights()).zip(self.laws()) {
                d.push(*p, *z, law);
            }
            if let Some(radii) = &self.summit_radii {
                d.summit_radii(radii);
            }
            let whole = d.finish();
            match self.placement {
                Some(place) => crate::checkpoint::mix(
                    whole,
                    self.laws()
                        .iter()
                        .flat_map(|law| crate::placement::probe_placed(place, law)),
                ),
                None => whole,
            }
        })
    }
}
