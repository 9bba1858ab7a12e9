//! The cloth entity's components and the world's resources.

use std::sync::Arc;

use bevy_ecs::prelude::*;
use glam::DVec3;
use rapier3d::prelude::PhysicsWorld;

use crate::bodies::ClothBodies;
use crate::forces::{ClothGeometry, ClothTopology, EffectKind, Effects, ForceBuffer};

/// The Rapier world (bodies, colliders, joints, pipeline), owned by the ECS world.
#[derive(Resource)]
pub struct Physics(pub PhysicsWorld);

/// One cloth's state mirrored out of Rapier each step, and its force accumulators.
#[derive(Component)]
pub struct ClothState {
    /// The woven grid.
    pub topology: Arc<ClothTopology>,
    /// Node positions (m), read from Rapier at the start of each step.
    pub positions: Vec<DVec3>,
    /// Node velocities (m/s), read with the positions.
    pub velocities: Vec<DVec3>,
    /// Node positions (m) one step earlier: how far each node moved over the latest step.
    pub previous_positions: Vec<DVec3>,
    /// Link directions and lengths of `positions`.
    pub geometry: ClothGeometry,
    /// This step's forces (N).
    pub forces: ForceBuffer,
}

impl ClothState {
    /// State buffers for `topology` at `positions` (m), at rest.
    pub fn new(topology: Arc<ClothTopology>, positions: Vec<DVec3>) -> Self {
        let mut geometry = ClothGeometry::new(topology.clone());
        geometry.update(&positions);
        Self {
            velocities: vec![DVec3::ZERO; positions.len()],
            previous_positions: positions.clone(),
            forces: ForceBuffer::new(&topology),
            topology,
            positions,
            geometry,
        }
    }
}

/// The Rapier bodies of a cloth.
#[derive(Component)]
pub struct ClothNodes(pub ClothBodies);

/// Present on a cloth whose forces are solved backward-Euler ([`crate::implicit`]); its system
/// runs only where this component exists.
#[derive(Component)]
pub struct Implicit(pub crate::implicit::ImplicitSolver);

/// Present on a cloth in a host's world, whose own dynamic bodies may land on it
/// ([`crate::embed::spawn_cloth`]; scenes have none): as [`crate::embed::KesCloth::step`] does,
/// the schedule then steps Rapier with [`crate::bodies::SheetContacts`] (a body's contacts with
/// nodes act along the sheet's normal), makes supported nodes immovable to the bodies
/// ([`crate::bodies::ClothBodies::back_supported_nodes`]) and hands the bodies' pushes back to
/// the cloth in the next step's forces.
#[derive(Component, Clone, Debug, Default)]
pub struct HostContacts {
    /// Force (N) on each node from the host's dynamic bodies over the latest step.
    pub loads: Vec<glam::DVec3>,
    /// Scratch space for the nodes' surface normals.
    pub normals: Vec<glam::DVec3>,
    /// The host's dynamic bodies solved with the cloth in the last step
    /// ([`crate::bodies::ClothBodies::read_carriers`]).
    pub carriers: crate::bodies::CarrierMemory,
}

/// The effects a cloth carries (see [`crate::forces::Effects`]): only these run.
#[derive(Component)]
pub struct ClothEffects(pub Effects);

/// Simulation time.
#[derive(Resource, Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Clock {
    /// Time step (s).
    pub dt: f64,
    /// Steps completed.
    pub step: u64,
    /// Simulated time (s).
    pub time: f64,
    /// Of `step`, those taken at the scene's step at rest (`integration.rest_dt_s`).
    #[serde(default)]
    pub rest_steps: u64,
    /// Whether the run has given up its step at rest (a quiet window undone while at it).
    #[serde(default)]
    pub rest_given_up: bool,
}

/// Calls and time spent per effect (for `metrics.json`).
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct EffectLedger {
    /// (effect name, calls, seconds), in a fixed order.
    pub entries: Vec<(&'static str, u64, f64)>,
}

/// Ledger entries besides the force generators': the implicit solve and Rapier's step.
const SOLVER_ENTRIES: [&str; 2] = ["implicit_solve", "rapier_step"];

impl EffectLedger {
    /// A ledger listing every effect ([`EffectKind::ALL`]), then the implicit solve and
    /// Rapier's step, with no calls: each appears in `metrics.json`, with 0 calls when the scene
    /// did not ask for it.
    pub fn with_all_effects() -> Self {
        let names = EffectKind::ALL.iter().map(|k| k.name()).chain(SOLVER_ENTRIES);
        Self {
            entries: names.map(|n| (n, 0, 0.0)).collect(),
        }
    }

    /// Records one call of `effect` that took `seconds`.
    pub fn record(&mut self, effect: &'static str, seconds: f64) {
        match self.entries.iter_mut().find(|e| e.0 == effect) {
            Some(e) => {
                e.1 += 1;
                e.2 += seconds;
            }
            None => self.entries.push((effect, 1, seconds)),
        }
    }

    /// Adds `seconds` to `effect`'s time without counting a call (work done for an effect outside
    /// its force system, e.g. advancing hysteresis state).
    pub fn add_seconds(&mut self, effect: &'static str, seconds: f64) {
        match self.entries.iter_mut().find(|e| e.0 == effect) {
            Some(e) => e.2 += seconds,
            None => self.entries.push((effect, 0, seconds)),
        }
    }

    /// Sets the totals of the effect named `effect` (a checkpoint's); unknown names are ignored.
    pub fn set(&mut self, effect: &str, calls: u64, seconds: f64) {
        if let Some(e) = self.entries.iter_mut().find(|e| e.0 == effect) {
            e.1 = calls;
            e.2 = seconds;
        }
    }

    /// (calls, seconds) of `effect`.
    pub fn get(&self, effect: &str) -> (u64, f64) {
        self.entries
            .iter()
            .find(|e| e.0 == effect)
            .map_or((0, 0.0), |e| (e.1, e.2))
    }
}

/// Why a run stopped early.
#[derive(Clone, Debug, PartialEq)]
pub struct SimulationFailure {
    /// Step at which it happened.
    pub step: u64,
    /// Simulated time (s).
    pub time: f64,
    /// The particle (node index).
    pub particle: usize,
    /// The effect that produced it (`rapier_step` for Rapier's own integration).
    pub effect: String,
    /// What went wrong and the likely cause.
    pub message: String,
}

/// Set by a system when the run must stop.
#[derive(Resource, Clone, Debug, Default, PartialEq)]
pub struct Failure(pub Option<SimulationFailure>);
