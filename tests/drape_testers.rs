//! The built-in testers of `kes-cloth drape`: a fabric file on a tester is the shipped scene of
//! that tester and fabric, field for field (name and fabric path aside), so it gives the same
//! numbers; a fabric the shipped scenes do not cover gets settings by the same rule.

use std::path::PathBuf;
use std::process::Command;

use kes_cloth::material::Thread;
use kes_cloth::scene::{FabricSource, IntegratorSpec, Scene, Tester, tester_scene};

mod common;

/// The shipped scene `scene` and the tester's scene for its fabric agree in every field but the
/// name and the fabric file's path; both load the same fabric.
fn assert_same_scene(tester: Tester, scene: &str, fabric: &str) {
    let shipped = Scene::load(common::crate_path(scene), &[]).expect("shipped scene loads");
    let built = tester_scene(
        tester,
        &common::crate_path(&format!("assets/fabrics/{fabric}.ron")),
        &[],
    )
    .expect("tester scene builds");
    assert_eq!(built.fabric, shipped.fabric, "{scene}");
    let mut spec = built.spec.clone();
    spec.name = shipped.spec.name.clone();
    spec.fabric = shipped.spec.fabric.clone();
    assert!(matches!(built.spec.fabric, FabricSource::File(_)));
    assert_eq!(
        spec,
        shipped.spec,
        "{} tester differs from {scene}",
        tester.name()
    );
}

/// Every shipped scene of a built-in tester is what `drape` builds for its fabric: the seed's
/// drapemeter (drape_*), the Cusick tester with a 30 cm specimen (cusick_*) and the tablecloth
/// (tablecloth_*), for thin wool (c = 1.53 cm) and thick cotton (c = 2.6 cm): on the drapemeters
/// the coarsest listed spacing within a sixth of c (2.5 mm for both), on the tablecloth 3.33 mm.
#[test]
fn each_tester_builds_the_shipped_scene_of_its_fabric() {
    for (fabric, short) in [("thin_wool", "wool"), ("thick_cotton", "cotton")] {
        assert_same_scene(Tester::Seed, &format!("scenes/drape_{short}.ron"), fabric);
        assert_same_scene(Tester::Cusick30, &format!("scenes/cusick_{short}.ron"), fabric);
        assert_same_scene(
            Tester::Tablecloth,
            &format!("scenes/tablecloth_{short}.ron"),
            fabric,
        );
    }
}

/// The 24 and 36 cm Cusick specimens are circles of that diameter on the 18 cm disk; a fabric
/// no shipped scene uses gets the coarsest listed spacing within a sixth of its bending length
/// and the testers' BDF2 step of 1/240 s; on the tablecloth it keeps the scene's 3.33 mm, a
/// thirtieth of the table's half-width.
#[test]
fn other_specimens_and_fabrics_get_the_rule() {
    for (tester, diameter) in [(Tester::Cusick24, 0.24), (Tester::Cusick36, 0.36)] {
        let scene = tester_scene(
            tester,
            &common::crate_path("assets/fabrics/polyester_faille.ron"),
            &[],
        )
        .expect("builds");
        assert_eq!(
            scene.field("cloth.shape"),
            Some(serde_json::json!({"Circle": {"diameter_m": diameter}})),
            "{}",
            tester.name()
        );
        let c = scene
            .fabric
            .bending_length(Thread::Warp)
            .min(scene.fabric.bending_length(Thread::Weft));
        let expected = [0.0025, 0.001875, 0.00125]
            .into_iter()
            .find(|s| *s <= c / 6.0)
            .unwrap_or(0.00125);
        assert_eq!(scene.spec.cloth.spacing_m, expected, "c = {c} m");
        assert_eq!(scene.spec.integration.integrator, IntegratorSpec::Bdf2);
        assert!((scene.spec.integration.dt_s - 1.0 / 240.0).abs() < 1e-9);
    }
    let scene = tester_scene(
        Tester::Tablecloth,
        &common::crate_path("assets/fabrics/polyester_faille.ron"),
        &[],
    )
    .expect("builds");
    assert_eq!(scene.spec.cloth.spacing_m, 0.1 / 30.0);
    assert_eq!(scene.spec.integration.integrator, IntegratorSpec::Bdf2);
}

/// The command runs a fabric file on a tester and writes what `run` writes, the report among
/// them; a tester it does not know is refused with the list of those it does.
#[test]
fn the_command_drapes_a_fabric_file_and_refuses_an_unknown_tester() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("drape_command");
    let run = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "drape",
            "assets/fabrics/thick_cotton.ron",
            "--tester",
            "cusick-30",
            "--quiet",
        ])
        .args([
            "--set",
            "integration.max_time_s=0.01",
            "--out",
            out.to_str().expect("utf-8"),
        ])
        .output()
        .expect("runs");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    for file in ["metrics.json", "final.obj", "top.png", "side.png", "report.html"] {
        assert!(out.join(file).exists(), "{file} not written");
    }
    // The report shows both pictures and the fabric in KES units.
    let report = std::fs::read_to_string(out.join("report.html")).expect("report");
    for part in [
        "<img src=\"top.png\"",
        "<img src=\"side.png\"",
        "id=\"fabric\"",
        "gf·cm²/cm",
    ] {
        assert!(report.contains(part), "{part} missing from report.html");
    }
    // With --repeat, the folder's own report has a row per seed and seed 0's 3D view.
    let repeated = out.with_file_name("drape_command_repeat");
    let run = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .args([
            "drape",
            "assets/fabrics/thick_cotton.ron",
            "--repeat",
            "2",
            "--quiet",
        ])
        .args([
            "--set",
            "integration.max_time_s=0.01",
            "--out",
            repeated.to_str().expect("utf-8"),
        ])
        .output()
        .expect("runs");
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    let report = std::fs::read_to_string(repeated.join("report.html")).expect("the repeat's report");
    assert_eq!(
        report.matches("<tr><td>").count(),
        2,
        "one row per seed:\n{report}"
    );
    assert!(report.contains("href=\"seed-0/final.glb\""), "{report}");
    assert!(report.contains("<img src=\"repeat.png\""), "{report}");
    assert!(repeated.join("repeat.png").exists(), "repeat.png not written");
    let refused = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .args([
            "drape",
            "assets/fabrics/thick_cotton.ron",
            "--tester",
            "cusick-99",
        ])
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("runs");
    let stderr = String::from_utf8_lossy(&refused.stderr);
    assert_eq!(refused.status.code(), Some(2), "{stderr}");
    assert!(
        stderr.contains("cusick-30") && stderr.contains("tablecloth"),
        "{stderr}"
    );
}
