//! The fold extension of K(θ) below π/4: continuous, with a continuous slope, and unbounded.

use std::f64::consts::FRAC_PI_4;

use kes_cloth::forces::bending::{curvature_of_angle, curvature_slope};

#[test]
fn circle_branch_is_the_circle_through_three_points() {
    let sigma = 0.005;
    assert!(curvature_of_angle(std::f64::consts::PI, sigma).abs() < 1e-12);
    // θ = π/2: the three points are on a circle of radius σ/√2.
    let k = curvature_of_angle(std::f64::consts::FRAC_PI_2, sigma);
    assert!((k - std::f64::consts::SQRT_2 / sigma).abs() < 1e-9);
}

/// Value and slope agree on both sides of π/4 to 1e-9 relative (steps of 1e-10 rad).
#[test]
fn extension_is_continuous_with_continuous_slope_at_pi_over_4() {
    for sigma in [0.002, 0.005, 0.01] {
        let eps = 1e-10;
        let (below, above) = (FRAC_PI_4 - eps, FRAC_PI_4 + eps);
        let k = curvature_of_angle(FRAC_PI_4, sigma);
        assert!((curvature_of_angle(below, sigma) - curvature_of_angle(above, sigma)).abs() < 1e-9 * k);
        let s = curvature_slope(FRAC_PI_4, sigma).abs();
        assert!((curvature_slope(below, sigma) - curvature_slope(above, sigma)).abs() < 1e-8 * s);
        // The closed form of the slope at the switch: −(1/σ)·sin(π/8) = −β.
        assert!(
            (curvature_slope(FRAC_PI_4, sigma) + (std::f64::consts::PI / 8.0).sin() / sigma).abs() < 1e-9 * s
        );
    }
}

/// K grows monotonically as the fold closes and exceeds any bound.
#[test]
fn extension_grows_without_bound() {
    let sigma = 0.005;
    let mut prev = curvature_of_angle(FRAC_PI_4, sigma);
    for k in 1..50 {
        let theta = FRAC_PI_4 * 0.8f64.powi(k);
        let c = curvature_of_angle(theta, sigma);
        assert!(c > prev, "not increasing at θ = {theta}");
        prev = c;
    }
    // At θ = 1e-5 rad the radius of curvature is below 1e-4 σ.
    assert!(curvature_of_angle(1e-5, sigma) > 1e4 / sigma);
}
