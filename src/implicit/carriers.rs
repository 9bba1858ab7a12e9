//! The host's dynamic bodies inside the implicit solve.
//!
//! A dynamic body touching the cloth, or holding it by a pin, is linked to it only by Rapier's
//! contact or joint, which Rapier resolves after our solve, node by node: a 50 g ball drives
//! the few nodes of 0.05 g it touches through the lattice at its own speed, a cloth falling onto
//! a box stops only at the nodes on top, and a cloth pinned to a light frame is held only at its
//! pins; at the host's step (1/60 s) each tears the cloth within a few steps. So each such
//! body, a *carrier*, joins the solve as a rigid body: its velocity change (ΔV, Δω) is solved
//! with the nodes', and the part of each coupled node's motion its surface prescribes (along
//! the contact normal; all of it where friction holds the node or a pin does) is the body's
//! motion at that node, ΔV + Δω × r (r from the body's centre of mass to the node). With
//! Δvᵢ = Pᵢ·yᵢ + (I − Pᵢ)·Gᵢ·ΔU + zᵢ (P the filter, G the body's motion at the node, z the
//! catch-up to the body's present velocity there), the solve minimises
//!
//!   ½·Δvᵀ·A·Δv − bᵀ·Δv + ½·ΔUᵀ·M_b·ΔU − h·ΔUᵀ·F_b,
//!
//! M_b the body's mass and inertia, F_b its weight. A body also resting on something else (a
//! box on the floor or on another box, a frame on a table) or jointed to another body keeps, in
//! the solve, the constraints Rapier's last step found there: its motion into each surface that
//! pushed it (or at each joint) is stopped, and the impulse that took, the weight of the body
//! and of the cloth on it included, is handed to the body before Rapier's step, whose contacts
//! and joints then carry it (Baraff & Witkin's filter, on the body's six velocities). The
//! coupled nodes move exactly with the body, the cloth's weight, pull and friction reach the
//! body within the step, and a light body holding a heavier cloth stays stable. Filled by
//! [`crate::bodies::ClothBodies::read_carriers`] before each solve.

use glam::{DMat3, DVec3};

/// A rigid body's six velocities (linear m/s, angular rad/s), or its six impulses (N·s,
/// N·m·s about the centre of mass).
pub type Twist = [DVec3; 2];

fn dot(a: &Twist, b: &Twist) -> f64 {
    a[0].dot(b[0]) + a[1].dot(b[1])
}

/// A host's dynamic body coupled to the cloth for one solve.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carrier {
    /// Mass (kg).
    pub mass: f64,
    /// Inertia tensor about the centre of mass in world axes (kg·m²); zero for a body that
    /// cannot turn (its rotations locked), whose Δω is then zero.
    pub inertia: DMat3,
    /// Its weight (N).
    pub weight: DVec3,
    /// Its velocity (m/s) and spin (rad/s) at the step's start, less any motion into its
    /// constraints ([`Self::constrained`]).
    pub velocity: Twist,
    /// Orthonormal basis of the directions in which its constraints stop it (rows n, r × n of
    /// each constraint, n its unit direction and r from the centre of mass to its point).
    basis: Vec<Twist>,
}

impl Carrier {
    /// A body of `mass` (kg) and world `inertia` (kg·m², zero if it cannot turn) with its
    /// `weight` (N), moving at `velocity`, held by `constraints`: (unit direction the body may
    /// not move along, from its centre of mass to the point, m).
    pub fn new(
        mass: f64,
        inertia: DMat3,
        weight: DVec3,
        velocity: Twist,
        constraints: &[(DVec3, DVec3)],
    ) -> Self {
        let mut basis: Vec<Twist> = Vec::new();
        for &(n, r) in constraints {
            let mut c: Twist = [n, r.cross(n)];
            if inertia == DMat3::ZERO {
                c[1] = DVec3::ZERO;
            }
            for q in &basis {
                let d = dot(&c, q);
                c = [c[0] - d * q[0], c[1] - d * q[1]];
            }
            let norm = dot(&c, &c).sqrt();
            // Directions already spanned (a box's fourth corner on the floor) add nothing.
            if norm > 1e-6 * (1.0 + r.length()) {
                basis.push([c[0] / norm, c[1] / norm]);
            }
        }
        let mut carrier = Self {
            mass,
            inertia,
            weight,
            velocity,
            basis,
        };
        carrier.velocity = carrier.constrained(velocity);
        carrier
    }

    /// `t` without its parts along the body's constraints (what the filter leaves free).
    pub fn constrained(&self, t: Twist) -> Twist {
        let mut t = t;
        for q in &self.basis {
            let d = dot(&t, q);
            t = [t[0] - d * q[0], t[1] - d * q[1]];
        }
        if self.inertia == DMat3::ZERO {
            t[1] = DVec3::ZERO;
        }
        t
    }

    /// Whether any constraint holds the body.
    pub fn is_held(&self) -> bool {
        !self.basis.is_empty()
    }

    /// M_b·t: the body's momentum (N·s, N·m·s) for the velocities `t`.
    pub fn momentum(&self, t: Twist) -> Twist {
        [self.mass * t[0], self.inertia * t[1]]
    }
}

/// The carriers of one solve and which nodes each one couples.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Carriers {
    /// The bodies.
    pub bodies: Vec<Carrier>,
    /// Per node: index into [`Self::bodies`] of the body coupled to it, `None` for most.
    pub of_node: Vec<Option<u32>>,
    /// Per node: from the body's centre of mass to the node's contact point or pin (m), where
    /// coupled.
    pub arm: Vec<DVec3>,
    /// Per node: coupled by a pin (`true`) rather than by contact.
    pub pinned: Vec<bool>,
    /// Output of the last solve: each body's velocity and spin change from
    /// [`Carrier::velocity`], its weight's share over the step included.
    pub changes: Vec<Twist>,
    /// Output of the last solve: the impulse its constraints took from each body (N·s, N·m·s
    /// about its centre of mass; zero for a body nothing else holds), to hand to it before
    /// Rapier's step, whose contacts and joints take it.
    pub held_impulses: Vec<Twist>,
}

impl Carriers {
    /// No carrier for `n` nodes.
    pub fn new(n: usize) -> Self {
        let mut carriers = Self::default();
        carriers.clear(n);
        carriers
    }

    /// Sizes the per-node lists for `n` nodes and removes every body.
    pub fn clear(&mut self, n: usize) {
        self.bodies.clear();
        self.changes.clear();
        self.held_impulses.clear();
        self.of_node.clear();
        self.of_node.resize(n, None);
        self.arm.clear();
        self.arm.resize(n, DVec3::ZERO);
        self.pinned.clear();
        self.pinned.resize(n, false);
    }

    /// Whether any body is coupled.
    pub fn is_empty(&self) -> bool {
        self.bodies.is_empty()
    }
}
