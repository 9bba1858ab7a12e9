//! Checkpoints: the whole state of a running scene in one file, so that a run stopped (Ctrl-C, a
//! crash, a time limit) resumes from its last checkpoint and ends exactly, bit for bit, where the
//! uninterrupted run ends.
//!
//! A checkpoint holds the resolved scene (the fabric is read again from its file on resume and
//! must be the one the run started with),
//! Rapier's world as Rapier serialises it (bodies, colliders, joints, contact manifolds with their
//! warm-start impulses, islands; the pipelines are workspaces Rapier rebuilds), and every piece of
//! kes-cloth state that carries from one step to the next: the clock, the node state, the
//! effects' own state (hysteresis slips), the implicit solve's warm start, release-rule and
//! friction memory and totals, the settle tracker, the creep watch, the motion statistics and
//! the per-effect call counts. It is written as CBOR (exact for every f32 and f64,
//! NaN included) to a temporary file and renamed over `checkpoint.cbor`, so a run killed while
//! writing keeps the previous checkpoint.

mod checkpoint_error;

use std::path::{Path, PathBuf};

use bevy_ecs::prelude::*;
use glam::DVec3;
use rapier3d::prelude::PhysicsWorld;
use serde::{Deserialize, Serialize};

pub use checkpoint_error::CheckpointError;

use crate::forces::EffectStates;
use crate::implicit::{Bdf2History, ImplicitStats};
use crate::measure::{CreepWatch, Motion, MovingColliders, SettleState, WorldColliders};
use crate::scene::{Scene, SceneFile};
use crate::schedule::{Clock, ClothEffects, ClothState, EffectLedger, Implicit, Physics};

/// The file a checkpoint is written to, inside a run's output folder.
pub const CHECKPOINT_FILE: &str = "checkpoint.cbor";

/// Format version; a checkpoint of another version is refused.
const FORMAT: u32 = 2;

/// The implicit solve's state that carries from step to step.
#[derive(Serialize, Deserialize)]
struct ImplicitState {
    /// Last step's velocity change per node (m/s): the next solve's warm start.
    warm_start: Vec<DVec3>,
    /// Running totals of the solves.
    stats: ImplicitStats,
    /// Per node: the support pushed in the last solve (the release rule's memory).
    pressed: Vec<bool>,
    /// Per node: the last friction impulse of a sliding node (N·s; 0 where not sliding).
    sliding: Vec<f64>,
    /// The system step h' (s) those impulses were taken over (0: unknown).
    #[serde(default)]
    sliding_step_s: f64,
    /// BDF2's lag and previous velocities (absent with backward Euler or before its first step).
    #[serde(default)]
    bdf2: Option<Bdf2History>,
    /// Per node: a hold that gave way in the last solve, sliding from the next step
    /// (`FrictionRelease::NextStep`; empty for none).
    #[serde(default)]
    releases_due: Vec<bool>,
    /// Where static friction holds each link an edge presses (link, material point 0–1, anchor
    /// in m; `implicit::LinkAnchors`; empty without link support).
    #[serde(default)]
    link_anchors: Vec<(usize, f64, DVec3)>,
}

/// Everything needed to continue a run.
#[derive(Serialize, Deserialize)]
pub struct Snapshot {
    format: u32,
    /// The scene file the run came from (fabric paths resolve against it).
    pub scene_path: PathBuf,
    /// The scene as run, overrides applied.
    pub scene: SceneFile,
    /// The fabric as loaded when the run started (its `Debug` form): a resume whose fabric file
    /// has changed since is refused.
    pub fabric: String,
    /// Checkpoint interval of the run (simulated s), kept on resume.
    pub every_s: Option<f64>,
    /// Wall-clock time the run had used (s).
    pub wall_time_s: f64,
    clock: Clock,
    physics: PhysicsWorld,
    positions: Vec<DVec3>,
    velocities: Vec<DVec3>,
    effects: EffectStates,
    implicit: Option<ImplicitState>,
    settle: SettleState,
    motion: Motion,
    effect_calls: Vec<(String, u64, f64)>,
    creep: Option<CreepWatch>,
}

impl Snapshot {
    /// Captures the state of `world` with its cloth entity `cloth`.
    pub fn capture(
        world: &World,
        cloth: Entity,
        scene: &Scene,
        every_s: Option<f64>,
        wall_time_s: f64,
    ) -> Result<Self, CheckpointError> {
        let state = world
            .get::<ClothState>(cloth)
            .ok_or(CheckpointError::Missing("cloth state"))?;
        let ledger = world.resource::<EffectLedger>();
        Ok(Self {
            format: FORMAT,
            // Absolute, so that `resume` works from any working directory.
            scene_path: std::fs::canonicalize(&scene.path).unwrap_or_else(|_| scene.path.clone()),
            scene: scene.spec.clone(),
            fabric: format!("{:?}", scene.fabric),
            every_s,
            wall_time_s,
            clock: *world.resource::<Clock>(),
            physics: clone_physics(&world.resource::<Physics>().0)?,
            positions: state.positions.clone(),
            velocities: state.velocities.clone(),
            effects: world
                .get::<ClothEffects>(cloth)
                .map(|e| e.0.states())
                .unwrap_or_default(),
            implicit: world.get::<Implicit>(cloth).map(|i| ImplicitState {
                warm_start: i.0.warm_start().to_vec(),
                stats: i.0.stats,
                pressed: i.0.pressed().to_vec(),
                sliding: i.0.sliding_impulses().0.to_vec(),
                sliding_step_s: i.0.sliding_impulses().1,
                bdf2: i.0.bdf2_history().cloned(),
                releases_due: i.0.releases_due().to_vec(),
                link_anchors: {
                    let mut anchors: Vec<_> =
                        i.0.supports
                            .anchors
                            .iter()
                            .map(|(l, (t, a))| (*l, *t, *a))
                            .collect();
                    anchors.sort_by_key(|(l, _, _)| *l);
                    anchors
                },
            }),
            settle: world.resource::<SettleState>().clone(),
            motion: *world.resource::<Motion>(),
            effect_calls: ledger
                .entries
                .iter()
                .map(|&(name, calls, seconds)| (name.to_string(), calls, seconds))
                .collect(),
            creep: world.get_resource::<CreepWatch>().cloned(),
        })
    }

    /// The step the snapshot was taken after.
    pub fn step(&self) -> u64 {
        self.clock.step
    }

    /// Puts the snapshot's state into `world`, freshly spawned from the same scene.
    pub fn restore(self, world: &mut World, cloth: Entity) -> Result<(), CheckpointError> {
        let mismatch = CheckpointError::Mismatch;
        {
            let mut state = world
                .get_mut::<ClothState>(cloth)
                .ok_or(CheckpointError::Missing("cloth state"))?;
            let n = state.positions.len();
            if self.positions.len() != n || self.velocities.len() != n {
                return Err(mismatch("node count"));
            }
            state.previous_positions = self.positions.clone();
            state.positions = self.positions;
            state.velocities = self.velocities;
        }
        let restored = world
            .get_mut::<ClothEffects>(cloth)
            .is_some_and(|mut e| e.0.restore_states(&self.effects));
        if !restored {
            return Err(mismatch("effect state (hysteresis)"));
        }
        let restored = match (world.get_mut::<Implicit>(cloth), &self.implicit) {
            (Some(mut i), Some(s)) => {
                i.0.stats = s.stats;
                i.0.supports.anchors = s.link_anchors.iter().map(|&(l, t, a)| (l, (t, a))).collect();
                i.0.restore_warm_start(&s.warm_start)
                    && i.0.restore_pressed(&s.pressed)
                    && i.0.restore_sliding_impulses(&s.sliding, s.sliding_step_s)
                    && i.0.restore_bdf2_history(s.bdf2.clone())
                    && i.0.restore_releases_due(&s.releases_due)
            }
            (i, s) => i.is_none() && s.is_none(),
        };
        if !restored {
            return Err(mismatch("implicit solver state"));
        }
        world.resource_mut::<Physics>().0 = self.physics;
        // Moving colliders' centres as of the snapshot (the penetration check reads them).
        let moving = world
            .get_resource::<MovingColliders>()
            .map(|m| m.0.clone())
            .unwrap_or_default();
        for (k, body) in moving {
            let centre = world
                .resource::<Physics>()
                .0
                .bodies
                .get(body)
                .map(|b| b.translation().as_dvec3());
            if let (Some(centre), Some(mut colliders)) = (centre, world.get_resource_mut::<WorldColliders>())
                && let Some(entry) = colliders.0.get_mut(k)
            {
                entry.1 = centre;
            }
        }
        *world.resource_mut::<Clock>() = self.clock;
        *world.resource_mut::<SettleState>() = self.settle;
        *world.resource_mut::<Motion>() = self.motion;
        if let Some(creep) = self.creep {
            world.insert_resource(creep);
        }
        let mut ledger = world.resource_mut::<EffectLedger>();
        for (name, calls, seconds) in &self.effect_calls {
            ledger.set(name, *calls, *seconds);
        }
        Ok(())
    }

    /// Writes the snapshot to `dir/checkpoint.cbor` (through a temporary file and a rename).
    pub fn write(&self, dir: &Path) -> Result<PathBuf, CheckpointError> {
        let path = dir.join(CHECKPOINT_FILE);
        let partial = dir.join(format!("{CHECKPOINT_FILE}.partial"));
        let io = |source| CheckpointError::Io {
            path: path.clone(),
            source,
        };
        std::fs::create_dir_all(dir).map_err(io)?;
        let file = std::fs::File::create(&partial).map_err(io)?;
        let mut writer = std::io::BufWriter::new(file);
        ciborium::into_writer(self, &mut writer).map_err(|e| CheckpointError::Encode {
            path: path.clone(),
            message: e.to_string(),
        })?;
        std::io::Write::flush(&mut writer).map_err(io)?;
        drop(writer);
        std::fs::rename(&partial, &path).map_err(io)?;
        Ok(path)
    }

    /// The simulated time the checkpoint was taken at (s).
    pub fn time_s(&self) -> f64 {
        self.clock.time
    }

    /// Reads `dir/checkpoint.cbor`.
    pub fn read(dir: &Path) -> Result<Self, CheckpointError> {
        let path = dir.join(CHECKPOINT_FILE);
        let file = std::fs::File::open(&path).map_err(|source| CheckpointError::Io {
            path: path.clone(),
            source,
        })?;
        let snapshot: Self =
            ciborium::from_reader(std::io::BufReader::new(file)).map_err(|e| CheckpointError::Decode {
                path: path.clone(),
                message: e.to_string(),
            })?;
        if snapshot.format != FORMAT {
            return Err(CheckpointError::Decode {
                path,
                message: format!("format {} (this build reads {FORMAT})", snapshot.format),
            });
        }
        Ok(snapshot)
    }
}

/// Rapier's world has no `Clone`; a serialisation round trip copies exactly what a checkpoint
/// keeps.
fn clone_physics(physics: &PhysicsWorld) -> Result<PhysicsWorld, CheckpointError> {
    let mut bytes = Vec::new();
    let encode = |e: &dyn std::fmt::Display| CheckpointError::Encode {
        path: PathBuf::from(CHECKPOINT_FILE),
        message: e.to_string(),
    };
    ciborium::into_writer(physics, &mut bytes).map_err(|e| encode(&e))?;
    ciborium::from_reader(bytes.as_slice()).map_err(|e| encode(&e))
}
