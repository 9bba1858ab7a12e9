//! The implicit solve's matrix, assembled once per step in link space.
//!
//! Every stiffness and damping term of our effects acts on thread links, as the forces do
//! ([`super::ForceBuffer`]): a stretch or damping spring on one link (a 3×3 block on that link's
//! diagonal), a bending spring or trellis corner on the pair of links that meet at its middle
//! particle (a 6×6 element: two diagonal blocks and one coupling block). The particle matrix is
//! Dᵀ·L·D, D the link difference operator (δd = δx_q − δx_p), plus a diagonal for effects that
//! act on particles (air drag).
//!
//! Assembling L costs about one matrix-free product ([`super::ForceGenerator::add_stiffness_product`]),
//! and each conjugate-gradient product afterwards is only block multiplications: no curve
//! lookup, square root or branch per element (the solve sums L into particle rows once,
//! [`super::ParticleMatrix`], which saves the link passes of each product). The pattern (which link pairs are coupled) is
//! fixed by the topology: one coupling slot per bending spring, then one per trellis corner, in
//! the order [`super::Trellising`] and [`super::Hysteresis`] visit them.

use glam::{DMat3, DVec3};

use super::{ClothTopology, ForceBuffer, Perturbation};

/// One coupling slot: the two links of an element, their signs (±1: the sign that points each
/// link away from the element's middle particle) and that shared particle.
#[derive(Clone, Copy, Debug)]
struct Slot {
    links: [u32; 2],
    signs: [f64; 2],
    /// The particle both links touch, and the product of the two links' incidence signs
    /// there (+1 if it is the second end of both links or of neither).
    shared: u32,
    incidence: f64,
}

/// L, the link-space matrix of one cloth, plus its particle diagonal. Units follow the scale
/// each term is added with: h²·H (kg, for the implicit solve), h·C (kg) or plain H (N/m).
#[derive(Clone, Debug)]
pub struct LinkMatrix {
    /// Diagonal block of each link.
    pub link: Vec<DMat3>,
    /// Diagonal block of each particle: terms that act on a particle's own motion (air drag,
    /// a support under a link, [`crate::implicit::LinkSupport`]).
    pub particle: Vec<DMat3>,
    /// Coupling block of each slot: the term for (first link's row, second link's column).
    coupling: Vec<DMat3>,
    slots: Vec<Slot>,
    bend_count: usize,
}

impl LinkMatrix {
    /// A zero matrix with the coupling pattern of `topology`.
    pub fn new(topology: &ClothTopology) -> Self {
        let mut pairs: Vec<[(u32, f64); 2]> =
            Vec::with_capacity(topology.bend_links.len() + topology.corner_count());
        // Bending spring a→b→c: link a→b arrives at b (sign −1 points it back to a), b→c leaves.
        pairs.extend(
            topology
                .bend_links
                .iter()
                .map(|&[l1, l2]| [(l1, -1.0), (l2, 1.0)]),
        );
        for &[up, wp, um, wm] in &topology.full_crossings {
            let (u1, w1, u2, w2) = ((up, 1.0), (wp, 1.0), (um, -1.0), (wm, -1.0));
            pairs.extend([[u1, w1], [u2, w1], [u2, w2], [u1, w2]]);
        }
        for &[lu, lw] in &topology.corner_links {
            pairs.push([(lu.index() as u32, lu.sign()), (lw.index() as u32, lw.sign())]);
        }
        let slots = pairs
            .into_iter()
            .map(|[(la, sa), (lb, sb)]| {
                let ([pa, qa], [pb, qb]) = (topology.links[la as usize], topology.links[lb as usize]);
                // Incidence of particle i on link [p, q]: +1 at q, −1 at p.
                let (shared, incidence) = if qa == qb {
                    (qa, 1.0)
                } else if pa == pb {
                    (pa, 1.0)
                } else if qa == pb {
                    (qa, -1.0)
                } else {
                    (pa, -1.0)
                };
                Slot {
                    links: [la, lb],
                    signs: [sa, sb],
                    shared,
                    incidence,
                }
            })
            .collect::<Vec<_>>();
        Self {
            link: vec![DMat3::ZERO; topology.links.len()],
            particle: vec![DMat3::ZERO; topology.particle_count],
            coupling: vec![DMat3::ZERO; slots.len()],
            slots,
            bend_count: topology.bend_links.len(),
        }
    }

    /// Sets every entry to zero (start of an assembly).
    pub fn clear(&mut self) {
        self.link.fill(DMat3::ZERO);
        self.particle.fill(DMat3::ZERO);
        self.coupling.fill(DMat3::ZERO);
    }

    /// How many coupling slots the pattern has.
    pub fn slot_count(&self) -> usize {
        self.slots.len()
    }

    /// The coupling block of `slot`: the term for (first link's row, second link's column).
    pub fn coupling_block(&self, slot: usize) -> DMat3 {
        self.coupling[slot]
    }

    /// The slot of bending spring `s` (an index into the topology's `bend_links`).
    pub fn bend_slot(&self, s: usize) -> usize {
        s
    }

    /// The slot of trellis corner `i` (interior crossings first, four each, then edge corners).
    pub fn corner_slot(&self, i: usize) -> usize {
        self.bend_count + i
    }

    /// The links of `slot` and their signs (±1, pointing each away from the middle particle).
    pub fn slot_links(&self, slot: usize) -> [(usize, f64); 2] {
        let s = &self.slots[slot];
        [
            (s.links[0] as usize, s.signs[0]),
            (s.links[1] as usize, s.signs[1]),
        ]
    }

    /// Adds an angle element on `slot`, given its blocks for the signed link vectors U = s_a·d_a,
    /// W = s_b·d_b: H_UU, H_UW and H_WW.
    pub fn add_element(&mut self, slot: usize, (uu, uw, ww): (DMat3, DMat3, DMat3)) {
        let s = self.slots[slot];
        let [la, lb] = s.links.map(|l| l as usize);
        self.link[la] += uu;
        self.link[lb] += ww;
        self.coupling[slot] += (s.signs[0] * s.signs[1]) * uw;
    }

    /// out = L·δ in link space plus the particle diagonal, resolved to particles: the force
    /// (per unit of the assembly's scale) on each particle for the perturbation `dx`.
    pub fn product<'a>(
        &self,
        topology: &ClothTopology,
        dx: &Perturbation,
        out: &'a mut ForceBuffer,
    ) -> &'a [DVec3] {
        for ((o, block), d) in out.link.iter_mut().zip(&self.link).zip(&dx.link) {
            *o = *block * *d;
        }
        for (slot, block) in self.slots.iter().zip(&self.coupling) {
            let [la, lb] = slot.links.map(|l| l as usize);
            let (da, db) = (dx.link[la], dx.link[lb]);
            out.link[la] += *block * db;
            out.link[lb] += DVec3::new(block.x_axis.dot(da), block.y_axis.dot(da), block.z_axis.dot(da));
        }
        for ((o, c), x) in out.particle.iter_mut().zip(&self.particle).zip(&dx.particle) {
            *o = *c * *x;
        }
        out.resolve(topology)
    }

    /// Adds each particle's 3×3 diagonal block of Dᵀ·L·D plus its particle term into `blocks`:
    /// the block-Jacobi preconditioner's blocks.
    pub fn add_particle_diagonal(&self, topology: &ClothTopology, blocks: &mut [DMat3]) {
        for (b, c) in blocks.iter_mut().zip(&self.particle) {
            *b += *c;
        }
        for (&[p, q], block) in topology.links.iter().zip(&self.link) {
            blocks[p as usize] += *block;
            blocks[q as usize] += *block;
        }
        for (slot, block) in self.slots.iter().zip(&self.coupling) {
            blocks[slot.shared as usize] += slot.incidence * (*block + block.transpose());
        }
    }
}
