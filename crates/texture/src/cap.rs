//! The caps of segmented asperities: the exact grid cap of a basin
//! ([`GridCap`]) and its table with a smooth onset ([`asperity_cap`]).

// Numerical kernels index several arrays in step.
#![allow(clippy::needless_range_loop)]

use tyreroad_asperity::{CapGeometry, CapMeasures, EllipticParaboloid, TabulatedCap};

use crate::error::TextureError;
use crate::heightmap::HeightMap;
use crate::segment::Segmentation;

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
/// `top` is the summit height of the [`crate::Asperity`]. The cap is exact while
/// the plane stays above every point on the basin's boundary (a point with
/// a neighbour outside the basin, or on the map's edge): that depth is
/// [`CapGeometry::max_depth`]; beyond it the measures are those of the
/// truncated basin (the contour stops at the boundary). A piece of a split
/// top ([`crate::split_wide_tops`]; its [`crate::Asperity::floor`] below its own
/// cells) stands on vertical walls at its cut: `Γ` also counts the parts of
/// its outline above the plane, so a flat tile is a flat punch of its
/// shape at every depth.
#[derive(Clone, Debug)]
pub struct GridCap {
    top: f64,
    max_depth: f64,
    tris: Vec<Tri>,
    /// The outline of a piece's complete cells (segments, relative to the
    /// summit), empty for a whole basin.
    walls: Vec<[[f64; 3]; 2]>,
}

impl GridCap {
    /// The grid cap of asperity `index` of `seg` (computed on `map`, the map
    /// that was segmented).
    pub fn new(map: &HeightMap, seg: &Segmentation, index: usize) -> Result<Self, TextureError> {
        let a = seg.asperities().get(index).ok_or_else(|| {
            TextureError::NotEnoughData(format!("asperity {index} of {}", seg.asperities().len()))
        })?;
        if (map.nx(), map.ny()) != seg.size() {
            return Err(TextureError::InvalidMap(
                "the map is not the one that was segmented".into(),
            ));
        }
        let (nx, ny) = seg.size();
        let id = index as u32;
        let inb = |i: usize, j: usize| seg.labels()[j * nx + i] == id;
        let (dx, dy) = (map.dx(), map.dy());
        let top = a.summit_height;
        let (sx, sy) = (a.summit[0], a.summit[1]);
        let mut boundary_max = f64::NEG_INFINITY;
        let mut tris = Vec::new();
        let h = map.heights();
        let lowest = a.cells.iter().map(|&c| h[c]).fold(f64::INFINITY, f64::min);
        let is_piece = a.floor < lowest;
        let complete = |i: usize, j: usize| {
            i + 1 < nx
                && j + 1 < ny
                && inb(i, j)
                && inb(i + 1, j)
                && inb(i, j + 1)
                && inb(i + 1, j + 1)
        };
        let mut walls = Vec::new();
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
            if complete(i, j) {
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
                if is_piece {
                    // Edges 0..4: bottom, right, top, left; an edge is on
                    // the outline when the cell across it is not complete.
                    let across = [
                        j > 0 && complete(i, j - 1),
                        complete(i + 1, j),
                        complete(i, j + 1),
                        i > 0 && complete(i - 1, j),
                    ];
                    for e in 0..4 {
                        if !across[e] {
                            walls.push([q[e], q[(e + 1) % 4]]);
                        }
                    }
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
            walls,
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
        // A piece's walls: the part of each outline segment above the plane.
        for [a, b] in &self.walls {
            let len = ((b[0] - a[0]).powi(2) + (b[1] - a[1]).powi(2)).sqrt();
            match (a[2] > zp, b[2] > zp) {
                (true, true) => m.perimeter += len,
                (false, false) => {}
                (above_a, _) => {
                    let dz = (b[2] - a[2]).abs();
                    let s = if above_a { a[2] - zp } else { b[2] - zp } / dz;
                    m.perimeter += s * len;
                    // The cut point runs down the segment as the plane sinks.
                    m.d_perimeter += len / dz;
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
    /// `δ_max`, see `TabulatedCap::default_grid`): from 2 to
    /// `TabulatedCap::MAX_NODES` (1e6).
    pub nodes: usize,
    /// Largest depth tabulated (m), finite and > 0; `None` = the grid cap's
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
/// paraboloid fits ([`crate::SummitFit`]), the table uses the cap of that
/// elliptic paraboloid (radii `r1`, `r2`) below `2δ₁`, with `δ₁ = top −
/// min(heights of the 3 × 3 points around the summit)`, the grid cap above
/// `10δ₁`, and a blend `w·paraboloid + (1 − w)·grid` between them, with `w` a smoothstep
/// in `ln δ`. `Ω` and `Σ` are then made non-decreasing (running maximum).
/// Without a fit the grid cap is tabulated as it is and `TabulatedCap`'s
/// power-law onset applies. Depths where the grid cap is still empty are
/// dropped.
///
/// Refused with [`TextureError::InvalidParameter`]: `opts.nodes` outside
/// `2..=TabulatedCap::MAX_NODES`, `opts.max_depth` given but not finite and
/// > 0.
pub fn asperity_cap(
    map: &HeightMap,
    seg: &Segmentation,
    index: usize,
    opts: &CapOptions,
) -> Result<TabulatedCap, TextureError> {
    if !(2..=TabulatedCap::MAX_NODES).contains(&opts.nodes) {
        return Err(TextureError::InvalidParameter {
            name: "cap options nodes",
            value: opts.nodes as f64,
            requirement: "≥ 2 and ≤ TabulatedCap::MAX_NODES = 1e6",
        });
    }
    if let Some(d) = opts.max_depth
        && !(d.is_finite() && d > 0.0)
    {
        // Not the "no depth range" of a summit level with its basin's rim:
        // the depth asked for is the fault.
        return Err(TextureError::InvalidParameter {
            name: "cap options max_depth (m)",
            value: d,
            requirement: "finite and > 0",
        });
    }
    let grid = GridCap::new(map, seg, index)?;
    let a = &seg.asperities()[index];
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
