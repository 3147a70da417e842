//! "No data" markers written as heights: a value an instrument's export
//! repeats at every point it did not measure (−9999, 1e30, its range limit)
//! instead of NaN or the format's own marker.
//!
//! Such a value is told from a road height by two things at once: it is
//! repeated exactly, and it lies far outside the other heights, more than
//! [`SENTINEL_SPANS`] times their span (1st to 99th percentile) beyond
//! that span. A road's deepest pore or highest chipping lies within a span
//! or two of the others; heights quantised by the format (micrometres in
//! a `.sur`) repeat, but inside the span. A single far point is a spike,
//! not a marker: it is left for the caller to warn of.
//!
//! Markers are peeled from the ends of the sorted heights, one repeated
//! value at a time, each judged against the heights left, so a map with
//! markers at both ends (−9999 and 9999), or with markers on half its
//! points, is read as a user would expect.

use crate::error::TextureError;
use crate::heightmap::HeightMap;

/// A repeated value farther than this many times the span of the other
/// heights (1st to 99th percentile) beyond that span is a marker, not a
/// height.
pub const SENTINEL_SPANS: f64 = 10.0;

/// Fewest other valid heights to judge a marker against: on fewer, the
/// percentiles say nothing.
const MIN_HEIGHTS: usize = 100;

/// A value read as a "no data" marker, and at how many points.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Sentinel {
    /// The repeated height (m as read).
    pub value: f64,
    /// Points that held it.
    pub points: usize,
}

/// The marker values among `map`'s valid heights, lowest first (empty when
/// none): each repeated at two points or more and more than
/// [`SENTINEL_SPANS`] times the others' span beyond it. A map whose other
/// heights are all one value (no span) has none: the caller's flat-map
/// warning speaks of it.
pub fn find_sentinels(map: &HeightMap) -> Vec<Sentinel> {
    let valid = || {
        map.heights()
            .iter()
            .zip(map.valid())
            .filter_map(|(h, ok)| ok.then_some(*h))
    };
    // A marker is the lowest or highest value, repeated: a measured map's
    // extremes are most often single, and then it needs no sort.
    let Some((lo, hi)) = map.min_max() else {
        return Vec::new();
    };
    let (at_lo, at_hi) = valid().fold((0usize, 0usize), |(a, b), h| {
        (a + usize::from(h == lo), b + usize::from(h == hi))
    });
    if at_lo < 2 && at_hi < 2 {
        return Vec::new();
    }
    let mut z: Vec<f64> = valid().collect();
    z.sort_unstable_by(f64::total_cmp);
    let (mut lo, mut hi) = (0, z.len());
    let mut found = Vec::new();
    while hi - lo >= MIN_HEIGHTS {
        let run_low = z[lo..hi].iter().take_while(|h| **h == z[lo]).count();
        let run_high = z[lo..hi]
            .iter()
            .rev()
            .take_while(|h| **h == z[hi - 1])
            .count();
        let low = (run_low >= 2).then(|| (z[lo], run_low));
        let high = (run_high >= 2).then(|| (z[hi - 1], run_high));
        let peel_low = low.filter(|&(v, n)| is_marker(v, &z[lo + n..hi]));
        let peel_high = high.filter(|&(v, n)| is_marker(v, &z[lo..hi - n]));
        match (peel_low, peel_high) {
            (Some((v, n)), _) => {
                found.push(Sentinel {
                    value: v,
                    points: n,
                });
                lo += n;
            }
            (None, Some((v, n))) => {
                found.push(Sentinel {
                    value: v,
                    points: n,
                });
                hi -= n;
            }
            (None, None) => break,
        }
    }
    found.sort_by(|a, b| a.value.total_cmp(&b.value));
    found
}

/// Whether `value` lies more than [`SENTINEL_SPANS`] spans outside the
/// 1st–99th percentile span of `others` (sorted).
fn is_marker(value: f64, others: &[f64]) -> bool {
    let n = others.len();
    if n < MIN_HEIGHTS {
        return false;
    }
    let (p1, p99) = (others[(n - 1) / 100], others[99 * (n - 1) / 100]);
    let span = p99 - p1;
    let beyond = (p1 - value).max(value - p99);
    span > 0.0 && beyond > SENTINEL_SPANS * span
}

impl HeightMap {
    /// A copy with the points holding one of `sentinels`' values marked
    /// missing (the rest unchanged), as if the file had written NaN there.
    ///
    /// # Errors
    /// [`TextureError::InvalidMap`] never for a valid map (same grid).
    pub fn without_values(&self, sentinels: &[Sentinel]) -> Result<Self, TextureError> {
        let valid: Vec<bool> = self
            .heights()
            .iter()
            .zip(self.valid())
            .map(|(h, ok)| *ok && !sentinels.iter().any(|s| s.value == *h))
            .collect();
        Self::with_mask(
            self.nx(),
            self.ny(),
            self.dx(),
            self.dy(),
            self.heights().to_vec(),
            valid,
        )
    }
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    /// A wavy 60 × 60 map, heights quantised to 1 µm (so they repeat), with
    /// `marker` at every point `k` for which `at(k)`.
    fn wavy(marker: f64, at: impl Fn(usize) -> bool) -> HeightMap {
        HeightMap::from_fn(60, 60, 1e-4, 1e-4, |x, y| {
            let h = 1e-3 * (x * 900.0).sin() * (y * 700.0).cos();
            (h * 1e6).round() * 1e-6
        })
        .map(|m| {
            let h: Vec<f64> = (0..m.heights().len())
                .map(|k| if at(k) { marker } else { m.heights()[k] })
                .collect();
            HeightMap::new(60, 60, 1e-4, 1e-4, h).unwrap()
        })
        .unwrap()
    }

    #[test]
    fn a_repeated_far_value_is_a_marker_and_quantised_heights_are_not() {
        assert!(find_sentinels(&wavy(0.0, |_| false)).is_empty());
        // 2 % of the points at −9999 m, then a third of them.
        for every in [50, 3] {
            let map = wavy(-9999.0, |k| k % every == 1);
            let found = find_sentinels(&map);
            assert_eq!(found.len(), 1, "{found:?}");
            assert_eq!(found[0].value, -9999.0);
            assert_eq!(
                found[0].points,
                (0..3600).filter(|k| k % every == 1).count()
            );
            let masked = map.without_values(&found).unwrap();
            assert_eq!(masked.valid_count(), 3600 - found[0].points);
            assert!(masked.min_max().unwrap().0 > -1.1e-3);
        }
    }

    #[test]
    fn markers_at_both_ends_are_found_and_a_lone_spike_is_not() {
        let map = wavy(f64::NAN, |_| false);
        let mut h = map.heights().to_vec();
        for k in (0..3600).step_by(97) {
            h[k] = -9999.0;
        }
        for k in (5..3600).step_by(89) {
            h[k] = 1e30;
        }
        h[3] = 2.0; // one spike: not repeated
        let map = HeightMap::new(60, 60, 1e-4, 1e-4, h).unwrap();
        let values: Vec<f64> = find_sentinels(&map).iter().map(|s| s.value).collect();
        assert_eq!(values, vec![-9999.0, 1e30]);
    }

    #[test]
    fn a_deep_pore_repeated_within_reach_of_the_others_is_a_height() {
        // Porous asphalt's voids: 5 % of the points 4 mm down, flat
        // (quantised) at the bottom, the tops within ±1 mm: within
        // SENTINEL_SPANS of the others' span.
        let map = wavy(-4e-3, |k| k % 20 == 0);
        assert!(find_sentinels(&map).is_empty());
    }
}
