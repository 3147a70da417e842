//! Segmentation of a height map into asperities (their caps: `crate::cap`).

// Numerical kernels index several arrays in step.
#![allow(clippy::needless_range_loop)]

use tyreroad_core::validate;

use crate::error::TextureError;
use crate::heightmap::HeightMap;
use crate::segment_taint::Taint;

/// Label of a grid point that belongs to no asperity (invalid points, and
/// points of rejected islands).
pub const UNLABELLED: u32 = u32::MAX;

/// Thresholds of the segmentation.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SegmentOptions {
    /// Smallest prominence (m) of a kept asperity: its summit height minus
    /// the height of its key saddle (the highest point at which its basin
    /// meets the basin of a higher summit).
    pub min_prominence: f64,
    /// Smallest plan area (m²) of a kept asperity's basin above its key
    /// saddle (cell count × dx·dy).
    pub min_area: f64,
}

/// A least-squares paraboloid fitted to the neighbourhood of a summit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SummitFit {
    /// Vertex x (m).
    pub x: f64,
    /// Vertex y (m).
    pub y: f64,
    /// Vertex height (m).
    pub z: f64,
    /// Principal radii of curvature (m), `r1 ≤ r2`.
    pub radii: (f64, f64),
}

/// One asperity of a [`Segmentation`].
#[derive(Clone, Debug, PartialEq)]
pub struct Asperity {
    /// Grid point `(i, j)` of the summit (highest point of the basin).
    pub summit_cell: (usize, usize),
    /// Summit position `(x, y)` (m): the vertex of the summit paraboloid when
    /// it fits (within 1.5 cells of the summit point, borne out by the grid:
    /// [`SummitFit`]), else the grid point.
    pub summit: [f64; 2],
    /// Summit height (m): the paraboloid vertex height when it fits (never
    /// below the grid maximum), else the grid maximum.
    pub summit_height: f64,
    /// Prominence (m): summit grid height minus key-saddle height; for the
    /// highest asperity (and isolated islands), summit minus lowest point of
    /// its basin.
    pub prominence: f64,
    /// Plan area of the whole basin (m²).
    pub area: f64,
    /// Indices (`j·nx + i`) of the basin's grid points.
    pub cells: Vec<usize>,
    /// The lowest valid point of the basin (m); for a piece of a split top
    /// ([`crate::split_wide_tops`]), of the basin it was cut from, so a flat
    /// tile inside a plateau keeps the plateau's depth range.
    pub floor: f64,
    /// The summit paraboloid, when the neighbourhood is concave and the
    /// grid bears its vertex out (not pulled up by a cliff or a pore wall
    /// in its window, docs/texture.md "Summits").
    pub fit: Option<SummitFit>,
    /// For a piece of a split top ([`crate::split_wide_tops`]): the index,
    /// in the segmentation that was split, of the basin it was cut from.
    /// Pieces with the same `plateau` are one body cut into tiles (a
    /// caller may calibrate them together); `None` for a basin kept whole.
    pub plateau: Option<usize>,
}

/// A height map split into asperities (basins of the inverted surface).
#[derive(Clone, Debug, PartialEq)]
pub struct Segmentation {
    nx: usize,
    ny: usize,
    /// Column of the whole map at this map's column 0 (0 unless a window of
    /// a larger map was segmented): positions are the whole map's.
    pub(crate) origin: usize,
    labels: Vec<u32>,
    asperities: Vec<Asperity>,
}

impl Segmentation {
    /// A segmentation from its parts (the labels and asperities agree).
    pub(crate) fn from_parts(
        nx: usize,
        ny: usize,
        origin: usize,
        labels: Vec<u32>,
        asperities: Vec<Asperity>,
    ) -> Self {
        Self {
            nx,
            ny,
            origin,
            labels,
            asperities,
        }
    }

    /// The asperities, highest summit first.
    pub fn asperities(&self) -> &[Asperity] {
        &self.asperities
    }
    /// Label map (row-major): the asperity index of each grid point, or
    /// [`UNLABELLED`].
    pub fn labels(&self) -> &[u32] {
        &self.labels
    }
    /// Grid size `(nx, ny)`.
    pub fn size(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }
}

fn find(parent: &mut [usize], mut k: usize) -> usize {
    while parent[k] != k {
        parent[k] = parent[parent[k]];
        k = parent[k];
    }
    k
}

/// Split `map` into asperities.
///
/// Algorithm (flooding from the top — a watershed of the inverted surface
/// with persistence-based merging): the valid points are visited by
/// decreasing height (ties by index), with union–find over basins and
/// 8-connectivity. A point with no visited neighbour starts a basin (its
/// summit). A point touching one basin joins it. A point touching several
/// basins is a saddle at height `h`: every basin but the one with the
/// highest summit is tested — if its prominence `summit − h` is below
/// `min_prominence` or its area so far is below `min_area`, it is merged
/// into the highest one; otherwise it is kept for good (its first such
/// saddle is its key saddle, the highest one, since points come by
/// decreasing height). The point then joins the basin of its highest
/// neighbour. Isolated islands (cut off by invalid points) that never meet
/// a higher basin are kept only if they pass both thresholds with
/// prominence `summit − lowest point`. The highest basin is always kept.
///
/// Each kept asperity then gets its summit paraboloid ([`SummitFit`]).
pub fn segment(map: &HeightMap, opts: &SegmentOptions) -> Result<Segmentation, TextureError> {
    flood(map, opts, 0, None, None)
}

/// [`segment`] on a map whose column 0 is the whole map's column `origin`;
/// `highest`: `None` for a whole map (its first point is the highest
/// basin's summit), `Some(p)` for a window, `p` the whole map's first point
/// if the window holds it. With `taint`, each union–find root's certainty
/// is tracked (crate::segment_window).
pub(crate) fn flood(
    map: &HeightMap,
    opts: &SegmentOptions,
    origin: usize,
    highest: Option<Option<usize>>,
    mut taint: Option<&mut Taint>,
) -> Result<Segmentation, TextureError> {
    validate::finite("min_prominence", opts.min_prominence)?;
    validate::finite("min_area", opts.min_area)?;
    let (nx, ny) = (map.nx(), map.ny());
    let h = map.heights();
    let valid = map.valid();
    let cell_area = map.dx() * map.dy();
    let mut order: Vec<usize> = (0..nx * ny).filter(|&k| valid[k]).collect();
    if order.is_empty() {
        return Err(TextureError::NotEnoughData(
            "the map has no valid point".into(),
        ));
    }
    order.sort_by(|&a, &b| h[b].total_cmp(&h[a]).then(a.cmp(&b)));
    let n = nx * ny;
    let mut parent: Vec<usize> = (0..n).collect();
    let mut label = vec![usize::MAX; n]; // basin of each visited point (a union–find node)
    let mut size = vec![0usize; n];
    let mut kept = vec![false; n];
    let mut prominence = vec![f64::NAN; n];
    let mut roots: Vec<usize> = Vec::with_capacity(8);
    // Visited neighbours and their roots (only read with `taint`).
    let mut visited: Vec<(usize, usize)> = Vec::with_capacity(8);
    for &k in &order {
        let (i, j) = (k % nx, k / nx);
        roots.clear();
        visited.clear();
        let mut best_nb: Option<usize> = None;
        for dj in -1i64..=1 {
            for di in -1i64..=1 {
                if di == 0 && dj == 0 {
                    continue;
                }
                let (ii, jj) = (i as i64 + di, j as i64 + dj);
                if ii < 0 || jj < 0 || ii >= nx as i64 || jj >= ny as i64 {
                    continue;
                }
                let kk = jj as usize * nx + ii as usize;
                if label[kk] == usize::MAX {
                    continue;
                }
                let r = find(&mut parent, label[kk]);
                if !roots.contains(&r) {
                    roots.push(r);
                }
                visited.push((kk, r));
                if best_nb.is_none_or(|b| h[kk] > h[b]) {
                    best_nb = Some(kk);
                }
            }
        }
        if let Some(t) = taint.as_deref_mut() {
            let fails = |r: usize| {
                h[r] - h[k] < opts.min_prominence || (size[r] as f64) * cell_area < opts.min_area
            };
            t.visit(k, i, h, &visited, &kept, fails);
        }
        let Some(nb) = best_nb else {
            label[k] = k;
            size[k] = 1;
            continue;
        };
        if roots.len() > 1 {
            roots.sort_by(|&a, &b| h[b].total_cmp(&h[a]).then(a.cmp(&b)));
            let top = roots[0];
            for &r in &roots[1..] {
                if kept[r] {
                    continue;
                }
                let prom = h[r] - h[k];
                if prom < opts.min_prominence || (size[r] as f64) * cell_area < opts.min_area {
                    parent[r] = top;
                    size[top] += size[r];
                    if let Some(t) = taint.as_deref_mut() {
                        t.merge(top, r);
                    }
                } else {
                    kept[r] = true;
                    prominence[r] = prom;
                }
            }
        }
        let r = find(&mut parent, label[nb]);
        label[k] = r;
        size[r] += 1;
    }
    // Final basins.
    let mut basin_cells: std::collections::BTreeMap<usize, Vec<usize>> = Default::default();
    for &k in &order {
        let r = find(&mut parent, label[k]);
        basin_cells.entry(r).or_default().push(k);
    }
    let highest = highest.unwrap_or(Some(order[0]));
    if let Some(t) = taint {
        t.finish(|p| find(&mut parent, p));
    }
    let mut basins: Vec<(usize, Vec<usize>)> = Vec::new();
    for (r, cells) in basin_cells {
        if Some(r) != highest && !kept[r] {
            // An island: never met a higher basin.
            let low = cells.iter().map(|&c| h[c]).fold(f64::INFINITY, f64::min);
            let prom = h[r] - low;
            if prom < opts.min_prominence || cells.len() as f64 * cell_area < opts.min_area {
                continue;
            }
            prominence[r] = prom;
        }
        if Some(r) == highest {
            let low = cells.iter().map(|&c| h[c]).fold(f64::INFINITY, f64::min);
            prominence[r] = h[r] - low;
        }
        basins.push((r, cells));
    }
    basins.sort_by(|a, b| h[b.0].total_cmp(&h[a.0]).then(a.0.cmp(&b.0)));
    let mut labels = vec![UNLABELLED; n];
    let mut asperities = Vec::with_capacity(basins.len());
    for (id, (r, mut cells)) in basins.into_iter().enumerate() {
        cells.sort_unstable();
        for &c in &cells {
            labels[c] = id as u32;
        }
        let floor = cells.iter().map(|&c| h[c]).fold(f64::INFINITY, f64::min);
        asperities.push(Asperity {
            summit_cell: (r % nx, r / nx),
            summit: [
                (r % nx + origin) as f64 * map.dx(),
                (r / nx) as f64 * map.dy(),
            ],
            summit_height: h[r],
            prominence: prominence[r],
            area: cells.len() as f64 * cell_area,
            cells,
            floor,
            fit: None,
            plateau: None,
        });
    }
    for (id, a) in asperities.iter_mut().enumerate() {
        a.fit = fit_summit(map, &labels, id as u32, a.summit_cell, origin);
        if let Some(f) = a.fit {
            a.summit = [f.x, f.y];
            a.summit_height = f.z.max(a.summit_height);
        }
    }
    Ok(Segmentation {
        nx,
        ny,
        origin,
        labels,
        asperities,
    })
}

/// The median of the drops from the summit point to its basin's points
/// among its 8 neighbours, `None` without any: the summit's height scale as
/// the grid sees it. A paraboloid of radius `R` on cells of size `h` drops
/// `h²/2R` to `h²/R` to most of them wherever its vertex lies in the cell
/// (a vertex on a cell's corner stands above its highest point by a
/// quarter of this median at most).
fn median_drop(map: &HeightMap, labels: &[u32], id: u32, (si, sj): (usize, usize)) -> Option<f64> {
    let (nx, ny) = (map.nx(), map.ny());
    let z0 = map.get(si, sj)?;
    let mut drops = [0.0; 8];
    let mut n = 0;
    for j in sj.saturating_sub(1)..(sj + 2).min(ny) {
        for i in si.saturating_sub(1)..(si + 2).min(nx) {
            if (i, j) == (si, sj) || labels[j * nx + i] != id {
                continue;
            }
            if let Some(z) = map.get(i, j) {
                drops[n] = z0 - z;
                n += 1;
            }
        }
    }
    let drops = &mut drops[..n];
    drops.sort_by(f64::total_cmp);
    match n {
        0 => None,
        _ if n % 2 == 1 => Some(drops[n / 2]),
        _ => Some(0.5 * (drops[n / 2 - 1] + drops[n / 2])),
    }
}

/// Solve the small dense system `a x = b` by Gaussian elimination with
/// partial pivoting; `None` if singular.
fn solve<const N: usize>(mut a: [[f64; N]; N], mut b: [f64; N]) -> Option<[f64; N]> {
    for c in 0..N {
        let p = (c..N).max_by(|&x, &y| a[x][c].abs().total_cmp(&a[y][c].abs()))?;
        if a[p][c].abs() < 1e-300 {
            return None;
        }
        a.swap(c, p);
        b.swap(c, p);
        for r in c + 1..N {
            let f = a[r][c] / a[c][c];
            for k in c..N {
                a[r][k] -= f * a[c][k];
            }
            b[r] -= f * b[c];
        }
    }
    let mut x = [0.0; N];
    for r in (0..N).rev() {
        let s: f64 = (r + 1..N).map(|k| a[r][k] * x[k]).sum();
        x[r] = (b[r] - s) / a[r][r];
    }
    x.iter().all(|v| v.is_finite()).then_some(x)
}

/// How far (a fraction of the summit's median drop, [`median_drop`]) a
/// summit paraboloid may overshoot the grid point nearest its vertex.
/// Smooth summits stay well within it: on the synthetic chip seal and dense
/// asphalt fixtures (ellipsoidal chippings) 99 % of the 5 × 5 fits
/// overshoot by at most 0.12 of the median drop and two fits in 2193 by
/// more than a quarter; on the polyhedral chippings of the exposed
/// aggregate and porous asphalt half the fits overshoot by 0.65–1 of it
/// (their summits are edges and facets, not paraboloids).
const VERTEX_OVERSHOOT: f64 = 0.25;

/// Least-squares paraboloid `z = c₀ + c₁u + c₂v + c₃u² + c₄uv + c₅v²` over
/// the basin's points within 2 cells of the summit point (`u, v` in cells);
/// `None` unless at least 9 points, a negative-definite Hessian and a vertex
/// within 1.5 cells and on the map that the grid bears out: standing above
/// the summit point by at most the median drop to its neighbours and
/// overshooting the grid point nearest it by at most [`VERTEX_OVERSHOOT`]
/// of that drop ([`median_drop`]); and
/// `None` on a plateau (five or more of the window's
/// points at exactly the summit height, e.g. a ground-flat top): there the summit point is merely the first plateau
/// point in index order, on the plateau's edge, and a paraboloid through
/// the edge raises the summit above the flat top and makes the law's onset
/// Hertzian where a flat punch is right (up to 180 times too soft at 1 µm on
/// a worn chip seal, docs/texture.md).
pub(crate) fn fit_summit(
    map: &HeightMap,
    labels: &[u32],
    id: u32,
    (si, sj): (usize, usize),
    origin: usize,
) -> Option<SummitFit> {
    let (nx, ny) = (map.nx(), map.ny());
    let mut ata = [[0.0; 6]; 6];
    let mut atb = [0.0; 6];
    let z0 = map.get(si, sj)?;
    // Four points of the window tie at most on a smooth summit that is
    // symmetric about the grid (a ball centred between four points); five or
    // more at exactly the summit height are a plateau.
    let mut level = 0;
    for j in sj.saturating_sub(2)..(sj + 3).min(ny) {
        for i in si.saturating_sub(2)..(si + 3).min(nx) {
            if labels[j * nx + i] == id && map.get(i, j) == Some(z0) {
                level += 1;
            }
        }
    }
    if level >= 5 {
        return None;
    }
    let mut count = 0;
    for j in sj.saturating_sub(2)..(sj + 3).min(ny) {
        for i in si.saturating_sub(2)..(si + 3).min(nx) {
            let k = j * nx + i;
            if labels[k] != id {
                continue;
            }
            let Some(z) = map.get(i, j) else { continue };
            let (u, v) = (i as f64 - si as f64, j as f64 - sj as f64);
            let row = [1.0, u, v, u * u, u * v, v * v];
            for a in 0..6 {
                for b in 0..6 {
                    ata[a][b] += row[a] * row[b];
                }
                atb[a] += row[a] * (z - z0);
            }
            count += 1;
        }
    }
    if count < 9 {
        return None;
    }
    let c = solve(ata, atb)?;
    let (hxx, hxy, hyy) = (2.0 * c[3], c[4], 2.0 * c[5]);
    let det = hxx * hyy - hxy * hxy;
    if !(hxx < 0.0 && det > 0.0) {
        return None;
    }
    // Vertex: H [u v]ᵀ = −[c₁ c₂]ᵀ.
    let u = (-c[1] * hyy + c[2] * hxy) / det;
    let v = (-c[2] * hxx + c[1] * hxy) / det;
    if u * u + v * v > 1.5 * 1.5 {
        return None;
    }
    let fit = |u: f64, v: f64| {
        z0 + c[0] + c[1] * u + c[2] * v + c[3] * u * u + c[4] * u * v + c[5] * v * v
    };
    let z = fit(u, v);
    // A vertex off the map is an extrapolation, not a measured summit.
    let (gu, gv) = (si as f64 + u.round(), sj as f64 + v.round());
    if !(gu >= 0.0 && gv >= 0.0 && gu <= (nx - 1) as f64 && gv <= (ny - 1) as f64) {
        return None;
    }
    // The grid point nearest the vertex (the summit point when that one is
    // outside the basin or unmeasured): a smooth summit's fit passes close
    // to it, so the vertex stands above it by what the fitted curvature
    // gives over the fraction of a cell between them. A paraboloid pulled
    // up by a cliff in its window (a chipping's top beside a pore, the edge
    // of a polyhedral chipping) overshoots it by far more: its vertex,
    // up to 1.5 mm above every cell on the synthetic porous asphalt, is no
    // summit of the sampled surface (docs/texture.md).
    let (ni, nj) = (gu as usize, gv as usize);
    let (nu, nv, zn) = match map.get(ni, nj) {
        Some(zn) if labels[nj * nx + ni] == id => {
            (ni as f64 - si as f64, nj as f64 - sj as f64, zn)
        }
        _ => (0.0, 0.0, z0),
    };
    let drop = median_drop(map, labels, id, (si, sj))?;
    if z - z0 > drop || fit(nu, nv) - zn > VERTEX_OVERSHOOT * drop {
        return None;
    }
    // Curvatures in physical units: scale the cell-unit Hessian by 1/(dx dy).
    let (dx, dy) = (map.dx(), map.dy());
    let (axx, axy, ayy) = (hxx / (dx * dx), hxy / (dx * dy), hyy / (dy * dy));
    let tr = axx + ayy;
    let disc = ((axx - ayy).powi(2) + 4.0 * axy * axy).sqrt();
    let (k1, k2) = (0.5 * (tr - disc), 0.5 * (tr + disc)); // both < 0, k1 most curved
    if !(k2 < 0.0) {
        return None;
    }
    Some(SummitFit {
        x: ((si + origin) as f64 + u) * dx,
        y: (sj as f64 + v) * dy,
        z,
        radii: (-1.0 / k1, -1.0 / k2),
    })
}
