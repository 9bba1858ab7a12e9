//! Embedding KES cloth in your own Rapier world, with or without bevy_ecs.
//!
//! - [`ClothBuilder`] adds a cloth (fabric, shape, spacing, pose, pins, effects) to a
//!   `PhysicsWorld` you own. Scenes use the same builder.
//!   It integrates implicitly when the world's step is beyond what the fabric's explicit forces
//!   take, and refuses explicit forces asked for at such a step ([`BuildError`]).
//! - [`KesCloth`]: the plain-Rapier way. Each frame call [`KesCloth::step`] (our forces, then
//!   Rapier's step) or [`KesCloth::apply_forces`], your own
//!   `world.step_with_events(&SheetContacts, &())` and [`KesCloth::after_step`]; a diverging
//!   cloth is a [`StepError`] naming step, node and effect. [`SheetContacts`] makes your dynamic
//!   bodies meet the cloth's surface, not its node balls (`docs/rapier.md`).
//! - [`prepare_world`]: the two Rapier parameters (one substep, no contact recycling) a cloth
//!   needs to come to rest at the host's step.
//! - [`install`] and [`spawn_cloth`]: the bevy_ecs way. Our systems go into your `Schedule`
//!   in the [`crate::schedule::Phase`] sets, so your systems can be ordered around them.

mod build_error;
mod cloth_builder;
mod ecs_install;
mod host_world;
mod kes_cloth;
mod outline_areas;
mod smooth_roughness;
mod step_error;

pub use crate::bodies::SheetContacts;
pub use build_error::BuildError;
pub use cloth_builder::{ClothBuilder, ClothOutline, ClothParts, LOWEST_CLEARANCE, Pin};
pub(crate) use ecs_install::spawn_scene_cloth;
pub use ecs_install::{install, spawn_cloth};
pub use host_world::prepare_world;
pub use kes_cloth::KesCloth;
pub use smooth_roughness::{MAX_SMOOTH_AMPLITUDE_M, Roughness, SmoothRoughness};
pub use step_error::StepError;
