//! README's "Your own fabric", followed literally: import the shipped example KES table, check
//! a fabric, drape it on the Cusick 30 cm tester, and open the report in headless Chromium: the
//! page loads its 3D view, the cloth covers part of it, and no script error is logged.

use std::path::{Path, PathBuf};
use std::process::Command;

fn kes_cloth(args: &[&str]) -> String {
    let out = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .args(args)
        .current_dir(env!("CARGO_MANIFEST_DIR"))
        .output()
        .expect("kes-cloth runs");
    assert!(
        out.status.success(),
        "kes-cloth {args:?}: {}",
        String::from_utf8_lossy(&out.stderr)
    );
    String::from_utf8_lossy(&out.stdout).into_owned()
}

/// The value of `attribute` on the first element of `dom` whose opening tag starts with `tag`.
fn attribute<'a>(dom: &'a str, tag: &str, attribute: &str) -> Option<&'a str> {
    let start = dom.find(tag)?;
    let end = start + dom[start..].find('>')?;
    let element = &dom[start..end];
    let key = format!("{attribute}=\"");
    let at = element.find(&key)? + key.len();
    element[at..].split('"').next()
}

/// Opens `page` in headless Chromium (`scripts/install-test-tools` installs Debian's) and returns the DOM after
/// 5 s of page time, writing a screenshot beside it.
fn open_headless(page: &Path) -> String {
    let url = format!("file://{}", page.display());
    let common = [
        "--headless",
        "--no-sandbox",
        "--disable-gpu",
        "--enable-unsafe-swiftshader",
        "--use-angle=swiftshader",
        "--window-size=1200,1800",
        "--virtual-time-budget=5000",
    ];
    let run = |extra: &str| {
        Command::new("chromium")
            .args(common)
            .arg(extra)
            .arg(&url)
            .output()
            .unwrap_or_else(|e| {
                panic!("chromium does not run ({e}): `scripts/install-test-tools` installs it")
            })
    };
    let shot = page.with_file_name("report.png");
    assert!(run(&format!("--screenshot={}", shot.display())).status.success());
    assert!(shot.exists(), "no screenshot");
    let dom = run("--dump-dom");
    assert!(dom.status.success());
    String::from_utf8_lossy(&dom.stdout).into_owned()
}

#[test]
fn the_readmes_own_fabric_steps_end_in_a_report_with_the_cloth_in_3d() {
    let work = PathBuf::from(env!("CARGO_TARGET_TMPDIR")).join("your_own_fabric");
    let _ = std::fs::remove_dir_all(&work);
    let fabrics = work.join("my_fabrics");
    let out = work.join("out");
    let (fabrics_arg, out_arg) = (fabrics.to_str().expect("utf-8"), out.to_str().expect("utf-8"));
    // Steps 2–4 of the README, with the folders placed in the test's own directory and the
    // drape at 5 mm instead of the tester's 2.5 mm for thin wool, at rest after its first quiet
    // window (no confirmation watch): this test checks the steps and the report, not the
    // drape's numbers (the tester's spacing rule: `tests/drape_testers.rs`).
    kes_cloth(&[
        "fabric",
        "import",
        "assets/kes_tables/example.csv",
        "--out",
        fabrics_arg,
    ]);
    let fabric = fabrics.join("thin_wool.ron");
    let sheet = kes_cloth(&["fabric", "check", fabric.to_str().expect("utf-8")]);
    assert!(sheet.contains("bending length"), "{sheet}");
    kes_cloth(&[
        "drape",
        fabric.to_str().expect("utf-8"),
        "--tester",
        "cusick-30",
        "--set",
        "cloth.spacing_m=0.005",
        "--set",
        "integration.settle.confirm_s=0",
        "--out",
        out_arg,
        "--quiet",
    ]);
    for file in [
        "metrics.json",
        "top.png",
        "side.png",
        "final.glb",
        "report.html",
        "viewer/three.min.js",
    ] {
        assert!(out.join(file).exists(), "{file} not written");
    }
    let dom = open_headless(&out.join("report.html"));
    assert_eq!(
        attribute(&dom, "<div id=\"view3d\"", "data-loaded"),
        Some("true"),
        "the 3D view did not load"
    );
    // The cloth covers about 16 % of the 3D view as framed (measured); a tenth of that shows
    // it is drawn at all.
    let coverage: f64 = attribute(&dom, "<div id=\"view3d\"", "data-coverage")
        .and_then(|c| c.parse().ok())
        .expect("coverage recorded");
    assert!(coverage > 0.016, "the cloth covers {coverage} of the 3D view");
    assert_eq!(
        attribute(&dom, "<body", "data-errors"),
        None,
        "the page logged errors"
    );
    // The thin wool's drape figures are on the page.
    for part in ["drape coefficient DC", "nodes (folds)", "gf·cm²/cm"] {
        assert!(dom.contains(part), "{part} missing from the page");
    }
}
