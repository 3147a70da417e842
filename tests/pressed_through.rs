//! A spike pressed through to the flat around it: a one-cell spike on a
//! flat map (a dropout in a scan) under a load its cap cannot carry. The
//! run finishes (the two-scale widening stops on the floor) and says what
//! happened, rather than hanging or answering without a word.

use tyreroad::scenario::{RunOptions, Scenario, ScenarioResult};
use tyreroad::texture::HeightMap;
use tyreroad::texture::io::text::write_ascii_grid;
use tyreroad::two_scale::LocalStatus;

type TestResult = Result<(), Box<dyn std::error::Error>>;

const SPIKE: f64 = 3e-4;

/// 10 × 10 points at 0.25 mm, flat, one point raised 0.3 mm.
fn spike_map() -> Result<HeightMap, Box<dyn std::error::Error>> {
    let mut heights = vec![0.0; 100];
    heights[5 * 10 + 5] = SPIKE;
    Ok(HeightMap::new(10, 10, 2.5e-4, 2.5e-4, heights)?)
}

#[test]
fn a_spike_pressed_to_the_flat_is_named_and_its_field_stops_on_the_floor() -> TestResult {
    let dir = tempfile::tempdir()?;
    write_ascii_grid(&spike_map()?, dir.path().join("spike.asc"))?;
    for fidelity in ["wilke", "calibrated"] {
        let text = format!(
            "name = \"spike\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [model]\nfidelity = \"{fidelity}\"\n[static]\nloads = [\"0.01 N\", \"5 N\"]\n\
             [texture]\nfile = \"spike.asc\"\nmin_prominence = \"0.1 mm\"\n\
             min_area = \"0.01 mm2\"\n"
        );
        let s = Scenario::parse(&text, "spike")?;
        let ScenarioResult::Texture(r) = s.run(&RunOptions::new(dir.path()))? else {
            return Err("not a texture result".into());
        };
        assert_eq!(r.loads.len(), 2, "{fidelity}");
        let (light, heavy) = (&r.loads[0], &r.loads[1]);
        // The light load stays on the spike.
        assert!(
            light.past_caps.is_empty(),
            "{fidelity}: {:?}",
            light.past_caps
        );
        assert_eq!(light.two_scale.fallbacks().count(), 0, "{fidelity}");
        // 5 N sinks the tread past the spike's 0.3 mm: named, with depths.
        let [past] = heavy.past_caps[..] else {
            return Err(format!("{fidelity}: {:?}", heavy.past_caps).into());
        };
        assert!(
            (past.cap_depth - SPIKE).abs() < 1e-9,
            "{fidelity}: {past:?}"
        );
        assert!(past.depth > SPIKE, "{fidelity}: {past:?}");
        // Its local field lies on the floor at the spike's foot, carrying
        // the whole load.
        let local = &heavy.two_scale.local[past.index];
        assert!(
            matches!(local.status, LocalStatus::PressedToFloor { depth } if (depth - SPIKE).abs() < 1e-9),
            "{fidelity}: {:?}",
            local.status
        );
        let map = heavy.two_scale.map.as_ref().ok_or("no map")?;
        assert!((map.integral() - 5.0).abs() < 1e-9 * 5.0, "{fidelity}");
    }
    Ok(())
}

/// `spike.asc` in `dir`: 120 × 80 points at 0.25 mm, flat, one point
/// raised 2 mm.
fn write_spike_road(dir: &std::path::Path) -> TestResult {
    let (nx, ny) = (120, 80);
    let mut heights = vec![0.0; nx * ny];
    heights[40 * nx + 60] = 2e-3;
    write_ascii_grid(
        &HeightMap::new(nx, ny, 2.5e-4, 2.5e-4, heights)?,
        dir.join("spike.asc"),
    )?;
    Ok(())
}

/// The same through a rolling run on the Wilke laws: a tyre over a 2 mm
/// spike on a flat map is told, step count and all, that the spike's law
/// was pressed past its cap (the Wilke approach there is the law's
/// extrapolation); a light tyre is not.
#[test]
fn a_tyre_sinking_a_spike_into_the_flat_is_warned_of_it() -> TestResult {
    use tyreroad::scenario::RoadSummary;
    let dir = tempfile::tempdir()?;
    write_spike_road(dir.path())?;
    let warnings = |load: &str, tread: &str| -> Result<Vec<String>, Box<dyn std::error::Error>> {
        let text = format!(
            "name = \"spike\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             {tread}[model]\nfidelity = \"wilke\"\n\
             [rolling]\nstart = \"14 mm\"\nend = \"17 mm\"\nstep = \"1 mm\"\nspeed = \"50 km/h\"\n\
             margin = \"0 mm\"\n\
             [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\n\
             length = \"20 mm\"\nwidth = \"15 mm\"\n\
             [rolling.control]\nload = \"{load}\"\n\
             [texture]\nfile = \"spike.asc\"\nmin_prominence = \"0.1 mm\"\nmin_area = \"0.01 mm2\"\n"
        );
        let s = Scenario::parse(&text, "spike")?;
        let ScenarioResult::Rolling(run) = s.run(&RunOptions::new(dir.path()))? else {
            return Err("not a rolling result".into());
        };
        let RoadSummary::Texture(t) = &run.road else {
            return Err("not a texture road".into());
        };
        Ok(t.warnings.clone())
    };
    let heavy = warnings("200 N", "")?;
    assert!(
        heavy
            .iter()
            .any(|w| w.starts_with("at 4 step(s), 4 contact(s) were pressed past")),
        "{heavy:?}"
    );
    let light = warnings("0.05 N", "")?;
    assert!(
        !light.iter().any(|w| w.contains("pressed past")),
        "{light:?}"
    );
    // Regression (2026-11-30): a viscoelastic tread (instantaneous modulus
    // 10 MPa against the laws' 6.54) was not told. Its contacts are
    // counted against the force its stiffest response gives at the cap.
    let visco = "[material.viscoelastic]\nlong_term = \"5 MPa\"\n\
                 [[material.viscoelastic.branch]]\nmodulus = \"5 MPa\"\n\
                 relaxation_time = \"1 ms\"\n";
    let heavy = warnings("200 N", visco)?;
    assert!(
        heavy.iter().any(|w| w
            .starts_with("at 4 step(s) or more, 4 contact(s) or more were pressed past")
            && w.contains("instantaneous modulus")),
        "{heavy:?}"
    );
    let light = warnings("0.05 N", visco)?;
    assert!(
        !light.iter().any(|w| w.contains("pressed past")),
        "{light:?}"
    );
    Ok(())
}

/// Regression (adversarial run, 2026-11-29): three 5 mm balls at 1000 N
/// were pressed 6 mm deep, past their equators, and the run said every
/// item converged at full fidelity. Each ball pressed past its radius is
/// now named per load; at 10 N none is.
#[test]
fn a_ball_pressed_past_its_equator_is_named() -> TestResult {
    let text = "name = \"s\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [default_shape]\nkind = \"sphere\"\nradius = \"5 mm\"\n\
                [static]\nloads = [\"10 N\", \"1000 N\"]\n\
                [[asperity]]\nid = 1\nx = \"0 mm\"\ny = \"0 mm\"\n\
                [[asperity]]\nid = 2\nx = \"12 mm\"\ny = \"0 mm\"\n\
                [[asperity]]\nid = 3\nx = \"6 mm\"\ny = \"10 mm\"\n";
    let s = Scenario::parse(text, "s")?;
    let ScenarioResult::Static(r) = s.run(&RunOptions::new("."))? else {
        return Err("not a static result".into());
    };
    assert_eq!(r.runs.len(), 2);
    assert!(r.runs[1].approach > 5e-3, "{}", r.runs[1].approach);
    assert_eq!(r.warnings.len(), 3, "{:?}", r.warnings);
    for (w, id) in r.warnings.iter().zip(1..) {
        assert!(
            w.starts_with(&format!(
                "load 1000 N, asperity {id}: a ball of radius 5.000 mm pressed "
            )) && w.contains("past its equator"),
            "{w}"
        );
    }
    Ok(())
}

/// The same spike rolled as an MPI run's rank 0 finishes it by default:
/// the records streamed into the output files as they arrive, never held
/// (`StepStream`). Regression (2026-11-30): such a run was not told; the
/// stream now counts the contacts past their caps as they pass, and the
/// finished run says what the whole run says.
#[test]
fn a_streamed_run_over_the_spike_is_warned_as_the_whole_run_is() -> TestResult {
    use tyreroad::scenario::RoadSummary;
    use tyreroad::scenario::output::OutputSet;
    use tyreroad::scenario::output::steps_stream::StepStream;
    let dir = tempfile::tempdir()?;
    write_spike_road(dir.path())?;
    let text = "name = \"spike\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
                [model]\nfidelity = \"wilke\"\n\
                [rolling]\nstart = \"14 mm\"\nend = \"17 mm\"\nstep = \"1 mm\"\n\
                speed = \"50 km/h\"\nmargin = \"0 mm\"\ncheckpoint = false\n\
                [rolling.tread]\nkind = \"tyre\"\nradius_x = \"0.3 m\"\nradius_y = \"0.5 m\"\n\
                length = \"20 mm\"\nwidth = \"15 mm\"\n\
                [rolling.control]\nload = \"200 N\"\n\
                [texture]\nfile = \"spike.asc\"\nmin_prominence = \"0.1 mm\"\n\
                min_area = \"0.01 mm2\"\n";
    let s = Scenario::parse(text, "spike")?;
    let options = RunOptions::new(dir.path());
    let warned = |road: &RoadSummary| -> Vec<String> {
        let RoadSummary::Texture(t) = road else {
            return Vec::new();
        };
        t.warnings
            .iter()
            .filter(|w| w.contains("pressed past"))
            .cloned()
            .collect()
    };
    let ScenarioResult::Rolling(whole) = s.run(&options)? else {
        return Err("not a rolling result".into());
    };
    let expected = warned(&whole.road);
    assert_eq!(expected.len(), 1, "{expected:?}");
    let mut set = OutputSet::new(dir.path().join("out"))?;
    let mut stream = StepStream::new(&mut set, &[])?;
    stream.count_past_caps(s.past_cap_tally(&options)?.ok_or("no tally")?);
    let steps = s.rolling_steps()?;
    s.roll_part_into(&options, 0..steps, 0, &mut |part| {
        part.steps.iter().try_for_each(|step| stream.push(step))
    })?;
    let signals = stream.finish(&mut set, 0.0)?;
    let streamed = s.finish_streamed(&options, signals, 0)?;
    assert_eq!(warned(&streamed.road), expected);
    Ok(())
}

/// Regression (adversarial run, 2026-11-30): balls on a rolling road pressed
/// far past their equators (an approach of 17 mm on 2–5 mm balls) ended
/// "every item converged" without a word, where a static run names them.
/// A rolling run on `[[asperity]]` balls (and on a synthetic road's) now
/// counts the contacts past their equators; a light load is not warned of.
#[test]
fn a_rolling_road_of_balls_pressed_past_their_equators_is_warned_of() -> TestResult {
    use tyreroad::scenario::RoadSummary;
    let run = |load: &str, visco: &str| -> Result<Vec<String>, Box<dyn std::error::Error>> {
        let text = format!(
            "name = \"balls\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n{visco}\
             [default_shape]\nkind = \"sphere\"\nradius = \"1 mm\"\n\
             [rolling]\nstart = \"20 mm\"\nend = \"23 mm\"\nstep = \"1 mm\"\n\
             speed = \"50 km/h\"\nmargin = \"0 mm\"\ncheckpoint = false\n\
             [rolling.tread]\nkind = \"block\"\nlength = \"60 mm\"\nwidth = \"20 mm\"\n\
             [rolling.control]\nload = \"{load}\"\n\
             [[asperity]]\nid = 1\nx = \"10 mm\"\ny = \"0 mm\"\n\
             [[asperity]]\nid = 2\nx = \"20 mm\"\ny = \"0 mm\"\n\
             [[asperity]]\nid = 3\nx = \"30 mm\"\ny = \"0 mm\"\n"
        );
        let s = Scenario::parse(&text, "balls")?;
        let ScenarioResult::Rolling(run) = s.run(&RunOptions::new("."))? else {
            return Err("not a rolling result".into());
        };
        assert!(matches!(run.road, RoadSummary::Asperities { count: 3, .. }));
        Ok(run.road.warnings().to_vec())
    };
    // Hertz at δ = R = 1 mm: (4/3) E* √R R^1.5 = 11.6 N a ball.
    let heavy = run("60 N", "")?;
    assert!(
        heavy.iter().any(|w| w
            .starts_with("at 4 step(s), 12 contact(s) were pressed past their balls' equators")),
        "{heavy:?}"
    );
    assert!(run("3 N", "")?.is_empty());
    // Regression (2026-11-30): under a viscoelastic tread the balls were
    // not counted. They are, against the force of its instantaneous
    // modulus (10 MPa against the laws' 6.54), "or more": 150 N presses
    // them past (at 60 N this stiffer tread holds them at 0.97 mm).
    let visco = "[material.viscoelastic]\nlong_term = \"5 MPa\"\n\
                 [[material.viscoelastic.branch]]\nmodulus = \"5 MPa\"\n\
                 relaxation_time = \"1 ms\"\n";
    let heavy = run("150 N", visco)?;
    assert!(
        heavy
            .iter()
            .any(|w| w.starts_with("at 4 step(s) or more, ")
                && w.contains("past their balls' equators")),
        "{heavy:?}"
    );
    assert!(run("3 N", visco)?.is_empty());
    Ok(())
}

/// Regression (adversarial run, 2026-11-30): on a rolling road of balls,
/// two summits 1 µm apart (each inside the other's patch, the point kernel
/// 1/r between them far too stiff) rolled with only the overlap note. The
/// run's road summary now warns, naming the two `[[asperity]]` entries;
/// the same balls 8 mm apart are not warned of.
#[test]
fn rolling_ball_summits_inside_each_others_patch_are_warned_of() -> TestResult {
    let run = |dx: &str| -> Result<Vec<String>, Box<dyn std::error::Error>> {
        let text = format!(
            "name = \"close\"\n[material]\nyoungs_modulus = \"6.54 MPa\"\npoisson_ratio = 0.5\n\
             [default_shape]\nkind = \"sphere\"\nradius = \"5 mm\"\n\
             [rolling]\nstart = \"20 mm\"\nend = \"23 mm\"\nstep = \"1 mm\"\n\
             speed = \"50 km/h\"\nmargin = \"5 mm\"\ncheckpoint = false\n\
             [rolling.tread]\nkind = \"block\"\nlength = \"40 mm\"\nwidth = \"30 mm\"\n\
             [rolling.control]\nload = \"20 N\"\n\
             [[asperity]]\nx = \"20 mm\"\ny = \"0 mm\"\n\
             [[asperity]]\nx = \"{dx}\"\ny = \"0 mm\"\n\
             [[asperity]]\nx = \"15 mm\"\ny = \"-5 mm\"\n"
        );
        let ScenarioResult::Rolling(run) =
            Scenario::parse(&text, "close")?.run(&RunOptions::new("."))?
        else {
            return Err("not a rolling result".into());
        };
        Ok(run.road.warnings().to_vec())
    };
    let close = run("20.001 mm")?;
    assert!(
        close.iter().any(
            |w| w.starts_with("at 4 of 4 steps, 4 pairs of ball summits")
                && w.contains("[[asperity]] #1 and [[asperity]] #2, 0.0010 mm apart")
        ),
        "{close:?}"
    );
    assert!(run("28 mm")?.is_empty());
    Ok(())
}
