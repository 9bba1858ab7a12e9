//! Embedding: a cloth added to a hand-built Rapier world through the public API interacts both
//! ways with the user's bodies, and every example runs and prints its figure.

use glam::{DVec3, Vec3};
use kes_cloth::embed::{ClothBuilder, ClothOutline, KesCloth};
use rapier3d::prelude::*;

mod common;

/// A 20 cm hammock of broadcloth pinned at its four corners to fixed posts at y = 0.5 m,
/// optionally with a 50 g ball dropped on its middle. Returns (cloth's lowest point, ball
/// height and speed) after 1.5 s.
fn hammock(with_ball: bool) -> (f64, Option<(f32, f32)>) {
    let mut world = PhysicsWorld::default();
    world.integration_parameters.dt = 1.0 / 4000.0;
    world.integration_parameters.num_solver_iterations = 1;
    world.integration_parameters.num_internal_pgs_iterations = 4;
    let mut builder = ClothBuilder::new(common::shipped_fabric("cotton_broadcloth"))
        .outline(ClothOutline::Rectangle { warp: 0.2, weft: 0.2 })
        .spacing(0.02)
        .pose(DVec3::new(0.0, 0.5, 0.0), 0.0);
    // Posts 16 cm apart hold a 20 cm cloth: it has slack to sag into.
    for (i, j, x, z) in [
        (0, 0, -0.08, -0.08),
        (10, 0, 0.08, -0.08),
        (0, 10, -0.08, 0.08),
        (10, 10, 0.08, 0.08),
    ] {
        let post = world.insert_body(
            RigidBodyBuilder::fixed()
                .translation(Vector::new(x, 0.5, z))
                .build(),
        );
        builder = builder.pin((i, j), post, Vec3::ZERO);
    }
    let mut cloth: KesCloth = builder.build(&mut world).expect("the hammock builds");
    let ball = with_ball.then(|| {
        let b = world.insert_body(
            RigidBodyBuilder::dynamic()
                .translation(Vector::new(0.0, 0.56, 0.0))
                .build(),
        );
        world.insert_collider(ColliderBuilder::ball(0.03).mass(0.05).build(), Some(b));
        b
    });
    for _ in 0..6000 {
        cloth.step(&mut world).expect("the hammock steps");
    }
    let ball = ball
        .and_then(|b| world.bodies.get(b))
        .map(|b| (b.translation().y, b.linvel().length()));
    (cloth.lowest_point(), ball)
}

/// The cloth holds the ball up (it comes to rest above the posts' level minus the sag, not on
/// the floor, which is absent: a ball that fell through would keep falling), and the ball
/// makes the cloth sag more than its own weight does.
#[test]
fn a_ball_rests_on_the_cloth_and_makes_it_sag() {
    let (alone, _) = hammock(false);
    let (loaded, ball) = hammock(true);
    let (ball_y, ball_speed) = ball.unwrap();
    assert!(ball_y > 0.3, "the ball fell through: y = {ball_y}");
    assert!(ball_speed < 0.05, "the ball is not at rest: {ball_speed} m/s");
    // The ball sits in the cloth: the cloth is a net of 1 cm node balls, so the 3 cm ball settles
    // into a pocket among them, its centre within ball + node radius (4 cm) of the lowest node.
    assert!(
        (ball_y as f64 - loaded).abs() < 0.04,
        "ball at {ball_y}, cloth bottom {loaded}"
    );
    assert!(
        loaded < alone - 0.01,
        "sag with ball {loaded} m, without {alone} m"
    );
}

/// Every example runs to completion and prints its sanity figure.
#[test]
fn the_examples_run() {
    let exe = std::env::current_exe().unwrap();
    let examples = exe.parent().and_then(|d| d.parent()).unwrap().join("examples");
    for (name, expect) in [
        ("embed_rapier", "cloth lowest point"),
        ("embed_ecs", "pinned corner"),
        ("flag", "free edge trails the pole"),
        ("custom_fabric", "DC"),
    ] {
        let out = std::process::Command::new(examples.join(name))
            .output()
            .unwrap_or_else(|e| panic!("{name}: {e}"));
        assert!(
            out.status.success(),
            "{name} failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        let stdout = String::from_utf8_lossy(&out.stdout);
        assert!(stdout.contains(expect), "{name} printed: {stdout}");
    }
}
