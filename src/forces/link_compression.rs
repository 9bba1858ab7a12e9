//! Resistance of thread links to compression, for stretch as a constraint.
//!
//! Rapier's rope joints hold a link at most σ long but let it shorten freely, and a cloth whose
//! links can collapse crumples in its own plane instead of folding out of it (measured on the
//! drape test: links shortened by up to 22 %). Woven threads resist shortening until they
//! buckle, which the bending springs represent; this one-sided spring,
//! E = ½·k·(σ − r)² for r < σ, keeps links near their length meanwhile.
//! k is chosen by the caller from the time step (the stiffest spring that stays stable when
//! applied explicitly, see `docs/model.md`), so it is a numerical device, not a KES quantity.

use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::add_link_spring_products;
use super::{ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, Perturbation};

/// One-sided compression springs on every thread link.
#[derive(Clone, Debug)]
pub struct LinkCompression {
    topology: Arc<ClothTopology>,
    /// k, stiffness per link (N/m).
    stiffness: f64,
}

impl LinkCompression {
    /// Compression springs of `stiffness` (N/m) per link.
    pub fn new(topology: Arc<ClothTopology>, stiffness: f64) -> Self {
        Self { topology, stiffness }
    }

    /// The step (s) at which the shipped explicit scenes size the spring: an implicit run with a
    /// longer step keeps this stiffness, so it integrates the same model.
    pub const REFERENCE_STEP: f64 = 2.5e-4;

    /// A per-link stiffness that explicit stepping at `dt` (s) keeps stable for nodes of mass
    /// `node_mass` (kg), leaving room for the other forces: along one thread the fastest
    /// (alternating) mode of a chain of springs k has ω² = 4k/m, and symplectic Euler needs
    /// ω·dt < 2; k = m/(4·dt²) gives ω·dt = 1 (measured: links then shorten by at most 3 % on
    /// the shipped scenes; with m/(6·dt²), 3.8 % on the cotton tablecloth).
    pub fn stable_stiffness(node_mass: f64, dt: f64) -> f64 {
        node_mass / (4.0 * dt * dt)
    }
}

impl ForceGenerator for LinkCompression {
    fn effect(&self) -> &'static str {
        "compression"
    }

    fn energy(&self, geometry: &ClothGeometry) -> f64 {
        let sigma = self.topology.spacing;
        geometry
            .length
            .iter()
            .map(|&r| {
                if r < sigma {
                    0.5 * self.stiffness * (sigma - r).powi(2)
                } else {
                    0.0
                }
            })
            .sum()
    }

    fn add_forces(&self, geometry: &ClothGeometry, _velocities: &[DVec3], forces: &mut ForceBuffer) {
        let sigma = self.topology.spacing;
        let k = self.stiffness;
        for ((&r, &unit), f) in geometry.length.iter().zip(&geometry.unit).zip(&mut forces.link) {
            if r < sigma {
                // Pushes the link's second node away from the first.
                *f += k * (sigma - r) * unit;
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
        let (k, sigma) = (self.stiffness, self.topology.spacing);
        add_link_spring_products(geometry, dx, scale, definite, out, |l| {
            let r = geometry.length[l];
            // E = ½k(σ − r)² below σ: dE/dr = −k(σ − r), d²E/dr² = k. The rope joint holds a
            // stretched link: the solver's matrix gives stretch the same axial stiffness, so
            // the velocity change it computes keeps the links' lengths as the joint will (a
            // majorant: the exact Hessian is 0 there).
            match (r < sigma, definite) {
                (true, _) => (-k * (sigma - r), k),
                (false, true) => (0.0, k),
                (false, false) => (0.0, 0.0),
            }
        });
    }
}
