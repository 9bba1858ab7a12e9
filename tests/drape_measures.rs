//! The drape measures on shapes with known answers.

use std::f64::consts::{PI, TAU};

use glam::DVec2;
use kes_cloth::measure::{NODE_PROMINENCE, measure_drape, union_area};

const DISK: f64 = 0.0635;

/// A star-shaped polygon r(α) triangulated as a fan around the origin, `n` sides.
fn fan(n: usize, r: impl Fn(f64) -> f64) -> Vec<[DVec2; 3]> {
    (0..n)
        .map(|k| {
            let (a, b) = (k as f64 / n as f64 * TAU, (k + 1) as f64 / n as f64 * TAU);
            [
                DVec2::ZERO,
                DVec2::from_angle(a) * r(a),
                DVec2::from_angle(b) * r(b),
            ]
        })
        .collect()
}

/// A polygonal disk's union area equals its exact polygon area to 1e-4 (rows 0.1 mm apart):
/// the row rule, not pixels, sets the error, and it is small.
#[test]
fn union_area_of_a_polygonal_disk_is_exact_to_1e_4() {
    let n = 720;
    let r = 0.127;
    let exact = 0.5 * n as f64 * r * r * (TAU / n as f64).sin();
    let got = union_area(&fan(n, |_| r), 1e-4);
    assert!((got / exact - 1.0).abs() < 1e-4, "{got} vs {exact}");
    // Overlapping copies do not add: the union of a shape with itself is the shape.
    let mut twice = fan(n, |_| r);
    twice.extend(fan(n, |_| r));
    assert!((union_area(&twice, 1e-4) / got - 1.0).abs() < 1e-12);
}

/// A flat specimen measures DC = 1 (no drape).
#[test]
fn flat_disk_has_drape_coefficient_one() {
    let flat = fan(720, |_| 0.127);
    let m = measure_drape(&flat, &flat, DVec2::ZERO, DISK, 1e-4, 0.0);
    assert!(
        (m.drape_coefficient - 1.0).abs() < 1e-4,
        "{}",
        m.drape_coefficient
    );
    assert_eq!(m.nodes, 0, "a circle has no folds");
}

/// A cloth hanging straight down casts the disk's shadow: DC = 0.
#[test]
fn cloth_hanging_straight_down_has_drape_coefficient_zero() {
    let flat = fan(720, |_| 0.127);
    let hanging = fan(720, |_| DISK);
    let m = measure_drape(&hanging, &flat, DVec2::ZERO, DISK, 1e-4, 0.0);
    assert!(m.drape_coefficient.abs() < 1e-3, "{}", m.drape_coefficient);
}

/// An outline with k lobes of 1.5 cm amplitude has k nodes, for k = 3..12, whatever its phase
/// and its centre.
#[test]
fn k_lobed_outline_has_k_nodes() {
    let flat = fan(720, |_| 0.127);
    for k in 3..=12 {
        for phase in [0.0, 0.3, 1.1] {
            let shape: Vec<[DVec2; 3]> = fan(1440, |a| 0.10 + 0.015 * (k as f64 * a + phase).cos())
                .into_iter()
                .map(|t| t.map(|p| p + DVec2::new(0.02, -0.01)))
                .collect();
            let m = measure_drape(&shape, &flat, DVec2::new(0.02, -0.01), DISK, 1e-4, 0.0);
            assert_eq!(m.nodes, k, "k = {k}, phase {phase}");
            // The ±2° smoothing lowers a 12-lobe amplitude by 4.5 % (0.7 mm of 15 mm).
            assert!(
                (m.fold_amplitude - 0.015).abs() < 0.001,
                "amplitude {}",
                m.fold_amplitude
            );
            assert!(
                (m.max_radius - 0.115).abs() < 0.001 && (m.min_radius - 0.085).abs() < 0.001,
                "k {k}: {} {}",
                m.min_radius,
                m.max_radius
            );
        }
    }
}

/// Ripples below the prominence threshold add no nodes.
#[test]
fn noise_below_the_prominence_adds_no_nodes() {
    let flat = fan(720, |_| 0.127);
    let ripple = 0.3 * NODE_PROMINENCE;
    let shape = fan(1440, |a| {
        0.10 + 0.015 * (6.0 * a).cos() + ripple * (37.0 * a).sin() + ripple * (53.0 * a + 1.0).cos()
    });
    let m = measure_drape(&shape, &flat, DVec2::ZERO, DISK, 1e-4, 0.0);
    assert_eq!(m.nodes, 6);
    // And a plain circle with the same ripples has none.
    let shape = fan(1440, |a| 0.10 + ripple * (37.0 * a).sin());
    assert_eq!(
        measure_drape(&shape, &flat, DVec2::ZERO, DISK, 1e-4, 0.0).nodes,
        0
    );
    let _ = PI;
}
