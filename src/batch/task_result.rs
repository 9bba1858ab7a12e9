//! Phase 3's input: each finished task's `results/K.json`.

use std::path::{Path, PathBuf};

use glam::DVec3;
use serde::{Deserialize, Serialize};

use super::{BatchError, task_path};
use crate::output::Metrics;

/// What one task leaves: its metrics and where its nodes came to rest.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct TaskResult {
    /// The task's index.
    pub task: usize,
    /// The task file's text the run was made from: a result counts only for that very task.
    pub task_text: String,
    /// The run's metrics (all SI, units in the keys, as `metrics.json`).
    pub metrics: Metrics,
    /// Final node positions (m), in node order; absent when one is not finite (a failed run).
    pub positions_m: Option<Vec<DVec3>>,
}

/// The file of task `index`'s result in the batch folder `dir`: `dir/results/<index>.json`.
pub fn result_path(dir: &Path, index: usize) -> PathBuf {
    dir.join("results").join(format!("{index}.json"))
}

impl TaskResult {
    /// Reads task `index`'s result if it exists and was made from the task file as it is now;
    /// `Ok(None)` when there is none yet (or only one of another plan).
    pub fn read_current(dir: &Path, index: usize) -> Result<Option<Self>, BatchError> {
        let path = result_path(dir, index);
        let text = match std::fs::read_to_string(&path) {
            Ok(t) => t,
            Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(None),
            Err(e) => return Err(BatchError::io(&path, e)),
        };
        let result: Self = serde_json::from_str(&text).map_err(|e| BatchError::malformed(&path, e))?;
        let task = task_path(dir, index);
        let current = std::fs::read_to_string(&task).map_err(|e| BatchError::io(&task, e))?;
        Ok((result.task_text == current).then_some(result))
    }

    /// Writes the result to `dir/results/<task>.json` through a temporary file and a rename.
    pub fn write(&self, dir: &Path) -> Result<(), BatchError> {
        let path = result_path(dir, self.task);
        let text = serde_json::to_string(self).map_err(|e| BatchError::malformed(&path, e))?;
        super::manifest::write_atomically(&path, (text + "\n").as_bytes())
    }
}

/// Every task's current result in the batch folder `dir` of `tasks` tasks, in task order
/// (`None` for a task not finished), and the indices of those missing.
pub fn load_results(dir: &Path, tasks: usize) -> Result<(Vec<Option<TaskResult>>, Vec<usize>), BatchError> {
    let results = (0..tasks)
        .map(|k| TaskResult::read_current(dir, k))
        .collect::<Result<Vec<_>, _>>()?;
    let missing = (0..tasks).filter(|&k| results[k].is_none()).collect();
    Ok((results, missing))
}
