//! Elastic curves M(K) and F(γ): smooth inside the samples, linear beyond, exact integrals.

use kes_cloth::material::{CurveSampleError, ElasticCurve};

/// A bending-like curve with a stiff start and a softer tail, in SI (K in 1/m, M in N).
fn sampled() -> ElasticCurve {
    ElasticCurve::from_samples(&[(50.0, 0.004), (100.0, 0.006), (150.0, 0.0075), (250.0, 0.0098)]).unwrap()
}

/// The curve is continuous with a continuous first derivative at every knot: left and right
/// limits agree to 1e-6 of the value scale (finite steps of 1e-9 in x).
#[test]
fn sampled_curve_is_c1_at_knots() {
    let c = sampled();
    for &x in &[0.0, 50.0, 100.0, 150.0, 250.0] {
        let eps = 1e-9;
        assert!(
            (c.value(x + eps) - c.value(x - eps)).abs() < 1e-9,
            "value jumps at {x}"
        );
        assert!(
            (c.slope(x + eps) - c.slope(x - eps)).abs() < 1e-6 * c.slope(x).abs().max(1e-6),
            "slope jumps at {x}"
        );
    }
}

#[test]
fn sampled_curve_passes_through_samples_and_is_monotone() {
    let c = sampled();
    for &(x, y) in &[(50.0, 0.004), (100.0, 0.006), (150.0, 0.0075), (250.0, 0.0098)] {
        assert!((c.value(x) - y).abs() < 1e-15);
    }
    let mut prev = c.value(-400.0);
    for k in -400..=400 {
        let v = c.value(k as f64);
        assert!(v >= prev - 1e-15, "not monotone at {k}");
        prev = v;
    }
}

/// Odd curve: y(−x) = −y(x), so the moment opposes curvature of either sign.
#[test]
fn curve_is_odd() {
    let c = sampled();
    for x in [1.0, 42.0, 180.0, 300.0] {
        assert_eq!(c.value(-x), -c.value(x));
        assert_eq!(c.integral(-x), c.integral(x));
    }
}

/// Beyond the last sample the curve continues as a straight line with the end slope.
#[test]
fn extrapolation_is_linear_with_end_slope() {
    let c = sampled();
    let s = c.slope(250.0);
    assert!(s > 0.0);
    for x in [260.0, 400.0, 1000.0] {
        assert!((c.value(x) - (0.0098 + s * (x - 250.0))).abs() < 1e-12);
        assert_eq!(c.slope(x), s);
    }
}

/// The integral used for energies equals a fine trapezoid sum of the values (error of the
/// trapezoid rule with 200 000 steps is ~1e-11 of the result).
#[test]
fn integral_is_exact() {
    let c = sampled();
    for x_end in [30.0, 120.0, 250.0, 420.0] {
        let n = 200_000;
        let h = x_end / n as f64;
        let trapezoid: f64 = (0..n)
            .map(|i| 0.5 * h * (c.value(i as f64 * h) + c.value((i + 1) as f64 * h)))
            .sum();
        assert!(
            (c.integral(x_end) - trapezoid).abs() < 1e-9 * trapezoid,
            "at {x_end}"
        );
    }
}

#[test]
fn linear_curve_energy_is_half_slope_x_squared() {
    let c = ElasticCurve::linear(3.0);
    assert_eq!(c.value(2.0), 6.0);
    assert_eq!(c.integral(2.0), 6.0);
    assert_eq!(c.secant(0.0), 3.0);
}

#[test]
fn bad_samples_are_rejected() {
    assert_eq!(
        ElasticCurve::from_samples(&[]),
        Err(CurveSampleError::TooFewSamples)
    );
    assert_eq!(
        ElasticCurve::from_samples(&[(0.0, 0.0)]),
        Err(CurveSampleError::TooFewSamples)
    );
    assert_eq!(
        ElasticCurve::from_samples(&[(1.0, 1.0), (0.5, 2.0)]),
        Err(CurveSampleError::XNotIncreasing { index: 1 })
    );
    assert_eq!(
        ElasticCurve::from_samples(&[(1.0, 1.0), (2.0, 0.5)]),
        Err(CurveSampleError::YDecreasing { index: 1 })
    );
    assert_eq!(
        ElasticCurve::from_samples(&[(0.0, 0.1), (2.0, 0.5)]),
        Err(CurveSampleError::NotThroughOrigin)
    );
    assert_eq!(
        ElasticCurve::from_samples(&[(1.0, f64::NAN)]),
        Err(CurveSampleError::NotFinite { index: 0 })
    );
}
