//! `kes-cloth converge`: a scene at three spacings, its observed order and extrapolated value.

use std::process::Command;

mod common;

/// Thick cotton with the KES tensile law, implicit at 1/240 s (each run well under a second) at
/// 2, 1.5 and 1 cm: the command writes its table, CSV and plot, one row per spacing, and an
/// extrapolation whose band is stated; the extrapolated DC lies within its own uncertainty of
/// the Richardson formula applied to the CSV's numbers.
#[test]
fn converge_writes_an_extrapolation_with_its_uncertainty() {
    let out = std::env::temp_dir().join("kes-cloth-converge-test");
    let _ = std::fs::remove_dir_all(&out);
    let status = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .args([
            "converge",
            "scenes/drape_cotton.ron",
            "--spacings",
            "0.02,0.015,0.01",
        ])
        .args(["--set", "integration.integrator=Implicit"])
        .args(["--set", "integration.dt_s=0.0041666667"])
        .args(["--set", "effects.stretch=Kes"])
        .arg("--out")
        .arg(&out)
        .current_dir(common::crate_path(""))
        .output()
        .unwrap();
    let stderr = String::from_utf8_lossy(&status.stderr);
    assert!(status.status.success(), "converge failed: {stderr}");
    for file in ["convergence.csv", "convergence.md", "convergence.png"] {
        assert!(out.join(file).exists(), "{file} missing");
    }
    let csv = std::fs::read_to_string(out.join("convergence.csv")).unwrap();
    let rows: Vec<Vec<&str>> = csv.lines().skip(1).map(|l| l.split(',').collect()).collect();
    assert_eq!(rows.len(), 3, "{csv}");
    // Coarsest first, each at the scene's own step (implicit: step exponent 0).
    let spacings: Vec<f64> = rows.iter().map(|r| r[0].parse().unwrap()).collect();
    assert_eq!(spacings, [0.02, 0.015, 0.01]);
    assert!(
        rows.iter()
            .all(|r| (r[1].parse::<f64>().unwrap() - 0.0041666667).abs() < 1e-12)
    );
    let dcs: Vec<f64> = rows.iter().map(|r| r[3].parse().unwrap()).collect();
    let e = kes_cloth::study::richardson::extrapolate_means(&spacings, &dcs, &[0.0; 3]).unwrap();
    let md = std::fs::read_to_string(out.join("convergence.md")).unwrap();
    assert!(
        md.contains(&format!("{:.4} ± {:.4}", e.value, e.uncertainty)),
        "the table's extrapolation is not the CSV's: {md}"
    );
    assert!(
        e.uncertainty > 0.0,
        "a band of zero width from three different DCs: {dcs:?}"
    );
}

/// Spacings at which the tablecloth's table edge lies on a node row at some and between rows at
/// others (10, 7.5 and 5 mm) are planned with a warning that names them and suggests spacings
/// that halve; those (1 cm, 5 mm, 2.5 mm) and the round disk's spacings plan without one.
#[test]
fn converge_warns_when_a_table_edge_meets_the_lattice_differently_across_spacings() {
    let plan = |scene: &str, spacings: &str| {
        let name = format!("kes-cloth-converge-plan-{}", spacings.replace(',', "-"));
        let out = std::env::temp_dir().join(name);
        let _ = std::fs::remove_dir_all(&out);
        let output = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
            .args(["converge", scene, "--spacings", spacings, "--plan", "--out"])
            .arg(&out)
            .current_dir(common::crate_path(""))
            .output()
            .unwrap();
        assert!(output.status.success());
        String::from_utf8_lossy(&output.stderr).into_owned()
    };
    let mixed = plan("scenes/tablecloth_cotton.ron", "0.01,0.0075,0.005");
    assert!(
        mixed.starts_with("warning:")
            && mixed.contains("on a row of nodes at 10 mm, 5 mm and between rows at 7.5 mm")
            && mixed.contains("0.01,0.005,0.0025"),
        "{mixed}"
    );
    assert_eq!(plan("scenes/tablecloth_cotton.ron", "0.01,0.005,0.0025"), "");
    assert_eq!(plan("scenes/drape_cotton.ron", "0.0075,0.005,0.00375"), "");
}
