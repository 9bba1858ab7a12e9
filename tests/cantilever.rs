//! The cantilever bending test against its analytic answer: a strip of thin wool clamped at its
//! root and overhanging 3 cm (1.83 bending lengths) bends under its own weight; the heavy
//! elastica (`study::heavy_elastica`, solved independently of the simulator) gives its chord
//! angle exactly. Run through the scene path (`scenes/bending_length/cantilever_wool.ron`).

use kes_cloth::study::{ConvergencePlan, run_convergence};

mod common;

/// At 5, 2.5 and 1.25 mm the simulated chord approaches the exact one from the same side with
/// every refinement, and the Richardson extrapolation of the three lands on the exact angle:
/// within its own stated uncertainty and within 1° (the bending-length test's resolution: 1° is
/// about 4 % of the rigidity at this overhang).
#[test]
fn the_cantilever_converges_to_the_heavy_elastica() {
    let plan = ConvergencePlan {
        spacings: vec![0.005, 0.0025, 0.00125],
        step_exponent: None,
        placements: 1,
    };
    let path = common::crate_path("scenes/bending_length/cantilever_wool.ron");
    let c = run_convergence(&path, &[], &plan, 2, |_, _| {}).unwrap();
    let exact = c.rows[0].metrics.cantilever_exact_deg.unwrap();
    let errors: Vec<f64> = c
        .rows
        .iter()
        .map(|r| {
            assert!(r.metrics.settled, "{} mm did not settle", r.spacing_m * 1e3);
            r.metrics.cantilever_chord_deg.unwrap() - exact
        })
        .collect();
    assert!(
        errors
            .windows(2)
            .all(|w| w[1].abs() < w[0].abs() && w[0] * w[1] > 0.0),
        "errors {errors:?} (deg) do not shrink monotonically"
    );
    let e = c.cantilever_chord_deg.unwrap();
    let miss = (e.value - exact).abs();
    assert!(
        miss <= e.uncertainty && miss < 1.0,
        "extrapolated {:.2} ± {:.2}°, exact {exact:.2}°",
        e.value,
        e.uncertainty
    );
}
