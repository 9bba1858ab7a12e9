//! Internal damping and our forces leave free fall alone: with no collider to touch, the cloth's
//! centre of mass falls at g, whatever effects are on (all of them are pair forces inside the
//! cloth). Air drag, which does slow a fall, is off.

use kes_cloth::material::STANDARD_GRAVITY;
use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;

mod common;

#[test]
fn a_falling_cloth_accelerates_at_g_within_one_percent() {
    for fabric in ["thin_wool", "thick_cotton"] {
        let sets = [
            common::explicit_drape("wool"),
            vec![
                "world.colliders=[]".to_string(),
                "measure=None".to_string(),
                "integration.max_time_s=0.2".to_string(),
                // Within the stability guard for both fabrics at 1 cm (thick cotton's compression:
                // 0.139 ms).
                "cloth.spacing_m=0.01".to_string(),
                "integration.dt_s=0.000125".to_string(),
                format!("fabric={{\"File\":\"../assets/fabrics/{fabric}.ron\"}}"),
            ],
        ]
        .concat();
        let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
        let outcome = simulate(&scene, &RunOptions::default());
        let t = outcome.metrics.sim_time_s;
        let start: f64 = kes_cloth::scene::spawn::cloth_grid(&scene)
            .1
            .iter()
            .map(|p| p.y)
            .sum::<f64>();
        let n = outcome.positions.len() as f64;
        let drop = (start - outcome.positions.iter().map(|p| p.y).sum::<f64>()) / n;
        // Symplectic Euler's fall after k steps is g·dt²·k(k+1)/2, 0.1 % above ½gt² here;
        // the 1 % tolerance leaves ten times that room.
        let expected = 0.5 * STANDARD_GRAVITY * t * t;
        assert!(
            (drop / expected - 1.0).abs() < 0.01,
            "{fabric}: fell {drop} m in {t} s, free fall {expected} m"
        );
        assert!(outcome.metrics.effects["damping"].calls > 0, "damping was on");
    }
}

/// The step speed measured from positions is the velocity Rapier integrated positions with: in
/// free fall (no contact to leave a velocity the position does not follow) it equals Rapier's
/// stored velocity of the fastest node, g·t after t seconds.
#[test]
fn step_speed_from_positions_is_the_fall_speed() {
    let sets = [
        common::explicit_drape("wool"),
        vec![
            "world.colliders=[]".to_string(),
            "measure=None".to_string(),
            "integration.max_time_s=0.1".to_string(),
            "integration.dt_s=0.0002".to_string(),
        ],
    ]
    .concat();
    let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &sets).unwrap();
    let m = simulate(&scene, &RunOptions::default()).metrics;
    let fall = STANDARD_GRAVITY * m.sim_time_s;
    // Rapier's positions are f32: a node near y = 0 moves ~0.2 mm a step, resolved to ~1e-8 m,
    // so the two speeds agree to ~1e-4 relative; the in-cloth forces move the fastest node's
    // speed off g·t by well under 1 %.
    assert!(
        (m.max_step_speed_m_per_s / m.max_speed_m_per_s - 1.0).abs() < 1e-3,
        "moved {} m/s over the last step, Rapier's velocity {} m/s",
        m.max_step_speed_m_per_s,
        m.max_speed_m_per_s
    );
    assert!(
        (m.max_speed_m_per_s / fall - 1.0).abs() < 0.01,
        "{} m/s after {} s",
        m.max_speed_m_per_s,
        m.sim_time_s
    );
}
