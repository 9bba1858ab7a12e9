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
    /// c of each link (N·s/m).
    coefficients: Vec<f64>,
}

impl LinkDamping {
    /// Damping at `rate` (1/s) for nodes of mass `node_mass` (kg).
    pub fn new(topology: Arc<ClothTopology>, rate: f64, node_mass: f64) -> Self {
        let masses = vec![node_mass; topology.particle_count];
        Self::with_masses(topology, rate, &masses)
    }

    /// Damping at `rate` (1/s) for nodes of `masses` (kg, in particle order): each link's c is
    /// `rate` times its pair's reduced mass m_p·m_q/(m_p + m_q), so every isolated pair's
    /// relative velocity decays at `rate` (c = rate·m/2 for equal masses).
    pub fn with_masses(topology: Arc<ClothTopology>, rate: f64, masses: &[f64]) -> Self {
        let coefficients = topology
            .links
            .iter()
            .map(|&[p, q]| {
                let (a, b) = (masses[p as usize], masses[q as usize]);
                if a == b {
                    0.5 * rate * a
                } else {
                    rate * a * b / (a + b)
                }
            })
            .collect();
        Self {
            topology,
            coefficients,
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
        for ((&[p, q], f), c) in self
            .topology
            .links
            .iter()
            .zip(&mut forces.link)
            .zip(&self.coefficients)
        {
            *f -= *c * (velocities[q as usize] - velocities[p as usize]);
        }
    }

    /// C·δv: each link's relative velocity change times c.
    fn add_damping_product(&self, dv: &Perturbation, scale: f64, out: &mut ForceBuffer) {
        for ((o, d), c) in out.link.iter_mut().zip(&dv.link).zip(&self.coefficients) {
            *o += scale * *c * *d;
        }
    }

    fn add_damping_blocks(&self, scale: f64, matrix: &mut LinkMatrix) {
        for (block, c) in matrix.link.iter_mut().zip(&self.coefficients) {
            *block += glam::DMat3::from_diagonal(DVec3::splat(scale * *c));
        }
    }
}
