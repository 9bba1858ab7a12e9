//! The step at rest (`integration.rest_dt_s`): once a drape is quiet, through its confirmation
//! watch and a creep watch, the run steps at 1/30 s instead of 1/240 s. Rest asks of the step
//! only that it follows slow motion, which BDF2 does at 1/30 s; so the drape ends where the
//! same run at the constant step ends, in fewer steps, and still neither creeps nor jitters.
//!
//! Both fabrics on the seed's drapemeter at 1 cm (cheap; the shipped scenes run with their
//! rest step in `tests/shipped_scenes.rs`), with the 2 s confirmation and a 5 s creep watch.

use kes_cloth::repeat::simulate_all;
use kes_cloth::scene::Scene;

mod common;

/// The drape `name` at 1 cm with a 5 s creep watch, at the rest step `rest` (s; 0 for none).
fn scene(name: &str, rest: f64) -> Scene {
    let sets = [
        "cloth.spacing_m=0.01".to_string(),
        "integration.settle.creep_check_s=5".to_string(),
        "integration.max_time_s=26".to_string(),
        format!("integration.rest_dt_s={rest}"),
    ];
    Scene::load(common::crate_path(&format!("scenes/{name}.ron")), &sets).unwrap()
}

#[test]
fn a_drape_stepped_long_at_rest_ends_where_the_constant_step_ends() {
    let names = ["drape_cotton", "drape_wool"];
    let scenes: Vec<Scene> = names
        .iter()
        .flat_map(|n| [scene(n, 0.0), scene(n, 1.0 / 30.0)])
        .collect();
    let runs = simulate_all(&scenes, 2, |_, _| {});
    for (name, pair) in names.iter().zip(runs.chunks(2)) {
        let (constant, rested) = (&pair[0].metrics, &pair[1].metrics);
        for m in [constant, rested] {
            assert!(m.settled && m.failure.is_none(), "{name}: {m:?}");
        }
        println!(
            "{name}: DC {:.5} / {:.5}, nodes {:?} / {:?}, steps {} / {} ({} at rest), creep {:.4} / {:.4} mm",
            constant.drape_coefficient.unwrap(),
            rested.drape_coefficient.unwrap(),
            constant.nodes,
            rested.nodes,
            constant.steps,
            rested.steps,
            rested.rest_steps,
            constant.creep_max_node_m.unwrap() * 1e3,
            rested.creep_max_node_m.unwrap() * 1e3,
        );
        // The rest step starts with the quiet window, after the drape has formed: the same rest
        // time, and from there on one step in eight.
        assert_eq!(constant.settle_time_s, rested.settle_time_s, "{name}");
        assert_eq!(constant.rest_steps, 0);
        assert!(rested.rest_steps > 0, "{name}: no step at rest");
        assert!(
            (rested.steps as f64) < 0.5 * constant.steps as f64,
            "{name}: {} steps against {}",
            rested.steps,
            constant.steps
        );
        // The same drape: DC to 0.001 (a tenth of the placement target; measured within 1e-4),
        // the same node count.
        let (a, b) = (
            constant.drape_coefficient.unwrap(),
            rested.drape_coefficient.unwrap(),
        );
        assert!(
            (a - b).abs() <= 1e-3,
            "{name}: DC {a:.5} at 1/240 s, {b:.5} with the rest step"
        );
        assert_eq!(constant.nodes, rested.nodes, "{name}: nodes");
        // And still at rest: the shipped scenes' bounds (`tests/shipped_scenes.rs`), 0.5 mm of
        // creep over the 5 s watch and 1 mm/s over the last step.
        assert!(rested.creep_max_node_m.unwrap() <= 0.5e-3, "{name}: creep");
        assert!(rested.max_step_speed_m_per_s < 1e-3, "{name}: jitter");
    }
}

/// `kes-cloth check` says when a scene steps at rest: the shipped drapes do, and not once their
/// links are Rapier's rope joints, which hold a resting cloth only as well as their step lets
/// them.
#[test]
fn check_says_where_the_rest_step_applies() {
    let load = |sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
        kes_cloth::scene::describe(&scene)
    };
    assert!(load(&[]).contains("steps of 0.0333"), "{}", load(&[]));
    let joints = load(&["effects.stretch=Constraint"]);
    assert!(!joints.contains("at rest"), "{joints}");
}
