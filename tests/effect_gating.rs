//! A scene runs only the effects it declares: an effect left out never runs and costs nothing;
//! declared, it runs every step.

use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;

mod common;

/// A short, coarse run of the wool drape with the given overrides.
fn effects_of(
    overrides: &[&str],
) -> (
    u64,
    std::collections::BTreeMap<String, kes_cloth::output::EffectCost>,
) {
    let mut sets: Vec<String> = common::explicit_drape("wool");
    sets.extend::<[String; 2]>([
        "cloth.spacing_m=0.02".into(),
        "integration.max_time_s=0.05".into(),
    ]);
    sets.extend(overrides.iter().map(|s| s.to_string()));
    let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
    let m = simulate(&scene, &RunOptions::default()).metrics;
    (m.steps, m.effects)
}

#[test]
fn undeclared_bending_and_trellising_never_run() {
    let (steps, effects) = effects_of(&["effects.bending=false", "effects.trellising=false"]);
    assert!(steps > 0);
    for name in ["bending", "trellising", "stretch_seed", "stretch_kes", "air_drag"] {
        assert_eq!(effects[name].calls, 0, "{name} ran");
        assert_eq!(effects[name].seconds, 0.0, "{name} cost time");
    }
    assert_eq!(effects["rapier_step"].calls, steps);
}

#[test]
fn declared_effects_run_every_step() {
    let (steps, effects) = effects_of(&["effects.air_drag={\"coefficient_n_s_per_m3\":0.1}"]);
    for name in [
        "bending",
        "trellising",
        "damping",
        "compression",
        "air_drag",
        "rapier_step",
    ] {
        assert_eq!(effects[name].calls, steps, "{name}");
    }
    assert_eq!(effects["stretch_kes"].calls, 0);
    let (steps, effects) = effects_of(&["effects.stretch=Seed", "integration.step_guard=false"]);
    assert_eq!(effects["stretch_seed"].calls, steps);
    assert_eq!(
        effects["compression"].calls, 0,
        "compression belongs to the constraint stretch"
    );
}
