//! Running a scene: step the schedule until the cloth settles or the time limit, then take the
//! measurements the scene declares and write the output files.

mod declared_measures;
mod error_estimate;
mod rest_step;
mod run_loop;
mod run_report;

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use bevy_ecs::prelude::*;
use glam::DVec3;

pub use declared_measures::{CantileverBend, Measured, TableHang, declared_disk, measure_declared};
pub use error_estimate::{
    ASSUMED_ORDER, ErrorEstimate, Estimated, companion_ratio, companion_scene, measures_something,
};
pub use run_report::{AT_REST_STEP_SPEED_M_PER_S, summary, write_outputs, write_repeat_report};

use crate::checkpoint::{CheckpointError, Snapshot};
use crate::forces::ClothTopology;
use crate::measure::DrapeMeasurement;
use crate::output::{FailureReport, Metrics};
use crate::scene::Scene;

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
    /// The drape test's measurement, for scenes that declare `measure: Drape(..)`.
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

/// Estimates the numerical error of a finished run's measured values by running its companion
/// on a coarser lattice ([`companion_scene`]) with `options` (no checkpoints), and records it in
/// the run's metrics. Nothing is run for a run that failed or was interrupted, or for a scene
/// that measures nothing; a companion that cannot be built is recorded as the reason.
pub fn estimate_error(scene: &Scene, outcome: &mut RunOutcome, options: &RunOptions) {
    let m = &outcome.metrics;
    if m.failure.is_some() || m.interrupted || !measures_something(scene) {
        return;
    }
    let ratio = companion_ratio(scene);
    let options = RunOptions {
        checkpoint: None,
        ..options.clone()
    };
    let estimate = match companion_scene(scene) {
        Ok(companion) => ErrorEstimate::from_runs(m, &simulate(&companion, &options).metrics, ratio),
        Err(e) => ErrorEstimate::not_run(
            scene.spec.cloth.spacing_m * ratio,
            ratio,
            format!("no companion run: {e}"),
        ),
    };
    outcome.metrics.numerical_error = Some(estimate);
}

/// Simulates `scene` ([`simulate`]) and, at the same time on a second thread, its companion on
/// a coarser lattice ([`companion_scene`]), whose values estimate the run's numerical error as
/// [`estimate_error`] would after the run: the same outcome, in about the wall time of the
/// longer of the two runs instead of their sum. The companion shows no progress and writes no
/// checkpoint; it is stopped as soon as the run fails or is interrupted (no estimate is
/// recorded then), and by an interrupt while the run waits for it.
pub fn simulate_with_error_estimate(scene: &Scene, options: &RunOptions) -> RunOutcome {
    let companion = match companion_scene(scene) {
        Ok(companion) if measures_something(scene) => companion,
        _ => {
            let mut outcome = simulate(scene, options);
            estimate_error(scene, &mut outcome, options);
            return outcome;
        }
    };
    let stop = Arc::new(AtomicBool::new(false));
    let companion_options = RunOptions {
        progress: false,
        checkpoint: None,
        interrupt: Some(stop.clone()),
    };
    let interrupted = || {
        options
            .interrupt
            .as_ref()
            .is_some_and(|flag| flag.load(Ordering::Relaxed))
    };
    std::thread::scope(|s| {
        let helper = s.spawn(|| simulate(&companion, &companion_options));
        let mut outcome = simulate(scene, options);
        let m = &outcome.metrics;
        let usable = m.failure.is_none() && !m.interrupted;
        while !helper.is_finished() {
            if !usable || interrupted() {
                stop.store(true, Ordering::Relaxed);
            }
            std::thread::sleep(std::time::Duration::from_millis(20));
        }
        let companion = helper
            .join()
            .unwrap_or_else(|panic| std::panic::resume_unwind(panic));
        if usable {
            let estimate = ErrorEstimate::from_runs(m, &companion.metrics, companion_ratio(scene));
            outcome.metrics.numerical_error = Some(estimate);
        }
        outcome
    })
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
    let ending = run_loop::RunLoop::new(scene, &mut world, options, wall_before).run(&mut world, cloth);
    run_loop::collect(scene, &world, cloth, ending)
}
