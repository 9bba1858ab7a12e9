//! A scene measures what it declares (`measure:`), on the collider it names, and a strip can be
//! declared (`Rectangle(warp_m, weft_m)`).

use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;

mod common;

/// `scene` with `overrides`, run for one step (the cloth still flat where it was laid).
fn one_step(scene: &str, overrides: &[&str]) -> kes_cloth::run::RunOutcome {
    let mut sets: Vec<String> = overrides.iter().map(|s| s.to_string()).collect();
    let scene_file = Scene::load(common::crate_path(scene), &sets).unwrap();
    sets.push(format!(
        "integration.max_time_s={}",
        scene_file.spec.integration.dt_s
    ));
    let scene = Scene::load(common::crate_path(scene), &sets).unwrap();
    simulate(&scene, &RunOptions::default())
}

/// The drape scene declares its disk and reports a drape coefficient; the same scene declaring
/// `None` reports none, though its disk is still there.
#[test]
fn a_drape_is_measured_only_where_declared() {
    let declared = one_step("scenes/drape_cotton.ron", &[]);
    let dc = declared
        .metrics
        .drape_coefficient
        .expect("declared drape measured");
    // Flat, one step after being laid 1 cm above the disk: its projection is the whole sample.
    assert!((dc - 1.0).abs() < 1e-3, "flat cloth has DC {dc}");
    let none = one_step("scenes/drape_cotton.ron", &["measure=None"]);
    assert_eq!(none.metrics.drape_coefficient, None);
    assert_eq!(none.metrics.nodes, None);
    assert_eq!(none.metrics.hang_corners_m, None);
}

/// A flat 40 cm × 24 cm rectangle laid 1 cm above the table top: every corner and mid-side hangs
/// −10 mm (above the top), within the 0.5 mm random perturbation of the scene.
#[test]
fn a_rectangular_tablecloth_hangs_at_its_own_corners() {
    let out = one_step(
        "scenes/tablecloth_cotton.ron",
        &[
            "cloth.shape=Rectangle(warp_m: 0.40, weft_m: 0.24)",
            "cloth.spacing_m=0.01",
        ],
    );
    assert_eq!(
        out.metrics.particles,
        41 * 25,
        "a 0.40 m × 0.24 m lattice at 1 cm"
    );
    let corners = out.metrics.hang_corners_m.expect("declared tablecloth measured");
    let sides = out
        .metrics
        .hang_mid_sides_m
        .expect("declared tablecloth measured");
    for hang in [corners, sides] {
        assert!((hang + 0.01).abs() < 0.6e-3, "hang {hang} m, expected −0.010 m");
    }
    assert_eq!(out.metrics.drape_coefficient, None);
}

/// A strip declared in a scene is a `warp × weft` lattice whose nodes span its outline.
#[test]
fn a_strip_spans_its_declared_outline() {
    let out = one_step(
        "scenes/tablecloth_cotton.ron",
        &[
            "cloth.shape=Rectangle(warp_m: 0.2, weft_m: 0.025)",
            "cloth.spacing_m=0.005",
            // The guard's limit for thick cotton's compression spring at 5 mm is 35 µs.
            "integration.dt_s=0.00003",
            "measure=None",
            // Flat: a perturbed node's rope joints would draw its neighbours in by δ²/2σ.
            "cloth.perturbation_m=0",
        ],
    );
    assert_eq!(out.metrics.particles, 41 * 6);
    let span = |axis: fn(&glam::DVec3) -> f64| {
        let (lo, hi) = out
            .positions
            .iter()
            .map(axis)
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), v| {
                (lo.min(v), hi.max(v))
            });
        hi - lo
    };
    // One step of an unperturbed free fall cannot move a node sideways by a micrometre.
    assert!((span(|p| p.x) - 0.2).abs() < 1e-6, "warp span {}", span(|p| p.x));
    assert!(
        (span(|p| p.z) - 0.025).abs() < 1e-6,
        "weft span {}",
        span(|p| p.z)
    );
}
