//! Every shipped scene loads, runs to rest with finite values, and drapes as a cloth should:
//! resting on its disk or table and hanging around it, links nearly inextensible, no node
//! inside a collider, outputs written.

use kes_cloth::run::{RunOptions, simulate, write_outputs};
use kes_cloth::scene::{Scene, describe};

mod common;

const SCENES: [&str; 6] = [
    "drape_wool",
    "drape_cotton",
    "cusick_wool",
    "cusick_cotton",
    "tablecloth_wool",
    "tablecloth_cotton",
];

#[test]
fn every_shipped_scene_is_listed_and_loads() {
    let mut found: Vec<String> = std::fs::read_dir(common::crate_path("scenes"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .map(|p| p.file_stem().unwrap().to_string_lossy().into_owned())
        .collect();
    found.sort();
    let mut listed: Vec<String> = SCENES.iter().map(|s| s.to_string()).collect();
    listed.sort();
    assert_eq!(found, listed, "every file in scenes/ must be run by this test");
    for name in SCENES {
        let scene = Scene::load(common::crate_path(&format!("scenes/{name}.ron")), &[]).unwrap();
        assert_eq!(scene.spec.name, name);
        assert!(describe(&scene).contains("nodes"));
    }
}

/// `max_strain`: largest |link length/σ − 1| allowed at rest; 3 % is "nearly inextensible"
/// for stretch as a constraint (the table corners, where four flaps meet, come closest).
fn run_and_check(name: &str, max_strain: f64) {
    let scene = Scene::load(common::crate_path(&format!("scenes/{name}.ron")), &[]).unwrap();
    let outcome = simulate(&scene, &RunOptions::default());
    let m = &outcome.metrics;
    assert!(m.failure.is_none(), "{name}: {:?}", m.failure);
    assert!(m.settled, "{name}: did not settle in {} s", m.sim_time_s);
    assert!(
        outcome.positions.iter().all(|p| p.is_finite()),
        "{name}: non-finite node"
    );
    assert!(
        m.max_strain < max_strain,
        "{name}: max link strain {:.2} %",
        m.max_strain * 100.0
    );
    // Contact softness lets node centres (the cloth's mid-surface) sink about a millimetre
    // into the support; 2 mm is a fifth of the node spacing.
    assert!(
        m.max_penetration_m < 0.002,
        "{name}: node {:.2} mm inside a collider",
        m.max_penetration_m * 1e3
    );
    // Rests on its support: the centre node is at the top (y = 0) within 2 mm ...
    let centre = outcome
        .positions
        .iter()
        .min_by(|a, b| (a.x * a.x + a.z * a.z).total_cmp(&(b.x * b.x + b.z * b.z)))
        .unwrap();
    assert!(
        centre.y.abs() < 0.002,
        "{name}: centre node at y = {} m",
        centre.y
    );
    // ... and the overhang hangs down by at least 3 cm (overhangs are 6 to 18 cm).
    assert!(
        m.min_height_m < -0.03,
        "{name}: lowest node only at {} m",
        m.min_height_m
    );

    let dir = std::env::temp_dir().join(format!("kes-cloth-test-{name}"));
    write_outputs(&scene, &outcome, &dir).unwrap();
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("metrics.json")).unwrap()).unwrap();
    for key in [
        "scene",
        "fabric",
        "particles",
        "steps",
        "sim_time_s",
        "wall_time_s",
        "settled",
        "settle_time_s",
        "max_strain",
        "min_height_m",
        "drape_coefficient",
        "nodes",
        "effects",
    ] {
        assert!(json.get(key).is_some(), "{name}: metrics.json lacks `{key}`");
    }
    assert_eq!(json["effects"]["bending"]["calls"], json["steps"]);
    let png = image::open(dir.join("top.png")).unwrap();
    assert_eq!(png.width(), scene.spec.output.image_size_px);
    let obj = std::fs::read_to_string(dir.join("final.obj")).unwrap();
    assert_eq!(obj.lines().filter(|l| l.starts_with("v ")).count(), m.particles);
}

#[test]
fn drape_wool_settles_on_the_disk() {
    run_and_check("drape_wool", 0.03);
}

#[test]
fn drape_cotton_settles_on_the_disk() {
    run_and_check("drape_cotton", 0.03);
}

#[test]
fn cusick_wool_settles_on_the_disk() {
    run_and_check("cusick_wool", 0.03);
}

#[test]
fn cusick_cotton_settles_on_the_disk() {
    run_and_check("cusick_cotton", 0.03);
}

#[test]
fn tablecloth_wool_settles_on_the_table() {
    run_and_check("tablecloth_wool", 0.03);
}

#[test]
fn tablecloth_cotton_settles_on_the_table() {
    run_and_check("tablecloth_cotton", 0.03);
}
