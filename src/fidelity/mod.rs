//! The ladder of fidelity (issue 15): which contact laws and which coupling
//! the multipoint model uses on a texture, and how far each choice lands
//! from the full BEM.
//!
//! Rungs ([`Fidelity`]), each mapped to a law source and solver options in
//! one place, [`Fidelity::rung`]:
//!
//! - `wilke`: the paper's interaction-potential law `P = dU/dδ` from each
//!   segmented cap's measures with the constant `c` (docs/theory.md §1),
//!   point (Boussinesq) coupling `T_ij = 1/(π E* r_ij)` (§3). Today's model.
//! - `calibrated`: each asperity's law `P(δ)` from a single-asperity BEM
//!   solve of its own cap (the texture's heights on its segmentation basin,
//!   [`calibrate`]), point coupling. The law is then exact for the asperity
//!   alone up to the BEM's discretisation; what remains of the error is the
//!   interaction's. It is also the one rung a `[rolling]` run on a texture
//!   takes: each asperity the path can select calibrated once, reused by
//!   every step ([`rolling`]).
//! - `distributed`: the calibrated laws, and near pairs coupled through
//!   their pressure fields instead of the point kernel
//!   ([`crate::multipoint::Interaction::DISTRIBUTED`], docs/theory.md §3);
//!   far pairs keep the point kernel.
//! - `calibrated_fields`: the calibrated laws, and every pair coupled
//!   through the two asperities' own calibrated pressure fields (the
//!   single-asperity BEM pressure binned per knot, [`field`]) at their
//!   current depths instead of point forces at the summits, by a fixed
//!   point over a sparse correction of the point kernel ([`coupling`],
//!   docs/theory.md §3 "Field coupling"). `distributed` keeps its Hertz
//!   discs: the two are measured side by side.
//! - `clustered`: the calibrated laws, point coupling, and asperities whose
//!   contact patches overlap merged into one body each
//!   ([`crate::multipoint::Clusters::Always`], docs/theory.md §3
//!   "Clusters"): where no patches overlap it is the `calibrated` rung.
//!
//! Invariants: a calibrated law keeps the [`crate::contact_law::ContactLaw`]
//! contract (`P = k = 0` for `δ ≤ 0`, `P` continuous and non-decreasing,
//! `k = dP/dδ` of the interpolant); equal caps share one table.

mod calibrate;
pub mod cap_sensors;
pub mod compare;
pub mod coupling;
pub mod field;
pub mod joint;
pub mod pair_sum;
mod reference_notes;
pub mod rolling;
pub mod rolling_fields;
pub mod segmentation;
pub mod table_depth;
mod texture;
pub mod under_tread;

use std::fmt;
use std::str::FromStr;

pub use calibrate::{
    CacheCounts, CalibratedLaw, CalibratedTable, CalibrationOptions, CalibrationStats, Calibrator,
    CapPatch, HEIGHT_QUANTUM, JointTile, PathNode, WarmStart, calibrate, calibrate_joint,
    calibrate_with_fields,
};
pub use joint::{body_correction, solve_calibrated};
pub use texture::{CapFallback, calibrated_set, calibrated_set_or_wilke, cap_patch};

use crate::multipoint::{Clusters, Interaction, SolverOptions};

/// Errors of the fidelity module.
#[derive(Debug, thiserror::Error)]
pub enum FidelityError {
    /// A value out of its range.
    #[error("invalid {key}: {value} (expected {expected})")]
    InvalidInput {
        /// What was given.
        key: &'static str,
        /// Its value.
        value: String,
        /// What is accepted.
        expected: String,
    },
    /// An unknown fidelity name.
    #[error(
        "unknown fidelity `{0}` (expected one of: wilke, calibrated, distributed, \
         calibrated_fields, clustered)"
    )]
    UnknownFidelity(String),
    /// A BEM solve failed.
    #[error("{context}: {source}")]
    Bem {
        /// Which solve.
        context: &'static str,
        /// The BEM's error.
        source: crate::bem::BemError,
    },
    /// A cap's own solve, placing a contact's force for the sensors
    /// ([`cap_sensors`]), failed.
    #[error("cap sensor forces at step {step}: {source}")]
    CapSensors {
        /// The rolling step (0-based).
        step: usize,
        /// The BEM's error.
        source: crate::bem::BemError,
    },
    /// The disk cache could not be written.
    #[error("calibration cache {}: {source}", path.display())]
    Cache {
        /// The file.
        path: std::path::PathBuf,
        /// The I/O error.
        source: std::io::Error,
    },
    /// A texture could not be turned into asperities.
    #[error(transparent)]
    TextureRoad(#[from] crate::texture_road::TextureRoadError),
    /// A multipoint solve failed.
    #[error("multipoint solve: {0}")]
    Solve(#[from] crate::multipoint::SolveError),
    /// The rolling run that bounds a calibration's approach failed.
    #[error("rolling run: {0}")]
    Rolling(#[from] crate::rolling::RollingError),
    /// The field coupling's fixed point did not settle.
    #[error("field coupling: forces still moving by {change:e} of the load after {rounds} rounds")]
    FieldCoupling {
        /// Rounds run.
        rounds: usize,
        /// The last round's largest force change over the load.
        change: f64,
    },
}

impl FidelityError {
    fn invalid(key: &'static str, value: impl fmt::Display, expected: impl fmt::Display) -> Self {
        Self::InvalidInput {
            key,
            value: value.to_string(),
            expected: expected.to_string(),
        }
    }
}

/// A rung of the ladder.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Fidelity {
    /// Wilke–Sameur potential laws, point coupling (the default).
    Wilke,
    /// BEM-calibrated laws, point coupling.
    Calibrated,
    /// BEM-calibrated laws, distributed near-pair coupling.
    Distributed,
    /// BEM-calibrated laws, pairs coupled through their calibrated
    /// pressure fields.
    CalibratedFields,
    /// BEM-calibrated laws, point coupling, overlapping contacts merged
    /// into clusters solved as one body.
    Clustered,
}

/// Every rung, in ladder order: the validation harness runs this list.
pub const RUNGS: [Fidelity; 5] = [
    Fidelity::Wilke,
    Fidelity::Calibrated,
    Fidelity::Distributed,
    Fidelity::Clustered,
    Fidelity::CalibratedFields,
];

/// Where a rung's laws come from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum LawSource {
    /// The potential law of each cap (`crate::texture_road`).
    Potential,
    /// A BEM-calibrated table per cap ([`Calibrator`]).
    Calibrated,
}

/// How a rung couples its asperities beyond what the solver options say.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Coupling {
    /// The solver's own interaction ([`SolverOptions::interaction`]).
    Solver,
    /// The calibrated pressure fields ([`coupling::solve_field_coupled`]
    /// over laws calibrated [`Calibrator::with_fields`]).
    Fields,
}

/// What a rung runs: its laws, its coupling and its solver options.
#[derive(Clone, Debug)]
pub struct Rung {
    /// The rung.
    pub fidelity: Fidelity,
    /// Where its laws come from.
    pub laws: LawSource,
    /// How its asperities couple.
    pub coupling: Coupling,
    /// Its solver options.
    pub solver: SolverOptions,
}

impl Fidelity {
    /// The name used in scenario files.
    pub fn name(self) -> &'static str {
        match self {
            Self::Wilke => "wilke",
            Self::Calibrated => "calibrated",
            Self::Distributed => "distributed",
            Self::CalibratedFields => "calibrated_fields",
            Self::Clustered => "clustered",
        }
    }

    /// The one place where a rung becomes (law source, solver options),
    /// starting from the caller's `base` options.
    /// The base's [`SolverOptions::interaction`] is replaced by the rung's,
    /// and its [`SolverOptions::clusters`] by `Always` on the `clustered`
    /// rung.
    ///
    /// # Errors
    /// None today; the `Result` leaves room for a rung that cannot run
    /// with the given options.
    pub fn rung(self, base: &SolverOptions) -> Result<Rung, FidelityError> {
        let (laws, interaction, clusters) = match self {
            Self::Wilke => (LawSource::Potential, Interaction::Point, base.clusters),
            Self::Calibrated => (LawSource::Calibrated, Interaction::Point, base.clusters),
            Self::Distributed => (
                LawSource::Calibrated,
                Interaction::DISTRIBUTED,
                base.clusters,
            ),
            // The correction rides on the point kernel; clusters have no
            // fields (the corrected solves run without them).
            Self::CalibratedFields => (LawSource::Calibrated, Interaction::Point, base.clusters),
            Self::Clustered => (LawSource::Calibrated, Interaction::Point, Clusters::Always),
        };
        let coupling = if self == Self::CalibratedFields {
            Coupling::Fields
        } else {
            Coupling::Solver
        };
        Ok(Rung {
            fidelity: self,
            laws,
            coupling,
            solver: SolverOptions {
                interaction,
                clusters,
                ..*base
            },
        })
    }
}

impl fmt::Display for Fidelity {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// `"a", "b" or "c"`: the names a scenario key accepts, for its error.
pub(crate) fn one_of<const N: usize>(names: [&str; N]) -> String {
    let quoted: Vec<String> = names.iter().map(|n| format!("{n:?}")).collect();
    match quoted.split_last() {
        None => String::new(),
        Some((last, [])) => last.clone(),
        Some((last, rest)) => format!("{} or {last}", rest.join(", ")),
    }
}

impl FromStr for Fidelity {
    type Err = FidelityError;
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        RUNGS
            .into_iter()
            .find(|r| r.name() == s)
            .ok_or_else(|| FidelityError::UnknownFidelity(s.to_string()))
    }
}

#[cfg(test)]
mod tests;
