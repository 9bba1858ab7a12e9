//! Fixed colliders of the scene, shrunk by the node radius.
//!
//! A ball node of radius r touching a shape S has its centre on the surface of S grown by r.
//! Shrinking each collider by r (and rounding its edges by r, which growing does anyway) puts
//! the node centres, i.e. the cloth's mid-surface, on the true surface: the disk keeps its
//! radius and its top, the table its height.

use rapier3d::prelude::*;

use super::cloth_bodies::WORLD_GROUP;

/// Shape of a fixed collider, true (unshrunk) dimensions in metres, +y up.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum WorldShape {
    /// Vertical cylinder of `radius` and `half_height`.
    Cylinder {
        /// Radius (m).
        radius: f64,
        /// Half height (m).
        half_height: f64,
    },
    /// Axis-aligned box of half extents (m).
    Cuboid {
        /// Half extents along x, y, z (m).
        half_extents: [f64; 3],
    },
    /// Sphere of `radius` (m).
    Ball {
        /// Radius (m).
        radius: f64,
    },
}

/// A world collider that moves: a dynamic rigid body of `mass` (kg) starting at `velocity` (m/s).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ThrownBody {
    /// Mass (kg).
    pub mass: f64,
    /// Initial velocity (m/s).
    pub velocity: [f64; 3],
}

/// Adds a collider at `centre` (m) with friction `mu` against the cloth, shrunk by the node
/// radius `r` (m): fixed, or on a new dynamic body when `thrown` (returned with the collider).
/// The caller has checked every dimension exceeds `r`.
pub fn add_world_collider(
    world: &mut PhysicsWorld,
    shape: WorldShape,
    centre: [f64; 3],
    mu: f64,
    r: f64,
    thrown: Option<ThrownBody>,
) -> (ColliderHandle, Option<RigidBodyHandle>) {
    let builder = match shape {
        WorldShape::Cylinder { radius, half_height } => {
            ColliderBuilder::cylinder((half_height - r) as f32, (radius - r) as f32)
        }
        WorldShape::Cuboid {
            half_extents: [x, y, z],
        } => ColliderBuilder::cuboid((x - r) as f32, (y - r) as f32, (z - r) as f32),
        WorldShape::Ball { radius } => ColliderBuilder::ball((radius - r) as f32),
    };
    let at = Vector::new(centre[0] as f32, centre[1] as f32, centre[2] as f32);
    let builder = match thrown {
        Some(t) => builder.mass(t.mass as f32),
        None => builder.translation(at),
    };
    let collider = builder
        .friction(mu as f32)
        .friction_combine_rule(CoefficientCombineRule::Max)
        .collision_groups(InteractionGroups::new(
            WORLD_GROUP,
            Group::ALL,
            InteractionTestMode::And,
        ))
        .build();
    match thrown {
        None => (world.insert_collider(collider, None), None),
        Some(t) => {
            let [vx, vy, vz] = t.velocity.map(|v| v as f32);
            // CCD: a ball thrown at 10 m/s crosses a cloth node in well under one step.
            let body = RigidBodyBuilder::dynamic()
                .translation(at)
                .linvel(Vector::new(vx, vy, vz))
                .ccd_enabled(true)
                .build();
            let handle = world.insert_body(body);
            (world.insert_collider(collider, Some(handle)), Some(handle))
        }
    }
}
