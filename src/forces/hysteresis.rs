//! Hysteresis: internal friction of bending and shear, in parallel with their elastic curves.
//!
//! Every bending spring and every trellis corner carries a friction element
//! ([`HysteresisLaw`]): the spring's moment (or the corner's shear force per length) becomes the
//! elastic mean value plus a friction value y_f that opposes the motion and reaches ±2HB/2 (or
//! ±2HG/2, ±2HG5/2) once sliding, so a KES cycle traces the measured loop. Bending elements act on
//! the signed out-of-plane curvature K_n = (Û + Ŵ)·n/σ (n the cloth's normal at the middle
//! crossing; it equals [`super::Bending`]'s K for a thread bent out of plane, and unlike K it has a
//! sign, which friction needs), corners on [`super::Trellising`]'s γ = cos ψ, with the same area
//! weights σ² and σ²/4 (`docs/model.md` §13).
//!
//! The slips are the effect's state: [`ForceGenerator::advance_state`] moves them once per step
//! to the configuration the step starts from (return mapping) and adds what the sliders
//! dissipated to [`Hysteresis::dissipated`]. Forces read the slips without changing them, so a
//! force evaluation has no side effect. Not conservative: [`ForceGenerator::energy`] is the
//! energy held in the elements' springs, and the rest of the work done on them is dissipated.

use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::{AngleClamp, add_angle_blocks, add_corner_product, angle_hessian_product};
use super::trellising::{add_crossing_forces, crossing_gammas};
use super::{
    ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation, cos_angle_gradients,
};
use crate::material::{Fabric, FrictionResponse, HysteresisLaw, Thread};

/// A trellis corner as its two links, each with the sign that points it away from the crossing.
type Corner = [(u32, f64); 2];

/// A bending spring's out-of-plane curvature and what its forces need.
struct SpringShape {
    /// K_n = (Û + Ŵ)·n/σ (m⁻¹): the curvature of the thread across the cloth, positive towards the
    /// normal; equal to the three-crossing curvature K of §4 for a thread bent out of the cloth's
    /// plane on the circle branch; 0 without a normal.
    curvature: f64,
    /// Unit vectors from the middle particle to the first and to the last.
    u: DVec3,
    w: DVec3,
    /// The cloth's unit normal at the middle particle (zero without a crossing thread).
    normal: DVec3,
}

/// Marks a missing link in [`Hysteresis`]'s crossing-thread table.
const NO_LINK: u32 = u32::MAX;

/// Friction elements on the bending springs and trellis corners of one cloth.
#[derive(Clone, Debug)]
pub struct Hysteresis {
    topology: Arc<ClothTopology>,
    /// Bending friction along [warp, weft]; `None` when bending is off.
    bending: Option<[HysteresisLaw; 2]>,
    /// Shear friction; `None` when trellising is off.
    shear: Option<HysteresisLaw>,
    /// Every trellis corner, interior crossings first (four each), then the edge corners.
    corners: Vec<Corner>,
    /// For each bending spring, the crossing thread's links at its middle particle (leaving,
    /// arriving; [`NO_LINK`] where absent), whose directions give the cloth's normal there.
    bend_cross: Vec<[u32; 2]>,
    /// Slip of each bending spring's element (m⁻¹).
    bend_slip: Vec<f64>,
    /// Slip of each corner's element (in γ, dimensionless).
    corner_slip: Vec<f64>,
    /// Energy the sliders have dissipated since the cloth was built (J).
    dissipated: f64,
}

impl Hysteresis {
    /// Friction for `topology` from the fabric's loop widths, on bending springs if `bending` and
    /// on trellis corners if `trellising`. All elements start unslipped at the initial shape.
    pub fn new(topology: Arc<ClothTopology>, fabric: &Fabric, bending: bool, trellising: bool) -> Self {
        let mut corners = Vec::with_capacity(4 * topology.full_crossings.len() + topology.corner_links.len());
        for &[up, wp, um, wm] in &topology.full_crossings {
            let (u1, w1, u2, w2) = ((up, 1.0), (wp, 1.0), (um, -1.0), (wm, -1.0));
            corners.extend([[u1, w1], [u2, w1], [u2, w2], [u1, w2]]);
        }
        for &[lu, lw] in &topology.corner_links {
            corners.push([(lu.index() as u32, lu.sign()), (lw.index() as u32, lw.sign())]);
        }
        let law = |t| HysteresisLaw::bending(fabric.bending(t));
        let bend_cross = crossing_links(&topology);
        Self {
            bend_cross,
            bending: bending.then(|| [law(Thread::Warp), law(Thread::Weft)]),
            shear: trellising.then(|| HysteresisLaw::shear(&fabric.shear)),
            bend_slip: vec![f64::NAN; topology.bend_links.len()],
            corner_slip: vec![f64::NAN; corners.len()],
            corners,
            topology,
            dissipated: 0.0,
        }
    }

    /// Energy dissipated by the sliders so far (J).
    pub fn dissipated(&self) -> f64 {
        self.dissipated
    }

    /// The friction laws along [warp, weft] for bending, if on.
    pub fn bending_laws(&self) -> Option<&[HysteresisLaw; 2]> {
        self.bending.as_ref()
    }

    /// The shear friction law, if on.
    pub fn shear_law(&self) -> Option<&HysteresisLaw> {
        self.shear.as_ref()
    }

    /// The out-of-plane curvature of bending spring `s` (see [`SpringShape`]).
    #[inline(always)]
    fn spring(&self, geometry: &ClothGeometry, s: usize) -> SpringShape {
        let [l1, l2] = self.topology.bend_links[s];
        let (u, w) = (-geometry.unit[l1 as usize], geometry.unit[l2 as usize]);
        let [out, inn] = self.bend_cross[s];
        let cross = [out, inn]
            .iter()
            .filter(|&&l| l != NO_LINK)
            .map(|&l| geometry.unit[l as usize])
            .sum::<DVec3>();
        let normal = (w - u).cross(cross).normalize_or_zero();
        // A spring standing for λσ along its thread bends over λσ (ClothTopology::bend_patch).
        let along = self.topology.bend_patch[s][1];
        SpringShape {
            curvature: (u + w).dot(normal) / (along * self.topology.spacing),
            u,
            w,
            normal,
        }
    }

    /// Adds the forces of bending element `s` carrying moment `m` (N·m/m) at `shape`:
    /// E' = σ²·m·K_n with K_n = (Û + Ŵ)·n/σ, so dE/da = σ·m·(n − (Û·n)Û)/|U|, likewise for c.
    #[inline(always)]
    fn add_bend_forces(
        &self,
        geometry: &ClothGeometry,
        s: usize,
        shape: &SpringShape,
        m: f64,
        forces: &mut ForceBuffer,
    ) {
        if m == 0.0 {
            return;
        }
        let [l1, l2] = self.topology.bend_links[s].map(|l| l as usize);
        let (u, w, n) = (shape.u, shape.w, shape.normal);
        // E' = w·λ·σ²·m·K_n with K_n over λσ: the force scales with the width w alone.
        let sm = self.topology.bend_patch[s][0] * self.topology.spacing * m;
        let de_da = sm * geometry.inv_length[l1] * (n - u.dot(n) * u);
        let de_dc = sm * geometry.inv_length[l2] * (n - w.dot(n) * w);
        // Link a→b carries −(force on a) at b; link b→c carries the force on c.
        forces.link[l1] += de_da;
        forces.link[l2] -= de_dc;
    }

    fn bend_response(&self, laws: &[HysteresisLaw; 2], s: usize, k: f64) -> FrictionResponse {
        let law = &laws[self.topology.bend_thread(s) as usize];
        let slip = self.bend_slip[s];
        law.respond(k, if slip.is_nan() { k } else { slip })
    }

    fn corner_gamma(geometry: &ClothGeometry, [(lu, su), (lw, sw)]: Corner) -> (f64, DVec3, DVec3) {
        let (u, w) = (su * geometry.unit[lu as usize], sw * geometry.unit[lw as usize]);
        (u.dot(w), u, w)
    }

    fn corner_response(&self, law: &HysteresisLaw, i: usize, gamma: f64) -> FrictionResponse {
        let slip = self.corner_slip[i];
        law.respond(gamma, if slip.is_nan() { gamma } else { slip })
    }
}

impl ForceGenerator for Hysteresis {
    fn effect(&self) -> &'static str {
        "hysteresis"
    }

    fn energy(&self, geometry: &ClothGeometry) -> f64 {
        let sigma2 = self.topology.spacing * self.topology.spacing;
        let mut e = 0.0;
        if let Some(laws) = &self.bending {
            for s in 0..self.bend_slip.len() {
                let k = self.spring(geometry, s).curvature;
                let law = &laws[self.topology.bend_thread(s) as usize];
                let [across, along] = self.topology.bend_patch[s];
                e += across * along * sigma2 * law.stored_energy(self.bend_response(laws, s, k).value);
            }
        }
        if let Some(law) = &self.shear {
            for (i, &corner) in self.corners.iter().enumerate() {
                let gamma = Self::corner_gamma(geometry, corner).0;
                e += 0.25 * sigma2 * law.stored_energy(self.corner_response(law, i, gamma).value);
            }
        }
        e
    }

    fn add_forces(&self, geometry: &ClothGeometry, _velocities: &[DVec3], forces: &mut ForceBuffer) {
        if let Some(laws) = &self.bending {
            for s in 0..self.bend_slip.len() {
                let shape = self.spring(geometry, s);
                if shape.normal != DVec3::ZERO {
                    let m = self.bend_response(laws, s, shape.curvature).value;
                    self.add_bend_forces(geometry, s, &shape, m, forces);
                }
            }
        }
        if let Some(law) = &self.shear {
            let q = 0.25 * self.topology.spacing * self.topology.spacing;
            let (unit, inv) = (&geometry.unit, &geometry.inv_length);
            // Interior crossings four corners at a time, as trellising does; then edge corners.
            let full = &self.topology.full_crossings;
            for (c, &crossing) in full.iter().enumerate() {
                let [up, wp, um, wm] = crossing.map(|l| l as usize);
                let vectors = [unit[up], unit[wp], -unit[um], -unit[wm]];
                let gammas = crossing_gammas(vectors);
                let values = [0, 1, 2, 3].map(|k| q * self.corner_response(law, 4 * c + k, gammas[k]).value);
                add_crossing_forces(inv, crossing, vectors, gammas, values, forces);
            }
            for (i, &corner) in self.corners.iter().enumerate().skip(4 * full.len()) {
                let [(lu, su), (lw, sw)] = corner;
                let (gamma, u, w) = Self::corner_gamma(geometry, corner);
                let de_dgamma = q * self.corner_response(law, i, gamma).value;
                if de_dgamma != 0.0 {
                    let (lu, lw) = (lu as usize, lw as usize);
                    let (_, grad_a, grad_c) = cos_angle_gradients(u, w, inv[lu], inv[lw]);
                    // −dE/dγ·∇γ on the neighbours; the sign maps them onto the links' second ends.
                    forces.link[lu] -= su * de_dgamma * grad_a;
                    forces.link[lw] -= sw * de_dgamma * grad_c;
                }
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
        let clamp = AngleClamp::for_definite(definite);
        let (unit, inv, d) = (&geometry.unit, &geometry.inv_length, &dx.link);
        if let Some(laws) = &self.bending {
            // A sticking element acts like a linear bending spring of rigidity k_f (dE/dc = k_f,
            // exact for an unslipped element bent out of plane on the circle branch).
            for (s, &[l1, l2]) in self.topology.bend_links.iter().enumerate() {
                let (l1, l2) = (l1 as usize, l2 as usize);
                let shape = self.spring(geometry, s);
                if shape.normal == DVec3::ZERO {
                    continue;
                }
                let (u, w) = (shape.u, shape.w);
                let r = self.bend_response(laws, s, shape.curvature);
                let law = &laws[self.topology.bend_thread(s) as usize];
                // A sliding element's moment is constant; only its direction turns with the
                // thread, a small term left out of the matrix.
                if !r.sticking {
                    continue;
                }
                let [across, along] = self.topology.bend_patch[s];
                let f1 = law.stick_stiffness * across / along;
                let (hu, hw) =
                    angle_hessian_product((u, w), (inv[l1], inv[l2]), (f1, 0.0), (-d[l1], d[l2]), clamp);
                out.link[l1] -= scale * hu;
                out.link[l2] += scale * hw;
            }
        }
        if let Some(law) = &self.shear {
            let q = 0.25 * self.topology.spacing * self.topology.spacing;
            for (i, &[(lu, su), (lw, sw)]) in self.corners.iter().enumerate() {
                let (lu, lw) = (lu as usize, lw as usize);
                let r = self.corner_response(law, i, (su * unit[lu]).dot(sw * unit[lw]));
                let slope = if r.sticking { law.stick_stiffness } else { 0.0 };
                let tangent = (q * r.value, q * slope);
                add_corner_product(geometry, dx, ((lu, su), (lw, sw)), tangent, scale, clamp, out);
            }
        }
    }

    fn add_stiffness_blocks(&self, geometry: &ClothGeometry, scale: f64, matrix: &mut LinkMatrix) {
        if let Some(laws) = &self.bending {
            for s in 0..self.topology.bend_links.len() {
                let shape = self.spring(geometry, s);
                if shape.normal == DVec3::ZERO {
                    continue;
                }
                // Sticking elements only, as in the product.
                if self.bend_response(laws, s, shape.curvature).sticking {
                    let [across, along] = self.topology.bend_patch[s];
                    let f1 = laws[self.topology.bend_thread(s) as usize].stick_stiffness * across / along;
                    add_angle_blocks(geometry, matrix, matrix.bend_slot(s), (f1, 0.0), scale);
                }
            }
        }
        if let Some(law) = &self.shear {
            let q = 0.25 * self.topology.spacing * self.topology.spacing;
            let unit = &geometry.unit;
            for (i, &[(lu, su), (lw, sw)]) in self.corners.iter().enumerate() {
                let r = self.corner_response(law, i, (su * unit[lu as usize]).dot(sw * unit[lw as usize]));
                let slope = if r.sticking { law.stick_stiffness } else { 0.0 };
                add_angle_blocks(
                    geometry,
                    matrix,
                    matrix.corner_slot(i),
                    (q * r.value, q * slope),
                    scale,
                );
            }
        }
    }

    fn advance_state(&mut self, geometry: &ClothGeometry) {
        let sigma2 = self.topology.spacing * self.topology.spacing;
        let mut dissipated = 0.0;
        if let Some(laws) = &self.bending {
            for s in 0..self.bend_slip.len() {
                let k = self.spring(geometry, s).curvature;
                let r = self.bend_response(laws, s, k);
                let old = self.bend_slip[s];
                if !old.is_nan() {
                    let [across, along] = self.topology.bend_patch[s];
                    dissipated += across * along * sigma2 * r.value.abs() * (r.slip - old).abs();
                }
                self.bend_slip[s] = r.slip;
            }
        }
        if let Some(law) = &self.shear {
            for i in 0..self.corners.len() {
                let gamma = Self::corner_gamma(geometry, self.corners[i]).0;
                let r = self.corner_response(law, i, gamma);
                let old = self.corner_slip[i];
                if !old.is_nan() {
                    dissipated += 0.25 * sigma2 * r.value.abs() * (r.slip - old).abs();
                }
                self.corner_slip[i] = r.slip;
            }
        }
        self.dissipated += dissipated;
    }

    /// Every bending spring's slip (m⁻¹), every corner's (dimensionless), then the energy
    /// dissipated (J); a slip is NaN before its element's first step.
    fn state(&self) -> Option<Vec<f64>> {
        let mut state = Vec::with_capacity(self.bend_slip.len() + self.corner_slip.len() + 1);
        state.extend_from_slice(&self.bend_slip);
        state.extend_from_slice(&self.corner_slip);
        state.push(self.dissipated);
        Some(state)
    }

    fn restore_state(&mut self, state: &[f64]) -> bool {
        let (bends, corners) = (self.bend_slip.len(), self.corner_slip.len());
        if state.len() != bends + corners + 1 {
            return false;
        }
        self.bend_slip.copy_from_slice(&state[..bends]);
        self.corner_slip.copy_from_slice(&state[bends..bends + corners]);
        self.dissipated = state[bends + corners];
        true
    }
}

/// For each bending spring, the links of the crossing thread at its middle particle: the one
/// leaving it and the one arriving at it (both oriented along the grid), [`NO_LINK`] where absent.
fn crossing_links(topology: &ClothTopology) -> Vec<[u32; 2]> {
    let n = topology.particle_count;
    // Per particle: [leaving, arriving] link of each thread direction.
    let mut at = vec![[[NO_LINK; 2]; 2]; n];
    for (l, &[p, q]) in topology.links.iter().enumerate() {
        let thread = usize::from(l >= topology.warp_link_count);
        at[p as usize][thread][0] = l as u32;
        at[q as usize][thread][1] = l as u32;
    }
    topology
        .bend_particles
        .iter()
        .enumerate()
        .map(|(s, &[_, b, _])| {
            let other = 1 - topology.bend_thread(s) as usize;
            at[b as usize][other]
        })
        .collect()
}
