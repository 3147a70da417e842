#![doc = include_str!("../README.md")]

/// Cap geometry of rigid asperities (`tyreroad-asperity`).
pub use tyreroad_asperity as asperity;
/// Reference full-grid BEM contact solver (`tyreroad-bem`).
pub use tyreroad_bem as bem;
/// Single-asperity contact laws (`tyreroad-contact-law`).
pub use tyreroad_contact_law as contact_law;
/// The shared core (`tyreroad-core`): material, grid and field, spectra,
/// PCHIP, validators, parallelism. Named `shared` because `core` is Rust's.
pub use tyreroad_core as shared;
/// Pressure-film post-processing (`tyreroad-film`).
pub use tyreroad_film as film;
/// Multipoint contact solver (`tyreroad-multipoint`).
pub use tyreroad_multipoint as multipoint;
/// Rolling-time assembly (`tyreroad-rolling`).
pub use tyreroad_rolling as rolling;
/// Road textures: height maps, synthesis, indicators, segmentation
/// (`tyreroad-texture`).
pub use tyreroad_texture as texture;
/// Viscoelastic tread: Prony series, hereditary multipoint solve and its
/// BEM reference (`tyreroad-viscoelastic`).
pub use tyreroad_viscoelastic as viscoelastic;

pub mod bem_rolling;
pub mod fidelity;
pub mod scenario;
pub mod texture_road;
pub mod two_scale;
