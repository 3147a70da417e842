//! Calibrated laws in rolling: one calibration per road, reused by every
//! step (docs/validation.md, "Calibrated laws in rolling").
//!
//! A rolling run on a texture selects, at footprint centre `(x_c, y_c)`,
//! the asperities with `|x − x_c| ≤ L/2 + m`, `|y − y_c| ≤ W/2 + m`
//! (`m` the tread's effective margin). Over the path `x_c ∈ [start, end]`,
//! `y_c = lateral`, only the asperities in the swept rectangle can ever be
//! selected ([`selectable`]); they are calibrated once, each cap by a
//! single-asperity BEM solve ([`super::Calibrator`], equal caps sharing one
//! table).
//!
//! The tables must cover the depths in use. At approach `δ0` (below the
//! road's reference plane `z_top`, the map's highest point,
//! [`crate::rolling::Road::top`]) asperity `i` is pressed at most
//! `δ0 − (z_top − z_i)` deep (the tread's profile `s ≥ 0` only lowers it),
//! so tabulating every cap to `margin × max δ0` covers the run (the
//! *bound*); `max δ0` is bounded by a Wilke run on a few evenly spaced
//! steps of the same path ([`approach_bound`]), and beyond its table a
//! calibrated law continues linearly, so a deeper step still solves. Under
//! a tyre the bound's deep knots are mostly never reached (the tread's
//! load sags the whole footprint): by default each table stops at the
//! cap's *estimated* depth, the bulk sag of the same coarse run taken off
//! ([`super::table_depth`]), and a whole run that presses a cap past its
//! table is repeated with that cap tabulated to the bound
//! ([`caps_past_tables`]).
//!
//! Invariants: the calibrated road keeps the Wilke road's positions,
//! heights and order for the asperities it keeps (`kept[i]` is asperity
//! `i`'s index in the texture road); the laws differ, so the rolling
//! checkpoint key (which probes each law) differs and a resume cannot mix
//! the rungs.

use std::time::{Duration, Instant};

use super::compare::APPROACH_MARGIN;
use super::table_depth::{BulkSag, TablePlan, estimated_lift, exclusion_radius, sagged_lifts};
use super::texture::{CapFallback, LawOf, OnCapFailure, StandIn, calibrated_laws_by};
use super::under_tread::{CalibrateUnder, CapShape, slope_nodes};
use super::{CacheCounts, CalibratedLaw, Calibrator, FidelityError, PathNode};
use crate::multipoint::AsperitySet;
use crate::rolling::{self, RollingConfig, StepStatus};
use crate::shared::{Material, Par, run_at};
use crate::texture::HeightMap;
use crate::texture_road::{TextureLaw, TextureRoad};

/// Steps of the Wilke run that bounds the approach: the path's ends and
/// evenly spaced steps between.
const BOUND_STEPS: usize = 9;

/// A texture road with calibrated laws for a rolling path.
#[derive(Debug)]
pub struct RollingCalibration {
    /// The selectable asperities with their calibrated laws, in the rolling
    /// frame (road order).
    pub set: AsperitySet<CalibratedLaw>,
    /// Index in the texture road of each asperity of `set`.
    pub kept: Vec<usize>,
    /// Largest approach (m) the tables cover, from the texture's highest
    /// summit (the plane the tables' depths are measured from).
    pub max_approach: f64,
    /// The largest bulk sag (m) taken off the tables' depths (0 for tables
    /// to the bound, [`super::table_depth`]).
    pub bulk_sag: f64,
    /// Tables solved, and found in the calibrator's caches.
    pub counts: CacheCounts,
    /// The caps whose calibration failed, each kept on its Wilke law.
    pub fallbacks: Vec<CapFallback>,
    /// Wall time of the approach bound and the calibration.
    pub time: Duration,
}

/// Indices of the `positions` (rolling frame, m) that `config`'s footprints
/// can select anywhere on its path.
pub fn selectable(positions: &[[f64; 2]], config: &RollingConfig) -> Vec<usize> {
    let (hx, hy) = config.tread.half_extents();
    let m = config.tread.effective_margin(config.margin);
    // The selection's own inclusive comparisons, with room for rounding.
    let slack = 1e-9 * (hx + hy);
    let (x0, x1) = (
        config.start.min(config.end) - hx - m - slack,
        config.start.max(config.end) + hx + m + slack,
    );
    let (y0, y1) = (
        config.lateral - hy - m - slack,
        config.lateral + hy + m + slack,
    );
    positions
        .iter()
        .enumerate()
        .filter(|(_, p)| p[0] >= x0 && p[0] <= x1 && p[1] >= y0 && p[1] <= y1)
        .map(|(i, _)| i)
        .collect()
}

/// For each asperity `indices[k]` of `road` (rolling frame), the smallest
/// gap (m) the tread's undeformed profile leaves it anywhere on
/// `config`'s path: the contact-point gap of [`crate::rolling::Tread`] at
/// the footprint centre nearest the asperity along the path (`ξ` clamped to
/// the path's ends; a tyre's gap grows with `|ξ|`), across at its fixed
/// lateral offset. Zero under a block or where the tread has no profile.
///
/// It bounds how deep the asperity can be pressed: `δ_i = δ0 − (z_top −
/// z_i) − s_i − u_i` with `s_i` at least this lift and the other contacts'
/// displacement `u_i ≥ 0`. The deformed slope (`ContactSlope::Deformed`)
/// can lower a gap below the profile's by `½ (σ_u² + 2 σ_s σ_u) R`, micrometres
/// for the slopes `σ_u` of neighbouring contacts, far inside the approach
/// margin the tables already carry.
pub fn profile_lifts(
    road: &rolling::Road<TextureLaw>,
    config: &RollingConfig,
    indices: &[usize],
) -> Vec<f64> {
    let (lo, hi) = (config.start.min(config.end), config.start.max(config.end));
    indices
        .iter()
        .map(|&i| {
            let [x, y] = road.positions()[i];
            let xi = x - x.clamp(lo, hi);
            config
                .tread
                .contact_gap(xi, y - config.lateral, road.summit_radius(i))
                .map_or(0.0, |(gap, _)| gap.max(0.0))
        })
        .collect()
}

/// The contacts of a rolling run on calibrated laws that were pressed past
/// their tables ([`contacts_past_tables`]). Beyond its last knot a law
/// continues linearly with its last slope: a force there is the table's
/// guess, not a BEM solve, so a run says how often it happened.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct PastTables {
    /// Steps with at least one such contact.
    pub steps: usize,
    /// Such contacts, counted over every step.
    pub contacts: usize,
    /// The largest contact force over the force at its table's last knot
    /// (0 when no contact went past its table).
    pub worst_ratio: f64,
}

impl PastTables {
    /// What a run's user is told when contacts went past their tables
    /// (`None` when none did).
    pub fn warning(&self) -> Option<String> {
        (self.contacts > 0).then(|| {
            format!(
                "at {} step(s) {} contact(s) were pressed past their calibration tables \
                 (up to {:.2}× the force at the last knot; the laws continue linearly there): \
                 the road's calibrated approach runs deeper than the tables reach",
                self.steps, self.contacts, self.worst_ratio
            )
        })
    }
}

/// Counts the contacts of `result` (a run on `road`) whose force exceeds
/// the force at their law's last tabulated depth. Tables to the bound
/// (`1.3 ×` the Wilke model's largest approach, less each cap's profile
/// lift) are passed only where the calibrated approach runs more than 30 %
/// deeper than the Wilke one's; tables to the estimated depth
/// ([`super::table_depth`]) may be passed, and a whole scenario run then
/// repeats itself with those caps tabulated to the bound: what is counted
/// after its last round is what still passed.
pub fn contacts_past_tables(
    road: &rolling::Road<CalibratedLaw>,
    result: &rolling::RollingResult,
) -> PastTables {
    let mut past = PastTables::default();
    let mut last_step = None;
    for (k, _, ratio) in passes(road, result) {
        past.contacts += 1;
        past.worst_ratio = past.worst_ratio.max(ratio);
        past.steps += usize::from(last_step != Some(k));
        last_step = Some(k);
    }
    past
}

/// The asperities (indices in `road`, sorted) that `result`, a run on
/// `road`, pressed past their tables at some step: those a repeated run
/// tabulates to the bound ([`TablePlan::deepened`]).
pub fn caps_past_tables(
    road: &rolling::Road<CalibratedLaw>,
    result: &rolling::RollingResult,
) -> Vec<usize> {
    let mut caps: Vec<usize> = passes(road, result).map(|(_, local, _)| local).collect();
    caps.sort_unstable();
    caps.dedup();
    caps
}

/// Each contact of `result` pressed past its table, in step order: `(step
/// index in the result, asperity index in road, force over the force at
/// the table's last knot)`.
fn passes<'a>(
    road: &'a rolling::Road<CalibratedLaw>,
    result: &'a rolling::RollingResult,
) -> impl Iterator<Item = (usize, usize, f64)> + 'a {
    result.steps.iter().enumerate().flat_map(move |(k, step)| {
        step.contact_ids
            .iter()
            .zip(&step.contact_forces)
            .filter_map(move |(&id, &force)| {
                let local = road.local_id(id)?;
                // A law placed along the path has the step's tables.
                let last = road.law_at(local, step.position).tabulated_force();
                (last > 0.0 && force > last * (1.0 + 1e-9)).then_some((k, local, force / last))
            })
    })
}

/// The largest approach (m) of `road` (Wilke laws) over nine
/// evenly spaced steps of `config`'s path.
///
/// # Errors
/// [`FidelityError::Rolling`] when the run fails; [`FidelityError::InvalidInput`]
/// when no step converges.
pub fn approach_bound(
    road: &rolling::Road<TextureLaw>,
    material: Material,
    config: &RollingConfig,
    par: Par,
) -> Result<f64, FidelityError> {
    Ok(coarse_run(road, material, config, par)?.0)
}

/// [`approach_bound`] and the coarse run that gives it.
fn coarse_run(
    road: &rolling::Road<TextureLaw>,
    material: Material,
    config: &RollingConfig,
    par: Par,
) -> Result<(f64, rolling::RollingResult), FidelityError> {
    let mut coarse = config.clone();
    coarse.sensors.clear();
    let span = (config.end - config.start).abs();
    coarse.step = config.step.max(span / (BOUND_STEPS - 1) as f64);
    let options = rolling::RunOptions {
        par,
        ..rolling::RunOptions::default()
    };
    let bound_of = |run: &rolling::RollingResult| {
        run.steps
            .iter()
            .filter(|s| s.status != StepStatus::Failed)
            .map(|s| s.approach)
            .fold(f64::NAN, f64::max)
    };
    // Under the deformed tread a cold step whose slopes do not settle is
    // kept on the profile's (`Recovery::ProfileSlope`): its approach is
    // within a percent of the deformed one's, and a table short of a
    // contact is deepened later.
    let run = rolling::roll(road, material, &coarse, &options)?;
    let bound = bound_of(&run);
    if bound.is_finite() && bound > 0.0 {
        Ok((bound, run))
    } else {
        let failed = run
            .steps
            .iter()
            .filter(|s| s.status == StepStatus::Failed)
            .count();
        Err(FidelityError::invalid(
            "rolling approach bound",
            format!(
                "{failed} of the {} Wilke steps from x = {} m to {} m that bound the \
                 calibrated tables failed, the others carried no load",
                run.steps.len(),
                config.start,
                config.end
            ),
            "a converged Wilke step with a positive approach on the path: the tables \
             cannot be sized (with [model] fidelity = \"wilke\" the run records each \
             failed step)",
        ))
    }
}

/// [`calibrate_rolling_road_under`] a flat punch, tables to their
/// estimated depth ([`TablePlan::new`]).
///
/// # Errors
/// As [`calibrate_rolling_road_under`].
pub fn calibrate_rolling_road(
    road: &TextureRoad,
    wilke: &rolling::Road<TextureLaw>,
    map: &HeightMap,
    config: &RollingConfig,
    calibrator: &Calibrator,
    par: Par,
) -> Result<RollingCalibration, FidelityError> {
    calibrate_rolling_road_under(
        road,
        wilke,
        map,
        config,
        calibrator,
        par,
        &TablePlan::new(CalibrateUnder::Flat),
    )
}

/// Calibrates the asperities of `road` that `config`'s path can select,
/// each cap under a flat punch or the tread's local shape (`plan.under`,
/// [`super::under_tread`]: an asperity may then be raised so that the
/// model's gap is its cap's first contact), each table as deep as `plan`
/// says ([`super::table_depth`]: the bound, or the bound less the tread's
/// bulk sag).
/// `wilke` is the same road in the rolling frame with its Wilke laws (and
/// summit radii, as the run uses them): it bounds the approach. `map` is the
/// segmented height map. The calibration runs on `par`'s threads.
///
/// # Errors
/// Those of [`approach_bound`] and of the calibration
/// ([`super::calibrated_set`]).
pub fn calibrate_rolling_road_under(
    road: &TextureRoad,
    wilke: &rolling::Road<TextureLaw>,
    map: &HeightMap,
    config: &RollingConfig,
    calibrator: &Calibrator,
    par: Par,
    plan: &TablePlan,
) -> Result<RollingCalibration, FidelityError> {
    let law_of: &LawOf<'_> = &|_, patch, depth| calibrator.law(patch, depth);
    calibrate_rolling_road_by((road, wilke, map), config, (calibrator, law_of), par, plan)
}

/// [`calibrate_rolling_road_under`] with each cap's table from `law_of`
/// (the calibrator sizes the stand-ins and counts its caches).
fn calibrate_rolling_road_by(
    (road, wilke, map): (&TextureRoad, &rolling::Road<TextureLaw>, &HeightMap),
    config: &RollingConfig,
    (calibrator, law_of): (&Calibrator, &LawOf<'_>),
    par: Par,
    plan: &TablePlan,
) -> Result<RollingCalibration, FidelityError> {
    plan.validate()?;
    let clock = Instant::now();
    let under = plan.under;
    let material = *calibrator.material();
    let (bound, coarse) = coarse_run(wilke, material, config, par)?;
    // The bound is measured from the rolling road's reference plane (a
    // texture's highest point, `Road::with_top`), the tables' depths from
    // the texture's highest summit, which a fitted vertex may raise above
    // that plane: the tables reach as much deeper.
    let max_approach = APPROACH_MARGIN * bound + (road.set.top() - wilke.top()).max(0.0);
    let kept = selectable(wilke.positions(), config);
    if kept.is_empty() {
        return Err(FidelityError::invalid(
            "rolling path",
            format!("x from {} m to {} m", config.start, config.end),
            "a path whose footprints cover at least one asperity",
        ));
    }
    let mut lifts = profile_lifts(wilke, config, &kept);
    let rho = exclusion_radius(config, kept.len());
    let bulk = (!plan.is_bound())
        .then(|| BulkSag::from_steps(wilke, config, &coarse, rho, material.boussinesq_factor()))
        .flatten();
    if let Some(bulk) = &bulk {
        let sagged = sagged_lifts(wilke, config, &kept, &lifts, bulk, plan.sag);
        let top = wilke.top();
        for (n, (lift, s)) in lifts.iter_mut().zip(sagged).enumerate() {
            if plan.deepen.binary_search(&n).is_err() {
                let headroom = top - wilke.heights()[kept[n]];
                *lift = estimated_lift(s, headroom, *lift, APPROACH_MARGIN);
            }
        }
    }
    let stand_in = StandIn::of(calibrator, map, OnCapFailure::WilkeLaw);
    let calibrate = |shape: &CapShape| {
        run_at(par, || {
            calibrated_laws_by(
                road,
                map,
                max_approach,
                law_of,
                (&kept, &lifts),
                shape,
                stand_in,
            )
        })
    };
    let mut fallbacks = Vec::new();
    let laws = match under {
        CalibrateUnder::TreadSlope => {
            let nodes = slope_nodes(&config.tread, config.margin);
            let mut by_node = Vec::with_capacity(nodes.len());
            for &xi in &nodes {
                let laws = calibrate(&cap_shape(wilke, config, &kept, under, xi))?;
                fallbacks.extend(laws.fallbacks);
                by_node.push(laws.laws);
            }
            // A cap that failed at several nodes is one failure.
            fallbacks.sort_by_key(|f: &CapFallback| f.id);
            fallbacks.dedup_by_key(|f| f.id);
            laws_along_path(wilke, config, &kept, &nodes, by_node)?
        }
        _ => {
            let laws = calibrate(&cap_shape(wilke, config, &kept, under, 0.0))?;
            fallbacks = laws.fallbacks;
            laws.laws
        }
    };
    // The outputs' ids and frame: the index among the kept asperities, the
    // rolling frame.
    for f in &mut fallbacks {
        f.summit = wilke.positions()[kept[f.id]];
    }
    let positions = kept.iter().map(|&i| wilke.positions()[i]).collect();
    let heights = kept
        .iter()
        .zip(&laws)
        .map(|(&i, (_, lift))| wilke.heights()[i] + lift)
        .collect();
    let laws = laws.into_iter().map(|(law, _)| law).collect();
    let set = AsperitySet::new(positions, heights, laws)?;
    Ok(RollingCalibration {
        set,
        kept,
        max_approach,
        bulk_sag: bulk.as_ref().map_or(0.0, BulkSag::max),
        counts: calibrator.counts(),
        fallbacks,
        time: clock.elapsed(),
    })
}

/// Each kept asperity's law along the path from its laws at `nodes`
/// (`by_node[k][n]`: node `k`, asperity `kept[n]`, with its lift): the
/// asperity is lifted by its largest lift and each node's table delayed by
/// what it lifts less ([`super::PathNode`]).
fn laws_along_path(
    wilke: &rolling::Road<TextureLaw>,
    config: &RollingConfig,
    kept: &[usize],
    nodes: &[f64],
    by_node: Vec<Vec<(CalibratedLaw, f64)>>,
) -> Result<Vec<(CalibratedLaw, f64)>, FidelityError> {
    let mut columns: Vec<_> = by_node.into_iter().map(Vec::into_iter).collect();
    kept.iter()
        .map(|&i| {
            let row: Vec<(CalibratedLaw, f64)> =
                columns.iter_mut().filter_map(Iterator::next).collect();
            let lift = row.iter().map(|r| r.1).fold(0.0, f64::max);
            let eta = wilke.positions()[i][1] - config.lateral;
            let radius = wilke.summit_radius(i);
            let path = nodes
                .iter()
                .zip(row)
                .map(|(&xi, (law, l))| PathNode {
                    xi,
                    law,
                    offset: config
                        .tread
                        .contact_gap(xi, eta, radius)
                        .map_or([0.0, 0.0], |(_, o)| o),
                    delay: lift - l,
                })
                .collect();
            Ok((CalibratedLaw::along_path(path)?, lift))
        })
        .collect()
}

/// The rolling road on a calibrated `set` with its summit `radii`, its
/// approach measured from `top` (m; the map's highest point,
/// [`crate::texture_road::TextureRoad::top`]): when
/// its laws are calibrated along the path
/// ([`CalibrateUnder::TreadSlope`]), each step places them at its own
/// offsets ([`CalibratedLaw::at_offset`], [`crate::rolling::Placement`]).
///
/// # Errors
/// Those of [`rolling::Road::with_summit_radii`].
pub fn calibrated_rolling_road(
    set: AsperitySet<CalibratedLaw>,
    radii: Vec<f64>,
    top: f64,
) -> Result<rolling::Road<CalibratedLaw>, rolling::RollingError> {
    let along = set.laws().iter().any(CalibratedLaw::is_along_path);
    let road = crate::texture_road::rolling_road(set, radii, top)?;
    if along {
        road.with_placement(CalibratedLaw::at_offset)
    } else {
        Ok(road)
    }
}

/// Where each of `wilke`'s asperities lies under `config`'s tread (by the
/// road's index), for `under`, at offset `xi` (m) from the footprint's
/// centre along the path. Lifts are bounded by the highest kept summit,
/// the calibrated road's reference for the approach.
fn cap_shape(
    wilke: &rolling::Road<TextureLaw>,
    config: &RollingConfig,
    kept: &[usize],
    under: CalibrateUnder,
    xi: f64,
) -> CapShape {
    match under {
        CalibrateUnder::Flat => CapShape::Flat,
        CalibrateUnder::Tread | CalibrateUnder::TreadSlope => {
            let top = kept
                .iter()
                .map(|&i| wilke.heights()[i])
                .fold(f64::NEG_INFINITY, f64::max);
            let n = wilke.len();
            CapShape::Tread {
                tread: config.tread,
                xi,
                eta: (0..n)
                    .map(|i| wilke.positions()[i][1] - config.lateral)
                    .collect(),
                radius: (0..n).map(|i| wilke.summit_radius(i)).collect(),
                headroom: (0..n).map(|i| top - wilke.heights()[i]).collect(),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::rolling::{RollingControl, Tread};
    use crate::texture_road::{TextureRoadOptions, texture_road};

    /// Three paraboloid caps (R = 5 mm) at x = 6, 18, 30 mm on a 36 × 12 mm
    /// map; a block selects the first two.
    #[test]
    fn a_rolling_fallback_is_named_by_its_road_npz_id_in_the_rolling_frame() {
        let summits = [(6e-3, 1.5e-3), (18e-3, 1.45e-3), (30e-3, 1.5e-3)];
        let map = HeightMap::from_fn(361, 121, 1e-4, 1e-4, move |x, y| {
            summits
                .iter()
                .map(|&(cx, top)| top - ((x - cx).powi(2) + (y - 6e-3).powi(2)) / 1e-2)
                .fold(0.0, f64::max)
        })
        .expect("map");
        let material = Material::new(6.54e6, 0.5).expect("material");
        let road =
            texture_road(&map, material, &TextureRoadOptions::new(0.1e-3, 1e-6)).expect("road");
        let wilke = rolling::Road::new(road.set.clone().translated([0.0, -6e-3]).expect("set"))
            .with_summit_radii(road.summit_radii())
            .expect("radii");
        let block = Tread::Block {
            length: 14e-3,
            width: 10e-3,
        };
        let config =
            RollingConfig::new(block, [11e-3, 13e-3, 1e-3], 10.0, RollingControl::Load(3.0));
        let calibrator = Calibrator::new(material, super::super::CalibrationOptions::default());
        // The cap at x = 18 mm fails, whatever its place in the road.
        let failing = road
            .set
            .positions()
            .iter()
            .position(|p| (p[0] - 18e-3).abs() < 1e-4)
            .expect("the middle cap");
        let law_of: &LawOf<'_> = &|i, patch, depth| {
            if i == failing {
                Err(FidelityError::invalid(
                    "BEM solve",
                    "injected",
                    "a converged solve",
                ))
            } else {
                calibrator.law(patch, depth)
            }
        };
        let calibrated = calibrate_rolling_road_by(
            (&road, &wilke, &map),
            &config,
            (&calibrator, law_of),
            Par::Seq,
            &TablePlan::bound(CalibrateUnder::Flat),
        )
        .expect("one cap stood in");
        assert_eq!(calibrated.kept.len(), 2);
        assert_eq!(calibrated.fallbacks.len(), 1);
        let f = &calibrated.fallbacks[0];
        // Its id among the kept asperities (road.npz), its summit as the
        // rolling set has it (y from the path's mid-width).
        let id = calibrated
            .kept
            .iter()
            .position(|&i| i == failing)
            .expect("kept");
        assert_eq!(f.id, id);
        assert_eq!(f.summit, calibrated.set.positions()[id]);
        assert!((f.summit[1]).abs() < 1e-3, "{:?}", f.summit);
        assert!(f.reason.contains("injected"), "{}", f.reason);
    }
}
