//! KES cloth inside a user's bevy_ecs world at the host's fixed step (1/60 s): kes-cloth's
//! systems go into the user's schedule, and a user system, ordered before kes-cloth's forces,
//! moves a kinematic hook that holds one corner. Prints the corner's and the cloth's lowest
//! point's heights.

use bevy_ecs::prelude::*;
use glam::{DVec3, Vec3};
use kes_cloth::embed::{ClothBuilder, ClothOutline, install, spawn_cloth};
use kes_cloth::material::Fabric;
use kes_cloth::scene::SettleSpec;
use kes_cloth::schedule::{Clock, ClothState, Failure, Phase, Physics};
use rapier3d::prelude::*;

/// The user's kinematic hook.
#[derive(Resource)]
struct Hook(RigidBodyHandle);

/// User system: lift the hook 10 cm/s.
fn lift_hook(hook: Res<Hook>, clock: Res<Clock>, mut physics: ResMut<Physics>) {
    if let Some(body) = physics.0.bodies.get_mut(hook.0) {
        let y = 0.3 + 0.1 * clock.time as f32;
        body.set_next_kinematic_translation(Vector::new(-0.1, y, -0.1));
    }
}

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The host's fixed step: Rapier's default 1/60 s. The builder integrates the cloth
    // implicitly there; `prepare_world` sets the two Rapier parameters it needs to come to rest.
    let mut physics = PhysicsWorld::default();
    kes_cloth::embed::prepare_world(&mut physics.integration_parameters);
    let dt = physics.integration_parameters.dt as f64;
    let hook = physics.insert_body(
        RigidBodyBuilder::kinematic_position_based()
            .translation(Vector::new(-0.1, 0.3, -0.1))
            .build(),
    );

    let fabric = Fabric::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/fabrics/cotton_broadcloth.ron"
    ))?;
    // A 20 cm square; node (0, 0) sits at (−0.1, 0.3, −0.1), right on the hook.
    let parts = ClothBuilder::new(fabric)
        .outline(ClothOutline::Rectangle { warp: 0.2, weft: 0.2 })
        .spacing(0.02)
        .pose(DVec3::new(0.0, 0.3, 0.0), 0.0)
        .pin((0, 0), hook, Vec3::ZERO)
        .build_parts(&mut physics)?;

    let mut world = World::new();
    let cloth = spawn_cloth(&mut world, parts);
    kes_cloth::scene::spawn::insert_resources(&mut world, physics, dt, &SettleSpec::default());
    world.insert_resource(Hook(hook));
    let mut schedule = Schedule::default();
    install(&mut schedule);
    schedule.add_systems(lift_hook.before(Phase::Forces));
    for _ in 0..(1.0 / dt).round() as usize {
        schedule.run(&mut world);
    }
    // A diverging cloth stops our systems and leaves its step, node and effect here.
    if let Some(failure) = &world.resource::<Failure>().0 {
        return Err(format!("the cloth diverged: {failure:?}").into());
    }
    let state = world.get::<ClothState>(cloth).ok_or("cloth")?;
    let lowest = state.positions.iter().map(|p| p.y).fold(f64::INFINITY, f64::min);
    println!(
        "after 1 s: pinned corner at y = {:.3} m (hook at 0.400), lowest point {:.3} m",
        state.positions[0].y, lowest
    );
    Ok(())
}
