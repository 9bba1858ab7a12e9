//! Turning a validated [`Scene`] into a bevy_ecs `World`: the Rapier world as a resource, the
//! cloth as an entity carrying one component per effect the scene asks for.

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::DVec3;
use rand::Rng;
use rand_chacha::ChaCha8Rng;
use rand_chacha::rand_core::SeedableRng;
use rapier3d::prelude::PhysicsWorld;

use super::{ClothShape, ColliderShape, Scene, StretchModel};
use crate::bodies::{ClothBodies, NodeOptions, WorldShape, add_world_collider, configure_world};
use crate::forces::{
    AirDrag, Bending, ClothTopology, KesTensile, LinkCompression, LinkDamping, SeedSeparation, Trellising,
};
use crate::measure::{Motion, SettleState};
use crate::schedule::{Clock, ClothNodes, ClothState, Effect, EffectLedger, Failure, Physics};

/// The woven grid of a cloth shape and its flat node positions (m), before perturbation.
pub fn cloth_grid(scene: &Scene) -> (ClothTopology, Vec<DVec3>) {
    let c = &scene.spec.cloth;
    let sigma = c.spacing_m;
    let (n, half, keep_radius) = match c.shape {
        ClothShape::Circle { diameter_m } => {
            let k = (diameter_m / 2.0 / sigma + 1e-9).floor() as usize;
            (2 * k + 1, k as f64, Some(diameter_m / 2.0))
        }
        ClothShape::Square { side_m } => {
            let n = (side_m / sigma).round() as usize + 1;
            (n, (n - 1) as f64 / 2.0, None)
        }
    };
    let topology = ClothTopology::from_mask(n, n, sigma, |i, j| {
        let (x, z) = ((i as f64 - half) * sigma, (j as f64 - half) * sigma);
        keep_radius.is_none_or(|r| x * x + z * z <= r * r * (1.0 + 1e-9))
    });
    let angle = c.warp_angle_deg.to_radians();
    let warp = DVec3::new(angle.cos(), 0.0, -angle.sin());
    let weft = DVec3::new(angle.sin(), 0.0, angle.cos());
    let centre = DVec3::from_array(c.centre_m);
    let origin = centre - half * sigma * (warp + weft);
    let positions = topology.rest_positions(origin, warp, weft);
    (topology, positions)
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
    let fx = &spec.effects;
    let mut physics = PhysicsWorld::default();
    let i = &spec.integration;
    configure_world(
        &mut physics,
        spec.world.gravity_m_per_s2,
        i.dt_s,
        i.solver_iterations,
        i.internal_pgs_iterations,
    );

    let radius = scene.node_radius();
    for (col, (shape, _)) in spec.world.colliders.iter().zip(world_shapes(scene)) {
        let mu = if fx.friction { col.friction } else { 0.0 };
        add_world_collider(&mut physics, shape, col.centre_m, mu, radius);
    }

    let (topology, mut positions) = cloth_grid(scene);
    let topology = Arc::new(topology);
    if spec.cloth.perturbation_m > 0.0 {
        let mut rng = ChaCha8Rng::seed_from_u64(spec.seed);
        for p in &mut positions {
            p.y += spec.cloth.perturbation_m * rng.random_range(-1.0..=1.0);
        }
    }
    let sigma = topology.spacing;
    let node_mass = scene.fabric.areal_density * sigma * sigma;
    let options = NodeOptions {
        mass: node_mass,
        radius,
        rope_links: fx.stretch == StretchModel::Constraint,
        contact: fx.contact,
        self_collision: fx.self_collision,
        gravity: fx.gravity,
    };
    let bodies = ClothBodies::spawn(&mut physics, &topology, &positions, &options);

    let mut world = World::new();
    let mut cloth = world.spawn((ClothState::new(topology.clone(), positions), ClothNodes(bodies)));
    let fabric = &scene.fabric;
    if fx.bending {
        cloth.insert(Effect(Bending::new(topology.clone(), fabric)));
    }
    if fx.trellising {
        cloth.insert(Effect(Trellising::new(topology.clone(), fabric)));
    }
    match fx.stretch {
        StretchModel::Constraint => {
            let k = LinkCompression::stable_stiffness(node_mass, i.dt_s);
            cloth.insert(Effect(LinkCompression::new(topology.clone(), k)));
        }
        StretchModel::Seed => {
            cloth.insert(Effect(SeedSeparation::new(topology.clone(), fabric)));
        }
        StretchModel::Kes => {
            cloth.insert(Effect(KesTensile::new(topology.clone(), fabric)));
        }
    }
    if let Some(d) = fx.damping {
        cloth.insert(Effect(LinkDamping::new(
            topology.clone(),
            d.rate_per_s,
            node_mass,
        )));
    }
    if let Some(a) = fx.air_drag {
        cloth.insert(Effect(AirDrag::new(a.coefficient_n_s_per_m3, sigma)));
    }
    let entity = cloth.id();

    world.insert_resource(Physics(physics));
    world.insert_resource(Clock {
        dt: i.dt_s,
        step: 0,
        time: 0.0,
    });
    world.insert_resource(EffectLedger::with_all_effects());
    world.insert_resource(Motion::default());
    world.insert_resource(Failure::default());
    world.insert_resource(SettleState::new(
        i.settle.max_speed_m_per_s,
        i.settle.hold_s,
        i.settle.min_time_s,
    ));
    (world, entity)
}
