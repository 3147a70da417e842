//! The one error type of the scenario layer.

use std::path::PathBuf;

/// What can go wrong reading, running or writing a scenario. Each variant
/// keeps the layer's own error as its source, with the section or the load
/// it happened at.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum ScenarioError {
    /// A file could not be read or written.
    #[error("{action} {}: {source}", path.display())]
    Io {
        /// What was being done ("reading", "writing", ...).
        action: &'static str,
        /// The file or directory.
        path: PathBuf,
        /// The system's error.
        source: std::io::Error,
    },
    /// The TOML text does not describe a scenario; the message names the
    /// offending key and its line.
    #[error("reading scenario {origin}: {message}")]
    Parse {
        /// Where the text came from (a path or a label).
        origin: String,
        /// The parser's message (key, line and column).
        message: String,
    },
    /// A value is out of the range where it means something; names the key.
    #[error("`{key}` = {value}: expected {expected}")]
    Value {
        /// The key, with its section (`[rolling] step`).
        key: String,
        /// The value as written or read.
        value: String,
        /// What it must be.
        expected: String,
    },
    /// The scenario parses but asks for something inconsistent or
    /// unsupported (the message names the section).
    #[error("{0}")]
    Invalid(String),
    /// A value of the shared core (material, grid, spectrum) is out of range.
    #[error("{context}: {source}")]
    Core {
        /// Section or output.
        context: String,
        /// The core error.
        source: tyreroad_core::CoreError,
    },
    /// A material, shape or law is out of range.
    #[error("{context}: {source}")]
    Law {
        /// Section or asperity.
        context: String,
        /// The contact-law error.
        source: tyreroad_contact_law::LawError,
    },
    /// A shape's geometry is out of range.
    #[error("{context}: {source}")]
    Geometry {
        /// Section or asperity.
        context: String,
        /// The geometry error.
        source: tyreroad_asperity::GeometryError,
    },
    /// A multipoint solve failed or the asperity set is malformed.
    #[error("{context}: {source}")]
    Solve {
        /// What was being solved.
        context: String,
        /// The solver's error.
        source: tyreroad_multipoint::SolveError,
    },
    /// A height map could not be read or synthesised.
    #[error("{context}: {source}")]
    Texture {
        /// Section.
        context: String,
        /// The texture error.
        source: tyreroad_texture::TextureError,
    },
    /// A texture could not be turned into asperities.
    #[error("turning the texture into asperities: {0}")]
    TextureRoad(#[from] crate::texture_road::TextureRoadError),
    /// Calibrating the laws of a `[model] fidelity = "calibrated"` run failed.
    #[error("[model] fidelity: {0}")]
    Fidelity(#[from] crate::fidelity::FidelityError),
    /// A two-scale rebuild failed.
    #[error("{context}: {source}")]
    TwoScale {
        /// The load.
        context: String,
        /// The two-scale error.
        source: crate::two_scale::TwoScaleError,
    },
    /// A rolling run failed.
    #[error("rolling: {0}")]
    Rolling(#[from] tyreroad_rolling::RollingError),
    /// A BEM reference solve failed.
    #[error("{context}: {source}")]
    Bem {
        /// What was being solved.
        context: String,
        /// The BEM error.
        source: tyreroad_bem::BemError,
    },
    /// An output could not be encoded.
    #[error("encoding {what}: {message}")]
    Encode {
        /// The output.
        what: String,
        /// The encoder's message.
        message: String,
    },
}

impl ScenarioError {
    /// A step with no asperity under the footprint, said in the scenario's
    /// terms: the path (keys) misses the road whose summits are `positions`
    /// (a part's window of it when `window`).
    pub(crate) fn off_road(
        positions: &[[f64; 2]],
        window: bool,
        lateral: f64,
        position: f64,
    ) -> Self {
        let span = |axis: usize| {
            positions
                .iter()
                .map(|p| p[axis])
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), v| {
                    (a.min(v), b.max(v))
                })
        };
        let ((x0, x1), (y0, y1)) = (span(0), span(1));
        Self::Invalid(format!(
            "[rolling] start/end/lateral: no asperity under the footprint at x = {position} m, \
             lateral {lateral} m; the {} span x ∈ [{x0:.4}, {x1:.4}] m, \
             y ∈ [{y0:.4}, {y1:.4}] m: put the path on the road",
            if window {
                "asperities of this part's window of the road"
            } else {
                "road's asperities"
            }
        ))
    }

    pub(crate) fn io(
        action: &'static str,
        path: impl Into<PathBuf>,
    ) -> impl FnOnce(std::io::Error) -> Self {
        let path = path.into();
        move |source| Self::Io {
            action,
            path,
            source,
        }
    }
}
