//! Where the deformed tread touches each cap ([`ContactSlope`]).
//!
//! Under a tyre the undeformed profile slopes by `(ξ/Rx, η/Ry)`, up to 0.2
//! at a footprint's ends, and a summit of radius `R` is first touched
//! `σ R` off it, where the gap is `½ σ² R` smaller
//! ([`crate::Tread::contact_gap`]). But the surface a cap meets is the
//! profile plus the displacement `u` the step's other contacts cause, so
//! its local slope is
//!
//! ```text
//! σ_j = ∇s(x_j) + ∇u_j,   ∇u_j = − f Σ_{i≠j} P_i (x_j − x_i) / max(r_ij, a_i + a_j)³
//! ```
//!
//! (`f = 1/(π E*)`, the point kernel's gradient; `a_i` the contact radii,
//! which floor the distance where two patches would overlap and the
//! kernel's gradient across a patch no longer stands for it). Inside a
//! footprint pressed flat the two partly cancel. With
//! [`ContactSlope::Deformed`] each step iterates its solve with the gaps
//! and contact points of [`crate::Tread::contact_gap_sloped`] at these
//! slopes until no gap moves (docs/rolling.md, "Where the tread touches a
//! cap").
//!
//! Invariants: with no other loaded contact `∇u = 0` and the profile's
//! contact point is recovered exactly; the slopes depend only on the
//! step's positions, forces and radii (not on the order or the chunking).

/// How a rolling step finds where the tread touches each cap (on a road
/// with summit radii; without radii every gap is the summit's).
///
/// Measured against the BEM (docs/validation.md, "The deformed tread's
/// slope"): on the chip seal and the dense asphalt `Deformed` brings the
/// centre sensors closer (chip seal, `calibrated` rung: 5.0 % → 2.1 % of
/// the peak), but on a field of spheres under a strongly curved tyre
/// `Profile` is the closer (0.2 % against 1.2 % of the load on the wrong
/// column), and the dense asphalt's shoulder is further off. `Profile`
/// stays the default until that is understood.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ContactSlope {
    /// The undeformed profile's slope.
    #[default]
    Profile,
    /// The profile's slope plus the gradient of the displacement the
    /// step's other contacts cause, iterated with the step's solve.
    Deformed,
}

/// `∇u_j` at each position: the displacement slope the other loaded
/// contacts cause there (module docs). `forces` and `radii` in the same
/// order as `positions`; zero forces contribute nothing. `factor` is
/// `1/(π E*)` (m/N).
pub fn deformation_slopes(
    positions: &[[f64; 2]],
    forces: &[f64],
    radii: &[f64],
    factor: f64,
) -> Vec<[f64; 2]> {
    let loaded: Vec<usize> = (0..positions.len()).filter(|&i| forces[i] > 0.0).collect();
    positions
        .iter()
        .enumerate()
        .map(|(j, pj)| {
            let mut g = [0.0, 0.0];
            for &i in &loaded {
                if i == j {
                    continue;
                }
                let d = [pj[0] - positions[i][0], pj[1] - positions[i][1]];
                let r = (d[0] * d[0] + d[1] * d[1]).sqrt().max(radii[i] + radii[j]);
                if !(r > 0.0) {
                    continue;
                }
                let k = factor * forces[i] / (r * r * r);
                g[0] -= k * d[0];
                g[1] -= k * d[1];
            }
            g
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_loaded_neighbour_tilts_the_tread_up_towards_itself() {
        // u = f P / r rises towards the neighbour: at x = 4 mm from a 10 N
        // contact the slope is −f P / r² along x.
        let f = 1e-7;
        let g = deformation_slopes(&[[0.0, 0.0], [4e-3, 0.0]], &[10.0, 0.0], &[0.0, 0.0], f);
        assert_eq!(g[0], [0.0, 0.0], "its own load does not tilt a contact");
        let expected = -f * 10.0 / (4e-3f64 * 4e-3);
        assert!((g[1][0] - expected).abs() < 1e-12 * expected.abs());
        assert_eq!(g[1][1], 0.0);
    }

    #[test]
    fn overlapping_patches_floor_the_distance_at_their_radii() {
        let f = 1e-7;
        let g = deformation_slopes(&[[0.0, 0.0], [1e-3, 0.0]], &[10.0, 5.0], &[1e-3, 1e-3], f);
        let expected = f * 10.0 * 1e-3 / (2e-3f64).powi(3);
        assert!((g[1][0] + expected).abs() < 1e-12 * expected);
        assert!((g[0][0] - 0.5 * expected).abs() < 1e-12 * expected);
    }
}
