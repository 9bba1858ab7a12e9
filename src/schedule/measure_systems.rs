//! Systems of the measure and output phases: what a step did to the cloth.

use bevy_ecs::prelude::*;

use super::cloth_components::{
    Clock, ClothNodes, ClothState, Failure, HostContacts, Implicit, Physics, SimulationFailure,
};
use crate::measure::{
    Motion, MovingColliders, Progress, SettleState, WorldColliders, is_runaway, max_penetration,
    non_finite_state, non_finite_state_message, runaway_message,
};

/// Phase 4 (cloths in a host's world only): the force each node received from the host's
/// dynamic bodies over the step, for the next step's forces.
pub fn read_body_loads(
    physics: Res<Physics>,
    clock: Res<Clock>,
    mut cloths: Query<(&ClothNodes, &mut HostContacts)>,
) {
    for (nodes, mut host) in &mut cloths {
        nodes.0.read_body_loads(&physics.0, clock.dt, &mut host.loads);
    }
}

/// Phase 4: reads the stepped state, brings an implicit cloth's links within the strain limit
/// (a last resort, [`crate::implicit::limit_strain`]), stops on a non-finite value or a
/// runaway, updates [`Motion`].
pub fn measure_motion(
    mut physics: ResMut<Physics>,
    clock: Res<Clock>,
    mut motion: ResMut<Motion>,
    mut failure: ResMut<Failure>,
    mut colliders: Option<ResMut<WorldColliders>>,
    moving: Option<Res<MovingColliders>>,
    mut cloths: Query<(&ClothNodes, &mut ClothState, Option<&Implicit>)>,
) {
    for (nodes, mut state, solver) in &mut cloths {
        let implicit = solver.is_some();
        let state = &mut *state;
        std::mem::swap(&mut state.positions, &mut state.previous_positions);
        nodes
            .0
            .read(&physics.0, &mut state.positions, &mut state.velocities);
        // An implicit cloth's links are held within the strain limit (implicit/strain_limit.rs).
        let limited = solver.map_or(0, |solver| {
            nodes.0.limit_strain(
                &mut physics.0,
                (&state.topology, solver.0.held()),
                &mut state.positions,
                &mut state.velocities,
            )
        });
        if let Some(i) = non_finite_state(&state.positions, &state.velocities) {
            failure.0 = Some(SimulationFailure {
                step: clock.step,
                time: clock.time,
                particle: i,
                effect: "rapier_step".into(),
                message: non_finite_state_message(state.positions[i], state.velocities[i], clock.dt),
            });
            return;
        }
        let (peak, peak_penetration) = (motion.peak_strain, motion.peak_penetration);
        let limited_steps = motion.strain_limited_steps + u64::from(limited > 0);
        let now = Motion::of(
            &state.topology,
            &nodes.0.masses,
            (&state.positions, &state.previous_positions, &state.velocities),
            clock.dt,
        );
        if is_runaway(&now) {
            failure.0 = Some(SimulationFailure {
                step: clock.step,
                time: clock.time,
                particle: now.fastest_node,
                // The run loop names the effect pushing hardest on this node.
                effect: String::from("(runaway)"),
                message: runaway_message(
                    &now,
                    implicit,
                    !nodes.0.joints.is_empty(),
                    (clock.dt, state.topology.spacing),
                ),
            });
            return;
        }
        *motion = now;
        motion.peak_strain = peak.max(motion.max_strain);
        motion.strain_limited_steps = limited_steps;
        if let (Some(colliders), Some(moving)) = (colliders.as_mut(), moving.as_ref()) {
            for &(k, body) in &moving.0 {
                if let (Some(b), Some(entry)) = (physics.0.bodies.get(body), colliders.0.get_mut(k)) {
                    entry.1 = b.translation().as_dvec3();
                }
            }
        }
        let depth = colliders
            .as_ref()
            .map_or(0.0, |c| max_penetration(&c.0, &state.positions).0);
        motion.peak_penetration = peak_penetration.max(depth);
    }
}

/// Phase 4: updates the settle criterion from the cloth's positions.
pub fn update_settle(clock: Res<Clock>, cloths: Query<&ClothState>, mut settle: ResMut<SettleState>) {
    for state in &cloths {
        settle.observe(clock.time, &state.positions);
    }
}

/// Phase 5: shows simulated time, fastest node and strain.
pub fn report_progress(clock: Res<Clock>, motion: Res<Motion>, progress: Res<Progress>) {
    progress.show(clock.step, clock.time, &motion);
}
