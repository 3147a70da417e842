//! Which basins of a window's flood are certain: the bookkeeping that
//! [`flood`](crate::segment) keeps when it floods a window of a larger map
//! (the argument is in [`crate::segment_window`]'s documentation). Kept apart
//! from both so that the flood and the window segmentation each depend on
//! it, not on each other.

/// Certainty bookkeeping of one flood (see the module documentation).
pub(crate) struct Taint {
    nx: usize,
    /// Column 0 borders columns that were not read.
    left_cut: bool,
    /// Column `nx − 1` borders columns that were not read.
    right_cut: bool,
    /// Uncertain, per union–find node (read at roots).
    pub(crate) tainted: Vec<bool>,
    /// Connected parts of the superlevel set: each root is its part's
    /// first (highest) point.
    sl_parent: Vec<usize>,
    /// Points that started a basin.
    starts: Vec<usize>,
    /// Starts whose final basin is uncertain, after [`Taint::finish`].
    pub(crate) uncertain_starts: Vec<usize>,
}

impl Taint {
    pub(crate) fn new(nx: usize, ny: usize, left_cut: bool, right_cut: bool) -> Self {
        Self {
            nx,
            left_cut,
            right_cut,
            tainted: vec![false; nx * ny],
            sl_parent: (0..nx * ny).collect(),
            starts: Vec::new(),
            uncertain_starts: Vec::new(),
        }
    }

    fn sl_find(&mut self, mut k: usize) -> usize {
        while self.sl_parent[k] != k {
            self.sl_parent[k] = self.sl_parent[self.sl_parent[k]];
            k = self.sl_parent[k];
        }
        k
    }

    /// Point `k` (column `i`) is visited, before its basins are merged:
    /// `visited` are its visited neighbours and their roots, `fails(r)`
    /// whether unkept root `r` would fail its test at `k`.
    pub(crate) fn visit(
        &mut self,
        k: usize,
        i: usize,
        h: &[f64],
        visited: &[(usize, usize)],
        kept: &[bool],
        fails: impl Fn(usize) -> bool,
    ) {
        // The flood's order: higher first, ties by index.
        let before = |a: usize, b: usize| h[b].total_cmp(&h[a]).then(a.cmp(&b)).is_lt();
        let cut = (i == 0 && self.left_cut) || (i + 1 == self.nx && self.right_cut);
        if visited.is_empty() {
            self.starts.push(k);
            self.tainted[k] = cut;
            return;
        }
        if cut {
            for &(_, r) in visited {
                self.tainted[r] = true;
            }
        } else if visited.iter().any(|&(_, r)| self.tainted[r]) {
            let mut highest_certain: Option<usize> = None;
            for &(_, r) in visited {
                if !self.tainted[r] && highest_certain.is_none_or(|c| before(r, c)) {
                    highest_certain = Some(r);
                }
            }
            if let Some(c) = highest_certain {
                let mut safe = kept[c];
                for &(p, r) in visited {
                    if !safe {
                        break;
                    }
                    if self.tainted[r] {
                        let first = self.sl_find(p);
                        safe = before(first, c);
                    } else if r != c && !kept[r] {
                        safe = !fails(r);
                    }
                }
                if !safe {
                    self.tainted[c] = true;
                }
            }
        }
        // `k` joins its neighbours' superlevel parts; the first point stays
        // the root.
        let mut first = k;
        for &(p, _) in visited {
            let s = self.sl_find(p);
            if before(s, first) {
                first = s;
            }
        }
        for &(p, _) in visited {
            let s = self.sl_find(p);
            self.sl_parent[s] = first;
        }
        self.sl_parent[k] = first;
    }

    /// Root `r` was merged into root `top`.
    pub(crate) fn merge(&mut self, top: usize, r: usize) {
        self.tainted[top] |= self.tainted[r];
    }

    /// After the flood: which starts ended in uncertain basins.
    pub(crate) fn finish(&mut self, mut root: impl FnMut(usize) -> usize) {
        let starts = std::mem::take(&mut self.starts);
        self.uncertain_starts = starts
            .into_iter()
            .filter(|&p| self.tainted[root(p)])
            .collect();
    }
}
