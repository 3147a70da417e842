//! The scenario file's parsing ([`super::Scenario::parse`]): the paper's
//! fixture, the texture section, and the refusals of unknown keys, units
//! and materials.
#![allow(clippy::unwrap_used)]

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
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("poisson"), "{err}");
    assert!(err.contains("line 14"), "{err}");
}

#[test]
fn unknown_shape_key_and_bad_units_are_refused() {
    let text = PAPER.replacen("radius = \"5 mm\"", "radius = \"5 mm\"\nradus = 2", 1);
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("radus"), "{err}");
    let text = PAPER.replacen("\"5 mm\"", "\"5 parsecs\"", 1);
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("unknown length unit `parsecs`"), "{err}");
}

const TEXTURE: &str = r#"
name = "tex"
[material]
youngs_modulus = "6.54 MPa"
poisson_ratio = 0.5
[static]
loads = ["50 N"]
[texture]
min_prominence = "0.2 mm"
min_area = "2 mm2"
[texture.synth]
kind = "aggregate"
nx = 100
ny = 80
spacing = "0.1 mm"
grading = "4/6"
seed = 3
"#;

#[test]
fn texture_section_parses_without_asperities() -> Result<()> {
    let s = Scenario::parse(TEXTURE, "tex")?;
    assert!(s.asperities.is_empty());
    let t = s.texture.as_ref().unwrap();
    assert_eq!(t.min_prominence.value(), 0.2e-3);
    assert!((t.min_area.value() - 2e-6).abs() < 1e-18);
    assert_eq!(t.road_options().constant, C_SPHERE);
    let map = t.height_map(Path::new("."))?;
    assert_eq!((map.nx(), map.ny()), (100, 80));
    Ok(())
}

#[test]
fn texture_unknown_keys_and_units_are_refused() {
    let text = TEXTURE.replacen("seed = 3", "seed = 3\nsed = 4", 1);
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("sed"), "{err}");
    let text = TEXTURE.replacen("min_area", "min_areas", 1);
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("min_areas"), "{err}");
    let text = TEXTURE.replacen("\"2 mm2\"", "\"2 acres\"", 1);
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("acres"), "{err}");
    let text = format!("{TEXTURE}\n[[asperity]]\nx = \"0 mm\"\ny = \"0 mm\"\n");
    let err = format!("{}", Scenario::parse(&text, "t").unwrap_err());
    assert!(err.contains("both given"), "{err}");
}

#[test]
fn invalid_material_is_refused() -> Result<()> {
    let text = PAPER.replacen("poisson_ratio = 0.5", "poisson_ratio = 0.7", 1);
    let s = Scenario::parse(&text, "t")?;
    let err = s.problem().err().map(|e| e.to_string()).unwrap_or_default();
    assert!(err.contains("Poisson"), "{err}");
    Ok(())
}
