//! Systems of the prepare, forces and step phases.

use std::time::Instant;

use bevy_ecs::prelude::*;

use super::cloth_components::{
    Clock, ClothNodes, ClothState, Effect, EffectLedger, Failure, Implicit, Physics, SimulationFailure,
};
use crate::forces::{
    AirDrag, Bending, ForceGenerator, Hysteresis, KesTensile, LinkCompression, LinkDamping, SeedSeparation,
    Trellising,
};

/// Phase 1, prepare: update link geometry from the node state (read from Rapier at the end of
/// the previous step, or set at spawn), clear forces.
pub fn prepare_forces(mut cloths: Query<&mut ClothState>) {
    for mut state in &mut cloths {
        let state = &mut *state;
        state.geometry.update(&state.positions);
        state.forces.clear();
    }
}

/// End of phase 1, for effects with internal state (hysteresis): move that state to the
/// configuration the step starts from, before any force is taken.
pub fn advance_effect_state<G: ForceGenerator + 'static>(
    mut cloths: Query<(&ClothState, &mut Effect<G>)>,
    mut ledger: ResMut<EffectLedger>,
) {
    for (state, mut effect) in &mut cloths {
        let start = Instant::now();
        effect.0.advance_state(&state.geometry);
        ledger.add_seconds(effect.0.effect(), start.elapsed().as_secs_f64());
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

/// End of phase 2: sum link forces onto nodes; stop on a non-finite force.
pub fn sum_forces(clock: Res<Clock>, mut failure: ResMut<Failure>, mut cloths: Query<&mut ClothState>) {
    for mut state in &mut cloths {
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
        }
    }
}

/// Every effect a cloth entity may carry, as optional components.
type EffectComponents = (
    Option<&'static Effect<Bending>>,
    Option<&'static Effect<Trellising>>,
    Option<&'static Effect<SeedSeparation>>,
    Option<&'static Effect<KesTensile>>,
    Option<&'static Effect<LinkCompression>>,
    Option<&'static Effect<LinkDamping>>,
    Option<&'static Effect<AirDrag>>,
    Option<&'static Effect<Hysteresis>>,
);

/// Phase 2 (implicit cloths only): replace the summed forces by the backward-Euler force
/// M·Δv/h (see [`crate::implicit`]).
pub fn solve_implicit(
    physics: Res<Physics>,
    clock: Res<Clock>,
    mut failure: ResMut<Failure>,
    mut ledger: ResMut<EffectLedger>,
    mut cloths: Query<(&mut ClothState, &mut Implicit, &ClothNodes, EffectComponents)>,
) {
    if failure.0.is_some() {
        return;
    }
    for (mut state, mut implicit, nodes, (b, t, ss, sk, c, d, a, h)) in &mut cloths {
        let start = Instant::now();
        let solver = &mut implicit.0;
        nodes.0.read_supports(&physics.0, &mut solver.supports);
        let state = &mut *state;
        let generators = [
            b.map(|e| &e.0 as &dyn ForceGenerator),
            t.map(|e| &e.0 as &dyn ForceGenerator),
            ss.map(|e| &e.0 as &dyn ForceGenerator),
            sk.map(|e| &e.0 as &dyn ForceGenerator),
            c.map(|e| &e.0 as &dyn ForceGenerator),
            d.map(|e| &e.0 as &dyn ForceGenerator),
            a.map(|e| &e.0 as &dyn ForceGenerator),
            h.map(|e| &e.0 as &dyn ForceGenerator),
        ];
        let forces = &mut state.forces.particle;
        let gravity = nodes.0.gravity(&physics.0);
        implicit.0.solve(
            &generators,
            &state.geometry,
            &state.velocities,
            forces,
            (clock.dt, gravity),
        );
        ledger.record("implicit_solve", start.elapsed().as_secs_f64());
        if let Some(i) = forces.iter().position(|f| !f.is_finite()) {
            failure.0 = Some(SimulationFailure {
                step: clock.step,
                time: clock.time,
                particle: i,
                effect: String::from("implicit_solve"),
                message: format!(
                    "non-finite velocity change (force {:?} N) from the implicit solve: a stiffness \
                     product or the solve produced NaN",
                    forces[i]
                ),
            });
            return;
        }
    }
}

/// End of phase 2: hand each cloth's node forces to Rapier (unless the run is failing).
pub fn push_forces(
    mut physics: ResMut<Physics>,
    failure: Res<Failure>,
    cloths: Query<(&ClothNodes, &ClothState)>,
) {
    if failure.0.is_some() {
        return;
    }
    for (nodes, state) in &cloths {
        nodes.0.write_forces(&mut physics.0, &state.forces.particle);
    }
}

/// Phase 3, step: Rapier integrates gravity, joints, contact and friction (our forces' kick is
/// already in the node velocities).
pub fn step_rapier(mut physics: ResMut<Physics>, mut clock: ResMut<Clock>, mut ledger: ResMut<EffectLedger>) {
    let start = Instant::now();
    physics.0.step();
    ledger.record("rapier_step", start.elapsed().as_secs_f64());
    clock.step += 1;
    clock.time = clock.step as f64 * clock.dt;
}
