//! What can go wrong planning, running or collecting a batch.

use std::path::PathBuf;

use crate::scene::SceneError;

/// A batch operation that failed, naming the file at fault.
#[derive(Debug, thiserror::Error)]
pub enum BatchError {
    /// A file of the batch could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file or folder.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
    /// A manifest, task or result file is not what kes-cloth writes.
    #[error("{}: {reason}", path.display())]
    Malformed {
        /// The file.
        path: PathBuf,
        /// What is wrong with it.
        reason: String,
    },
    /// A task index outside the plan.
    #[error("{}: task {index} does not exist: the plan has tasks 0 to {} ({count} in all)", dir.display(), count.saturating_sub(1))]
    NoSuchTask {
        /// The batch folder.
        dir: PathBuf,
        /// The index asked for.
        index: usize,
        /// Tasks in the plan.
        count: usize,
    },
    /// Results still missing where every task must have finished.
    #[error("{}: tasks {missing:?} have not finished: run them (`kes-cloth task DIR K`) and collect again", dir.display())]
    Unfinished {
        /// The batch folder.
        dir: PathBuf,
        /// The tasks without a result.
        missing: Vec<usize>,
    },
    /// A run's outputs could not be written.
    #[error(transparent)]
    Output(#[from] crate::output::OutputError),
    /// A task's scene (or the scene being planned) is invalid.
    #[error(transparent)]
    Scene(#[from] SceneError),
}

impl BatchError {
    /// An I/O error on `path`.
    pub(crate) fn io(path: impl Into<PathBuf>, source: std::io::Error) -> Self {
        Self::Io {
            path: path.into(),
            source,
        }
    }

    /// A file whose content is not what kes-cloth writes.
    pub(crate) fn malformed(path: impl Into<PathBuf>, reason: impl std::fmt::Display) -> Self {
        Self::Malformed {
            path: path.into(),
            reason: reason.to_string(),
        }
    }
}
