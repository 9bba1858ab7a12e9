//! Linear air drag against still air: force −c·A·v on each node, A = σ² its share of cloth.
//!
//! A deliberately simple law (Stokes-like, per unit area) for flags and falling cloth; unlike
//! [`super::LinkDamping`] it does slow free fall, as air does.

use glam::{DMat3, DVec3};

use super::{ClothGeometry, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation};

/// Linear drag on every node.
#[derive(Clone, Debug)]
pub struct AirDrag {
    /// c·A, drag per node (N·s/m).
    per_node: f64,
}

impl AirDrag {
    /// Drag of `coefficient` (N·s/m³) on nodes of area `spacing²` (m²).
    pub fn new(coefficient: f64, spacing: f64) -> Self {
        Self {
            per_node: coefficient * spacing * spacing,
        }
    }
}

impl ForceGenerator for AirDrag {
    fn effect(&self) -> &'static str {
        "air_drag"
    }

    /// Dissipative: stores no energy.
    fn energy(&self, _geometry: &ClothGeometry) -> f64 {
        0.0
    }

    fn add_forces(&self, _geometry: &ClothGeometry, velocities: &[DVec3], forces: &mut ForceBuffer) {
        for (f, v) in forces.particle.iter_mut().zip(velocities) {
            *f -= self.per_node * *v;
        }
    }

    /// C·δv = c·A·δv on each node.
    fn add_damping_product(&self, dv: &Perturbation, scale: f64, out: &mut ForceBuffer) {
        let c = scale * self.per_node;
        for (o, d) in out.particle.iter_mut().zip(&dv.particle) {
            *o += c * *d;
        }
    }

    fn add_damping_blocks(&self, scale: f64, matrix: &mut LinkMatrix) {
        for c in &mut matrix.particle {
            *c += DMat3::from_diagonal(DVec3::splat(scale * self.per_node));
        }
    }
}
