//! Laws that change with where the footprint lies over their cap
//! (docs/rolling.md, "Laws placed along the path").
//!
//! A road's law is one [`ContactLaw`] per asperity for the whole run. A
//! law calibrated under the tread depends on the tread's shape over its
//! cap, and on a straight path the only part of that shape that changes
//! from step to step is the longitudinal slope `ξ/Rx`, `ξ = x_i − x_c` the
//! summit's offset from the footprint's centre. A road may carry a
//! [`Placement`]: at each step, before the step's problem is built, every
//! selected asperity's law is handed its `ξ` and gives back the law of
//! that step (`None`: its own). The placed laws live for the step; the
//! solver sees plain laws, so the law still knows nothing of the solver,
//! and a road without a placement runs exactly as before.
//!
//! Invariants: a placement is a pure function of the law and `ξ`, so a
//! step's problem does not depend on the chunking or the threads; the
//! checkpoint key probes the placed laws at a few `ξ`
//! ([`PLACEMENT_PROBES`]), so a run with a placement never resumes one
//! without, or the reverse.

use std::borrow::Cow;

use tyreroad_contact_law::ContactLaw;

use crate::Road;

/// How asperity law `law` becomes the law of a step whose footprint
/// centre lies `ξ` (m) before the summit (`ξ = x_i − x_c`, the tread's
/// frame); `None` keeps `law`.
pub type Placement<L> = fn(&L, f64) -> Option<L>;

/// The offsets `ξ` (m) at which the checkpoint key probes placed laws.
pub(crate) const PLACEMENT_PROBES: [f64; 4] = [-0.03, -0.01, 0.01, 0.03];

impl<L: Clone> Road<L> {
    /// The law asperity `local` has at a step whose footprint is centred
    /// at `xc` (m): its [`Placement`]'s when the road has one, its own
    /// otherwise. For recounting a finished step's contacts.
    pub fn law_at(&self, local: usize, xc: f64) -> Cow<'_, L> {
        let law = &self.laws()[local];
        match self.placement() {
            Some(place) => {
                place(law, self.positions()[local][0] - xc).map_or(Cow::Borrowed(law), Cow::Owned)
            }
            None => Cow::Borrowed(law),
        }
    }
}

/// The placed laws of asperities `ids` at a step centred at `xc`, in the
/// same order (`None` where an asperity keeps its own); `None` when the
/// road has no placement.
pub(crate) fn placed_laws<L>(road: &Road<L>, ids: &[usize], xc: f64) -> Option<Vec<Option<L>>> {
    let place = road.placement()?;
    Some(
        ids.iter()
            .map(|&i| place(&road.laws()[i], road.positions()[i][0] - xc))
            .collect(),
    )
}

/// The laws a step's problem borrows: the placed ones where given, the
/// road's otherwise.
pub(crate) fn step_laws<'a, L>(
    road: &'a Road<L>,
    ids: &[usize],
    placed: Option<&'a [Option<L>]>,
) -> Vec<&'a L> {
    ids.iter()
        .enumerate()
        .map(|(a, &i)| {
            placed
                .and_then(|p| p[a].as_ref())
                .unwrap_or(&road.laws()[i])
        })
        .collect()
}

/// The diagnostics that hand out a step's problem borrow the road's laws:
/// a road whose laws are placed per step ([`crate::Placement`]) has none
/// to lend.
pub(crate) fn unplaced<L>(road: &Road<L>) -> Result<(), crate::RollingError> {
    match road.placement() {
        Some(_) => Err(crate::RollingError::InvalidInput(
            "a road whose laws are placed along the path has no single step problem to hand out \
             (roll it instead)"
                .into(),
        )),
        None => Ok(()),
    }
}

/// The probes of asperity `law`'s placed laws for the checkpoint key:
/// force and stiffness at the digest's depths, at each
/// [`PLACEMENT_PROBES`] offset.
pub(crate) fn probe_placed<L: ContactLaw>(place: Placement<L>, law: &L) -> Vec<f64> {
    let mut out = Vec::new();
    for xi in PLACEMENT_PROBES {
        let placed = place(law, xi);
        let law = placed.as_ref().unwrap_or(law);
        for (force, stiffness) in crate::RoadDigest::probe(law) {
            out.extend([force, stiffness]);
        }
    }
    out
}
