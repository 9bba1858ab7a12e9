//! A single run's numerical error, estimated from a companion run on a coarser lattice
//! (`kes-cloth run`'s default).

use std::process::Command;

use kes_cloth::run::{RunOptions, estimate_error, simulate, simulate_with_error_estimate};
use kes_cloth::scene::Scene;

mod common;

/// The cantilever at 2.5 mm, whose exact chord is known: the companion at 5 mm (twice the
/// spacing, the clamp's edge staying on a row of nodes) gives an estimated error that covers the
/// true one, and is not uselessly wide: the chord converges at second order, so the first-order
/// estimate |f(σ) − f(2σ)| is about three times the true error; more than four would mean the
/// estimate measures something other than the spacing.
#[test]
fn the_estimate_covers_the_cantilevers_true_error() {
    let scene = Scene::load(
        common::crate_path("scenes/bending_length/cantilever_wool.ron"),
        &["cloth.spacing_m=0.0025".to_string()],
    )
    .unwrap();
    let options = RunOptions::default();
    let mut outcome = simulate(&scene, &options);
    estimate_error(&scene, &mut outcome, &options);
    let m = &outcome.metrics;
    let estimate = m.numerical_error.as_ref().expect("an estimate");
    assert_eq!(estimate.companion_spacing_m, 0.005);
    let chord = estimate.cantilever_chord_deg.expect("a chord estimate");
    let true_error = (m.cantilever_chord_deg.unwrap() - m.cantilever_exact_deg.unwrap()).abs();
    assert!(
        chord.error >= true_error && chord.error <= 4.0 * true_error,
        "estimated {:.3}°, true {true_error:.3}°",
        chord.error
    );
}

/// The companion run alongside the run, on a second thread (what `kes-cloth run` does), gives
/// exactly the outcome of the run followed by its companion: the same metrics to the bit, the
/// estimate among them, wall-clock times aside. (Thin wool's cantilever at 5 mm, companion at
/// 1 cm.)
#[test]
fn the_companion_run_alongside_gives_the_estimate_of_the_companion_run_after() {
    let scene = Scene::load(
        common::crate_path("scenes/bending_length/cantilever_wool.ron"),
        &["cloth.spacing_m=0.005".to_string()],
    )
    .unwrap();
    let options = RunOptions::default();
    let mut after = simulate(&scene, &options);
    estimate_error(&scene, &mut after, &options);
    let alongside = simulate_with_error_estimate(&scene, &options);
    assert!(alongside.metrics.numerical_error.is_some(), "no estimate");
    assert_eq!(
        common::without_clock_times(&after.metrics),
        common::without_clock_times(&alongside.metrics)
    );
}

/// `kes-cloth run` on a drape prints DC as value ± error and records the companion (1.5 times
/// the spacing) in `metrics.json`; with `--no-error-estimate` it says the error is not estimated
/// instead of printing a bare number. Thick cotton with the KES law, implicit at 1/240 s, 1.5 cm
/// (each run about a second).
#[test]
fn run_prints_dc_with_its_error_or_says_it_is_not_estimated() {
    let out = std::env::temp_dir().join("kes-cloth-error-estimate");
    let run = |extra: &[&str]| {
        let _ = std::fs::remove_dir_all(&out);
        let o = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
            .args(["run", "scenes/drape_cotton.ron"])
            .args(["--set", "cloth.spacing_m=0.015"])
            .args(["--set", "integration.integrator=Implicit"])
            .args(["--set", "integration.dt_s=0.0041666667"])
            .args(["--set", "effects.stretch=Kes"])
            .arg("--out")
            .arg(&out)
            .args(extra)
            .current_dir(common::crate_path(""))
            .output()
            .unwrap();
        assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
        let metrics: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(out.join("metrics.json")).unwrap()).unwrap();
        (String::from_utf8_lossy(&o.stdout).to_string(), metrics)
    };

    let (stdout, metrics) = run(&[]);
    let e = &metrics["numerical_error"];
    let companion = e["companion_spacing_m"].as_f64().unwrap();
    assert!((companion - 0.0225).abs() < 1e-12, "{e}");
    let dc = metrics["drape_coefficient"].as_f64().unwrap();
    let other = e["drape_coefficient"]["companion"].as_f64().unwrap();
    let error = e["drape_coefficient"]["error"].as_f64().unwrap();
    // First order at r = 1.5: twice the difference.
    assert!((error - 2.0 * (dc - other).abs()).abs() < 1e-12, "{e}");
    let line = format!("drape coefficient {dc:.3} ± {error:.3}");
    assert!(stdout.contains(&line), "no '{line}' in:\n{stdout}");

    let (stdout, metrics) = run(&["--no-error-estimate"]);
    assert!(metrics["numerical_error"].is_null());
    assert!(
        stdout.contains("(numerical error not estimated)"),
        "a bare DC:\n{stdout}"
    );
}

/// The companion keeps every straight support edge where it lies against the node rows: the
/// cloth can leave a table's edge or a clamp only at a row of nodes, so a companion whose rows
/// fall otherwise against the edge would measure where the lattice meets it, not the spacing.
/// The tablecloth's table edge (10 cm from the cloth's centre) lies on a row at the shipped
/// 3.33 mm and at 5 mm (ratio 1.5), at 5 mm and 1 cm but not at 7.5 mm (ratio 2), between rows
/// at 3.75 mm and at 5.625 mm (ratio 1.5); the cantilever's 1 cm clamp
/// on a row at 1.25 mm and 2.5 mm, not at 1.875 mm (ratio 2); a circle on a disk has no straight
/// edge (1.5).
#[test]
fn the_companion_keeps_a_table_edge_or_a_clamp_on_a_node_row() {
    let ratio = |scene: &str, sets: &[&str]| {
        let sets: Vec<String> = sets.iter().map(|s| s.to_string()).collect();
        let scene = Scene::load(common::crate_path(scene), &sets).unwrap();
        kes_cloth::run::companion_ratio(&scene)
    };
    assert_eq!(ratio("scenes/tablecloth_cotton.ron", &[]), 1.5);
    assert_eq!(
        ratio("scenes/tablecloth_cotton.ron", &["cloth.spacing_m=0.005"]),
        2.0
    );
    assert_eq!(
        ratio("scenes/tablecloth_wool.ron", &["cloth.spacing_m=0.0025"]),
        2.0
    );
    assert_eq!(
        ratio("scenes/tablecloth_cotton.ron", &["cloth.spacing_m=0.00375"]),
        1.5
    );
    assert_eq!(ratio("scenes/bending_length/cantilever_wool.ron", &[]), 2.0);
    assert_eq!(ratio("scenes/drape_wool.ron", &[]), 1.5);
    // A table moved by a third of the spacing: its edges lie between rows at 5 mm and at 7.5 mm.
    let moved = "world.colliders.0.centre_m=(0.0016667, -0.02, 0.0016667)";
    assert_eq!(
        ratio("scenes/tablecloth_cotton.ron", &[moved, "cloth.spacing_m=0.005"]),
        1.5
    );
}
