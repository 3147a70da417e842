//! How a path is split over ranks.

use std::ops::Range;

/// Warm-up steps each rank solves before its first own step (docs/distributed.md):
/// the solver converges to `1e-12` from any start, so none are needed for
/// the signals to equal a single run to `1e-9` (measured: 0 warm-up steps
/// already give `< 1e-10` relative); two make the first step's warm start
/// (and so its iteration count and recovery path) that of the single run
/// in the usual case.
pub const DEFAULT_WARMUP: usize = 2;

/// The contiguous part of `total` steps of rank `rank` of `ranks`: sizes
/// differ by at most one, earlier ranks take the extra steps, parts are in
/// rank order and cover `0..total` exactly. A rank past the steps (more
/// ranks than steps) gets an empty range.
pub fn rank_range(total: usize, rank: usize, ranks: usize) -> Range<usize> {
    let ranks = ranks.max(1);
    let (base, extra) = (total / ranks, total % ranks);
    let start = rank * base + rank.min(extra);
    let len = base + usize::from(rank < extra);
    start.min(total)..(start + len).min(total)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parts_cover_the_path_in_order_and_differ_by_at_most_one() {
        for total in [0, 1, 2, 7, 40, 1001] {
            for ranks in 1..=9 {
                let parts: Vec<_> = (0..ranks).map(|r| rank_range(total, r, ranks)).collect();
                let mut next = 0;
                for p in &parts {
                    assert_eq!(p.start, next, "{total} {ranks} {parts:?}");
                    next = p.end;
                }
                assert_eq!(next, total);
                let lens: Vec<usize> = parts.iter().map(|p| p.len()).collect();
                let (lo, hi) = (lens.iter().min(), lens.iter().max());
                assert!(hi.zip(lo).is_some_and(|(h, l)| h - l <= 1), "{lens:?}");
            }
        }
    }
}
