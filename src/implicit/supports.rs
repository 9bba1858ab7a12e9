//! What the implicit solve knows about the surfaces under the cloth, read from Rapier.

use glam::DVec3;

use super::{LinkAnchors, LinkSupport};

/// Per node, the fixed or kinematic surfaces Rapier's last step found under it, filled by
/// [`crate::bodies::ClothBodies::read_supports`] before each [`super::ImplicitSolver::solve`],
/// and in a host's world the dynamic bodies carrying it ([`super::Carriers`]).
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Supports {
    /// Unit normal (towards the node) of the surface that pushed the node in Rapier's last
    /// step (a contact with a positive normal impulse; the deepest if several did); zero for a
    /// node no surface pushed.
    pub pushed: Vec<DVec3>,
    /// Unit normal of the nearest surface within [`crate::bodies::TOUCH_DISTANCE`] of the node,
    /// whether it pushed or not; zero if none is that close.
    pub touching: Vec<DVec3>,
    /// Coulomb friction coefficient μ (dimensionless) between the node and the surface in
    /// [`Self::pushed`], or, where none pushed, the one in [`Self::touching`]; 0 if neither.
    pub friction: Vec<f64>,
    /// Velocity (m/s) of the surface in [`Self::pushed`] at the node: a carrier's
    /// ([`super::Carriers`]); zero for a fixed or kinematic collider.
    pub velocity: Vec<DVec3>,
    /// Links a fixed surface's edge presses between their nodes ([`LinkSupport`]), filled by
    /// [`crate::bodies::ClothBodies::read_link_supports`]; empty unless the cloth asks for
    /// link support.
    pub links: Vec<LinkSupport>,
    /// Where static friction holds each link in [`Self::links`], kept from step to step (not
    /// cleared by [`Self::clear`]; [`crate::bodies::ClothBodies::read_link_supports`] keeps
    /// the anchors of links still pressed).
    pub anchors: LinkAnchors,
}

impl Supports {
    /// No surface under any of `n` nodes.
    pub fn new(n: usize) -> Self {
        Self {
            pushed: vec![DVec3::ZERO; n],
            touching: vec![DVec3::ZERO; n],
            friction: vec![0.0; n],
            velocity: vec![DVec3::ZERO; n],
            links: Vec::new(),
            anchors: LinkAnchors::new(),
        }
    }

    /// Sizes the lists for `n` nodes and clears them.
    pub fn clear(&mut self, n: usize) {
        for list in [&mut self.pushed, &mut self.touching, &mut self.velocity] {
            list.clear();
            list.resize(n, DVec3::ZERO);
        }
        self.friction.clear();
        self.friction.resize(n, 0.0);
        self.links.clear();
    }
}
