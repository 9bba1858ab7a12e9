//! Two analytic references, each run through the scene path and solved independently of the
//! simulator (`study::heavy_elastica`):
//!
//! - the cantilever bending test: a strip of thin wool clamped at its root and overhanging 2.5,
//!   3 and 4 cm (1.52, 1.83 and 2.44 bending lengths) bends under its own weight
//!   (`scenes/bending_length/cantilever_wool.ron`, its length overridden);
//! - Greenhill's heavy column: the same strip with gravity turned back along it stands upright
//!   on its clamp, straight below its critical length (1.99 bending lengths) and buckled beyond
//!   (`scenes/bending_length/heavy_column_wool.ron`).

use kes_cloth::study::{Convergence, ConvergencePlan, run_convergence};

mod common;

/// Runs `scene` (with `set`) at 5, 2.5 and 1.25 mm, each to rest.
fn converge(scene: &str, set: &[String]) -> Convergence {
    let plan = ConvergencePlan {
        spacings: vec![0.005, 0.0025, 0.00125],
        step_exponent: None,
        placements: 1,
    };
    let path = common::crate_path(scene);
    static RUNS: std::sync::atomic::AtomicUsize = std::sync::atomic::AtomicUsize::new(0);
    let tag = format!(
        "converge-{}",
        RUNS.fetch_add(1, std::sync::atomic::Ordering::Relaxed)
    );
    run_convergence(&path, set, &plan, &common::fresh_dir(&tag), 2, |_, _| {}).unwrap()
}

/// Checks that `c`'s chord converges at second order to the heavy elastica's exact angle:
/// the error shrinks with every refinement, from the same side, at an observed order in
/// [1.5, 2.5] (a first-order error fails that, since alone it halves per halving of σ); the
/// Richardson extrapolation lands on the exact angle within its own stated uncertainty and
/// within 0.2°; and the finest run is within `finest_within` (deg). Returns the exact angle.
fn assert_second_order(c: &Convergence, label: &str, finest_within: f64) -> f64 {
    let exact = c.rows[0].metrics.cantilever_exact_deg.unwrap();
    let errors: Vec<f64> = c
        .rows
        .iter()
        .map(|r| {
            assert!(
                r.metrics.settled,
                "{label}: {} mm did not settle",
                r.spacing_m * 1e3
            );
            r.metrics.cantilever_chord_deg.unwrap() - exact
        })
        .collect();
    let label = format!("{label} (exact {exact:.2}°)");
    assert!(
        errors
            .windows(2)
            .all(|w| w[1].abs() < w[0].abs() && w[0] * w[1] > 0.0),
        "{label}: errors {errors:?} (deg) do not shrink monotonically"
    );
    let e = c.cantilever_chord_deg.unwrap();
    let order = e.order.unwrap_or(f64::NAN);
    assert!(
        (1.5..=2.5).contains(&order),
        "{label}: observed order {order:.2}, errors {errors:?} (deg)"
    );
    let miss = (e.value - exact).abs();
    assert!(
        miss <= e.uncertainty && miss < 0.2,
        "{label}: extrapolated {:.3} ± {:.3}°",
        e.value,
        e.uncertainty
    );
    let finest = errors[errors.len() - 1];
    assert!(
        finest.abs() < finest_within,
        "{label}: 1.25 mm is {finest:.3}° off"
    );
    exact
}

/// At every overhang the chord converges at second order to the heavy elastica's
/// (`assert_second_order`): the first-order errors of the clamp's edge, the free end lumped as
/// a whole cell or the strip's side threads counted at full width would each fail it. The
/// 1.25 mm run is within 0.25° (the bending-length test reads 1°, about 4 % of the rigidity at
/// these overhangs; 0.25° is a quarter of that).
#[test]
fn the_cantilever_converges_at_second_order_to_the_heavy_elastica() {
    for length_m in [0.035, 0.04, 0.05] {
        let set = [format!("cloth.shape=Rectangle(warp_m: {length_m}, weft_m: 0.02)")];
        let c = converge("scenes/bending_length/cantilever_wool.ron", &set);
        let overhang = format!("overhang {:.1} cm", (length_m - 0.01) * 100.0);
        assert_second_order(&c, &overhang, 0.25);
    }
}

/// The upright strip's 4 cm (2.44 bending lengths, beyond Greenhill's critical 1.99) buckle and
/// bend over by 95° from the clamp's direction, and the chord converges to the exact one at
/// second order (`assert_second_order`). The 1.25 mm run is within 0.5°: the column's chord is
/// 3–4 times as sensitive to a length error as the cantilever's at this length (about 90°
/// against 26° per bending length), hence twice the cantilever's 0.25°, still half of the 1° the
/// bending-length test reads. Measured: 98.94 / 96.05 / 95.27° against 94.96°, order 1.88.
#[test]
fn the_heavy_column_buckles_and_converges_at_second_order_to_greenhills_elastica() {
    let c = converge("scenes/bending_length/heavy_column_wool.ron", &[]);
    let exact = assert_second_order(&c, "column of 4 cm", 0.5);
    assert!(
        (90.0..100.0).contains(&exact),
        "exact {exact}°: not the buckled column"
    );
}

/// Below Greenhill's critical length the upright strip stands straight: 3 cm (1.83 bending
/// lengths) stay within 0.5° of the clamp's direction at 5, 2.5 and 1.25 mm, although 0.1 mm of
/// seeded roughness (`perturbation_m`) starts them crooked. (Measured: 0.00, 0.00 and 0.07°; the
/// exact column is straight, and its deflection under an imperfection grows as
/// 1/(1 − (l/l_c)³), 4.4 times at this length.)
#[test]
fn a_heavy_column_below_its_critical_length_stands_straight() {
    let set = ["cloth.shape=Rectangle(warp_m: 0.04, weft_m: 0.02)".to_string()];
    let c = converge("scenes/bending_length/heavy_column_wool.ron", &set);
    for r in &c.rows {
        let chord = r.metrics.cantilever_chord_deg.unwrap();
        let exact = r.metrics.cantilever_exact_deg.unwrap();
        assert!(exact.abs() < 1e-6, "exact {exact}°: not the straight column");
        assert!(
            r.metrics.settled && chord.abs() < 0.5,
            "{} mm: {chord:.3}°",
            r.spacing_m * 1e3
        );
    }
}
