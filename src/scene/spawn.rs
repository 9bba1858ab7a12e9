//! Turning a validated [`Scene`] into a bevy_ecs `World`: the Rapier world as a resource, the
//! cloth as an entity carrying one component per effect the scene asks for. The cloth itself is
//! made by the same [`ClothBuilder`] that embedding users call.

use bevy_ecs::prelude::*;
use glam::DVec3;
use rapier3d::prelude::{PhysicsWorld, RigidBodyBuilder};

use super::{ClothShape, ColliderMotion, ColliderShape, IntegrationSpec, IntegratorSpec, Scene};
use crate::bodies::{ThrownBody, WorldShape, add_world_collider, configure_world};
use crate::embed::{ClothBuilder, ClothOutline, spawn_scene_cloth};
use crate::forces::ClothTopology;
use crate::implicit::{ImplicitSettings, Integrator, Scheme};
use crate::measure::{Motion, MovingColliders, SettleState, WorldColliders};
use crate::schedule::{Clock, EffectLedger, Failure, Physics};

/// The scene's cloth as a [`ClothBuilder`] (fabric, outline, spacing, pose, perturbation,
/// effects).
pub fn cloth_builder(scene: &Scene) -> ClothBuilder {
    let c = &scene.spec.cloth;
    let fx = &scene.spec.effects;
    let contact = &scene.spec.world.contact;
    let outline = match c.shape {
        ClothShape::Circle { diameter_m } => ClothOutline::Circle(diameter_m),
        ClothShape::Square { side_m } => ClothOutline::Rectangle {
            warp: side_m,
            weft: side_m,
        },
        ClothShape::Rectangle { warp_m, weft_m } => ClothOutline::Rectangle {
            warp: warp_m,
            weft: weft_m,
        },
    };
    ClothBuilder::new(scene.fabric.clone())
        .outline(outline)
        .spacing(c.spacing_m)
        .pose(DVec3::from_array(c.centre_m), c.warp_angle_deg)
        .initial_shear(c.initial_shear_deg)
        .lattice_offset(c.lattice_offset_m)
        .fold(c.fold_gap_m)
        .node_radius(scene.node_radius())
        .perturbation(c.perturbation_m, scene.spec.seed)
        .roughness(c.roughness)
        .node_mass(c.node_mass)
        .stretch(fx.stretch)
        .compression_modulus(fx.compression_modulus_n_per_m)
        .bending_and_trellising(fx.bending, fx.trellising)
        .damping(fx.damping.map(|d| d.rate_per_s))
        .air_drag(fx.air_drag.map(|a| a.coefficient_n_s_per_m3))
        .hysteresis(fx.hysteresis)
        .collisions_and_gravity(fx.contact, fx.self_collision, fx.gravity)
        .integrator(integrator(&scene.spec.integration))
        .link_support(contact.link_support.then_some(contact.fixed_hz))
}

fn integrator(spec: &IntegrationSpec) -> Integrator {
    match spec.integrator {
        IntegratorSpec::Explicit => Integrator::Explicit,
        IntegratorSpec::Implicit | IntegratorSpec::Bdf2 => Integrator::Implicit(ImplicitSettings {
            max_iterations: spec.implicit_solver.max_iterations,
            tolerance: spec.implicit_solver.tolerance,
            velocity_tolerance: spec.implicit_solver.velocity_tolerance_m_per_s,
            friction: spec.implicit_solver.friction,
            preconditioner: spec.implicit_solver.preconditioner,
            friction_release: spec.implicit_solver.friction_release,
            scheme: match spec.integrator {
                IntegratorSpec::Bdf2 => Scheme::Bdf2,
                _ => Scheme::BackwardEuler,
            },
        }),
    }
}

/// The woven grid of the scene's cloth and its flat node positions (m), before perturbation.
pub fn cloth_grid(scene: &Scene) -> (ClothTopology, Vec<DVec3>) {
    cloth_builder(scene).grid()
}

/// The scene's colliders as true shapes (m) with their centres (m).
pub fn world_shapes(scene: &Scene) -> Vec<(WorldShape, DVec3)> {
    scene
        .spec
        .world
        .colliders
        .iter()
        .map(|col| {
            let shape = match col.shape {
                ColliderShape::Cylinder {
                    radius_m,
                    half_height_m,
                } => WorldShape::Cylinder {
                    radius: radius_m,
                    half_height: half_height_m,
                },
                ColliderShape::Cuboid { half_extents_m } => WorldShape::Cuboid {
                    half_extents: half_extents_m,
                },
                ColliderShape::Ball { radius_m } => WorldShape::Ball { radius: radius_m },
            };
            (shape, DVec3::from_array(col.centre_m))
        })
        .collect()
}

/// Builds the ECS world for `scene`: returns it with the cloth's entity.
pub fn spawn(scene: &Scene) -> (World, Entity) {
    let spec = &scene.spec;
    let i = &spec.integration;
    let mut physics = PhysicsWorld::default();
    configure_world(
        &mut physics,
        spec.world.gravity_m_per_s2,
        i.dt_s,
        (i.solver_iterations, i.internal_pgs_iterations),
        spec.world.contact.stiffness(),
    );
    let mut builder = cloth_builder(scene);
    let (topology, flat) = builder.grid();
    for node in scene.pinned_nodes().into_iter().chain(scene.clamped_nodes()) {
        let anchor = physics.insert_body(RigidBodyBuilder::fixed().translation(flat[node].as_vec3()));
        builder = builder.pin(topology.grid_coords[node], anchor, glam::Vec3::ZERO);
    }
    let parts = builder.build_scene_parts(&mut physics);
    // The world's colliders come after the cloth's nodes, so that in each node–surface pair the
    // node is Rapier's first collider: adding a pair then searches the node's few contact-graph
    // edges, not the thousands a disk or table under the cloth has (docs/rapier.md, "Cost at
    // fine lattices").
    let radius = scene.node_radius();
    let mut moving = Vec::new();
    for (k, (col, (shape, _))) in spec.world.colliders.iter().zip(world_shapes(scene)).enumerate() {
        let mu = if spec.effects.friction { col.friction } else { 0.0 };
        let thrown = match col.motion {
            ColliderMotion::Fixed => None,
            ColliderMotion::Dynamic {
                mass_kg,
                velocity_m_per_s,
            } => Some(ThrownBody {
                mass: mass_kg,
                velocity: velocity_m_per_s,
            }),
        };
        if let (_, Some(body)) = add_world_collider(&mut physics, shape, col.centre_m, mu, radius, thrown) {
            moving.push((k, body));
        }
    }
    let mut world = World::new();
    let entity = spawn_scene_cloth(&mut world, parts);
    insert_resources(&mut world, physics, i.dt_s, &i.settle);
    world.insert_resource(WorldColliders(world_shapes(scene)));
    world.insert_resource(MovingColliders(moving));
    (world, entity)
}

/// Inserts the resources kes-cloth's systems need: the Rapier world, the clock at step `dt`
/// (s; the same step as `physics.integration_parameters.dt`, kept in f64 for the clock), the
/// effect ledger, motion statistics, the failure slot and the settle tracker.
pub fn insert_resources(world: &mut World, physics: PhysicsWorld, dt: f64, settle: &super::SettleSpec) {
    world.insert_resource(Clock {
        dt,
        step: 0,
        time: 0.0,
        rest_steps: 0,
        rest_given_up: false,
    });
    world.insert_resource(Physics(physics));
    world.insert_resource(EffectLedger::with_all_effects());
    world.insert_resource(Motion::default());
    world.insert_resource(Failure::default());
    world.insert_resource(SettleState::new(
        settle.max_speed_m_per_s,
        settle.hold_s,
        settle.min_time_s,
        settle.confirm_s,
    ));
}
