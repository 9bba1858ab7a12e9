//! The Rapier settings a cloth needs from its host world.

use rapier3d::prelude::IntegrationParameters;

/// Sets the two Rapier parameters an embedded cloth needs to come to rest at the host's step
/// (`docs/rapier.md`, "Embedding at the host's step"), leaving the step and everything else
/// as the host has them:
///
/// - `num_solver_iterations = 1` (Rapier's default is 4 substeps) with
///   `num_internal_pgs_iterations = 4` sweeps: the cloth's velocity change reaches Rapier once
///   per step, and with 4 substeps a cloth draped over an edge keeps moving at 40–120 mm/s;
/// - `contact_recycling = false`: contacts recomputed every step, not reused while bodies move
///   little; the implicit solve reads which nodes rest on a support from them.
///
/// Neither alone is enough (thick cotton over a table edge, KES tensile law, implicit, 1/240 s:
/// 44–64 mm/s after 4 s with one of them, at rest by 0.7 s with both).
pub fn prepare_world(parameters: &mut IntegrationParameters) {
    parameters.num_solver_iterations = 1;
    parameters.num_internal_pgs_iterations = 4;
    parameters.contact_recycling = false;
}
