//! Every number of a scenario checked against the range where the model
//! means something, before anything is allocated or solved: an absurd value
//! is an error that names its key, never a panic, a runaway allocation, or a
//! silently wrong result.
//!
//! The ranges themselves and the single-value checks live in
//! [`super::ranges`].

use super::ScenarioError;
use super::ranges::*;
use super::rolling_spec::{RollingSpec, TreadSpec};
use super::spec::{Scenario, ShapeSpec, SynthSpec};
use crate::fidelity::Fidelity;
use crate::fidelity::under_tread::CalibrateUnder;

/// Fewest steps a rolling path may have: a spectrum needs 4 samples.
const MIN_ROLLING_STEPS: usize = 4;

/// Checks that the sections name one road, then every value of `scenario`
/// (see the module doc).
pub fn check(scenario: &Scenario) -> Result<(), ScenarioError> {
    let synthetic_road = scenario
        .rolling
        .as_ref()
        .is_some_and(|r| r.synthetic_road.is_some());
    let invalid = |what: &str| Err(ScenarioError::Invalid(what.into()));
    if scenario.texture.is_some() && !scenario.asperities.is_empty() {
        return invalid("[texture] and [[asperity]] both given: choose one");
    }
    if scenario.texture.is_some() && synthetic_road {
        return invalid("[texture] and [rolling.synthetic_road] both given: choose one");
    }
    if scenario.asperities.is_empty() && !synthetic_road && scenario.texture.is_none() {
        return invalid("no [[asperity]] given");
    }
    check_name(&scenario.name)?;
    check_fidelity(scenario)?;
    in_range(
        "[material] youngs_modulus",
        scenario.material.youngs_modulus.value(),
        MODULUS_RANGE,
        false,
        "Pa",
    )?;
    if let Some(t) = scenario.solver.tolerance {
        in_range("[solver] tolerance", t, TOLERANCE_RANGE, false, "")?;
    }
    if let Some(m) = scenario.solver.max_iterations
        && !(1..=MAX_ITERATIONS).contains(&m)
    {
        return Err(bad("[solver] max_iterations", m, "1 to 100000"));
    }
    if let Some(visco) = &scenario.material.viscoelastic {
        visco.check()?;
    }
    if let Some(shape) = &scenario.default_shape {
        check_shape("[default_shape]", shape)?;
    }
    if let Some(s) = &scenario.static_case {
        if s.loads.is_empty() && s.history.is_none() {
            return Err(bad(
                "[static] loads",
                "[]",
                "at least one load (or a [static.history])",
            ));
        }
        if let Some(history) = &s.history {
            history.samples()?;
            // Only the history is run: loads given beside it would be
            // silently dropped.
            if !s.loads.is_empty() {
                return Err(bad(
                    "[static] loads",
                    "given beside a [static.history]",
                    "either loads or a [static.history], not both (a history runs alone: \
                     give its loads as segments, or run the loads from another scenario)",
                ));
            }
        }
        for (k, w) in s.loads.iter().enumerate() {
            in_range(
                &format!("[static] loads[{k}]"),
                w.value(),
                [MIN_STATIC_LOAD, LOAD_RANGE[1]],
                false,
                "N",
            )?;
        }
    }
    let mut ids = std::collections::HashMap::new();
    for (k, a) in scenario.asperities.iter().enumerate() {
        let key = |field: &str| format!("[[asperity]] #{} {field}", k + 1);
        coordinate(&key("x"), a.x.value())?;
        coordinate(&key("y"), a.y.value())?;
        if let Some(h) = a.height {
            coordinate(&key("height"), h.value())?;
        }
        if let Some(shape) = &a.shape {
            check_shape(&key("shape"), shape)?;
        }
        let id = a.id.unwrap_or(k as u32 + 1);
        if let Some(first) = ids.insert(id, k + 1) {
            return Err(bad(
                &key("id"),
                id,
                &format!("an id no other asperity has (#{first} has it too)"),
            ));
        }
    }
    // Two summits at one point: said here by entry and id, not by the
    // solver's 0-based positions ("summits 1 and 2 coincide").
    let mut at: Vec<(u64, u64, usize)> = scenario
        .asperities
        .iter()
        .enumerate()
        .map(|(k, a)| {
            (
                (a.x.value() + 0.0).to_bits(),
                (a.y.value() + 0.0).to_bits(),
                k,
            )
        })
        .collect();
    at.sort_unstable();
    if let Some(w) = at.windows(2).find(|w| (w[0].0, w[0].1) == (w[1].0, w[1].1)) {
        let (first, second) = (w[0].2.min(w[1].2), w[0].2.max(w[1].2));
        let entry = |k: usize| {
            let a = &scenario.asperities[k];
            format!("#{} (id {})", k + 1, a.id.unwrap_or(k as u32 + 1))
        };
        let a = &scenario.asperities[first];
        return Err(ScenarioError::Invalid(format!(
            "[[asperity]] {} and {} lie at the same point (x = {} m, y = {} m): the Boussinesq \
             coupling 1/r between them is infinite; merge them or move one",
            entry(first),
            entry(second),
            a.x.value(),
            a.y.value()
        )));
    }
    if let Some(t) = &scenario.texture {
        in_range(
            "[texture] min_prominence",
            t.min_prominence.value(),
            [0.0, 1.0],
            false,
            "m",
        )?;
        in_range(
            "[texture] min_area",
            t.min_area.value(),
            [0.0, 1e2],
            false,
            "m2",
        )?;
        if let Some(c) = t.constant {
            in_range("[texture] constant", c, CONSTANT_RANGE, false, "")?;
        }
        // From 10 µm (finer than any road's grid) to a metre (no road's top).
        if let Some(w) = t.max_cap_width {
            in_range("[texture] max_cap_width", w.value(), [1e-5, 1.0], true, "m")?;
        }
        if let Some(synth) = &t.synth {
            check_synth(synth)?;
        }
    }
    if let Some(r) = &scenario.rolling {
        check_rolling(scenario, r)?;
    }
    Ok(())
}

fn check_shape(key: &str, shape: &ShapeSpec) -> Result<(), ScenarioError> {
    let constant = match shape {
        ShapeSpec::Sphere { radius, constant } => {
            size(&format!("{key} radius"), radius.value())?;
            constant
        }
        ShapeSpec::Cone {
            half_angle,
            constant,
        } => {
            let a = half_angle.value();
            if !(a.is_finite() && a > 0.0 && a < std::f64::consts::FRAC_PI_2) {
                return Err(bad(
                    &format!("{key} half_angle"),
                    format!("{a} rad"),
                    "an angle in (0, 90) deg",
                ));
            }
            constant
        }
        ShapeSpec::EllipticParaboloid {
            radius_x,
            radius_y,
            constant,
        } => {
            size(&format!("{key} radius_x"), radius_x.value())?;
            size(&format!("{key} radius_y"), radius_y.value())?;
            constant
        }
    };
    if let Some(c) = constant {
        in_range(&format!("{key} constant"), *c, CONSTANT_RANGE, false, "")?;
    }
    Ok(())
}

fn check_synth(synth: &SynthSpec) -> Result<(), ScenarioError> {
    let (nx, ny, spacing) = match synth {
        SynthSpec::Aggregate {
            nx,
            ny,
            spacing,
            coverage,
            embedding,
            ..
        } => {
            if let Some(c) = coverage {
                in_range("[texture.synth] coverage", *c, [1e-3, 10.0], false, "")?;
            }
            if let Some([lo, hi]) = embedding
                && !(lo.is_finite() && hi.is_finite() && 0.0 <= *lo && lo <= hi && *hi < 1.0)
            {
                return Err(bad(
                    "[texture.synth] embedding",
                    format!("[{lo}, {hi}]"),
                    "0 ≤ min ≤ max < 1",
                ));
            }
            (*nx, *ny, spacing.value())
        }
        SynthSpec::SelfAffine {
            nx,
            ny,
            spacing,
            rms,
            lambda_long,
            lambda_short,
            ..
        } => {
            size("[texture.synth] rms", rms.value())?;
            size("[texture.synth] lambda_long", lambda_long.value())?;
            size("[texture.synth] lambda_short", lambda_short.value())?;
            (*nx, *ny, spacing.value())
        }
        SynthSpec::TransverseTining(g)
        | SynthSpec::LongitudinalTining(g)
        | SynthSpec::BrushedConcrete(g)
        | SynthSpec::ExposedAggregate(g)
        | SynthSpec::PorousAsphalt(g)
        | SynthSpec::WornChipSeal(g)
        | SynthSpec::Pave(g) => (g.nx, g.ny, g.spacing.value()),
    };
    size("[texture.synth] spacing", spacing)?;
    if nx < 2 || ny < 2 {
        return Err(bad(
            "[texture.synth] nx, ny",
            format!("{nx} × {ny}"),
            "at least 2 × 2 points",
        ));
    }
    let points = nx as f64 * ny as f64;
    if points > MAX_MAP_POINTS {
        return Err(bad(
            "[texture.synth] nx, ny",
            format!("{nx} × {ny} = {points:e} points"),
            &format!("at most {MAX_MAP_POINTS:e} points"),
        ));
    }
    Ok(())
}

fn check_rolling(scenario: &Scenario, r: &RollingSpec) -> Result<(), ScenarioError> {
    // Sections a rolling run does not read would be silently ignored.
    if scenario.static_case.is_some() {
        return Err(bad(
            "[static]",
            "given",
            "absent in a rolling scenario (a rolling run has no static loads)",
        ));
    }
    if scenario.default_shape.is_some() && scenario.asperities.is_empty() {
        return Err(bad(
            "[default_shape]",
            "given",
            "absent unless [[asperity]] entries use it (textures and synthetic roads have their own shapes)",
        ));
    }
    if r.tolerance.is_some() && scenario.solver.tolerance.is_some() {
        return Err(bad(
            "[rolling] tolerance",
            "given with [solver] tolerance",
            "one of the two",
        ));
    }
    if let Some(t) = r.tolerance {
        in_range("[rolling] tolerance", t, TOLERANCE_RANGE, false, "")?;
    }
    coordinate("[rolling] start", r.start.value())?;
    coordinate("[rolling] end", r.end.value())?;
    size("[rolling] step", r.step.value())?;
    if let Some(l) = r.lateral {
        coordinate("[rolling] lateral", l.value())?;
    }
    if let Some(m) = r.margin {
        in_range(
            "[rolling] margin",
            m.value(),
            [0.0, SIZE_RANGE[1]],
            false,
            "m",
        )?;
    }
    let steps = (r.end.value() - r.start.value()) / r.step.value() + 1.0;
    if !(steps >= 1.0) {
        return Err(bad(
            "[rolling] end",
            format!("{:e} m", r.end.value()),
            "≥ start",
        ));
    }
    // The spectra a run ends with need four samples: refused before any
    // step is solved, not after.
    let path_steps = tyreroad_rolling::path_steps(r.start.value(), r.end.value(), r.step.value());
    if path_steps < MIN_ROLLING_STEPS as f64 {
        return Err(bad(
            "[rolling] end",
            format!(
                "{:e} m ({} step(s) of {:e} m from {:e} m)",
                r.end.value(),
                path_steps,
                r.step.value(),
                r.start.value()
            ),
            &format!(
                "a path of at least {MIN_ROLLING_STEPS} steps from start to end (the \
                 one-third-octave spectra need {MIN_ROLLING_STEPS} samples)"
            ),
        ));
    }
    // The rolling crate's own bound, checked here first so the error names the key.
    if steps > tyreroad_rolling::MAX_STEPS as f64 {
        return Err(bad(
            "[rolling] step",
            format!("{:e} m ({steps:e} steps)", r.step.value()),
            &format!(
                "a step giving at most {} steps from start to end",
                tyreroad_rolling::MAX_STEPS
            ),
        ));
    }
    in_range(
        "[rolling] speed",
        r.speed.value(),
        SPEED_RANGE,
        false,
        "m/s",
    )?;
    match r.tread {
        TreadSpec::Block { length, width } => {
            size("[rolling.tread] length", length.value())?;
            size("[rolling.tread] width", width.value())?;
        }
        TreadSpec::Tyre {
            radius_x,
            radius_y,
            length,
            width,
        } => {
            size("[rolling.tread] radius_x", radius_x.value())?;
            size("[rolling.tread] radius_y", radius_y.value())?;
            size("[rolling.tread] length", length.value())?;
            size("[rolling.tread] width", width.value())?;
        }
    }
    let c = &r.control;
    if let Some(w) = c.load {
        in_range(
            "[rolling.control] load",
            w.value(),
            [MIN_STATIC_LOAD, LOAD_RANGE[1]],
            false,
            "N",
        )?;
    }
    if let Some(d) = c.approach {
        coordinate("[rolling.control] approach", d.value())?;
    }
    if let Some(h) = c.tread_height {
        in_range(
            "[rolling.control] tread_height",
            h.value(),
            [0.0, MAX_COORDINATE],
            false,
            "m",
        )?;
    }
    if let Some(f) = r.reference_force {
        in_range(
            "[rolling] reference_force",
            f.value(),
            [MIN_REFERENCE_FORCE, LOAD_RANGE[1]],
            false,
            "N",
        )?;
    }
    if let Some(n) = r.threads {
        check_threads("[rolling] threads", n)?;
    }
    // The path's own count of steps (what the run rolls), not the ratio
    // `(end − start) / step + 1`, which rounding may put a hair under it.
    if let Some(k) = r.chunks
        && !(1.0..=path_steps).contains(&(k as f64))
    {
        return Err(bad(
            "[rolling] chunks",
            k,
            &format!("1 to the {path_steps} steps"),
        ));
    }
    if let Some(s) = r.segment
        && s < 8
    {
        return Err(bad("[rolling] segment", s, "at least 8 samples"));
    }
    let mut names = std::collections::HashSet::new();
    for (k, s) in r.sensors.iter().enumerate() {
        let key = |field: &str| format!("[[rolling.sensor]] #{} {field}", k + 1);
        let printable = !s.name.is_empty()
            && s.name.len() <= MAX_NAME_LEN
            && !s.name.chars().any(char::is_control);
        if !printable {
            return Err(bad(
                &key("name"),
                format!("{:?}", s.name),
                "1 to 100 printable characters",
            ));
        }
        if !names.insert(s.name.as_str()) {
            return Err(bad(
                &key("name"),
                format!("{:?}", s.name),
                "a name no other sensor has",
            ));
        }
        for (field, q) in [("x0", s.x0), ("x1", s.x1), ("y0", s.y0), ("y1", s.y1)] {
            coordinate(&key(field), q.value())?;
        }
        if !(s.x0.value() < s.x1.value() && s.y0.value() < s.y1.value()) {
            return Err(bad(
                &key("x0, x1, y0, y1"),
                "an empty rectangle",
                "x0 < x1 and y0 < y1",
            ));
        }
    }
    if let Some(road) = &r.synthetic_road {
        let g = road.road();
        size("[rolling.synthetic_road] length", g.length)?;
        size("[rolling.synthetic_road] width", g.width)?;
        size("[rolling.synthetic_road] min_spacing", g.min_spacing)?;
        size("[rolling.synthetic_road] radius_min", g.radius_min)?;
        size("[rolling.synthetic_road] radius_max", g.radius_max)?;
        in_range(
            "[rolling.synthetic_road] height_spread",
            g.height_spread,
            [0.0, SIZE_RANGE[1]],
            false,
            "m",
        )?;
        if g.radius_max < g.radius_min {
            return Err(bad(
                "[rolling.synthetic_road] radius_max",
                g.radius_max,
                "≥ radius_min",
            ));
        }
        in_range(
            "[rolling.synthetic_road] density",
            g.density,
            [0.0, 1e9],
            true,
            "1/m2",
        )?;
        // Both the density and the spacing bound the summit count (a disc of
        // diameter min_spacing around each).
        let area = g.length * g.width;
        let packed = area / (0.5 * g.min_spacing * g.min_spacing);
        let summits = (g.density * area).min(packed);
        // The road holds round(density · area) summits (rolling::synth):
        // none at all is a road with nothing to touch.
        if (g.density * area).round() < 1.0 {
            return Err(bad(
                "[rolling.synthetic_road] density",
                format!("{} 1/m2", g.density),
                &format!(
                    "at least one summit on the {} × {} m road (density ≥ {:.3e} 1/m2)",
                    g.length,
                    g.width,
                    0.5 / area
                ),
            ));
        }
        if summits > MAX_SYNTHETIC_SUMMITS {
            return Err(bad(
                "[rolling.synthetic_road] density",
                format!("{:e} summits", summits),
                &format!("at most {MAX_SYNTHETIC_SUMMITS:e} summits on the road"),
            ));
        }
    }
    Ok(())
}

/// `[model] fidelity`: a known rung, available, and one this kind of run
/// implements (the calibrated laws are built from a texture's caps).
pub(super) fn check_fidelity(scenario: &Scenario) -> Result<(), ScenarioError> {
    let fidelity = scenario.fidelity()?;
    if let Err(e) = fidelity.rung(&scenario.solver_options()) {
        return Err(bad(
            "[model] fidelity",
            format!("{:?}", fidelity.name()),
            &e.to_string(),
        ));
    }
    let static_texture = scenario.texture.is_some() && scenario.rolling.is_none();
    // Rolling on a texture, elastic or viscoelastic, takes calibrated laws
    // with point coupling (crate::fidelity::rolling) or coupled through
    // their fields (crate::fidelity::rolling_fields); the other coupled
    // rungs (distributed, clustered) are static only.
    let rolling_texture = scenario.texture.is_some() && scenario.rolling.is_some();
    let allowed = fidelity == Fidelity::Wilke
        || static_texture
        || (rolling_texture
            && matches!(fidelity, Fidelity::Calibrated | Fidelity::CalibratedFields));
    if !allowed {
        let expected = if rolling_texture {
            "\"wilke\", \"calibrated\" or \"calibrated_fields\" in a [rolling] run on a [texture]"
        } else {
            "\"wilke\" here: calibrated laws are built for a [texture] scenario"
        };
        return Err(bad(
            "[model] fidelity",
            format!("{:?}", fidelity.name()),
            expected,
        ));
    }
    // The tiles of a split plateau are coupled as one body, through the
    // point kernel (crate::fidelity::joint): the near-pair and the forced
    // clusters' rungs cannot take them; refused here, not at the first
    // solve that meets a split plateau.
    if matches!(fidelity, Fidelity::Distributed | Fidelity::Clustered)
        && scenario
            .texture
            .as_ref()
            .is_some_and(|t| t.max_cap_width.is_some())
    {
        return Err(bad(
            "[model] fidelity",
            format!("{:?}", fidelity.name()),
            "\"wilke\", \"calibrated\" or \"calibrated_fields\" with [texture] max_cap_width \
             (a split plateau's tiles are coupled as one body through the point kernel)",
        ));
    }
    // A tread to calibrate under exists only in a rolling run on a
    // texture's calibrated laws.
    let under = scenario.model.calibrate_under()?;
    if under != CalibrateUnder::Flat
        && !(rolling_texture
            && matches!(fidelity, Fidelity::Calibrated | Fidelity::CalibratedFields))
    {
        return Err(bad(
            "[model] calibrate_under",
            format!("{:?}", under.name()),
            "\"flat\" unless [model] fidelity is \"calibrated\" or \"calibrated_fields\" \
             in a [rolling] run on a [texture]",
        ));
    }
    // The hereditary step solves its own laws per step and does not place
    // them along the path (crate::fidelity::rolling::calibrated_rolling_road).
    if under == CalibrateUnder::TreadSlope && scenario.material.viscoelastic.is_some() {
        return Err(bad(
            "[model] calibrate_under",
            "\"tread_slope\"",
            "\"flat\" or \"tread\" on a viscoelastic tread (laws placed along the path \
             are elastic only)",
        ));
    }
    Ok(())
}

#[cfg(test)]
#[path = "check_tests.rs"]
mod tests;
