//! What looks wrong with an `[[asperity]]` list's shapes, said by every
//! run on it (static, rolling, viscoelastic).

use super::{Scenario, ShapeSpec};

impl Scenario {
    /// Cones whose flanks are steeper than 45° (half-angle under
    /// [`STEEPEST_CONE`]), said once for all of them, static or rolling:
    /// Sneddon's cone, and the half-space theory under every law here,
    /// take the surface's slopes as small, and a needle's `cot α` of
    /// thousands gives approaches of metres.
    pub(crate) fn steep_cone_warning(&self) -> Option<String> {
        let steep: Vec<(u32, f64)> = self
            .ids()
            .into_iter()
            .enumerate()
            .filter_map(|(k, id)| match self.shape_of(k) {
                Ok(ShapeSpec::Cone { half_angle, .. }) if half_angle.value() < STEEPEST_CONE => {
                    Some((id, half_angle.value()))
                }
                _ => None,
            })
            .collect();
        let &(id, alpha) = steep.iter().min_by(|a, b| a.1.total_cmp(&b.1))?;
        Some(format!(
            "{} cone(s) with flanks steeper than 45°, the steepest asperity {id} (half-angle \
             {:.4e}°, flank slope cot α = {:.3e}): the half-space theory takes a surface's slopes \
             as small, so such a cone's forces and approach are no road's (half-angles of 60–85° \
             are a road's)",
            steep.len(),
            alpha.to_degrees(),
            1.0 / alpha.tan()
        ))
    }
}

/// The half-angle (rad) under which a cone's flank is steeper than 45°.
const STEEPEST_CONE: f64 = std::f64::consts::FRAC_PI_4;
