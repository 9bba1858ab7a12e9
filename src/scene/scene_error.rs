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
    #[error("{}{}: field `{field}` = {value}: {reason}", path.display(), place(at))]
    Invalid {
        /// The scene file.
        path: PathBuf,
        /// 1-based line and column of the field in the file, where the file writes it (not for
        /// a default or a `--set` value).
        at: Option<(u32, u32)>,
        /// Path of the field, e.g. `integration.dt_s`.
        field: String,
        /// The offending value.
        value: String,
        /// The allowed range or rule.
        reason: String,
    },
    /// The explicit step is longer than the stability guard allows (`docs/model.md` §10).
    #[error("{}{}: field `integration.dt_s` = {dt_s}: {reason}", path.display(), place(at))]
    StepTooLong {
        /// The scene file.
        path: PathBuf,
        /// 1-based line and column of `integration.dt_s` in the file, where the file writes it.
        at: Option<(u32, u32)>,
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

/// `:line:column` of a located field, nothing otherwise.
fn place(at: &Option<(u32, u32)>) -> String {
    at.map_or(String::new(), |(line, column)| format!(":{line}:{column}"))
}

impl SceneError {
    /// An invalid `field` of the scene at `path` (a command-line option counts as a field), its
    /// `value` and the `reason` (the allowed range), with no place in the file.
    pub fn invalid(path: &std::path::Path, field: &str, value: impl Into<String>, reason: &str) -> Self {
        SceneError::Invalid {
            path: path.to_path_buf(),
            at: None,
            field: field.to_string(),
            value: value.into(),
            reason: reason.to_string(),
        }
    }

    /// The same error, with an invalid field's (or a refused step's) place in the scene `text`
    /// filled in, unless one of `overrides` (`KEY=VALUE`) set that field (its value then is not
    /// the file's).
    pub(crate) fn located(self, text: &str, overrides: &[String]) -> Self {
        let place_of = |field: &str| {
            let dotted = field.replace('[', ".").replace(']', "");
            let overridden = overrides.iter().any(|o| {
                let key = o.split_once('=').map_or(o.as_str(), |(k, _)| k).trim();
                dotted == key
                    || dotted.starts_with(&format!("{key}."))
                    || key.starts_with(&format!("{dotted}."))
            });
            if overridden {
                None
            } else {
                super::field_location::locate_field(text, field).map(|(l, c)| (l as u32, c as u32))
            }
        };
        match self {
            SceneError::Invalid {
                path,
                at: None,
                field,
                value,
                reason,
            } => SceneError::Invalid {
                path,
                at: place_of(&field),
                field,
                value,
                reason,
            },
            SceneError::StepTooLong {
                path,
                at: None,
                dt_s,
                effect,
                max_step_s,
                reason,
            } => SceneError::StepTooLong {
                path,
                at: place_of("integration.dt_s"),
                dt_s,
                effect,
                max_step_s,
                reason,
            },
            other => other,
        }
    }
}
