//! The bevy_ecs way in: our systems in your schedule, our cloth in your world.

use bevy_ecs::prelude::*;

use super::ClothParts;
use crate::schedule::{ClothEffects, ClothNodes, Implicit};

/// Adds kes-cloth's per-step systems to `schedule`, in the chained [`crate::schedule::Phase`]
/// sets (prepare → forces → step → measure → output). Order your own systems with
/// `.before(Phase::Forces)`, `.after(Phase::Step)` and so on. The world needs the resources
/// that [`crate::scene::spawn::insert_resources`] inserts (the Rapier world among them).
pub fn install(schedule: &mut Schedule) {
    crate::schedule::add_step_systems(schedule);
}

/// Spawns a built cloth as an entity: its state, its bodies, its effects (which the force
/// systems run) and, for an implicit cloth, its solver.
pub fn spawn_cloth(world: &mut World, parts: ClothParts) -> Entity {
    let mut e = world.spawn((parts.state, ClothNodes(parts.bodies), ClothEffects(parts.effects)));
    if let Some(solver) = parts.implicit {
        e.insert(Implicit(solver));
    }
    e.id()
}
