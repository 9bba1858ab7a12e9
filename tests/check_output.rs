//! `kes-cloth check` speaks plain quantities with units: for every shipped scene, no Rust debug
//! structure (`Name { field: … }`, `Some(…)`, `[a, b, c]` arrays) reaches the reader.

use std::process::Command;

mod common;

#[test]
fn check_prints_plain_quantities_for_every_shipped_scene() {
    let mut scenes = Vec::new();
    for dir in [
        "scenes",
        "scenes/hard",
        "scenes/hysteresis",
        "scenes/bending_length",
    ] {
        for entry in std::fs::read_dir(common::crate_path(dir)).expect("scene folder") {
            let path = entry.expect("entry").path();
            if path.extension().is_some_and(|e| e == "ron") {
                scenes.push(path);
            }
        }
    }
    assert!(scenes.len() >= 10, "found only {} scenes", scenes.len());
    for scene in scenes {
        let out = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
            .arg("check")
            .arg(&scene)
            .output()
            .expect("runs");
        assert!(out.status.success(), "{}", String::from_utf8_lossy(&out.stderr));
        let text = String::from_utf8_lossy(&out.stdout);
        for debug in [" { ", "Some(", "None", "Spec", ": [", "Warp:", "Weft:"] {
            assert!(
                !text.contains(debug),
                "{}: `{debug}` in:\n{text}",
                scene.display()
            );
        }
        for plain in ["kg/m²", "N·m", "spacing", "m/s²", "effects:"] {
            assert!(
                text.contains(plain),
                "{}: `{plain}` missing:\n{text}",
                scene.display()
            );
        }
    }
}
