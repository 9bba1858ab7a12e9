//! Bending along the warp and along the weft (seed eq. 2), from M(K).
//!
//! A bending spring joins three consecutive crossings a–b–c of one thread; θ is the angle at b
//! (π when straight). The thread's curvature is that of the circle through the three points,
//! K(θ) = (2/σ)·cos(θ/2), for θ > π/4. Below π/4 (a fold closing) the circle formula flattens
//! out, so the curvature is continued by
//! K(θ) = α − (π/4)·β + (π/4)²·β/θ,  α = (2/σ)cos(π/8),  β = (1/σ)sin(π/8),
//! which matches K and dK/dθ at π/4 and grows without bound as θ → 0 (the seed prints a
//! discontinuous version; see `docs/model.md`).
//!
//! Each spring stands for a σ×σ patch of cloth, so its energy is E = σ²·∫₀^K M(k) dk (J).
//! For M = B·K that is B·(1 + cos θ), independent of σ. Forces are −∇E, written through
//! c = cos θ: on the circle branch dE/dc = M(K)/K, finite even for a straight thread.
//!
//! A spring standing for a patch w·σ across by λ·σ along its thread
//! ([`ClothTopology::bend_patch`]) bends over λ·σ: its curvature is K(θ) at spacing λσ and its
//! energy w·λ·σ²·∫₀^K M(k) dk, which is (w/λ) times a whole spring's at spacing λσ (for
//! M = B·K, (w/λ)·B·(1 + cos θ)).

use std::f64::consts::FRAC_PI_4;
use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::{AngleClamp, add_angle_blocks, angle_hessian_product};
use super::{
    ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation, cos_angle_gradients,
};
use crate::material::{ElasticCurve, Fabric, Thread};

/// cos(π/4): the angle θ = π/4 where the curvature switches to its extension.
const COS_SWITCH: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Smallest angle (rad) used in the fold extension. At θ = 0 the extension is infinite; the
/// clamp keeps forces finite for a fully closed fold, which self-collision must prevent anyway.
const MIN_FOLD_ANGLE: f64 = 1e-6;

/// Curvature K (m⁻¹) of a thread whose three crossings, spaced σ (m), meet at angle θ (rad).
pub fn curvature_of_angle(theta: f64, spacing: f64) -> f64 {
    if theta > FRAC_PI_4 {
        2.0 / spacing * (theta / 2.0).cos()
    } else {
        let (alpha, beta) = extension_constants(spacing);
        alpha - FRAC_PI_4 * beta + FRAC_PI_4 * FRAC_PI_4 * beta / theta.max(MIN_FOLD_ANGLE)
    }
}

/// dK/dθ (m⁻¹ per rad) of [`curvature_of_angle`].
pub fn curvature_slope(theta: f64, spacing: f64) -> f64 {
    if theta > FRAC_PI_4 {
        -(theta / 2.0).sin() / spacing
    } else {
        let (_, beta) = extension_constants(spacing);
        let t = theta.max(MIN_FOLD_ANGLE);
        -FRAC_PI_4 * FRAC_PI_4 * beta / (t * t)
    }
}

/// d²K/dθ² (m⁻¹ per rad²) of the fold extension (θ < π/4).
fn fold_curvature_bend(theta: f64, spacing: f64) -> f64 {
    let (_, beta) = extension_constants(spacing);
    let t = theta.max(MIN_FOLD_ANGLE);
    2.0 * FRAC_PI_4 * FRAC_PI_4 * beta / (t * t * t)
}

fn extension_constants(spacing: f64) -> (f64, f64) {
    let pi_8 = std::f64::consts::PI / 8.0;
    (2.0 / spacing * pi_8.cos(), pi_8.sin() / spacing)
}

/// Bending springs along both thread directions.
#[derive(Clone, Debug)]
pub struct Bending {
    topology: Arc<ClothTopology>,
    /// M(K) along [warp, weft]: moment per width (N·m/m) of curvature (m⁻¹).
    moment: [ElasticCurve; 2],
}

impl Bending {
    /// Bending for `topology` with the fabric's elastic M(K) curves.
    pub fn new(topology: Arc<ClothTopology>, fabric: &Fabric) -> Self {
        Self {
            topology,
            moment: [
                fabric.bending(Thread::Warp).moment.clone(),
                fabric.bending(Thread::Weft).moment.clone(),
            ],
        }
    }

    /// Energy E (J) and dE/dc of one whole spring bending over `sigma` (m), c = cos θ;
    /// `sin_theta` ≥ 0.
    #[inline(always)]
    fn spring(curve: &ElasticCurve, sigma: f64, c: f64, sin_theta: f64) -> (f64, f64) {
        if c < COS_SWITCH {
            let k = 2.0 / sigma * (0.5 * (1.0 + c)).max(0.0).sqrt();
            (sigma * sigma * curve.integral(k), curve.secant(k))
        } else {
            let theta = sin_theta.atan2(c).max(MIN_FOLD_ANGLE);
            let k = curvature_of_angle(theta, sigma);
            let dk_dtheta = curvature_slope(theta, sigma);
            // dθ/dc = −1/sin θ.
            let de_dc = -sigma * sigma * curve.value(k) * dk_dtheta / sin_theta.max(MIN_FOLD_ANGLE);
            (sigma * sigma * curve.integral(k), de_dc)
        }
    }

    /// dE/dc and d²E/dc² (J) of one whole spring bending over `sigma` (m), c = cos θ;
    /// `sin_theta` ≥ 0.
    fn spring_tangent(curve: &ElasticCurve, sigma: f64, c: f64, sin_theta: f64) -> (f64, f64) {
        if c < COS_SWITCH {
            // dK/dc = 1/(σ²K): dE/dc = M/K, d²E/dc² = (M' − M/K)/(σ²K²), zero for a linear M.
            let k = 2.0 / sigma * (0.5 * (1.0 + c)).max(0.0).sqrt();
            let secant = curve.secant(k);
            let f2 = match curve.as_linear() {
                Some(_) => 0.0,
                None if k > 0.0 => (curve.slope(k) - secant) / (sigma * sigma * k * k),
                None => 0.0,
            };
            (secant, f2)
        } else {
            let theta = sin_theta.atan2(c).max(MIN_FOLD_ANGLE);
            let s = sin_theta.max(MIN_FOLD_ANGLE);
            let k = curvature_of_angle(theta, sigma);
            let (k1, k2) = (curvature_slope(theta, sigma), fold_curvature_bend(theta, sigma));
            let e_theta = sigma * sigma * curve.value(k) * k1;
            let e_theta2 = sigma * sigma * (curve.slope(k) * k1 * k1 + curve.value(k) * k2);
            // dθ/dc = −1/sin θ, d²θ/dc² = −cos θ/sin³θ.
            (-e_theta / s, e_theta2 / (s * s) - e_theta * c / (s * s * s))
        }
    }

    fn curve(&self, bend: usize) -> &ElasticCurve {
        &self.moment[self.topology.bend_thread(bend) as usize]
    }

    /// Spring `s`'s bending length λσ (m) and the factor w/λ on a whole spring's energy there.
    #[inline(always)]
    fn patch(&self, s: usize) -> (f64, f64) {
        let [across, along] = self.topology.bend_patch[s];
        (along * self.topology.spacing, across / along)
    }

    /// [`Self::spring_tangent`] of spring `s`, its patch included.
    fn tangent(&self, s: usize, c: f64, sin_theta: f64) -> (f64, f64) {
        let (sigma, scale) = self.patch(s);
        let (d1, d2) = Self::spring_tangent(self.curve(s), sigma, c, sin_theta);
        (scale * d1, scale * d2)
    }
}

impl ForceGenerator for Bending {
    fn effect(&self) -> &'static str {
        "bending"
    }

    fn energy(&self, geometry: &ClothGeometry) -> f64 {
        let topo = &self.topology;
        (0..topo.bend_links.len())
            .map(|s| {
                let [l1, l2] = topo.bend_links[s];
                let (u, w) = (-geometry.unit[l1 as usize], geometry.unit[l2 as usize]);
                let (sigma, scale) = self.patch(s);
                scale * Self::spring(self.curve(s), sigma, u.dot(w), u.cross(w).length()).0
            })
            .sum()
    }

    fn add_forces(&self, geometry: &ClothGeometry, _velocities: &[DVec3], forces: &mut ForceBuffer) {
        let topo = &*self.topology;
        let split = topo.warp_bend_count;
        for (thread, range) in [(0, 0..split), (1, split..topo.bend_links.len())] {
            let curve = &self.moment[thread];
            // For M = B·K the circle branch has dE/dc = M/K = B: no square root needed.
            let linear = curve.as_linear();
            for s in range {
                let links = topo.bend_links[s];
                let (sigma, scale) = self.patch(s);
                let (u, w) = (
                    -geometry.unit[links[0] as usize],
                    geometry.unit[links[1] as usize],
                );
                let (inv_lu, inv_lw) = (
                    geometry.inv_length[links[0] as usize],
                    geometry.inv_length[links[1] as usize],
                );
                let (c, grad_a, grad_c) = cos_angle_gradients(u, w, inv_lu, inv_lw);
                let de_dc = scale
                    * match linear {
                        Some(rigidity) if c < COS_SWITCH => rigidity,
                        // The fold branch needs sin θ; the circle branch does not.
                        _ => {
                            let sin_theta = if c < COS_SWITCH { 0.0 } else { u.cross(w).length() };
                            Self::spring(curve, sigma, c, sin_theta).1
                        }
                    };
                // Link a→b carries −(force on a) at its end b; link b→c carries the force on c.
                forces.link[links[0] as usize] += de_dc * grad_a;
                forces.link[links[1] as usize] -= de_dc * grad_c;
            }
        }
    }

    fn add_stiffness_product(
        &self,
        geometry: &ClothGeometry,
        dx: &Perturbation,
        scale: f64,
        definite: bool,
        out: &mut ForceBuffer,
    ) {
        let topo = &*self.topology;
        let clamp = AngleClamp::for_definite(definite);
        for (s, &[l1, l2]) in topo.bend_links.iter().enumerate() {
            let (l1, l2) = (l1 as usize, l2 as usize);
            let (u, w) = (-geometry.unit[l1], geometry.unit[l2]);
            let tangent = self.tangent(s, u.dot(w), u.cross(w).length());
            let (hu, hw) = angle_hessian_product(
                (u, w),
                (geometry.inv_length[l1], geometry.inv_length[l2]),
                tangent,
                (-dx.link[l1], dx.link[l2]),
                clamp,
            );
            out.link[l1] -= scale * hu;
            out.link[l2] += scale * hw;
        }
    }

    fn add_stiffness_blocks(&self, geometry: &ClothGeometry, scale: f64, matrix: &mut LinkMatrix) {
        for (s, &[l1, l2]) in self.topology.bend_links.iter().enumerate() {
            let (u, w) = (-geometry.unit[l1 as usize], geometry.unit[l2 as usize]);
            let tangent = self.tangent(s, u.dot(w), u.cross(w).length());
            add_angle_blocks(geometry, matrix, matrix.bend_slot(s), tangent, scale);
        }
    }
}
