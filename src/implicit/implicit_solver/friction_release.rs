//! After each pass of a step's solve, what each supported node's surface did: whether it pushed
//! (the support stays for the next step), and whether a hold left its friction cone (the node
//! slides, in a repeated pass or from the next step).

use glam::DVec3;

use super::FRICTION_SPEED;
use super::friction_start::Holds;
use super::vectors::tangential;

/// One pass's solution and what it was solved from, per node (the solver's vectors, borrowed).
pub(super) struct Pass<'a> {
    /// Each node's support normal (unit; zero where no surface supports it).
    pub normals: &'a [DVec3],
    /// Each node's friction coefficient μ with its surface (dimensionless).
    pub friction: &'a [f64],
    /// Nodes pinned to a fixed or kinematic body.
    pub held: &'a [bool],
    /// Node masses (kg).
    pub masses: &'a [f64],
    /// The pass's velocity change Δv (m/s).
    pub dv: &'a [DVec3],
    /// The step's matrix without its mass term (h²·H + h·C at the scheme's step h, with the
    /// particle diagonal of the supports' links) times Δv (N·s).
    pub product: &'a [DVec3],
    /// The right-hand side b + h·M·g before the filter (N·s).
    pub rhs: &'a [DVec3],
    /// Velocities at the step's start (m/s).
    pub velocities: &'a [DVec3],
}

/// What to do with a hold that left its friction cone.
#[derive(Clone, Copy)]
pub(super) struct Release {
    /// Mark it for the next step ([`super::FrictionRelease::NextStep`]): held through this one.
    pub next_step: bool,
    /// Release it now, for a repeated pass (false in the step's last pass, which only judges).
    pub now: bool,
}

/// Judges each surface's impulse on its node, M·Δv + A·Δv − b: a push (normal part ≥ 0) keeps
/// the support (`pressed`) for the next step, a pull releases it; a hold needs its tangential
/// part within μ times the normal one. Holds that leave the cone are released as `release`
/// says, and the nodes released now are appended to `released`. Returns whether any was
/// released now (the step then solves again).
pub(super) fn judge_holds(
    pass: Pass,
    holds: Holds,
    pressed: &mut [bool],
    released: &mut Vec<u32>,
    release: Release,
) -> bool {
    let mut any = false;
    for (i, pressed) in pressed.iter_mut().enumerate() {
        let n = pass.normals[i];
        let impulse = pass.masses[i] * pass.dv[i] + pass.product[i] - pass.rhs[i];
        let normal = impulse.dot(n);
        *pressed = n != DVec3::ZERO && normal >= 0.0;
        let holding = holds.fixed[i] && !pass.held[i];
        let sideways = tangential(n, impulse).length();
        let mu = pass.friction[i];
        if holds.drag[i] > 0.0 {
            holds.impulse[i] = mu * normal.max(0.0);
        }
        if release.next_step && holding && sideways > mu * normal.max(0.0) {
            // Held through this step; from the next it slides against μ·λ_n.
            holds.impulse[i] = mu * normal.max(0.0);
            holds.release_next[i] = true;
            continue;
        }
        if release.now && holding && sideways > mu * normal.max(0.0) {
            // It slides: the surface resists with kinetic friction μ·λ_n against the sliding,
            // which the solve takes as a drag μ·λ_n/s, s the node's sliding speed at the step's
            // start (at least FRICTION_SPEED), so it cannot reverse the motion. A node starting
            // from rest thus speeds up by at most |λ_t|/(μ·λ_n) a step until the drag is
            // Coulomb's; any larger estimate of s (from the hold's excess impulse) let rim nodes
            // overshoot and flicker at 50 mm/s on the drapemeter (docs/model.md §12).
            let speed = tangential(n, pass.velocities[i]).length().max(FRICTION_SPEED);
            holds.impulse[i] = mu * normal.max(0.0);
            holds.drag[i] = holds.impulse[i] / speed;
            holds.fixed[i] = false;
            released.push(i as u32);
            any = true;
        }
    }
    any
}
