//! Embedding KES cloth in your own Rapier world, with or without bevy_ecs.
//!
//! - [`ClothBuilder`] adds a cloth (fabric, shape, spacing, pose, pins, effects) to a
//!   `PhysicsWorld` you own. Scenes use the same builder.
//! - [`KesCloth`]: the plain-Rapier way. Each frame call [`KesCloth::step`] (our forces, then
//!   Rapier's step) or [`KesCloth::apply_forces`] before your own `world.step()`.
//! - [`install`] and [`spawn_cloth`]: the bevy_ecs way. Our systems go into your `Schedule`
//!   in the [`crate::schedule::Phase`] sets, so your systems can be ordered around them.

mod cloth_builder;
mod ecs_install;
mod kes_cloth;

pub use cloth_builder::{ClothBuilder, ClothOutline, ClothParts, Pin};
pub use ecs_install::{install, spawn_cloth};
pub use kes_cloth::KesCloth;
