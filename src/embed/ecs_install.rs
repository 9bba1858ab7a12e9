//! The bevy_ecs way in: our systems in your schedule, our cloth in your world.

use bevy_ecs::prelude::*;

use super::ClothParts;
use crate::schedule::{ClothEffects, ClothNodes, HostContacts, Implicit};

/// Adds kes-cloth's per-step systems to `schedule`, in the chained [`crate::schedule::Phase`]
/// sets (prepare → forces → step → measure → output). Order your own systems with
/// `.before(Phase::Forces)`, `.after(Phase::Step)` and so on. The world needs the resources
/// that [`crate::scene::spawn::insert_resources`] inserts (the Rapier world among them).
pub fn install(schedule: &mut Schedule) {
    crate::schedule::add_step_systems(schedule);
}

/// Spawns a built cloth as an entity: its state, its bodies, its effects (which the force
/// systems run), for an implicit cloth its solver, and [`HostContacts`]: the schedule then treats
/// your dynamic bodies' contacts with the cloth as [`super::KesCloth::step`] does (along the
/// sheet's normal, supported nodes immovable to them, their pushes handed to the cloth), so the
/// two ways in step the same cloth alike.
pub fn spawn_cloth(world: &mut World, parts: ClothParts) -> Entity {
    let e = spawn_scene_cloth(world, parts);
    world.entity_mut(e).insert(HostContacts::default());
    e
}

/// A scene's cloth: as [`spawn_cloth`], without [`HostContacts`] (a scene has no dynamic bodies
/// of its own to land on the cloth).
pub(crate) fn spawn_scene_cloth(world: &mut World, parts: ClothParts) -> Entity {
    let mut e = world.spawn((parts.state, ClothNodes(parts.bodies), ClothEffects(parts.effects)));
    if let Some(solver) = parts.implicit {
        e.insert(Implicit(solver));
    }
    e.id()
}
