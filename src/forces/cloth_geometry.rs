//! Per-step geometry shared by all force generators: the unit vector and length of every link.
//!
//! Each link is used by up to two bending springs, four trellis corners and one stretch spring;
//! computing its direction once per step (one square root, one division) and letting every
//! generator read it keeps the force pass to a single sweep over flat arrays.

use std::sync::Arc;

use glam::DVec3;

use super::cloth_topology::ClothTopology;

/// Link directions and lengths of one cloth configuration.
#[derive(Clone, Debug)]
pub struct ClothGeometry {
    topology: Arc<ClothTopology>,
    /// Unit vector along each link, from its first particle to its second.
    pub unit: Vec<DVec3>,
    /// Length of each link (m).
    pub length: Vec<f64>,
    /// 1/length of each link (m⁻¹); 0 for a zero-length link.
    pub inv_length: Vec<f64>,
}

impl ClothGeometry {
    /// Geometry buffers for `topology` (all links of zero length until [`Self::update`]).
    pub fn new(topology: Arc<ClothTopology>) -> Self {
        let n = topology.links.len();
        Self {
            topology,
            unit: vec![DVec3::ZERO; n],
            length: vec![0.0; n],
            inv_length: vec![0.0; n],
        }
    }

    /// The topology this geometry belongs to.
    pub fn topology(&self) -> &ClothTopology {
        &self.topology
    }

    /// Recomputes every link from particle positions (m). Allocates nothing.
    pub fn update(&mut self, positions: &[DVec3]) {
        let links = self.topology.links.iter();
        for (((link, unit), length), inv) in links
            .zip(&mut self.unit)
            .zip(&mut self.length)
            .zip(&mut self.inv_length)
        {
            let d = positions[link[1] as usize] - positions[link[0] as usize];
            let l = d.length();
            // A zero-length link has no direction; its forces vanish with it.
            let inv_l = if l > 0.0 { 1.0 / l } else { 0.0 };
            *length = l;
            *inv = inv_l;
            *unit = d * inv_l;
        }
    }
}

/// cos of the angle at `b` between the segments to `a` and `c`, and its gradients with respect
/// to `a` and `c` (the gradient at `b` is minus their sum).
///
/// `u`, `w`: unit vectors b→a, b→c; `inv_lu`, `inv_lw`: their inverse lengths (m⁻¹).
#[inline(always)]
pub(crate) fn cos_angle_gradients(u: DVec3, w: DVec3, inv_lu: f64, inv_lw: f64) -> (f64, DVec3, DVec3) {
    let c = u.dot(w);
    let grad_a = (w - c * u) * inv_lu;
    let grad_c = (u - c * w) * inv_lw;
    (c, grad_a, grad_c)
}
