//! Stretch by the KES tensile law T(ε) along each thread.
//!
//! A link of rest length σ stands for a strip of width σ and length σ, so its energy is
//! E = σ²·∫₀^ε T dε' with ε = r/σ − 1, and the tension it carries is dE/dr = σ·T(ε).
//! T(ε) is the power law of [`crate::material::TensileLaw`], which reproduces EMT, LT and WT.

use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::{add_link_spring_blocks, add_link_spring_products};
use super::{ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation};
use crate::material::{Fabric, TensileLaw, Thread};

/// KES tensile springs on every thread link.
#[derive(Clone, Debug)]
pub struct KesTensile {
    topology: Arc<ClothTopology>,
    /// T(ε) along [warp, weft].
    law: [TensileLaw; 2],
}

impl KesTensile {
    /// Tensile springs with the fabric's warp and weft laws.
    pub fn new(topology: Arc<ClothTopology>, fabric: &Fabric) -> Self {
        Self {
            topology,
            law: [fabric.tensile(Thread::Warp).law, fabric.tensile(Thread::Weft).law],
        }
    }
}

impl KesTensile {
    /// dE/dr (N) and d²E/dr² (N/m) of link `l`.
    fn tangent(&self, geometry: &ClothGeometry, l: usize) -> (f64, f64) {
        let sigma = self.topology.spacing;
        let law = &self.law[self.topology.link_thread(l) as usize];
        let strain = geometry.length[l] / sigma - 1.0;
        // dE/dr = σ·T(ε), d²E/dr² = T'(ε) (dε/dr = 1/σ).
        (sigma * law.tension(strain), law.stiffness(strain))
    }
}

impl ForceGenerator for KesTensile {
    fn effect(&self) -> &'static str {
        "stretch_kes"
    }

    fn energy(&self, geometry: &ClothGeometry) -> f64 {
        let sigma = self.topology.spacing;
        (0..self.topology.links.len())
            .map(|l| {
                let law = &self.law[self.topology.link_thread(l) as usize];
                sigma * sigma * law.energy_density(geometry.length[l] / sigma - 1.0)
            })
            .sum()
    }

    fn add_forces(&self, geometry: &ClothGeometry, _velocities: &[DVec3], forces: &mut ForceBuffer) {
        let topo = &self.topology;
        let sigma = topo.spacing;
        for (range, law) in [
            (0..topo.warp_link_count, &self.law[0]),
            (topo.warp_link_count..topo.links.len(), &self.law[1]),
        ] {
            let links = geometry.length[range.clone()]
                .iter()
                .zip(&geometry.unit[range.clone()])
                .zip(&mut forces.link[range]);
            for ((&length, &unit), link_force) in links {
                let f = sigma * law.tension(length / sigma - 1.0) * unit;
                // Tension pulls the second particle back towards the first.
                *link_force -= f;
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
        add_link_spring_products(geometry, dx, scale, definite, out, |l| self.tangent(geometry, l));
    }

    fn add_stiffness_blocks(&self, geometry: &ClothGeometry, scale: f64, matrix: &mut LinkMatrix) {
        add_link_spring_blocks(geometry, scale, matrix, |l| self.tangent(geometry, l));
    }
}
