//! Phase 2, the tasks: one run per task file, on this machine's cores or one per scheduler job.

use std::path::Path;
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::de::IgnoredAny;

use super::{BatchError, Manifest, TaskResult, parallel_map, read_manifest, run_dir, task_path};
use crate::run::{RunOptions, simulate, write_outputs};
use crate::scene::Scene;

/// What running a task did.
#[derive(Clone, Debug, PartialEq)]
pub enum TaskStatus {
    /// The task ran; its result is written.
    Ran(Box<TaskResult>),
    /// Its result was already there (made from the same task file): nothing ran.
    AlreadyDone,
}

/// Runs task `index` of the batch in `dir`, writes its outputs into its run folder and then
/// `dir/results/<index>.json`, unless a result of the same task file is already there.
pub fn run_task(dir: &Path, index: usize) -> Result<TaskStatus, BatchError> {
    let manifest: Manifest<IgnoredAny> = read_manifest(dir)?;
    let tasks = manifest.tasks;
    if index >= tasks {
        return Err(BatchError::NoSuchTask {
            dir: dir.to_path_buf(),
            index,
            count: tasks,
        });
    }
    if TaskResult::read_current(dir, index)?.is_some() {
        return Ok(TaskStatus::AlreadyDone);
    }
    let path = task_path(dir, index);
    let text = std::fs::read_to_string(&path).map_err(|e| BatchError::io(&path, e))?;
    let scene = Scene::from_text(&text, path, &[])?;
    let outcome = simulate(&scene, &RunOptions::default());
    write_outputs(&scene, &outcome, &run_dir(dir, &manifest, index)).map_err(BatchError::Output)?;
    let finite = outcome.positions.iter().all(|p| p.is_finite());
    let result = TaskResult {
        task: index,
        task_text: text,
        metrics: outcome.metrics,
        positions_m: finite.then_some(outcome.positions),
    };
    result.write(dir)?;
    Ok(TaskStatus::Ran(Box::new(result)))
}

/// Runs every unfinished task of the batch in `dir` (`tasks` of them), `threads` at a time, each
/// on one thread; `on_done(finished, total)` reports progress (finished tasks count from the
/// start). Returns the tasks that could not run, with why.
pub fn run_tasks(
    dir: &Path,
    tasks: usize,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Vec<(usize, BatchError)> {
    let finished = AtomicUsize::new(0);
    on_done(0, tasks);
    let outcomes = parallel_map(tasks, threads, |k| {
        let outcome = run_task(dir, k);
        on_done(finished.fetch_add(1, Ordering::Relaxed) + 1, tasks);
        outcome
    });
    (0..tasks)
        .zip(outcomes)
        .filter_map(|(k, outcome)| outcome.err().map(|e| (k, e)))
        .collect()
}

/// [`run_tasks`], with the first task that could not run as the error.
pub fn run_all(
    dir: &Path,
    tasks: usize,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<(), BatchError> {
    match run_tasks(dir, tasks, threads, on_done).into_iter().next() {
        Some((_, e)) => Err(e),
        None => Ok(()),
    }
}
