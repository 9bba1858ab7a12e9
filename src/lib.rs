//! # kes-cloth
//!
//! Woven cloth simulated from Kawabata (KES-F) measurements, after the particle model of
//! Horiba & Shimizu (after Breen et al.).
//!
//! Data flows one way:
//!
//! ```text
//!  assets/fabrics/*.ron ──► material::KesFabric ──► material::Fabric (SI) ──┐
//!  (KES units)              (schema)        kes_units: the one conversion     │
//!                                                                            ▼
//!  grid of crossings ──► forces::ClothTopology ──► forces::{Bending, Trellising,
//!                                                   SeedSeparation, KesTensile}
//!                        positions ──► forces::ClothGeometry ──► forces (N) per particle
//! ```
//!
//! A scene then runs step by step:
//!
//! ```text
//!  scenes/*.ron ──► scene::Scene ──► embed::ClothBuilder ──► Rapier bodies + joints (bodies)
//!                                                   └──► cloth entity with its ClothEffects
//!  each step (schedule::Phase): prepare ─► forces (each effect the cloth carries) ─► Rapier step
//!                               ─► measure (motion, settle, finite guard) ─► output (progress)
//!  at rest: the scene's declared `measure` (drape, tablecloth) ─► output (metrics.json, ...)
//! ```
//!
//! ## Three ways in
//! 1. **A scene file**: `kes-cloth run scenes/drape_wool.ron`, or [`run::simulate`] on a
//!    [`scene::Scene`].
//! 2. **Your bevy_ecs world**: [`embed::install`] adds our systems to your `Schedule` in the
//!    [`schedule::Phase`] sets; [`embed::spawn_cloth`] spawns a cloth built by
//!    [`embed::ClothBuilder::build_parts`]; [`scene::spawn::insert_resources`] adds the resources
//!    (your Rapier world among them). See `examples/embed_ecs.rs`.
//! 3. **A plain Rapier loop**: [`embed::ClothBuilder::build`] adds a cloth to your
//!    `PhysicsWorld` and returns an [`embed::KesCloth`]; call [`embed::KesCloth::step`] each
//!    frame (or [`embed::KesCloth::apply_forces`], your own `world.step()`, then
//!    [`embed::KesCloth::after_step`]). A diverging cloth is an [`embed::StepError`] naming step,
//!    node and effect. See `examples/embed_rapier.rs`, `examples/flag.rs`,
//!    `examples/custom_fabric.rs`.
//!
//! The world's step decides the integrator: our forces are explicit (symplectic Euler at any
//! `num_solver_iterations`) where the fabric's stability limit allows the step, and
//! [`implicit::Integrator::Implicit`] (stable at any step) beyond it, unless you choose;
//! explicit forces asked for at a step they cannot take are refused
//! ([`embed::BuildError`]). At the host's own step (1/60 s) call [`embed::prepare_world`]
//! (`docs/rapier.md`, "Embedding at the host's step").
//!
//! ## Modules
//! - [`material`]: KES data, its conversion to SI, the elastic curves.
//! - [`forces`]: one force generator per effect, behind [`forces::ForceGenerator`].
//! - [`implicit`]: the linearly implicit (backward Euler) solve of those forces.
//! - [`scene`]: the RON schema, validation, `--set`, spawning.
//! - [`schedule`]: the step's phases and systems.
//! - [`bodies`]: cloth nodes as Rapier bodies (the one place that knows how).
//! - [`embed`]: the builder, the plain-Rapier cloth and the bevy_ecs installer.
//! - [`measure`], [`output`], [`run`], [`repeat`]: measurements, files, running, repeats.
//! - [`study`]: work–precision and convergence studies across settings.
//! - [`batch`]: a study as task files, run by any scheduler, and collected.
//!
//! All quantities are SI (N, m, kg, s, rad) unless a name or doc says otherwise.

#![forbid(unsafe_code)]
#![warn(missing_docs)]

pub mod batch;
pub mod bodies;
pub mod checkpoint;
pub mod embed;
pub mod forces;
pub mod implicit;
pub mod kes_lab;
pub mod material;
pub mod measure;
pub mod output;
pub mod repeat;
mod ron_file;
pub mod run;
pub mod scene;
pub mod schedule;
pub mod study;

pub use ron_file::RonError;
