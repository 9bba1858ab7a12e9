//! Support under a link: a fixed surface's sharp edge (a drapemeter's rim, a table's edge)
//! pressing on the thread between two nodes.
//!
//! Rapier's contacts are the nodes' balls: a cloth could leave an edge only at a node, and the
//! link from the last supported node to the first free one would cut the edge's corner, so the
//! cloth's line of departure lay up to a spacing inside the edge (`docs/model.md` §1, "Link
//! support"). A [`LinkSupport`] is a penalty spring at the point of the link nearest the
//! surface, with static (Coulomb) friction as a spring across the normal holding the material
//! point where the contact began until it would pull harder than μ times the normal force: both
//! forces are shared by the link's two nodes in proportion to where their points lie, and the
//! implicit solve carries their stiffness, the points and normal held over the step.

use glam::{DMat3, DVec3};

use crate::forces::LinkMatrix;

/// One link pressed by a fixed surface at a point between its nodes, read from Rapier's world
/// by [`crate::bodies::ClothBodies::read_link_supports`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LinkSupport {
    /// Index of the link in the topology's `links` (its nodes `[p, q]`).
    pub link: usize,
    /// The link's nodes `[p, q]`.
    pub nodes: [usize; 2],
    /// Where along the link the surface presses, from p (0) to q (1); strictly between.
    pub at: f64,
    /// Unit normal of the surface there, pointing out of it towards the link.
    pub normal: DVec3,
    /// How far (m) the link's centre line lies inside the nodes' contact clearance at that point,
    /// beyond what its two ends do (a link lying flat on a face presses no deeper than its
    /// nodes, and gets no force).
    pub depth: f64,
    /// Stiffness k (N/m) of the penalty spring, along the normal and, for static friction,
    /// across it.
    pub stiffness: f64,
    /// Where along the link (0 at p, 1 at q) the material point lies that static friction
    /// holds: the point pressed when the contact began or last slipped.
    pub held_at: f64,
    /// How far (m) that material point has moved across the normal from where friction holds
    /// it ([`LinkAnchors`]), at most μ·depth, so that the friction force k·|shift| stays within
    /// μ times the normal force k·depth.
    pub shift: DVec3,
}

/// Where static friction holds each pressed link, kept from step to step: the material point
/// (0 at p, 1 at q) and its anchor on the surface (m), by link index. A link no surface presses
/// loses its anchor; a new contact starts held where it touches.
pub type LinkAnchors = std::collections::HashMap<usize, (f64, DVec3)>;

impl LinkSupport {
    /// The surface's push k·depth along the normal on the point pressed, and its friction
    /// −k·shift on the point held (N), each shared by its two nodes as (1 − t, t).
    pub fn add_forces(&self, forces: &mut [DVec3]) {
        let push = self.stiffness * self.depth * self.normal;
        self.share(self.at, push, forces);
        self.share(self.held_at, -self.stiffness * self.shift, forces);
    }

    fn share(&self, t: f64, force: DVec3, forces: &mut [DVec3]) {
        for (node, w) in self.nodes.into_iter().zip([1.0 - t, t]) {
            if let Some(f) = forces.get_mut(node) {
                *f += w * force;
            }
        }
    }

    /// Adds `scale`·H of the two springs to `matrix`: k·(w wᵀ ⊗ n nᵀ) at the point pressed and
    /// k·(w wᵀ ⊗ (I − n nᵀ)) at the point held, w = (1 − t, t) of each point.
    pub fn add_stiffness_blocks(&self, scale: f64, matrix: &mut LinkMatrix) {
        let normal = outer(self.normal);
        self.add_weighted(self.at, scale * self.stiffness * normal, matrix);
        let across = DMat3::IDENTITY - normal;
        self.add_weighted(self.held_at, scale * self.stiffness * across, matrix);
    }

    /// Adds w wᵀ ⊗ `block` to `matrix`, w = (1 − t, t): as a particle diagonal w_i·block at
    /// each node and −w_p·w_q·block on the link (the matrix's Dᵀ·L·D), which sum to exactly
    /// that.
    fn add_weighted(&self, t: f64, block: DMat3, matrix: &mut LinkMatrix) {
        let (wp, wq) = (1.0 - t, t);
        let [p, q] = self.nodes;
        if let (Some(link), true) = (matrix.link.get_mut(self.link), p.max(q) < matrix.particle.len()) {
            *link -= (wp * wq) * block;
            matrix.particle[p] += wp * block;
            matrix.particle[q] += wq * block;
        }
    }
}

/// n nᵀ.
fn outer(n: DVec3) -> DMat3 {
    DMat3::from_cols(n * n.x, n * n.y, n * n.z)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::{ClothTopology, ForceBuffer, Perturbation};

    /// The split into a particle diagonal and a link term is exact: with the point held where
    /// the point pressed is, the matrix's product with any perturbation is the two springs'
    /// k·w·δX, δX = w_p δx_p + w_q δx_q the point's displacement (normal and across alike; to
    /// rounding, 1e-12 of the entries).
    #[test]
    fn the_matrix_carries_the_springs_stiffness_exactly() {
        let topo = ClothTopology::rectangle(3, 2, 0.01);
        let [p, q] = topo.links[0].map(|i| i as usize);
        let support = LinkSupport {
            link: 0,
            nodes: [p, q],
            at: 0.3,
            normal: DVec3::new(0.6, 0.8, 0.0),
            depth: 1e-5,
            stiffness: 120.0,
            held_at: 0.3,
            shift: DVec3::ZERO,
        };
        let mut matrix = LinkMatrix::new(&topo);
        support.add_stiffness_blocks(1.0, &mut matrix);
        let x: Vec<DVec3> = (0..topo.particle_count)
            .map(|i| DVec3::new(i as f64 + 0.5, -(i as f64), 0.25 * i as f64))
            .collect();
        let mut pert = Perturbation::new(&topo);
        pert.set(&topo, &x);
        let mut buffer = ForceBuffer::new(&topo);
        let got = matrix.product(&topo, &pert, &mut buffer).to_vec();
        let moved = 0.7 * x[p] + 0.3 * x[q];
        for (i, g) in got.iter().enumerate() {
            let w = if i == p {
                0.7
            } else if i == q {
                0.3
            } else {
                0.0
            };
            let expected = support.stiffness * w * moved;
            assert!(
                (*g - expected).length() < 1e-12 * 120.0 * 10.0,
                "node {i}: {g} vs {expected}"
            );
        }
    }
}
