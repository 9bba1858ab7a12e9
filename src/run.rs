//! Running a scene: step the schedule until the cloth settles or the time limit, then collect
//! metrics and write the output files.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Instant;

use bevy_ecs::prelude::*;
use glam::DVec3;

use crate::checkpoint::{CheckpointError, Snapshot};
use crate::forces::{
    AirDrag, Bending, ClothTopology, ForceBuffer, ForceGenerator, Hysteresis, KesTensile, LinkCompression,
    LinkDamping, SeedSeparation, Trellising,
};
use crate::measure::{
    CreepWatch, DrapeMeasurement, Motion, Progress, SettleState, WorldColliders, measure_drape, project,
};
use crate::output::{
    EffectCost, FailureReport, Metrics, OutputError, TopViewOutline, write_obj, write_top_view,
};
use crate::scene::{ColliderShape, Scene};
use crate::schedule::{Clock, ClothState, Effect, EffectLedger, Failure, Implicit, build_step_schedule};

/// How to run.
#[derive(Clone, Debug, Default)]
pub struct RunOptions {
    /// Show a progress bar on the terminal.
    pub progress: bool,
    /// Write checkpoints (see [`crate::checkpoint`]).
    pub checkpoint: Option<CheckpointPlan>,
    /// Set from outside (e.g. by a Ctrl-C handler) to stop the run after the current step; the
    /// run then writes a checkpoint (with a plan) and returns its partial results.
    pub interrupt: Option<Arc<AtomicBool>>,
}

/// Where and how often a run writes its checkpoint.
#[derive(Clone, Debug, PartialEq)]
pub struct CheckpointPlan {
    /// The folder `checkpoint.cbor` is written to (the run's output folder).
    pub dir: PathBuf,
    /// Interval in simulated time (s), rounded to whole steps; a checkpoint is also written when
    /// the run is interrupted.
    pub every_s: f64,
}

/// The result of a run: its metrics and the final cloth.
#[derive(Clone, Debug)]
pub struct RunOutcome {
    /// The numbers of `metrics.json`.
    pub metrics: Metrics,
    /// The woven grid.
    pub topology: Arc<ClothTopology>,
    /// Final node positions (m); finite unless the run failed.
    pub positions: Vec<DVec3>,
    /// The drape test's measurement, for scenes with a drapemeter disk (a cylinder).
    pub drape: Option<DrapeMeasurement>,
    /// Final centre of each of the scene's colliders, in scene order (m): where a thrown ball
    /// ended up, not where it started.
    pub collider_centres: Vec<DVec3>,
    /// The first checkpoint that could not be written, if any (the run went on without it).
    pub checkpoint_error: Option<String>,
}

/// A run that stopped on a non-finite value.
#[derive(Debug, thiserror::Error)]
#[error(
    "simulation diverged at step {} (t = {:.4} s): particle {}, effect `{}`: {}",
    .0.step, .0.time_s, .0.particle, .0.effect, .0.message
)]
pub struct DivergenceError(pub FailureReport);

/// Simulates `scene` to rest or to its time limit. A failure is recorded in the metrics.
pub fn simulate(scene: &Scene, options: &RunOptions) -> RunOutcome {
    let (world, cloth) = crate::scene::spawn::spawn(scene);
    run_to_end(scene, world, cloth, options, 0.0)
}

/// Continues the run whose checkpoint is in `dir` to its end, writing further checkpoints there
/// at the interval it was started with. Returns the scene (as the checkpoint recorded it) and
/// the outcome, which is exactly that of the uninterrupted run (wall time aside).
pub fn resume(dir: &Path, options: &RunOptions) -> Result<(Scene, RunOutcome), CheckpointError> {
    let snapshot = Snapshot::read(dir)?;
    let scene = Scene::from_spec(snapshot.scene.clone(), snapshot.scene_path.clone())
        .map_err(|e| CheckpointError::Scene(Box::new(e)))?;
    if format!("{:?}", scene.fabric) != snapshot.fabric {
        return Err(CheckpointError::Mismatch(
            "the fabric (its file changed since the checkpoint)",
        ));
    }
    let (mut world, cloth) = crate::scene::spawn::spawn(&scene);
    let every_s = snapshot.every_s;
    let wall = snapshot.wall_time_s;
    snapshot.restore(&mut world, cloth)?;
    let mut options = options.clone();
    if options.checkpoint.is_none() {
        options.checkpoint = every_s.map(|every_s| CheckpointPlan {
            dir: dir.to_path_buf(),
            every_s,
        });
    }
    let outcome = run_to_end(&scene, world, cloth, &options, wall);
    Ok((scene, outcome))
}

/// Steps `world` until the cloth settles, the time limit, a failure or an interrupt, then
/// measures. `wall_before` (s) is wall time already spent on this run (a resumed one).
fn run_to_end(
    scene: &Scene,
    mut world: World,
    cloth: Entity,
    options: &RunOptions,
    wall_before: f64,
) -> RunOutcome {
    let mut schedule = build_step_schedule();
    let max_time = scene.spec.integration.max_time_s;
    let dt = scene.spec.integration.dt_s;
    let max_steps = (max_time / dt).ceil() as u64;
    if options.progress {
        world.insert_resource(Progress::new(max_time, (0.02 / dt).ceil() as u64));
    }
    let checkpoint_steps = options
        .checkpoint
        .as_ref()
        .map(|c| ((c.every_s / dt).round() as u64).max(1));
    let mut checkpoint_error = None;
    let mut interrupted = false;
    let start = Instant::now();
    let mut failure = None;
    let creep_check = scene.spec.integration.settle.creep_check_s;
    loop {
        let clock = *world.resource::<Clock>();
        if world.resource::<SettleState>().settled_at.is_some() {
            // Settled: stop, or first watch for creep over `creep_check` more seconds.
            let Some(watch) = world.get_resource::<CreepWatch>() else {
                if creep_check <= 0.0 {
                    break;
                }
                let positions = world.get::<ClothState>(cloth).map(|s| s.positions.clone());
                world.insert_resource(CreepWatch {
                    start_time: clock.time,
                    positions: positions.unwrap_or_default(),
                });
                continue;
            };
            if clock.time - watch.start_time >= creep_check - 0.5 * dt {
                break;
            }
        }
        if clock.step >= max_steps {
            break;
        }
        schedule.run(&mut world);
        if let Some(f) = world.resource::<Failure>().0.clone() {
            let effect = match f.effect.as_str() {
                "(forces)" => diagnose_forces(&world, cloth).unwrap_or("unknown").to_string(),
                "(runaway)" => strongest_effect(&world, cloth, f.particle)
                    .unwrap_or("rapier_step")
                    .to_string(),
                _ => f.effect.clone(),
            };
            failure = Some(FailureReport {
                step: f.step,
                time_s: f.time,
                particle: f.particle,
                effect,
                message: f.message,
            });
            break;
        }
        let step = world.resource::<Clock>().step;
        let stop = options
            .interrupt
            .as_ref()
            .is_some_and(|i| i.load(Ordering::Relaxed));
        let due = checkpoint_steps.is_some_and(|n| step % n == 0);
        if let (Some(plan), true) = (&options.checkpoint, stop || due) {
            let wall = wall_before + start.elapsed().as_secs_f64();
            let written = Snapshot::capture(&world, cloth, scene, Some(plan.every_s), wall)
                .and_then(|s| s.write(&plan.dir));
            if let Err(e) = written {
                checkpoint_error.get_or_insert(e.to_string());
            }
        }
        if stop {
            interrupted = true;
            break;
        }
    }
    let wall = wall_before + start.elapsed().as_secs_f64();
    if let Some(p) = world.get_resource::<Progress>() {
        p.finish();
    }

    let clock = *world.resource::<Clock>();
    let motion = *world.resource::<Motion>();
    let settle = world.resource::<SettleState>().clone();
    let ledger = world.resource::<EffectLedger>().clone();
    let state = world.get::<ClothState>(cloth);
    let (topology, positions) = match state {
        Some(s) => (s.topology.clone(), s.positions.clone()),
        None => (Arc::new(ClothTopology::rectangle(0, 0, 1.0)), Vec::new()),
    };
    let drape = if failure.is_none() {
        measure_scene_drape(scene, &topology, &positions)
    } else {
        None
    };
    let table = if failure.is_none() {
        measure_scene_table(scene, &topology, &positions)
    } else {
        None
    };
    let implicit = world.get::<Implicit>(cloth).map(|i| i.0.stats);
    let colliders = world
        .get_resource::<WorldColliders>()
        .map(|c| c.0.clone())
        .unwrap_or_else(|| crate::scene::spawn::world_shapes(scene));
    let creep = world
        .get_resource::<CreepWatch>()
        .filter(|_| failure.is_none())
        .map(|w| w.creep(clock.time, &positions));
    let metrics = Metrics {
        integrator: format!("{:?}", scene.spec.integration.integrator),
        cg_iterations_mean: implicit.map(|s| s.iterations as f64 / s.solves.max(1) as f64),
        cg_unconverged_steps: implicit.map(|s| s.unconverged),
        cg_repeated_steps: implicit.map(|s| s.repeated),
        scene: scene.spec.name.clone(),
        fabric: scene.fabric.name.clone(),
        particles: topology.particle_count,
        spacing_m: topology.spacing,
        lattice_offset_m: scene.spec.cloth.lattice_offset_m,
        dt_s: dt,
        steps: clock.step,
        sim_time_s: clock.time,
        wall_time_s: wall,
        settled: settle.settled_at.is_some() && failure.is_none(),
        settle_time_s: settle.settled_at,
        max_strain: motion.max_strain,
        peak_strain: motion.peak_strain,
        min_height_m: if motion.min_height.is_finite() {
            motion.min_height
        } else {
            0.0
        },
        max_penetration_m: if positions.iter().all(|p| p.is_finite()) {
            crate::measure::max_penetration(&colliders, &positions).0
        } else {
            0.0
        },
        peak_penetration_m: motion.peak_penetration,
        max_speed_m_per_s: motion.max_speed,
        max_step_speed_m_per_s: motion.max_step_speed,
        window_speed_m_per_s: settle.window_speed,
        kinetic_energy_j: motion.kinetic_energy,
        drape_coefficient: drape.as_ref().map(|d| d.drape_coefficient),
        nodes: drape.as_ref().map(|d| d.nodes),
        outline_min_radius_m: drape.as_ref().map(|d| d.min_radius),
        outline_max_radius_m: drape.as_ref().map(|d| d.max_radius),
        fold_amplitude_m: drape.as_ref().map(|d| d.fold_amplitude),
        hang_corners_m: table.map(|t| t.0),
        hang_mid_sides_m: table.map(|t| t.1),
        skirt_folds: table.map(|t| t.2),
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
        creep_window_s: creep.map(|c| c.window),
        creep_max_node_m: creep.map(|c| c.max_node),
        creep_centroid_m: creep.map(|c| c.centroid),
        failure,
        interrupted,
    };
    RunOutcome {
        metrics,
        topology,
        positions,
        drape,
        collider_centres: colliders.iter().map(|c| c.1).collect(),
        checkpoint_error,
    }
}

/// For a square cloth on a table (a table-sized box, and no drapemeter disk): the mean hang of
/// the four corners and of the four mid-sides below the table top (m), and the skirt's folds.
fn measure_scene_table(
    scene: &Scene,
    topology: &ClothTopology,
    positions: &[DVec3],
) -> Option<(f64, f64, u32)> {
    if drapemeter_disk(scene).is_some()
        || !matches!(scene.spec.cloth.shape, crate::scene::ClothShape::Square { .. })
    {
        return None;
    }
    let (centre, half) = scene.spec.world.colliders.iter().find_map(|c| match c.shape {
        ColliderShape::Cuboid { half_extents_m: h } if h[0] < 1.0 && h[2] < 1.0 => Some((c.centre_m, h)),
        _ => None,
    })?;
    let top = centre[1] + half[1];
    let n = topology.grid_coords.iter().map(|&(i, _)| i).max()?;
    let mid = n / 2;
    let at = |i: u32, j: u32| {
        topology
            .grid_coords
            .iter()
            .position(|&c| c == (i, j))
            .map(|p| top - positions[p].y)
    };
    let mean = |pts: [(u32, u32); 4]| -> Option<f64> {
        let hangs: Option<Vec<f64>> = pts.iter().map(|&(i, j)| at(i, j)).collect();
        hangs.map(|h| h.iter().sum::<f64>() / 4.0)
    };
    let corners = mean([(0, 0), (n, 0), (0, n), (n, n)])?;
    let sides = mean([(mid, 0), (0, mid), (n, mid), (mid, n)])?;
    let skirt = crate::measure::measure_skirt(
        &project(&topology.triangles, positions),
        glam::DVec2::new(centre[0], centre[2]),
        glam::DVec2::new(half[0], half[2]),
        topology.spacing / 50.0,
        2.0 * topology.spacing,
    );
    Some((corners, sides, skirt.folds))
}

/// Centre (x, z) (m) and radius (m) of the scene's drapemeter disk: its first cylinder.
fn drapemeter_disk(scene: &Scene) -> Option<(glam::DVec2, f64)> {
    scene.spec.world.colliders.iter().find_map(|c| match c.shape {
        ColliderShape::Cylinder { radius_m, .. } => {
            Some((glam::DVec2::new(c.centre_m[0], c.centre_m[2]), radius_m))
        }
        _ => None,
    })
}

/// Measures the drape around the scene's first cylinder (the drapemeter disk), if it has one.
fn measure_scene_drape(
    scene: &Scene,
    topology: &ClothTopology,
    positions: &[DVec3],
) -> Option<DrapeMeasurement> {
    let disk = drapemeter_disk(scene)?;
    let (_, flat) = crate::scene::spawn::cloth_grid(scene);
    // Rows σ/50 apart: the row rule's error is then far below the mesh's (docs/validation.md).
    let dz = topology.spacing / 50.0;
    Some(measure_drape(
        &project(&topology.triangles, positions),
        &project(&topology.triangles, &flat),
        disk.0,
        disk.1,
        dz,
        2.0 * topology.spacing,
    ))
}

/// Re-evaluates each effect on the cloth's current state, alone, and names the one pushing
/// hardest on `node`: in a runaway, the likeliest culprit.
fn strongest_effect(world: &World, cloth: Entity, node: usize) -> Option<&'static str> {
    fn force<G: ForceGenerator + 'static>(
        world: &World,
        cloth: Entity,
        state: &ClothState,
        node: usize,
    ) -> Option<(f64, &'static str)> {
        let effect = world.get::<Effect<G>>(cloth)?;
        let mut geometry = state.geometry.clone();
        geometry.update(&state.positions);
        let mut buffer = ForceBuffer::new(&state.topology);
        effect.0.add_forces(&geometry, &state.velocities, &mut buffer);
        let f = buffer.resolve(&state.topology).get(node)?.length();
        f.is_finite().then_some((f, effect.0.effect()))
    }
    let state = world.get::<ClothState>(cloth)?;
    [
        force::<Bending>(world, cloth, state, node),
        force::<Trellising>(world, cloth, state, node),
        force::<SeedSeparation>(world, cloth, state, node),
        force::<KesTensile>(world, cloth, state, node),
        force::<LinkCompression>(world, cloth, state, node),
        force::<LinkDamping>(world, cloth, state, node),
        force::<AirDrag>(world, cloth, state, node),
        force::<Hysteresis>(world, cloth, state, node),
    ]
    .into_iter()
    .flatten()
    .max_by(|a, b| a.0.total_cmp(&b.0))
    .map(|(_, name)| name)
}

/// Re-evaluates each effect on the cloth's current state, alone, and names the first whose
/// forces are not finite.
fn diagnose_forces(world: &World, cloth: Entity) -> Option<&'static str> {
    fn check<G: ForceGenerator + 'static>(
        world: &World,
        cloth: Entity,
        state: &ClothState,
    ) -> Option<&'static str> {
        let effect = world.get::<Effect<G>>(cloth)?;
        let mut buffer = ForceBuffer::new(&state.topology);
        effect
            .0
            .add_forces(&state.geometry, &state.velocities, &mut buffer);
        let bad = buffer.resolve(&state.topology).iter().any(|f| !f.is_finite());
        bad.then(|| effect.0.effect())
    }
    let state = world.get::<ClothState>(cloth)?;
    check::<Bending>(world, cloth, state)
        .or_else(|| check::<Trellising>(world, cloth, state))
        .or_else(|| check::<SeedSeparation>(world, cloth, state))
        .or_else(|| check::<KesTensile>(world, cloth, state))
        .or_else(|| check::<LinkCompression>(world, cloth, state))
        .or_else(|| check::<LinkDamping>(world, cloth, state))
        .or_else(|| check::<AirDrag>(world, cloth, state))
        .or_else(|| check::<Hysteresis>(world, cloth, state))
}

/// Writes `metrics.json` and, for a run that did not fail, `final.obj` and `top.png`.
pub fn write_outputs(scene: &Scene, outcome: &RunOutcome, dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::new(dir, e))?;
    outcome.metrics.write(dir)?;
    if outcome.metrics.failure.is_some() {
        return Ok(());
    }
    let out = &scene.spec.output;
    if out.mesh_obj {
        write_obj(dir, &scene.spec.name, &outcome.topology, &outcome.positions)?;
    }
    if out.top_png {
        // A thrown body that ended beyond the cloth (bounced off, fell away) is left out, so the
        // picture stays framed on the cloth.
        let cloth_extent = outcome
            .positions
            .iter()
            .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.z.abs()));
        let outlines: Vec<TopViewOutline> = scene
            .spec
            .world
            .colliders
            .iter()
            .zip(&outcome.collider_centres)
            .filter(|(c, at)| {
                c.motion == crate::scene::ColliderMotion::Fixed || at.x.abs().max(at.z.abs()) <= cloth_extent
            })
            .filter_map(|(c, at)| {
                let centre = [at.x, at.z];
                match c.shape {
                    ColliderShape::Cylinder { radius_m, .. } => Some(TopViewOutline::Circle {
                        centre,
                        radius: radius_m,
                    }),
                    ColliderShape::Cuboid {
                        half_extents_m: [x, _, z],
                    } if x < 1.0 && z < 1.0 => Some(TopViewOutline::Rectangle { centre, half: [x, z] }),
                    // A floor-sized box would only frame the picture.
                    ColliderShape::Cuboid { .. } => None,
                    ColliderShape::Ball { radius_m } => Some(TopViewOutline::Circle {
                        centre,
                        radius: radius_m,
                    }),
                }
            })
            .collect();
        let markers: Vec<[f64; 2]> = match (&outcome.drape, drapemeter_disk(scene)) {
            (Some(d), Some((centre, _))) => d
                .node_angles
                .iter()
                .zip(&d.node_radii)
                .map(|(a, r)| [centre.x + r * a.cos(), centre.y + r * a.sin()])
                .collect(),
            _ => Vec::new(),
        };
        write_top_view(
            dir,
            out.image_size_px,
            &outcome.topology,
            &outcome.positions,
            &outlines,
            &markers,
        )?;
    }
    Ok(())
}

/// The short summary printed after a run.
pub fn summary(outcome: &RunOutcome) -> String {
    let m = &outcome.metrics;
    let mut s = format!(
        "{} ({}): {} nodes at {:.1} mm, dt {:.3} ms, {}\n",
        m.scene,
        m.fabric,
        m.particles,
        m.spacing_m * 1e3,
        m.dt_s * 1e3,
        match m.cg_iterations_mean {
            Some(it) => format!("implicit ({it:.0} CG products per step)"),
            None => "explicit".to_string(),
        }
    );
    match (m.settled, m.settle_time_s) {
        (true, Some(t)) => s += &format!("  settled at t = {t:.2} s"),
        _ => s += "  NOT settled: the numbers below are provisional",
    }
    s += &format!(
        " ({} steps, {:.2} s simulated, {:.1} s wall)\n",
        m.steps, m.sim_time_s, m.wall_time_s
    );
    s += &format!(
        "  lowest node {:.1} mm, max link strain {:.2} % (peak {:.2} %)\n  fastest node: moved {:.2} mm/s over the last step (Rapier's velocity {:.2} mm/s), {} over the settle window\n",
        m.min_height_m * 1e3,
        m.max_strain * 100.0,
        m.peak_strain * 100.0,
        m.max_step_speed_m_per_s * 1e3,
        m.max_speed_m_per_s * 1e3,
        m.window_speed_m_per_s
            .map_or("-".to_string(), |v| format!("{:.2} mm/s", v * 1e3))
    );
    s += &format!(
        "  deepest node inside a collider: {:.2} mm now, {:.2} mm at the worst step\n",
        m.max_penetration_m * 1e3,
        m.peak_penetration_m * 1e3
    );
    if let (Some(w), Some(node), Some(centroid)) = (m.creep_window_s, m.creep_max_node_m, m.creep_centroid_m)
    {
        s += &format!(
            "  creep over {w:.2} s after settling: nodes moved at most {:.3} mm, the centroid {:.3} mm\n",
            node * 1e3,
            centroid * 1e3
        );
    }
    if let (Some(dc), Some(n)) = (m.drape_coefficient, m.nodes) {
        let tag = if m.settled {
            ""
        } else {
            " (provisional: not settled)"
        };
        s += &format!("  drape coefficient {dc:.3}, {n} nodes{tag}\n");
    }
    if let (Some(c), Some(side), Some(f)) = (m.hang_corners_m, m.hang_mid_sides_m, m.skirt_folds) {
        s += &format!(
            "  hang: corners {:.1} mm, mid-sides {:.1} mm; {f} skirt folds\n",
            c * 1e3,
            side * 1e3
        );
    }
    let ours: f64 = m
        .effects
        .iter()
        .filter(|(k, _)| *k != "rapier_step")
        .map(|(_, c)| c.seconds)
        .sum();
    let rapier = m.effects.get("rapier_step").map_or(0.0, |c| c.seconds);
    s += &format!("  time: our forces {ours:.2} s");
    if let Some(solve) = m.effects.get("implicit_solve").filter(|c| c.calls > 0) {
        s += &format!(" (of which the implicit solve {:.2} s)", solve.seconds);
    }
    s += &format!(", Rapier's step {rapier:.2} s");
    s
}
