//! Where force generators write: per-link force pairs and per-particle forces.
//!
//! Every elastic KES force in the model is a sum of equal and opposite pairs across single thread
//! links (a bending spring pushes a against b and c against b; a trellis corner likewise; a
//! stretch spring pulls along its link). Generators therefore add into one vector per *link*
//! (the force on its second particle; minus that on its first), which they read and write in
//! nearly sequential order, and [`ForceBuffer::resolve`] scatters the links to particles once.
//! This halves the random-access writes of the hot loop. Effects that are not pair forces
//! (damping against a medium, air drag) write to [`ForceBuffer::particle`] directly.

use glam::DVec3;

use super::ClothTopology;

/// Force accumulators of one cloth (N).
#[derive(Clone, Debug)]
pub struct ForceBuffer {
    /// Force on each particle (N).
    pub particle: Vec<DVec3>,
    /// For each link `[p, q]`, the force on `q` (N); `p` receives its opposite.
    pub link: Vec<DVec3>,
}

impl ForceBuffer {
    /// Zeroed buffers sized for `topology`.
    pub fn new(topology: &ClothTopology) -> Self {
        Self {
            particle: vec![DVec3::ZERO; topology.particle_count],
            link: vec![DVec3::ZERO; topology.links.len()],
        }
    }

    /// Sets every force to zero (start of a step).
    pub fn clear(&mut self) {
        self.particle.fill(DVec3::ZERO);
        self.link.fill(DVec3::ZERO);
    }

    /// Adds the link pairs into the particle forces, zeroes the link buffer, and returns the
    /// total force on each particle (N).
    pub fn resolve(&mut self, topology: &ClothTopology) -> &[DVec3] {
        for (&[p, q], f) in topology.links.iter().zip(&mut self.link) {
            self.particle[q as usize] += *f;
            self.particle[p as usize] -= *f;
            *f = DVec3::ZERO;
        }
        &self.particle
    }
}
