//! Fabrics from a KES table: `kes-cloth fabric import` turns each row of a CSV table into a
//! fabric file equal to one written by hand, and a bad table is refused with the row and column
//! at fault, a non-zero exit and no panic.

use std::path::PathBuf;
use std::process::Command;

use kes_cloth::material::{Fabric, read_kes_table};

mod common;

fn kes_cloth(args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("kes-cloth runs")
}

/// The shipped example table holds thick cotton and thin wool with the shipped files' values:
/// imported through the command, each file loads to exactly the fabric of the shipped file (SI
/// values compared bit for bit), and `fabric check` prints its values with units.
#[test]
fn the_example_table_imports_to_the_shipped_fabrics() {
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fabric_import_example");
    let _ = std::fs::remove_dir_all(&out);
    let run = kes_cloth(&[
        "fabric",
        "import",
        "assets/kes_tables/example.csv",
        "--out",
        out.to_str().expect("utf-8 path"),
    ]);
    assert!(run.status.success(), "{}", String::from_utf8_lossy(&run.stderr));
    for stem in ["thick_cotton", "thin_wool"] {
        let imported = Fabric::load(out.join(format!("{stem}.ron"))).expect("imported file loads");
        let shipped = common::shipped_fabric(stem);
        assert_eq!(imported.bending, shipped.bending, "{stem}");
        assert_eq!(imported.shear, shipped.shear, "{stem}");
        assert_eq!(imported.tensile, shipped.tensile, "{stem}");
        assert_eq!(imported.areal_density, shipped.areal_density, "{stem}");
        assert_eq!(imported.thickness, shipped.thickness, "{stem}");
    }
    let check = kes_cloth(&[
        "fabric",
        "check",
        out.join("thin_wool.ron").to_str().expect("utf-8 path"),
    ]);
    assert!(check.status.success());
    let sheet = String::from_utf8_lossy(&check.stdout);
    // B along the warp, 0.055 gf·cm²/cm = 5.394e-6 N·m; the bending length (B/W)^(1/3) with
    // W = 0.125 kg/m² × 9.80665 m/s² is 1.64 cm.
    for expected in ["0.055", "gf·cm²/cm", "5.394e-6", "N·m", "warp 1.64 cm"] {
        assert!(sheet.contains(expected), "{expected:?} missing from:\n{sheet}");
    }
}

/// A units row with g/m² for W is read as such: 125 g/m² is 12.5 mg/cm².
#[test]
fn a_units_row_converts_the_weight_from_grams_per_square_metre() {
    let dir = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fabric_import_units");
    std::fs::create_dir_all(&dir).expect("temp dir");
    let table = dir.join("grams.csv");
    std::fs::write(
        &table,
        "name,source,W,T,B,2HB,G,2HG,2HG5,LT,WT,RT,EMT\n\
         units,,g/m²,mm,gf·cm²/cm,gf·cm/cm,gf/(cm·deg),gf/cm,gf/cm,,gf·cm/cm²,%,%\n\
         wool,estimate,125,0.45,0.05,0.03,0.55,0.8,1.6,0.62,12.4,60,8\n",
    )
    .expect("table written");
    let fabrics = read_kes_table(&table).expect("reads");
    assert_eq!(fabrics.len(), 1);
    assert_eq!(fabrics[0].row, 3);
    assert!((fabrics[0].kes.weight_mg_per_cm2 - 12.5).abs() < 1e-12);
    assert_eq!(fabrics[0].kes.bending.warp, fabrics[0].kes.bending.weft);
}

/// Each bad table in `tests/bad_kes_tables/` is refused by the command with a message naming
/// the file, the row and the column (or the missing column), a non-zero exit, and no panic.
#[test]
fn bad_tables_are_refused_naming_row_and_column() {
    let cases = [
        ("missing_column.csv", "row 1 (the header): no column `2HG5`"),
        (
            "text_in_number.csv",
            "row 3, column 6 (`B-2`): `n/a` is not a number",
        ),
        (
            "negative_b.csv",
            "row 3, column 5 (`B-1`): field `bending.warp.b` = -0.055: must lie in (0, 100]",
        ),
        (
            "duplicate_names.csv",
            "row 3, column 1 (`name`): `thin wool` is already the name of row 2",
        ),
        ("unknown_unit.csv", "row 2, column 3 (`W`): unit `oz/yd2`"),
    ];
    let out = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("fabric_import_bad");
    for (file, expected) in cases {
        let path = format!("tests/bad_kes_tables/{file}");
        let run = kes_cloth(&["fabric", "import", &path, "--out", out.to_str().expect("utf-8")]);
        let stderr = String::from_utf8_lossy(&run.stderr);
        assert_eq!(run.status.code(), Some(1), "{file}: {stderr}");
        assert!(!stderr.contains("panicked"), "{file}: {stderr}");
        assert!(stderr.contains(&path), "{file}: the file is not named: {stderr}");
        assert!(
            stderr.contains(expected),
            "{file}: {expected:?} missing from: {stderr}"
        );
    }
}
