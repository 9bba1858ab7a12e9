//! No preferred direction: turning the cloth's warp by 45° or 90° about the vertical on the
//! round drapemeter changes neither the drape coefficient (within 0.01) nor the node count.
//! (A global drift or a solver-order bias would show here; the measured DC agrees to 1e-3.)

use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;

mod common;

fn drape(scene: &str, angle: f64) -> (f64, u32) {
    let sets = [format!("cloth.warp_angle_deg={angle}")];
    let scene = Scene::load(common::crate_path(&format!("scenes/{scene}.ron")), &sets).unwrap();
    let m = simulate(&scene, &RunOptions::default()).metrics;
    assert!(m.settled);
    (m.drape_coefficient.unwrap(), m.nodes.unwrap())
}

#[test]
fn turning_the_cloth_does_not_change_its_drape() {
    for scene in ["drape_wool", "drape_cotton"] {
        let (dc0, n0) = drape(scene, 0.0);
        for angle in [45.0, 90.0] {
            let (dc, n) = drape(scene, angle);
            assert!(
                (dc - dc0).abs() < 0.01,
                "{scene} at {angle}°: DC {dc:.4} against {dc0:.4}"
            );
            assert_eq!(n, n0, "{scene} at {angle}°: nodes");
        }
    }
}
