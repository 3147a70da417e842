//! Scenario files fuzzed: mutated fixtures (values swapped for absurd ones,
//! lines dropped, characters replaced) must parse to a scenario or to a
//! clear error — never a panic — and a scenario that parses must build its
//! material, solver options, asperities and rolling configuration without
//! panicking either.

use proptest::prelude::*;
use tyreroad::scenario::Scenario;

const FIXTURES: [&str; 3] = [
    include_str!("../fixtures/paper_25_spheres.toml"),
    include_str!("../fixtures/texture_block_static.toml"),
    include_str!("../fixtures/rolling_tyre_dense_asphalt.toml"),
];

/// Values a careless or hostile file may hold where a quantity is expected.
const NASTY: [&str; 16] = [
    "\"1e-300 m\"",
    "\"1e300 N\"",
    "\"-5 mm\"",
    "\"0\"",
    "\"nan m\"",
    "\"inf Pa\"",
    "\"5 furlongs\"",
    "\"\"",
    "\"0.001 um\"",
    "-1",
    "0",
    "1e308",
    "18446744073709551615",
    "true",
    "[]",
    "\"../../x\"",
];

/// Every scenario that parses is exercised as far as it goes without a solve.
fn exercise(text: &str) {
    let Ok(scenario) = Scenario::parse(text, "fuzz") else {
        return;
    };
    let _ = scenario.material();
    let _ = scenario.solver_options();
    if scenario.texture.is_none() && !scenario.asperities.is_empty() {
        let _ = scenario.asperity_set();
    }
    if scenario.rolling.is_some() {
        let _ = scenario.rolling_config();
    }
}

/// The byte offsets just after each `= ` (the start of a value).
fn value_starts(text: &str) -> Vec<usize> {
    text.match_indices("= ").map(|(i, _)| i + 2).collect()
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(512))]

    #[test]
    fn swapped_values_never_panic(f in 0..FIXTURES.len(), pick in any::<prop::sample::Index>(), nasty in 0..NASTY.len()) {
        let text = FIXTURES[f];
        let starts = value_starts(text);
        let at = starts[pick.index(starts.len())];
        let end = text[at..].find('\n').map_or(text.len(), |e| at + e);
        let mutated = format!("{}{}{}", &text[..at], NASTY[nasty], &text[end..]);
        exercise(&mutated);
    }

    #[test]
    fn dropped_lines_never_panic(f in 0..FIXTURES.len(), drop in prop::collection::vec(any::<prop::sample::Index>(), 1..4)) {
        let lines: Vec<&str> = FIXTURES[f].lines().collect();
        let gone: Vec<usize> = drop.iter().map(|d| d.index(lines.len())).collect();
        let kept: Vec<&str> = lines
            .iter()
            .enumerate()
            .filter(|(k, _)| !gone.contains(k))
            .map(|(_, l)| *l)
            .collect();
        exercise(&kept.join("\n"));
    }

    #[test]
    fn replaced_characters_never_panic(f in 0..FIXTURES.len(), edits in prop::collection::vec((any::<prop::sample::Index>(), any::<char>()), 1..6)) {
        let mut chars: Vec<char> = FIXTURES[f].chars().collect();
        for (at, c) in edits {
            let k = at.index(chars.len());
            chars[k] = c;
        }
        exercise(&chars.into_iter().collect::<String>());
    }
}

#[test]
fn a_refused_value_names_its_key_and_line_or_range() {
    let text = FIXTURES[0].replacen("\"6.54 MPa\"", "\"5 furlongs\"", 1);
    let e = Scenario::parse(&text, "f").expect_err("unknown unit");
    assert!(e.to_string().contains("furlongs"), "{e}");
    let text = FIXTURES[0].replacen("\"6.54 MPa\"", "\"1e-300 Pa\"", 1);
    let e = Scenario::parse(&text, "f").expect_err("absurd modulus");
    assert!(e.to_string().contains("youngs_modulus"), "{e}");
}
