//! A small change of every particle (a displacement δx in m, or a velocity change δv in m/s),
//! together with the change of every link vector it causes, δd = δx_q − δx_p.
//!
//! Stiffness and damping products (the implicit integrator's matrix–vector products) act on
//! links, as the forces do; computing the link differences once per product lets every
//! generator read them in order.

use glam::DVec3;

use super::ClothTopology;

/// Per-particle values and their per-link differences.
#[derive(Clone, Debug)]
pub struct Perturbation {
    /// The value at each particle.
    pub particle: Vec<DVec3>,
    /// For each link `[p, q]`, `particle[q] − particle[p]`.
    pub link: Vec<DVec3>,
}

impl Perturbation {
    /// Zeroed buffers sized for `topology`.
    pub fn new(topology: &ClothTopology) -> Self {
        Self {
            particle: vec![DVec3::ZERO; topology.particle_count],
            link: vec![DVec3::ZERO; topology.links.len()],
        }
    }

    /// Sets the particle values and recomputes the link differences. Allocates nothing.
    pub fn set(&mut self, topology: &ClothTopology, values: &[DVec3]) {
        self.particle.copy_from_slice(values);
        for (&[p, q], d) in topology.links.iter().zip(&mut self.link) {
            *d = values[q as usize] - values[p as usize];
        }
    }
}
