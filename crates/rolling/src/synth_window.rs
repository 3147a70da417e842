//! Windows of the synthetic road built without the whole road
//! (docs/distributed.md, "Memory per rank"): the summits a whole-road
//! build ([`SyntheticRoad::generate`]) puts in an x-range, with their ids,
//! positions, heights and laws, bit for bit, in memory bounded by the
//! window and one tile of the road.
//!
//! The whole-road generator throws darts in one random sequence over the
//! whole road: candidate `k` (draws `2k`, `2k + 1` of the ChaCha8 stream)
//! is kept when no kept summit lies within `min_spacing`, until `target`
//! summits are kept or `50 · target` candidates were drawn; then one radius
//! draw per summit, then three height draws per summit, in id order (a
//! summit's id is its rank among the kept candidates). So a summit's radius
//! and height are draws at known positions of the stream (ChaCha8 seeks in
//! O(1)); only the keep decisions need the other candidates.
//!
//! **Keep decisions by tiles.** The road's grid columns (one `min_spacing`
//! wide, the generator's own grid) are cut into tiles. For each tile the
//! dart throwing is replayed, in the same order and with the same cell
//! scans, on the candidates of the tile plus a halo of columns on each side,
//! ignoring the rest. A decision there can only be wrong if it depends,
//! through a chain of earlier neighbours, on a candidate outside the halo;
//! the replay tracks that: a candidate whose scan reaches past the halo, or
//! that is free of every surely-kept neighbour but near one that is unsure,
//! is itself *unsure* (kept as a possible blocker), while a candidate near
//! a surely-kept one is surely rejected. When a candidate of the tile ends
//! unsure, the halo is doubled and the tile replayed (at worst the halo is
//! the whole road, where nothing is unsure). So every decision is certified
//! exact, not merely likely. The decisions are one bit per candidate (about
//! 1.6 candidates per summit), kept for the whole road: about 0.2 B per
//! summit.
//!
//! The stop (the candidate that kept the `target`-th summit) is the
//! `target`-th set bit; the candidates are replayed up to a cap that
//! doubles until it is found (decisions before a candidate never depend on
//! later ones). A last pass streams the kept candidates, radii and heights
//! in id order: the window keeps its summits; the whole road's highest
//! summit and its [`RoadDigest`] are folded on the way.

use rand::{Rng, SeedableRng};
use rand_chacha::ChaCha8Rng;
use tyreroad_asperity::Sphere;
use tyreroad_contact_law::{Material, PotentialLaw};
use tyreroad_multipoint::AsperitySet;

use crate::checkpoint::RoadDigest;
use crate::{Road, RollingError, SyntheticRoad};

/// Grid columns per tile (one column is `min_spacing` wide).
const TILE_COLUMNS: usize = 1024;
/// First halo, in columns each side; doubled while a decision is unsure.
const FIRST_HALO: usize = 16;
/// Candidates drawn per summit, at most (the whole-road generator's cap).
const MAX_TRIES_PER_SUMMIT: usize = 50;

/// One bit per candidate: kept or not.
struct Bits(Vec<u64>);

impl Bits {
    fn new(len: usize) -> Self {
        Self(vec![0; len.div_ceil(64)])
    }
    fn set(&mut self, k: usize) {
        self.0[k / 64] |= 1 << (k % 64);
    }
    fn get(&self, k: usize) -> bool {
        self.0.get(k / 64).is_some_and(|w| w >> (k % 64) & 1 == 1)
    }
    fn count(&self) -> usize {
        self.0.iter().map(|w| w.count_ones() as usize).sum()
    }
    /// Index of the `n`-th set bit (1-based), if any.
    fn nth_set(&self, n: usize) -> Option<usize> {
        let mut left = n;
        for (i, &w) in self.0.iter().enumerate() {
            let ones = w.count_ones() as usize;
            if left > ones {
                left -= ones;
                continue;
            }
            let mut w = w;
            for _ in 1..left {
                w &= w - 1;
            }
            return Some(64 * i + w.trailing_zeros() as usize);
        }
        None
    }
    fn clear_from(&mut self, k: usize) {
        let w = k / 64;
        if let Some(word) = self.0.get_mut(w) {
            *word &= (1u64 << (k % 64)) - 1;
            self.0[w + 1..].fill(0);
        }
    }
}

/// What the keep pass found for the whole road.
struct Plan {
    kept: Bits,
    /// Candidates the whole-road generator draws.
    tries: usize,
    /// Summits it keeps.
    count: usize,
}

/// The generator's grid: the geometry every decision is made on.
#[derive(Clone, Copy)]
struct Grid {
    length: f64,
    width: f64,
    cell: f64,
    d2: f64,
    nx: usize,
    ny: usize,
}

impl Grid {
    fn of(road: &SyntheticRoad) -> Self {
        let cell = road.min_spacing;
        Self {
            length: road.length,
            width: road.width,
            cell,
            d2: road.min_spacing * road.min_spacing,
            nx: (road.length / cell).ceil() as usize + 1,
            ny: (road.width / cell).ceil() as usize + 1,
        }
    }
    /// Candidate `(x, y)` from its two draws, as the generator computes it.
    fn candidate(&self, u: f64, v: f64) -> [f64; 2] {
        [u * self.length, (v - 0.5) * self.width]
    }
    /// Unclamped cell of a candidate (the scan's centre).
    fn cell_of(&self, [x, y]: [f64; 2]) -> (usize, usize) {
        (
            (x / self.cell) as usize,
            ((y + 0.5 * self.width) / self.cell) as usize,
        )
    }
}

#[derive(Clone, Copy, PartialEq)]
enum Fate {
    Kept,
    Unsure,
}

/// The ChaCha8 stream of `seed` positioned at draw `draw` (each `f64` draw
/// is one `u64`, two 32-bit words).
fn stream_at(seed: u64, draw: usize) -> ChaCha8Rng {
    let mut rng = ChaCha8Rng::seed_from_u64(seed);
    rng.set_word_pos(2 * draw as u128);
    rng
}

/// Replays the candidates `0..cap` on the columns `c0 − halo .. c1 + halo`
/// and sets the bits of the candidates of columns `c0..c1` that are kept.
/// `false` when one of those is unsure (the halo is too narrow).
fn replay_tile(
    road: &SyntheticRoad,
    g: Grid,
    (c0, c1): (usize, usize),
    halo: usize,
    cap: usize,
    kept: &mut Bits,
) -> bool {
    let (s0, s1) = (c0.saturating_sub(halo), (c1 + halo).min(g.nx));
    let mut cells: Vec<Vec<u32>> = vec![Vec::new(); (s1 - s0) * g.ny];
    let mut points: Vec<([f64; 2], Fate)> = Vec::new();
    let mut rng = stream_at(road.seed, 0);
    for k in 0..cap {
        let u = rng.random::<f64>();
        let v = rng.random::<f64>();
        let p = g.candidate(u, v);
        let (cx, cy) = g.cell_of(p);
        let column = cx.min(g.nx - 1);
        if !(s0..s1).contains(&column) {
            continue;
        }
        // The generator scans columns cx−1..=cx+1 (within the road): some
        // of them outside the replayed ones are neighbours never seen.
        let (scan0, scan1) = (cx.saturating_sub(1), (cx + 2).min(g.nx));
        let mut unsure = scan0 < s0 || scan1 > s1;
        let mut blocked = false;
        'scan: for gx in scan0.max(s0)..scan1.min(s1) {
            for gy in cy.saturating_sub(1)..(cy + 2).min(g.ny) {
                for &j in &cells[(gx - s0) * g.ny + gy] {
                    let ([px, py], fate) = points[j as usize];
                    if (px - p[0]).powi(2) + (py - p[1]).powi(2) < g.d2 {
                        if fate == Fate::Kept {
                            blocked = true;
                            break 'scan;
                        }
                        unsure = true;
                    }
                }
            }
        }
        if blocked {
            continue;
        }
        let core = (c0..c1).contains(&column);
        if unsure && core {
            return false;
        }
        if core {
            kept.set(k);
        }
        cells[(column - s0) * g.ny + cy.min(g.ny - 1)].push(points.len() as u32);
        points.push((p, if unsure { Fate::Unsure } else { Fate::Kept }));
    }
    true
}

impl SyntheticRoad {
    fn check(&self) -> Result<usize, RollingError> {
        let positive = |v: f64| v.is_finite() && v > 0.0;
        let target = (self.density * self.length * self.width).round();
        let ok = [
            self.length,
            self.width,
            self.density,
            self.min_spacing,
            self.radius_min,
        ]
        .into_iter()
        .all(positive)
            && self.height_spread.is_finite()
            && self.height_spread >= 0.0
            && self.radius_max.is_finite()
            && self.radius_max >= self.radius_min
            && target < 1e8
            && (self.length / self.min_spacing) < 1e9;
        if !ok {
            return Err(RollingError::InvalidInput(format!(
                "synthetic road: positive sizes, density, spacing and radii, radius_max ≥ \
                 radius_min, height_spread ≥ 0 and < 1e8 summits needed: {self:?}"
            )));
        }
        Ok(target as usize)
    }

    /// The keep decision of every candidate the whole-road generator draws.
    fn plan(&self) -> Result<Plan, RollingError> {
        let target = self.check()?;
        let g = Grid::of(self);
        let max_tries = MAX_TRIES_PER_SUMMIT * target;
        let mut cap = (2 * target + 1024).min(max_tries);
        loop {
            let mut kept = Bits::new(cap);
            for c0 in (0..g.nx).step_by(TILE_COLUMNS) {
                let c1 = (c0 + TILE_COLUMNS).min(g.nx);
                let mut halo = FIRST_HALO;
                // With the halo over the whole road nothing is unsure.
                while !replay_tile(self, g, (c0, c1), halo, cap, &mut kept) {
                    halo *= 2;
                }
            }
            if let Some(last) = kept.nth_set(target) {
                kept.clear_from(last + 1);
                return Ok(Plan {
                    kept,
                    tries: last + 1,
                    count: target,
                });
            }
            if cap == max_tries {
                let count = kept.count();
                return Ok(Plan {
                    kept,
                    tries: cap,
                    count,
                });
            }
            cap = (2 * cap).min(max_tries);
        }
    }

    /// Streams the whole road's summits in id order: `visit(id, position,
    /// height, radius)`.
    fn stream(&self, plan: &Plan, mut visit: impl FnMut(usize, [f64; 2], f64, f64)) {
        let g = Grid::of(self);
        let mut candidates = stream_at(self.seed, 0);
        let mut radii = stream_at(self.seed, 2 * plan.tries);
        let mut heights = stream_at(self.seed, 2 * plan.tries + plan.count);
        let mut id = 0;
        for k in 0..plan.tries {
            let u = candidates.random::<f64>();
            let v = candidates.random::<f64>();
            if !plan.kept.get(k) {
                continue;
            }
            let radius =
                self.radius_min + radii.random::<f64>() * (self.radius_max - self.radius_min);
            let u3: f64 = (0..3).map(|_| heights.random::<f64>()).sum();
            let height = self.height_spread * u3 / 3.0;
            visit(id, g.candidate(u, v), height, radius);
            id += 1;
        }
    }

    /// The summits of [`SyntheticRoad::generate`] with `x0 ≤ x ≤ x1` as a
    /// window of the whole road ([`Road::window_of`]): the same ids,
    /// positions, heights and laws, the whole road's highest summit and
    /// digest, built without holding the whole road (module docs). For
    /// several windows of one road, [`SyntheticRoad::windows`] finds the
    /// keep decisions and the digest once.
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] for malformed parameters, a road that
    /// keeps no summit, or a window that holds none.
    pub fn window_road(
        &self,
        material: Material,
        window: [f64; 2],
    ) -> Result<Road<PotentialLaw<Sphere>>, RollingError> {
        self.windows(material)?.window(window)
    }

    /// What every window of the road needs from the whole road: the keep
    /// decisions (one bit per candidate), the highest summit and the
    /// digest, found by one pass over the road (module docs).
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] for malformed parameters or a road
    /// that keeps no summit.
    pub fn windows(&self, material: Material) -> Result<SyntheticWindows, RollingError> {
        let plan = self.plan()?;
        if plan.count == 0 {
            return Err(RollingError::InvalidInput(
                "synthetic road: a sphere-summit field needs at least one summit".into(),
            ));
        }
        let mut digest = RoadDigest::new(plan.count);
        let mut top = f64::NEG_INFINITY;
        let mut bad_radius = None;
        self.stream(&plan, |_, p, z, radius| match Sphere::new(radius) {
            Ok(s) => {
                digest.push(p, z, &PotentialLaw::sphere(s, material));
                top = top.max(z);
            }
            Err(e) => {
                bad_radius.get_or_insert(format!("radius {radius}: {e}"));
            }
        });
        if let Some(why) = bad_radius {
            return Err(RollingError::InvalidInput(format!("synthetic road: {why}")));
        }
        Ok(SyntheticWindows {
            road: *self,
            material,
            plan,
            top,
            digest: digest.finish(),
        })
    }

    /// Every summit's position `(x, y)` and height (m), by id, as
    /// [`SyntheticRoad::generate`] gives them, streamed without the laws
    /// (24 B a summit: what a road's output file needs).
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] for malformed parameters.
    pub fn summits(&self) -> Result<(Vec<[f64; 2]>, Vec<f64>), RollingError> {
        let plan = self.plan()?;
        let (mut positions, mut heights) = (
            Vec::with_capacity(plan.count),
            Vec::with_capacity(plan.count),
        );
        self.stream(&plan, |_, p, z, _| {
            positions.push(p);
            heights.push(z);
        });
        Ok((positions, heights))
    }
}

impl SyntheticRoad {
    /// [`SyntheticRoad::summits`] as a stream that can be walked more than
    /// once ([`SummitStream::each`]) without holding the summits: the keep
    /// pass is done here, once; each walk replays the kept candidates
    /// (about 1 ms per metre of road).
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] for malformed parameters.
    pub fn summit_stream(&self) -> Result<SummitStream, RollingError> {
        Ok(SummitStream {
            road: *self,
            plan: self.plan()?,
        })
    }
}

/// The summits of a synthetic road, walked on demand
/// ([`SyntheticRoad::summit_stream`]).
pub struct SummitStream {
    road: SyntheticRoad,
    plan: Plan,
}

impl std::fmt::Debug for SummitStream {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SummitStream")
            .field("road", &self.road)
            .field("count", &self.plan.count)
            .finish()
    }
}

impl SummitStream {
    /// Summits on the road.
    pub fn count(&self) -> usize {
        self.plan.count
    }

    /// Visits every summit in id order: its position `(x, y)` and height
    /// (m), as [`SyntheticRoad::summits`] lists them.
    pub fn each(&self, mut visit: impl FnMut([f64; 2], f64)) {
        self.road.stream(&self.plan, |_, p, z, _| visit(p, z));
    }
}

/// Windows of one synthetic road ([`SyntheticRoad::windows`]): each
/// window streams the road's candidates once and keeps its own summits
/// (`O(candidates)` time, memory of the window only).
pub struct SyntheticWindows {
    road: SyntheticRoad,
    material: Material,
    plan: Plan,
    top: f64,
    digest: u64,
}

impl SyntheticWindows {
    /// Summits on the whole road.
    pub fn count(&self) -> usize {
        self.plan.count
    }

    /// The summits with `x0 ≤ x ≤ x1`, as [`SyntheticRoad::window_road`].
    ///
    /// # Errors
    /// [`RollingError::InvalidInput`] when the window holds no summit.
    pub fn window(&self, [x0, x1]: [f64; 2]) -> Result<Road<PotentialLaw<Sphere>>, RollingError> {
        let (mut ids, mut positions, mut heights, mut laws) =
            (Vec::new(), Vec::new(), Vec::new(), Vec::new());
        let mut bad_radius = None;
        self.road.stream(&self.plan, |id, p, z, radius| {
            if !(x0..=x1).contains(&p[0]) {
                return;
            }
            match Sphere::new(radius) {
                Ok(s) => {
                    ids.push(id);
                    positions.push(p);
                    heights.push(z);
                    laws.push(PotentialLaw::sphere(s, self.material));
                }
                Err(e) => {
                    bad_radius.get_or_insert(format!("radius {radius}: {e}"));
                }
            }
        });
        if let Some(why) = bad_radius {
            return Err(RollingError::InvalidInput(format!("synthetic road: {why}")));
        }
        let set = AsperitySet::new(positions, heights, laws).map_err(|e| {
            RollingError::InvalidInput(format!(
                "synthetic road window x ∈ [{x0}, {x1}] m: {e} (the road spans x ∈ [0, {}) m)",
                self.road.length
            ))
        })?;
        Road::window_of(set, ids, self.plan.count, self.top, self.digest)
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use tyreroad_contact_law::ContactLaw;

    use super::*;

    fn same_law(a: &PotentialLaw<Sphere>, b: &PotentialLaw<Sphere>) -> bool {
        [1e-7, 1e-5, 1e-3].iter().all(|&d| {
            let (p, q) = (a.evaluate(d), b.evaluate(d));
            p.force.to_bits() == q.force.to_bits() && p.stiffness.to_bits() == q.stiffness.to_bits()
        })
    }

    /// Every window (inside, across the ends, past the road, the whole
    /// road) equals the whole build restricted to it: ids, positions,
    /// heights, laws bit for bit, with the whole road's top and digest; on a
    /// road of several tiles, and on one so dense that the generator runs
    /// out of tries (the stop is the cap, not the target).
    #[test]
    fn a_window_is_the_whole_road_restricted_to_it() {
        let rubber = Material::new(6.54e6, 0.5).unwrap();
        let long = SyntheticRoad {
            seed: 17,
            length: 4.5,
            width: 0.02,
            ..SyntheticRoad::default()
        };
        let jammed = SyntheticRoad {
            seed: 3,
            length: 0.06,
            width: 0.03,
            density: 400_000.0,
            ..SyntheticRoad::default()
        };
        for (road, windows) in [
            (
                long,
                vec![[1.999, 2.101], [-1.0, 0.05], [4.45, 9.0], [-1.0, 9.0]],
            ),
            (jammed, vec![[0.01, 0.02], [-1.0, 1.0]]),
        ] {
            let whole = Road::new(road.generate(rubber).unwrap());
            let target = (road.density * road.length * road.width).round() as usize;
            if road.density > 300_000.0 {
                assert!(whole.len() < target, "the jammed road reaches its target");
            }
            let (pos, z) = road.summits().unwrap();
            assert_eq!(pos, whole.positions());
            assert_eq!(z, whole.heights());
            for [x0, x1] in windows {
                let w = road.window_road(rubber, [x0, x1]).unwrap();
                let expect: Vec<usize> = (0..whole.len())
                    .filter(|&i| (x0..=x1).contains(&whole.positions()[i][0]))
                    .collect();
                assert!(!expect.is_empty());
                assert_eq!(w.len(), expect.len(), "{x0} {x1}");
                assert_eq!((w.global_len(), w.is_window()), (whole.len(), true));
                assert_eq!(w.top().to_bits(), whole.top().to_bits());
                assert_eq!(w.digest(), whole.digest());
                for (local, &g) in expect.iter().enumerate() {
                    assert_eq!(w.global_id(local), g);
                    assert_eq!(w.local_id(g), Some(local));
                    assert_eq!(w.positions()[local], whole.positions()[g]);
                    assert_eq!(w.heights()[local].to_bits(), whole.heights()[g].to_bits());
                    assert!(same_law(&w.laws()[local], &whole.laws()[g]));
                }
            }
        }
    }

    #[test]
    fn a_window_off_the_road_or_bad_parameters_are_named_errors() {
        let rubber = Material::new(6.54e6, 0.5).unwrap();
        let road = SyntheticRoad {
            length: 0.05,
            width: 0.02,
            ..SyntheticRoad::default()
        };
        let e = road.window_road(rubber, [1.0, 2.0]).unwrap_err();
        assert!(e.to_string().contains("window x ∈ [1, 2]"), "{e}");
        let bad = SyntheticRoad {
            min_spacing: 0.0,
            ..road
        };
        assert!(matches!(
            bad.window_road(rubber, [0.0, 1.0]),
            Err(RollingError::InvalidInput(_))
        ));
    }

    /// The certificate fires: with no halo a tile's decisions near its
    /// edges depend on unseen neighbours and the replay says so; with the
    /// whole road as halo it never does.
    #[test]
    fn a_too_narrow_halo_is_detected() {
        let road = SyntheticRoad {
            seed: 5,
            length: 0.2,
            width: 0.03,
            ..SyntheticRoad::default()
        };
        let g = Grid::of(&road);
        let cap = 4 * (road.density * road.length * road.width) as usize;
        let mut bits = Bits::new(cap);
        assert!(!replay_tile(&road, g, (40, 60), 0, cap, &mut bits));
        assert!(replay_tile(&road, g, (40, 60), g.nx, cap, &mut bits));
    }

    #[test]
    fn bits_find_the_nth_set_bit_and_clear_a_tail() {
        let mut b = Bits::new(200);
        for k in [0, 5, 63, 64, 130, 199] {
            b.set(k);
        }
        assert_eq!(b.nth_set(1), Some(0));
        assert_eq!(b.nth_set(3), Some(63));
        assert_eq!(b.nth_set(4), Some(64));
        assert_eq!(b.nth_set(6), Some(199));
        assert_eq!(b.nth_set(7), None);
        b.clear_from(64);
        assert_eq!(b.count(), 3);
        assert!(b.get(63) && !b.get(64) && !b.get(130));
    }
}
