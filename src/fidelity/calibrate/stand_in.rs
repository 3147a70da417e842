//! A stand-in table for a cap whose BEM calibration failed: the cap keeps
//! the law it had before calibration (its Wilke potential law), sampled at
//! the knots a calibration would have solved, so the run goes on with that
//! one asperity at the lower rung and says so
//! ([`crate::fidelity::CapFallback`]).
//!
//! With fields, each knot's pressure is the law's own rebuilt local contact
//! ([`ContactLaw::local_contact`]: Hertz or Sneddon's cone over the
//! equivalent disc) sampled at the centres of a square grid centred on the
//! summit, so the field coupling and the field-based sensor accounting see
//! the pressure the Wilke model would rebuild there.

use std::sync::Arc;

use tyreroad_contact_law::ContactLaw;

use super::super::field::BinnedField;
use super::{CalibratedLaw, CalibratedTable};

/// Cells kept around the largest local contact on a stand-in's grid.
const MARGIN_CELLS: usize = 1;

/// `law` tabulated at `nodes` depths `δ_max (k/n)²` (the calibration's
/// spacing) up to `max_depth` (m, > 0), with its local contacts binned on
/// a grid of `cell` (m) when `field_cell` is given.
pub(crate) fn stand_in_law(
    law: &impl ContactLaw,
    max_depth: f64,
    nodes: usize,
    field_cell: Option<f64>,
) -> CalibratedLaw {
    let n = nodes.max(4);
    let depth: Vec<f64> = std::iter::once(0.0)
        .chain((1..=n).map(|k| max_depth * (k as f64 / n as f64).powi(2)))
        .collect();
    let contacts: Vec<_> = depth
        .iter()
        .map(|&d| law.local_contact(law.force(d), d))
        .collect();
    let force = contacts.iter().map(|c| c.force).collect();
    let area = contacts.iter().map(|c| c.area()).collect();
    let mut table = CalibratedTable::from_knots(depth, force, area, false);
    let Some(cell) = field_cell.filter(|c| c.is_finite() && *c > 0.0) else {
        return CalibratedLaw::new(Arc::new(table));
    };
    let largest = contacts.iter().map(|c| c.radius).fold(0.0, f64::max);
    let half = (largest / cell).ceil() as usize + MARGIN_CELLS;
    let side = 2 * half + 1;
    let mut field = BinnedField::new(side, side, cell, cell);
    let mut pressure = vec![0.0; side * side];
    for c in &contacts {
        if !(c.force > 0.0 && c.radius > 0.0) {
            field.push_knot(None, side, cell, cell);
            continue;
        }
        for (k, p) in pressure.iter_mut().enumerate() {
            let x = (k % side) as f64 - half as f64;
            let y = (k / side) as f64 - half as f64;
            *p = c.pressure_at(cell * x.hypot(y));
        }
        // A contact smaller than a cell still presses on the summit's cell.
        if pressure.iter().all(|p| *p <= 0.0) {
            pressure[half * side + half] = c.mean_pressure();
        }
        field.push_knot(Some(&pressure), side, cell, cell);
    }
    table.field = Some(field);
    let origin = -(half as f64) * cell;
    CalibratedLaw::with_origin(Arc::new(table), [origin, origin])
}

#[cfg(test)]
mod tests {
    use super::*;
    use tyreroad_contact_law::{HertzLaw, Material};

    fn sphere_law() -> HertzLaw {
        let material = Material::new(6.54e6, 0.5).expect("material");
        HertzLaw::new(5e-3, material).expect("law")
    }

    #[test]
    fn a_stand_in_keeps_its_law_between_knots() {
        let law = sphere_law();
        let stand_in = stand_in_law(&law, 0.4e-3, 16, None);
        for k in 1..=40 {
            let d = 0.4e-3 * k as f64 / 40.0;
            let (want, got) = (law.force(d), stand_in.force(d));
            // PCHIP through 16 knots of a δ^{3/2} law.
            assert!(
                (got - want).abs() < 2e-3 * law.force(0.4e-3),
                "δ = {d}: {got} vs {want}"
            );
        }
        assert!(stand_in.table().field().is_none());
    }

    #[test]
    fn a_stand_in_field_is_the_hertz_disc_on_the_summit() {
        let law = sphere_law();
        let cell = 0.05e-3;
        let stand_in = stand_in_law(&law, 0.4e-3, 16, Some(cell));
        let d = 0.3e-3;
        let a = law.local_contact(law.force(d), d).radius;
        let field = stand_in.unit_field(d).expect("a field");
        let total: f64 = field.iter().map(|(_, w)| w).sum();
        let centroid = field
            .iter()
            .fold([0.0, 0.0], |c, (x, w)| [c[0] + w * x[0], c[1] + w * x[1]]);
        let spread: f64 = field
            .iter()
            .map(|(x, w)| w * (x[0] * x[0] + x[1] * x[1]))
            .sum();
        assert!((total - 1.0).abs() < 1e-12);
        assert!(centroid[0].abs() < 1e-3 * a && centroid[1].abs() < 1e-3 * a);
        // Hertz: ⟨r²⟩ = 2a²/5 over the pressure; bins lump a cell or two.
        let want = 0.4 * a * a;
        assert!(
            (spread - want).abs() < 0.05 * want,
            "⟨r²⟩ {spread} vs 2a²/5 = {want} (a = {a})"
        );
    }
}
