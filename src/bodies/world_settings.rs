//! Rapier integration settings for centimetre-scale cloth.

use rapier3d::prelude::*;

/// Damping ratio of every contact (dimensionless): Rapier's default, 10.
const CONTACT_DAMPING_RATIO: f32 = 10.0;

/// How stiff Rapier's contacts are: the natural frequency of the soft contact constraint (Hz).
/// A stiffer contact lets a body sink less under a given load (sinking ∝ load/frequency²).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ContactStiffness {
    /// Contacts with a fixed body (Hz; default 960). At Rapier's 60 Hz light rim nodes sank
    /// ~3 mm into the drapemeter's disk edge, at 240 Hz up to 0.5 mm; 960 Hz keeps a drape's
    /// deepest node within 0.2 mm.
    pub fixed_hz: f64,
    /// Contacts between two moving bodies: nodes with each other (self-collision) or with a
    /// thrown ball (Hz; default 30, Rapier's).
    pub moving_hz: f64,
}

impl Default for ContactStiffness {
    fn default() -> Self {
        Self {
            fixed_hz: 960.0,
            moving_hz: 30.0,
        }
    }
}

/// Sets the step and solver, and scales Rapier's metre-scale contact distances to cloth.
///
/// - contact recycling off: with it, rim nodes rest on stale top-face contacts and the skirt
///   hangs too far out (measured: DC 0.12–0.14 instead of 0.03–0.05, `../shared` notes);
/// - contact stiffness from `contact` ([`ContactStiffness`]; by default 960 Hz against fixed
///   bodies, Rapier's 30 Hz between moving ones);
/// - friction in the bias pass: without it, the position correction slides rim nodes along the
///   disk without friction, and a skirt on a sharp rim creeps by millimetres after it settled;
/// - joints warm-started: stiff rope chains converge in fewer sweeps;
/// - prediction distance 5 mm and slop 1 mm instead of 2 cm and 5 mm, with a length unit of
///   1 cm ([`LENGTH_UNIT_M`]).
pub fn configure_world(
    world: &mut PhysicsWorld,
    gravity: [f64; 3],
    dt: f64,
    (solver_iterations, pgs_iterations): (usize, usize),
    contact: ContactStiffness,
) {
    world.gravity = Vector::new(gravity[0] as f32, gravity[1] as f32, gravity[2] as f32);
    let p = &mut world.integration_parameters;
    p.dt = dt as f32;
    p.num_solver_iterations = solver_iterations;
    p.num_internal_pgs_iterations = pgs_iterations;
    p.contact_recycling = false;
    p.static_contact_softness = SpringCoefficients::new(contact.fixed_hz as f32, CONTACT_DAMPING_RATIO);
    p.contact_softness = SpringCoefficients::new(contact.moving_hz as f32, CONTACT_DAMPING_RATIO);
    p.friction_in_bias_pass = true;
    p.warmstart_joints = true;
    set_length_unit(p, LENGTH_UNIT_M);
    p.normalized_prediction_distance = PREDICTION_DISTANCE_M / LENGTH_UNIT_M;
    p.normalized_allowed_linear_error = ALLOWED_LINEAR_ERROR_M / LENGTH_UNIT_M;
}

/// How far apart a node and a surface may be when Rapier starts a contact between them (m).
pub const PREDICTION_DISTANCE_M: f32 = 0.005;

/// How deep Rapier lets a contact rest before its position correction pushes back (m).
pub const ALLOWED_LINEAR_ERROR_M: f32 = 0.001;

/// Rapier's length unit in scenes (m; Rapier's own default is 1 m). Besides the distances set
/// from it above, it sizes the margin by which Rapier's broad phase fattens every collider's
/// box (4 % of the unit): at 1 m, 4 cm around every node, so that each node that moves
/// beyond its margin is checked against every node within 4 cm (about 800 at 2.5 mm, 3,000 at
/// 1.25 mm), before the collision groups drop the pairs; at 1 cm the margin is 0.4 mm
/// (`docs/rapier.md`, "Cost at fine lattices").
pub const LENGTH_UNIT_M: f32 = 0.01;

/// Sets Rapier's length unit to `unit` (m) without changing any distance or speed it scales:
/// each normalised setting is rescaled by the old unit over the new one.
fn set_length_unit(p: &mut IntegrationParameters, unit: f32) {
    let scale = p.length_unit / unit;
    let rescale = |v: &mut Real| {
        if *v != Real::MAX {
            *v *= scale;
        }
    };
    rescale(&mut p.normalized_allowed_linear_error);
    rescale(&mut p.normalized_max_corrective_velocity);
    rescale(&mut p.normalized_prediction_distance);
    rescale(&mut p.normalized_max_linear_velocity);
    rescale(&mut p.normalized_contact_recycle_distance);
    p.length_unit = unit;
}
