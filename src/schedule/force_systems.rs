//! Systems of the prepare, forces and step phases.

use std::time::Instant;

use bevy_ecs::prelude::*;

use super::cloth_components::{
    Clock, ClothEffects, ClothNodes, ClothState, EffectLedger, Failure, HostContacts, Implicit, Physics,
    SimulationFailure,
};
use crate::bodies::SheetContacts;

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
pub fn advance_effect_states(
    mut cloths: Query<(&ClothState, &mut ClothEffects)>,
    mut ledger: ResMut<EffectLedger>,
) {
    for (state, mut effects) in &mut cloths {
        for g in effects.0.iter_mut() {
            let start = Instant::now();
            g.advance_state(&state.geometry);
            ledger.add_seconds(g.effect(), start.elapsed().as_secs_f64());
        }
    }
}

/// Phase 2, forces: each effect the cloth carries adds its forces, in the registry's order
/// ([`crate::forces::EffectKind::ALL`]); each call is timed into the ledger.
pub fn apply_effects(mut cloths: Query<(&mut ClothState, &ClothEffects)>, mut ledger: ResMut<EffectLedger>) {
    for (mut state, effects) in &mut cloths {
        let state = &mut *state;
        for g in effects.0.iter() {
            let start = Instant::now();
            g.add_forces(&state.geometry, &state.velocities, &mut state.forces);
            ledger.record(g.effect(), start.elapsed().as_secs_f64());
        }
    }
}

/// End of phase 2: sum link forces onto nodes; stop on a non-finite force.
pub fn sum_forces(clock: Res<Clock>, mut failure: ResMut<Failure>, mut cloths: Query<&mut ClothState>) {
    for mut state in &mut cloths {
        let state = &mut *state;
        let forces = state.forces.resolve(&state.topology);
        if let Some(i) = crate::measure::non_finite_force(forces) {
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

/// End of phase 2's sums (cloths in a host's world only): add the force each node received from
/// the host's dynamic bodies over the last step.
pub fn add_body_loads(mut cloths: Query<(&mut ClothState, &HostContacts)>) {
    for (mut state, host) in &mut cloths {
        for (f, load) in state.forces.particle.iter_mut().zip(&host.loads) {
            *f += *load;
        }
    }
}

/// Phase 2 (implicit cloths only): replace the summed forces by the backward-Euler force
/// M·Δv/h (see [`crate::implicit`]).
pub fn solve_implicit(
    mut physics: ResMut<Physics>,
    clock: Res<Clock>,
    mut failure: ResMut<Failure>,
    mut ledger: ResMut<EffectLedger>,
    mut cloths: Query<(
        &mut ClothState,
        &mut Implicit,
        &ClothNodes,
        &ClothEffects,
        Option<&mut HostContacts>,
    )>,
) {
    if failure.0.is_some() {
        return;
    }
    for (mut state, mut implicit, nodes, effects, host) in &mut cloths {
        let start = Instant::now();
        let solver = &mut implicit.0;
        nodes.0.read_supports(&physics.0, &mut solver.supports);
        let links = &state.topology.links;
        nodes
            .0
            .read_link_supports(&physics.0, links, &state.positions, &mut solver.supports);
        if host.is_some() {
            nodes.0.back_supported_nodes(&mut physics.0, &solver.supports);
        }
        nodes
            .0
            .read_pin_velocities(&physics.0, clock.dt, &mut solver.pin_velocities);
        if let Some(mut host) = host {
            nodes.0.read_carriers(&physics.0, solver, &mut host.carriers);
        }
        let state = &mut *state;
        let generators: Vec<_> = effects.0.iter().map(Some).collect();
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
        if let Some(i) = crate::measure::non_finite_force(forces) {
            failure.0 = Some(SimulationFailure {
                step: clock.step,
                time: clock.time,
                particle: i,
                effect: String::from("implicit_solve"),
                message: crate::measure::non_finite_solve_message(forces[i]),
            });
            return;
        }
    }
}

/// End of phase 2: hand each cloth's node forces to Rapier (unless the run is failing).
/// For a cloth in a host's world, also write its surface normals for [`SheetContacts`].
pub fn push_forces(
    mut physics: ResMut<Physics>,
    failure: Res<Failure>,
    mut cloths: Query<(
        &ClothNodes,
        &ClothState,
        Option<&mut HostContacts>,
        Option<&Implicit>,
    )>,
) {
    if failure.0.is_some() {
        return;
    }
    for (nodes, state, host, implicit) in &mut cloths {
        nodes.0.write_forces(&mut physics.0, &state.forces.particle);
        if let Some(mut host) = host {
            if let Some(implicit) = implicit {
                nodes
                    .0
                    .move_carriers(&mut physics.0, &implicit.0.carriers, &host.carriers);
            }
            nodes.0.write_sheet_normals(
                &mut physics.0,
                &state.topology,
                &state.positions,
                &mut host.normals,
            );
        }
    }
}

/// Phase 3, step: Rapier integrates gravity, joints, contact and friction (our forces' kick is
/// already in the node velocities); with [`SheetContacts`] when a cloth is in a host's world.
pub fn step_rapier(
    mut physics: ResMut<Physics>,
    mut clock: ResMut<Clock>,
    mut ledger: ResMut<EffectLedger>,
    host: Query<(), With<HostContacts>>,
) {
    let start = Instant::now();
    if host.is_empty() {
        physics.0.step();
    } else {
        physics.0.step_with_events(&SheetContacts, &());
    }
    ledger.record("rapier_step", start.elapsed().as_secs_f64());
    clock.step += 1;
    clock.time += clock.dt;
}
