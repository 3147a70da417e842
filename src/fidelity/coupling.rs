//! The `calibrated_fields` coupling: asperities coupled through their own
//! calibrated pressure fields instead of point forces at their summits
//! (issue 15 rung 2; docs/theory.md §3, "Field coupling").
//!
//! With `w_ia` at `x_ia` the unit field of asperity `i` at its current
//! depth `δ_i` ([`CalibratedLaw::unit_field`], binned BEM pressure of its
//! own cap, [`super::field`]), the coupling of `i` and `j` is the
//! work-conjugate mean displacement of one field under the other,
//!
//! ```text
//! T_ij + C_ij = f Σ_a Σ_b w_ia w_jb / |x_ia − x_jb|,    f = 1/(π E*)
//! C_ij = f (G_ij − 1/r_ij)
//! ```
//!
//! handed to the solver as a fixed sparse correction of the point kernel
//! ([`crate::multipoint::PairCorrection`]; the solver knows nothing of
//! fields). Pairs closer than `reach (R_i + R_j)` (`R` the largest distance
//! of a field's bins from its summit) take the double sum; farther pairs
//! take the two fields' centroids, `G_ij = 1/|c_i − c_j|` (what is left,
//! the fields' second moments, is `O((R/r)²) < 1/reach²` of `1/r`); pairs
//! where `|G_ij r_ij − 1| < ` [`NEGLIGIBLE`] are left out. An asperity out
//! of contact has the field of its first loaded knot (its contact at
//! onset), which is what decides whether it comes into contact.
//!
//! Since `C` depends on the depths, an outer fixed point: solve with the
//! point kernel, compute `C` at the solution's depths, solve again from
//! that solution with `T + C`, and repeat until no force moves by more than
//! `tolerance × scale` (the load, or the total force under approach
//! control) between rounds. Each round's solve converges to the solver's
//! tolerance; the fixed point is the consistent state.
//!
//! Tiles of one body ([`super::joint`]) hold their mutual coupling in their
//! tables: between them `C_ij = −1/(π E* r_ij)` cancels the point kernel
//! whole, whatever their distance (in the rolling correction, between the
//! pairs it visits: rolling laws are calibrated alone and carry no body).

use rayon::prelude::*;

use super::field::{UnitField, centroid_and_reach, field_compliance};
use super::pair_sum::{PackedField, packed_compliance};
use super::{CalibratedLaw, FidelityError};
use crate::multipoint::{
    Control, PairCorrection, Problem, Solution, SolverOptions, solve_corrected,
};

/// Pairs whose field coupling differs from the point kernel by less than
/// this fraction of it are left to the point kernel.
pub const NEGLIGIBLE: f64 = 1e-4;

/// How the field coupling is computed and iterated.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FieldCouplingOptions {
    /// Pairs closer than `reach (R_i + R_j)` take the binned double sum,
    /// farther ones their centroids (module docs). Default 4.
    pub reach: f64,
    /// The fixed point stops when no force moves by more than this
    /// fraction of the scale between rounds. Default 1e-6.
    pub tolerance: f64,
    /// Most rounds of the fixed point. Default 30.
    pub max_rounds: usize,
}

impl Default for FieldCouplingOptions {
    fn default() -> Self {
        Self {
            reach: 4.0,
            tolerance: 1e-6,
            max_rounds: 30,
        }
    }
}

impl FieldCouplingOptions {
    fn validate(&self) -> Result<(), FidelityError> {
        if !(self.reach.is_finite() && self.reach >= 1.0) {
            return Err(FidelityError::invalid(
                "field coupling reach",
                self.reach,
                "finite and >= 1",
            ));
        }
        if !(self.tolerance.is_finite() && self.tolerance > 0.0) {
            return Err(FidelityError::invalid(
                "field coupling tolerance",
                self.tolerance,
                "finite and > 0",
            ));
        }
        if self.max_rounds == 0 {
            return Err(FidelityError::invalid("field coupling rounds", 0, ">= 1"));
        }
        Ok(())
    }
}

/// The correction at one state, and how its pairs were computed.
#[derive(Clone, Debug)]
pub struct FieldCorrection {
    /// `C` for the solver.
    pub correction: PairCorrection,
    /// Pairs computed by the binned double sum.
    pub field_pairs: usize,
    /// Pairs computed from the fields' centroids.
    pub centroid_pairs: usize,
}

/// The correction `C` of the point kernel at the asperities' `depths`
/// (module docs).
///
/// # Errors
/// [`FidelityError::InvalidInput`] for a depth count that is not the
/// problem's, an invalid `reach`, or a law calibrated without fields
/// ([`super::Calibrator::with_fields`]).
pub fn field_correction(
    problem: &Problem<CalibratedLaw>,
    depths: &[f64],
    reach: f64,
) -> Result<FieldCorrection, FidelityError> {
    let n = problem.len();
    if depths.len() != n {
        return Err(FidelityError::invalid(
            "depths",
            depths.len(),
            format!("{n} values"),
        ));
    }
    if !(reach.is_finite() && reach >= 1.0) {
        return Err(FidelityError::invalid(
            "field coupling reach",
            reach,
            "finite and >= 1",
        ));
    }
    let positions = problem.positions();
    let laws = problem.laws();
    let fields = placed_fields(laws.iter(), positions, depths)?;
    let factor = problem.material().boussinesq_factor();
    let rows: Vec<Vec<(usize, usize, f64, bool)>> = (0..n)
        .into_par_iter()
        .map(|i| {
            let ri = fields[i].2;
            let mut row = Vec::new();
            for (j, rj) in fields.iter().map(|f| f.2).enumerate().skip(i + 1) {
                let r =
                    (positions[i][0] - positions[j][0]).hypot(positions[i][1] - positions[j][1]);
                if r == 0.0 {
                    // Coincident summits have no point coupling to correct.
                    continue;
                }
                if same_body(&laws[i], &laws[j]) {
                    row.push((i, j, -factor / r, true));
                    continue;
                }
                let near = r < reach * (ri + rj);
                let g = if near {
                    field_compliance(
                        &fields[i].0,
                        &fields[j].0,
                        0.5 * fields[i].3.min(fields[j].3),
                    )
                } else {
                    centroid_compliance(&fields[i], &fields[j])
                };
                if let Some(c) = pair_correction(g, r, factor) {
                    row.push((i, j, c, near));
                }
            }
            row
        })
        .collect();
    field_correction_of(n, rows)
}

/// A field-coupled solution.
#[derive(Clone, Debug)]
pub struct FieldSolution {
    /// The solution of the last round (coupling `T + C` at its own depths
    /// to the fixed point's tolerance).
    pub solution: Solution,
    /// Rounds of the fixed point (corrected solves).
    pub rounds: usize,
    /// The largest force change of the last round over the scale.
    pub change: f64,
    /// The last correction's pairs: binned double sums and centroid ones.
    pub field_pairs: usize,
    /// See [`Self::field_pairs`].
    pub centroid_pairs: usize,
}

/// Solves `problem` (calibrated with fields) under `control` with the field
/// coupling (module docs), from `initial` or cold.
///
/// # Errors
/// As [`field_correction`]; [`FidelityError::Solve`] when a round's solve
/// fails; [`FidelityError::FieldCoupling`] when the fixed point has not
/// settled after `options.max_rounds` rounds.
pub fn solve_field_coupled(
    problem: &Problem<CalibratedLaw>,
    control: Control,
    solver: &SolverOptions,
    options: &FieldCouplingOptions,
    initial: Option<&Solution>,
) -> Result<FieldSolution, FidelityError> {
    options.validate()?;
    let mut s = super::solve_calibrated(problem, control, solver, initial)?;
    let scale = match control {
        Control::Load(w) => w,
        Control::Approach(_) => s.forces.iter().sum(),
    };
    if !(scale > 0.0) {
        // Nothing in contact: nothing to couple.
        return Ok(FieldSolution {
            solution: s,
            rounds: 0,
            change: 0.0,
            field_pairs: 0,
            centroid_pairs: 0,
        });
    }
    let mut change = f64::INFINITY;
    for round in 1..=options.max_rounds {
        let c = field_correction(problem, &s.depths, options.reach)?;
        let next = solve_corrected(problem, control, solver, Some(&s), &c.correction)?;
        change = next
            .forces
            .iter()
            .zip(&s.forces)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
            / scale;
        s = next;
        if change <= options.tolerance {
            return Ok(FieldSolution {
                solution: s,
                rounds: round,
                change,
                field_pairs: c.field_pairs,
                centroid_pairs: c.centroid_pairs,
            });
        }
    }
    Err(FidelityError::FieldCoupling {
        rounds: options.max_rounds,
        change,
    })
}

/// How a rolling step's field correction limits its pairs
/// ([`sparse_field_correction`]).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairReach {
    /// Pairs closer than `near (R_i + R_j)` take the binned double sum.
    pub near: f64,
    /// Pairs farther than `far (R_i + R_j)` keep the point kernel; between
    /// `near` and `far` they take the fields' centroids.
    pub far: f64,
}

impl Default for PairReach {
    /// `near` 4 (as the static rung's reach), `far` 10: a centroid term
    /// left out is below `(R_i + R_j)/r < 1/10` of the point kernel of a
    /// pair more than ten field extents apart, and of either sign.
    fn default() -> Self {
        Self {
            near: 4.0,
            far: 10.0,
        }
    }
}

/// How the rolling correction evaluates a near pair's double sum.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum PairSum {
    /// Packed once a round, `f32` positions about each field's centroid
    /// ([`super::pair_sum::packed_compliance`]): the `f64` sum to ~1e-6
    /// relative, at a fraction of its cost (docs/performance.md, "The
    /// `calibrated_fields` rung in rolling").
    #[default]
    Packed,
    /// Bin by bin in `f64` ([`field_compliance`]): the reference the
    /// packed sum is tested against.
    Exact,
}

/// The field correction `C` of a step's asperities at `positions` (m, the
/// points the point kernel couples: each field's points are taken relative
/// to its asperity's position), `depths` (m) and `forces` (N), without
/// visiting all `N²` pairs: the asperities sorted by x, each loaded one
/// paired only with those within `far (R_i + R_max)` along x, and then by
/// distance as [`PairReach`] says, near pairs' double sums as `sum` says.
/// Pairs where neither asperity carries a force are never visited (their
/// correction multiplies zero forces; a pair that comes into contact is
/// picked up by the next round of the fixed point).
///
/// # Errors
/// [`FidelityError::InvalidInput`] for slices of different lengths, a
/// reach that is not finite with `1 ≤ near ≤ far`, or a law calibrated
/// without fields.
pub fn sparse_field_correction(
    positions: &[[f64; 2]],
    laws: &[&CalibratedLaw],
    depths: &[f64],
    forces: &[f64],
    factor: f64,
    reach: PairReach,
    sum: PairSum,
) -> Result<FieldCorrection, FidelityError> {
    let n = positions.len();
    if laws.len() != n || depths.len() != n || forces.len() != n {
        return Err(FidelityError::invalid(
            "field correction",
            format!(
                "{n} positions, {} laws, {} depths, {} forces",
                laws.len(),
                depths.len(),
                forces.len()
            ),
            "one law, depth and force per position",
        ));
    }
    if !(reach.near.is_finite() && reach.far.is_finite() && reach.near >= 1.0)
        || reach.far < reach.near
    {
        return Err(FidelityError::invalid(
            "field coupling reach",
            format!("near {}, far {}", reach.near, reach.far),
            "finite, 1 <= near <= far",
        ));
    }
    let fields = placed_fields(laws.iter().copied(), positions, depths)?;
    let extent_max = fields.iter().map(|f| f.2).fold(0.0, f64::max);
    // Packed once a round, not once a pair.
    let packed: Vec<PackedField> = match sum {
        PairSum::Packed => fields
            .par_iter()
            .map(|f| PackedField::new(&f.0, f.1))
            .collect(),
        PairSum::Exact => Vec::new(),
    };
    let mut by_x: Vec<usize> = (0..n).collect();
    by_x.sort_by(|&a, &b| positions[a][0].total_cmp(&positions[b][0]));
    let loaded = |i: usize| forces[i] > 0.0;
    // Each pair with a loaded asperity is visited once, from a loaded one:
    // rightwards to every asperity in the window, leftwards to the unloaded
    // ones only (a loaded one on the left visits the pair itself). Most of
    // a step's asperities carry no force, and no unloaded one is scanned.
    let pair = |i: usize, j: usize, row: &mut Vec<(usize, usize, f64, bool)>| {
        let (ri, rj) = (fields[i].2, fields[j].2);
        let (dx, dy) = (
            positions[j][0] - positions[i][0],
            positions[j][1] - positions[i][1],
        );
        let r2 = dx * dx + dy * dy;
        let far = reach.far * (ri + rj);
        // Coincident points have no point coupling to correct.
        if r2 == 0.0 {
            return;
        }
        if same_body(laws[i], laws[j]) {
            row.push((i.min(j), i.max(j), -factor / r2.sqrt(), true));
            return;
        }
        if r2 >= far * far {
            return;
        }
        let r = r2.sqrt();
        let near = r < reach.near * (ri + rj);
        let g = if near {
            let floor = 0.5 * fields[i].3.min(fields[j].3);
            match sum {
                PairSum::Packed => packed_compliance(&packed[i], &packed[j], floor),
                PairSum::Exact => field_compliance(&fields[i].0, &fields[j].0, floor),
            }
        } else {
            centroid_compliance(&fields[i], &fields[j])
        };
        if let Some(c) = pair_correction(g, r, factor) {
            row.push((i.min(j), i.max(j), c, near));
        }
    };
    let rows: Vec<Vec<(usize, usize, f64, bool)>> = (0..n)
        .into_par_iter()
        .filter(|&k| loaded(by_x[k]))
        .fold(Vec::new, |mut row, k| {
            let i = by_x[k];
            let window = reach.far * (fields[i].2 + extent_max);
            let x = positions[i][0];
            for &j in by_x[k + 1..]
                .iter()
                .take_while(|&&j| positions[j][0] - x <= window)
            {
                pair(i, j, &mut row);
            }
            for &j in by_x[..k]
                .iter()
                .rev()
                .take_while(|&&j| x - positions[j][0] <= window)
            {
                if !loaded(j) {
                    pair(i, j, &mut row);
                }
            }
            row
        })
        .collect();
    field_correction_of(n, rows)
}

/// Each asperity's unit field at its depth placed at its summit, with the
/// field's centroid, its reach from the summit and its bin size.
type PlacedField = (UnitField, [f64; 2], f64, f64);

/// The [`PlacedField`] of every asperity; an asperity whose law has no
/// field is a named error.
fn placed_fields<'l>(
    laws: impl Iterator<Item = &'l CalibratedLaw>,
    positions: &[[f64; 2]],
    depths: &[f64],
) -> Result<Vec<PlacedField>, FidelityError> {
    laws.zip(positions)
        .zip(depths)
        .enumerate()
        .map(|(i, ((law, p), &d))| {
            let bin = law.table().field().map(|f| f.bin_size());
            let (Some(local), Some(bin)) = (law.unit_field(d), bin) else {
                return Err(FidelityError::invalid(
                    "asperity law",
                    format!("asperity {i} without a pressure field"),
                    "a table calibrated with fields (Calibrator::with_fields)",
                ));
            };
            let field: UnitField = local
                .into_iter()
                .map(|(x, w)| ([p[0] + x[0], p[1] + x[1]], w))
                .collect();
            let (centroid, extent) = centroid_and_reach(&field, *p);
            Ok((field, centroid, extent, bin))
        })
        .collect()
}

/// `G` of two fields far enough apart to be taken at their centroids
/// (module docs): `1/|c_a − c_b|`.
fn centroid_compliance(a: &PlacedField, b: &PlacedField) -> f64 {
    let (dx, dy) = (a.1[0] - b.1[0], a.1[1] - b.1[1]);
    1.0 / (dx * dx + dy * dy).sqrt()
}

/// The correction `f (g − 1/r)` of one pair whose summits lie `r` apart
/// and whose fields couple by `g` (1/m: the double sum of a near pair, the
/// centroids' of a farther one); `None` where `g` is the point kernel to
/// [`NEGLIGIBLE`] (or not finite).
/// Whether two laws are tiles of one body ([`super::joint`]): their tables
/// hold their coupling, which the correction then cancels whole.
fn same_body(a: &CalibratedLaw, b: &CalibratedLaw) -> bool {
    a.body().is_some() && a.body() == b.body()
}

fn pair_correction(g: f64, r: f64, factor: f64) -> Option<f64> {
    ((g * r - 1.0).abs() >= NEGLIGIBLE && g.is_finite()).then(|| factor * (g - 1.0 / r))
}

/// The correction of `n` asperities from its pairs `(i, j, C_ij, near)`,
/// with the count of each kind.
fn field_correction_of(
    n: usize,
    rows: Vec<Vec<(usize, usize, f64, bool)>>,
) -> Result<FieldCorrection, FidelityError> {
    let pairs: Vec<_> = rows.into_iter().flatten().collect();
    let field_pairs = pairs.iter().filter(|p| p.3).count();
    let centroid_pairs = pairs.len() - field_pairs;
    let correction =
        PairCorrection::new(n, pairs.into_iter().map(|(i, j, c, _)| (i, j, c)).collect())?;
    Ok(FieldCorrection {
        correction,
        field_pairs,
        centroid_pairs,
    })
}
