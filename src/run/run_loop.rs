//! Stepping a spawned scene to its end, in named stages:
//!
//! 1. [`RunLoop::new`]: the schedule, the step budget, the checkpoint interval, progress.
//! 2. [`RunLoop::done`]: settled (and creep watched, if asked for), out of time.
//! 3. [`RunLoop::step`]: one run of the schedule at the step [`RestStep`] chooses; a failure
//!    is named by its effect.
//! 4. [`RunLoop::checkpoint_if_due`]: a checkpoint at its interval or on an interrupt.
//! 5. [`collect`]: the declared measurements and `metrics.json`'s numbers.

use std::sync::Arc;
use std::sync::atomic::Ordering;
use std::time::Instant;

use bevy_ecs::prelude::*;
use glam::DVec3;

use super::declared_measures::{Measured, measure_declared};
use super::rest_step::RestStep;
use super::{RunOptions, RunOutcome};
use crate::checkpoint::Snapshot;
use crate::forces::{ClothGeometry, ClothTopology};
use crate::implicit::ImplicitStats;
use crate::measure::{
    CreepWatch, Motion, PotentialEnergy, Progress, SettleState, WorldColliders, potential_energy,
};
use crate::output::{EffectCost, FailureReport, Metrics, SolveSplit};
use crate::scene::Scene;
use crate::schedule::{
    Clock, ClothEffects, ClothNodes, ClothState, EffectLedger, Failure, Implicit, build_step_schedule,
};

/// How a run ended.
#[derive(Debug, Default)]
pub(super) struct Ending {
    /// The failure that stopped it, its effect named.
    pub failure: Option<FailureReport>,
    /// Stopped by an interrupt.
    pub interrupted: bool,
    /// The first checkpoint that could not be written.
    pub checkpoint_error: Option<String>,
    /// Wall time of the whole run, resumed parts included (s).
    pub wall_s: f64,
}

/// A scene's world being stepped.
pub(super) struct RunLoop<'a> {
    scene: &'a Scene,
    options: &'a RunOptions,
    schedule: Schedule,
    /// Simulated time at which the run stops (s), less a millionth of a step for rounding.
    end_time: f64,
    /// The simulated time (s) at which the next checkpoint is due.
    next_checkpoint: Option<f64>,
    /// The step in motion and at rest.
    steps: RestStep,
    start: Instant,
    wall_before: f64,
}

impl<'a> RunLoop<'a> {
    /// Stage 1: the schedule and budgets for `scene`; `wall_before` (s) is wall time already
    /// spent on this run (a resumed one).
    pub fn new(scene: &'a Scene, world: &mut World, options: &'a RunOptions, wall_before: f64) -> Self {
        let max_time = scene.spec.integration.max_time_s;
        let dt = scene.spec.integration.dt_s;
        if options.progress {
            world.insert_resource(Progress::new(max_time, (0.02 / dt).ceil() as u64));
        }
        Self {
            scene,
            options,
            schedule: build_step_schedule(),
            end_time: max_time - 1e-6 * dt,
            next_checkpoint: options.checkpoint.as_ref().map(|c| {
                let now = world.resource::<Clock>().time;
                (now / c.every_s + 1e-6).floor() * c.every_s + c.every_s
            }),
            steps: RestStep::new(scene),
            start: Instant::now(),
            wall_before,
        }
    }

    /// Stage 2: whether the run is over: settled (and, with `settle.creep_check_s`, watched for
    /// creep that long), or at its time limit. Starts the creep watch when the cloth settles.
    pub fn done(&self, world: &mut World, cloth: Entity) -> bool {
        let clock = *world.resource::<Clock>();
        if world.resource::<SettleState>().settled_at.is_some() {
            let creep_check = self.scene.spec.integration.settle.creep_check_s;
            let Some(watch) = world.get_resource::<CreepWatch>() else {
                if creep_check <= 0.0 {
                    return true;
                }
                let positions = world.get::<ClothState>(cloth).map(|s| s.positions.clone());
                world.insert_resource(CreepWatch {
                    start_time: clock.time,
                    positions: positions.unwrap_or_default(),
                });
                return self.done(world, cloth);
            };
            if clock.time - watch.start_time >= creep_check - 0.5 * clock.dt {
                return true;
            }
        }
        clock.time >= self.end_time
    }

    /// Stage 3: one step; a failure comes back with the effect at fault named.
    pub fn step(&mut self, world: &mut World, cloth: Entity) -> Option<FailureReport> {
        self.steps.choose(world);
        self.schedule.run(world);
        self.steps.judge(world);
        let f = world.resource::<Failure>().0.clone()?;
        let named = |find: &dyn Fn(&ClothEffects, &ClothState) -> Option<&'static str>| {
            world
                .get::<ClothEffects>(cloth)
                .zip(world.get::<ClothState>(cloth))
                .and_then(|(e, s)| find(e, s))
        };
        let effect = match f.effect.as_str() {
            "(forces)" => named(&|e, s| e.0.first_non_finite(&s.topology, &s.positions, &s.velocities))
                .unwrap_or("unknown")
                .to_string(),
            "(runaway)" => named(&|e, s| {
                e.0.strongest_at(f.particle, &s.topology, &s.positions, &s.velocities)
            })
            .unwrap_or("rapier_step")
            .to_string(),
            _ => f.effect.clone(),
        };
        Some(FailureReport {
            step: f.step,
            time_s: f.time,
            particle: f.particle,
            effect,
            message: f.message,
        })
    }

    /// Wall time of the run so far, resumed parts included (s).
    pub fn wall_s(&self) -> f64 {
        self.wall_before + self.start.elapsed().as_secs_f64()
    }

    /// Whether an interrupt asks the run to stop.
    pub fn interrupted(&self) -> bool {
        self.options
            .interrupt
            .as_ref()
            .is_some_and(|i| i.load(Ordering::Relaxed))
    }

    /// Stage 4: writes a checkpoint when one is due or `stopping`; the first error is kept in
    /// `error` and the run goes on.
    pub fn checkpoint_if_due(
        &mut self,
        world: &World,
        cloth: Entity,
        stopping: bool,
        error: &mut Option<String>,
    ) {
        let Some(plan) = &self.options.checkpoint else {
            return;
        };
        let clock = world.resource::<Clock>();
        let due = self
            .next_checkpoint
            .is_some_and(|t| clock.time >= t - 1e-6 * clock.dt);
        if due {
            let every = plan.every_s;
            self.next_checkpoint = Some(((clock.time / every + 1e-6).floor() + 1.0) * every);
        }
        if !(stopping || due) {
            return;
        }
        let written = Snapshot::capture(world, cloth, self.scene, Some(plan.every_s), self.wall_s())
            .and_then(|s| s.write(&plan.dir));
        if let Err(e) = written {
            error.get_or_insert(e.to_string());
        }
    }

    /// Runs stages 2–4 until the run is over.
    pub fn run(mut self, world: &mut World, cloth: Entity) -> Ending {
        let mut ending = Ending::default();
        while !self.done(world, cloth) {
            if let Some(failure) = self.step(world, cloth) {
                ending.failure = Some(failure);
                break;
            }
            let stop = self.interrupted();
            self.checkpoint_if_due(world, cloth, stop, &mut ending.checkpoint_error);
            if stop {
                ending.interrupted = true;
                break;
            }
        }
        ending.wall_s = self.wall_s();
        if let Some(p) = world.get_resource::<Progress>() {
            p.finish();
        }
        ending
    }
}

/// Stage 5: the declared measurements (unless the run failed) and the metrics.
pub(super) fn collect(scene: &Scene, world: &World, cloth: Entity, ending: Ending) -> RunOutcome {
    let state = world.get::<ClothState>(cloth);
    let (topology, positions) = match state {
        Some(s) => (s.topology.clone(), s.positions.clone()),
        None => (Arc::new(ClothTopology::rectangle(0, 0, 1.0)), Vec::new()),
    };
    let failed = ending.failure.is_some();
    let measured = if failed {
        Measured::default()
    } else {
        measure_declared(scene, &topology, &positions)
    };
    let colliders = world
        .get_resource::<WorldColliders>()
        .map(|c| c.0.clone())
        .unwrap_or_else(|| crate::scene::spawn::world_shapes(scene));
    let clock = *world.resource::<Clock>();
    let creep = world
        .get_resource::<CreepWatch>()
        .filter(|_| !failed)
        .map(|w| w.creep(clock.time, &positions));
    let finite = positions.iter().all(|p| p.is_finite());
    let max_penetration_m = if finite {
        crate::measure::max_penetration(&colliders, &positions).0
    } else {
        0.0
    };
    let implicit = world.get::<Implicit>(cloth).map(|i| i.0.stats);
    let mut metrics = run_metrics(scene, world, &topology, implicit, &ending);
    metrics.max_penetration_m = max_penetration_m;
    let energy = (finite && !failed).then(|| final_energy(scene, world, cloth, &positions));
    if let Some(energy) = energy.flatten() {
        metrics.gravitational_energy_j = Some(energy.gravitational);
        metrics.elastic_energy_j = Some(energy.elastic);
    }
    metrics.creep_window_s = creep.map(|c| c.window);
    metrics.creep_max_node_m = creep.map(|c| c.max_node);
    metrics.creep_centroid_m = creep.map(|c| c.centroid);
    let drape = measured.drape.as_ref();
    metrics.drape_coefficient = drape.map(|d| d.drape_coefficient);
    metrics.nodes = drape.map(|d| d.nodes);
    metrics.outline_min_radius_m = drape.map(|d| d.min_radius);
    metrics.outline_max_radius_m = drape.map(|d| d.max_radius);
    metrics.fold_amplitude_m = drape.map(|d| d.fold_amplitude);
    metrics.hang_corners_m = measured.table.map(|t| t.corners);
    metrics.hang_mid_sides_m = measured.table.map(|t| t.mid_sides);
    metrics.skirt_folds = measured.table.map(|t| t.folds);
    metrics.cantilever_chord_deg = measured.cantilever.map(|c| c.chord.to_degrees());
    metrics.cantilever_exact_deg = measured.cantilever.map(|c| c.exact.to_degrees());
    RunOutcome {
        metrics,
        topology,
        positions,
        drape: measured.drape,
        collider_centres: colliders.iter().map(|c| c.1).collect(),
        checkpoint_error: ending.checkpoint_error,
    }
}

/// The potential energy of the cloth at `positions` (m); `None` for a cloth without its
/// bodies, effects or state.
fn final_energy(scene: &Scene, world: &World, cloth: Entity, positions: &[DVec3]) -> Option<PotentialEnergy> {
    let (nodes, effects, state) = (
        world.get::<ClothNodes>(cloth)?,
        world.get::<ClothEffects>(cloth)?,
        world.get::<ClothState>(cloth)?,
    );
    let mut geometry = ClothGeometry::new(state.topology.clone());
    let gravity = DVec3::from_array(scene.spec.world.gravity_m_per_s2);
    Some(potential_energy(
        &effects.0,
        &mut geometry,
        &nodes.0.masses,
        positions,
        gravity,
    ))
}

/// The metrics every run has: settings, time, motion, the implicit solve, the effects' costs;
/// the measurements' fields are left empty.
fn run_metrics(
    scene: &Scene,
    world: &World,
    topology: &ClothTopology,
    implicit: Option<ImplicitStats>,
    ending: &Ending,
) -> Metrics {
    let clock = *world.resource::<Clock>();
    let motion = *world.resource::<Motion>();
    let settle = world.resource::<SettleState>();
    let ledger = world.resource::<EffectLedger>();
    Metrics {
        numerical_error: None,
        integrator: format!("{:?}", scene.spec.integration.integrator),
        cg_iterations_mean: implicit.map(|s| s.iterations as f64 / s.solves.max(1) as f64),
        cg_unconverged_steps: implicit.map(|s| s.unconverged),
        cg_repeated_steps: implicit.map(|s| s.repeated),
        cg_factorisations: implicit.map(|s| s.factorisations),
        solve_split: implicit.map(|s| SolveSplit {
            assembly_s: s.assembly_s,
            preconditioner_s: s.preconditioner_s,
            cg_s: s.cg_s,
        }),
        scene: scene.spec.name.clone(),
        fabric: scene.fabric.name.clone(),
        particles: topology.particle_count,
        spacing_m: topology.spacing,
        lattice_offset_m: scene.spec.cloth.lattice_offset_m,
        dt_s: scene.spec.integration.dt_s,
        rest_dt_s: Some(scene.spec.integration.rest_dt_s).filter(|_| clock.rest_steps > 0),
        rest_steps: clock.rest_steps,
        steps: clock.step,
        sim_time_s: clock.time,
        wall_time_s: ending.wall_s,
        settled: settle.settled_at.is_some() && ending.failure.is_none(),
        settle_time_s: settle.settled_at,
        settle_restarts: settle.restarts,
        max_strain: motion.max_strain,
        peak_strain: motion.peak_strain,
        strain_limited_steps: motion.strain_limited_steps,
        min_height_m: if motion.min_height.is_finite() {
            motion.min_height
        } else {
            0.0
        },
        max_penetration_m: 0.0,
        peak_penetration_m: motion.peak_penetration,
        max_speed_m_per_s: motion.max_speed,
        max_step_speed_m_per_s: motion.max_step_speed,
        window_speed_m_per_s: settle.window_speed,
        kinetic_energy_j: motion.kinetic_energy,
        gravitational_energy_j: None,
        elastic_energy_j: None,
        drape_coefficient: None,
        nodes: None,
        outline_min_radius_m: None,
        outline_max_radius_m: None,
        fold_amplitude_m: None,
        hang_corners_m: None,
        hang_mid_sides_m: None,
        skirt_folds: None,
        cantilever_chord_deg: None,
        cantilever_exact_deg: None,
        effects: ledger
            .entries
            .iter()
            .map(|(name, calls, seconds)| {
                (
                    name.to_string(),
                    EffectCost {
                        calls: *calls,
                        seconds: *seconds,
                    },
                )
            })
            .collect(),
        creep_window_s: None,
        creep_max_node_m: None,
        creep_centroid_m: None,
        failure: ending.failure.clone(),
        interrupted: ending.interrupted,
    }
}
