//! Damping of motion inside the cloth: each thread link resists the relative velocity of its
//! two nodes.
//!
//! The force on a link's second node is −c·(v_q − v_p), its opposite on the first, with
//! c = rate·m/2 (m the node mass), so that the relative velocity of an isolated pair decays at
//! `rate` (1/s). The forces come in equal and opposite pairs: a cloth falling or sliding as a
//! whole is not slowed at all. It damps stretching, bending and shearing motion of neighbours
//! (and, slightly, a spinning cloth). Explicit at the step: stable while rate·dt < 1/4 for an
//! interior node with four links (the scene runner checks this).

use std::sync::Arc;

use glam::DVec3;

use super::{ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation};

/// Relative-velocity damping on every thread link.
#[derive(Clone, Debug)]
pub struct LinkDamping {
    topology: Arc<ClothTopology>,
    /// c, damping coefficient per link (N·s/m).
    coefficient: f64,
}

impl LinkDamping {
    /// Damping at `rate` (1/s) for nodes of mass `node_mass` (kg).
    pub fn new(topology: Arc<ClothTopology>, rate: f64, node_mass: f64) -> Self {
        Self {
            topology,
            coefficient: 0.5 * rate * node_mass,
        }
    }
}

impl ForceGenerator for LinkDamping {
    fn effect(&self) -> &'static str {
        "damping"
    }

    /// Dissipative: stores no energy.
    fn energy(&self, _geometry: &ClothGeometry) -> f64 {
        0.0
    }

    fn add_forces(&self, _geometry: &ClothGeometry, velocities: &[DVec3], forces: &mut ForceBuffer) {
        let c = self.coefficient;
        for (&[p, q], f) in self.topology.links.iter().zip(&mut forces.link) {
            *f -= c * (velocities[q as usize] - velocities[p as usize]);
        }
    }

    /// C·δv: each link's relative velocity change times c.
    fn add_damping_product(&self, dv: &Perturbation, scale: f64, out: &mut ForceBuffer) {
        let c = scale * self.coefficient;
        for (o, d) in out.link.iter_mut().zip(&dv.link) {
            *o += c * *d;
        }
    }

    fn add_damping_blocks(&self, scale: f64, matrix: &mut LinkMatrix) {
        let c = glam::DMat3::from_diagonal(DVec3::splat(scale * self.coefficient));
        for block in &mut matrix.link {
            *block += c;
        }
    }
}
