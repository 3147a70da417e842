//! Scenario files: TOML, units written out ("5 mm"), unknown keys refused
//! with their name and line.

use anyhow::{Context, Result, bail};
use serde::Deserialize;
use tyreroad_asperity::{Cone, EllipticParaboloid, Sphere};
use tyreroad_contact_law::{C_CONE, C_SPHERE, ContactLaw, LocalRule, Material, PotentialLaw};
use tyreroad_multipoint::{Problem, SolverOptions};

use crate::units::{Angle, Force, Length, Pressure};

/// A law usable in a mixed set of asperities.
pub type DynLaw = Box<dyn ContactLaw + Send + Sync>;

/// Summit positions (m), summit heights (m) and laws, in file order.
pub type AsperityParts = (Vec<[f64; 2]>, Vec<f64>, Vec<DynLaw>);

/// A scenario: a tread material, asperities, and what to solve.
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    /// Short name, used for output file names.
    pub name: String,
    /// One line for reports.
    #[serde(default)]
    pub description: String,
    /// The elastic half-space.
    pub material: MaterialSpec,
    /// Solver tuning.
    #[serde(default)]
    pub solver: SolverSpec,
    /// Shape of every asperity that does not give its own.
    pub default_shape: Option<ShapeSpec>,
    /// A static contact at one or more loads.
    #[serde(rename = "static")]
    pub static_case: Option<StaticSpec>,
    /// A rolling run along a path (DESIGN §2.4).
    pub rolling: Option<crate::rolling_cmd::RollingSpec>,
    /// The asperities.
    #[serde(rename = "asperity", default)]
    pub asperities: Vec<AsperitySpec>,
}

/// `[material]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct MaterialSpec {
    /// E, e.g. "6.54 MPa".
    pub youngs_modulus: Pressure,
    /// ν.
    pub poisson_ratio: f64,
}

/// `[solver]`
#[derive(Debug, Default, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct SolverSpec {
    /// Relative residual tolerance.
    pub tolerance: Option<f64>,
    /// Newton iterations per load step.
    pub max_iterations: Option<usize>,
}

/// A shape and its law constant.
#[derive(Debug, Clone, Deserialize)]
#[serde(tag = "kind", rename_all = "snake_case", deny_unknown_fields)]
pub enum ShapeSpec {
    /// A ball of radius `radius`.
    Sphere {
        /// R.
        radius: Length,
        /// c (default 0.36).
        constant: Option<f64>,
    },
    /// A cone of half-angle `half_angle`.
    Cone {
        /// α, e.g. "60 deg".
        half_angle: Angle,
        /// c (default 0.45).
        constant: Option<f64>,
    },
    /// An elliptic paraboloid with principal radii `radius_x`, `radius_y`.
    EllipticParaboloid {
        /// Rx.
        radius_x: Length,
        /// Ry.
        radius_y: Length,
        /// c (default 0.36).
        constant: Option<f64>,
    },
}

/// `[static]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct StaticSpec {
    /// Total loads to solve at.
    pub loads: Vec<Force>,
}

/// `[[asperity]]`
#[derive(Debug, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct AsperitySpec {
    /// Label in reports (defaults to the 1-based position in the file).
    pub id: Option<u32>,
    /// Summit x.
    pub x: Length,
    /// Summit y.
    pub y: Length,
    /// Summit height (up, towards the tread; default 0).
    pub height: Option<Length>,
    /// Shape, if not the default one.
    pub shape: Option<ShapeSpec>,
}

impl Scenario {
    /// Parses a scenario; errors name the offending key and its line.
    pub fn parse(text: &str, origin: &str) -> Result<Self> {
        let scenario: Scenario =
            toml::from_str(text).with_context(|| format!("reading scenario {origin}"))?;
        let synthetic_road = scenario
            .rolling
            .as_ref()
            .is_some_and(|r| r.synthetic_road.is_some());
        if scenario.asperities.is_empty() && !synthetic_road {
            bail!("scenario {origin}: no [[asperity]] given");
        }
        Ok(scenario)
    }

    /// The material, validated.
    pub fn material(&self) -> Result<Material> {
        Material::new(
            self.material.youngs_modulus.value(),
            self.material.poisson_ratio,
        )
        .context("[material]")
    }

    /// Solver options from `[solver]` over the defaults.
    pub fn solver_options(&self) -> SolverOptions {
        let mut o = SolverOptions::default();
        if let Some(t) = self.solver.tolerance {
            o.tolerance = t;
        }
        if let Some(m) = self.solver.max_iterations {
            o.max_iterations = m;
        }
        o
    }

    /// Asperity labels, in file order.
    pub fn ids(&self) -> Vec<u32> {
        self.asperities
            .iter()
            .enumerate()
            .map(|(k, a)| a.id.unwrap_or(k as u32 + 1))
            .collect()
    }

    /// The multipoint problem: laws built, heights turned into gaps.
    pub fn problem(&self) -> Result<Problem<DynLaw>> {
        let (positions, heights, laws) = self.asperity_parts()?;
        Ok(Problem::from_heights(
            positions,
            &heights,
            laws,
            self.material()?,
        )?)
    }

    /// Summit positions, heights and laws of the `[[asperity]]` list.
    pub fn asperity_parts(&self) -> Result<AsperityParts> {
        let material = self.material()?;
        let mut positions = Vec::with_capacity(self.asperities.len());
        let mut heights = Vec::with_capacity(self.asperities.len());
        let mut laws = Vec::with_capacity(self.asperities.len());
        for (k, a) in self.asperities.iter().enumerate() {
            let shape = a
                .shape
                .as_ref()
                .or(self.default_shape.as_ref())
                .with_context(|| {
                    format!("asperity #{}: no shape, and no [default_shape]", k + 1)
                })?;
            positions.push([a.x.value(), a.y.value()]);
            heights.push(a.height.map_or(0.0, |h| h.value()));
            laws.push(build_law(shape, material).with_context(|| format!("asperity #{}", k + 1))?);
        }
        Ok((positions, heights, laws))
    }
}

fn build_law(shape: &ShapeSpec, material: Material) -> Result<DynLaw> {
    Ok(match *shape {
        ShapeSpec::Sphere { radius, constant } => {
            let law = PotentialLaw::sphere(Sphere::new(radius.value())?, material);
            Box::new(law.with_constant(constant.unwrap_or(C_SPHERE))?)
        }
        ShapeSpec::Cone {
            half_angle,
            constant,
        } => {
            let law = PotentialLaw::cone(Cone::new(half_angle.value())?, material);
            Box::new(law.with_constant(constant.unwrap_or(C_CONE))?)
        }
        ShapeSpec::EllipticParaboloid {
            radius_x,
            radius_y,
            constant,
        } => {
            let g = EllipticParaboloid::new(radius_x.value(), radius_y.value())?;
            let rule = LocalRule::Hertz {
                radius: (radius_x.value() * radius_y.value()).sqrt(),
            };
            Box::new(PotentialLaw::new(
                g,
                material,
                constant.unwrap_or(C_SPHERE),
                rule,
            )?)
        }
    })
}

#[cfg(test)]
#[allow(clippy::unwrap_used)]
mod tests {
    use super::*;

    const PAPER: &str = include_str!("../../fixtures/paper_25_spheres.toml");

    #[test]
    fn paper_fixture_parses_into_25_balls() -> Result<()> {
        let s = Scenario::parse(PAPER, "paper")?;
        assert_eq!(s.asperities.len(), 25);
        assert_eq!(s.ids(), (1..=25).collect::<Vec<_>>());
        let p = s.problem()?;
        assert_eq!(p.positions()[0], [0.02, -0.02]);
        assert_eq!(p.positions()[24], [-0.02, 0.02]);
        assert_eq!(s.material()?.youngs_modulus(), 6.54e6);
        Ok(())
    }

    #[test]
    fn unknown_key_is_named_with_its_line() {
        let text = PAPER.replacen(
            "poisson_ratio = 0.5",
            "poisson_ratio = 0.5\npoisson = 0.4",
            1,
        );
        let err = format!("{:#}", Scenario::parse(&text, "t").unwrap_err());
        assert!(err.contains("poisson"), "{err}");
        assert!(err.contains("line 14"), "{err}");
    }

    #[test]
    fn unknown_shape_key_and_bad_units_are_refused() {
        let text = PAPER.replacen("radius = \"5 mm\"", "radius = \"5 mm\"\nradus = 2", 1);
        let err = format!("{:#}", Scenario::parse(&text, "t").unwrap_err());
        assert!(err.contains("radus"), "{err}");
        let text = PAPER.replacen("\"5 mm\"", "\"5 parsecs\"", 1);
        let err = format!("{:#}", Scenario::parse(&text, "t").unwrap_err());
        assert!(err.contains("unknown length unit `parsecs`"), "{err}");
    }

    #[test]
    fn invalid_material_is_refused() -> Result<()> {
        let text = PAPER.replacen("poisson_ratio = 0.5", "poisson_ratio = 0.7", 1);
        let s = Scenario::parse(&text, "t")?;
        let err = format!(
            "{:#}",
            s.problem()
                .err()
                .unwrap_or_else(|| anyhow::anyhow!("accepted"))
        );
        assert!(err.contains("Poisson"), "{err}");
        Ok(())
    }
}
