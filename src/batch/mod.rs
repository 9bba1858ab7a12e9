//! Batches of independent runs (a study's grid, a convergence's spacings) as task files, so that
//! any scheduler can run them: this machine's cores, a Slurm job array, a Kubernetes Indexed Job.
//!
//! A batch lives in one folder, `DIR`, and goes through three phases:
//!
//! 1. **Plan** ([`write_plan`]): `DIR/manifest.json` says what the batch is and how its results
//!    combine (the layout, e.g. a study's grid and reference); `DIR/tasks/K.ron` (K = 0, 1, …)
//!    is each run as a self-contained scene file, overrides applied and the fabric written
//!    inline, so that it runs on a machine without the original scene or fabric files
//!    (`kes-cloth run DIR/tasks/K.ron` runs it like any scene).
//! 2. **Tasks** ([`run_task`], [`run_tasks`] on a thread pool): task K runs its scene, writes
//!    the run's outputs (`metrics.json`, pictures, mesh, report, as `kes-cloth run` does) into
//!    its run folder ([`run_dir`]: `DIR/runs/K/`, `DIR/seed-K/` for repeats), then
//!    `DIR/results/K.json` (its metrics and final node positions, in SI) to a temporary file
//!    renamed into place, so a task killed mid-run leaves no result, never a torn one. A result
//!    records the task file it was made from: re-running a finished task does nothing, and a
//!    result left by another plan in the same folder is ignored and replaced.
//! 3. **Collect** ([`load_results`]): whatever has finished, in task order, with the tasks still
//!    missing; [`collect`] combines them as the batch's kind ([`BatchLayout`]) does, into its
//!    tables and plots.
//!
//! Tasks may run in any order, on any machine that sees `DIR`, any number of times: a run
//! depends only on its task file, so the collected results equal a local run's, wall-clock
//! times aside.

mod batch_error;
mod kinds;
mod manifest;
mod task_result;
mod task_runner;
mod thread_pool;

pub use batch_error::BatchError;
pub use kinds::{BatchLayout, Collected, collect};
pub use manifest::{MANIFEST_FILE, Manifest, read_manifest, run_dir, task_path, write_plan};
pub use task_result::{TaskResult, load_results, result_path};
pub use task_runner::{TaskStatus, run_all, run_task, run_tasks};
pub use thread_pool::parallel_map;
