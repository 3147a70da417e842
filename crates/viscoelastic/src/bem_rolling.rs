//! The tread's memory for the viscoelastic rolling BEM: the Prony internal
//! variables of every cell of a footprint window, carried along as the
//! window moves over the road.
//!
//! # Which frame the memory lives in
//!
//! A rolling tread does not slip on the road: a rubber element in the
//! footprint stays over the same road point from the moment it touches down
//! at the leading edge until it lifts off at the trailing edge. Its history
//! (`w` and the branch pressures `q_k` of [`ViscoBem`](crate::ViscoBem)'s
//! recursion) is therefore fixed to the road, while the BEM window moves
//! with the footprint. When the window moves by `(di, dj)` cells the stored
//! fields are shifted by `(−di, −dj)` in window indices
//! ([`TreadMemory::shift`]): exact when the window moves by a whole number
//! of cells, which is why the caller must refuse other steps. Cells entering
//! at the leading edge are fresh rubber (`w = q = 0`: it has been out of
//! contact for a wheel revolution, long against the relaxation times); cells
//! leaving at the trailing edge take their memory with them, which neglects
//! the displacement that their remaining memory would cause inside the
//! window (they are out of the tread's footprint by then).
//!
//! # One step
//!
//! Per cell, with `w` the elastic-equivalent pressure (`u = K̃ w`):
//!
//! ```text
//! p_c = E_eff w_c + h_c,   h_c = Σ_k (e^{−Δt/τ_k} q_ck − E_k γ_k w_c,n)
//! q_ck ← e^{−Δt/τ_k} q_ck + E_k γ_k (w_c − w_c,n)
//! ```
//!
//! so the contact at a step is an elastic BEM problem of modulus `E_eff` on
//! the road raised by the displacement `K_eff h` ([`TreadMemory::history`],
//! then [`TreadMemory::commit`] with the solved pressure). The invariants,
//! tested by the rolling BEM that uses it: `Δt ≫ τ_max` gives the elastic
//! solution with `E∞`, `Δt ≪ τ_min` the one with `E∞ + Σ E_k`.

use crate::error::positive;
use crate::history::step_coefficients;
use crate::{Prony, ViscoError};

/// The Prony internal variables of an `nx × ny` window (row-major, x
/// fastest), fixed to the road.
#[derive(Clone, Debug, PartialEq)]
pub struct TreadMemory {
    material: Prony,
    nx: usize,
    ny: usize,
    /// `w_c` per cell (dimensionless: pressure per unit modulus).
    equivalent: Vec<f64>,
    /// `q_ck` per cell and branch (Pa), cell-major.
    branch_pressure: Vec<f64>,
}

/// What a step of length `Δt` needs: `E_eff` and every cell's `h_c`.
#[derive(Clone, Debug, PartialEq)]
pub struct StepHistory {
    /// Step length (s).
    pub dt: f64,
    /// `E_eff = E∞ + Σ_k E_k γ_k` (Pa): the modulus of the step's elastic
    /// solve.
    pub effective_modulus: f64,
    /// `h_c` per cell (Pa): the pressure the memory carries at zero `w`.
    pub pressure: Vec<f64>,
}

impl TreadMemory {
    /// A window of fresh rubber (no history).
    pub fn new(material: Prony, nx: usize, ny: usize) -> Self {
        let branches = material.branches().len();
        Self {
            material,
            nx,
            ny,
            equivalent: vec![0.0; nx * ny],
            branch_pressure: vec![0.0; nx * ny * branches],
        }
    }

    /// The material.
    pub fn material(&self) -> &Prony {
        &self.material
    }

    /// Cells `(nx, ny)` of the window.
    pub fn cells(&self) -> (usize, usize) {
        (self.nx, self.ny)
    }

    /// The window moved by `(di, dj)` cells over the road: the road-fixed
    /// memory moves by `(−di, −dj)` in window indices; cells entering the
    /// window are fresh.
    pub fn shift(&mut self, di: i64, dj: i64) {
        if di == 0 && dj == 0 {
            return;
        }
        let branches = self.material.branches().len();
        let (nx, ny) = (self.nx, self.ny);
        let mut equivalent = vec![0.0; nx * ny];
        let mut branch_pressure = vec![0.0; nx * ny * branches];
        for j in 0..ny {
            let sj = j as i64 + dj;
            if sj < 0 || sj >= ny as i64 {
                continue;
            }
            for i in 0..nx {
                let si = i as i64 + di;
                if si < 0 || si >= nx as i64 {
                    continue;
                }
                let (to, from) = (j * nx + i, sj as usize * nx + si as usize);
                equivalent[to] = self.equivalent[from];
                branch_pressure[to * branches..(to + 1) * branches]
                    .copy_from_slice(&self.branch_pressure[from * branches..(from + 1) * branches]);
            }
        }
        self.equivalent = equivalent;
        self.branch_pressure = branch_pressure;
    }

    /// `E_eff` and every cell's `h_c` for a step of `dt` (s).
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for `dt ≤ 0` or not finite.
    pub fn history(&self, dt: f64) -> Result<StepHistory, ViscoError> {
        positive("time step (s)", dt)?;
        let coefficients = step_coefficients(&self.material, dt);
        let effective = self.material.long_term() + coefficients.iter().map(|c| c.1).sum::<f64>();
        let branches = coefficients.len();
        let pressure = self
            .equivalent
            .iter()
            .enumerate()
            .map(|(c, w)| {
                coefficients
                    .iter()
                    .enumerate()
                    .map(|(k, (decay, weight))| {
                        decay * self.branch_pressure[c * branches + k] - weight * w
                    })
                    .sum()
            })
            .collect();
        Ok(StepHistory {
            dt,
            effective_modulus: effective,
            pressure,
        })
    }

    /// Ends the step of `history` with the solved contact pressure per
    /// cell (Pa): `w_c = (p_c − h_c)/E_eff`, and the branch recursion.
    ///
    /// # Errors
    /// [`ViscoError::LengthMismatch`] when `pressure` or `history` is not
    /// one value per cell.
    pub fn commit(&mut self, history: &StepHistory, pressure: &[f64]) -> Result<(), ViscoError> {
        let cells = self.nx * self.ny;
        for (name, found) in [
            ("solved pressure", pressure.len()),
            ("step history", history.pressure.len()),
        ] {
            if found != cells {
                return Err(ViscoError::LengthMismatch {
                    name,
                    found,
                    expected: cells,
                });
            }
        }
        let coefficients = step_coefficients(&self.material, history.dt);
        let branches = coefficients.len();
        for (c, (p, h)) in pressure.iter().zip(&history.pressure).enumerate() {
            let w = (p - h) / history.effective_modulus;
            for (k, (decay, weight)) in coefficients.iter().enumerate() {
                let q = &mut self.branch_pressure[c * branches + k];
                *q = decay * *q + weight * (w - self.equivalent[c]);
            }
            self.equivalent[c] = w;
        }
        Ok(())
    }

    /// Ends a step whose solve failed: the elastic-equivalent pressure is
    /// held (`Δw = 0`) and the branch pressures relax. An approximation for
    /// that one step, counted by the caller as a failed step.
    ///
    /// # Errors
    /// [`ViscoError::InvalidValue`] for `dt ≤ 0` or not finite.
    pub fn hold(&mut self, dt: f64) -> Result<(), ViscoError> {
        positive("time step (s)", dt)?;
        let coefficients = step_coefficients(&self.material, dt);
        let branches = coefficients.len().max(1);
        for (i, q) in self.branch_pressure.iter_mut().enumerate() {
            *q *= coefficients[i % branches].0;
        }
        Ok(())
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Branch;

    fn tread() -> Prony {
        Prony::new(
            2e6,
            vec![
                Branch {
                    modulus: 3e6,
                    relaxation_time: 1e-3,
                },
                Branch {
                    modulus: 5e6,
                    relaxation_time: 2e-5,
                },
            ],
            0.5,
        )
        .expect("valid tread")
    }

    /// One cell held at a constant `w` from a step: its pressure relaxes as
    /// `E(t) w`, the relaxation modulus (the recursion's exactness for a
    /// step in `w`, independent of the step length).
    #[test]
    fn a_held_cell_relaxes_as_the_relaxation_modulus() {
        let material = tread();
        let mut memory = TreadMemory::new(material.clone(), 1, 1);
        let w = 1e-3;
        // A step taken in a very short first step: p = E0 w.
        let first = memory.history(1e-12).expect("history");
        let p0 = first.effective_modulus * w + first.pressure[0];
        memory.commit(&first, &[p0]).expect("commit");
        let mut time = 1e-12;
        for dt in [1e-5, 3e-5, 1e-4, 1e-3, 5e-3] {
            let step = memory.history(dt).expect("history");
            let p = step.effective_modulus * w + step.pressure[0];
            memory.commit(&step, &[p]).expect("commit");
            time += dt;
            let expected = material.relaxation(time) * w;
            assert!(
                (p - expected).abs() < 1e-6 * material.instantaneous() * w,
                "t = {time}: {p} vs {expected}"
            );
        }
    }

    /// A shift moves every variable by the window's move and clears the
    /// entering cells; shifting back restores the overlap.
    #[test]
    fn shifting_moves_the_memory_with_the_road() {
        let mut memory = TreadMemory::new(tread(), 4, 2);
        let step = memory.history(1e-4).expect("history");
        let pressure: Vec<f64> = (0..8).map(|c| 1e5 * (c + 1) as f64).collect();
        memory.commit(&step, &pressure).expect("commit");
        let before = memory.clone();
        memory.shift(1, 0);
        for j in 0..2 {
            for i in 0..3 {
                assert_eq!(
                    memory.equivalent[j * 4 + i],
                    before.equivalent[j * 4 + i + 1]
                );
            }
            assert_eq!(memory.equivalent[j * 4 + 3], 0.0);
            assert_eq!(memory.branch_pressure[(j * 4 + 3) * 2], 0.0);
        }
        assert_eq!(
            memory.branch_pressure[2..4],
            before.branch_pressure[4..6],
            "branch pressures move with their cell"
        );
    }

    #[test]
    fn mismatched_lengths_are_refused() {
        let mut memory = TreadMemory::new(tread(), 2, 2);
        let step = memory.history(1e-4).expect("history");
        assert!(matches!(
            memory.commit(&step, &[0.0; 3]),
            Err(ViscoError::LengthMismatch { found: 3, .. })
        ));
        assert!(memory.history(0.0).is_err());
    }
}
