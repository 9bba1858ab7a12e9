//! Resistance of thread links to compression, for stretch as a constraint.
//!
//! Rapier's rope joints hold a link at most σ long but let it shorten freely, and a cloth whose
//! links can collapse crumples in its own plane instead of folding out of it (measured on the
//! drape test: links shortened by up to 22 %). A woven fabric barely shortens in its plane: it
//! buckles out of it, which the bending springs represent. This one-sided spring,
//! E = ½·k·(σ − r)² for r < σ, makes shortening cost more than buckling: by default its in-plane
//! modulus is [`BUCKLING_MARGIN`] times the Euler load of the shortest buckle the lattice can
//! form, so a compressed link folds before it shortens by 1/[`BUCKLING_MARGIN`]
//! (`docs/model.md` §9). The modulus depends on the fabric and the spacing, never on the step.

use std::sync::Arc;

use glam::DVec3;

use super::element_stiffness::{add_link_spring_blocks, add_link_spring_products};
use crate::material::{Fabric, Thread};

/// How many times the Euler buckling load of a one-spacing strip the default compression
/// modulus is (dimensionless): a link buckles before it shortens by 1 % (`docs/model.md` §9).
pub const BUCKLING_MARGIN: f64 = 100.0;
use super::{ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation};

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

    /// The default in-plane modulus (N/m, which is also each link's stiffness k in a square
    /// lattice) for `fabric` at spacing `spacing` (m): C·π²·B/σ², C = [`BUCKLING_MARGIN`], B the
    /// larger of warp and weft bending rigidity (N·m). π²·B/σ² is the load per unit width
    /// (N/m) at which a strip one spacing long buckles; measured on the drape test, the drape
    /// coefficient stops depending on the modulus from about this value up (`docs/model.md` §9).
    pub fn default_modulus(fabric: &Fabric, spacing: f64) -> f64 {
        let rigidity = fabric
            .bending(Thread::Warp)
            .rigidity
            .max(fabric.bending(Thread::Weft).rigidity);
        BUCKLING_MARGIN * std::f64::consts::PI.powi(2) * rigidity / (spacing * spacing)
    }
}

impl LinkCompression {
    /// dE/dr (N) and d²E/dr² (N/m) of a link of length `r` (m), or of its definite stand-in.
    fn tangent(&self, r: f64, definite: bool) -> (f64, f64) {
        let (k, sigma) = (self.stiffness, self.topology.spacing);
        // E = ½k(σ − r)² below σ: dE/dr = −k(σ − r), d²E/dr² = k. The rope joint holds a
        // stretched link: the solver's matrix gives stretch the same axial stiffness, so
        // the velocity change it computes keeps the links' lengths as the joint will (a
        // majorant: the exact Hessian is 0 there).
        match (r < sigma, definite) {
            (true, _) => (-k * (sigma - r), k),
            (false, true) => (0.0, k),
            (false, false) => (0.0, 0.0),
        }
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
        add_link_spring_products(geometry, dx, scale, definite, out, |l| {
            self.tangent(geometry.length[l], definite)
        });
    }

    fn add_stiffness_blocks(&self, geometry: &ClothGeometry, scale: f64, matrix: &mut LinkMatrix) {
        add_link_spring_blocks(geometry, scale, matrix, |l| {
            self.tangent(geometry.length[l], true)
        });
    }
}
