//! The viscoelastic BEM reference: the project's full-grid BEM time-stepped
//! with internal variables per cell and Maxwell branch.
//!
//! # Formulation
//!
//! With `ν` constant the surface of the viscoelastic half-space obeys
//! `p(t) = ∫_0^t E(t − s) dw/ds ds`, `u = K̃ w`, where `K̃` is the
//! unit-modulus influence operator and `w` the "elastic-equivalent" pressure
//! (the one whose unit-modulus displacement is `u`). A cell never in contact
//! has `p ≡ 0`, hence `w ≡ 0`: truncating the operator to the grid is exact.
//! The Prony recursion of the `history` module gives, over a step,
//! `p = E_eff w + h` cell by cell, so `u = K_eff p − K_eff h` with
//! `K_eff = K̃/E_eff`: each step is an elastic BEM contact problem of modulus
//! `E_eff` on the surface raised by `K_eff h` (the displacement the history
//! pressures cause), solved with the full complementarity conditions. Unlike
//! the multipoint recursion it assumes nothing about growing contacts: cells
//! that leave contact do so because the complementarity says so, which makes
//! it the reference for unloading and hysteresis (Ting's regime).

use tyreroad_bem::{BemError, BemOptions, Control, HeightMap, Solver};
use tyreroad_core::Field;

use crate::error::{non_negative, positive};
use crate::history::step_coefficients;
use crate::{Prony, ViscoError};

/// One step of the viscoelastic BEM.
#[derive(Clone, Debug, PartialEq)]
pub struct ViscoBemStep {
    /// Time at the end of the step (s).
    pub time: f64,
    /// Pressure per cell (Pa), row-major on the surface's grid.
    pub pressure: Vec<f64>,
    /// Total force (N).
    pub force: f64,
    /// Rigid approach of the tread from first touch of the road's highest
    /// point (m).
    pub approach: f64,
}

/// The time-stepped viscoelastic BEM on a rigid `surface`.
pub struct ViscoBem {
    surface: HeightMap,
    material: Prony,
    options: BemOptions,
    /// The elastic solver of the current step's `E_eff` and the `dt` it is for.
    solver: Option<(f64, Solver)>,
    time: f64,
    /// `w_n` per cell (Pa per Pa of modulus: m/m, dimensionless strain-like).
    equivalent: Vec<f64>,
    /// `q_{c,k,n}` per cell and branch (Pa), cell-major.
    branch_pressure: Vec<f64>,
    pressure: Vec<f64>,
}

impl ViscoBem {
    /// A viscoelastic BEM at rest at time 0.
    pub fn new(surface: HeightMap, material: Prony, options: BemOptions) -> Self {
        let cells = surface.grid().len();
        let branches = material.branches().len();
        Self {
            surface,
            material,
            options,
            solver: None,
            time: 0.0,
            equivalent: vec![0.0; cells],
            branch_pressure: vec![0.0; cells * branches],
            pressure: vec![0.0; cells],
        }
    }

    /// Time reached (s).
    pub fn time(&self) -> f64 {
        self.time
    }

    /// Advances by `dt` (s) to the total load `load` (N).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for `dt ≤ 0` or a negative load;
    /// [`ViscoError::Bem`] when the elastic BEM fails.
    pub fn step_load(&mut self, dt: f64, load: f64) -> Result<ViscoBemStep, ViscoError> {
        positive("time step (s)", dt)?;
        non_negative("load (N)", load)?;
        let coefficients = step_coefficients(&self.material, dt);
        let effective = self.material.long_term() + coefficients.iter().map(|c| c.1).sum::<f64>();
        let branches = coefficients.len();
        let history: Vec<f64> = (0..self.equivalent.len())
            .map(|c| {
                coefficients
                    .iter()
                    .enumerate()
                    .map(|(k, (decay, weight))| {
                        decay * self.branch_pressure[c * branches + k] - weight * self.equivalent[c]
                    })
                    .sum()
            })
            .collect();
        let time = self.time + dt;
        let bem = |source: BemError| ViscoError::Bem { time, source };
        if self.solver.as_ref().is_none_or(|(d, _)| *d != dt) {
            let elastic = self.material.elastic(effective)?;
            let solver = Solver::new(self.surface.grid(), &elastic, &self.options).map_err(bem)?;
            self.solver = Some((dt, solver));
        }
        let Some((_, solver)) = self.solver.as_mut() else {
            unreachable!("the solver was just built")
        };
        let raise = solver.displacement(&history).map_err(bem)?;
        let raised: Vec<f64> = self
            .surface
            .values()
            .iter()
            .zip(&raise)
            .map(|(h, r)| h + r)
            .collect();
        let raised =
            Field::new(self.surface.grid().clone(), raised).map_err(|e| ViscoError::Bem {
                time,
                source: BemError::InvalidInput(e.to_string()),
            })?;
        let solution = if self.pressure.iter().any(|p| *p > 0.0) && load > 0.0 {
            solver.solve_from(&raised, Control::Load(load), &self.pressure)
        } else {
            solver.solve(&raised, Control::Load(load))
        }
        .map_err(bem)?;
        let top = self
            .surface
            .values()
            .iter()
            .fold(f64::NEG_INFINITY, |m, v| m.max(*v));
        for (c, p) in solution.pressure.iter().enumerate() {
            let w = (p - history[c]) / effective;
            for (k, (decay, weight)) in coefficients.iter().enumerate() {
                let q = &mut self.branch_pressure[c * branches + k];
                *q = decay * *q + weight * (w - self.equivalent[c]);
            }
            self.equivalent[c] = w;
        }
        self.pressure.clone_from(&solution.pressure);
        self.time = time;
        Ok(ViscoBemStep {
            time,
            pressure: solution.pressure,
            force: solution.force,
            approach: solution.approach + top - solution.reference_height,
        })
    }
}
