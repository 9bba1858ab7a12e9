//! Why a checkpoint could not be written or resumed.

use std::path::PathBuf;

/// Writing, reading or restoring a checkpoint failed.
#[derive(Debug, thiserror::Error)]
pub enum CheckpointError {
    /// The file could not be read or written.
    #[error("{}: {source}", path.display())]
    Io {
        /// The checkpoint file.
        path: PathBuf,
        /// The system error.
        source: std::io::Error,
    },
    /// The state could not be encoded.
    #[error("{}: cannot encode the checkpoint: {message}", path.display())]
    Encode {
        /// The checkpoint file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The file is not a checkpoint this build can read.
    #[error("{}: not a kes-cloth checkpoint this build can read: {message}", path.display())]
    Decode {
        /// The checkpoint file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The scene as loaded now does not fit the checkpoint (e.g. its fabric file changed).
    #[error("the checkpoint does not fit the scene as loaded now: {0} differs")]
    Mismatch(&'static str),
    /// The scene recorded in the checkpoint no longer loads (e.g. its fabric file moved).
    #[error("{0}")]
    Scene(Box<crate::scene::SceneError>),
    /// The world lacks a part every running scene has.
    #[error("the world has no {0}")]
    Missing(&'static str),
}
