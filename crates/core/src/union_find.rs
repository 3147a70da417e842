//! Disjoint sets of indices `0..n` (union–find with path halving): the
//! connected parts of a mesh, the clusters of touching contacts.
//!
//! Invariant: each set's root is its smallest member, so [`UnionFind::groups`]
//! and the roots themselves do not depend on the order of the unions.

/// Disjoint sets of the indices `0..n`, each at first alone.
#[derive(Debug, Clone)]
pub struct UnionFind(Vec<usize>);

impl UnionFind {
    /// `n` sets `{0}, …, {n − 1}`.
    pub fn new(n: usize) -> Self {
        Self((0..n).collect())
    }

    /// The root (smallest member) of the set of `i`.
    ///
    /// # Panics
    /// If `i ≥ n`.
    pub fn find(&mut self, mut i: usize) -> usize {
        while self.0[i] != i {
            self.0[i] = self.0[self.0[i]];
            i = self.0[i];
        }
        i
    }

    /// Merges the sets of `i` and `j`; true when they were apart.
    ///
    /// # Panics
    /// If `i ≥ n` or `j ≥ n`.
    pub fn union(&mut self, i: usize, j: usize) -> bool {
        let (a, b) = (self.find(i), self.find(j));
        if a == b {
            return false;
        }
        self.0[a.max(b)] = a.min(b);
        true
    }

    /// Every set, each sorted, ordered by its smallest member.
    pub fn groups(&mut self) -> Vec<Vec<usize>> {
        let n = self.0.len();
        let mut slot = vec![usize::MAX; n];
        let mut groups: Vec<Vec<usize>> = Vec::new();
        for i in 0..n {
            let r = self.find(i);
            if slot[r] == usize::MAX {
                slot[r] = groups.len();
                groups.push(Vec::new());
            }
            groups[slot[r]].push(i);
        }
        groups
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn sets_merge_whatever_the_order_of_the_unions() {
        let mut a = UnionFind::new(6);
        assert!(a.union(4, 1) && a.union(5, 3) && a.union(1, 5));
        assert!(!a.union(3, 4), "already one set");
        let mut b = UnionFind::new(6);
        assert!(b.union(1, 3) && b.union(3, 5) && b.union(4, 5));
        assert_eq!(a.groups(), vec![vec![0], vec![1, 3, 4, 5], vec![2]]);
        assert_eq!(a.groups(), b.groups());
        assert_eq!((a.find(5), a.find(2)), (1, 2));
    }
}
