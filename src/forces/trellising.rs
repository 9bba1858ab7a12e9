//! Trellising (shear) between warp and weft at each crossing (seed eq. 3), from F(φ).
//!
//! At a crossing b the warp segment to a and the weft segment to c meet at angle ψ (π/2 at
//! rest); the shear angle is φ = π/2 − ψ, and the trellis shear measure is γ = sin φ = cos ψ,
//! the sideways travel per unit height of a trellis of inextensible threads. Each crossing has
//! up to four such corners, one per grid cell around it, and every cell has four corners, so a
//! corner stands for a quarter cell: E = (σ²/4)·∫₀^γ F dγ' (J). The torque about the corner is
//! dE/dφ = (σ²/4)·F·cos φ, the seed's "F cos φ" with a dimensionally consistent prefactor.
//! Forces are −∇E = −(σ²/4)·F(γ)·∇cos ψ: no trigonometric call in the hot loop.

use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::{AngleClamp, add_angle_blocks, add_corner_product};
use super::{
    ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation, cos_angle_gradients,
};
use crate::material::{ElasticCurve, Fabric};

/// Four trellis springs per interior crossing.
#[derive(Clone, Debug)]
pub struct Trellising {
    topology: Arc<ClothTopology>,
    /// F against γ = sin φ (N/m).
    force: ElasticCurve,
}

/// One corner: from unit vectors b→a, b→c and their inverse lengths, the energy derivative
/// dE/dγ = (σ²/4)·F(γ) and the forces on a and on c (N).
#[inline(always)]
fn corner(
    u: DVec3,
    w: DVec3,
    inv_u: f64,
    inv_w: f64,
    quarter_cell: f64,
    f: &impl Fn(f64) -> f64,
) -> (DVec3, DVec3) {
    let (gamma, grad_a, grad_c) = cos_angle_gradients(u, w, inv_u, inv_w);
    let de_dgamma = quarter_cell * f(gamma);
    (-de_dgamma * grad_a, -de_dgamma * grad_c)
}

/// Adds the forces of the four corners of an interior crossing (links `[+warp, +weft, −warp,
/// −weft]`, unit vectors u1, w1 leaving it and u2, w2 the arriving ones reversed), given each
/// corner's γ and dE/dγ (J) in the order (u1, w1), (u2, w1), (u2, w2), (u1, w2). Each link is read
/// and written once; `inv` holds the links' inverse lengths (m⁻¹).
#[inline(always)]
pub(crate) fn add_crossing_forces(
    inv: &[f64],
    crossing: [u32; 4],
    [u1, w1, u2, w2]: [DVec3; 4],
    [g11, g21, g22, g12]: [f64; 4],
    [d11, d21, d22, d12]: [f64; 4],
    forces: &mut ForceBuffer,
) {
    let [up, wp, um, wm] = crossing.map(|l| l as usize);
    // Corner (u, w) pushes the end of u by −dE/dγ·(w − γu)/|u|; the two corners that share a link
    // are summed before the division by its length.
    let on_u1 = (d11 * w1 + d12 * w2 - (d11 * g11 + d12 * g12) * u1) * inv[up];
    let on_u2 = (d21 * w1 + d22 * w2 - (d21 * g21 + d22 * g22) * u2) * inv[um];
    let on_w1 = (d11 * u1 + d21 * u2 - (d11 * g11 + d21 * g21) * w1) * inv[wp];
    let on_w2 = (d12 * u1 + d22 * u2 - (d12 * g12 + d22 * g22) * w2) * inv[wm];
    // Outgoing links end at the neighbour (force −on_·); incoming links start there.
    forces.link[up] -= on_u1;
    forces.link[wp] -= on_w1;
    forces.link[um] += on_u2;
    forces.link[wm] += on_w2;
}

/// γ of the four corners of a crossing, in [`add_crossing_forces`]'s order.
#[inline(always)]
pub(crate) fn crossing_gammas([u1, w1, u2, w2]: [DVec3; 4]) -> [f64; 4] {
    [u1.dot(w1), u2.dot(w1), u2.dot(w2), u1.dot(w2)]
}

impl Trellising {
    /// Trellising for `topology` with the fabric's elastic shear curve.
    pub fn new(topology: Arc<ClothTopology>, fabric: &Fabric) -> Self {
        Self {
            topology,
            force: fabric.shear.force.clone(),
        }
    }

    /// The force loop, specialised on the curve `f(γ)` (N/m).
    #[inline(always)]
    fn accumulate(&self, geometry: &ClothGeometry, forces: &mut ForceBuffer, f: impl Fn(f64) -> f64) {
        let topo = &*self.topology;
        let q = 0.25 * topo.spacing * topo.spacing;
        let (unit, inv) = (&geometry.unit, &geometry.inv_length);
        // Interior crossings: four links, four corners, each link read and written once.
        for &crossing in &topo.full_crossings {
            let [up, wp, um, wm] = crossing.map(|l| l as usize);
            let vectors = [unit[up], unit[wp], -unit[um], -unit[wm]];
            let gammas = crossing_gammas(vectors);
            add_crossing_forces(inv, crossing, vectors, gammas, gammas.map(|g| q * f(g)), forces);
        }
        // Edge crossings: corner by corner.
        for &[lu, lw] in &topo.corner_links {
            let (su, sw) = (lu.sign(), lw.sign());
            let (lu, lw) = (lu.index(), lw.index());
            let (fa, fc) = corner(su * unit[lu], sw * unit[lw], inv[lu], inv[lw], q, &f);
            // The sign turns "force on the neighbour" into "force on the link's second end".
            forces.link[lu] += su * fa;
            forces.link[lw] += sw * fc;
        }
    }
}

impl ForceGenerator for Trellising {
    fn effect(&self) -> &'static str {
        "trellising"
    }

    fn energy(&self, geometry: &ClothGeometry) -> f64 {
        let topo = &*self.topology;
        let quarter_cell = 0.25 * topo.spacing * topo.spacing;
        let unit = &geometry.unit;
        let e = |u: DVec3, w: DVec3| quarter_cell * self.force.integral(u.dot(w));
        let full: f64 = topo
            .full_crossings
            .iter()
            .map(|&[up, wp, um, wm]| {
                let (u1, w1, u2, w2) = (
                    unit[up as usize],
                    unit[wp as usize],
                    -unit[um as usize],
                    -unit[wm as usize],
                );
                e(u1, w1) + e(u2, w1) + e(u2, w2) + e(u1, w2)
            })
            .sum();
        let edge: f64 = topo
            .corner_links
            .iter()
            .map(|&[lu, lw]| e(lu.sign() * unit[lu.index()], lw.sign() * unit[lw.index()]))
            .sum();
        full + edge
    }

    fn add_forces(&self, geometry: &ClothGeometry, _velocities: &[DVec3], forces: &mut ForceBuffer) {
        match self.force.as_linear() {
            Some(g) => self.accumulate(geometry, forces, |gamma| g * gamma),
            None => self.accumulate(geometry, forces, |gamma| self.force.value(gamma)),
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
        let q = 0.25 * topo.spacing * topo.spacing;
        let clamp = AngleClamp::for_definite(definite);
        let unit = &geometry.unit;
        // One corner: E = (σ²/4)·∫F dγ, so f' = (σ²/4)·F, f'' = (σ²/4)·F'.
        let mut corner = |(lu, su): (usize, f64), (lw, sw): (usize, f64)| {
            let gamma = (su * unit[lu]).dot(sw * unit[lw]);
            let tangent = (q * self.force.value(gamma), q * self.force.slope(gamma));
            add_corner_product(geometry, dx, ((lu, su), (lw, sw)), tangent, scale, clamp, out);
        };
        for &[up, wp, um, wm] in &topo.full_crossings {
            let (u1, w1) = ((up as usize, 1.0), (wp as usize, 1.0));
            let (u2, w2) = ((um as usize, -1.0), (wm as usize, -1.0));
            corner(u1, w1);
            corner(u2, w1);
            corner(u2, w2);
            corner(u1, w2);
        }
        for &[lu, lw] in &topo.corner_links {
            corner((lu.index(), lu.sign()), (lw.index(), lw.sign()));
        }
    }

    fn add_stiffness_blocks(&self, geometry: &ClothGeometry, scale: f64, matrix: &mut LinkMatrix) {
        let q = 0.25 * self.topology.spacing * self.topology.spacing;
        for i in 0..self.topology.corner_count() {
            let slot = matrix.corner_slot(i);
            let [(lu, su), (lw, sw)] = matrix.slot_links(slot);
            let gamma = (su * geometry.unit[lu]).dot(sw * geometry.unit[lw]);
            let tangent = (q * self.force.value(gamma), q * self.force.slope(gamma));
            add_angle_blocks(geometry, matrix, slot, tangent, scale);
        }
    }
}
