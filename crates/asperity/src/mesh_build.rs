//! Builders of closed, outward-oriented triangle meshes, `z` up.
//!
//! Parry's primitive meshes are `y`-up and its "cone" is a pyramid, hence
//! these.

use std::collections::HashMap;
use std::f64::consts::PI;

use crate::GeometryError;
use crate::error::check_positive;

/// Vertex and index buffers of a triangle mesh (triangles counter-clockwise
/// seen from outside), with builders of the closed meshes used for asperities.
///
/// Turn them into an asperity with
/// [`MeshAsperity::from_buffers`](crate::MeshAsperity::from_buffers).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshBuffers {
    /// Vertex coordinates `[x, y, z]` (m), `z` up.
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as indices into `vertices`.
    pub indices: Vec<[u32; 3]>,
}

const MAX_VERTICES: usize = 1 << 28;

fn too_big(n: usize) -> Result<(), GeometryError> {
    if n > MAX_VERTICES {
        Err(GeometryError::InvalidMesh(format!(
            "{n} vertices requested: at most {MAX_VERTICES}"
        )))
    } else {
        Ok(())
    }
}

fn at_least(name: &'static str, value: u32, min: u32) -> Result<(), GeometryError> {
    if value >= min {
        Ok(())
    } else {
        Err(GeometryError::InvalidParameter {
            name,
            value: f64::from(value),
            requirement: match min {
                1 => "≥ 1",
                _ => "≥ 3",
            },
        })
    }
}

impl MeshBuffers {
    /// A geodesic sphere of radius `radius` centred at the origin: an
    /// icosahedron with a vertex at the summit `(0, 0, R)`, each triangle split
    /// in 4 `subdivisions` times, vertices projected on the sphere
    /// (`20·4ⁿ` triangles, `n ≤ 10`). All vertices lie on the sphere, so the
    /// mesh is inscribed in it.
    pub fn icosphere(radius: f64, subdivisions: u32) -> Result<Self, GeometryError> {
        let r = check_positive("sphere radius", radius)?;
        if subdivisions > 10 {
            return Err(GeometryError::InvalidParameter {
                name: "icosphere subdivisions",
                value: f64::from(subdivisions),
                requirement: "≤ 10",
            });
        }
        let zr = 1.0 / 5f64.sqrt();
        let sr = 2.0 * zr;
        let mut v = vec![[0.0, 0.0, 1.0]];
        for k in 0..5 {
            let a = 2.0 * PI * f64::from(k) / 5.0;
            v.push([sr * a.cos(), sr * a.sin(), zr]);
        }
        for k in 0..5 {
            let a = 2.0 * PI * (f64::from(k) + 0.5) / 5.0;
            v.push([sr * a.cos(), sr * a.sin(), -zr]);
        }
        v.push([0.0, 0.0, -1.0]);
        let (top, bottom) = (0u32, 11u32);
        let up = |k: u32| 1 + k % 5;
        let lo = |k: u32| 6 + k % 5;
        let mut f = Vec::with_capacity(20);
        for k in 0..5 {
            f.push([top, up(k), up(k + 1)]);
            f.push([up(k), lo(k), up(k + 1)]);
            f.push([up(k + 1), lo(k), lo(k + 1)]);
            f.push([bottom, lo(k + 1), lo(k)]);
        }
        for _ in 0..subdivisions {
            let mut mid: HashMap<(u32, u32), u32> = HashMap::new();
            let mut nf = Vec::with_capacity(4 * f.len());
            let mut midpoint = |a: u32, b: u32, v: &mut Vec<[f64; 3]>| {
                let key = (a.min(b), a.max(b));
                *mid.entry(key).or_insert_with(|| {
                    let (p, q) = (v[a as usize], v[b as usize]);
                    let m = [p[0] + q[0], p[1] + q[1], p[2] + q[2]];
                    let l = (m[0] * m[0] + m[1] * m[1] + m[2] * m[2]).sqrt();
                    v.push([m[0] / l, m[1] / l, m[2] / l]);
                    (v.len() - 1) as u32
                })
            };
            for &[a, b, c] in &f {
                let ab = midpoint(a, b, &mut v);
                let bc = midpoint(b, c, &mut v);
                let ca = midpoint(c, a, &mut v);
                nf.extend([[a, ab, ca], [ab, b, bc], [ca, bc, c], [ab, bc, ca]]);
            }
            f = nf;
        }
        // Exact poles, then scale.
        let vertices = v
            .into_iter()
            .map(|p| [r * p[0], r * p[1], r * p[2]])
            .collect();
        Ok(Self {
            vertices,
            indices: f,
        })
    }

    /// A right circular cone of half-angle `half_angle` (rad, in `(0, π/2)`)
    /// and height `height` (m), apex up at `(0, 0, height)`, closed by its base
    /// disc at `z = 0`: a pyramid with `segments ≥ 3` flanks inscribed in the
    /// cone. Its section at depth `δ < height` is the regular `segments`-gon
    /// inscribed in the circle of radius `δ tan α`.
    pub fn cone(half_angle: f64, height: f64, segments: u32) -> Result<Self, GeometryError> {
        if !(half_angle.is_finite() && half_angle > 0.0 && half_angle < PI / 2.0) {
            return Err(GeometryError::InvalidParameter {
                name: "cone half-angle",
                value: half_angle,
                requirement: "strictly between 0 and π/2 rad",
            });
        }
        let h = check_positive("cone height", height)?;
        at_least("cone segments", segments, 3)?;
        too_big(segments as usize + 2)?;
        let rho = h * half_angle.tan();
        let mut vertices = vec![[0.0, 0.0, h], [0.0, 0.0, 0.0]];
        for k in 0..segments {
            let a = 2.0 * PI * f64::from(k) / f64::from(segments);
            vertices.push([rho * a.cos(), rho * a.sin(), 0.0]);
        }
        let ring = |k: u32| 2 + k % segments;
        let mut indices = Vec::with_capacity(2 * segments as usize);
        for k in 0..segments {
            indices.push([0, ring(k), ring(k + 1)]);
            indices.push([1, ring(k + 1), ring(k)]);
        }
        Ok(Self { vertices, indices })
    }

    /// The closed mesh of the height function `z = f(x, y)` over the disc of
    /// radius `radius` centred at the origin, closed by a vertical wall and a
    /// flat bottom at `z = bottom`.
    ///
    /// The top is sampled on a polar grid: the centre, then `rings ≥ 1` circles
    /// of radii `radius·j/rings` with `segments ≥ 3` points each (at angles
    /// `2πk/segments`). A radial profile `f(r)` that is linear in `r` between
    /// rings therefore has exactly polygonal sections: regular
    /// `segments`-gons. Every `f` value must be finite and strictly above
    /// `bottom`.
    pub fn height_field_disc(
        radius: f64,
        rings: u32,
        segments: u32,
        bottom: f64,
        f: impl Fn(f64, f64) -> f64,
    ) -> Result<Self, GeometryError> {
        let rho = check_positive("disc radius", radius)?;
        at_least("disc rings", rings, 1)?;
        at_least("disc segments", segments, 3)?;
        check_bottom(bottom)?;
        let (nr, ns) = (rings as usize, segments as usize);
        too_big(nr.saturating_mul(ns).saturating_add(ns + 2))?;
        let mut vertices = Vec::with_capacity(nr * ns + ns + 2);
        vertices.push(top_point(0.0, 0.0, bottom, &f)?);
        for j in 1..=rings {
            let r = rho * f64::from(j) / f64::from(rings);
            for k in 0..segments {
                let a = 2.0 * PI * f64::from(k) / f64::from(segments);
                vertices.push(top_point(r * a.cos(), r * a.sin(), bottom, &f)?);
            }
        }
        let node = |j: u32, k: u32| 1 + (j - 1) * segments + k % segments;
        let mut indices = Vec::new();
        for k in 0..segments {
            indices.push([0, node(1, k), node(1, k + 1)]);
        }
        for j in 1..rings {
            for k in 0..segments {
                let (a, b, c, d) = (
                    node(j, k),
                    node(j + 1, k),
                    node(j + 1, k + 1),
                    node(j, k + 1),
                );
                indices.push([a, b, c]);
                indices.push([a, c, d]);
            }
        }
        let boundary: Vec<u32> = (0..segments).map(|k| node(rings, k)).collect();
        close_with_wall(&mut vertices, &mut indices, &boundary, bottom, [0.0, 0.0]);
        Ok(Self { vertices, indices })
    }

    /// The closed mesh of the height function `z = f(x, y)` over the rectangle
    /// `x[0] ≤ x ≤ x[1]`, `y[0] ≤ y ≤ y[1]`, sampled on a regular grid of
    /// `nx × ny ≥ 1` cells (each split along its diagonal from `(i, j)` to
    /// `(i+1, j+1)`), closed by vertical walls and a flat bottom at
    /// `z = bottom`. Every `f` value must be finite and strictly above `bottom`.
    /// Refused with [`GeometryError::InvalidParameter`]: a range with a
    /// non-finite bound or width (`[-1e308, 1e308]`) or not increasing.
    ///
    /// Road textures sampled on a grid become meshes this way.
    pub fn height_field_rect(
        x: [f64; 2],
        y: [f64; 2],
        nx: u32,
        ny: u32,
        bottom: f64,
        f: impl Fn(f64, f64) -> f64,
    ) -> Result<Self, GeometryError> {
        for (name, r) in [("rectangle x range", x), ("rectangle y range", y)] {
            // A width past f64::MAX (bounds ±1e308) would make every vertex NaN.
            let width = r[1] - r[0];
            if !(r[0].is_finite() && r[1].is_finite() && width.is_finite() && width > 0.0) {
                return Err(GeometryError::InvalidParameter {
                    name,
                    value: width,
                    requirement: "> 0 with finite bounds and a finite width",
                });
            }
        }
        at_least("grid cells along x", nx, 1)?;
        at_least("grid cells along y", ny, 1)?;
        check_bottom(bottom)?;
        let (cx, cy) = (nx as usize + 1, ny as usize + 1);
        too_big(cx.saturating_mul(cy).saturating_mul(2))?;
        let gx = |i: u32| x[0] + (x[1] - x[0]) * f64::from(i) / f64::from(nx);
        let gy = |j: u32| y[0] + (y[1] - y[0]) * f64::from(j) / f64::from(ny);
        let mut vertices = Vec::with_capacity(cx * cy + 2 * (cx + cy));
        for j in 0..=ny {
            for i in 0..=nx {
                vertices.push(top_point(gx(i), gy(j), bottom, &f)?);
            }
        }
        let node = |i: u32, j: u32| j * (nx + 1) + i;
        let mut indices = Vec::with_capacity(2 * (nx * ny) as usize);
        for j in 0..ny {
            for i in 0..nx {
                let (a, b, c, d) = (
                    node(i, j),
                    node(i + 1, j),
                    node(i + 1, j + 1),
                    node(i, j + 1),
                );
                indices.push([a, b, c]);
                indices.push([a, c, d]);
            }
        }
        // Boundary, counter-clockwise seen from above.
        let mut boundary = Vec::with_capacity(2 * (nx + ny) as usize);
        boundary.extend((0..nx).map(|i| node(i, 0)));
        boundary.extend((0..ny).map(|j| node(nx, j)));
        boundary.extend((1..=nx).rev().map(|i| node(i, ny)));
        boundary.extend((1..=ny).rev().map(|j| node(0, j)));
        // Halves first: `x[0] + x[1]` overflows for bounds near ±f64::MAX.
        let centre = [0.5 * x[0] + 0.5 * x[1], 0.5 * y[0] + 0.5 * y[1]];
        close_with_wall(&mut vertices, &mut indices, &boundary, bottom, centre);
        Ok(Self { vertices, indices })
    }

    /// Merge vertices with exactly equal coordinates (as in a triangle soup
    /// read from STL) and drop the triangles this makes degenerate.
    pub fn merge_duplicate_vertices(&mut self) {
        let mut map: HashMap<[u64; 3], u32> = HashMap::new();
        let mut vertices = Vec::new();
        let mut remap = Vec::with_capacity(self.vertices.len());
        for v in &self.vertices {
            // +0.0 and −0.0 are the same point.
            let key = v.map(|c| if c == 0.0 { 0 } else { c.to_bits() });
            let id = *map.entry(key).or_insert_with(|| {
                vertices.push(*v);
                (vertices.len() - 1) as u32
            });
            remap.push(id);
        }
        let indices = self
            .indices
            .iter()
            .filter(|t| t.iter().all(|&i| (i as usize) < remap.len()))
            .map(|t| t.map(|i| remap[i as usize]))
            .filter(|[a, b, c]| a != b && b != c && c != a)
            .collect();
        self.vertices = vertices;
        self.indices = indices;
    }
}

fn check_bottom(bottom: f64) -> Result<(), GeometryError> {
    if bottom.is_finite() {
        Ok(())
    } else {
        Err(GeometryError::InvalidParameter {
            name: "height field bottom",
            value: bottom,
            requirement: "finite",
        })
    }
}

fn top_point(
    x: f64,
    y: f64,
    bottom: f64,
    f: &impl Fn(f64, f64) -> f64,
) -> Result<[f64; 3], GeometryError> {
    let z = f(x, y);
    if z.is_finite() && z > bottom {
        Ok([x, y, z])
    } else {
        Err(GeometryError::InvalidMesh(format!(
            "height function gives {z} at ({x}, {y}): must be finite and above the bottom {bottom}"
        )))
    }
}

/// Close a top surface whose boundary loop (counter-clockwise seen from above)
/// is `boundary` with vertical walls down to `bottom` and a flat bottom fanned
/// from `centre` (which must see the whole boundary: disc or rectangle).
fn close_with_wall(
    vertices: &mut Vec<[f64; 3]>,
    indices: &mut Vec<[u32; 3]>,
    boundary: &[u32],
    bottom: f64,
    centre: [f64; 2],
) {
    let first = vertices.len() as u32;
    for &b in boundary {
        let p = vertices[b as usize];
        vertices.push([p[0], p[1], bottom]);
    }
    vertices.push([centre[0], centre[1], bottom]);
    let c = vertices.len() as u32 - 1;
    let n = boundary.len();
    for k in 0..n {
        let (t0, t1) = (boundary[k], boundary[(k + 1) % n]);
        let (b0, b1) = (first + k as u32, first + ((k + 1) % n) as u32);
        indices.push([t0, b0, b1]);
        indices.push([t0, b1, t1]);
        indices.push([c, b1, b0]);
    }
}
