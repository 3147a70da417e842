//! Segmentation of a height map into asperities, and their caps.

// Numerical kernels index several arrays in step.
#![allow(clippy::needless_range_loop)]

use tyreroad_asperity::{CapGeometry, CapMeasures, EllipticParaboloid, TabulatedCap};

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
    /// The summit paraboloid, when the neighbourhood is concave and the
    /// grid bears its vertex out (not pulled up by a cliff or a pore wall
    /// in its window, docs/texture.md "Summits").
    pub fit: Option<SummitFit>,
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
            fit: None,
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
fn fit_summit(
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

/// One triangle of a grid cap: vertices relative to the summit.
#[derive(Clone, Copy, Debug)]
struct Tri {
    p: [[f64; 3]; 3],
    zmax: f64,
}

/// The exact cap of an asperity's basin on the grid.
///
/// The basin's surface is the piecewise-linear interpolant of its grid
/// points: each grid cell whose four corners belong to the basin is split
/// into four triangles about its centre (height = mean of the corners). At
/// depth `δ` the plane is `z = top − δ` and, summing over triangles:
///
/// ```text
/// Σ = area of the parts of the triangles above the plane (projected)
/// Ω = ∫ max(0, h − plane) dA            (exact for linear pieces)
/// Γ = length of the iso-contour h = plane (marching triangles)
/// Σ' = Σₜ Lₜ / |∇hₜ|,   Γ' = Σₜ dLₜ/dδ,   Σ'' = Σₜ Lₜ'/|∇hₜ|,   Γ'' = 0
/// ```
///
/// `top` is the summit height of the [`Asperity`]. The cap is exact while
/// the plane stays above every point on the basin's boundary (a point with
/// a neighbour outside the basin, or on the map's edge): that depth is
/// [`CapGeometry::max_depth`]; beyond it the measures are those of the
/// truncated basin (the contour stops at the boundary).
#[derive(Clone, Debug)]
pub struct GridCap {
    top: f64,
    max_depth: f64,
    tris: Vec<Tri>,
}

impl GridCap {
    /// The grid cap of asperity `index` of `seg` (computed on `map`, the map
    /// that was segmented).
    pub fn new(map: &HeightMap, seg: &Segmentation, index: usize) -> Result<Self, TextureError> {
        let a = seg.asperities.get(index).ok_or_else(|| {
            TextureError::NotEnoughData(format!("asperity {index} of {}", seg.asperities.len()))
        })?;
        if (map.nx(), map.ny()) != (seg.nx, seg.ny) {
            return Err(TextureError::InvalidMap(
                "the map is not the one that was segmented".into(),
            ));
        }
        let (nx, ny) = (seg.nx, seg.ny);
        let id = index as u32;
        let inb = |i: usize, j: usize| seg.labels[j * nx + i] == id;
        let (dx, dy) = (map.dx(), map.dy());
        let top = a.summit_height;
        let (sx, sy) = (a.summit[0], a.summit[1]);
        let mut boundary_max = f64::NEG_INFINITY;
        let mut tris = Vec::new();
        let h = map.heights();
        for &c in &a.cells {
            let (i, j) = (c % nx, c / nx);
            let mut edge = i == 0 || j == 0 || i + 1 == nx || j + 1 == ny;
            if !edge {
                'n: for jj in j - 1..=j + 1 {
                    for ii in i - 1..=i + 1 {
                        if !inb(ii, jj) {
                            edge = true;
                            break 'n;
                        }
                    }
                }
            }
            if edge {
                boundary_max = boundary_max.max(h[c]);
            }
            if i + 1 < nx && j + 1 < ny && inb(i + 1, j) && inb(i, j + 1) && inb(i + 1, j + 1) {
                let corner = |ii: usize, jj: usize| {
                    [
                        (ii + seg.origin) as f64 * dx - sx,
                        jj as f64 * dy - sy,
                        h[jj * nx + ii] - top,
                    ]
                };
                let q = [
                    corner(i, j),
                    corner(i + 1, j),
                    corner(i + 1, j + 1),
                    corner(i, j + 1),
                ];
                let m = [
                    ((i + seg.origin) as f64 + 0.5) * dx - sx,
                    (j as f64 + 0.5) * dy - sy,
                    0.25 * (q[0][2] + q[1][2] + q[2][2] + q[3][2]),
                ];
                for e in 0..4 {
                    let p = [q[e], q[(e + 1) % 4], m];
                    let zmax = p[0][2].max(p[1][2]).max(p[2][2]);
                    tris.push(Tri { p, zmax });
                }
            }
        }
        if tris.is_empty() {
            return Err(TextureError::NotEnoughData(format!(
                "asperity {index} has no complete grid cell"
            )));
        }
        tris.sort_by(|a, b| b.zmax.total_cmp(&a.zmax));
        let max_depth = (top - boundary_max).max(0.0);
        Ok(Self {
            top,
            max_depth,
            tris,
        })
    }

    /// Summit height used as the cap's reference (m).
    pub fn top(&self) -> f64 {
        self.top
    }
}

impl CapGeometry for GridCap {
    fn cap(&self, depth: f64) -> CapMeasures {
        if depth.is_nan() || depth <= 0.0 {
            return CapMeasures::EMPTY;
        }
        let zp = -depth;
        let mut m = CapMeasures::EMPTY;
        for t in &self.tris {
            if t.zmax <= zp {
                break;
            }
            let p = &t.p;
            // Clip the triangle to z > zp.
            let mut poly: [[f64; 3]; 4] = [[0.0; 3]; 4];
            let mut np = 0;
            let mut cut: [[f64; 2]; 2] = [[0.0; 2]; 2];
            let mut dcut: [[f64; 2]; 2] = [[0.0; 2]; 2];
            let mut nc = 0;
            for e in 0..3 {
                let (a, b) = (p[e], p[(e + 1) % 3]);
                let (ia, ib) = (a[2] > zp, b[2] > zp);
                if ia {
                    poly[np] = a;
                    np += 1;
                }
                if ia != ib {
                    let s = (zp - a[2]) / (b[2] - a[2]);
                    let x = [a[0] + s * (b[0] - a[0]), a[1] + s * (b[1] - a[1]), zp];
                    if np < 4 {
                        poly[np] = x;
                        np += 1;
                    }
                    if nc < 2 {
                        cut[nc] = [x[0], x[1]];
                        // d(point)/d(zp) along the edge.
                        let dz = b[2] - a[2];
                        dcut[nc] = [(b[0] - a[0]) / dz, (b[1] - a[1]) / dz];
                        nc += 1;
                    }
                }
            }
            if np < 3 {
                continue;
            }
            for k in 1..np - 1 {
                let (a, b, c) = (poly[0], poly[k], poly[k + 1]);
                let area =
                    0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (c[0] - a[0]) * (b[1] - a[1])).abs();
                m.base_area += area;
                m.volume += area * ((a[2] + b[2] + c[2]) / 3.0 - zp);
            }
            if nc == 2 {
                let s = [cut[1][0] - cut[0][0], cut[1][1] - cut[0][1]];
                let len = (s[0] * s[0] + s[1] * s[1]).sqrt();
                m.perimeter += len;
                // Gradient magnitude of the triangle's plane.
                let (u, v) = (
                    [p[1][0] - p[0][0], p[1][1] - p[0][1], p[1][2] - p[0][2]],
                    [p[2][0] - p[0][0], p[2][1] - p[0][1], p[2][2] - p[0][2]],
                );
                let nrm = [
                    u[1] * v[2] - u[2] * v[1],
                    u[2] * v[0] - u[0] * v[2],
                    u[0] * v[1] - u[1] * v[0],
                ];
                if nrm[2].abs() > 0.0 {
                    let grad = (nrm[0] * nrm[0] + nrm[1] * nrm[1]).sqrt() / nrm[2].abs();
                    let dlen = if len > 0.0 {
                        let ds = [dcut[1][0] - dcut[0][0], dcut[1][1] - dcut[0][1]];
                        -(s[0] * ds[0] + s[1] * ds[1]) / len
                    } else {
                        0.0
                    };
                    if grad > 0.0 {
                        m.d_base_area += len / grad;
                        m.d2_base_area += dlen / grad;
                    }
                    m.d_perimeter += dlen;
                }
            }
        }
        m
    }

    fn max_depth(&self) -> f64 {
        self.max_depth
    }
}

/// Start of the paraboloid-to-grid blend, in units of `δ₁`.
const BLEND_START: f64 = 2.0;
/// End of the paraboloid-to-grid blend, in units of `δ₁`.
const BLEND_END: f64 = 10.0;

/// How an asperity's cap is tabulated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CapOptions {
    /// Number of depths in the table (geometric grid from `1e-6·δ_max` to
    /// `δ_max`, see `TabulatedCap::default_grid`).
    pub nodes: usize,
    /// Largest depth tabulated (m); `None` = the grid cap's
    /// [`CapGeometry::max_depth`] (summit − highest boundary point).
    pub max_depth: Option<f64>,
}

impl Default for CapOptions {
    fn default() -> Self {
        Self {
            nodes: 120,
            max_depth: None,
        }
    }
}

/// The tabulated cap of asperity `index`, smooth at contact onset.
///
/// The grid cap of a summit sampled by few points is a pyramid near
/// `δ = 0` (`Σ ∝ δ²`), not a smooth cap (`Σ ∝ δ`). So, when the summit
/// paraboloid fits ([`SummitFit`]), the table uses the cap of that
/// elliptic paraboloid (radii `r1`, `r2`) below `2δ₁`, with `δ₁ = top −
/// min(heights of the 3 × 3 points around the summit)`, the grid cap above
/// `10δ₁`, and a blend `w·paraboloid + (1 − w)·grid` between them, with `w` a smoothstep
/// in `ln δ`. `Ω` and `Σ` are then made non-decreasing (running maximum).
/// Without a fit the grid cap is tabulated as it is and `TabulatedCap`'s
/// power-law onset applies. Depths where the grid cap is still empty are
/// dropped.
pub fn asperity_cap(
    map: &HeightMap,
    seg: &Segmentation,
    index: usize,
    opts: &CapOptions,
) -> Result<TabulatedCap, TextureError> {
    let grid = GridCap::new(map, seg, index)?;
    let a = &seg.asperities[index];
    let dmax = opts.max_depth.unwrap_or(grid.max_depth());
    if !(dmax.is_finite() && dmax > 0.0) {
        return Err(TextureError::NotEnoughData(format!(
            "asperity {index}: no depth range (summit at the basin's boundary height)"
        )));
    }
    let depths = TabulatedCap::default_grid(dmax, opts.nodes)?;
    let (si, sj) = a.summit_cell;
    let mut low = f64::INFINITY;
    for j in sj.saturating_sub(1)..(sj + 2).min(map.ny()) {
        for i in si.saturating_sub(1)..(si + 2).min(map.nx()) {
            if let Some(z) = map.get(i, j) {
                low = low.min(z);
            }
        }
    }
    let d1 = (a.summit_height - low).max(0.0);
    let para = match a.fit {
        Some(f) if d1 > 0.0 => Some(EllipticParaboloid::new(f.radii.0, f.radii.1)?),
        _ => None,
    };
    let (mut dep, mut vol, mut area, mut per) = (vec![], vec![], vec![], vec![]);
    let (mut vmax, mut amax) = (0.0f64, 0.0f64);
    for &d in &depths {
        let g = grid.cap(d);
        let c = match &para {
            Some(p) if d < BLEND_END * d1 => {
                let q = p.cap(d);
                let t = if d <= BLEND_START * d1 {
                    0.0
                } else {
                    ((d / (BLEND_START * d1)).ln() / (BLEND_END / BLEND_START).ln()).clamp(0.0, 1.0)
                };
                let w = 1.0 - t * t * (3.0 - 2.0 * t);
                CapMeasures {
                    volume: w * q.volume + (1.0 - w) * g.volume,
                    base_area: w * q.base_area + (1.0 - w) * g.base_area,
                    perimeter: w * q.perimeter + (1.0 - w) * g.perimeter,
                    ..CapMeasures::EMPTY
                }
            }
            _ => g,
        };
        if !(c.volume > 0.0 && c.base_area > 0.0 && c.perimeter > 0.0) {
            continue;
        }
        vmax = vmax.max(c.volume);
        amax = amax.max(c.base_area);
        dep.push(d);
        vol.push(vmax);
        area.push(amax);
        per.push(c.perimeter);
    }
    if dep.len() < 2 {
        return Err(TextureError::NotEnoughData(format!(
            "asperity {index}: fewer than 2 non-empty cap samples"
        )));
    }
    // Ω₀ ≤ Σ₀δ₀ is needed by the table (a cap cannot hold more volume).
    vol[0] = vol[0].min(area[0] * dep[0]);
    Ok(TabulatedCap::from_samples(&dep, &vol, &area, &per)?)
}
