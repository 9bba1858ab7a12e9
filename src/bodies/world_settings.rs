//! Rapier integration settings for centimetre-scale cloth.

use rapier3d::prelude::*;

/// Sets the step and solver, and scales Rapier's metre-scale contact distances to cloth.
///
/// - contact recycling off: with it, rim nodes rest on stale top-face contacts and the skirt
///   hangs too far out (measured: DC 0.12–0.14 instead of 0.03–0.05, `../shared` notes);
/// - fixed-contact softness 960 Hz: at Rapier's 60 Hz light rim nodes sank ~3 mm into the disk
///   edge, at 240 Hz up to 0.5 mm; 960 Hz keeps a drape's deepest node within 0.2 mm;
/// - friction in the bias pass: without it, the position correction slides rim nodes along the
///   disk without friction, and a skirt on a sharp rim creeps by millimetres after it settled;
/// - joints warm-started: stiff rope chains converge in fewer sweeps;
/// - prediction distance 5 mm and slop 1 mm instead of 2 cm and 5 mm.
pub fn configure_world(
    world: &mut PhysicsWorld,
    gravity: [f64; 3],
    dt: f64,
    solver_iterations: usize,
    pgs_iterations: usize,
) {
    world.gravity = Vector::new(gravity[0] as f32, gravity[1] as f32, gravity[2] as f32);
    let p = &mut world.integration_parameters;
    p.dt = dt as f32;
    p.num_solver_iterations = solver_iterations;
    p.num_internal_pgs_iterations = pgs_iterations;
    p.contact_recycling = false;
    p.static_contact_softness = SpringCoefficients::new(960.0, 10.0);
    p.friction_in_bias_pass = true;
    p.warmstart_joints = true;
    p.normalized_prediction_distance = 0.005;
    p.normalized_allowed_linear_error = 0.001;
}
