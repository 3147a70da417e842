//! A calibrated law along the path: one table per longitudinal offset `ξ`
//! of the cap from the footprint's centre, blended at each step's `ξ`
//! (docs/validation.md, "Caps calibrated along the tread's slope").
//!
//! Under a tyre the tread's longitudinal slope over a cap is `ξ/Rx`; a cap
//! with a long flat top is pressed at one end of it or the other as `ξ`
//! changes sign. Each node `k` is the cap calibrated under the tread at
//! `ξ_k` ([`super::super::under_tread`]): a table `T_k`, its field, the
//! model's contact-point offset `o_k` there (which the field's origin had
//! taken off) and a delay `d_k ≥ 0`, how much deeper than the road's gap
//! the node's first contact lies (nodes may lift their asperity by
//! different amounts; the road keeps the largest lift). At offset `ξ`
//! between nodes `k` and `k + 1`, `t = (ξ − ξ_k)/(ξ_{k+1} − ξ_k)`:
//!
//! ```text
//! d(ξ)    = (1 − t) d_k + t d_{k+1}
//! P(δ; ξ) = (1 − t) T_k(δ − d(ξ)) + t T_{k+1}(δ − d(ξ))
//! A(δ; ξ) = (1 − t) A_k(δ − d(ξ)) + t A_{k+1}(δ − d(ξ))
//! field   = each node's unit field weighted by its share of P,
//!           origin moved by o_k − o(ξ), o(ξ) linear in ξ through the nodes
//! ```
//!
//! (the first contact `d(ξ)` moves between the nodes' own; `t` clamped to
//! `[0, 1]` beyond the end nodes, `o(ξ)` extrapolated: the
//! model's offset `−ξ R/(R + Rx)` is linear in `ξ`, so the field lands on
//! the summit's own frame at every step.)
//!
//! Invariants: a blend of laws that keep the [`ContactLaw`] contract keeps
//! it (`P = k = 0` for `δ ≤ 0` as `d_k ≥ 0`, `P` continuous and
//! non-decreasing, `k = dP/dδ`); at a node's `ξ` the placed law is that
//! node's; a law with one node is that node's law everywhere (its origin
//! moved with the offset).

use std::sync::Arc;

use tyreroad_contact_law::{ContactLaw, LawPoint, LocalContact, PressureProfile};

use super::{CalibratedLaw, CalibratedTable};
use crate::fidelity::FidelityError;
use crate::fidelity::field::UnitField;

/// One offset's calibration of a cap along the path.
#[derive(Clone, Debug)]
pub struct PathNode {
    /// The cap's offset from the footprint's centre along the path (m).
    pub xi: f64,
    /// The cap's law calibrated under the tread there (a plain law: its
    /// table and its field's origin, the model's offset `offset` taken off).
    pub law: CalibratedLaw,
    /// The model's contact-point offset from the summit at `xi` (m).
    pub offset: [f64; 2],
    /// How much deeper than the road's gap this node's table starts (m, ≥ 0).
    pub delay: f64,
}

/// What a law along the path holds.
#[derive(Clone, Debug)]
pub(super) enum Along {
    /// The nodes, by increasing `ξ` (a road's law: placed per step).
    Nodes(Arc<[PathNode]>),
    /// The two nodes around one `ξ` with their weights (a placed law).
    Blend([Part; 2]),
}

/// One weighted table of a blend.
#[derive(Clone, Debug)]
pub(super) struct Part {
    table: Arc<CalibratedTable>,
    origin: [f64; 2],
    delay: f64,
    weight: f64,
}

impl Part {
    /// This part's weighted force and stiffness at the road's `depth`.
    fn force(&self, depth: f64) -> (f64, f64) {
        let d = depth - self.delay;
        if !(d > 0.0 && self.weight > 0.0) {
            return (0.0, 0.0);
        }
        let (f, k) = self.table.force_at(d);
        (self.weight * f.max(0.0), self.weight * k.max(0.0))
    }

    /// The depth past which this part's table extrapolates.
    fn end(&self) -> f64 {
        self.table.max_depth() + self.delay
    }
}

/// The blend of `nodes` at `xi` (module docs).
fn blend(nodes: &[PathNode], xi: f64) -> [Part; 2] {
    let n = nodes.len();
    let j = if n < 2 {
        0
    } else {
        (nodes.partition_point(|p| p.xi <= xi).max(1) - 1).min(n - 2)
    };
    let (a, b) = (&nodes[j], &nodes[(j + 1).min(n - 1)]);
    let t = if n < 2 {
        0.0
    } else {
        (xi - a.xi) / (b.xi - a.xi)
    };
    let offset = [
        a.offset[0] + t * (b.offset[0] - a.offset[0]),
        a.offset[1] + t * (b.offset[1] - a.offset[1]),
    ];
    let w = t.clamp(0.0, 1.0);
    // The first contact moves with ξ between the nodes' own: both tables
    // are read from the blended one, so that the two share the load as
    // their weights say from the first contact on.
    let delay = (1.0 - w) * a.delay + w * b.delay;
    let part = |p: &PathNode, weight: f64| Part {
        table: Arc::clone(&p.law.table),
        origin: [
            p.law.origin[0] + p.offset[0] - offset[0],
            p.law.origin[1] + p.offset[1] - offset[1],
        ],
        delay,
        weight,
    };
    [part(a, 1.0 - w), part(b, w)]
}

impl CalibratedLaw {
    /// A cap's law along the path from its `nodes` (module docs); the
    /// road's law until a step places it ([`Self::at_offset`]), the blend at
    /// `ξ = 0` when evaluated unplaced.
    ///
    /// # Errors
    /// [`FidelityError::InvalidInput`] without nodes, for offsets that are
    /// not finite and strictly increasing, a delay that is not finite and
    /// ≥ 0, a node that is itself a law along the path, or nodes of which
    /// some have fields and others not.
    pub fn along_path(nodes: Vec<PathNode>) -> Result<Self, FidelityError> {
        let bad = |value: String, expected: &str| {
            Err(FidelityError::invalid(
                "law along the path",
                value,
                expected,
            ))
        };
        if nodes.is_empty() {
            return bad("no node".into(), "at least one node");
        }
        if !nodes.windows(2).all(|w| w[0].xi < w[1].xi) || !nodes.iter().all(|p| p.xi.is_finite()) {
            return bad(
                format!(
                    "offsets {:?}",
                    nodes.iter().map(|p| p.xi).collect::<Vec<_>>()
                ),
                "finite offsets, strictly increasing",
            );
        }
        if let Some(p) = nodes
            .iter()
            .find(|p| !(p.delay.is_finite() && p.delay >= 0.0))
        {
            return bad(format!("delay {} m", p.delay), "finite and >= 0 m");
        }
        if nodes.iter().any(|p| p.law.along.is_some()) {
            return bad(
                "a node along the path".into(),
                "plain calibrated laws as nodes",
            );
        }
        let fields = nodes
            .iter()
            .filter(|p| p.law.table.field().is_some())
            .count();
        if fields != 0 && fields != nodes.len() {
            return bad(
                format!("{fields} of {} nodes with fields", nodes.len()),
                "fields on every node or none",
            );
        }
        let centre = nodes
            .iter()
            .min_by(|a, b| a.xi.abs().total_cmp(&b.xi.abs()))
            .map(|p| p.law.clone())
            .unwrap_or_else(|| nodes[0].law.clone());
        Ok(Self {
            along: Some(Along::Nodes(nodes.into())),
            ..centre
        })
    }

    /// The law of a step at which this cap lies `xi` (m) from the
    /// footprint's centre along the path; `None` for a law that does not
    /// move with the footprint. A [`crate::rolling::Placement`].
    pub fn at_offset(&self, xi: f64) -> Option<Self> {
        let Some(Along::Nodes(nodes)) = &self.along else {
            return None;
        };
        let parts = blend(nodes, xi);
        let main = if parts[1].weight > parts[0].weight {
            1
        } else {
            0
        };
        Some(Self {
            table: Arc::clone(&parts[main].table),
            origin: parts[main].origin,
            along: Some(Along::Blend(parts)),
            body: self.body,
        })
    }

    /// Whether this law moves with the footprint (built by
    /// [`Self::along_path`], not yet placed).
    pub fn is_along_path(&self) -> bool {
        matches!(self.along, Some(Along::Nodes(_)))
    }

    /// The force (N) past which some table of this law extrapolates (its
    /// own table's last knot for a plain law).
    pub fn tabulated_force(&self) -> f64 {
        let end = self.with_parts(|parts| {
            parts
                .iter()
                .filter(|p| p.weight > 0.0)
                .map(Part::end)
                .fold(f64::INFINITY, f64::min)
        });
        match end {
            Some(end) => self.evaluate(end).force,
            None => self.table.knots().last().map_or(0.0, |(_, f, _)| f),
        }
    }

    /// `f` of the weighted tables this law blends (the blend at `ξ = 0`
    /// for an unplaced law along the path); `None` for a plain law.
    pub(super) fn with_parts<R>(&self, f: impl FnOnce(&[Part; 2]) -> R) -> Option<R> {
        match self.along.as_ref()? {
            Along::Nodes(nodes) => Some(f(&blend(nodes, 0.0))),
            Along::Blend(parts) => Some(f(parts)),
        }
    }
}

/// `P` and `k` of a blend at `depth`.
pub(super) fn evaluate(parts: &[Part; 2], depth: f64) -> LawPoint {
    let (a, b) = (parts[0].force(depth), parts[1].force(depth));
    LawPoint {
        force: a.0 + b.0,
        stiffness: a.1 + b.1,
    }
}

/// The blend's contact at `depth` carrying `force`: the weighted areas.
pub(super) fn local_contact(parts: &[Part; 2], force: f64, depth: f64) -> LocalContact {
    if !(force > 0.0 && depth > 0.0) {
        return LocalContact::NONE;
    }
    let area: f64 = parts
        .iter()
        .filter(|p| p.weight > 0.0 && depth > p.delay)
        .map(|p| p.weight * p.table.area_at(depth - p.delay).max(0.0))
        .sum();
    LocalContact {
        force,
        radius: (area / std::f64::consts::PI).sqrt(),
        profile: PressureProfile::Hertz,
    }
}

/// The blend's unit field at `depth`: each part's field weighted by its
/// share of the force (by its weight where neither carries any yet).
pub(super) fn unit_field(parts: &[Part; 2], depth: f64) -> Option<UnitField> {
    let forces = [parts[0].force(depth).0, parts[1].force(depth).0];
    let total: f64 = forces.iter().sum();
    let mut out = UnitField::new();
    for (p, f) in parts.iter().zip(forces) {
        let share = if total > 0.0 { f / total } else { p.weight };
        if !(share > 0.0) {
            continue;
        }
        let field = p.table.unit_field(depth - p.delay, p.origin)?;
        out.extend(field.into_iter().map(|(x, w)| (x, w * share)));
    }
    Some(out)
}

/// The depth at which the blend carries `force` (bisection on its
/// monotone force), 0 for a force ≤ 0, NaN beyond a metre.
pub(super) fn depth_for(parts: &[Part; 2], force: f64) -> f64 {
    let start = parts.iter().map(Part::end).fold(0.0, f64::max);
    super::depth_for_force(force, start, |d| evaluate(parts, d).force)
}
