//! The solve's small vector rules: a support's filter on a node's velocity, and the cloth's
//! total mass.

use glam::DVec3;

/// `v` with its component along `n` (a support's unit normal, or zero) removed, or zero for a
/// fixed node.
pub(super) fn filter(n: DVec3, fixed: bool, v: DVec3) -> DVec3 {
    if fixed { DVec3::ZERO } else { tangential(n, v) }
}

/// `v` with its component along the unit normal `n` removed (`v` itself for `n` = 0).
pub(super) fn tangential(n: DVec3, v: DVec3) -> DVec3 {
    v - n.dot(v) * n
}

/// Σm (kg), as N·m exactly when every node weighs the same.
pub(super) fn total_mass(masses: &[f64]) -> f64 {
    match masses.first() {
        Some(&m) if masses.iter().all(|&x| x == m) => m * masses.len() as f64,
        _ => masses.iter().sum(),
    }
}
