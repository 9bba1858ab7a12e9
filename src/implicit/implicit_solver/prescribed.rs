//! The part of a pass's Δv that is prescribed rather than solved for: a pinned node's, and
//! with friction in the solve a supported node's motion along its normal and a held node's
//! whole motion.

use glam::DVec3;

use super::vectors::tangential;

/// What each node's prescribed Δv follows from (the solver's own vectors, borrowed).
pub(super) struct Prescription<'a> {
    /// Nodes pinned to a body that is not dynamic.
    pub held: &'a [bool],
    /// The velocity (m/s) a held node's pin will have over the step (`None`: at rest).
    pub pin_velocities: &'a [Option<DVec3>],
    /// Whether the supports' friction is in the solve.
    pub friction: bool,
    /// Each supported node's surface normal (zero where none).
    pub normals: &'a [DVec3],
    /// Each support's velocity (m/s; a carrier moves its surface).
    pub surface: &'a [DVec3],
    /// Nodes whose whole Δv is prescribed this pass (pinned, or held by static friction).
    pub fixed: &'a [bool],
}

impl Prescription<'_> {
    /// Writes each node's prescribed Δv (m/s) into `z`, from its velocity `velocities` (m/s),
    /// zero where nothing is prescribed; returns whether any node's is not zero. With friction
    /// in the solve, the solve's surface stops a supported node's motion along its normal
    /// (Rapier's contact, left the node's weight to carry, does not), and a node stuck by
    /// friction stops altogether; a held node moves with its pin.
    pub fn write(&self, velocities: &[DVec3], z: &mut [DVec3]) -> bool {
        let mut any = false;
        for (i, (z, v)) in z.iter_mut().zip(velocities).enumerate() {
            let n = self.normals[i];
            // Relative to the surface, which a carrier moves.
            let surface = self.surface[i];
            *z = if self.held[i] {
                self.pin_velocities
                    .get(i)
                    .copied()
                    .flatten()
                    .map_or(DVec3::ZERO, |u| u - *v)
            } else if !self.friction || n == DVec3::ZERO {
                DVec3::ZERO
            } else if self.fixed[i] {
                -(*v - surface)
            } else {
                tangential(n, *v - surface) - (*v - surface)
            };
            any |= *z != DVec3::ZERO;
        }
        any
    }
}
