//! The force a solve hands Rapier for each node: the kick of its velocity change, less the
//! weight something else carries.

use glam::DVec3;

use super::vectors::filter;
use crate::implicit::{Bdf2History, Carriers};

/// What decides each node's kick.
pub(super) struct Kicks<'a> {
    /// Each node's support normal this step (zero for none).
    pub normals: &'a [DVec3],
    /// Node masses (kg).
    pub masses: &'a [f64],
    /// Nodes pinned to a body that is not dynamic, or to a carrier.
    pub held: &'a [bool],
    /// Whether the supports' friction is in the solve.
    pub friction: bool,
    /// The host's bodies solved with the cloth.
    pub carriers: &'a Carriers,
    /// BDF2's history, from its second step on.
    pub bdf2: Option<&'a Bdf2History>,
}

impl Kicks<'_> {
    /// Writes into `forces` (N) the force M·kick/h − carried weight for the solved velocity
    /// changes `dv` (m/s) over the step `h` (s) under `gravity` (m/s²).
    ///
    /// The kick leaves out the gravity Rapier adds back, except what pulls a pinned node (the
    /// pin takes that) and, without friction in the solve, what presses a node onto its
    /// support (Rapier's contact takes that, and bounds its friction by it). With friction in
    /// the solve, the solve's surface has carried the whole weight and the friction: Rapier's
    /// contact, left with nothing to stop, adds no friction of its own. A node coupled to a
    /// carrier: the carrier's row took its weight, so Rapier's contact or pin must not take it
    /// again.
    pub fn forces(&self, dv: &[DVec3], (h, gravity): (f64, DVec3), forces: &mut [DVec3]) {
        for (i, (f, dv)) in forces.iter_mut().zip(dv).enumerate() {
            let (n, m, held) = (self.normals[i], self.masses[i], self.held[i]);
            let weight = m * gravity;
            let coupled = self.carriers.of_node.get(i).is_some_and(|b| b.is_some())
                && (!held || self.carriers.pinned[i]);
            let carried = if (self.friction && n != DVec3::ZERO && !held) || coupled {
                weight
            } else {
                filter(n, held, weight)
            };
            let kick = self.bdf2.map_or(*dv, |history| history.kick(i, *dv));
            *f = (m / h) * kick - carried;
        }
    }
}
