//! One load is one item: a load whose solve cannot converge is recorded and
//! the other loads of the sweep are solved and kept
//! (`tyreroad::scenario::run_static_problem`).

use tyreroad::asperity::Sphere;
use tyreroad::contact_law::{Material, PotentialLaw};
use tyreroad::multipoint::{Clusters, Problem, SolverOptions, layouts};
use tyreroad::scenario::run_static_problem;

fn lcg(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64
}

/// `layouts::folding_field` from seed 1: the point-force model's load path
/// folds at 88 % of 100 N (crates/multipoint/tests/recovery.rs), so 100 N
/// has no solution on the branch the solver follows while 40 and 50 N do.
/// (With clusters, the solver's default last recovery, 100 N converges as
/// one merged body, crates/multipoint/tests/clusters.rs; these tests keep
/// the point model, where it fails.)
fn folding_layout() -> Result<Problem<PotentialLaw<Sphere>>, Box<dyn std::error::Error>> {
    let mut seed = 1;
    Ok(layouts::folding_field(Material::new(6.54e6, 0.5)?, || {
        lcg(&mut seed)
    })?)
}

fn point_only() -> SolverOptions {
    SolverOptions {
        clusters: Clusters::Off,
        ..SolverOptions::default()
    }
}

#[test]
fn a_load_that_cannot_converge_is_recorded_and_the_others_are_solved()
-> Result<(), Box<dyn std::error::Error>> {
    let problem = folding_layout()?;
    let ids: Vec<u32> = (1..=36).collect();
    let solved = run_static_problem(
        "folding",
        &problem,
        &ids,
        &[50.0, 100.0, 40.0],
        &point_only(),
    )?;
    let r = &solved.result;
    let solved_loads: Vec<f64> = r.runs.iter().map(|run| run.load).collect();
    assert_eq!(solved_loads, vec![50.0, 40.0]);
    assert_eq!(r.failed_loads.len(), 1);
    assert_eq!(r.failed_loads[0].0, 100.0);
    assert!(
        r.failed_loads[0].1.contains("did not converge"),
        "{}",
        r.failed_loads[0].1
    );
    // The solved loads balance, and only they have rows.
    for run in &r.runs {
        assert!((run.total - run.load).abs() <= 1e-9 * run.load);
        assert_eq!(r.at_load(run.load).len(), 36);
    }
    assert!(r.at_load(100.0).is_empty());
    // With no load solved the sweep is an error that names the load.
    let e = run_static_problem("folding", &problem, &ids, &[100.0], &point_only())
        .expect_err("nothing solved");
    assert!(e.to_string().contains("100 N"), "{e}");
    Ok(())
}
