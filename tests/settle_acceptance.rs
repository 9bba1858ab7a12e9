//! A drape that settles: on the shipped drapemeter and Cusick scenes, both fabrics, the cloth
//! comes to rest within 5 s of simulated time and then stays put: 5 more simulated seconds move
//! no node more than 0.5 mm and the cloth's centroid less than 0.5 mm (no creep, no slide-off);
//! and at no step does a node centre sit more than 0.5 mm inside the disk or the floor. At the
//! end, no node moves faster than 1 mm/s over a step (measured from positions: Rapier's stored
//! velocity of a node resting on the rim reads 5–26 mm/s while the node stays put).
//! These are the acceptance bounds of the settling issue; they are not loosened here.

use kes_cloth::repeat::simulate_all;
use kes_cloth::scene::Scene;

mod common;

/// Largest node displacement and centroid displacement allowed over the creep check (m).
const CREEP_BOUND: f64 = 0.5e-3;
/// Deepest a node centre may sit inside a collider at the end of any step (m).
const PENETRATION_BOUND: f64 = 0.5e-3;
/// Fastest a node may move over the last step once settled (m/s): "no jitter", the implicit
/// integrator issue's bound. Measured on these scenes in session 9: 0.11–0.15 mm/s.
const JITTER_BOUND: f64 = 1e-3;

#[test]
fn drapes_settle_within_five_seconds_and_do_not_creep() {
    let names = ["drape_cotton", "drape_wool", "cusick_cotton", "cusick_wool"];
    let sets = [
        "integration.settle.creep_check_s=5".to_string(),
        "integration.max_time_s=11".to_string(),
    ];
    let scenes: Vec<Scene> = names
        .iter()
        .map(|n| Scene::load(common::crate_path(&format!("scenes/{n}.ron")), &sets).unwrap())
        .collect();
    for (name, outcome) in names.iter().zip(simulate_all(&scenes, 2, |_, _| {})) {
        let m = &outcome.metrics;
        let settle = m.settle_time_s.unwrap_or(f64::INFINITY);
        // `settle_time_s` opens the quiet window; the window (0.5 s) must also end within 5 s.
        assert!(m.settled && settle + 0.5 <= 5.0, "{name}: settled at {settle} s");
        let window = m.creep_window_s.unwrap_or(0.0);
        assert!(
            (window - 5.0).abs() < 1e-6,
            "{name}: watched {window} s after settling, not 5 s"
        );
        assert!(
            m.peak_penetration_m <= PENETRATION_BOUND,
            "{name}: a node sat {:.3} mm inside a collider at the worst step",
            m.peak_penetration_m * 1e3
        );
        let (node, centroid) = (m.creep_max_node_m.unwrap(), m.creep_centroid_m.unwrap());
        assert!(
            node <= CREEP_BOUND && centroid <= CREEP_BOUND,
            "{name}: over 5 s after settling a node moved {:.3} mm, the centroid {:.3} mm",
            node * 1e3,
            centroid * 1e3
        );
        assert!(
            m.max_step_speed_m_per_s < JITTER_BOUND,
            "{name}: a node moved {:.2} mm/s over the last step, 5 s after settling",
            m.max_step_speed_m_per_s * 1e3
        );
    }
}
