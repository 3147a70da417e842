//! Caps of closed, outward-oriented triangle meshes (the paper's "random
//! shapes"), computed exactly by clipping every triangle against the cutting
//! plane.
//!
//! See [`MeshAsperity`] for the algorithm and its guarantees.

use std::collections::{HashMap, HashSet};
use std::fmt;

use nalgebra::Point3;
use parry3d_f64::math::Vector;
use parry3d_f64::shape::{TriMesh, TriMeshFlags};
use tyreroad_core::UnionFind;

use crate::run_out::{RunOut, past_the_end, with_run_out_ends};
use crate::{CapGeometry, CapMeasures, GeometryError, MeshBuffers};

/// One triangle, in coordinates relative to the summit (local `z ≤ 0`).
#[derive(Clone, Copy, Debug)]
struct Tri {
    /// Vertices relative to the summit, in the mesh's (outward) order.
    v: [[f64; 3]; 3],
    /// Highest local z of the three vertices.
    top: f64,
    /// Lowest local z of the three vertices.
    bottom: f64,
    /// `det(a, b, c) / 6` in summit coordinates.
    vol0: f64,
    /// Signed area of the projection on the horizontal plane (`+` facing up).
    area: f64,
    /// `n_z / |n_xy|` of the unit normal: `dΣ/dδ` per unit length of cut.
    slope: f64,
}

/// Sums of the contributions of the kept parts of the triangles.
#[derive(Clone, Copy, Debug, Default)]
struct Acc {
    volume: f64,
    area: f64,
    length: f64,
    d_area: f64,
    d2_area: f64,
    d_length: f64,
}

impl Acc {
    fn add(&mut self, o: &Acc) {
        self.volume += o.volume;
        self.area += o.area;
        self.length += o.length;
        self.d_area += o.d_area;
        self.d2_area += o.d2_area;
        self.d_length += o.d_length;
    }

    fn measures(&self) -> CapMeasures {
        CapMeasures {
            volume: self.volume,
            base_area: self.area,
            perimeter: self.length,
            d_base_area: self.d_area,
            d_perimeter: self.d_length,
            d2_base_area: self.d2_area,
            d2_perimeter: 0.0,
        }
    }
}

/// A rigid asperity described by a closed, outward-oriented triangle mesh.
///
/// `z` is up (towards the elastic body); the summit is the highest vertex.
/// The mesh is validated when built and kept as a parry [`TriMesh`] (see
/// [`MeshAsperity::trimesh`]), so it can also be used for parry's queries.
///
/// # Algorithm (exact to rounding)
///
/// The cutting plane at depth `δ` is `z = z_summit − δ`. A vertex is *above*
/// when its height exceeds the plane's by more than `1e-10` of the mesh's
/// height (a vertex lying on the plane, to rounding, counts as below). Every
/// triangle with a vertex above is clipped to its part above the plane (a
/// triangle, or a quadrilateral), and with `O` a point of the plane:
///
/// - `Ω = Σ det(p₀ − O, pᵢ − O, pᵢ₊₁ − O) / 6` over the fans of the kept
///   parts: the divergence theorem on the closed surface "kept parts + flat
///   base", whose base adds nothing because it contains `O`;
/// - `Σ` = signed sum of the kept parts' areas projected on the plane (facing
///   up `+`, facing down `−`, so overhangs cancel): the projection of a closed
///   surface has zero signed area, and the base's projection is `−Σ`;
/// - `Γ` = total length of the cut segments, one per cut triangle.
///
/// Triangles are sorted by their highest vertex, so an evaluation visits only
/// the triangles above the plane and needs no allocation. Parry's
/// `canonical_split` + mass properties (unconstrained cap triangulation) and
/// per-loop shoelace areas of `canonical_intersection_with_plane` (holes
/// counted as area) are deliberately not used.
///
/// # Derivatives (exact, one-sided at vertex heights)
///
/// Between two consecutive vertex heights the set of cut triangles is fixed,
/// each cut segment moves linearly along its two cut edges, and its length
/// `Lₜ` is affine in `δ`. Hence `Γ` is piecewise linear, `Σ` piecewise
/// quadratic and `Ω` piecewise cubic in `δ`, and
///
/// - `dΩ/dδ = Σ` (exactly, everywhere: `Ω` is C¹);
/// - `dΣ/dδ = Σₜ Lₜ · n_z/|n_xy|` (`n` the unit normal of the cut triangle: a
///   level line of length `L` moves horizontally by `|n_z|/|n_xy|` per unit of
///   `δ`);
/// - `dΓ/dδ = Σₜ dLₜ/dδ`, `d²Σ/dδ² = Σₜ (n_z/|n_xy|) dLₜ/dδ`, `d²Γ/dδ² = 0`.
///
/// `Σ` and `Γ` are continuous; their derivatives jump where the plane crosses
/// a vertex. At a depth exactly equal to a vertex's the derivatives returned
/// are those of the side of smaller `δ` (left derivatives).
///
/// # Depth range and extension
///
/// [`CapGeometry::max_depth`] is by default [`MeshAsperity::monotone_depth`]:
/// the whole height of the mesh for a *terrain* (no face facing down except a
/// flat bottom at the lowest height, e.g. every mesh built by
/// [`MeshBuffers::height_field_disc`] or [`MeshBuffers::height_field_rect`]),
/// or the depth of the first overhanging face met (≈ the equator of a sphere
/// mesh). Above it no face facing down is cut, so every cut triangle adds
/// `Lₜ n_z/|n_xy| ≥ 0` to `dΣ/dδ`: `Σ` and `Ω` never decrease. Beyond
/// `max_depth` the asperity is continued as a [`TabulatedCap`](crate::TabulatedCap)
/// is past its last node: `Σ` and `Γ` run out from their values and slopes
/// at `max_depth` along a monotone cubic to a slope of 0 (over the mesh's
/// last piece of depth, at most a tenth of `max_depth`), then stay constant
/// (vertical walls, like [`Sphere`](crate::Sphere) below its equator); `Ω`
/// stays their integral. Walls started at once would make the potential
/// law's force jump where `Σ'` does not vanish (twice over at a pyramid's
/// base). [`MeshAsperity::with_max_depth`] moves that limit (up to the whole
/// height).
///
/// # Example
///
/// ```
/// use tyreroad_asperity::{CapGeometry, MeshAsperity, MeshBuffers};
///
/// // A cone of half-angle 45°, 1 mm high, with 64 flanks.
/// let mesh = MeshAsperity::from_buffers(&MeshBuffers::cone(0.25 * std::f64::consts::PI, 1e-3, 64)?)?;
/// let cap = mesh.cap(0.5e-3);
/// // The section is a regular 64-gon of circumradius 0.5 mm.
/// let n = 64.0;
/// let r: f64 = 0.5e-3;
/// let area = 0.5 * n * r * r * (2.0 * std::f64::consts::PI / n).sin();
/// assert!((cap.base_area - area).abs() < 1e-12 * area);
/// assert!((cap.volume - area * 0.5e-3 / 3.0).abs() < 1e-12 * cap.volume);
/// # Ok::<(), tyreroad_asperity::GeometryError>(())
/// ```
#[derive(Clone)]
pub struct MeshAsperity {
    mesh: TriMesh,
    summit: [f64; 3],
    /// Triangles sorted by decreasing `top`.
    tris: Vec<Tri>,
    /// `neighbors[t][k]`: sorted index of the triangle across edge `v[k] → v[k+1]`.
    neighbors: Vec<[u32; 3]>,
    height: f64,
    volume: f64,
    first_ring_depth: f64,
    monotone_depth: f64,
    max_depth: f64,
    /// Height within which a vertex counts as on the cutting plane:
    /// vertices of one ring rounded apart by a few ulps are cut together,
    /// not as pieces of depth 1e-17 wide whose slopes are 1e15.
    on_plane: f64,
    at_max: CapMeasures,
    /// `Σ` past `max_depth`.
    area_run_out: RunOut,
    /// `Γ` past `max_depth`.
    perimeter_run_out: RunOut,
}

impl fmt::Debug for MeshAsperity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.debug_struct("MeshAsperity")
            .field("triangles", &self.tris.len())
            .field("vertices", &self.mesh.vertices().len())
            .field("summit", &self.summit)
            .field("height", &self.height)
            .field("volume", &self.volume)
            .field("max_depth", &self.max_depth)
            .finish_non_exhaustive()
    }
}

/// One connected cap of a [`MeshSection`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct CapPatch {
    /// Volume of this connected part of the cap (m³).
    pub volume: f64,
    /// Area of its base (m²).
    pub base_area: f64,
    /// Perimeter of its base, all its loops (m).
    pub perimeter: f64,
    /// Number of closed loops bounding its base: 1 for a disc-like section,
    /// 2 for an annulus (a crater cut between its floor and its rim), …
    pub loops: usize,
}

/// The cap of a mesh with its topology: see [`MeshAsperity::section`].
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshSection {
    /// The measures of the whole cap, as returned by [`CapGeometry::cap`].
    pub measures: CapMeasures,
    /// Number of closed loops of the section (connected components of the cut
    /// segments).
    pub loops: usize,
    /// The connected parts of the cap, the one holding the summit first, then
    /// by decreasing height. For a mesh without overhangs each patch is one
    /// connected region of the section.
    pub patches: Vec<CapPatch>,
}

impl MeshAsperity {
    /// An asperity from vertices and triangles (indices into `vertices`,
    /// counter-clockwise seen from outside).
    ///
    /// Refused with [`GeometryError::InvalidMesh`]: fewer than 4 triangles,
    /// indices out of range, non-finite coordinates, degenerate (repeated
    /// vertex or zero-area) triangles, non-manifold or inconsistently oriented
    /// edges (an edge used twice in the same direction, e.g. by a flipped
    /// triangle), open meshes (an edge with no opposite triangle), meshes of
    /// more than one closed shell (triangles connected across edges: two
    /// bodies, or a body with a cavity, whose volumes would add up), and
    /// meshes oriented inwards (negative total volume). Vertices used by no
    /// triangle are ignored.
    pub fn new(vertices: &[[f64; 3]], indices: &[[u32; 3]]) -> Result<Self, GeometryError> {
        Self::build(vertices.to_vec(), indices.to_vec())
    }

    /// Same as [`MeshAsperity::new`] with nalgebra points.
    pub fn from_points(
        vertices: &[Point3<f64>],
        indices: &[[u32; 3]],
    ) -> Result<Self, GeometryError> {
        Self::build(
            vertices.iter().map(|p| [p.x, p.y, p.z]).collect(),
            indices.to_vec(),
        )
    }

    /// Same as [`MeshAsperity::new`] with the buffers of a [`MeshBuffers`].
    pub fn from_buffers(buffers: &MeshBuffers) -> Result<Self, GeometryError> {
        Self::new(&buffers.vertices, &buffers.indices)
    }

    /// Same as [`MeshAsperity::new`] with the vertices and triangles of a parry
    /// [`TriMesh`] (validated the same way).
    pub fn from_trimesh(mesh: &TriMesh) -> Result<Self, GeometryError> {
        Self::build(
            mesh.vertices().iter().map(|p| [p.x, p.y, p.z]).collect(),
            mesh.indices().to_vec(),
        )
    }

    fn build(vertices: Vec<[f64; 3]>, indices: Vec<[u32; 3]>) -> Result<Self, GeometryError> {
        let bad = |m: String| Err(GeometryError::InvalidMesh(m));
        if indices.len() < 4 {
            return bad(format!(
                "{} triangle(s): a closed mesh needs at least 4",
                indices.len()
            ));
        }
        if vertices.len() > u32::MAX as usize || indices.len() > (u32::MAX / 3) as usize {
            return bad("too many vertices or triangles (indices are 32-bit)".into());
        }
        let nv = vertices.len();
        for (t, tri) in indices.iter().enumerate() {
            for &i in tri {
                if i as usize >= nv {
                    return bad(format!(
                        "triangle {t} refers to vertex {i} but there are only {nv} vertices"
                    ));
                }
            }
        }
        for (i, v) in vertices.iter().enumerate() {
            if !v.iter().all(|c| c.is_finite()) {
                return bad(format!("vertex {i} has a non-finite coordinate: {v:?}"));
            }
        }
        let pos = |i: u32| vertices[i as usize];
        for (t, &[a, b, c]) in indices.iter().enumerate() {
            if a == b || b == c || c == a {
                return bad(format!(
                    "triangle {t} is degenerate: it repeats a vertex ({a}, {b}, {c})"
                ));
            }
            let (pa, pb, pc) = (pos(a), pos(b), pos(c));
            let n = cross(sub(pb, pa), sub(pc, pa));
            let l2 = norm2(sub(pb, pa))
                .max(norm2(sub(pc, pb)))
                .max(norm2(sub(pa, pc)));
            let n2 = norm2(n);
            if !n2.is_finite() || !l2.is_finite() {
                return bad(format!(
                    "triangle {t} has coordinates too large to be measured"
                ));
            }
            if n2.sqrt() <= 64.0 * f64::EPSILON * l2 {
                return bad(format!(
                    "triangle {t} ({a}, {b}, {c}) is degenerate: zero area (collinear or coincident vertices)"
                ));
            }
        }

        // Directed edges: each must be used once, and its reverse once.
        let mut edges: HashMap<(u32, u32), (u32, u8)> = HashMap::with_capacity(3 * indices.len());
        for (t, tri) in indices.iter().enumerate() {
            for k in 0..3 {
                let e = (tri[k], tri[(k + 1) % 3]);
                if let Some((t0, _)) = edges.insert(e, (t as u32, k as u8)) {
                    return bad(format!(
                        "edge ({}, {}) is used in the same direction by triangles {t0} and {t}: \
                         the mesh is non-manifold or inconsistently oriented (a flipped triangle?)",
                        e.0, e.1
                    ));
                }
            }
        }
        let mut boundary = 0usize;
        let mut first_boundary = None;
        for (&(i, j), &(t, _)) in &edges {
            if !edges.contains_key(&(j, i)) {
                boundary += 1;
                let cand = (t, i, j);
                if first_boundary.is_none_or(|f| cand < f) {
                    first_boundary = Some(cand);
                }
            }
        }
        if let Some((t, i, j)) = first_boundary {
            return bad(format!(
                "the mesh is not closed: {boundary} boundary edge(s), e.g. edge ({i}, {j}) of \
                 triangle {t} has no opposite triangle"
            ));
        }
        // Each shell would count as solid: two overlapping copies twice, a
        // cavity's wall as a second body.
        let mut shells = UnionFind::new(indices.len());
        for (&(i, j), &(t, _)) in &edges {
            shells.union(t as usize, edges[&(j, i)].0 as usize);
        }
        let roots: HashSet<usize> = (0..indices.len()).map(|t| shells.find(t)).collect();
        if roots.len() > 1 {
            return bad(format!(
                "the mesh is made of {} separate closed shells (triangles connected across \
                 edges): an asperity must be one closed surface, not several bodies or a body \
                 with a cavity",
                roots.len()
            ));
        }

        // Summit, height, volume (relative to the summit for precision).
        let mut used = vec![false; nv];
        for tri in &indices {
            for &i in tri {
                used[i as usize] = true;
            }
        }
        let mut summit_index = 0usize;
        let mut z_min = f64::INFINITY;
        let mut z_max = f64::NEG_INFINITY;
        for (i, v) in vertices.iter().enumerate() {
            if used[i] {
                if v[2] > z_max {
                    z_max = v[2];
                    summit_index = i;
                }
                z_min = z_min.min(v[2]);
            }
        }
        let summit = vertices[summit_index];
        let local = |i: u32| sub(pos(i), summit);
        let mut second = f64::NEG_INFINITY;
        for (i, v) in vertices.iter().enumerate() {
            if used[i] && v[2] < z_max {
                second = second.max(v[2]);
            }
        }
        let height = z_max - z_min;

        let mut tris: Vec<(Tri, usize)> = Vec::with_capacity(indices.len());
        let mut volume = 0.0;
        for (t, &[a, b, c]) in indices.iter().enumerate() {
            let v = [local(a), local(b), local(c)];
            let n = cross(sub(v[1], v[0]), sub(v[2], v[0]));
            let nxy = n[0].hypot(n[1]);
            let vol0 = det(v[0], v[1], v[2]) / 6.0;
            volume += vol0;
            let tri = Tri {
                v,
                top: v[0][2].max(v[1][2]).max(v[2][2]),
                bottom: v[0][2].min(v[1][2]).min(v[2][2]),
                vol0,
                area: 0.5 * n[2],
                slope: if nxy > 0.0 { n[2] / nxy } else { 0.0 },
            };
            tris.push((tri, t));
        }
        if !volume.is_finite() {
            return bad("the total volume is not finite".into());
        }
        if volume < 0.0 {
            return bad(format!(
                "the mesh is oriented inwards (total signed volume {volume:e} < 0): its triangles \
                 must be counter-clockwise seen from outside"
            ));
        }
        if volume == 0.0 {
            return bad("the mesh encloses no volume".into());
        }

        // Hand it to parry, checking the topology it computes (`with_flags`
        // ignores topology errors, so use `new` + `set_flags`).
        let pverts: Vec<Vector> = vertices
            .iter()
            .map(|v| Vector::new(v[0], v[1], v[2]))
            .collect();
        let mut mesh = TriMesh::new(pverts, indices.clone())
            .map_err(|e| GeometryError::InvalidMesh(format!("parry refused the mesh: {e}")))?;
        mesh.set_flags(
            TriMeshFlags::ORIENTED
                | TriMeshFlags::HALF_EDGE_TOPOLOGY
                | TriMeshFlags::CONNECTED_COMPONENTS,
        )
        .map_err(|e| GeometryError::InvalidMesh(format!("parry's topology check failed: {e}")))?;

        // Sort by decreasing top (stable: ties keep the input order).
        tris.sort_by(|x, y| y.0.top.total_cmp(&x.0.top));
        let mut rank = vec![0u32; indices.len()];
        for (s, &(_, t)) in tris.iter().enumerate() {
            rank[t] = s as u32;
        }
        let mut neighbors = vec![[0u32; 3]; indices.len()];
        for (s, &(_, t)) in tris.iter().enumerate() {
            let tri = indices[t];
            for k in 0..3 {
                let rev = (tri[(k + 1) % 3], tri[k]);
                // Present: checked above.
                if let Some(&(o, _)) = edges.get(&rev) {
                    neighbors[s][k] = rank[o as usize];
                }
            }
        }
        let tris: Vec<Tri> = tris.into_iter().map(|(t, _)| t).collect();

        // Depth of the first face facing down that is not the flat bottom.
        let bottom_local = z_min - z_max;
        let overhang = tris
            .iter()
            .filter(|t| t.area < 0.0 && t.top > bottom_local)
            .map(|t| -t.top)
            .fold(f64::INFINITY, f64::min);
        let monotone_depth = if overhang > 0.0 && overhang < height {
            overhang
        } else {
            height
        };

        let mut out = Self {
            mesh,
            summit,
            tris,
            neighbors,
            height,
            volume,
            first_ring_depth: if second.is_finite() {
                z_max - second
            } else {
                height
            },
            monotone_depth,
            max_depth: monotone_depth,
            on_plane: ON_PLANE * height,
            at_max: CapMeasures::EMPTY,
            area_run_out: RunOut::new(0.0, 0.0, 0.0),
            perimeter_run_out: RunOut::new(0.0, 0.0, 0.0),
        };
        out.end_at(monotone_depth);
        Ok(out)
    }

    /// The same asperity continued by vertical walls below `max_depth`
    /// instead of [`MeshAsperity::monotone_depth`] (see the type's doc).
    /// `max_depth` must lie in `(0, height]`; beyond `monotone_depth` the mesh's
    /// own overhangs may make `Σ` decrease.
    pub fn with_max_depth(mut self, max_depth: f64) -> Result<Self, GeometryError> {
        if !(max_depth > 0.0 && max_depth <= self.height) {
            return Err(GeometryError::InvalidParameter {
                name: "mesh max_depth",
                value: max_depth,
                requirement: "> 0 and ≤ the mesh height",
            });
        }
        self.end_at(max_depth);
        Ok(self)
    }

    /// Ends the described shape at `max_depth`: its measures there, and the
    /// run-outs of `Σ` and `Γ` beyond, each over the last piece of the
    /// mesh (from the deepest vertex above `max_depth`), at most a tenth of
    /// `max_depth`, so the extension stays close to the walls.
    fn end_at(&mut self, max_depth: f64) {
        self.max_depth = max_depth;
        self.at_max = self.raw_cap(max_depth);
        let above = self
            .tris
            .iter()
            .flat_map(|t| t.v.iter().map(|v| -v[2]))
            .filter(|&d| d < max_depth)
            .fold(0.0f64, f64::max);
        let piece = (max_depth - above).min(0.1 * max_depth);
        let m = self.at_max;
        self.area_run_out = RunOut::new(m.base_area, m.d_base_area, piece);
        self.perimeter_run_out = RunOut::new(m.perimeter, m.d_perimeter, piece);
    }

    /// The validated parry mesh (vertices and triangles as given, with
    /// `ORIENTED | HALF_EDGE_TOPOLOGY | CONNECTED_COMPONENTS`).
    pub fn trimesh(&self) -> &TriMesh {
        &self.mesh
    }

    /// The summit: the highest vertex (the first one met if several tie).
    pub fn summit(&self) -> [f64; 3] {
        self.summit
    }

    /// Height of the mesh: summit minus lowest vertex (m).
    pub fn height(&self) -> f64 {
        self.height
    }

    /// Volume enclosed by the mesh (m³).
    pub fn volume(&self) -> f64 {
        self.volume
    }

    /// Number of triangles.
    pub fn num_triangles(&self) -> usize {
        self.tris.len()
    }

    /// Depth of the highest vertex below the summit's height. On
    /// `(0, first_ring_depth]` the cut triangles are those around the summit,
    /// so for a single summit vertex `Ω ∝ δ³`, `Σ ∝ δ²`, `Γ ∝ δ` exactly: a
    /// mesh's contact onset is that of a pyramid, whatever the shape it
    /// approximates (see [`TabulatedCap`](crate::TabulatedCap) for the onset
    /// law of a table).
    pub fn first_ring_depth(&self) -> f64 {
        self.first_ring_depth
    }

    /// Largest depth down to which no face facing down is cut, so that `Σ`
    /// cannot decrease: the whole height for a mesh without overhangs (a flat
    /// bottom at the lowest height does not count). The default
    /// [`CapGeometry::max_depth`].
    pub fn monotone_depth(&self) -> f64 {
        self.monotone_depth
    }

    /// The cap at `depth`, computed on the mesh (no extension).
    fn raw_cap(&self, depth: f64) -> CapMeasures {
        let mut acc = Acc::default();
        for t in &self.tris {
            if t.top + depth <= self.on_plane {
                break;
            }
            acc.add(&clip(t, depth, self.on_plane).0);
        }
        acc.measures()
    }

    /// The cap at `depth` with its topology: the loops of the section and the
    /// connected parts of the cap with their own measures (union–find over the
    /// kept triangles and over the cut edges). Allocates; use
    /// [`CapGeometry::cap`] inside solvers. Beyond [`CapGeometry::max_depth`]
    /// the topology is that at `max_depth` and each patch is continued by
    /// vertical walls.
    pub fn section(&self, depth: f64) -> MeshSection {
        if depth.is_nan() || depth <= 0.0 {
            return MeshSection::default();
        }
        let d = depth.min(self.max_depth);
        let kept = self
            .tris
            .iter()
            .take_while(|t| t.top + d > self.on_plane)
            .count();
        let mut parts = UnionFind::new(kept);
        let mut rings = UnionFind::new(kept);
        let mut pieces = Vec::with_capacity(kept);
        for (s, t) in self.tris[..kept].iter().enumerate() {
            let (acc, above) = clip(t, d, self.on_plane);
            for k in 0..3 {
                let (a, b) = (above[k], above[(k + 1) % 3]);
                let o = self.neighbors[s][k] as usize;
                // A neighbour below the section (past `kept`) joins nothing.
                if o >= kept {
                    continue;
                }
                if a || b {
                    parts.union(s, o);
                }
                if a != b {
                    rings.union(s, o);
                }
            }
            let cut = !(above[0] && above[1] && above[2]);
            pieces.push((acc, cut));
        }
        let mut patch_of_root: HashMap<usize, usize> = HashMap::new();
        let mut patches: Vec<CapPatch> = Vec::new();
        let mut loop_roots: HashSet<usize> = HashSet::new();
        for (s, (acc, cut)) in pieces.iter().enumerate() {
            let root = parts.find(s);
            let p = *patch_of_root.entry(root).or_insert_with(|| {
                patches.push(CapPatch::default());
                patches.len() - 1
            });
            let patch = &mut patches[p];
            patch.volume += acc.volume;
            patch.base_area += acc.area;
            patch.perimeter += acc.length;
            if *cut && loop_roots.insert(rings.find(s)) {
                patch.loops += 1;
            }
        }
        // A closed component wholly above the plane has no base: not a patch.
        patches.retain(|p| p.loops > 0);
        let mut measures = self.raw_cap(d);
        if depth > self.max_depth {
            // Each patch takes its share of the run-out, by its base.
            measures = self.cap(depth);
            let m = self.at_max;
            for p in &mut patches {
                let share = p.base_area / m.base_area;
                p.volume += share * (measures.volume - m.volume);
                p.base_area = share * measures.base_area;
                p.perimeter *= measures.perimeter / m.perimeter;
            }
        }
        MeshSection {
            measures,
            loops: loop_roots.len(),
            patches,
        }
    }
}

impl CapGeometry for MeshAsperity {
    /// Exact cap of the mesh (see the type's doc); beyond
    /// [`CapGeometry::max_depth`], continued by vertical walls.
    fn cap(&self, depth: f64) -> CapMeasures {
        if depth.is_nan() || depth <= 0.0 {
            return CapMeasures::EMPTY;
        }
        if depth <= self.max_depth {
            return self.raw_cap(depth);
        }
        past_the_end(
            self.at_max.volume,
            &self.area_run_out,
            &self.perimeter_run_out,
            depth - self.max_depth,
        )
    }

    fn max_depth(&self) -> f64 {
        self.max_depth
    }

    /// `max_depth`, then the ends of the run-outs of `Σ` and `Γ`: where a
    /// law scans for stretches too soft to solve.
    fn breakpoints(&self) -> Vec<f64> {
        with_run_out_ends(
            vec![self.max_depth],
            &self.area_run_out,
            &self.perimeter_run_out,
        )
    }
}

/// `MeshAsperity::on_plane` relative to the mesh's height.
const ON_PLANE: f64 = 1e-10;

/// The kept part of one triangle at `depth`, and which vertices are above
/// (higher than the plane by more than `on_plane`).
#[inline]
fn clip(t: &Tri, depth: f64, on_plane: f64) -> (Acc, [bool; 3]) {
    let h = [t.v[0][2] + depth, t.v[1][2] + depth, t.v[2][2] + depth];
    let above = [h[0] > on_plane, h[1] > on_plane, h[2] > on_plane];
    if t.bottom + depth > on_plane {
        // Wholly above: det(a + δe, b + δe, c + δe) = det(a, b, c) + 2 δ A_z.
        let acc = Acc {
            volume: t.vol0 + depth * t.area / 3.0,
            area: t.area,
            ..Acc::default()
        };
        return (acc, [true; 3]);
    }
    // Points relative to O = (summit x, summit y, plane): (x, y, height).
    let p = |k: usize| [t.v[k][0], t.v[k][1], h[k]];
    let n_above = above.iter().filter(|&&a| a).count();
    // Cut point on the edge from above vertex `a` to below vertex `b`, and its
    // velocity d/dδ (horizontal).
    let cut = |a: usize, b: usize| {
        let (pa, pb) = (p(a), p(b));
        let dz = pa[2] - pb[2];
        let s = pa[2] / dz;
        let dx = pb[0] - pa[0];
        let dy = pb[1] - pa[1];
        ([pa[0] + s * dx, pa[1] + s * dy, 0.0], [dx / dz, dy / dz])
    };
    // `vanishing`: the plane through (to rounding) the one vertex below two
    // above, where the cut segment has just shrunk to nothing.
    let (poly, n, (q0, v0), (q1, v1), vanishing) = if n_above == 1 {
        let i = if above[0] {
            0
        } else if above[1] {
            1
        } else {
            2
        };
        let (j, k) = ((i + 1) % 3, (i + 2) % 3);
        let c0 = cut(i, j);
        let c1 = cut(i, k);
        ([p(i), c0.0, c1.0, [0.0; 3]], 3, c0, c1, false)
    } else {
        // Two above: `i` is the one below.
        let i = if !above[0] {
            0
        } else if !above[1] {
            1
        } else {
            2
        };
        let (a, b) = ((i + 1) % 3, (i + 2) % 3);
        let c0 = cut(b, i);
        let c1 = cut(a, i);
        ([p(a), p(b), c0.0, c1.0], 4, c0, c1, h[i] >= -on_plane)
    };
    let mut acc = Acc::default();
    for m in 1..n - 1 {
        let (a, b, c) = (poly[0], poly[m], poly[m + 1]);
        acc.volume += det(a, b, c) / 6.0;
        acc.area += 0.5 * ((b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0]));
    }
    let ux = q1[0] - q0[0];
    let uy = q1[1] - q0[1];
    let len = if vanishing { 0.0 } else { ux.hypot(uy) };
    acc.length = len;
    let dl = if vanishing {
        // Its left derivative (as everywhere at vertex heights): the rate
        // at which its two ends part; the direction of a segment of
        // rounding noise would say nothing.
        -(v1[0] - v0[0]).hypot(v1[1] - v0[1])
    } else if len > 0.0 {
        (ux * (v1[0] - v0[0]) + uy * (v1[1] - v0[1])) / len
    } else {
        0.0
    };
    acc.d_length = dl;
    acc.d_area = t.slope * len;
    acc.d2_area = t.slope * dl;
    (acc, above)
}

fn sub(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

fn cross(a: [f64; 3], b: [f64; 3]) -> [f64; 3] {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

fn norm2(a: [f64; 3]) -> f64 {
    a[0] * a[0] + a[1] * a[1] + a[2] * a[2]
}

fn det(a: [f64; 3], b: [f64; 3], c: [f64; 3]) -> f64 {
    let n = cross(b, c);
    a[0] * n[0] + a[1] * n[1] + a[2] * n[2]
}
