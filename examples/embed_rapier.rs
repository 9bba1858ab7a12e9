//! A KES cloth in a user's own Rapier world, driven from a plain Rapier loop at the host's step
//! (Rapier's default 1/60 s): the cloth falls onto the user's table, lying on it with its lower
//! face, and a stack of three 100 g boxes is then dropped onto it. Prints where the cloth and
//! the boxes came to rest.

use glam::DVec3;
use kes_cloth::embed::{ClothBuilder, ClothOutline, prepare_world};
use kes_cloth::material::Fabric;
use rapier3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    // The user's world, at its own step; `prepare_world` sets the two Rapier parameters a
    // cloth needs to come to rest there (one substep, no contact recycling).
    let mut world = PhysicsWorld::default();
    let dt = world.integration_parameters.dt;
    prepare_world(&mut world.integration_parameters);

    // The user's scene: a floor and a 20 cm table, 10 cm high.
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.05, 1.0)
            .translation(Vector::new(0.0, -0.05, 0.0))
            .build(),
        None,
    );
    world.insert_collider(
        ColliderBuilder::cuboid(0.1, 0.05, 0.1)
            .translation(Vector::new(0.0, 0.05, 0.0))
            .build(),
        None,
    );

    // A 30 cm square of thin wool 2 cm above the table. The world's step is beyond the
    // fabric's explicit limit, so the builder integrates it implicitly.
    let fabric = Fabric::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/fabrics/thin_wool.ron"
    ))?;
    let mut cloth = ClothBuilder::new(fabric)
        .outline(ClothOutline::Rectangle { warp: 0.3, weft: 0.3 })
        .spacing(0.01)
        .pose(DVec3::new(0.0, 0.12, 0.0), 0.0)
        .rest_on_lower_face(true)
        .build(&mut world)?;
    let frames = |seconds: f32| (seconds / dt).round() as usize;
    for _ in 0..frames(1.5) {
        cloth.step(&mut world)?;
    }

    // Three 5 cm boxes of 100 g, stacked 5 cm above the cloth's middle, dropped.
    let mut boxes = Vec::new();
    for k in 0..3 {
        let body = world.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 0.175 + 0.06 * k as f32, 0.0))
                .build(),
        );
        world.insert_collider(
            ColliderBuilder::cuboid(0.025, 0.025, 0.025).mass(0.1).build(),
            Some(body),
        );
        boxes.push(body);
    }
    for _ in 0..frames(2.5) {
        // A diverging cloth would stop here with an error naming its step, node and effect.
        cloth.step(&mut world)?;
    }

    let motion = cloth.motion();
    println!(
        "cloth lowest point: {:.1} mm above the floor (the table's top at 100 mm); fastest node {:.2} mm/s",
        cloth.lowest_point() * 1e3,
        motion.max_speed * 1e3
    );
    for (k, body) in boxes.iter().enumerate() {
        let b = world.bodies.get(*body).ok_or("a box")?;
        println!(
            "box {}: centre {:.1} mm above the floor, {:.2} mm/s",
            k + 1,
            b.translation().y * 1e3,
            b.linvel().length() * 1e3
        );
    }
    Ok(())
}
