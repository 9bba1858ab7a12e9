//! Bad scene files: each in `tests/bad_scenes/` is rejected with the message its `// expect:`
//! lines give (file, line/column or field, allowed range), without a panic, and the command
//! exits non-zero.

use std::process::Command;

use kes_cloth::scene::Scene;

mod common;

fn bad_scenes() -> Vec<(std::path::PathBuf, Vec<String>)> {
    let dir = common::crate_path("tests/bad_scenes");
    let mut out: Vec<_> = std::fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().path())
        .map(|p| {
            let expects = common::expect_lines(&p);
            (p, expects)
        })
        .collect();
    out.sort();
    out
}

#[test]
fn every_bad_scene_gives_its_expected_message() {
    let cases = bad_scenes();
    assert!(cases.len() >= 10);
    for (path, expects) in cases {
        assert!(!expects.is_empty(), "{}: no `// expect:` line", path.display());
        let message = common::rejection_message(&path, || Scene::load(&path, &[]));
        assert!(
            message.starts_with(&path.display().to_string()),
            "message lacks the file: {message}"
        );
        for e in &expects {
            assert!(
                message.contains(e.as_str()),
                "{}:\n  got      {message}\n  expected {e}",
                path.display()
            );
        }
    }
}

/// The command reports the same message on stderr and exits with a failure code, for `check`
/// and for `run`.
#[test]
fn the_command_exits_non_zero_on_bad_scenes() {
    for (path, expects) in bad_scenes() {
        for sub in ["check", "run"] {
            let mut cmd = Command::new(env!("CARGO_BIN_EXE_kes-cloth"));
            cmd.args([sub, path.to_str().unwrap()]);
            if sub == "run" {
                cmd.arg("--quiet")
                    .arg("--out")
                    .arg(std::env::temp_dir().join("kes-cloth-bad-scene"));
            }
            let out = cmd.output().unwrap();
            let stderr = String::from_utf8_lossy(&out.stderr);
            assert!(!out.status.success(), "{sub} {} succeeded", path.display());
            assert_eq!(
                out.status.code(),
                Some(1),
                "{sub} {}: not a clean error exit: {stderr}",
                path.display()
            );
            assert!(stderr.starts_with("error: "), "{stderr}");
            assert!(
                stderr.contains(expects[0].as_str()),
                "{sub} {}: {stderr}",
                path.display()
            );
        }
    }
}

#[test]
fn set_overrides_reach_nested_fields_and_reject_unknown_ones() {
    let path = common::crate_path("scenes/drape_wool.ron");
    let s = Scene::load(
        &path,
        &[
            "integration.dt_s=0.0005".into(),
            "seed=7".into(),
            "cloth.shape.diameter_m=0.2".into(),
            "effects.stretch=Kes".into(),
            // The KES law needs a far smaller explicit step; this test is about overrides.
            "integration.step_guard=false".into(),
        ],
    )
    .unwrap();
    assert_eq!(s.spec.integration.dt_s, 0.0005);
    assert_eq!(s.spec.seed, 7);
    assert_eq!(
        s.spec.cloth.shape,
        kes_cloth::scene::ClothShape::Circle { diameter_m: 0.2 }
    );
    assert_eq!(s.spec.effects.stretch, kes_cloth::scene::StretchModel::Kes);
    // Regression (`--set cloth.centre_m=(0.005,0.01,0.0)` was refused: tuples are how scene
    // files write vectors): RON tuples and structs are read like the file's, JSON arrays too.
    let s = Scene::load(
        &path,
        &[
            "cloth.centre_m=(0.005, 0.01, 0.0)".into(),
            "integration.settle=(max_speed_m_per_s: 0.002, hold_s: 1.0)".into(),
        ],
    )
    .unwrap();
    assert_eq!(s.spec.cloth.centre_m, [0.005, 0.01, 0.0]);
    assert_eq!(s.spec.integration.settle.hold_s, 1.0);
    assert_eq!(s.spec.integration.settle.max_speed_m_per_s, 0.002);
    let s = Scene::load(&path, &["cloth.centre_m=[0.0, 0.02, 0.0]".into()]).unwrap();
    assert_eq!(s.spec.cloth.centre_m, [0.0, 0.02, 0.0]);
    // Regression (a list element could not be reached, `world.colliders.0.friction`, and a RON
    // list of tuples, as a scene file writes pins, was refused as text).
    let s = Scene::load(
        &path,
        &[
            "world.colliders.0.friction=0.0".into(),
            "cloth.pins_m=[(0.0, 0.01, 0.0), (0.01, 0.01, 0.0),]".into(),
        ],
    )
    .unwrap();
    assert_eq!(s.spec.world.colliders[0].friction, 0.0);
    assert_eq!(s.spec.cloth.pins_m, vec![[0.0, 0.01, 0.0], [0.01, 0.01, 0.0]]);
    let e = Scene::load(&path, &["world.colliders.9.friction=0".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("no field `world.colliders.9`"), "{e}");
    // Regression (an enum variant with fields, written as the file writes it, was refused:
    // "unknown variant `Dynamic(mass_kg: ...)`").
    let ball = common::crate_path("scenes/hard/ball_impact.ron");
    let s = Scene::load(
        &ball,
        &["world.colliders.0.motion=Dynamic(mass_kg: 0.05, velocity_m_per_s: (0.0, -1.0, 0.0))".into()],
    )
    .unwrap();
    assert_eq!(
        s.spec.world.colliders[0].motion,
        kes_cloth::scene::ColliderMotion::Dynamic {
            mass_kg: 0.05,
            velocity_m_per_s: [0.0, -1.0, 0.0]
        }
    );
    let s = Scene::load(&path, &["cloth.shape=Square(side_m: 0.3)".into()]).unwrap();
    assert_eq!(
        s.spec.cloth.shape,
        kes_cloth::scene::ClothShape::Square { side_m: 0.3 }
    );
    let e = Scene::load(&ball, &["world.colliders.0.motion=Dynamic(mass: 0.05)".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("mass"), "{e}");
    // Text that happens to read as RON still reaches a text field as text: the fabric path
    // `(1, 2)`, valid RON for a list, is looked up as a file (and is missing), not refused.
    let e = Scene::load(&path, &["fabric.File=(1, 2)".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("(1, 2)") && !e.contains("does not accept"), "{e}");
    let e = Scene::load(&path, &["integration.dtt=1".into()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("--set integration.dtt=1: the scene has no field `integration.dtt`"),
        "{e}"
    );
    let e = Scene::load(&path, &["integration.dt_s=-1".into()])
        .unwrap_err()
        .to_string();
    assert!(e.contains("field `integration.dt_s` = -1"), "{e}");
    let e = Scene::load(&path, &["seed=abc".into()]).unwrap_err().to_string();
    assert!(e.contains("--set seed=abc"), "{e}");
}

/// A pin that misses the cloth is refused, naming the pin and the distance.
#[test]
fn a_pin_away_from_the_cloth_is_rejected() {
    let path = common::crate_path("scenes/hard/hanging_damped.ron");
    let e = Scene::load(&path, &["cloth.pins_m=[[0.5,0.5,0.0]]".into()])
        .err()
        .map(|e| e.to_string())
        .unwrap_or_default();
    assert!(
        e.contains("cloth.pins_m[0]") && e.contains("within one spacing"),
        "{e}"
    );
}

/// A field out of range is reported where the file writes it (line and column), but a value a
/// `--set` gave has no place in the file, and none is claimed.
#[test]
fn a_bad_value_is_placed_in_the_file_unless_set_on_the_command_line() {
    let path = common::crate_path("tests/bad_scenes/negative_dt.ron");
    let e = Scene::load(&path, &[]).unwrap_err().to_string();
    assert!(
        e.contains("negative_dt.ron:29:9: field `integration.dt_s`"),
        "{e}"
    );
    let shipped = common::crate_path("scenes/drape_wool.ron");
    let e = Scene::load(&shipped, &["integration.dt_s=-0.001".into()])
        .unwrap_err()
        .to_string();
    assert!(
        e.contains("drape_wool.ron: field `integration.dt_s` = -0.001"),
        "{e}"
    );
}
