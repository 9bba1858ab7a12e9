//! Errors of loading a scene: file, syntax, a field's value, the fabric it names, a `--set`.

use std::path::PathBuf;

use crate::material::FabricLoadError;

/// Loading or validating a scene failed.
#[derive(Debug, thiserror::Error)]
pub enum SceneError {
    /// The scene file could not be read.
    #[error("{}: cannot read scene file: {source}", path.display())]
    Io {
        /// The scene file.
        path: PathBuf,
        /// The I/O failure.
        source: std::io::Error,
    },
    /// Not valid RON for the scene schema (syntax, unknown or missing field, wrong type).
    #[error("{}:{line}:{column}: {message}", path.display())]
    Syntax {
        /// The scene file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        column: usize,
        /// The parser's message, naming the field where it knows it.
        message: String,
    },
    /// A value is out of its physical or numerical range.
    #[error("{}: field `{field}` = {value}: {reason}", path.display())]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// Path of the field, e.g. `integration.dt_s`.
        field: String,
        /// The offending value.
        value: String,
        /// The allowed range or rule.
        reason: String,
    },
    /// The explicit step is longer than the stability guard allows (`docs/model.md` §10).
    #[error("{}: field `integration.dt_s` = {dt_s}: {reason}", path.display())]
    StepTooLong {
        /// The scene file.
        path: PathBuf,
        /// The scene's step (s).
        dt_s: f64,
        /// The effect with the tightest limit, as scenes and metrics name it.
        effect: &'static str,
        /// That effect's largest stable step (s).
        max_step_s: f64,
        /// The allowed range, the effect, and the ways out.
        reason: String,
    },
    /// The fabric the scene names could not be loaded.
    #[error("{}: field `fabric`: {source}", path.display())]
    Fabric {
        /// The scene file.
        path: PathBuf,
        /// Why the fabric failed.
        source: FabricLoadError,
    },
    /// A `--set KEY=VALUE` override does not fit the schema.
    #[error("{}: --set {assignment}: {reason}", path.display())]
    Override {
        /// The scene file.
        path: PathBuf,
        /// The override as given.
        assignment: String,
        /// What is wrong with it.
        reason: String,
    },
}
