//! Hard cases stay numerically stable (`scenes/hard/`): ten times gravity, a 1 m drop onto the
//! disk rim, the stiffest fabric at the coarsest spacing and the guard's largest step, the
//! lightest fabric at the finest spacing, the stiffest shear released from 60° (and −60°), the
//! stiffest fabric folded flat onto itself (θ → 12° at the fold, self-collision), and a 2 g and
//! a 10 g ball thrown at 10 m/s into a hanging cloth. Each run must end without a failure, with every value
//! finite, no node centre more than 3 mm inside a collider at the end of any step (the node
//! balls are 1–10 mm in radius; measured worst 0–2.4 mm), link strain within a stated bound at every step, and the
//! cloth at rest (settle window met, no node moving faster than 1 mm/s over the last step,
//! kinetic energy decayed below 1e-5 J).

use bevy_ecs::prelude::*;
use kes_cloth::forces::ClothGeometry;
use kes_cloth::material::STANDARD_GRAVITY;
use kes_cloth::repeat::simulate_all;
use kes_cloth::run::{AT_REST_STEP_SPEED_M_PER_S, RunOptions, simulate};
use kes_cloth::scene::Scene;
use kes_cloth::scene::spawn::spawn;
use kes_cloth::schedule::{ClothEffects, ClothState, Failure, build_step_schedule};

mod common;

/// (scene, bound on the peak link strain over the run, with the measured value).
const CASES: [(&str, f64); 8] = [
    // Impact at 4.4 m/s: measured peak 20.2 %.
    ("scenes/hard/rim_drop.ron", 0.25),
    // Ten times the load on every joint: measured peak 3.2 %, 1.4 % at rest.
    ("scenes/hard/ten_g_drape.ron", 0.20),
    // Measured peak 1.4 %.
    ("scenes/hard/stiff_coarse.ron", 0.10),
    // Measured peak 1.0 %.
    ("scenes/hard/thin_fine.ron", 0.10),
    // Released from 60° of shear (KES stretch, implicit): measured peak 6.4 %.
    ("scenes/hard/sheared_release.ron", 0.10),
    // Folded flat onto itself, springing open on the floor: measured peak 1.8 %.
    ("scenes/hard/folded.ron", 0.10),
    // A 2 g ball at 10 m/s into a hanging cloth: measured peak 18.2 % at the impact, 0.24 % at
    // rest.
    ("scenes/hard/ball_impact.ron", 0.45),
    // A 10 g ball into the same cloth, KES stretch implicit: measured peak 10.7 %, 1.4 mm deep.
    ("scenes/hard/heavy_ball_impact.ron", 0.15),
];

#[test]
fn every_hard_scene_is_run_by_this_test() {
    let mut found: Vec<String> = std::fs::read_dir(common::crate_path("scenes/hard"))
        .unwrap()
        .map(|e| format!("scenes/hard/{}", e.unwrap().file_name().to_string_lossy()))
        .collect();
    found.sort();
    let mut listed: Vec<String> = CASES.iter().map(|c| c.0.to_string()).collect();
    listed.push(HANGING.to_string());
    listed.sort();
    assert_eq!(found, listed);
}

#[test]
fn hard_scenes_stay_finite_out_of_the_colliders_and_come_to_rest() {
    let runs = CASES.iter().map(|&(path, bound)| (path, vec![], bound)).chain([(
        "scenes/hard/sheared_release.ron",
        vec!["cloth.initial_shear_deg=-60".to_string()],
        0.10,
    )]);
    let (scenes, bounds): (Vec<Scene>, Vec<f64>) = runs
        .map(|(path, sets, bound)| (Scene::load(common::crate_path(path), &sets).unwrap(), bound))
        .unzip();
    // Two runs at a time, one per core.
    let outcomes = simulate_all(&scenes, 2, |_, _| {});
    for ((scene, outcome), strain_bound) in scenes.iter().zip(outcomes).zip(bounds) {
        let m = outcome.metrics;
        let name = &scene.spec.name;
        assert!(m.failure.is_none(), "{name}: {:?}", m.failure);
        for (what, v) in [
            ("max strain", m.max_strain),
            ("peak strain", m.peak_strain),
            ("kinetic energy", m.kinetic_energy_j),
            ("penetration", m.max_penetration_m),
            ("lowest node", m.min_height_m),
        ] {
            assert!(v.is_finite(), "{name}: {what} is {v}");
        }
        // At the end of every step, not only the last (measured worst: 2.4 mm, the
        // 2 g ball's impact and the stiff coarse drape; 1.4 mm for the 10 g ball; node balls are
        // 5–10 mm in radius).
        assert!(
            m.peak_penetration_m < 0.003,
            "{name}: {:.2} mm inside a collider at the worst step",
            m.peak_penetration_m * 1e3
        );
        assert!(
            m.peak_strain < strain_bound,
            "{name}: peak strain {:.1} % (bound {:.0} %)",
            m.peak_strain * 100.0,
            strain_bound * 100.0
        );
        assert!(m.settled, "{name}: not at rest after {} s", m.sim_time_s);
        // At rest means still, not flickering in place: the bound a settled shipped scene keeps
        // (`tests/shipped_scenes.rs`). Without their 2 s watch the folded cloth and the thin
        // fine drape stopped with a node at 27 and 6 mm/s.
        assert!(
            m.max_step_speed_m_per_s < AT_REST_STEP_SPEED_M_PER_S,
            "{name}: a node moved {:.2} mm/s over the last step",
            m.max_step_speed_m_per_s * 1e3
        );
        assert!(
            m.kinetic_energy_j < 1e-5,
            "{name}: kinetic energy {:e} J",
            m.kinetic_energy_j
        );
    }
}

/// Regression (`top.png` drew the thrown ball where it started): the outcome reports each
/// collider where it ended. The ball thrown down at the hanging cloth is deflected off it and
/// falls (the scene has no floor; measured: 4.9 m below its start after 1.5 s), so it must be
/// reported well below where it started, not at its start.
#[test]
fn thrown_ball_is_reported_where_it_ended() {
    let scene = Scene::load(common::crate_path("scenes/hard/ball_impact.ron"), &[]).unwrap();
    let outcome = simulate(&scene, &RunOptions::default());
    let start: Vec<f64> = scene.spec.world.colliders.iter().map(|c| c.centre_m[1]).collect();
    assert_eq!(outcome.collider_centres.len(), start.len());
    let ball = scene
        .spec
        .world
        .colliders
        .iter()
        .position(|c| c.name == "ball")
        .unwrap();
    let dropped = start[ball] - outcome.collider_centres[ball].y;
    assert!(dropped > 1.0, "the ball is reported {dropped} m below its start");
}

const HANGING: &str = "scenes/hard/hanging_damped.ron";

/// Total energy (J): kinetic, gravitational (y up) and every elastic effect's.
fn total_energy(world: &World, cloth: Entity, node_mass: f64) -> f64 {
    let state = world.get::<ClothState>(cloth).unwrap();
    let mut geometry = ClothGeometry::new(state.topology.clone());
    geometry.update(&state.positions);
    let motion: f64 = state
        .positions
        .iter()
        .zip(&state.velocities)
        .map(|(x, v)| node_mass * (0.5 * v.length_squared() + STANDARD_GRAVITY * x.y))
        .sum();
    let effects = &world.get::<ClothEffects>(cloth).unwrap().0;
    let elastic: f64 = ["bending", "trellising", "compression"]
        .iter()
        .filter_map(|name| effects.get(name))
        .map(|e| e.energy(&geometry))
        .sum();
    motion + elastic
}

/// A damped cloth hanging from two pins loses energy and never gains it: sampled every 0.25 s
/// over the first 10 s (the scene runs 60 s by hand), the total energy never rises by more than
/// 1e-7 J (0.005 % of the 2.1 mJ the swing releases, measured; late samples differ by ~1e-10 J;
/// Rapier's joint drift correction may inject a little), and ends with kinetic energy < 1e-6 J.
#[test]
fn a_damped_hanging_cloth_never_gains_energy() {
    let scene = Scene::load(common::crate_path(HANGING), &[]).unwrap();
    let node_mass = scene.fabric.areal_density * scene.spec.cloth.spacing_m.powi(2);
    let (mut world, cloth) = spawn(&scene);
    let mut schedule = build_step_schedule();
    let steps_per_sample = (0.25 / scene.spec.integration.dt_s).round() as usize;
    let mut energies = vec![total_energy(&world, cloth, node_mass)];
    for _ in 0..40 {
        for _ in 0..steps_per_sample {
            schedule.run(&mut world);
        }
        assert!(
            world.resource::<Failure>().0.is_none(),
            "{:?}",
            world.resource::<Failure>().0
        );
        energies.push(total_energy(&world, cloth, node_mass));
    }
    for (k, pair) in energies.windows(2).enumerate() {
        assert!(
            pair[1] <= pair[0] + 1e-7,
            "energy rose from {:e} J to {:e} J between {} s and {} s",
            pair[0],
            pair[1],
            0.25 * k as f64,
            0.25 * (k + 1) as f64
        );
    }
    let state = world.get::<ClothState>(cloth).unwrap();
    let kinetic: f64 = state
        .velocities
        .iter()
        .map(|v| 0.5 * node_mass * v.length_squared())
        .sum();
    assert!(
        kinetic < 1e-6,
        "still moving after 10 s: kinetic energy {kinetic:e} J"
    );
}

/// Regression (`kes-cloth check` left out a thrown ball's mass and velocity, and the contact
/// stiffness): the description names both.
#[test]
fn check_describes_the_thrown_ball_and_the_contact_stiffness() {
    let scene = Scene::load(common::crate_path("scenes/hard/heavy_ball_impact.ron"), &[]).unwrap();
    let text = kes_cloth::scene::describe(&scene);
    assert!(
        text.contains("dynamic, 0.01 kg thrown at (0, -10, 0) m/s"),
        "{text}"
    );
    assert!(
        text.contains("contact stiffness 960 Hz against fixed bodies, 960 Hz between moving ones"),
        "{text}"
    );
}
