//! Rigid bodies dropped onto an embedded cloth at the host's step: a cloth lying on a floor,
//! built with the defaults into a world stepping at 1/60 s or 1/240 s, catches a dozen boxes and
//! balls from 2 g to ten times its own mass, thrown down at 5 and 15 m/s, and everything comes
//! to rest: no failure, no node or body below the floor.

use glam::DVec3;
use kes_cloth::batch::parallel_map;
use kes_cloth::embed::{ClothBuilder, ClothOutline, prepare_world};
use kes_cloth::schedule::Physics;
use rapier3d::prelude::*;

mod common;

/// Side of the square cloth (m) and its lattice spacing (m).
const SIDE: f64 = 0.4;
const SPACING: f64 = 0.01;

/// One dropped body: a box (half extents `size`, 0.6 `size`, `size`) or a ball (radius `size`),
/// with its mass (kg), where it starts and how fast it is thrown down (m/s).
struct Drop {
    ball: bool,
    size: f32,
    mass: f32,
    start: Vector,
    speed: f32,
}

/// Twelve bodies on a 4 × 3 grid 9 cm apart (so that they land on the cloth, not on each
/// other), boxes and balls in turn, sizes 8–20 mm, masses spaced evenly on a log scale from 2 g
/// to `heaviest` (kg); every other one thrown at 15 m/s, the rest at 5 m/s.
fn drops(heaviest: f32) -> Vec<Drop> {
    let n = 12;
    (0..n)
        .map(|k| {
            let f = k as f32 / (n - 1) as f32;
            Drop {
                ball: k % 2 == 1,
                size: 0.008 + 0.012 * ((k * 5) % n) as f32 / (n - 1) as f32,
                mass: 0.002f32.powf(1.0 - f) * heaviest.powf(f),
                start: Vector::new(
                    -0.135 + 0.09 * (k % 4) as f32,
                    0.1 + 0.03 * (k % 3) as f32,
                    -0.09 + 0.09 * (k / 4) as f32,
                ),
                speed: if k % 2 == 0 { 15.0 } else { 5.0 },
            }
        })
        .collect()
}

/// Adds `drop` to `world` as a dynamic body with continuous collision detection. Balls get an
/// angular damping of 2 /s: Rapier has no rolling resistance, and under a body the cloth is
/// backed by the floor, so nothing else would stop a ball that a neighbour set rolling.
fn add_body(world: &mut PhysicsWorld, drop: &Drop) -> RigidBodyHandle {
    let body = RigidBodyBuilder::dynamic()
        .translation(drop.start)
        .linvel(Vector::new(0.0, -drop.speed, 0.0))
        .ccd_enabled(true)
        .angular_damping(if drop.ball { 2.0 } else { 0.0 })
        .build();
    let handle = world.insert_body(body);
    let s = drop.size;
    let (shape, volume) = if drop.ball {
        (
            ColliderBuilder::ball(s),
            4.0 / 3.0 * std::f32::consts::PI * s * s * s,
        )
    } else {
        (ColliderBuilder::cuboid(s, 0.6 * s, s), 8.0 * 0.6 * s * s * s)
    };
    world.insert_collider(
        shape.density(drop.mass / volume).friction(0.5).build(),
        Some(handle),
    );
    handle
}

/// What one run found.
struct Outcome {
    /// Time (s) after the throw from which nothing moved faster than 1 mm/s.
    rest_after: Option<f64>,
    /// Lowest node centre and lowest point of any body (m; the floor's top is at 0).
    lowest_node: f64,
    lowest_body: f64,
}

/// Settles `fabric` on the floor for 0.5 s at `hz` (on its lower face if `lower_face`, else on
/// its nodes' balls), throws the twelve bodies and runs 3.5 s.
/// A world stepping at 1/`hz` s with a 2 m × 2 m floor, its top at y = 0, friction 0.5.
fn floor_world(hz: f64) -> PhysicsWorld {
    let mut world = PhysicsWorld::default();
    world.integration_parameters.dt = (1.0 / hz) as f32;
    prepare_world(&mut world.integration_parameters);
    world.insert_collider(
        ColliderBuilder::cuboid(1.0, 0.01, 1.0)
            .translation(Vector::new(0.0, -0.01, 0.0))
            .friction(0.5)
            .build(),
        None,
    );
    world
}

/// The square cloth of `fabric`, 6 mm above the floor, with the builder's defaults.
fn floor_cloth(fabric: &str, lower_face: bool) -> ClothBuilder {
    ClothBuilder::new(common::shipped_fabric(fabric))
        .outline(ClothOutline::Rectangle {
            warp: SIDE,
            weft: SIDE,
        })
        .spacing(SPACING)
        .pose(DVec3::new(0.0, 0.006, 0.0), 0.0)
        .rest_on_lower_face(lower_face)
}

fn run(fabric: &str, hz: f64, lower_face: bool) -> Outcome {
    let mut world = floor_world(hz);
    let mut cloth = floor_cloth(fabric, lower_face).build(&mut world).expect("builds");
    for _ in 0..(0.5 * hz) as usize {
        cloth.step(&mut world).expect("settles");
    }
    let cloth_mass: f64 = cloth.parts().bodies.masses.iter().sum();
    let thrown = drops(10.0 * cloth_mass as f32);
    let handles: Vec<RigidBodyHandle> = thrown.iter().map(|d| add_body(&mut world, d)).collect();
    let mut outcome = Outcome {
        rest_after: None,
        lowest_node: f64::INFINITY,
        lowest_body: f64::INFINITY,
    };
    let steps = (3.5 * hz) as usize;
    for k in 0..steps {
        cloth
            .step(&mut world)
            .unwrap_or_else(|e| panic!("{fabric} at 1/{hz} s: {e}"));
        let t = (k + 1) as f64 / hz;
        let m = cloth.motion();
        let mut fastest = m.max_speed.max(m.max_step_speed);
        for (h, d) in handles.iter().zip(&thrown) {
            let b = &world.bodies[*h];
            assert!(
                b.translation().is_finite(),
                "{fabric} at 1/{hz} s: a body left the world"
            );
            // Speed of the body's fastest point: centre plus spin times its reach.
            let reach = if d.ball { d.size } else { 1.5 * d.size };
            fastest = fastest.max((b.linvel().length() + b.angvel().length() * reach) as f64);
            let aabb = b
                .colliders()
                .iter()
                .map(|c| world.colliders[*c].compute_aabb().mins.y)
                .fold(f32::INFINITY, f32::min);
            outcome.lowest_body = outcome.lowest_body.min(aabb as f64);
        }
        outcome.lowest_node = outcome.lowest_node.min(cloth.lowest_point());
        if fastest > 1e-3 {
            outcome.rest_after = None;
        } else if outcome.rest_after.is_none() {
            outcome.rest_after = Some(t);
        }
    }
    outcome
}

/// Every shipped fabric at 1/60 s and 1/240 s catches the twelve bodies: each step succeeds,
/// no node centre goes below the floor's top and no body's lowest point more than 1 mm below it
/// (Rapier's contacts rest at up to its allowed linear error, 1 mm by default, into a surface),
/// and everything is at rest (no node, no point of a body faster than 1 mm/s) within 3 s of the
/// throw, which is within 3 s of the last impact (every body reaches the cloth within 0.05 s).
/// The same holds with the cloth resting on its lower face (`rest_on_lower_face`, its node
/// centres half its thickness above the floor instead of a node radius). Measured (every shipped
/// fabric alike: where the floor backs the cloth, a body meets it as it would the floor,
/// `docs/rapier.md`): at rest 0.17 s (1/60 s) and 0.53 s (1/240 s) after the throw, 0.15 s and
/// 0.49 s on the lower face; at 1/240 s two boxes tumble off the cloth's edge onto the floor
/// (lowest point -0.12 mm, resting on the floor).
#[test]
fn bodies_dropped_onto_a_cloth_on_a_floor_are_caught_and_come_to_rest_at_the_hosts_step() {
    let cases: Vec<(String, f64, bool)> = common::shipped_fabric_paths()
        .iter()
        .flat_map(|path| {
            let stem = path.file_stem().and_then(|s| s.to_str()).expect("a file stem");
            [(60.0, false), (240.0, false), (60.0, true), (240.0, true)]
                .map(|(hz, lower_face)| (stem.to_string(), hz, lower_face))
        })
        .collect();
    // Each case is its own world; two run at a time.
    let outcomes = parallel_map(cases.len(), 2, |i| {
        let (stem, hz, lower_face) = &cases[i];
        run(stem, *hz, *lower_face)
    });
    let mut report = Vec::new();
    for ((stem, hz, lower_face), o) in cases.iter().zip(outcomes) {
        let (hz, lower_face) = (*hz, *lower_face);
        let rests_on = if lower_face { "lower face" } else { "nodes' balls" };
        report.push(format!(
            "{stem} 1/{hz} s on its {rests_on}: at rest from {:?} s after the throw, lowest node {:.2} mm, lowest body point {:.2} mm",
            o.rest_after,
            o.lowest_node * 1e3,
            o.lowest_body * 1e3
        ));
        assert!(
            o.lowest_node >= 0.0,
            "{stem} at 1/{hz} s: a node below the floor: {}",
            report.last().unwrap()
        );
        assert!(
            o.lowest_body >= -1e-3,
            "{stem} at 1/{hz} s: a body below the floor: {}",
            report.last().unwrap()
        );
        assert!(
            o.rest_after.is_some_and(|t| t <= 3.0),
            "{stem} at 1/{hz} s not at rest: {}",
            report.last().unwrap()
        );
    }
    println!("{}", report.join("\n"));
}

/// The bevy_ecs way in steps a cloth under dropped bodies exactly as `KesCloth::step` does: the
/// same world, the same cloth (thin wool, settled 0.25 s on the floor at 1/60 s) and the same
/// six bodies thrown down at 5 and 15 m/s, stepped 0.5 s either way, end with every node and
/// every body at the same position to the bit. Both ways step Rapier with `SheetContacts`, make
/// supported nodes immovable to the bodies and hand the bodies' pushes back to the cloth; a
/// schedule that left out any of them would drift from the plain loop within a step of the
/// first impact.
#[test]
fn in_a_bevy_schedule_dropped_bodies_and_the_cloth_move_exactly_as_with_kes_cloth_step() {
    let hz = 60.0;
    let (settle, after) = ((0.25 * hz) as usize, (0.5 * hz) as usize);

    let mut plain = floor_world(hz);
    let mut cloth = floor_cloth("thin_wool", false).build(&mut plain).expect("builds");
    for _ in 0..settle {
        cloth.step(&mut plain).expect("settles");
    }
    let cloth_mass: f64 = cloth.parts().bodies.masses.iter().sum();
    let thrown: Vec<Drop> = drops(10.0 * cloth_mass as f32).into_iter().take(6).collect();
    let handles: Vec<RigidBodyHandle> = thrown.iter().map(|d| add_body(&mut plain, d)).collect();
    for _ in 0..after {
        cloth.step(&mut plain).expect("catches the bodies");
    }

    let mut physics = floor_world(hz);
    let parts = floor_cloth("thin_wool", false)
        .build_parts(&mut physics)
        .expect("builds");
    let (mut world, mut schedule, entity) = common::host_schedule(physics, parts);
    for _ in 0..settle {
        schedule.run(&mut world);
    }
    let ecs_handles: Vec<RigidBodyHandle> = {
        let physics = &mut world.resource_mut::<Physics>().0;
        thrown.iter().map(|d| add_body(physics, d)).collect()
    };
    assert_eq!(handles, ecs_handles, "the bodies' handles");
    for _ in 0..after {
        schedule.run(&mut world);
    }
    common::assert_same_as_plain(&world, entity, &cloth, &plain, &handles);
    // And the bodies were caught: none below the floor's top by more than Rapier's allowed error.
    let lowest = handles
        .iter()
        .flat_map(|h| plain.bodies[*h].colliders().to_vec())
        .map(|c| plain.colliders[c].compute_aabb().mins.y)
        .fold(f32::INFINITY, f32::min);
    assert!(lowest >= -1e-3, "a body sank to {lowest} m");
}
