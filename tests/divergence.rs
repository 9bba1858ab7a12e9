//! A run that diverges stops with an error naming the step, the node and the effect, records it
//! in `metrics.json` without any NaN, and the command exits non-zero.

use std::process::Command;

mod common;

/// The KES tensile law is far too stiff to apply explicitly at the seed's explicit 0.2 ms step
/// for thin wool (ω·dt ≫ 2): the run must be stopped, and the tensile effect blamed.
#[test]
fn an_explicitly_unstable_stretch_law_is_stopped_and_named() {
    let dir = std::env::temp_dir().join("kes-cloth-divergence");
    let explicit = common::explicit_drape("wool");
    let out = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .args([
            "run",
            common::crate_path("scenes/drape_wool.ron").to_str().unwrap(),
            "--quiet",
        ])
        .args(explicit.iter().flat_map(|s| ["--set", s.as_str()]))
        .args([
            "--set",
            "effects.stretch=Kes",
            // Past the stability guard on purpose: this is what it would have refused.
            "--set",
            "integration.step_guard=false",
            "--out",
        ])
        .arg(&dir)
        .output()
        .unwrap();
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert!(stderr.contains("simulation diverged at step"), "{stderr}");
    assert!(stderr.contains("effect `stretch_kes`"), "{stderr}");
    assert!(stderr.contains("particle "), "{stderr}");
    let text = std::fs::read_to_string(dir.join("metrics.json")).unwrap();
    assert!(!text.contains("NaN") && !text.contains("inf"), "{text}");
    let json: serde_json::Value = serde_json::from_str(&text).unwrap();
    assert_eq!(json["failure"]["effect"], "stretch_kes");
    assert_eq!(json["settled"], false);
}

/// Regression: an implicit run that ran away was told its step was too large "for this effect's
/// stiffness when applied explicitly", which the implicit solve rules out. With rope joints the
/// message must point at the joints (Rapier solves them after our solve) and their remedies.
/// A 10 g ball tears the rope-joint hammock within a few milliseconds at one solver iteration.
#[test]
fn an_implicit_runaway_blames_the_rope_joints_not_an_explicit_step() {
    let sets = [
        "integration.integrator=Implicit".to_string(),
        "world.colliders.0.motion.mass_kg=0.01".to_string(),
    ];
    let scene =
        kes_cloth::scene::Scene::load(common::crate_path("scenes/hard/ball_impact.ron"), &sets).unwrap();
    let outcome = kes_cloth::run::simulate(&scene, &kes_cloth::run::RunOptions::default());
    let failure = outcome
        .metrics
        .failure
        .expect("the 10 g ball tears the rope joints");
    assert!(failure.message.contains("runaway"), "{}", failure.message);
    assert!(failure.message.contains("rope joints"), "{}", failure.message);
    assert!(
        failure.message.contains("solver_iterations"),
        "{}",
        failure.message
    );
    assert!(
        !failure.message.contains("applied explicitly"),
        "{}",
        failure.message
    );
}
