//! Hard cases stay numerically stable (`scenes/hard/`): ten times gravity, a 1 m drop onto the
//! disk rim, the stiffest fabric at the coarsest spacing and the guard's largest step, the
//! lightest fabric at the finest spacing, and the stiffest shear released from 60° (and −60°). Each run must end without a failure, with every value
//! finite, no node centre more than 3 mm inside a collider at the end of any step (the node
//! balls are 5–10 mm in radius; measured worst 0.6–2.9 mm), link strain within a stated bound at every step, and the
//! cloth at rest (settle window met, kinetic energy decayed below 1e-5 J).

use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;

mod common;

/// (scene, bound on the peak link strain over the run, with the measured value).
const CASES: [(&str, f64); 5] = [
    // Impact at 4.4 m/s: measured peak 18.9 %.
    ("scenes/hard/rim_drop.ron", 0.25),
    // Ten times the load on every joint: measured peak 13.3 %, 5.6 % at rest.
    ("scenes/hard/ten_g_drape.ron", 0.20),
    // Measured peak 3.8 %.
    ("scenes/hard/stiff_coarse.ron", 0.10),
    // Measured peak 5.7 %.
    ("scenes/hard/thin_fine.ron", 0.10),
    // Released from 60° of shear (KES stretch, implicit): measured peak 6.3 %.
    ("scenes/hard/sheared_release.ron", 0.10),
];

#[test]
fn every_hard_scene_is_run_by_this_test() {
    let mut found: Vec<String> = std::fs::read_dir(common::crate_path("scenes/hard"))
        .unwrap()
        .map(|e| format!("scenes/hard/{}", e.unwrap().file_name().to_string_lossy()))
        .collect();
    found.sort();
    let mut listed: Vec<String> = CASES.iter().map(|c| c.0.to_string()).collect();
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
    for (path, sets, strain_bound) in runs {
        let scene = Scene::load(common::crate_path(path), &sets).unwrap();
        let m = simulate(&scene, &RunOptions::default()).metrics;
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
        assert!(
            m.max_penetration_m < 0.003,
            "{name}: {:.2} mm inside a collider",
            m.max_penetration_m * 1e3
        );
        assert!(
            m.peak_strain < strain_bound,
            "{name}: peak strain {:.1} % (bound {:.0} %)",
            m.peak_strain * 100.0,
            strain_bound * 100.0
        );
        assert!(m.settled, "{name}: not at rest after {} s", m.sim_time_s);
        assert!(
            m.kinetic_energy_j < 1e-5,
            "{name}: kinetic energy {:e} J",
            m.kinetic_energy_j
        );
    }
}
