//! The implicit integrator drapes thick cotton, with its full measured B and G, at the step
//! contact needs (1/240 s), where the explicit integrator diverges.
//!
//! Measured (seed 0, sharp rim, gravity in the solve, supports from Rapier's contact
//! impulses): explicit at 0.125 ms DC 0.738 with 4 nodes; implicit at 1/240 s DC 0.702 with 4
//! nodes, settled at 0.6 s simulated, link strain 1.6 %, fastest node at the end 2.3 mm/s, CG 40
//! iterations a step on average (on the rim rounded by 5 mm: 0.678 and 0.696). The DC
//! tolerance here, 0.05, is the spread of the implicit result over steps from 0.5 to 4.2 ms
//! (0.652–0.703); a 0.02 agreement is not reached at every step and is not asserted.

use kes_cloth::output::Metrics;
use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;

mod common;

const CONTACT_STEP: &str = "integration.dt_s=0.0041666667";

fn drape(sets: &[&str]) -> kes_cloth::run::RunOutcome {
    // The seed's explicit cotton drape (1 cm, rope joints), then `sets`.
    let mut all = common::explicit_drape("cotton");
    all.extend(sets.iter().map(|s| s.to_string()));
    let scene = Scene::load(common::crate_path("scenes/drape_cotton.ron"), &all).unwrap();
    simulate(&scene, &RunOptions::default())
}

/// `implicit` did not diverge, settled, drapes within `tolerance` of `reference`'s DC, and has
/// its node count.
fn assert_settled_near(implicit: &Metrics, reference: &Metrics, tolerance: f64) {
    assert!(implicit.failure.is_none(), "diverged: {:?}", implicit.failure);
    assert!(implicit.settled, "did not settle in {} s", implicit.sim_time_s);
    let (dc, dc_ref) = (
        implicit.drape_coefficient.unwrap(),
        reference.drape_coefficient.unwrap(),
    );
    assert!(
        (dc - dc_ref).abs() <= tolerance,
        "implicit DC {dc:.3} vs explicit reference {dc_ref:.3}"
    );
    assert_eq!(implicit.nodes, reference.nodes, "node counts differ");
}

#[test]
fn explicit_cotton_diverges_at_the_contact_step() {
    // Damping within the explicit limit at this step (1/(4·dt) = 60/s), and past the stability
    // guard on purpose (it refuses this step).
    let outcome = drape(&[
        CONTACT_STEP,
        "integration.max_time_s=1",
        "effects.damping.rate_per_s=50",
        "integration.step_guard=false",
    ]);
    let failure = outcome
        .metrics
        .failure
        .expect("explicit KES forces at 1/240 s must diverge");
    assert!(failure.message.contains("runaway") || failure.message.contains("non-finite"));
}

#[test]
fn implicit_cotton_settles_at_the_contact_step_near_the_explicit_reference() {
    let reference = drape(&[]).metrics;
    let implicit = drape(&[CONTACT_STEP, "integration.integrator=Implicit"]).metrics;
    assert_settled_near(&implicit, &reference, 0.05);
    // Rapier's rope joints at one iteration per 4.2 ms step hold the links less tightly than
    // at 0.125 ms (1 %): measured 2.8 % (8 % before the compression spring had a fixed
    // modulus); 12 % would mean the joints are losing the cloth.
    assert!(
        implicit.max_strain < 0.12,
        "link strain {:.1} %",
        implicit.max_strain * 100.0
    );
    assert!(implicit.cg_unconverged_steps == Some(0), "CG stopped early");
    // Regression (nodes flickering on and off the disk, 63 mm/s at the end of a settled run):
    // the solve held a node's normal velocity at zero by a 1 mm gap rule of its own, which
    // Rapier's contact disagreed with every other step; it now takes the nodes Rapier's contact
    // pushed. Measured 2.3 mm/s; 10 mm/s leaves room for the seed-to-seed spread of a settled
    // run's last step, and is a quarter of the flicker.
    assert!(
        implicit.max_speed_m_per_s < 0.010,
        "fastest node {:.1} mm/s at the end",
        implicit.max_speed_m_per_s * 1e3
    );
}

/// With the KES tensile law in the solve (no rope joints), thick cotton at 1 cm and 1/240 s
/// drapes within 0.02 of the explicit reference, with its node
/// count. Regression (supports flickering at the rim, 59 CG products a step, settled only at
/// 5.2 s, DC 0.725): a node kept off the disk by the filter was released when Rapier's contact
/// stopped pushing it, pulled back by the cloth, and held again, every other step. Supports now
/// stay while the node touches and the surface pushed in the last solve. Measured: DC 0.746
/// against 0.738, 4 nodes, 11 products a step, settled at 1.6 s; 30 products is half the flicker.
/// Friction in the solve (`tests/implicit_friction.rs`) is off here: this test is
/// about the supports alone, and friction's extra solve per step would hide the flicker's cost.
#[test]
fn implicit_cotton_with_kes_stretch_keeps_its_supports() {
    let reference = drape(&[]).metrics;
    let implicit = drape(&[
        CONTACT_STEP,
        "integration.integrator=Implicit",
        "effects.stretch=Kes",
        "integration.implicit_solver.friction=false",
    ])
    .metrics;
    assert_settled_near(&implicit, &reference, 0.02);
    let cg = implicit.cg_iterations_mean.unwrap();
    assert!(cg < 30.0, "{cg:.0} CG products a step");
}
