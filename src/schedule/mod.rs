//! The bevy_ecs schedule that advances a scene by one step.
//!
//! One run of the schedule is one time step, in five chained phases:
//!
//! 1. [`Phase::Prepare`]: update the link geometry from the node state, clear the force
//!    buffers, then move effect state (hysteresis slips) to that geometry.
//! 2. [`Phase::Forces`]: each effect the cloth carries ([`ClothEffects`], built from the one
//!    list of effects, [`crate::forces::EffectKind`]) adds its forces; an effect the scene did
//!    not ask for is not in that list and never runs. Then the link forces are summed onto
//!    nodes; for a cloth with the
//!    [`Implicit`] component they are replaced by the backward-Euler force ([`crate::implicit`]);
//!    then they are handed to Rapier as one velocity kick per node. A cloth in a host's world
//!    ([`HostContacts`]) first takes the host's bodies' pushes of the last step.
//! 3. [`Phase::Step`]: Rapier's step (gravity, joints, contact, friction; with
//!    [`crate::bodies::SheetContacts`] when a cloth carries [`HostContacts`]).
//! 4. [`Phase::Measure`]: read node positions and velocities out of Rapier, hold an implicit
//!    cloth's links within the strain limit (a last resort for a step too long for the
//!    lattice, [`crate::implicit::limit_strain`]), the finite-value and runaway guards,
//!    motion statistics, the host's bodies' pushes on the nodes, the settle criterion.
//! 5. [`Phase::Output`]: progress reporting (only when a [`Progress`] resource exists).
//!
//! Systems run on a single thread in this order, with ambiguity detection set to error: two
//! unordered writers of one resource would fail to build rather than race.

mod cloth_components;
mod force_systems;
mod measure_systems;

use bevy_ecs::prelude::*;
use bevy_ecs::schedule::{LogLevel, ScheduleBuildSettings};

pub use cloth_components::{
    Clock, ClothEffects, ClothNodes, ClothState, EffectLedger, Failure, HostContacts, Implicit, Physics,
    SimulationFailure,
};
pub use force_systems::{
    add_body_loads, advance_effect_states, apply_effects, prepare_forces, push_forces, solve_implicit,
    step_rapier, sum_forces,
};
pub use measure_systems::{measure_motion, read_body_loads, report_progress, update_settle};

use crate::measure::Progress;

/// The phases of one step, run in this order.
#[derive(SystemSet, Debug, Clone, Copy, PartialEq, Eq, Hash)]
pub enum Phase {
    /// 1. Read state from Rapier, clear forces.
    Prepare,
    /// 2. Our force generators, each gated by its effect.
    Forces,
    /// 3. Rapier's step.
    Step,
    /// 4. Measurements and guards.
    Measure,
    /// 5. Progress and other per-step output.
    Output,
}

/// Builds the step schedule. The force systems run each cloth's own effects; the implicit solve
/// runs only where an [`Implicit`] component exists, progress only with a [`Progress`] resource.
pub fn build_step_schedule() -> Schedule {
    let mut schedule = Schedule::default();
    schedule.set_build_settings(ScheduleBuildSettings {
        ambiguity_detection: LogLevel::Error,
        ..Default::default()
    });
    add_step_systems(&mut schedule);
    schedule
}

/// Adds the phases and every per-step system to an existing schedule (the bevy_ecs way in:
/// see [`crate::embed::install`]).
pub fn add_step_systems(schedule: &mut Schedule) {
    schedule.configure_sets(
        (
            Phase::Prepare,
            Phase::Forces,
            Phase::Step,
            Phase::Measure,
            Phase::Output,
        )
            .chain(),
    );
    schedule.add_systems(
        (prepare_forces, advance_effect_states)
            .chain()
            .in_set(Phase::Prepare),
    );
    schedule.add_systems(
        (
            apply_effects,
            sum_forces,
            add_body_loads.run_if(any_with_component::<HostContacts>),
            solve_implicit.run_if(any_with_component::<Implicit>),
            push_forces,
        )
            .chain()
            .in_set(Phase::Forces),
    );
    schedule.add_systems(step_rapier.in_set(Phase::Step));
    schedule.add_systems(
        (
            measure_motion,
            read_body_loads.run_if(any_with_component::<HostContacts>),
            update_settle,
        )
            .chain()
            .in_set(Phase::Measure),
    );
    schedule.add_systems(
        report_progress
            .run_if(resource_exists::<Progress>)
            .in_set(Phase::Output),
    );
}
