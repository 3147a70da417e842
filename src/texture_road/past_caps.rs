//! Contacts pressed past the depth their caps are tabulated to
//! ([`super::TextureRoad::cap_depths`]): named per asperity in a static run
//! ([`pressed_past_caps`]), counted over the steps of a rolling run
//! ([`PastCapTally`], whole records or streamed ones).
//!
//! Past its cap depth an asperity's whole basin is in contact and its law
//! goes on with vertical walls, an extrapolation rather than the road's
//! shape: a spike pressed through to the flat around it is the usual case.
//! A law is monotone in the depth, so in a rolling record (forces, not
//! depths) a force above the law's force at its cap depth is a depth past
//! the cap.

use crate::asperity::CapGeometry;
use crate::contact_law::{ContactLaw, PotentialLaw};
use crate::rolling::{Road, StepRecord};

/// An asperity pressed deeper than its cap is tabulated
/// ([`super::TextureRoad::cap_depths`]): its whole basin is in contact, and
/// its law's force there is a vertical-wall extrapolation, not the road's
/// shape (a spike on a flat map, pressed through to the flat, is one).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PastCap {
    /// Asperity index (set order).
    pub index: usize,
    /// Its interpenetration `δ_i` (m).
    pub depth: f64,
    /// The depth its cap is tabulated to (m).
    pub cap_depth: f64,
}

impl std::fmt::Display for PastCap {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "pressed {:.3} mm into a cap tabulated to {:.3} mm: its whole basin is in \
             contact, and past that depth its law is an extrapolation (vertical walls), \
             not the road's shape",
            self.depth * 1e3,
            self.cap_depth * 1e3
        )
    }
}

/// The asperities whose interpenetration `depths[i]` (m) exceeds the
/// depth `cap_depths[i]` their caps are tabulated to (both in set order).
pub fn pressed_past_caps(cap_depths: &[f64], depths: &[f64]) -> Vec<PastCap> {
    cap_depths
        .iter()
        .zip(depths)
        .enumerate()
        .filter(|&(_, (&cap_depth, &depth))| depth > cap_depth * (1.0 + 1e-9))
        .map(|(index, (&cap_depth, &depth))| PastCap {
            index,
            depth,
            cap_depth,
        })
        .collect()
}

/// The contacts of a rolling run on a texture road's Wilke laws pressed
/// past their caps, counted record by record (module docs): the steps, the
/// contacts over all steps, and the largest force over the bound.
///
/// `stiffening` bounds a contact's force over its law's at the same depth:
/// 1 for an elastic tread of the laws' modulus; `E₀/E_ref` for a
/// viscoelastic one (its force `(E_eff/E_ref) P(δ) + h` with `E_eff ≤ E₀`
/// and the memory `h ≤ 0`, docs/viscoelastic.md), whose contacts above
/// that bound are certainly past their caps and are counted "or more".
#[derive(Clone, Debug)]
pub struct PastCapTally {
    /// Each asperity's bound, by its id on the whole road (NaN: not on
    /// this road or window).
    at_caps: Vec<f64>,
    stiffening: f64,
    shape: PastShape,
    steps: usize,
    contacts: usize,
    worst: f64,
}

/// What the depth a contact was pressed past is, for the warning's words.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum PastShape {
    /// A texture cap's table ([`super::TextureRoad::cap_depths`]).
    Caps,
    /// A ball's equator: past it its law goes on as a cylinder.
    Equators,
}

impl PastCapTally {
    /// A tally for records rolled on `road` (a whole road or a window of
    /// one), each law's force at the depth its shape is described to
    /// ([`CapGeometry::max_depth`]: a cap's table, a ball's equator)
    /// computed once.
    pub fn new<G: CapGeometry>(
        road: &Road<PotentialLaw<G>>,
        stiffening: f64,
        shape: PastShape,
    ) -> Self {
        let mut at_depth = vec![f64::NAN; road.global_len()];
        for (local, law) in road.laws().iter().enumerate() {
            if let Some(slot) = at_depth.get_mut(road.global_id(local)) {
                *slot = law.force(law.geometry().max_depth());
            }
        }
        Self::from_bounds(at_depth, stiffening, shape)
    }

    /// A tally of balls: `radii[id]` each asperity's ball radius (m; NaN
    /// for another shape, which gets no bound) and `laws[id]` its law,
    /// bounded by its force at the equator.
    pub fn at_equators<L: ContactLaw>(radii: &[f64], laws: &[L], stiffening: f64) -> Self {
        let at_equator = radii
            .iter()
            .zip(laws)
            .map(|(&r, law)| {
                if r.is_finite() {
                    law.force(r)
                } else {
                    f64::NAN
                }
            })
            .collect();
        Self::from_bounds(at_equator, stiffening, PastShape::Equators)
    }

    /// A tally of the bounds `at_depth[id]`: each asperity's law force at
    /// the depth its shape is described to (N; NaN or 0: no bound), by its
    /// id on the whole road.
    pub fn from_bounds(mut at_depth: Vec<f64>, stiffening: f64, shape: PastShape) -> Self {
        let stiffening = stiffening.max(1.0);
        at_depth.iter_mut().for_each(|f| *f *= stiffening);
        Self {
            at_caps: at_depth,
            stiffening,
            shape,
            steps: 0,
            contacts: 0,
            worst: 0.0,
        }
    }

    /// Counts one step's contacts.
    pub fn count(&mut self, step: &StepRecord) {
        let mut here = 0;
        for (&id, &force) in step.contact_ids.iter().zip(&step.contact_forces) {
            let Some(&at_cap) = self.at_caps.get(id) else {
                continue;
            };
            if at_cap > 0.0 && force > at_cap * (1.0 + 1e-9) {
                here += 1;
                self.worst = self.worst.max(force / at_cap);
            }
        }
        self.contacts += here;
        self.steps += usize::from(here > 0);
    }

    /// [`Self::warning`] once every step of `steps` is counted (whole
    /// records).
    pub fn warning_over(mut self, steps: &[StepRecord]) -> Option<String> {
        for step in steps {
            self.count(step);
        }
        self.warning()
    }

    /// What the run is told (`None` when no contact was pressed past its
    /// cap).
    pub fn warning(&self) -> Option<String> {
        let (or_more, there) = if self.stiffening > 1.0 {
            (
                " or more",
                "the force the tread's instantaneous modulus gives there",
            )
        } else {
            ("", "the force there")
        };
        let (steps, contacts, worst) = (self.steps, self.contacts, self.worst);
        let (past, after) = match self.shape {
            PastShape::Caps => (
                "the depth their caps are tabulated to",
                "their whole basins were in contact, and past that depth their laws are an \
                 extrapolation (vertical walls), not the road's shape (a spike pressed through \
                 to a flat around it?)",
            ),
            PastShape::Equators => (
                "their balls' equators",
                "past it a ball's law goes on as a cylinder, and Hertz's small-contact picture \
                 ended well before: no ball road carries this (a lighter load or a smaller \
                 approach, or larger summits?)",
            ),
        };
        (contacts > 0).then(|| {
            format!(
                "at {steps} step(s){or_more}, {contacts} contact(s){or_more} were pressed past \
                 {past} (up to {worst:.2}× {there}): {after}"
            )
        })
    }
}
