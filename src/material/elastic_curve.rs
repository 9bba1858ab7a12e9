//! Elastic (mean) response curves y(x) of a fabric: M(K) for bending, F(φ) for shear.
//!
//! A curve is odd (y(−x) = −y(x)), passes through the origin and is non-decreasing. It is either
//! linear (generated from a KES summary slope) or a monotone cubic Hermite interpolant through
//! measured samples (Steffen 1990): continuous with a continuous first derivative everywhere,
//! never overshooting the data. Beyond the last sample it continues as a straight line with the
//! end slope (documented in `docs/model.md`): KES bending data stop at 2.5 cm⁻¹ and shear data at
//! 8°, and a tight fold or large shear needs *some* stated law there.
//!
//! Energies need the integral Y(x) = ∫₀ˣ y dx', which is computed exactly (cubic segments
//! integrate in closed form), so forces are the exact gradient of the energies.

/// An odd, monotone, C¹ curve y(x) with its exact integral; x and y in SI.
#[derive(Clone, Debug, PartialEq)]
pub struct ElasticCurve {
    shape: CurveShape,
}

#[derive(Clone, Debug, PartialEq)]
enum CurveShape {
    /// y = slope · x.
    Linear { slope: f64 },
    /// Monotone Hermite cubic through `x[i], y[i]` with slopes `m[i]`, `x[0] = 0`, `y[0] = 0`.
    Sampled {
        x: Vec<f64>,
        y: Vec<f64>,
        m: Vec<f64>,
        /// ∫₀^{x[i]} y dx, for the energy.
        integral_at: Vec<f64>,
    },
}

/// Why samples cannot form an elastic curve. The caller adds the file and field.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
pub enum CurveSampleError {
    /// Fewer than two samples (the origin counts).
    #[error("needs at least one sample with x > 0")]
    TooFewSamples,
    /// A non-finite coordinate.
    #[error("sample {index} is not a finite number")]
    NotFinite {
        /// Index of the offending sample.
        index: usize,
    },
    /// x not strictly increasing or negative.
    #[error("sample {index}: x must be ≥ 0 and strictly increasing")]
    XNotIncreasing {
        /// Index of the offending sample.
        index: usize,
    },
    /// y decreasing: an elastic curve must be monotone.
    #[error("sample {index}: y must not decrease (the elastic curve is monotone)")]
    YDecreasing {
        /// Index of the offending sample.
        index: usize,
    },
    /// A sample at x = 0 with y ≠ 0: the elastic curve passes through the origin.
    #[error("the elastic (mean) curve must pass through the origin: y(0) = 0")]
    NotThroughOrigin,
}

impl ElasticCurve {
    /// The straight line y = slope · x (slope ≥ 0, SI units of y per unit of x).
    pub fn linear(slope: f64) -> Self {
        Self {
            shape: CurveShape::Linear { slope },
        }
    }

    /// A monotone C¹ interpolant through samples (x ≥ 0 increasing, y non-decreasing).
    /// The origin is added when the first sample has x > 0; negative x follow by odd symmetry.
    pub fn from_samples(samples: &[(f64, f64)]) -> Result<Self, CurveSampleError> {
        let mut x = Vec::with_capacity(samples.len() + 1);
        let mut y = Vec::with_capacity(samples.len() + 1);
        for (index, &(xi, yi)) in samples.iter().enumerate() {
            if !xi.is_finite() || !yi.is_finite() {
                return Err(CurveSampleError::NotFinite { index });
            }
            if index == 0 {
                if xi < 0.0 {
                    return Err(CurveSampleError::XNotIncreasing { index });
                }
                if xi == 0.0 && yi != 0.0 {
                    return Err(CurveSampleError::NotThroughOrigin);
                }
                if xi > 0.0 {
                    if yi < 0.0 {
                        return Err(CurveSampleError::YDecreasing { index });
                    }
                    x.push(0.0);
                    y.push(0.0);
                }
            } else {
                let (px, py) = samples[index - 1];
                if xi <= px {
                    return Err(CurveSampleError::XNotIncreasing { index });
                }
                if yi < py {
                    return Err(CurveSampleError::YDecreasing { index });
                }
            }
            x.push(xi);
            y.push(yi);
        }
        if x.len() < 2 {
            return Err(CurveSampleError::TooFewSamples);
        }
        let m = steffen_slopes(&x, &y);
        let mut integral_at = vec![0.0; x.len()];
        for i in 0..x.len() - 1 {
            let h = x[i + 1] - x[i];
            integral_at[i + 1] =
                integral_at[i] + h * (y[i] + y[i + 1]) / 2.0 + h * h * (m[i] - m[i + 1]) / 12.0;
        }
        Ok(Self {
            shape: CurveShape::Sampled { x, y, m, integral_at },
        })
    }

    /// The slope if the curve is a straight line y = slope·x (lets hot loops specialise).
    pub fn as_linear(&self) -> Option<f64> {
        match self.shape {
            CurveShape::Linear { slope } => Some(slope),
            CurveShape::Sampled { .. } => None,
        }
    }

    /// y(x).
    #[inline]
    pub fn value(&self, x: f64) -> f64 {
        match &self.shape {
            CurveShape::Linear { slope } => slope * x,
            CurveShape::Sampled { .. } => x.signum() * self.sampled(x.abs()).0,
        }
    }

    /// dy/dx at x (the tangent stiffness).
    #[inline]
    pub fn slope(&self, x: f64) -> f64 {
        match &self.shape {
            CurveShape::Linear { slope } => *slope,
            CurveShape::Sampled { .. } => self.sampled(x.abs()).1,
        }
    }

    /// Y(x) = ∫₀ˣ y(x') dx' (even in x, ≥ 0): the energy per unit area of a deformation x.
    #[inline]
    pub fn integral(&self, x: f64) -> f64 {
        match &self.shape {
            CurveShape::Linear { slope } => 0.5 * slope * x * x,
            CurveShape::Sampled { .. } => self.sampled(x.abs()).2,
        }
    }

    /// y(x)/x, continued by the slope at 0 (finite where y is): the secant stiffness.
    #[inline]
    pub fn secant(&self, x: f64) -> f64 {
        match &self.shape {
            CurveShape::Linear { slope } => *slope,
            CurveShape::Sampled { m, .. } => {
                if x.abs() < 1e-12 {
                    m[0]
                } else {
                    self.value(x) / x
                }
            }
        }
    }

    /// The largest tangent stiffness dy/dx over |x| ≤ `x_max` (for time-step bounds).
    pub fn max_slope(&self, x_max: f64) -> f64 {
        match &self.shape {
            CurveShape::Linear { slope } => *slope,
            CurveShape::Sampled { x, m, .. } => {
                // Hermite slopes peak at knots or inside segments; sample densely and at knots.
                let mut best = m
                    .iter()
                    .zip(x)
                    .filter(|(_, xi)| **xi <= x_max)
                    .map(|(mi, _)| *mi)
                    .fold(0.0, f64::max);
                for k in 0..=256 {
                    best = best.max(self.slope(x_max * k as f64 / 256.0));
                }
                best
            }
        }
    }

    /// Value, slope and integral at x ≥ 0 on a sampled curve.
    fn sampled(&self, x: f64) -> (f64, f64, f64) {
        let CurveShape::Sampled {
            x: xs,
            y,
            m,
            integral_at,
        } = &self.shape
        else {
            unreachable!("only called on sampled curves")
        };
        let last = xs.len() - 1;
        if x >= xs[last] {
            let d = x - xs[last];
            return (
                y[last] + m[last] * d,
                m[last],
                integral_at[last] + y[last] * d + 0.5 * m[last] * d * d,
            );
        }
        let i = xs.partition_point(|&xi| xi <= x).saturating_sub(1).min(last - 1);
        let h = xs[i + 1] - xs[i];
        let t = (x - xs[i]) / h;
        let (t2, t3) = (t * t, t * t * t);
        let h00 = 2.0 * t3 - 3.0 * t2 + 1.0;
        let h10 = t3 - 2.0 * t2 + t;
        let h01 = -2.0 * t3 + 3.0 * t2;
        let h11 = t3 - t2;
        let value = h00 * y[i] + h10 * h * m[i] + h01 * y[i + 1] + h11 * h * m[i + 1];
        let slope = ((6.0 * t2 - 6.0 * t) * y[i]
            + (3.0 * t2 - 4.0 * t + 1.0) * h * m[i]
            + (-6.0 * t2 + 6.0 * t) * y[i + 1]
            + (3.0 * t2 - 2.0 * t) * h * m[i + 1])
            / h;
        // ∫₀ᵗ of the Hermite basis, times h.
        let t4 = t2 * t2;
        let i00 = t4 / 2.0 - t3 + t;
        let i10 = t4 / 4.0 - 2.0 * t3 / 3.0 + t2 / 2.0;
        let i01 = -t4 / 2.0 + t3;
        let i11 = t4 / 4.0 - t3 / 3.0;
        let integral =
            integral_at[i] + h * (i00 * y[i] + i10 * h * m[i] + i01 * y[i + 1] + i11 * h * m[i + 1]);
        (value, slope, integral)
    }
}

/// Knot slopes of Steffen's monotone cubic interpolation (A&A 239, 443, 1990).
///
/// At x = 0 the slope is the first secant, which is what Steffen's interior rule gives when the
/// odd mirror image of the data is taken as the previous interval: the curve is then C¹ across
/// the origin.
fn steffen_slopes(x: &[f64], y: &[f64]) -> Vec<f64> {
    let n = x.len();
    let h: Vec<f64> = (0..n - 1).map(|i| x[i + 1] - x[i]).collect();
    let d: Vec<f64> = (0..n - 1).map(|i| (y[i + 1] - y[i]) / h[i]).collect();
    let mut m = vec![0.0; n];
    m[0] = d[0];
    for i in 1..n - 1 {
        let p = (d[i - 1] * h[i] + d[i] * h[i - 1]) / (h[i - 1] + h[i]);
        m[i] = if d[i - 1] * d[i] <= 0.0 {
            0.0
        } else {
            d[i - 1].signum() * d[i - 1].abs().min(d[i].abs()).min(0.5 * p.abs()) * 2.0
        };
    }
    if n == 2 {
        m[1] = d[0];
    } else {
        let (h0, h1) = (h[n - 2], h[n - 3]);
        let p = d[n - 2] * (1.0 + h0 / (h0 + h1)) - d[n - 3] * h0 / (h0 + h1);
        m[n - 1] = if p * d[n - 2] <= 0.0 {
            0.0
        } else if p.abs() > 2.0 * d[n - 2].abs() {
            2.0 * d[n - 2]
        } else {
            p
        };
    }
    m
}
