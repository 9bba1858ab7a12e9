//! The bevy_ecs way in: our systems in your schedule, our cloth in your world.

use bevy_ecs::prelude::*;

use super::ClothParts;
use crate::forces::ForceGenerator;
use crate::schedule::{ClothNodes, Effect, Implicit};

/// Adds kes-cloth's per-step systems to `schedule`, in the chained [`crate::schedule::Phase`]
/// sets (prepare → forces → step → measure → output). Order your own systems with
/// `.before(Phase::Forces)`, `.after(Phase::Step)` and so on. The world needs the resources
/// that [`crate::scene::spawn::insert_resources`] inserts (the Rapier world among them).
pub fn install(schedule: &mut Schedule) {
    crate::schedule::add_step_systems(schedule);
}

/// Spawns a built cloth as an entity: its state, its bodies, and one [`Effect`] component per
/// effect it asked for (which is what lets that effect's system run).
pub fn spawn_cloth(world: &mut World, parts: ClothParts) -> Entity {
    let mut e = world.spawn((parts.state, ClothNodes(parts.bodies)));
    insert_effect(&mut e, parts.bending);
    insert_effect(&mut e, parts.trellising);
    insert_effect(&mut e, parts.stretch_seed);
    insert_effect(&mut e, parts.stretch_kes);
    insert_effect(&mut e, parts.compression);
    insert_effect(&mut e, parts.damping);
    insert_effect(&mut e, parts.air_drag);
    insert_effect(&mut e, parts.hysteresis);
    if let Some(solver) = parts.implicit {
        e.insert(Implicit(solver));
    }
    e.id()
}

fn insert_effect<G: ForceGenerator + 'static>(e: &mut EntityWorldMut, generator: Option<G>) {
    if let Some(g) = generator {
        e.insert(Effect(g));
    }
}
