//! The host's dynamic bodies solved with an embedded cloth at the host's step: a ball dropped
//! into a hammock, a frame holding the hammock on the floor, a cloth lying on a box and a cloth
//! dropped onto a pile of boxes, at 1/60 s and 1/240 s. The cloth and the bodies exchange
//! their weight and momentum within each step (`implicit::Carriers`): nothing tears, everything
//! comes to rest, and the floor carries exactly what stands on it.

use glam::{DVec3, Vec3};
use kes_cloth::embed::{ClothBuilder, ClothOutline, KesCloth, prepare_world};
use kes_cloth::forces::StretchModel;
use kes_cloth::implicit::{ImplicitSettings, Integrator, Scheme};
use rapier3d::prelude::*;

mod common;

/// Standard gravity as Rapier's default world has it (m/s²).
const G: f64 = 9.81;

/// The host's two steps (Hz).
const STEPS: [f64; 2] = [60.0, 240.0];

/// An empty world at `hz` with the cloth's two Rapier settings, and a fixed floor whose top is
/// at y = 0.
fn world(hz: f64) -> (PhysicsWorld, ColliderHandle) {
    let mut world = PhysicsWorld::default();
    world.integration_parameters.dt = (1.0 / hz) as f32;
    prepare_world(&mut world.integration_parameters);
    let floor = world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.05, 1.0)
            .translation(Vector::new(0.0, -0.05, 0.0))
            .build(),
        None,
    );
    (world, floor)
}

/// The floor's push on `body` (N): their contact impulses over Rapier's last step (a node
/// that reached the floor is not counted).
fn floor_force(world: &PhysicsWorld, floor: ColliderHandle, body: RigidBodyHandle) -> f64 {
    let on_body = |c: ColliderHandle| world.colliders.get(c).and_then(|c| c.parent()) == Some(body);
    let impulse: f64 = world
        .contact_pairs_with(floor)
        .filter(|pair| on_body(pair.collider1) || on_body(pair.collider2))
        .flat_map(|pair| pair.manifolds().iter())
        .flat_map(|m| m.points.iter())
        .map(|p| p.data.impulse as f64)
        .sum();
    impulse / world.integration_parameters.dt as f64
}

/// Steps `cloth` in `world` for `seconds` (s) and returns the floor's mean push on `body` (N)
/// over the last second: its corner contacts share a load differently step by step.
fn weigh(
    cloth: &mut KesCloth,
    world: &mut PhysicsWorld,
    (floor, body): (ColliderHandle, RigidBodyHandle),
    seconds: f64,
) -> f64 {
    let hz = (1.0 / world.integration_parameters.dt as f64).round();
    let steps = (seconds * hz) as usize;
    let (mut sum, mut count) = (0.0, 0);
    for s in 0..steps {
        cloth.step(world).expect("the bodies carry the cloth");
        if s >= steps - hz as usize {
            sum += floor_force(world, floor, body);
            count += 1;
        }
    }
    sum / count as f64
}

/// Fastest node (m/s).
fn fastest(cloth: &KesCloth) -> f64 {
    cloth.velocities().iter().map(|v| v.length()).fold(0.0, f64::max)
}

/// A hammock: a 20 cm square of broadcloth at 2 cm spacing, its four corners pinned where
/// they lie, 0.5 m up, to a frame (a 30 cm plate of 1 kg on the floor, `dynamic`, or fixed),
/// and a 50 g ball of 3 cm radius released 3 cm above the cloth's middle. Returns the world,
/// the floor, the cloth, the ball and the frame.
fn hammock(
    hz: f64,
    dynamic: bool,
) -> (
    PhysicsWorld,
    ColliderHandle,
    ClothBuilder,
    RigidBodyHandle,
    RigidBodyHandle,
) {
    let (mut world, floor) = world(hz);
    let frame = world.insert_body(if dynamic {
        RigidBodyBuilder::dynamic().build()
    } else {
        RigidBodyBuilder::fixed().build()
    });
    world.insert_collider(
        ColliderBuilder::cuboid(0.15, 0.005, 0.15)
            .translation(Vector::new(0.0, 0.005, 0.0))
            .mass(1.0)
            .build(),
        Some(frame),
    );
    let mut builder = ClothBuilder::new(common::shipped_fabric("cotton_broadcloth"))
        .outline(ClothOutline::Rectangle { warp: 0.2, weft: 0.2 })
        .spacing(0.02)
        .pose(DVec3::new(0.0, 0.5, 0.0), 0.0);
    for (i, j, x, z) in [
        (0, 0, -0.1, -0.1),
        (10, 0, 0.1, -0.1),
        (0, 10, -0.1, 0.1),
        (10, 10, 0.1, 0.1),
    ] {
        builder = builder.pin((i, j), frame, Vec3::new(x, 0.5, z));
    }
    let ball = world.insert_body(
        RigidBodyBuilder::dynamic()
            .translation(Vector::new(0.0, 0.56, 0.0))
            .build(),
    );
    world.insert_collider(ColliderBuilder::ball(0.03).mass(0.05).build(), Some(ball));
    (world, floor, builder, ball, frame)
}

/// A 50 g ball dropped into a hammock pinned to fixed posts is caught by the cloth alone: it
/// stretches the cloth (broadcloth is stiff: 4 cm of sag) but never tears it, and ball and cloth
/// come to rest (≤ 1 mm/s, the acceptance's rest) within 3 s. Before the ball was solved with
/// the cloth, it drove the few nodes it touched through the lattice at its own speed and the run
/// stopped at the impact, at both steps.
#[test]
fn a_ball_dropped_into_a_hammock_at_the_hosts_step_is_caught_and_comes_to_rest() {
    for hz in STEPS {
        let (mut world, _, builder, ball, _) = hammock(hz, false);
        let mut cloth = builder.build(&mut world).expect("the hammock builds");
        for _ in 0..(3.0 * hz) as usize {
            cloth.step(&mut world).expect("the hammock catches the ball");
        }
        let ball = &world.bodies[ball];
        let (y, speed) = (ball.translation().y, ball.linvel().length());
        println!(
            "{hz} Hz: ball at {y:.4} m, {:.2} mm/s; fastest node {:.2} mm/s; cloth's lowest {:.4} m",
            speed * 1e3,
            fastest(&cloth) * 1e3,
            cloth.lowest_point()
        );
        // Caught above the posts' plate, within the cloth's stretch: its centre its radius and
        // a node's (3 + 1 cm) above the lowest node, within a node radius.
        assert!(y > 0.45, "{hz} Hz: the ball fell through to {y} m");
        assert!(
            (y as f64 - cloth.lowest_point() - 0.04).abs() < 0.01,
            "{hz} Hz: ball at {y} m"
        );
        assert!(speed <= 1e-3, "{hz} Hz: the ball moves at {speed} m/s");
        assert!(
            fastest(&cloth) <= 1e-3,
            "{hz} Hz: a node moves at {} m/s",
            fastest(&cloth)
        );
    }
}

/// Newton's third law through the coupling: with the hammock's posts on a 1 kg plate standing
/// on the floor, the floor carries the plate, the cloth and the ball (10.36 N) once all is at
/// rest: the solve hands the plate the cloth's pull, the ball's weight goes through the cloth,
/// and no push is counted twice (a body's contact impulse that Rapier applied to a node is not
/// handed back to the cloth as a load as well). Tolerance 0.3 mN, two of the cloth's nodes'
/// weight (0.14 mN each), so that a node's weight lost or counted twice at the four pins fails
/// it (measured within 0.1 mN); the mean over the last second is taken ([`weigh`]).
#[test]
fn a_frame_holding_a_hammock_with_a_ball_in_it_puts_all_their_weight_on_the_floor() {
    for hz in STEPS {
        let (mut world, floor, builder, ball, frame) = hammock(hz, true);
        let mut cloth = builder.build(&mut world).expect("the hammock builds");
        let cloth_mass: f64 = cloth.parts().bodies.masses.iter().sum();
        let carried = weigh(&mut cloth, &mut world, (floor, frame), 3.0);
        let weight = (1.0 + 0.05 + cloth_mass) * G;
        let moving = [ball, frame].map(|b| world.bodies[b].linvel().length());
        println!(
            "{hz} Hz: floor carries {carried:.4} N of {weight:.4} N; ball {:.2} mm/s, frame {:.2} mm/s, fastest node {:.2} mm/s",
            moving[0] * 1e3,
            moving[1] * 1e3,
            fastest(&cloth) * 1e3
        );
        assert!(
            (carried - weight).abs() <= 3e-4,
            "{hz} Hz: the floor carries {carried} N, not {weight} N"
        );
        assert!(
            world.bodies[ball].translation().y > 0.45,
            "{hz} Hz: the ball fell through"
        );
        assert!(
            moving.iter().all(|v| *v <= 1e-3) && fastest(&cloth) <= 1e-3,
            "{hz} Hz: not at rest: {moving:?}"
        );
    }
}

/// A cloth lying on a dynamic box weighs on it: once at rest, the floor under a 100 g box
/// carries the box and the whole cloth (a 10 cm square on a 20 cm box), for every shipped
/// fabric at both steps, and for thin wool also with BDF2 (whose solve runs at 2/3 of the step:
/// the box's rows are scaled to match) and with friction left to Rapier (the rope-joint cloth's
/// setting, where the box's contacts with the cloth stay Rapier's, which must not count the
/// cloth's weight twice either). Tolerance 2 % of the cloth's weight (0.3–1 mN); the cloth
/// must stay on the box.
#[test]
fn a_cloth_lying_on_a_box_adds_its_weight_to_the_boxs_load_on_the_floor() {
    let bdf2 = ImplicitSettings {
        scheme: Scheme::Bdf2,
        ..ImplicitSettings::default()
    };
    let frictionless = ImplicitSettings {
        friction: Some(false),
        ..ImplicitSettings::default()
    };
    let mut cases: Vec<(String, ImplicitSettings)> = common::shipped_fabric_paths()
        .iter()
        .map(|p| {
            (
                p.file_stem().unwrap().to_string_lossy().to_string(),
                ImplicitSettings::default(),
            )
        })
        .collect();
    cases.push(("thin_wool".into(), bdf2));
    cases.push(("thin_wool".into(), frictionless));
    for (stem, settings) in cases {
        for hz in STEPS {
            let (mut world, floor) = world(hz);
            let block = world.insert_body(
                RigidBodyBuilder::dynamic()
                    .translation(Vector::new(0.0, 0.025, 0.0))
                    .build(),
            );
            world.insert_collider(
                ColliderBuilder::cuboid(0.1, 0.025, 0.1).mass(0.1).build(),
                Some(block),
            );
            // Node radius 5 mm: the cloth starts 2 mm above the box's top.
            let mut cloth = ClothBuilder::new(common::shipped_fabric(&stem))
                .outline(ClothOutline::Rectangle { warp: 0.1, weft: 0.1 })
                .spacing(0.01)
                .pose(DVec3::new(0.0, 0.057, 0.0), 0.0)
                .integrator(Integrator::Implicit(settings))
                .stretch(StretchModel::Kes)
                .build(&mut world)
                .expect("the cloth builds");
            let cloth_mass: f64 = cloth.parts().bodies.masses.iter().sum();
            let carried = weigh(&mut cloth, &mut world, (floor, block), 2.0);
            let weight = (0.1 + cloth_mass) * G;
            let case = format!(
                "{stem} {:?} friction {:?} {hz} Hz",
                settings.scheme, settings.friction
            );
            println!(
                "{case}: floor carries {carried:.5} N of {weight:.5} N (cloth {:.5} N); fastest node {:.3} mm/s",
                cloth_mass * G,
                fastest(&cloth) * 1e3
            );
            assert!(
                (carried - weight).abs() <= 0.02 * cloth_mass * G,
                "{case}: the floor carries {carried} N, not {weight} N"
            );
            assert!(cloth.lowest_point() > 0.05, "{case}: the cloth slid off the box");
            assert!(
                fastest(&cloth) <= 1e-3,
                "{case}: a node moves at {} m/s",
                fastest(&cloth)
            );
        }
    }
}

/// A 30 cm cloth of thin wool dropped from 5 cm onto a pile of three 5 cm boxes of 100 g each
/// (five times the cloth's mass) drapes over it at the host's step: the cloth lands at 1 m/s
/// on the top box, which the solve holds against the box below as Rapier's last step found it,
/// nothing tears, the pile stands (the top box within 2 mm of where it started sideways; down by
/// no more than Rapier's allowed penetration, 1 mm a contact, three contacts), no node goes
/// below the floor, and everything comes to rest.
#[test]
fn a_cloth_dropped_onto_a_pile_of_boxes_drapes_over_it_and_the_pile_stands() {
    for hz in STEPS {
        let (mut world, _) = world(hz);
        let boxes: Vec<RigidBodyHandle> = (0..3)
            .map(|k| {
                let b = world.insert_body(
                    RigidBodyBuilder::dynamic()
                        .translation(Vector::new(0.0, 0.025 + 0.05 * k as f32, 0.0))
                        .build(),
                );
                world.insert_collider(
                    ColliderBuilder::cuboid(0.025, 0.025, 0.025).mass(0.1).build(),
                    Some(b),
                );
                b
            })
            .collect();
        let spacing = 0.015;
        let mut cloth = ClothBuilder::new(common::shipped_fabric("thin_wool"))
            .outline(ClothOutline::Rectangle { warp: 0.3, weft: 0.3 })
            .spacing(spacing)
            .pose(DVec3::new(0.0, 0.2, 0.0), 0.0)
            .build(&mut world)
            .expect("the cloth builds");
        let top_start = world.bodies[boxes[2]].translation();
        let mut rest_from = None;
        let seconds = 6.0;
        for s in 0..(seconds * hz) as usize {
            cloth.step(&mut world).expect("the cloth drapes over the pile");
            let still = fastest(&cloth) <= 1e-3;
            rest_from = match (still, rest_from) {
                (true, None) => Some(s as f64 / hz),
                (true, since) => since,
                (false, _) => None,
            };
        }
        let moved = world.bodies[boxes[2]].translation() - top_start;
        let sideways = Vec3::new(moved.x, 0.0, moved.z).length();
        let lowest = cloth.lowest_point();
        println!(
            "{hz} Hz: top box moved {:.2} mm sideways, {:.2} mm up; lowest node {lowest:.4} m; fastest node {:.2} mm/s; at rest from {rest_from:?} s",
            sideways * 1e3,
            moved.y * 1e3,
            fastest(&cloth) * 1e3
        );
        assert!(
            sideways < 2e-3 && moved.y.abs() < 3e-3,
            "{hz} Hz: the top box moved by {moved:?}"
        );
        // Node centres rest a node radius (7.5 mm) above the floor, within Rapier's allowed
        // penetration.
        assert!(lowest > spacing / 2.0 - 1e-3, "{hz} Hz: a node at {lowest} m");
        assert!(
            rest_from.is_some(),
            "{hz} Hz: still moving at {} m/s after {seconds} s",
            fastest(&cloth)
        );
    }
}

/// The bevy_ecs way in steps the hammock on its frame exactly as `KesCloth::step` does: the
/// same world stepped 1 s either way ends with every node, the ball and the frame at the same
/// position to the bit. A schedule that left out the carriers (or read them at another point
/// of the step) would drift from the plain loop at the ball's impact.
#[test]
fn in_a_bevy_schedule_carriers_move_exactly_as_with_kes_cloth_step() {
    let hz = 60.0;
    let steps = hz as usize;

    let (mut plain, _, builder, ball, frame) = hammock(hz, true);
    let mut cloth = builder.build(&mut plain).expect("builds");
    for _ in 0..steps {
        cloth.step(&mut plain).expect("steps");
    }

    let (mut physics, _, builder, _, _) = hammock(hz, true);
    let parts = builder.build_parts(&mut physics).expect("builds");
    let (mut world, mut schedule, entity) = common::host_schedule(physics, parts);
    for _ in 0..steps {
        schedule.run(&mut world);
    }
    common::assert_same_as_plain(&world, entity, &cloth, &plain, &[ball, frame]);
}
