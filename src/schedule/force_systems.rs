//! Systems of the prepare, forces and step phases.

use std::time::Instant;

use bevy_ecs::prelude::*;

use super::cloth_components::{
    Clock, ClothNodes, ClothState, Effect, EffectLedger, Failure, Physics, SimulationFailure,
};
use crate::forces::ForceGenerator;

/// Phase 1, prepare: update link geometry from the node state (read from Rapier at the end of
/// the previous step, or set at spawn), clear forces.
pub fn prepare_forces(mut cloths: Query<&mut ClothState>) {
    for mut state in &mut cloths {
        let state = &mut *state;
        state.geometry.update(&state.positions);
        state.forces.clear();
    }
}

/// Phase 2, forces: one instance per effect, e.g. `apply_effect::<Bending>`.
pub fn apply_effect<G: ForceGenerator + 'static>(
    mut cloths: Query<(&mut ClothState, &Effect<G>)>,
    mut ledger: ResMut<EffectLedger>,
) {
    for (mut state, effect) in &mut cloths {
        let start = Instant::now();
        let state = &mut *state;
        effect
            .0
            .add_forces(&state.geometry, &state.velocities, &mut state.forces);
        ledger.record(effect.0.effect(), start.elapsed().as_secs_f64());
    }
}

/// End of phase 2: sum link forces onto nodes, stop on a non-finite force, hand them to Rapier.
pub fn push_forces(
    mut physics: ResMut<Physics>,
    clock: Res<Clock>,
    mut failure: ResMut<Failure>,
    mut cloths: Query<(&ClothNodes, &mut ClothState)>,
) {
    for (nodes, mut state) in &mut cloths {
        let state = &mut *state;
        let forces = state.forces.resolve(&state.topology);
        if let Some(i) = forces.iter().position(|f| !f.is_finite()) {
            failure.0 = Some(SimulationFailure {
                step: clock.step,
                time: clock.time,
                particle: i,
                // The run loop re-evaluates each effect to name the one at fault.
                effect: String::from("(forces)"),
                message: format!("non-finite force {:?} N", forces[i]),
            });
            return;
        }
        nodes.0.write_forces(&mut physics.0, forces);
    }
}

/// Phase 3, step: Rapier integrates gravity, our forces, joints, contact and friction.
pub fn step_rapier(mut physics: ResMut<Physics>, mut clock: ResMut<Clock>, mut ledger: ResMut<EffectLedger>) {
    let start = Instant::now();
    physics.0.step();
    ledger.record("rapier_step", start.elapsed().as_secs_f64());
    clock.step += 1;
    clock.time = clock.step as f64 * clock.dt;
}
