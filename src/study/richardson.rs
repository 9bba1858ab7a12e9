//! Richardson extrapolation in the node spacing: the observed order of convergence, the
//! extrapolated value and its numerical uncertainty (Roache's grid convergence index), from a
//! quantity measured at three or more spacings.
//!
//! With f(σ) = f₀ + C·σᵖ + higher-order terms, three spacings σ₁ > σ₂ > σ₃ (any ratios) give the
//! order p from
//!
//!   (f₁ − f₂)/(f₂ − f₃) = (σ₁ᵖ − σ₂ᵖ)/(σ₂ᵖ − σ₃ᵖ),
//!
//! solved by bisection, then C = (f₂ − f₃)/(σ₂ᵖ − σ₃ᵖ) and f₀ = f₃ − C·σ₃ᵖ. The uncertainty of
//! f₀ is the grid convergence index of the finest pair, Fs·|f₂ − f₃|/(rᵖ − 1) with r = σ₂/σ₃,
//! Fs = 1.25 when the order is trustworthy (monotone convergence, 0.5 ≤ p ≤ 4). Otherwise the
//! spacings are not in the asymptotic range: no order is claimed, and the uncertainty is
//! Fs = 3 times the largest change between neighbouring spacings, with f₀ the finest value.
//! With more than three spacings, the finest three decide; the others show the trend.
//!
//! When each value is a mean over runs that scatter (lattice placements, seeds), its standard
//! error enters too ([`extrapolate_means`]): propagated through f₀ = f₃ + (f₃ − f₂)/(rᵖ − 1)
//! (or f₀ = f₃ without an order) and doubled (about 95 % coverage), it is added to the
//! discretisation uncertainty in quadrature.

/// Safety factor of the grid convergence index for a trustworthy observed order.
pub const SAFETY_ORDER_OBSERVED: f64 = 1.25;
/// Safety factor when no trustworthy order could be observed.
pub const SAFETY_NO_ORDER: f64 = 3.0;
/// Range of orders accepted as observed.
pub const ORDER_RANGE: (f64, f64) = (0.5, 4.0);

/// The extrapolation of one quantity.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Extrapolation {
    /// The observed order p, if the finest three spacings converge monotonically with p in
    /// [`ORDER_RANGE`].
    pub order: Option<f64>,
    /// The extrapolated value f₀ (the finest value when no order is observed).
    pub value: f64,
    /// Numerical uncertainty of `value` (same unit; a half-width).
    pub uncertainty: f64,
    /// The estimated error of the finest run, |f₃ − f₀| (same unit).
    pub finest_error: f64,
    /// The part of `uncertainty` from the scatter of the means (same unit; 0 for single runs).
    pub noise: f64,
}

/// Extrapolates `values` measured at `spacings` (m, any order, at least three distinct).
/// `None` with fewer than three spacings or a non-finite value.
pub fn extrapolate(spacings: &[f64], values: &[f64]) -> Option<Extrapolation> {
    if spacings.len() != values.len() || spacings.len() < 3 {
        return None;
    }
    let mut points: Vec<(f64, f64)> = spacings.iter().copied().zip(values.iter().copied()).collect();
    if points
        .iter()
        .any(|(s, f)| !s.is_finite() || *s <= 0.0 || !f.is_finite())
    {
        return None;
    }
    points.sort_by(|a, b| b.0.total_cmp(&a.0));
    let n = points.len();
    let [(s1, f1), (s2, f2), (s3, f3)] = [points[n - 3], points[n - 2], points[n - 1]];
    if !(s1 > s2 && s2 > s3) {
        return None;
    }
    let largest_step = points
        .windows(2)
        .map(|w| (w[0].1 - w[1].1).abs())
        .fold(0.0, f64::max);
    let unobserved = Extrapolation {
        order: None,
        value: f3,
        uncertainty: SAFETY_NO_ORDER * largest_step,
        finest_error: 0.0,
        noise: 0.0,
    };
    let (d12, d23) = (f1 - f2, f2 - f3);
    if d23 == 0.0 && d12 == 0.0 {
        return Some(Extrapolation {
            order: None,
            value: f3,
            uncertainty: 0.0,
            finest_error: 0.0,
            noise: 0.0,
        });
    }
    // Monotone convergence: both differences of one sign, shrinking towards the fine end.
    if d12 * d23 <= 0.0 {
        return Some(unobserved);
    }
    let ratio = d12 / d23;
    let model = |p: f64| (s1.powf(p) - s2.powf(p)) / (s2.powf(p) - s3.powf(p));
    let (lo, hi) = ORDER_RANGE;
    // model(p) grows with p: bisect for model(p) = ratio within the accepted range.
    if !(model(lo) <= ratio && ratio <= model(hi)) {
        return Some(unobserved);
    }
    let (mut a, mut b) = (lo, hi);
    for _ in 0..100 {
        let m = 0.5 * (a + b);
        if model(m) < ratio {
            a = m;
        } else {
            b = m;
        }
    }
    let p = 0.5 * (a + b);
    let c = d23 / (s2.powf(p) - s3.powf(p));
    let value = f3 - c * s3.powf(p);
    let r = s2 / s3;
    Some(Extrapolation {
        order: Some(p),
        value,
        uncertainty: SAFETY_ORDER_OBSERVED * d23.abs() / (r.powf(p) - 1.0),
        finest_error: (f3 - value).abs(),
        noise: 0.0,
    })
}

/// [`extrapolate`] for values that are means with standard errors `standard_errors` (same unit,
/// one per spacing): the uncertainty also covers twice the means' propagated scatter.
pub fn extrapolate_means(spacings: &[f64], values: &[f64], standard_errors: &[f64]) -> Option<Extrapolation> {
    let mut e = extrapolate(spacings, values)?;
    if standard_errors.len() != spacings.len() {
        return None;
    }
    let mut by_spacing: Vec<(f64, f64)> = spacings
        .iter()
        .copied()
        .zip(standard_errors.iter().copied())
        .collect();
    by_spacing.sort_by(|a, b| b.0.total_cmp(&a.0));
    let n = by_spacing.len();
    let [(s2, e2), (s3, e3)] = [by_spacing[n - 2], by_spacing[n - 1]];
    let variance = match e.order {
        Some(p) => {
            let g = 1.0 / ((s2 / s3).powf(p) - 1.0);
            ((1.0 + g) * e3).powi(2) + (g * e2).powi(2)
        }
        None => e3 * e3,
    };
    e.noise = 2.0 * variance.sqrt();
    e.uncertainty = e.uncertainty.hypot(e.noise);
    Some(e)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// An exact power law is extrapolated exactly, at its own order, whatever the ratios.
    #[test]
    fn a_power_law_is_recovered() {
        for p in [1.0, 1.5, 2.0, 3.0] {
            let s = [0.01, 0.0075, 0.005, 0.0025];
            let f: Vec<f64> = s.iter().map(|s: &f64| 0.4 + 30.0 * s.powf(p)).collect();
            let e = extrapolate(&s, &f).unwrap();
            assert!((e.order.unwrap() - p).abs() < 1e-9, "p = {p}: {e:?}");
            assert!((e.value - 0.4).abs() < 1e-12, "p = {p}: {e:?}");
        }
    }

    /// Oscillating values give no order and the finest value with a wide band.
    #[test]
    fn oscillation_claims_no_order() {
        let e = extrapolate(&[0.01, 0.0075, 0.005], &[0.50, 0.45, 0.47]).unwrap();
        assert_eq!(e.order, None);
        assert_eq!(e.value, 0.47);
        assert!((e.uncertainty - 3.0 * 0.05).abs() < 1e-12);
    }

    /// Differences that grow towards the fine end (divergence, or a pre-asymptotic range) give
    /// no order.
    #[test]
    fn growing_differences_claim_no_order() {
        let e = extrapolate(&[0.01, 0.0075, 0.005], &[0.52, 0.51, 0.45]).unwrap();
        assert_eq!(e.order, None);
    }

    /// The scatter of the means widens the band: an exact power law whose finest mean has a
    /// standard error of 0.01 (and the others none) gets at least twice that, scaled by the
    /// extrapolation's leverage 1 + 1/(rᵖ − 1).
    #[test]
    fn scattered_means_widen_the_band() {
        let s = [0.01, 0.0075, 0.005];
        let f: Vec<f64> = s.iter().map(|s: &f64| 0.4 + 30.0 * s * s).collect();
        let e = extrapolate_means(&s, &f, &[0.0, 0.0, 0.01]).unwrap();
        let leverage = 1.0 + 1.0 / (1.5f64.powi(2) - 1.0);
        assert!((e.noise - 2.0 * 0.01 * leverage).abs() < 1e-9, "{e:?}");
        assert!(e.uncertainty >= e.noise);
    }

    /// Too few spacings, or a repeated one, give nothing.
    #[test]
    fn three_distinct_spacings_are_needed() {
        assert_eq!(extrapolate(&[0.01, 0.005], &[0.5, 0.4]), None);
        assert_eq!(extrapolate(&[0.01, 0.005, 0.005], &[0.5, 0.4, 0.4]), None);
    }
}
