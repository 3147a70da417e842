//! Calibrated laws for the asperities of a segmented texture.

use rayon::prelude::*;

use super::under_tread::CapShape;
use super::{CalibratedLaw, Calibrator, CapPatch, FidelityError};
use crate::multipoint::AsperitySet;
use crate::texture::{Asperity, HeightMap};
use crate::texture_road::TextureRoad;

/// Cells kept around the cells that can touch: the contact never reaches
/// the window's border inside the depth range, so the patch holds it whole.
const MARGIN_CELLS: usize = 3;

/// The patch of asperity `a` for depths up to `max_depth` (m, from its
/// summit): the bounding box of the basin's cells within `max_depth` of the
/// summit, widened by a margin; the basin's own heights where they are
/// within `max_depth` of the summit, a floor below any reachable depth
/// elsewhere (deeper cells, neighbouring basins, invalid points), so the
/// solve sees this cap alone.
///
/// # Errors
/// [`FidelityError::InvalidInput`] if `max_depth` is not finite and > 0 or
/// the asperity has no valid cell within it.
pub fn cap_patch(map: &HeightMap, a: &Asperity, max_depth: f64) -> Result<CapPatch, FidelityError> {
    if !(max_depth.is_finite() && max_depth > 0.0) {
        return Err(FidelityError::invalid(
            "calibration depth",
            max_depth,
            "finite and > 0 m",
        ));
    }
    let (nx, ny) = (map.nx(), map.ny());
    let reach = a.summit_height - max_depth;
    let (mut i0, mut j0, mut i1, mut j1) = (usize::MAX, usize::MAX, 0, 0);
    for &c in &a.cells {
        if map.valid()[c] && map.heights()[c] >= reach {
            let (i, j) = (c % nx, c / nx);
            (i0, j0, i1, j1) = (i0.min(i), j0.min(j), i1.max(i), j1.max(j));
        }
    }
    if i0 == usize::MAX {
        return Err(FidelityError::invalid(
            "asperity",
            format!("summit at {:?}", a.summit),
            "a valid cell within the calibration depth",
        ));
    }
    let (i0, j0) = (
        i0.saturating_sub(MARGIN_CELLS),
        j0.saturating_sub(MARGIN_CELLS),
    );
    let (i1, j1) = (
        (i1 + MARGIN_CELLS).min(nx - 1),
        (j1 + MARGIN_CELLS).min(ny - 1),
    );
    let (pnx, pny) = ((i1 - i0 + 1).max(3), (j1 - j0 + 1).max(3));
    let floor = -(1.5 * max_depth + map.dx().max(map.dy()));
    let mut inside = vec![false; nx * ny];
    for &c in &a.cells {
        inside[c] = map.valid()[c];
    }
    let heights = (0..pnx * pny)
        .map(|k| {
            let (i, j) = (i0 + k % pnx, j0 + k / pnx);
            if i >= nx || j >= ny {
                return floor;
            }
            let c = map.index(i, j);
            let z = map.heights()[c] - a.summit_height;
            // A cell deeper than the range can never touch within it: the
            // floor there changes no solve, and keeps equal caps equal
            // whatever the segmentation did with the ground around them.
            if inside[c] && z >= -max_depth {
                z.min(0.0)
            } else {
                floor
            }
        })
        .collect();
    Ok(CapPatch {
        nx: pnx,
        ny: pny,
        dx: map.dx(),
        dy: map.dy(),
        heights,
        origin: [
            i0 as f64 * map.dx() - a.summit[0],
            j0 as f64 * map.dy() - a.summit[1],
        ],
    })
}

/// The road's asperities with calibrated laws (same positions, heights and
/// order as `road.set`), for approaches up to `max_approach` (m, from the
/// highest summit): asperity `i` is tabulated to
/// `max(max_approach − (top − z_i), max_approach / 10)`, the depth it
/// reaches at that approach (with a floor so that low asperities still get
/// a range), and at least twice the height of its fitted summit above its
/// highest cell (so that the range holds a cell). Caps are calibrated in
/// parallel on rayon's current pool. Every cap must calibrate: a
/// comparison of rungs wants the rung or an error
/// ([`calibrated_set_or_wilke`] lets a cap that fails keep its Wilke law).
///
/// # Errors
/// [`FidelityError::InvalidInput`] if `map` is not the segmented map or
/// `max_approach` is not finite and > 0; the first calibration error.
pub fn calibrated_set(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
) -> Result<AsperitySet<CalibratedLaw>, FidelityError> {
    calibrated_set_on(road, map, max_approach, calibrator, OnCapFailure::Abort).map(|(set, _)| set)
}

/// [`calibrated_set`], where a cap whose calibration fails keeps its Wilke
/// law instead ([`CapFallback`], one per such cap, in road order): one bad
/// cap is that cap's failure, not the run's.
///
/// # Errors
/// As [`calibrated_set`] for the inputs; the first calibration error if
/// every cap failed, or if the disk cache cannot be written.
pub fn calibrated_set_or_wilke(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
) -> Result<(AsperitySet<CalibratedLaw>, Vec<CapFallback>), FidelityError> {
    calibrated_set_on(road, map, max_approach, calibrator, OnCapFailure::WilkeLaw)
}

fn calibrated_set_on(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
    on_failure: OnCapFailure,
) -> Result<(AsperitySet<CalibratedLaw>, Vec<CapFallback>), FidelityError> {
    let all: Vec<usize> = (0..road.len()).collect();
    // Tiles of one plateau as one body (super::joint); the rest alone.
    let mut bodies =
        super::joint::body_laws(road, map, max_approach, calibrator, &all, on_failure)?;
    let alone: Vec<usize> = all
        .iter()
        .copied()
        .filter(|&i| bodies[i].is_none())
        .collect();
    let mut laws = calibrated_laws(
        road,
        map,
        max_approach,
        calibrator,
        (&alone, &[]),
        &CapShape::Flat,
        on_failure,
    )?;
    // Back to road order; a fallback's id is its position among `alone`.
    for f in &mut laws.fallbacks {
        f.id = alone[f.id];
    }
    let mut alone_laws = laws.laws.into_iter().map(|(law, _)| law);
    let merged: Vec<CalibratedLaw> = bodies
        .iter_mut()
        .map(|body| body.take().or_else(|| alone_laws.next()))
        .collect::<Option<_>>()
        .ok_or_else(|| FidelityError::invalid("calibrated laws", "fewer", "one per asperity"))?;
    let set = AsperitySet::new(
        road.set.positions().to_vec(),
        road.set.heights().to_vec(),
        merged,
    )
    .map_err(FidelityError::Solve)?;
    // A static run's indenters are 1-based.
    let fallbacks = laws
        .fallbacks
        .into_iter()
        .map(|f| CapFallback { id: f.id + 1, ..f })
        .collect();
    Ok((set, fallbacks))
}

/// A cap whose calibration failed and that kept its Wilke law, sampled at
/// the knots its table would have had (with the Wilke model's rebuilt
/// pressure as its field, when the rung uses fields).
#[derive(Clone, Debug, PartialEq)]
pub struct CapFallback {
    /// The asperity's id in the run's outputs: a static texture run's
    /// indenter (1-based, road order), a rolling run's `road.npz` id (the
    /// 0-based index among the asperities its path can select).
    pub id: usize,
    /// Its summit `(x, y)` (m) in the frame of the run's outputs: the
    /// height map's for a static run, the rolling frame (`y` from the
    /// path's mid-width) for a rolling one.
    pub summit: [f64; 2],
    /// Why its calibration failed.
    pub reason: String,
}

impl std::fmt::Display for CapFallback {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "asperity {} (summit at x = {:.3} mm, y = {:.3} mm): calibration failed ({}); \
             its Wilke law kept",
            self.id,
            self.summit[0] * 1e3,
            self.summit[1] * 1e3,
            self.reason
        )
    }
}

/// What a cap whose calibration fails gets.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum OnCapFailure {
    /// The first failure is the whole set's error.
    Abort,
    /// The cap keeps its Wilke law ([`CapFallback`]); the set fails only
    /// if every cap did, or the disk cache could not be written.
    WilkeLaw,
}

/// Calibrated laws, each with how far its asperity is lifted, and the caps
/// that kept their Wilke law (`id`: the position in the indices the laws
/// were asked for; `summit` in the height map's frame).
#[derive(Debug)]
pub(crate) struct CalibratedLaws {
    pub laws: Vec<(CalibratedLaw, f64)>,
    pub fallbacks: Vec<CapFallback>,
}

/// The depth range rule of [`super::calibrated_set`] for asperity `a` at
/// height `z` (the road's), `top` the road's highest summit.
pub(super) fn table_depth(
    map: &HeightMap,
    a: &Asperity,
    z: f64,
    top: f64,
    max_approach: f64,
) -> f64 {
    (max_approach - (top - z))
        .max(0.1 * max_approach)
        .max(2.0 * top_cell_offset(map, a))
}

/// How far (m) `a`'s summit stands above its highest valid cell (0 for a
/// summit on a cell, or when no cell is valid: `cap_patch` says so).
fn top_cell_offset(map: &HeightMap, a: &Asperity) -> f64 {
    let highest = a
        .cells
        .iter()
        .filter(|&&c| map.valid()[c])
        .map(|&c| map.heights()[c])
        .fold(f64::NEG_INFINITY, f64::max);
    if highest.is_finite() {
        (a.summit_height - highest).max(0.0)
    } else {
        0.0
    }
}

/// The calibrated laws of the road's asperities `indices` (indices into
/// `road.set`), tabulated as in [`calibrated_set`], in parallel on rayon's
/// current pool, each cap under `shape` (with how far its asperity is
/// lifted, [`super::under_tread`]). `lifts` (m, one per index, or empty for
/// none) is how far the tread's profile at least keeps each asperity from
/// the approach (a rolling path: [`super::rolling::profile_lifts`];
/// missing entries are no lift); a
/// lifted asperity can only be pressed `max_approach − (top − z_i) −
/// lift_i` deep, so its table stops there (with the same floor) instead of
/// paying for depths the run cannot reach. A cap whose calibration fails
/// is handled as `on_failure` says.
///
/// # Errors
/// As [`calibrated_set`]; [`FidelityError::InvalidInput`] for an index out
/// of the road.
pub(crate) fn calibrated_laws(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    calibrator: &Calibrator,
    (indices, lifts): (&[usize], &[f64]),
    shape: &CapShape,
    on_failure: OnCapFailure,
) -> Result<CalibratedLaws, FidelityError> {
    let stand_in = StandIn::of(calibrator, map, on_failure);
    calibrated_laws_by(
        road,
        map,
        max_approach,
        &|_, patch, depth| calibrator.law(patch, depth),
        (indices, lifts),
        shape,
        stand_in,
    )
}

/// How a failed cap is stood in for: its Wilke law at `nodes` knots, with
/// fields on a grid of `field_cell`.
#[derive(Clone, Copy, Debug)]
pub(super) struct StandIn {
    nodes: usize,
    field_cell: Option<f64>,
    on_failure: OnCapFailure,
}

impl StandIn {
    /// Stand-ins as `calibrator`'s tables would be (its knots, fields on
    /// `map`'s grid when it keeps fields).
    pub(super) fn of(calibrator: &Calibrator, map: &HeightMap, on_failure: OnCapFailure) -> Self {
        Self {
            nodes: calibrator.options().nodes,
            field_cell: calibrator.has_fields().then(|| map.dx().max(map.dy())),
            on_failure,
        }
    }
}

/// One cap's calibrated law (`law_of` asperity `i`'s patch to a depth) or
/// the error that stopped it.
pub(super) type LawOf<'c> =
    dyn Fn(usize, &CapPatch, f64) -> Result<CalibratedLaw, FidelityError> + Sync + 'c;

/// [`calibrated_laws`] with each table from `law_of`.
pub(super) fn calibrated_laws_by(
    road: &TextureRoad,
    map: &HeightMap,
    max_approach: f64,
    law_of: &LawOf<'_>,
    (indices, lifts): (&[usize], &[f64]),
    shape: &CapShape,
    stand_in: StandIn,
) -> Result<CalibratedLaws, FidelityError> {
    if road.segmentation.size() != (map.nx(), map.ny()) {
        return Err(FidelityError::invalid(
            "height map",
            format!("{} × {}", map.nx(), map.ny()),
            format!("the segmented size {:?}", road.segmentation.size()),
        ));
    }
    if !(max_approach.is_finite() && max_approach > 0.0) {
        return Err(FidelityError::invalid(
            "largest approach",
            max_approach,
            "finite and > 0 m",
        ));
    }
    let top = road.set.top();
    let outcomes = indices
        .par_iter()
        .enumerate()
        .map(|(n, &i)| {
            let (Some(&k), Some(&z)) = (road.asperity_index.get(i), road.set.heights().get(i))
            else {
                return Err(FidelityError::invalid(
                    "asperity index",
                    i,
                    format!("below the road's {} asperities", road.len()),
                ));
            };
            let a = &road.segmentation.asperities()[k];
            // A missing or non-positive lift is no lift: a deeper table,
            // never a shorter one.
            let lift = lifts.get(n).copied().filter(|l| *l > 0.0).unwrap_or(0.0);
            // A fitted summit may stand above every cell of a flat or
            // faceted top: the range must reach the highest cell (and as
            // far past it as the summit stands above it), or the cap has
            // no cell to calibrate.
            let depth = table_depth(map, a, z - lift, top, max_approach);
            let calibrated = shape.patch(map, a, i, depth).and_then(|shaped| {
                let patch = shaped.patch;
                // A cap raised to touch where its shape says is pressed
                // deeper by as much; the top cell may lie below a refined
                // summit, and the table must reach past it.
                let deeper = (depth + shaped.lift).max(2.0 * patch.summit_offset());
                Ok((law_of(i, &patch, deeper)?, shaped.lift))
            });
            match calibrated {
                Ok(law) => Ok(CapOutcome::Calibrated(law)),
                // The disk is not the cap's: a cache that cannot be
                // written stops the run as any unwritable output does.
                Err(e @ FidelityError::Cache { .. }) => Err(e),
                Err(e) if stand_in.on_failure == OnCapFailure::Abort => Err(e),
                Err(e) => {
                    // The Wilke law over the range the table would have had.
                    let law = super::calibrate::stand_in_law(
                        &road.set.laws()[i],
                        depth,
                        stand_in.nodes,
                        stand_in.field_cell,
                    );
                    Ok(CapOutcome::StoodIn(law, (n, i), e))
                }
            }
        })
        .collect::<Result<Vec<_>, _>>()?;
    let failed = outcomes
        .iter()
        .filter(|o| matches!(o, CapOutcome::StoodIn(..)))
        .count();
    let mut laws = Vec::with_capacity(outcomes.len());
    let mut fallbacks = Vec::with_capacity(failed);
    for outcome in outcomes {
        match outcome {
            CapOutcome::Calibrated(law) => laws.push(law),
            // Nothing calibrated is no calibrated rung: say why.
            CapOutcome::StoodIn(_, _, e) if failed == indices.len() => return Err(e),
            CapOutcome::StoodIn(law, (n, i), e) => {
                fallbacks.push(CapFallback {
                    id: n,
                    summit: road.set.positions()[i],
                    reason: e.to_string(),
                });
                laws.push((law, 0.0));
            }
        }
    }
    Ok(CalibratedLaws { laws, fallbacks })
}

/// One cap's law: calibrated (with its lift), or its Wilke law standing in
/// for a calibration that failed (its position among the indices and its
/// index in the road, the failure).
enum CapOutcome {
    Calibrated((CalibratedLaw, f64)),
    StoodIn(CalibratedLaw, (usize, usize), FidelityError),
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::contact_law::{ContactLaw, Material};
    use crate::fidelity::CalibrationOptions;
    use crate::texture_road::{TextureRoadOptions, texture_road};

    /// Three paraboloid caps (R = 4 mm) at x = 4, 12, 20 mm on a 24 × 8 mm
    /// map of 0.1 mm cells, summits 1.0, 0.95 and 0.9 mm high.
    fn three_caps() -> (TextureRoad, HeightMap, Calibrator) {
        let summits = [(4e-3, 1.0e-3), (12e-3, 0.95e-3), (20e-3, 0.9e-3)];
        let map = HeightMap::from_fn(241, 81, 1e-4, 1e-4, move |x, y| {
            summits
                .iter()
                .map(|&(cx, top)| top - ((x - cx).powi(2) + (y - 4e-3).powi(2)) / 8e-3)
                .fold(0.0, f64::max)
        })
        .expect("map");
        let material = Material::new(6.54e6, 0.5).expect("material");
        let road =
            texture_road(&map, material, &TextureRoadOptions::new(0.1e-3, 1e-6)).expect("road");
        assert_eq!(road.len(), 3);
        let calibrator = Calibrator::new(material, CalibrationOptions::default()).with_fields();
        (road, map, calibrator)
    }

    fn laws_failing(
        (road, map, calibrator): &(TextureRoad, HeightMap, Calibrator),
        fails: impl Fn(usize) -> Option<FidelityError> + Sync,
        on_failure: OnCapFailure,
    ) -> Result<CalibratedLaws, FidelityError> {
        let all: Vec<usize> = (0..road.len()).collect();
        let stand_in = StandIn {
            nodes: calibrator.options().nodes,
            field_cell: Some(map.dx()),
            on_failure,
        };
        calibrated_laws_by(
            road,
            map,
            0.4e-3,
            &|i, patch, depth| match fails(i) {
                Some(e) => Err(e),
                None => calibrator.law(patch, depth),
            },
            (&all, &[]),
            &CapShape::Flat,
            stand_in,
        )
    }

    fn not_converged() -> FidelityError {
        FidelityError::invalid("BEM solve", "injected", "a converged solve")
    }

    #[test]
    fn a_cap_whose_calibration_fails_keeps_its_wilke_law_and_the_others_are_calibrated() {
        let setup = three_caps();
        let road = &setup.0;
        let good = laws_failing(&setup, |_| None, OnCapFailure::WilkeLaw).expect("calibrated");
        assert!(good.fallbacks.is_empty());
        let laws = laws_failing(
            &setup,
            |i| (i == 1).then(not_converged),
            OnCapFailure::WilkeLaw,
        )
        .expect("one cap stood in");
        assert_eq!(laws.fallbacks.len(), 1);
        let f = &laws.fallbacks[0];
        // Asked for every asperity in road order: its id is its index.
        assert_eq!((f.id, f.summit), (1, road.set.positions()[1]));
        assert!(f.reason.contains("injected"), "{}", f.reason);
        assert!(f.to_string().starts_with("asperity 1 (summit at"), "{f}");
        let wilke = &road.set.laws()[1];
        // The table's range: 0.4 mm less the cap's 0.05 mm below the top.
        let range = 0.35e-3;
        for k in 1..=20 {
            let d = range * k as f64 / 20.0;
            for i in [0, 2] {
                assert_eq!(laws.laws[i].0.force(d), good.laws[i].0.force(d));
            }
            let (got, want) = (laws.laws[1].0.force(d), wilke.force(d));
            assert!(
                (got - want).abs() < 5e-3 * wilke.force(range),
                "δ = {d}: {got} vs the Wilke law's {want}"
            );
            assert!(laws.laws[1].0.unit_field(d).is_some(), "a field at δ = {d}");
        }
    }

    #[test]
    fn a_failed_cap_aborts_a_strict_set_and_every_cap_failing_is_an_error() {
        let setup = three_caps();
        let one = laws_failing(
            &setup,
            |i| (i == 0).then(not_converged),
            OnCapFailure::Abort,
        );
        assert!(one.is_err_and(|e| e.to_string().contains("injected")));
        let all = laws_failing(&setup, |_| Some(not_converged()), OnCapFailure::WilkeLaw);
        assert!(all.is_err_and(|e| e.to_string().contains("injected")));
        // A disk cache that cannot be written is the run's failure.
        let cache = |_| {
            Some(FidelityError::Cache {
                path: "/nowhere".into(),
                source: std::io::Error::other("read-only"),
            })
        };
        let disk = laws_failing(
            &setup,
            |i| (i == 2).then(|| cache(i)).flatten(),
            OnCapFailure::WilkeLaw,
        );
        assert!(disk.is_err_and(|e| matches!(e, FidelityError::Cache { .. })));
    }
}
