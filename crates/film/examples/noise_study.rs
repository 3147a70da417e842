//! How the film post-processing errors grow with grain noise and blur.
//!
//! The paper's experiment (25 balls, R = 5 mm, E_eq = 6.54 MPa, ν = 0.5,
//! loads 289–500 N) with Hertz forces and radii is rendered on LLW film
//! (curve B, 25 µm pixels, 16-bit) at several grain and blur levels,
//! analysed, and compared with the exact values. Prints a Markdown table of
//! the largest |ε| over the 4 loads × 25 balls, per estimator.
//!
//! Run: `cargo run --release -p tyreroad-film --example noise_study`

use tyreroad_film::{Estimator, Result, SyntheticOptions, paper_hertz_rows, synthetic_round_trip};

fn main() -> Result<()> {
    let rows = paper_hertz_rows(&[289.0, 355.0, 419.0, 500.0], 6.54e6, 0.5, 5e-3);
    println!(
        "| grain σ_D | blur σ (px) | bits | MeanGrey max|ε_P| | max|ε_a| | PixelMean max|ε_P| | max|ε_a| | HertzFit max|ε_P| | max|ε_a| |"
    );
    println!("|---|---|---|---|---|---|---|---|---|");
    let cases = [
        (0.0, 0.0, 16),
        (0.01, 1.0, 16),
        (0.02, 1.0, 16),
        (0.05, 1.0, 16),
        (0.1, 1.0, 16),
        (0.01, 2.0, 16),
        (0.01, 4.0, 16),
        (0.01, 8.0, 16),
        (0.01, 1.0, 8),
        (0.05, 2.0, 8),
    ];
    for (grain, blur, bits) in cases {
        let mut o = SyntheticOptions::llw_default()?;
        o.render.grain_sigma = grain;
        o.render.blur_sigma_px = blur;
        o.render.bit_depth = bits;
        let res = synthetic_round_trip(&rows, &o)?;
        let worst = |e: Estimator| {
            let mut f: f64 = 0.0;
            let mut a: f64 = 0.0;
            for l in &res {
                for c in &l.by(e).indenters {
                    f = f.max(c.eps_force.abs());
                    a = a.max(c.eps_radius.abs());
                }
            }
            (100.0 * f, 100.0 * a)
        };
        let (f1, a1) = worst(Estimator::MeanGrey);
        let (f2, a2) = worst(Estimator::PixelMean);
        let (f3, a3) = worst(Estimator::HertzFit);
        println!(
            "| {grain} | {blur} | {bits} | {f1:.2} % | {a1:.2} % | {f2:.2} % | {a2:.2} % | {f3:.2} % | {a3:.2} % |"
        );
    }
    // Per load, the paper's estimator and the Hertz fit at the default
    // noise (the Table 1 the validate runner prints).
    let o = SyntheticOptions::llw_default()?;
    let res = synthetic_round_trip(&rows, &o)?;
    println!("\nDefault synthetic options, per load (mean |ε| ± sd, %):");
    println!("| P (N) | MeanGrey ε_P | ε_a | HertzFit ε_P | ε_a |");
    println!("|---|---|---|---|---|");
    for l in &res {
        let m = &l.mean_grey.table1;
        let h = &l.hertz_fit.table1;
        println!(
            "| {} | {:.2} ± {:.2} | {:.2} ± {:.2} | {:.2} ± {:.2} | {:.2} ± {:.2} |",
            l.load_n,
            100.0 * m.force.mean_abs,
            100.0 * m.force.std_abs,
            100.0 * m.radius.mean_abs,
            100.0 * m.radius.std_abs,
            100.0 * h.force.mean_abs,
            100.0 * h.force.std_abs,
            100.0 * h.radius.mean_abs,
            100.0 * h.radius.std_abs,
        );
    }
    Ok(())
}
