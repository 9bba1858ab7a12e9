//! A KES cloth dropped onto a user's pile of rigid boxes, driven from a plain Rapier loop.
//! Prints where the cloth came to rest and how far the top box was pushed.

use glam::DVec3;
use kes_cloth::embed::{ClothBuilder, ClothOutline};
use kes_cloth::material::Fabric;
use rapier3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let mut world = PhysicsWorld::default();
    // kes-cloth's forces are explicit: a step its stiffest spring allows (one substep is enough).
    world.integration_parameters.dt = 1.0 / 4000.0;
    world.integration_parameters.num_solver_iterations = 1;
    world.integration_parameters.num_internal_pgs_iterations = 4;

    // The user's scene: a floor and a pile of three boxes (5 cm cubes, 100 g each).
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.05, 1.0)
            .translation(Vector::new(0.0, -0.05, 0.0))
            .build(),
        None,
    );
    let mut top = None;
    for k in 0..3 {
        let body = world.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 0.025 + 0.05 * k as f32, 0.0))
                .build(),
        );
        world.insert_collider(
            ColliderBuilder::cuboid(0.025, 0.025, 0.025).mass(0.1).build(),
            Some(body),
        );
        top = Some(body);
    }
    let top = top.ok_or("no boxes")?;
    let start = world.bodies.get(top).ok_or("box")?.translation();

    let fabric = Fabric::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/fabrics/thin_wool.ron"
    ))?;
    let mut cloth = ClothBuilder::new(fabric)
        .outline(ClothOutline::Rectangle { warp: 0.3, weft: 0.3 })
        .spacing(0.015)
        .pose(DVec3::new(0.0, 0.2, 0.0), 0.0)
        .build(&mut world)?;
    for _ in 0..4000 {
        cloth.step(&mut world)?;
    }
    let end = world.bodies.get(top).ok_or("box")?.translation();
    println!("cloth lowest point: {:.3} m (floor at 0)", cloth.lowest_point());
    let highest = cloth.positions().iter().map(|p| p.y).fold(f64::MIN, f64::max);
    println!(
        "cloth's highest point {highest:.3} m (draped over the 0.15 m pile); top box moved {:.1} mm",
        (end - start).length() * 1000.0
    );
    Ok(())
}
