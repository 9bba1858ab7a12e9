//! Hysteresis (internal friction) of bending and shear, from the KES loop widths 2HB, 2HG, 2HG5.
//!
//! Each bending spring and each trellis corner carries a friction element in parallel with its
//! elastic mean curve: a spring of stiffness k_f in series with a Coulomb slider that yields at a
//! threshold h(x) (a Jenkins element). Its moment (or force per length) is
//! y_f = k_f·(x − s), |y_f| ≤ h(x), with s the slip, the element's internal state. Once sliding,
//! y_f = ±h(x), so the loading branch runs h above the mean curve and the unloading branch h below
//! it: a loop of width 2h, the quantity KES reports. After a reversal the element sticks until
//! y_f has crossed from +h to −h, over the *reversal span* 2h/k_f of x. The slider dissipates
//! |y_f|·|Δs| (per unit area); over a closed cycle that equals the loop's area (`docs/model.md`
//! §13).
//!
//! * Bending, x = K_n (m⁻¹): the out-of-plane curvature (Û + Ŵ)·n/σ, positive towards the cloth's normal,
//!   y in N·m/m: h = HB = 2HB/2 at every curvature. Reversal span [`BENDING_REVERSAL_SPAN`].
//! * Shear, x = γ = sin φ, y in N/m: h = 2HG/2 up to φ = 0.5°, 2HG5/2 from φ = 5°, linear in γ
//!   between. Reversal span [`SHEAR_REVERSAL_SPAN_DEG`] at the larger of the two.
//!
//! The reversal spans are model choices (KES publishes loop widths, not the shape of a
//! reversal): short enough that every KES reading point lies on a fully sliding branch of the
//! standard sweeps (±2.5 cm⁻¹, ±8°), long enough that the stick stiffness k_f stays near the
//! elastic one and the explicit step limit (§10) shrinks by at most about 1.5×.

use super::fabric::{BendingLaw, ShearLaw};

/// Curvature change (m⁻¹) over which bending friction reverses fully: 0.8 cm⁻¹.
pub const BENDING_REVERSAL_SPAN: f64 = 80.0;

/// Shear-angle change (degrees) over which shear friction reverses fully.
pub const SHEAR_REVERSAL_SPAN_DEG: f64 = 2.5;

/// A Jenkins friction element: stick stiffness and a yield threshold h(|x|).
#[derive(Clone, Debug, PartialEq)]
pub struct HysteresisLaw {
    /// k_f, stiffness while sticking (y per unit x; N·m/m per m⁻¹ = N·m for bending, N/m per
    /// unit γ for shear). 0 when the fabric has no hysteresis.
    pub stick_stiffness: f64,
    /// Threshold h (y units) at |x|: linear between these two points (x, h), constant outside.
    threshold: [(f64, f64); 2],
}

/// The friction element's answer at a given x.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FrictionResponse {
    /// y_f, the friction moment or force (y units).
    pub value: f64,
    /// The slip after the step (x units).
    pub slip: f64,
    /// Whether the element sticks (|y_f| below its threshold), i.e. its tangent is k_f, not 0.
    pub sticking: bool,
}

impl HysteresisLaw {
    /// Bending friction along one thread: half-width HB = 2HB/2 (N·m/m).
    pub fn bending(law: &BendingLaw) -> Self {
        let h = 0.5 * law.hysteresis_width;
        Self {
            stick_stiffness: 2.0 * h / BENDING_REVERSAL_SPAN,
            threshold: [(0.0, h), (0.0, h)],
        }
    }

    /// Shear friction: half-widths 2HG/2 at 0.5° and 2HG5/2 at 5° (N/m).
    pub fn shear(law: &ShearLaw) -> Self {
        let (h1, h5) = (0.5 * law.hysteresis_width_small, 0.5 * law.hysteresis_width_large);
        let span = SHEAR_REVERSAL_SPAN_DEG.to_radians();
        Self {
            stick_stiffness: 2.0 * h1.max(h5) / span,
            threshold: [(0.5_f64.to_radians().sin(), h1), (5.0_f64.to_radians().sin(), h5)],
        }
    }

    /// Whether this law ever produces a force.
    pub fn is_active(&self) -> bool {
        self.stick_stiffness > 0.0
    }

    /// The slider's threshold h (y units) at `x`.
    #[inline]
    pub fn threshold(&self, x: f64) -> f64 {
        let x = x.abs();
        let [a, b] = self.threshold;
        if x <= a.0 {
            a.1
        } else if x >= b.0 {
            b.1
        } else {
            a.1 + (b.1 - a.1) * (x - a.0) / (b.0 - a.0)
        }
    }

    /// Return mapping: the element at `x` with slip `slip` before the step.
    #[inline]
    pub fn respond(&self, x: f64, slip: f64) -> FrictionResponse {
        if !self.is_active() {
            return FrictionResponse {
                value: 0.0,
                slip: x,
                sticking: false,
            };
        }
        let trial = self.stick_stiffness * (x - slip);
        let h = self.threshold(x);
        if trial.abs() <= h {
            FrictionResponse {
                value: trial,
                slip,
                sticking: true,
            }
        } else {
            let value = h.copysign(trial);
            FrictionResponse {
                value,
                slip: x - value / self.stick_stiffness,
                sticking: false,
            }
        }
    }

    /// Energy (y·x units) held in the element's spring when it carries `value`.
    pub fn stored_energy(&self, value: f64) -> f64 {
        if self.is_active() {
            0.5 * value * value / self.stick_stiffness
        } else {
            0.0
        }
    }
}
