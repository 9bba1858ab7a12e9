//! Stretch by the seed's separation law (eq. 1), made dimensionally consistent.
//!
//! For a link of length r and rest length σ the seed prints
//! F = 5·C₀·(r − σ)⁴/σ⁵ when stretched and F = −C₀·(4r + σ)·(r − σ)⁴/σ² when compressed.
//! As typeset the two branches have different units; we read the second denominator as σ⁶, so
//! both are C₀/length (C₀ an energy, J) and both derive from one energy:
//! E = C₀·(r − σ)⁵/σ⁵ (r > σ),  E = −C₀·(r − σ)⁵·(2r + σ)/(3σ⁶) (r ≤ σ),
//! which is C⁴-smooth at r = σ. The seed gives no value for C₀; we take it from the KES tensile
//! test so that a link of width σ carries T_m·σ at the strain EMT: C₀ = T_m·σ²/(5·EMT⁴).
//! The quartic law is very soft at small strain: the seed itself reports that it over-stretches.

use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::{add_link_spring_blocks, add_link_spring_products};
use super::{ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation};
use crate::material::{Fabric, Thread};

/// The seed's separation springs on every thread link.
#[derive(Clone, Debug)]
pub struct SeedSeparation {
    topology: Arc<ClothTopology>,
    /// C₀ along [warp, weft] (J).
    c0: [f64; 2],
}

impl SeedSeparation {
    /// Separation springs with C₀ from the fabric's tensile test.
    pub fn new(topology: Arc<ClothTopology>, fabric: &Fabric) -> Self {
        let sigma = topology.spacing;
        let c0 = |t: Thread| {
            let law = fabric.tensile(t).law;
            law.max_load * sigma * sigma / (5.0 * law.strain_at_max_load.powi(4))
        };
        Self {
            topology,
            c0: [c0(Thread::Warp), c0(Thread::Weft)],
        }
    }

    /// C₀ along a thread (J).
    pub fn c0(&self, thread: Thread) -> f64 {
        self.c0[thread as usize]
    }

    /// Energy (J) and dE/dr (N) of one link of length `r` (m).
    #[inline(always)]
    fn link(&self, c0: f64, r: f64) -> (f64, f64) {
        let sigma = self.topology.spacing;
        let d = r - sigma;
        let d4 = (d * d) * (d * d);
        let s5 = sigma.powi(5);
        if d > 0.0 {
            (c0 * d4 * d / s5, 5.0 * c0 * d4 / s5)
        } else {
            let s6 = s5 * sigma;
            (
                -c0 * d4 * d * (2.0 * r + sigma) / (3.0 * s6),
                -c0 * (4.0 * r + sigma) * d4 / s6,
            )
        }
    }
}

impl SeedSeparation {
    /// dE/dr (N) and d²E/dr² (N/m) of one link of length `r` (m).
    fn link_tangent(&self, c0: f64, r: f64) -> (f64, f64) {
        let sigma = self.topology.spacing;
        let d = r - sigma;
        let d3 = d * d * d;
        let s5 = sigma.powi(5);
        if d > 0.0 {
            (5.0 * c0 * d3 * d / s5, 20.0 * c0 * d3 / s5)
        } else {
            let s6 = s5 * sigma;
            (
                -c0 * (4.0 * r + sigma) * d3 * d / s6,
                -c0 * (4.0 * d3 * d + 4.0 * (4.0 * r + sigma) * d3) / s6,
            )
        }
    }
}

impl ForceGenerator for SeedSeparation {
    fn effect(&self) -> &'static str {
        "stretch_seed"
    }

    fn energy(&self, geometry: &ClothGeometry) -> f64 {
        (0..self.topology.links.len())
            .map(|l| {
                self.link(self.c0[self.topology.link_thread(l) as usize], geometry.length[l])
                    .0
            })
            .sum()
    }

    fn add_forces(&self, geometry: &ClothGeometry, _velocities: &[DVec3], forces: &mut ForceBuffer) {
        let topo = &self.topology;
        for (range, c0) in [
            (0..topo.warp_link_count, self.c0[0]),
            (topo.warp_link_count..topo.links.len(), self.c0[1]),
        ] {
            let links = geometry.length[range.clone()]
                .iter()
                .zip(&geometry.unit[range.clone()])
                .zip(&mut forces.link[range]);
            for ((&length, &unit), link_force) in links {
                let f = self.link(c0, length).1 * unit;
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
        add_link_spring_products(geometry, dx, scale, definite, out, |l| {
            self.link_tangent(self.c0[self.topology.link_thread(l) as usize], geometry.length[l])
        });
    }

    fn add_stiffness_blocks(&self, geometry: &ClothGeometry, scale: f64, matrix: &mut LinkMatrix) {
        add_link_spring_blocks(geometry, scale, matrix, |l| {
            self.link_tangent(self.c0[self.topology.link_thread(l) as usize], geometry.length[l])
        });
    }
}
