//! The hereditary multipoint model against the viscoelastic BEM on a field of
//! spheres under a load history: the comparison the tests and the
//! `bem_compare` example run.

use tyreroad_asperity::Sphere as Cap;
use tyreroad_bem::{BemOptions, Sphere, nearest_labels, spherical_caps};
use tyreroad_contact_law::PotentialLaw;
use tyreroad_core::Grid;
use tyreroad_multipoint::{Problem, SolverOptions};

#[cfg(doc)]
use crate::run_load_history;
use crate::{Prony, Receding, ViscoBem, ViscoError, run_load_history_with};

/// A square field of equal spheres: `side × side` summits of radius `radius`
/// (m) at `pitch` (m), summit heights lowered by `gaps` (m, row-major,
/// `side²` values), meshed for the BEM with cells of `cell` (m) over the
/// field plus one pitch all round.
#[derive(Clone, Debug, PartialEq)]
pub struct SphereField {
    /// Summits per side.
    pub side: usize,
    /// Sphere radius (m).
    pub radius: f64,
    /// Summit spacing (m).
    pub pitch: f64,
    /// Initial gap of each summit below the highest (m).
    pub gaps: Vec<f64>,
    /// BEM cell size (m).
    pub cell: f64,
}

/// Per-step forces of both methods.
#[derive(Clone, Debug, PartialEq)]
pub struct Comparison {
    /// Times (s).
    pub time: Vec<f64>,
    /// Model forces per step and summit (N).
    pub model: Vec<Vec<f64>>,
    /// BEM forces per step and summit (Voronoi regions of the summits, N).
    pub bem: Vec<Vec<f64>>,
    /// Model approach per step (m).
    pub model_approach: Vec<f64>,
    /// BEM approach per step (m).
    pub bem_approach: Vec<f64>,
}

impl Comparison {
    /// Largest difference of a summit force over all steps, relative to the
    /// step's largest BEM summit force.
    pub fn worst_force_difference(&self) -> f64 {
        self.model
            .iter()
            .zip(&self.bem)
            .map(|(m, b)| {
                let scale = b.iter().fold(0.0f64, |s, v| s.max(v.abs()));
                m.iter()
                    .zip(b)
                    .map(|(x, y)| (x - y).abs() / scale)
                    .fold(0.0, f64::max)
            })
            .fold(0.0, f64::max)
    }
}

/// Runs `samples` (`(time, load)`) on `field` with both methods, the model
/// with the default treatment of receding contacts ([`Receding::default`]).
///
/// # Errors
/// As [`run_load_history`] and [`ViscoBem::step_load`];
/// [`ViscoError::InvalidValue`] for a malformed field.
pub fn compare_on_spheres(
    field: &SphereField,
    material: &Prony,
    samples: &[(f64, f64)],
) -> Result<Comparison, ViscoError> {
    compare_on_spheres_with(field, material, Receding::default(), samples)
}

/// As [`compare_on_spheres`], the model treating receding contacts by
/// `receding`.
///
/// # Errors
/// As [`compare_on_spheres`].
pub fn compare_on_spheres_with(
    field: &SphereField,
    material: &Prony,
    receding: Receding,
    samples: &[(f64, f64)],
) -> Result<Comparison, ViscoError> {
    let n = field.side * field.side;
    if field.gaps.len() != n {
        return Err(ViscoError::LengthMismatch {
            name: "sphere field gaps",
            found: field.gaps.len(),
            expected: n,
        });
    }
    let centres: Vec<[f64; 2]> = (0..n)
        .map(|k| {
            [
                field.pitch * (k % field.side) as f64,
                field.pitch * (k / field.side) as f64,
            ]
        })
        .collect();
    let reference = material.elastic(material.long_term())?;
    let cap = Cap::new(field.radius).map_err(|_| ViscoError::InvalidValue {
        name: "sphere radius (m)",
        value: field.radius,
        expected: "finite and > 0",
    })?;
    let law = PotentialLaw::sphere(cap, reference);
    let problem = Problem::new(centres.clone(), field.gaps.clone(), vec![law; n], reference)
        .map_err(|source| ViscoError::Solve {
            step: 0,
            time: 0.0,
            source,
        })?;
    let model = run_load_history_with(
        &problem,
        material.clone(),
        SolverOptions::default(),
        receding,
        samples,
    )?;

    let span = field.pitch * (field.side + 1) as f64;
    let cells = (span / field.cell).ceil() as usize;
    let invalid = |_| ViscoError::InvalidValue {
        name: "BEM cell size (m)",
        value: field.cell,
        expected: "finite, > 0 and a grid that fits",
    };
    let grid = Grid::new(cells, cells, field.cell, field.cell)
        .and_then(|g| g.with_origin([-field.pitch, -field.pitch]))
        .map_err(invalid)?;
    let spheres: Vec<Sphere> = centres
        .iter()
        .zip(&field.gaps)
        .map(|(c, g)| Sphere {
            centre: *c,
            radius: field.radius,
            summit: -g,
        })
        .collect();
    let bem_err = |source| ViscoError::Bem { time: 0.0, source };
    let surface = spherical_caps(&grid, &spheres, -field.radius).map_err(bem_err)?;
    let labels = nearest_labels(&grid, &centres);
    let mut bem = ViscoBem::new(surface, material.clone(), BemOptions::default());
    let area = grid.cell_area();
    let mut comparison = Comparison {
        time: Vec::new(),
        model: Vec::new(),
        bem: Vec::new(),
        model_approach: Vec::new(),
        bem_approach: Vec::new(),
    };
    for (&(time, load), step) in samples.iter().zip(&model) {
        let b = bem.step_load(time - bem.time(), load)?;
        let mut per = vec![0.0; n];
        for (p, &l) in b.pressure.iter().zip(&labels) {
            per[l] += p * area;
        }
        comparison.time.push(time);
        comparison.model.push(step.forces.clone());
        comparison.bem.push(per);
        comparison.model_approach.push(step.approach);
        comparison.bem_approach.push(b.approach);
    }
    Ok(comparison)
}
