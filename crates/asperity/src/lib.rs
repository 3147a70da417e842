//! Geometry of the interpenetrated cap of a rigid road asperity.
//!
//! An asperity is pressed `δ` into an elastic half-space. Cut the asperity with
//! the horizontal plane lying `δ` below its summit; the part above is the
//! *cap*. The contact law of Wilke and Sameur (see `tyreroad-contact-law`)
//! needs three measures of it:
//!
//! - `Ω(δ)`: the cap's volume (the interpenetrated volume),
//! - `Σ(δ)`: the area of its base (the section in the cutting plane),
//! - `Γ(δ)`: the perimeter of that base (all loops of the section),
//!
//! and, for Newton's method, `dΣ/dδ`, `dΓ/dδ` and their second derivatives.
//!
//! # Invariants
//!
//! Every [`CapGeometry`] keeps these, and the tests check them:
//!
//! - `δ ≤ 0` (or NaN) gives the empty cap [`CapMeasures::EMPTY`];
//! - `Ω` and `Σ` never decrease with `δ`;
//! - `dΩ/dδ = Σ` exactly: lowering the cutting plane by `dδ` adds a slab of
//!   area `Σ`.
//!
//! # Shapes
//!
//! - closed forms: [`Sphere`], [`Cone`], [`EllipticParaboloid`];
//! - closed triangle meshes (the paper's "random shapes"): [`MeshAsperity`],
//!   exact to rounding, with [`MeshAsperity::section`] for the patches and
//!   loops of the section, and [`MeshBuffers`] to build sphere, cone and
//!   height-function meshes;
//! - tabulated caps: [`TabulatedCap`], any of the above sampled on a grid of
//!   depths and interpolated monotonically (fast inside a Newton loop).
//!
//! # Meshes
//!
//! A [`MeshAsperity`] is a closed, outward-oriented triangle mesh (`z` up),
//! validated when built (closed, one shell, manifold, consistently oriented,
//! no degenerate triangle, positive volume) and kept as a parry `TriMesh`. Its cap
//! is computed by clipping every triangle against the plane `z = z_top − δ`;
//! with `O` any point of the plane and the kept parts fanned into triangles
//! `(p₀, pᵢ, pᵢ₊₁)`:
//!
//! ```text
//! Ω = Σ det(p₀ − O, pᵢ − O, pᵢ₊₁ − O) / 6      (the flat base adds nothing)
//! Σ = Σ signed area of the projection of each kept part on the plane
//! Γ = Σ length of the cut segments
//! dΣ/dδ = Σₜ Lₜ n_z/|n_xy|,   dΓ/dδ = Σₜ dLₜ/dδ,   d²Γ/dδ² = 0
//! ```
//!
//! over the cut triangles `t` (cut length `Lₜ`, unit normal `n`): between
//! vertex heights `Γ` is linear, `Σ` quadratic and `Ω` cubic in `δ`. A mesh's
//! summit is a vertex, so below the first ring of vertices its cap is that of a
//! pyramid (`Σ ∝ δ²`), even for a sphere mesh. Beyond
//! [`CapGeometry::max_depth`] (the whole height, or the first overhang) a mesh,
//! like a table past its last node, runs out C¹ into vertical walls, so that
//! a law holding `Σ'` and `Γ'` does not jump there.
//!
//! ```
//! use tyreroad_asperity::{CapGeometry, MeshAsperity, MeshBuffers, Sphere};
//!
//! let r = 5e-3;
//! let mesh = MeshAsperity::from_buffers(&MeshBuffers::icosphere(r, 5)?)?;
//! let (m, s) = (mesh.cap(0.1 * r), Sphere::new(r)?.cap(0.1 * r));
//! // 20480 triangles: errors 3.6e-3, 1.8e-3, 7.5e-4 (second order in the edge).
//! assert!((m.volume / s.volume - 1.0).abs() < 4e-3);
//! assert!((m.base_area / s.base_area - 1.0).abs() < 2e-3);
//! assert!((m.perimeter / s.perimeter - 1.0).abs() < 1e-3);
//! // A ball has one patch bounded by one loop.
//! let section = mesh.section(0.1 * r);
//! assert_eq!((section.patches.len(), section.loops), (1, 1));
//! # Ok::<(), tyreroad_asperity::GeometryError>(())
//! ```
//!
//! # Tables
//!
//! A [`TabulatedCap`] interpolates samples `(δₖ, Ωₖ, Σₖ, Γₖ)`: `Σ` and `Γ` by
//! monotone cubic Hermite (Fritsch–Carlson), `Ω` as the integral of the `Σ`
//! interpolant (so `dΩ/dδ = Σ` exactly), a power law `Σ₀ (δ/δ₀)^p` from 0 to
//! the first node, and a short C¹ run-out into vertical walls beyond the last
//! one: `Σ` and `Γ` are C¹ everywhere, so a law built on them is continuous.
//!
//! ```
//! use tyreroad_asperity::{CapGeometry, Cone, TabulatedCap};
//!
//! let cone = Cone::new(1.2)?;
//! let table = TabulatedCap::from_geometry(&cone, 1e-3, 100)?;
//! let (exact, fast) = (cone.cap(1e-9), table.cap(1e-9)); // below the first node
//! assert!((fast.base_area / exact.base_area - 1.0).abs() < 1e-9);
//! # Ok::<(), tyreroad_asperity::GeometryError>(())
//! ```
//!
//! # Example
//!
//! ```
//! use tyreroad_asperity::{CapGeometry, Sphere};
//!
//! let ball = Sphere::new(5e-3)?; // R = 5 mm
//! let cap = ball.cap(0.1e-3); // δ = 0.1 mm
//! // Σ = π (2Rδ − δ²)
//! let expected = std::f64::consts::PI * (2.0 * 5e-3 * 0.1e-3 - 0.1e-3_f64.powi(2));
//! assert!((cap.base_area - expected).abs() < 1e-15);
//! # Ok::<(), tyreroad_asperity::GeometryError>(())
//! ```
//!
//! This layer knows nothing of elasticity: it is pure geometry, SI units.

mod analytic;
mod cap;
mod error;
mod mesh;
mod mesh_build;
mod run_out;
mod table;

pub use analytic::{Cone, EllipticParaboloid, Sphere, ellipse_perimeter};
pub use cap::{CapGeometry, CapMeasures};
pub use error::GeometryError;
pub use mesh::{CapPatch, MeshAsperity, MeshSection};
pub use mesh_build::MeshBuffers;
// Re-exported on purpose: `MeshAsperity::trimesh` returns and
// `MeshAsperity::from_trimesh` takes parry's `TriMesh`, so a caller must
// build against this very parry; nalgebra's `Point3` (for
// `MeshAsperity::from_points`) is parry's own point type's conversion partner.
pub use parry3d_f64;
pub use table::{CapTable, TabulatedCap};
