//! The host's dynamic bodies that carry or pin the cloth, read for the implicit solve
//! ([`crate::implicit::Carriers`]), and moved as it solved them.

use std::collections::HashMap;

use glam::{DMat3, DVec3};
use rapier3d::prelude::*;

use super::cloth_bodies::body_pairs;
use super::{ClothBodies, TOUCH_DISTANCE};
use crate::implicit::{Carrier, Carriers, ImplicitSolver};

/// The carriers of one cloth's last solve: their body handles, in [`Carriers::bodies`] order.
#[derive(Clone, Debug, Default)]
pub struct CarrierMemory {
    handles: Vec<RigidBodyHandle>,
}

impl ClothBodies {
    /// Fills `carriers` for the coming solve of a step of `dt` (s), after
    /// [`Self::read_supports`], [`Self::back_supported_nodes`] and
    /// [`Self::read_pin_velocities`]:
    ///
    /// - a node pinned to a dynamic body ([`Self::dynamic_pins`]) goes with that body, its pin
    ///   velocity the body's velocity at the anchor;
    /// - a node that no fixed or kinematic surface supports, in contact with a dynamic body
    ///   (not a node) that touches it (within [`TOUCH_DISTANCE`], or pushed it in Rapier's last
    ///   step), or will reach it within the step at their present velocities, or pushed it in
    ///   the last solve (`pressed`) and is still in contact with it, is supported by
    ///   that body (the nearest, if several): `supports` gets the contact's normal, the body
    ///   collider's friction coefficient and the body's velocity at the node. Only with
    ///   friction in the solve (the KES tensile law; with rope joints Rapier's contact carries
    ///   a supported node's weight and friction, and a body's contacts stay Rapier's).
    ///
    /// Each body brings its weight, and the constraints that held it in Rapier's last step: the
    /// normal of every contact with a collider that is not a node and pushed it, and the three
    /// axes at every joint to a body that is not a node ([`Carrier::new`]).
    pub fn read_carriers(
        &self,
        world: &PhysicsWorld,
        solver: &mut ImplicitSolver,
        memory: &mut CarrierMemory,
    ) {
        let dt = world.integration_parameters.dt as f64;
        let pressed = solver.pressed().to_vec();
        // Without friction in the solve (rope joints), Rapier's contact carries a supported
        // node's weight and friction: a body's contacts with the cloth stay Rapier's.
        let contacts = solver.has_friction();
        let ImplicitSolver {
            supports,
            pin_velocities,
            carriers,
            ..
        } = solver;
        let n = self.handles.len();
        carriers.clear(n);
        memory.handles.clear();
        let mut index: HashMap<RigidBodyHandle, u32> = HashMap::new();
        let mut register = |handle: RigidBodyHandle, body: &RigidBody, carriers: &mut Carriers| -> u32 {
            *index.entry(handle).or_insert_with(|| {
                carriers.bodies.push(self.carrier(world, handle, body));
                memory.handles.push(handle);
                (carriers.bodies.len() - 1) as u32
            })
        };
        for &(node, handle, anchor) in &self.dynamic_pins {
            let Some(body) = world.bodies.get(handle).filter(|_| node < n) else {
                continue;
            };
            let k = register(handle, body, carriers);
            let arm = (body.position().transform_point(anchor) - body.center_of_mass()).as_dvec3();
            carriers.of_node[node] = Some(k);
            carriers.pinned[node] = true;
            carriers.arm[node] = arm;
            if let Some(slot) = pin_velocities.get_mut(node) {
                *slot = Some(point_velocity(&carriers.bodies[k as usize], arm));
            }
        }
        for (i, h) in self.handles.iter().enumerate() {
            let supported = supports.pushed[i] != DVec3::ZERO || supports.touching[i] != DVec3::ZERO;
            if supported || carriers.pinned[i] || !contacts {
                continue;
            }
            let Some(node) = world.bodies.get(*h) else {
                continue;
            };
            // A node its carrier pushed in the last solve keeps it while their contact lasts:
            // the solve leaves them touching without pressing, and without this rule every
            // other step would let go of them (the ball on a hammock at 1/60 s: 16 and 4 nodes
            // carried by turns, and never at rest).
            let kept = pressed.get(i) == Some(&true);
            let Some((handle, body, normal, mu, at)) = self.nearest_carrier(world, node, dt, kept) else {
                continue;
            };
            let k = register(handle, body, carriers);
            let arm = (at - body.center_of_mass()).as_dvec3();
            carriers.of_node[i] = Some(k);
            carriers.arm[i] = arm;
            supports.pushed[i] = normal;
            supports.touching[i] = normal;
            supports.friction[i] = mu;
            supports.velocity[i] = point_velocity(&carriers.bodies[k as usize], arm);
        }
    }

    /// The dynamic body (not a node) nearest to `node` among those touching it or reaching it
    /// within `dt` (s), or any in contact if `kept`: its handle, the body, the contact's unit
    /// normal towards the node (the
    /// sheet's, as [`super::SheetContacts`] made it), the body collider's friction coefficient
    /// and the contact's point on the body (m; a ball's point nearest the sheet, as
    /// [`super::SheetContacts`] puts it).
    fn nearest_carrier<'w>(
        &self,
        world: &'w PhysicsWorld,
        node: &RigidBody,
        dt: f64,
        kept: bool,
    ) -> Option<(RigidBodyHandle, &'w RigidBody, DVec3, f64, Vec3)> {
        let v = node.linvel().as_dvec3();
        let mut nearest: Option<(f64, RigidBodyHandle, &RigidBody, DVec3, f64, Vec3)> = None;
        for (pair, other, node_first) in body_pairs(world, node) {
            let Some(collider) = world.colliders.get(other) else {
                continue;
            };
            let Some((handle, body)) = collider
                .parent()
                .and_then(|b| world.bodies.get(b).map(|body| (b, body)))
                .filter(|(_, body)| body.is_dynamic() && !self.is_node(body))
            else {
                continue;
            };
            let u = body.velocity_at_point(node.translation()).as_dvec3();
            for manifold in pair.manifolds() {
                // The manifold normal points from collider 1 to collider 2.
                let normal = manifold.data.normal.as_dvec3();
                let towards_node = if node_first { -normal } else { normal };
                // How far the gap closes within the step (m).
                let closing = (-(v - u).dot(towards_node) * dt).max(0.0);
                for point in &manifold.points {
                    let dist = point.dist as f64;
                    let touches =
                        kept || point.data.impulse > 0.0 || dist <= TOUCH_DISTANCE as f64 || dist <= closing;
                    if touches && nearest.is_none_or(|(d, ..)| dist < d) {
                        let local = if node_first {
                            point.local_p2
                        } else {
                            point.local_p1
                        };
                        let at = match collider.shape().as_ball() {
                            Some(ball) => {
                                collider.position().translation + ball.radius * towards_node.as_vec3()
                            }
                            None => collider.position().transform_point(local),
                        };
                        // Nodes have friction 0 and a body's collider the Max rule by
                        // default; the collider's own coefficient is the pair's.
                        let mu = collider.friction() as f64;
                        nearest = Some((dist, handle, body, towards_node, mu, at));
                    }
                }
            }
        }
        nearest.map(|(_, handle, body, normal, mu, at)| (handle, body, normal, mu, at))
    }

    /// `body` as a carrier: its mass, world inertia (zero if it cannot turn freely), weight,
    /// velocity, and the constraints that held it in Rapier's last step.
    fn carrier(&self, world: &PhysicsWorld, handle: RigidBodyHandle, body: &RigidBody) -> Carrier {
        let props = body.mass_properties();
        let w = props.effective_world_inv_inertia;
        let inverse = DMat3::from_cols_array(&[
            w.m11 as f64,
            w.m12 as f64,
            w.m13 as f64,
            w.m12 as f64,
            w.m22 as f64,
            w.m23 as f64,
            w.m13 as f64,
            w.m23 as f64,
            w.m33 as f64,
        ]);
        let free = !body.locked_axes().intersects(LockedAxes::ROTATION_LOCKED);
        let inertia = if free && inverse.determinant() > 0.0 {
            inverse.inverse()
        } else {
            DMat3::ZERO
        };
        let mass = body.mass() as f64;
        let weight = mass * (world.gravity * body.gravity_scale()).as_dvec3();
        let centre = body.center_of_mass();
        let not_node = |b: Option<RigidBodyHandle>| {
            b.and_then(|b| world.bodies.get(b))
                .is_none_or(|b| !self.is_node(b))
        };
        let mut constraints = Vec::new();
        for (pair, other, body_first) in body_pairs(world, body) {
            let own = if body_first {
                pair.collider1
            } else {
                pair.collider2
            };
            let Some(collider) = world.colliders.get(own) else {
                continue;
            };
            let other_parent = world.colliders.get(other).and_then(|o| o.parent());
            if !not_node(other_parent) {
                continue;
            }
            let other_body = other_parent.and_then(|o| world.bodies.get(o));
            for manifold in pair.manifolds() {
                // The manifold normal points from collider 1 to collider 2; the body may
                // not move against the normal towards it.
                let normal = manifold.data.normal.as_dvec3();
                let towards_body = if body_first { -normal } else { normal };
                for point in manifold.points.iter().filter(|p| p.data.impulse > 0.0) {
                    let local = if body_first {
                        point.local_p1
                    } else {
                        point.local_p2
                    };
                    let at = collider.position().transform_point(local);
                    let arm = (at - centre).as_dvec3();
                    // A contact that is not sliding holds the body in every direction (its
                    // friction, as far as Rapier's cone allows), one that slides along
                    // its normal only.
                    let other_velocity = other_body.map_or(Vec3::ZERO, |o| o.velocity_at_point(at));
                    let slip = (body.velocity_at_point(at) - other_velocity).as_dvec3();
                    let sliding = (slip - slip.dot(towards_body) * towards_body).length() > STILL;
                    if sliding {
                        constraints.push((towards_body, arm));
                    } else {
                        constraints.extend([DVec3::X, DVec3::Y, DVec3::Z].map(|axis| (axis, arm)));
                    }
                }
            }
        }
        for (a, b, _, joint) in world.impulse_joints.attached_joints(handle) {
            let (other, anchor) = if a == handle {
                (b, joint.data.local_frame1.translation)
            } else {
                (a, joint.data.local_frame2.translation)
            };
            if not_node(Some(other)) {
                let arm = (body.position().transform_point(anchor) - centre).as_dvec3();
                for axis in [DVec3::X, DVec3::Y, DVec3::Z] {
                    constraints.push((axis, arm));
                }
            }
        }
        let velocity = [body.linvel().as_dvec3(), body.angvel().as_dvec3()];
        Carrier::new(mass, inertia, weight, velocity, &constraints)
    }

    /// Gives each carrier of the last solve ([`Self::read_carriers`]) its solved velocity and
    /// spin (`carriers.changes`), less the gravity Rapier's step adds back, and hands a held
    /// one the impulse its constraints took in the solve (`carriers.held_impulses`: its
    /// weight and the cloth's on it), for Rapier's contacts and joints to take. Call it after
    /// [`Self::write_forces`], right before the world's step.
    pub fn move_carriers(&self, world: &mut PhysicsWorld, carriers: &Carriers, memory: &CarrierMemory) {
        let (gravity, dt) = (world.gravity, world.integration_parameters.dt);
        for (k, handle) in memory.handles.iter().enumerate() {
            let (Some(body), Some(carrier), Some([dv, dw])) = (
                world.bodies.get_mut(*handle),
                carriers.bodies.get(k),
                carriers.changes.get(k),
            ) else {
                continue;
            };
            let [v, w] = carrier.velocity;
            body.set_linvel((v + *dv).as_vec3() - gravity * body.gravity_scale() * dt, true);
            // A body with a locked rotation axis is solved without turning: its spin is Rapier's.
            if carrier.inertia != DMat3::ZERO {
                body.set_angvel((w + *dw).as_vec3(), true);
            }
            if let Some([j, t]) = carriers.held_impulses.get(k) {
                body.apply_impulse(j.as_vec3(), true);
                body.apply_torque_impulse(t.as_vec3(), true);
            }
        }
    }
}

/// Relative speed (m/s) along a contact below which a carrier's contact with something other
/// than the cloth holds it in every direction ([`ClothBodies::read_carriers`]).
const STILL: f64 = 1e-3;

/// The velocity (m/s) of `carrier` at `arm` (m) from its centre of mass, as the solve starts it.
fn point_velocity(carrier: &Carrier, arm: DVec3) -> DVec3 {
    carrier.velocity[0] + carrier.velocity[1].cross(arm)
}
