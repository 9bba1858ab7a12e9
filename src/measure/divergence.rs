//! The divergence checks of every step (`docs/model.md` §11), shared by the scene schedule and
//! embedded cloths: what failed, at which node, and the message that explains it.

use glam::DVec3;

use super::motion::{Motion, RUNAWAY_SPEED, RUNAWAY_STRAIN, runaway_causes};

/// The first node whose force (N) is not finite.
pub fn non_finite_force(forces: &[DVec3]) -> Option<usize> {
    forces.iter().position(|f| !f.is_finite())
}

/// The first node whose position (m) or velocity (m/s) is not finite.
pub fn non_finite_state(positions: &[DVec3], velocities: &[DVec3]) -> Option<usize> {
    positions
        .iter()
        .zip(velocities)
        .position(|(x, v)| !x.is_finite() || !v.is_finite())
}

/// Whether the cloth is running away: a node faster than [`RUNAWAY_SPEED`] or a link strained
/// beyond [`RUNAWAY_STRAIN`].
pub fn is_runaway(motion: &Motion) -> bool {
    motion.max_strain > RUNAWAY_STRAIN || motion.max_speed > RUNAWAY_SPEED
}

/// The message for a node whose position `x` (m) or velocity `v` (m/s) is not finite after
/// Rapier's step of `dt` (s).
pub fn non_finite_state_message(x: DVec3, v: DVec3, dt: f64) -> String {
    format!(
        "node position {x:?} m or velocity {v:?} m/s is not finite after Rapier's step; likely \
         cause: a force or contact too stiff for dt = {dt} s"
    )
}

/// The message for a non-finite implicit velocity change (`force`, N).
pub fn non_finite_solve_message(force: DVec3) -> String {
    format!(
        "non-finite velocity change (force {force:?} N) from the implicit solve: a stiffness \
         product or the solve produced NaN"
    )
}

/// The message for a runaway, with its likely causes (implicit or not, rope joints or not, the
/// step `dt`, s, and the lattice's spacing `spacing_m`, m).
pub fn runaway_message(
    motion: &Motion,
    implicit: bool,
    rope_joints: bool,
    (dt, spacing_m): (f64, f64),
) -> String {
    format!(
        "runaway: fastest node {:.2} m/s, largest link strain {:.0} %; {}",
        motion.max_speed,
        motion.max_strain * 100.0,
        runaway_causes(
            implicit,
            rope_joints,
            dt,
            (motion.max_speed * dt / spacing_m, spacing_m)
        )
    )
}
