//! Spawning cloth nodes and links, reading their state, writing our forces.

use glam::DVec3;
use rapier3d::prelude::*;

use super::{encode_normal, encode_surface_depth, sheet_normals};
use crate::forces::ClothTopology;
use crate::implicit::Supports;

/// Collision group of the fixed world (table, disk, floor, user bodies).
pub(crate) const WORLD_GROUP: Group = Group::GROUP_1;
/// Collision group of cloth nodes.
pub(crate) const CLOTH_GROUP: Group = Group::GROUP_2;

/// How to make the nodes of one cloth.
#[derive(Clone, Debug, PartialEq)]
pub struct NodeOptions {
    /// Mass of each node (kg), in particle order: areal density × the area it stands for.
    pub masses: Vec<f64>,
    /// Contact radius of each node's ball (m).
    pub radius: f64,
    /// Link warp/weft neighbours by rope joints at the rest spacing (stretch as a constraint).
    pub rope_links: bool,
    /// Nodes touch the world's colliders.
    pub contact: bool,
    /// Nodes touch each other (not their linked neighbours).
    pub self_collision: bool,
    /// Gravity acts on the nodes.
    pub gravity: bool,
    /// How much deeper than Rapier measures a node's ball its contacts with fixed and
    /// kinematic colliders are read (m, at most the radius; 0: as measured): the ball's centre
    /// then rests this much closer to the surface. Only in effect where the world is stepped
    /// with [`super::SheetContacts`].
    pub surface_depth: f64,
    /// Links, not only nodes, rest on the edges of fixed and kinematic colliders
    /// ([`crate::implicit::LinkSupport`], read by [`ClothBodies::read_link_supports`]), with a
    /// penalty spring whose natural frequency on the link's mean node mass is this (Hz);
    /// `None`: node contact only.
    pub link_support_hz: Option<f64>,
}

/// The Rapier bodies of one cloth, in particle order.
#[derive(Clone, Debug)]
pub struct ClothBodies {
    /// One dynamic rigid body per node.
    pub handles: Vec<RigidBodyHandle>,
    /// Rope joints, one per thread link (empty unless stretch is a constraint).
    pub joints: Vec<ImpulseJointHandle>,
    /// Mass of each node (kg), in particle order.
    pub masses: Vec<f64>,
    /// Nodes pinned to a kinematic body: (node, body, anchor in the body's frame, m). The
    /// implicit solve moves each with its pin ([`Self::read_pin_velocities`]).
    pub moving_pins: Vec<(usize, RigidBodyHandle, glam::Vec3)>,
    /// Nodes pinned to a dynamic body: (node, body, anchor in the body's frame, m). The
    /// implicit solve moves each with its body, which shares its mass with them
    /// ([`Self::read_carriers`]).
    pub dynamic_pins: Vec<(usize, RigidBodyHandle, glam::Vec3)>,
    /// [`NodeOptions::surface_depth`] (m).
    pub surface_depth: f64,
    /// Contact radius of each node's ball (m).
    pub radius: f64,
    /// [`NodeOptions::link_support_hz`] (Hz).
    pub link_support_hz: Option<f64>,
}

impl ClothBodies {
    /// Adds one node per particle at `positions` (m) and, if asked, a rope joint per link.
    pub fn spawn(
        world: &mut PhysicsWorld,
        topology: &ClothTopology,
        positions: &[DVec3],
        options: &NodeOptions,
    ) -> Self {
        let filter = match (options.contact, options.self_collision) {
            (true, true) => WORLD_GROUP | CLOTH_GROUP,
            (true, false) => WORLD_GROUP,
            (false, true) => CLOTH_GROUP,
            (false, false) => Group::NONE,
        };
        let groups = InteractionGroups::new(CLOTH_GROUP, filter, InteractionTestMode::And);
        let surface_depth = options.surface_depth.clamp(0.0, options.radius);
        let handles: Vec<RigidBodyHandle> = positions
            .iter()
            .zip(&options.masses)
            .map(|(p, &mass)| {
                let body = RigidBodyBuilder::dynamic()
                    .translation(p.as_vec3())
                    .lock_rotations()
                    .can_sleep(false)
                    .gravity_scale(if options.gravity { 1.0 } else { 0.0 })
                    .build();
                let handle = world.insert_body(body);
                // Friction 0 with the world's Max rule: the world collider's μ applies as given.
                let ball = ColliderBuilder::ball(options.radius as f32)
                    .mass(mass as f32)
                    .friction(0.0)
                    .collision_groups(groups)
                    .active_hooks(ActiveHooks::MODIFY_SOLVER_CONTACTS)
                    .user_data(if surface_depth > 0.0 {
                        encode_surface_depth(surface_depth as f32)
                    } else {
                        0
                    })
                    .build();
                world.insert_collider(ball, Some(handle));
                handle
            })
            .collect();
        let joints = if options.rope_links {
            topology
                .links
                .iter()
                .map(|&[p, q]| {
                    // Tension only: a rope joint's lower distance limit is not enforced (measured),
                    // so compression is resisted by `forces::LinkCompression` instead.
                    let rope = RopeJointBuilder::new(topology.spacing as f32)
                        .contacts_enabled(false)
                        .build();
                    world.insert_impulse_joint(handles[p as usize], handles[q as usize], rope)
                })
                .collect()
        } else {
            Vec::new()
        };
        Self {
            handles,
            joints,
            masses: options.masses.clone(),
            moving_pins: Vec::new(),
            dynamic_pins: Vec::new(),
            surface_depth,
            radius: options.radius,
            link_support_hz: options.link_support_hz,
        }
    }

    /// The velocity (m/s) each node pinned to a kinematic body will have over the coming step
    /// of `dt` (s): the anchor's displacement to the body's next pose over `dt` for a
    /// position-based body, the body's velocity at the anchor for a velocity-based one; `None`
    /// for every other node.
    pub fn read_pin_velocities(&self, world: &PhysicsWorld, dt: f64, out: &mut Vec<Option<DVec3>>) {
        out.clear();
        out.resize(self.handles.len(), None);
        for &(node, body, anchor) in &self.moving_pins {
            let Some(b) = world.bodies.get(body) else {
                continue;
            };
            let now = b.position().transform_point(anchor);
            let velocity = match b.body_type() {
                RigidBodyType::KinematicPositionBased => {
                    (b.next_position().transform_point(anchor) - now) / dt as f32
                }
                RigidBodyType::KinematicVelocityBased => b.velocity_at_point(now),
                _ => continue,
            };
            if let Some(slot) = out.get_mut(node) {
                *slot = Some(velocity.as_dvec3());
            }
        }
    }

    /// Copies node positions (m) and velocities (m/s) out of Rapier.
    pub fn read(&self, world: &PhysicsWorld, positions: &mut [DVec3], velocities: &mut [DVec3]) {
        for ((h, x), v) in self.handles.iter().zip(positions).zip(velocities) {
            if let Some(body) = world.bodies.get(*h) {
                *x = body.translation().as_dvec3();
                *v = body.linvel().as_dvec3();
            }
        }
    }

    /// Applies the strain limit ([`crate::implicit::limit_strain`]) to the state Rapier's step
    /// left, `positions` (m) and `velocities` (m/s) as just read: if a link of `topology` is
    /// outside the limit, moves the nodes (those `held` and those on a host's dynamic body stay)
    /// and writes the moved ones back into Rapier. Returns how many nodes it moved (0: nothing
    /// changed, the usual case). A cloth held by rope joints is left to them.
    pub fn limit_strain(
        &self,
        world: &mut PhysicsWorld,
        (topology, held): (&ClothTopology, &[bool]),
        positions: &mut [DVec3],
        velocities: &mut [DVec3],
    ) -> usize {
        if !self.joints.is_empty() || !crate::implicit::over_limit(topology, positions) {
            return 0;
        }
        // A node on a host's dynamic body stays too: moved into the body, Rapier's contact would
        // push the body away.
        let immovable: Vec<bool> = self
            .handles
            .iter()
            .zip(held)
            .map(|(h, held)| *held || self.touches_dynamic_body(world, *h))
            .collect();
        let moved = crate::implicit::limit_strain(topology, &self.masses, &immovable, positions, velocities);
        for &i in &moved {
            if let Some(body) = self.handles.get(i).and_then(|h| world.bodies.get_mut(*h)) {
                body.set_translation(positions[i].as_vec3(), false);
                body.set_linvel(velocities[i].as_vec3(), false);
                // The state holds what Rapier holds (f32), as a read would give.
                positions[i] = body.translation().as_dvec3();
                velocities[i] = body.linvel().as_dvec3();
            }
        }
        moved.len()
    }

    /// The acceleration (m/s²) Rapier's gravity gives the nodes: the world's gravity times the
    /// nodes' gravity scale (zero for a cloth built without gravity).
    pub fn gravity(&self, world: &PhysicsWorld) -> DVec3 {
        self.handles
            .first()
            .and_then(|h| world.bodies.get(*h))
            .map_or(DVec3::ZERO, |b| {
                world.gravity.as_dvec3() * b.gravity_scale() as f64
            })
    }

    /// Fills `supports` ([`Supports`]) from Rapier's last step. A node's pushing surface is one
    /// of a fixed or kinematic collider's contact points with a positive normal impulse (the
    /// deepest if several did), with that collider's friction coefficient: Rapier's own active
    /// set decides, so a node its contact no longer pushes (lifting off, or merely near the
    /// surface) is free, with no threshold of ours that could disagree. `touching` gets, for
    /// every node within [`TOUCH_DISTANCE`] of such a collider, the normal of the nearest one,
    /// whether it pushed or not.
    pub fn read_supports(&self, world: &PhysicsWorld, supports: &mut Supports) {
        supports.clear(self.handles.len());
        // Contacts are read as deep as `SheetContacts` makes Rapier read them.
        let depth = self.surface_depth as f32;
        let Supports {
            pushed,
            touching,
            friction,
            ..
        } = supports;
        for (((h, n), touch), mu) in self
            .handles
            .iter()
            .zip(pushed.iter_mut())
            .zip(touching.iter_mut())
            .zip(friction.iter_mut())
        {
            let mut nearest = TOUCH_DISTANCE;
            let Some(body) = world.bodies.get(*h) else {
                continue;
            };
            let mut deepest = f32::INFINITY;
            let mut touching_friction = 0.0;
            for (pair, other, node_first) in body_pairs(world, body) {
                let Some(surface) = world.colliders.get(other) else {
                    continue;
                };
                let support = surface
                    .parent()
                    .and_then(|b| world.bodies.get(b))
                    .is_none_or(|b| !b.is_dynamic());
                if !support {
                    continue;
                }
                for manifold in pair.manifolds() {
                    // The manifold normal points from collider 1 to collider 2.
                    let normal = manifold.data.normal.as_dvec3();
                    let towards_node = if node_first { -normal } else { normal };
                    for point in &manifold.points {
                        let dist = point.dist + depth;
                        if dist <= nearest {
                            nearest = dist;
                            *touch = towards_node;
                            touching_friction = surface.friction() as f64;
                        }
                        if point.data.impulse > 0.0 && dist <= deepest {
                            deepest = dist;
                            *n = towards_node;
                            // Nodes have friction 0 and world colliders the Max rule, so
                            // the surface's own coefficient is the pair's.
                            *mu = surface.friction() as f64;
                        }
                    }
                }
            }
            if *n == DVec3::ZERO {
                *mu = touching_friction;
            }
        }
    }

    /// Writes the cloth's unit surface normal at every node into its body's `user_data`, where
    /// [`super::SheetContacts`] reads it during the coming step; `normals` is scratch space.
    pub fn write_sheet_normals(
        &self,
        world: &mut PhysicsWorld,
        topology: &ClothTopology,
        positions: &[DVec3],
        normals: &mut Vec<DVec3>,
    ) {
        sheet_normals(topology, positions, normals);
        for (h, n) in self.handles.iter().zip(normals.iter()) {
            if let Some(body) = world.bodies.get_mut(*h) {
                body.user_data = encode_normal(n.as_vec3());
            }
        }
    }

    /// Makes every node resting on a fixed or kinematic surface (`supports`) immovable to the
    /// host's dynamic bodies for the coming step (a higher Rapier dominance group), and every
    /// other node an ordinary dynamic body. A body landing on the cloth where a support backs it
    /// then stops on the cloth as it would on the support, instead of driving nodes a thousand
    /// times lighter than itself through the support within one step; the body's push still
    /// reaches the cloth, one step later, through [`Self::read_body_loads`].
    pub fn back_supported_nodes(&self, world: &mut PhysicsWorld, supports: &Supports) {
        for ((h, pushed), touching) in self.handles.iter().zip(&supports.pushed).zip(&supports.touching) {
            let backed = *pushed != DVec3::ZERO || *touching != DVec3::ZERO;
            if let Some(body) = world.bodies.get_mut(*h) {
                let group = i8::from(backed);
                if body.dominance_group() != group {
                    body.set_dominance_group(group);
                }
            }
        }
    }

    /// The force (N) each node backed by a support ([`Self::back_supported_nodes`]) received
    /// from the host's dynamic bodies over Rapier's last step: the normal impulses of their
    /// contacts over the step `dt` (s), pushing the node away from the body, which Rapier did
    /// not apply to a node it held immovable. Any other node took its impulses in Rapier's
    /// step (zero here). Friction between a body and the cloth acts on the body but is not
    /// handed back.
    pub fn read_body_loads(&self, world: &PhysicsWorld, dt: f64, loads: &mut Vec<DVec3>) {
        loads.clear();
        loads.resize(self.handles.len(), DVec3::ZERO);
        for (h, load) in self.handles.iter().zip(loads.iter_mut()) {
            // A node not backed by a support took the bodies' impulses in Rapier's step itself.
            let Some(body) = world.bodies.get(*h).filter(|b| b.dominance_group() > 0) else {
                continue;
            };
            for (pair, other, node_first) in body_pairs(world, body) {
                let pushing_body =
                    collider_body(world, other).is_some_and(|b| b.is_dynamic() && !self.is_node(b));
                if !pushing_body {
                    continue;
                }
                for manifold in pair.manifolds() {
                    // The normal points from collider 1 to collider 2.
                    let away = manifold.data.normal.as_dvec3() * if node_first { -1.0 } else { 1.0 };
                    let impulse: f64 = manifold.points.iter().map(|p| p.data.impulse as f64).sum();
                    *load += away * (impulse / dt);
                }
            }
        }
    }

    /// Whether Rapier's last step found node `node` in contact with a dynamic body that is not
    /// a cloth node.
    fn touches_dynamic_body(&self, world: &PhysicsWorld, node: RigidBodyHandle) -> bool {
        world.bodies.get(node).is_some_and(|body| {
            body_pairs(world, body).any(|(pair, other, _)| {
                pair.has_any_active_contact()
                    && collider_body(world, other).is_some_and(|b| b.is_dynamic() && !self.is_node(b))
            })
        })
    }

    /// Whether `body` is a cloth node (of any cloth): nodes carry a surface normal.
    pub(super) fn is_node(&self, body: &RigidBody) -> bool {
        super::sheet_contacts::is_node(body)
    }

    /// Hands our node forces (N) to Rapier for the next step as a velocity kick F·dt/m (m the
    /// node mass), applied before the step, so that Rapier's substeps integrate positions with
    /// the whole kick (symplectic Euler at any substep count; a user force held over n substeps
    /// is not: `docs/rapier.md`). Call it once, right before `world.step()`. Any user force left
    /// on a node is cleared.
    pub fn write_forces(&self, world: &mut PhysicsWorld, forces: &[DVec3]) {
        let dt = world.integration_parameters.dt as f64;
        for ((h, f), m) in self.handles.iter().zip(forces).zip(&self.masses) {
            if let Some(body) = world.bodies.get_mut(*h) {
                body.reset_forces(false);
                let v = body.linvel().as_dvec3() + *f * (dt / m);
                body.set_linvel(v.as_vec3(), false);
            }
        }
    }
}

/// The rigid body a collider is attached to (`None` for a collider on no body, or unknown).
pub(super) fn collider_body(world: &PhysicsWorld, collider: ColliderHandle) -> Option<&RigidBody> {
    world
        .colliders
        .get(collider)
        .and_then(|c| c.parent())
        .and_then(|b| world.bodies.get(b))
}

/// Every contact pair of `body`'s colliders: the pair, the collider on its other side, and
/// whether `body`'s collider is the pair's first (a manifold's normal points from the first
/// collider to the second).
pub(super) fn body_pairs<'w>(
    world: &'w PhysicsWorld,
    body: &'w RigidBody,
) -> impl Iterator<Item = (&'w ContactPair, ColliderHandle, bool)> + 'w {
    body.colliders().iter().flat_map(move |&c| {
        world.contact_pairs_with(c).map(move |pair| {
            let first = pair.collider1 == c;
            (pair, if first { pair.collider2 } else { pair.collider1 }, first)
        })
    })
}

/// Contact distance (m) within which a node still touches a surface: a node the implicit solve
/// held on a surface keeps that support while this close (`docs/model.md` §12).
pub const TOUCH_DISTANCE: f32 = 2e-4;
