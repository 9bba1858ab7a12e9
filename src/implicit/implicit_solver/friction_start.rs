//! Where each supported node starts a step: held by its surface's static friction, or sliding
//! against its kinetic friction.

use glam::DVec3;

use super::FRICTION_SPEED;
use super::vectors::tangential;
use crate::implicit::supports::Supports;

/// The per-node friction state a step starts from (the solver's own vectors, borrowed).
pub(super) struct Holds<'a> {
    /// Whether the node's whole Δv is prescribed (pinned or held).
    pub fixed: &'a mut [bool],
    /// Kinetic friction drag of a sliding node (N·s/m; 0 elsewhere).
    pub drag: &'a mut [f64],
    /// The last friction impulse μ·λ_n of a sliding node (N·s).
    pub impulse: &'a mut [f64],
    /// Holds that gave way in the last solve, released from this step.
    pub release_next: &'a mut [bool],
}

/// Sets this step's holds and sliding drags from the pins (`held`), the `supports`, whether
/// friction is in the solve, and the nodes' velocities (m/s) at the step's start.
pub(super) fn start_holds(
    holds: Holds,
    held: &[bool],
    supports: &Supports,
    friction: bool,
    velocities: &[DVec3],
) {
    // Static friction: every node a surface supports starts the step held (unless it is
    // still sliding, below); a hold whose impulse leaves the friction cone is released
    // after the solve and the solve repeated.
    let normals = &supports.pushed;
    for (((fixed, held), n), mu) in holds
        .fixed
        .iter_mut()
        .zip(held)
        .zip(normals)
        .zip(&supports.friction)
    {
        *fixed = *held || (friction && *n != DVec3::ZERO && *mu > 0.0);
    }
    // Kinetic friction: a node that slid in the last step and still slides (faster than
    // FRICTION_SPEED along its surface) starts this one sliding, against the drag of its
    // last friction impulse at its current speed; only a hold that gives way needs a
    // second solve. A node that has all but stopped is held again, unless its hold gave way
    // in the last solve and is released from this step (FrictionRelease::NextStep).
    for (i, (drag, impulse)) in holds.drag.iter_mut().zip(holds.impulse.iter_mut()).enumerate() {
        let speed = tangential(normals[i], velocities[i]).length();
        *drag = 0.0;
        let gave_way = std::mem::take(&mut holds.release_next[i]);
        if gave_way && holds.fixed[i] && !held[i] && *impulse > 0.0 {
            *drag = *impulse / speed.max(FRICTION_SPEED);
            holds.fixed[i] = false;
        } else if !holds.fixed[i] || held[i] || speed <= FRICTION_SPEED {
            *impulse = 0.0;
        } else if *impulse > 0.0 {
            *drag = *impulse / speed;
            holds.fixed[i] = false;
        }
    }
}
