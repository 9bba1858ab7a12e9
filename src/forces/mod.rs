//! Force generators: the KES effects as forces on cloth particles, without any Rapier type.
//!
//! Every generator derives its forces from an energy (force = −∇E), so each is conservative by
//! construction and checked against finite differences of its energy. All read the shared
//! per-step [`ClothGeometry`] and add into a [`ForceBuffer`]; none allocates per step.
//!
//! | effect | file | energy |
//! |---|---|---|
//! | bending along warp and weft (seed eq. 2) | [`bending`] | σ²∫₀^K M dk per spring |
//! | trellising, four corners per crossing (seed eq. 3) | [`trellising`] | (σ²/4)∫₀^γ F dγ', γ = sin φ |
//! | stretch: the seed's separation law (eq. 1) | [`seed_separation`] | quintic in r − σ |
//! | stretch: KES tensile power law | [`kes_tensile`] | σ²∫₀^ε T dε' |
//! | compression of links held by Rapier rope joints | [`link_compression`] | ½k(σ − r)², r < σ |
//! | damping of relative motion along links | [`link_damping`] | dissipative |
//! | linear air drag | [`air_drag`] | dissipative |
//! | bending and shear hysteresis (KES 2HB, 2HG, 2HG5) | [`hysteresis`] | friction elements, dissipative |
//!
//! [`EffectKind`] is the one list of these effects (name, build condition, order); a cloth carries
//! the ones it asks for as [`Effects`].
//!
//! Each generator also gives the products of its energy Hessian and damping matrix with a
//! perturbation (matrix-free, the reference the tests check against finite differences) and the
//! same matrices assembled into a [`LinkMatrix`], which the implicit integrator
//! ([`crate::implicit`]) solves with.

pub mod air_drag;
pub mod bending;
mod cloth_geometry;
mod cloth_topology;
mod effects;
mod element_stiffness;
mod explicit_limit;
mod force_buffer;
pub mod hysteresis;
pub mod kes_tensile;
pub mod link_compression;
pub mod link_damping;
mod link_matrix;
mod particle_matrix;
mod perturbation;
pub mod seed_separation;
pub mod trellising;

use glam::DVec3;

pub use air_drag::AirDrag;
pub use bending::Bending;
pub use cloth_geometry::ClothGeometry;
pub(crate) use cloth_geometry::cos_angle_gradients;
pub use cloth_topology::{ClothTopology, NodeMass, SignedLink};
pub use effects::{EffectChoice, EffectKind, EffectStates, Effects, StretchModel};
pub(crate) use element_stiffness::outer;
pub use explicit_limit::{MAX_OMEGA_DT, StepLimit, explicit_step_limits, step_limits};
pub use force_buffer::ForceBuffer;
pub use hysteresis::Hysteresis;
pub use kes_tensile::KesTensile;
pub use link_compression::{BUCKLING_MARGIN, LinkCompression};
pub use link_damping::LinkDamping;
pub use link_matrix::LinkMatrix;
pub use particle_matrix::ParticleMatrix;
pub(crate) use particle_matrix::compress_rows;
pub use perturbation::Perturbation;
pub use seed_separation::SeedSeparation;
pub use trellising::Trellising;

/// One effect acting on the cloth's particles.
pub trait ForceGenerator: Send + Sync {
    /// The effect's name, as scenes and metrics spell it (e.g. `"bending"`).
    fn effect(&self) -> &'static str;

    /// Potential energy (J) stored in this effect for the given geometry.
    fn energy(&self, geometry: &ClothGeometry) -> f64;

    /// Adds this effect's forces (N) to `forces` (link pairs or particle forces).
    /// `velocities` (m/s) are there for dissipative effects; elastic ones ignore them.
    fn add_forces(&self, geometry: &ClothGeometry, velocities: &[DVec3], forces: &mut ForceBuffer);

    /// Adds `scale`·H·δx into `out` (N per unit scale), H = ∂²E/∂x² the Hessian of this effect's
    /// energy (N/m) at `geometry`, for the displacement δx (m) in `dx`. With `definite`, H is
    /// replaced by its positive semi-definite clamp, the matrix the implicit integrator solves
    /// with (`docs/model.md` §12). Effects without stiffness add nothing (the default).
    fn add_stiffness_product(
        &self,
        _geometry: &ClothGeometry,
        _dx: &Perturbation,
        _scale: f64,
        _definite: bool,
        _out: &mut ForceBuffer,
    ) {
    }

    /// Adds `scale`·C·δv into `out`, C = −∂F/∂v the damping matrix (N·s/m), for the velocity
    /// change δv (m/s) in `dv`. Elastic effects add nothing (the default).
    fn add_damping_product(&self, _dv: &Perturbation, _scale: f64, _out: &mut ForceBuffer) {}

    /// Adds `scale`·H into the assembled `matrix`, H the positive semi-definite clamp of this
    /// effect's Hessian (the matrix [`Self::add_stiffness_product`] multiplies by with
    /// `definite`). Effects without stiffness add nothing (the default).
    fn add_stiffness_blocks(&self, _geometry: &ClothGeometry, _scale: f64, _matrix: &mut LinkMatrix) {}

    /// Adds `scale`·C into the assembled `matrix`, C the damping matrix of
    /// [`Self::add_damping_product`]. Elastic effects add nothing (the default).
    fn add_damping_blocks(&self, _scale: f64, _matrix: &mut LinkMatrix) {}

    /// Moves the effect's internal state (friction slips) to the configuration `geometry`, once
    /// per step before its forces are taken; forces then read that state without changing it.
    /// Stateless effects do nothing (the default).
    fn advance_state(&mut self, _geometry: &ClothGeometry) {}

    /// The internal state [`Self::advance_state`] moves, as numbers a checkpoint keeps exactly;
    /// `None` for stateless effects (the default).
    fn state(&self) -> Option<Vec<f64>> {
        None
    }

    /// Restores a state saved by [`Self::state`]; `false` (and nothing changed) if it does not
    /// fit this effect. Stateless effects accept nothing (the default).
    fn restore_state(&mut self, _state: &[f64]) -> bool {
        false
    }
}
