//! Phase 1, the plan: `manifest.json` and one self-contained scene file per task.

use std::path::{Path, PathBuf};

use serde::Serialize;
use serde::de::DeserializeOwned;

use super::BatchError;
use crate::material::Fabric;
use crate::scene::{FabricSource, Scene};

/// The manifest's file name inside a batch folder.
pub const MANIFEST_FILE: &str = "manifest.json";

/// Format version of a batch folder; another version is refused.
const FORMAT: u32 = 1;

/// What a batch is: how many tasks, and how their results combine.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Manifest<L> {
    /// Format version of the folder.
    pub format: u32,
    /// The scene file the batch was planned from (for messages: tasks never read it).
    pub scene_path: PathBuf,
    /// Number of tasks, numbered 0 to `tasks` − 1.
    pub tasks: usize,
    /// Task K's outputs go into `DIR/<run_folder>K/` (e.g. `runs/`, `seed-`).
    pub run_folder: String,
    /// How the results combine (a study's grid and reference, a convergence's spacings).
    pub layout: L,
}

impl<L> Manifest<L> {
    /// A manifest of `tasks` tasks planned from `scene_path`, their outputs in `DIR/runs/K/`.
    pub fn new(scene_path: &Path, tasks: usize, layout: L) -> Self {
        Self {
            format: FORMAT,
            scene_path: scene_path.to_path_buf(),
            tasks,
            run_folder: "runs/".to_string(),
            layout,
        }
    }

    /// The same manifest with its layout mapped by `f`.
    pub fn map<M>(self, f: impl FnOnce(L) -> M) -> Manifest<M> {
        Manifest {
            format: self.format,
            scene_path: self.scene_path,
            tasks: self.tasks,
            run_folder: self.run_folder,
            layout: f(self.layout),
        }
    }
}

/// The folder of task `index`'s outputs in the batch folder `dir`.
pub fn run_dir<L>(dir: &Path, manifest: &Manifest<L>, index: usize) -> PathBuf {
    dir.join(format!("{}{index}", manifest.run_folder))
}

/// The file of task `index` in the batch folder `dir`: `dir/tasks/<index>.ron`.
pub fn task_path(dir: &Path, index: usize) -> PathBuf {
    dir.join("tasks").join(format!("{index}.ron"))
}

/// Writes the plan into `dir`: one task file per scene (task K is `scenes[K]`) and the manifest,
/// last, so a folder with a manifest has all its tasks. Task files of a larger earlier plan in
/// the same folder are removed. With `resume`, results already in the folder are kept (each
/// names the task file it was made from, so only those of unchanged tasks count and their tasks
/// do not run again); without, they are removed and every task runs.
pub fn write_plan<L: Serialize>(
    dir: &Path,
    manifest: &Manifest<L>,
    scenes: &[Scene],
    resume: bool,
) -> Result<(), BatchError> {
    let tasks = dir.join("tasks");
    std::fs::create_dir_all(&tasks).map_err(|e| BatchError::io(&tasks, e))?;
    let results = dir.join("results");
    if !resume && results.exists() {
        std::fs::remove_dir_all(&results).map_err(|e| BatchError::io(&results, e))?;
    }
    std::fs::create_dir_all(&results).map_err(|e| BatchError::io(&results, e))?;
    for (k, scene) in scenes.iter().enumerate() {
        let path = task_path(dir, k);
        let text = task_text(scene, k)?;
        if std::fs::read_to_string(&path).ok().as_deref() != Some(text.as_str()) {
            write_atomically(&path, text.as_bytes())?;
        }
    }
    let listing = std::fs::read_dir(&tasks).map_err(|e| BatchError::io(&tasks, e))?;
    for entry in listing.flatten() {
        let name = entry.file_name();
        let index = name
            .to_str()
            .and_then(|n| n.strip_suffix(".ron"))
            .and_then(|n| n.parse::<usize>().ok());
        if index.is_some_and(|k| k >= scenes.len()) {
            std::fs::remove_file(entry.path()).map_err(|e| BatchError::io(entry.path(), e))?;
        }
    }
    let text = serde_json::to_string_pretty(manifest)
        .map_err(|e| BatchError::malformed(dir.join(MANIFEST_FILE), e))?;
    write_atomically(&dir.join(MANIFEST_FILE), (text + "\n").as_bytes())
}

/// Reads the manifest of the batch folder `dir`.
pub fn read_manifest<L: DeserializeOwned>(dir: &Path) -> Result<Manifest<L>, BatchError> {
    let path = dir.join(MANIFEST_FILE);
    let text = std::fs::read_to_string(&path).map_err(|e| BatchError::io(&path, e))?;
    let manifest: Manifest<L> = serde_json::from_str(&text).map_err(|e| BatchError::malformed(&path, e))?;
    if manifest.format != FORMAT {
        return Err(BatchError::malformed(
            &path,
            format!(
                "format {} (this kes-cloth reads format {FORMAT}): plan the batch again",
                manifest.format
            ),
        ));
    }
    Ok(manifest)
}

/// Task `index`'s file: the scene as it will run, its fabric written inline in KES units.
fn task_text(scene: &Scene, index: usize) -> Result<String, BatchError> {
    let mut spec = scene.spec.clone();
    if let FabricSource::File(file) = &spec.fabric {
        let base = scene.path.parent().unwrap_or(Path::new("."));
        let (kes, _) =
            Fabric::load_with_kes(base.join(file)).map_err(|source| crate::scene::SceneError::Fabric {
                path: scene.path.clone(),
                source,
            })?;
        spec.fabric = FabricSource::Inline(Box::new(kes));
    }
    let body = ron::ser::to_string_pretty(&spec, ron::ser::PrettyConfig::default())
        .map_err(|e| BatchError::malformed(&scene.path, format!("cannot be written as a task: {e}")))?;
    Ok(format!(
        "// Task {index} of a kes-cloth batch planned from {}.\n\
         // The scene as it runs, overrides applied, its fabric inline (KES units).\n\
         // `kes-cloth task DIR {index}` runs it.\n{body}\n",
        scene.path.display()
    ))
}

/// Writes `bytes` to `path` through a temporary file beside it and a rename, so that a reader
/// (or a task killed while writing) never sees a partial file.
pub(super) fn write_atomically(path: &Path, bytes: &[u8]) -> Result<(), BatchError> {
    let name = path.file_name().and_then(|n| n.to_str()).unwrap_or("file");
    let partial = path.with_file_name(format!(".{name}.{}.partial", std::process::id()));
    std::fs::write(&partial, bytes).map_err(|e| BatchError::io(&partial, e))?;
    std::fs::rename(&partial, path).map_err(|e| BatchError::io(path, e))
}
