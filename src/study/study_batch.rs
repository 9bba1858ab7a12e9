//! A study as a batch ([`crate::batch`]): its plan (grid points × placements, and the
//! reference) as tasks, and its rows collected from whatever tasks have finished.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::shape_error::ReferenceSurface;
use super::study_plan::same_value;
use super::{Refusal, RefusedPoint, Study, StudyPlan, StudyRow, aggregate, placed_runs};
use crate::batch::{BatchError, Manifest, TaskResult, load_results, task_path};
use crate::output::Metrics;
use crate::scene::{ClothShape, Scene, SceneError};

/// How a study's tasks combine: grid point g's runs are tasks g·placements to
/// (g + 1)·placements − 1; the reference's are those of group `reference_group`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct StudyLayout {
    /// Scene name.
    pub scene: String,
    /// The varied keys, in `--vary` order.
    pub keys: Vec<String>,
    /// The reference's overrides (`KEY=VALUE`).
    pub reference_setting: Vec<String>,
    /// Runs per grid point and for the reference.
    pub placements: usize,
    /// The grid points that run, in grid order.
    pub settings: Vec<Vec<(String, String)>>,
    /// Per grid point: whether every varied key has the scene's own value.
    pub is_default: Vec<bool>,
    /// The reference's group: a grid point's index when the reference is one of them, else
    /// `settings.len()` (its own runs, after the grid's).
    pub reference_group: usize,
    /// Grid points not run, and why.
    pub refused: Vec<RefusedPoint>,
}

impl StudyLayout {
    /// Groups of runs: the grid points and, unless it is one of them, the reference.
    fn groups(&self) -> usize {
        self.settings.len().max(self.reference_group + 1)
    }
}

/// Plans the study of the scene at `path` (with `base` overrides on every run): its manifest and
/// the scene of every task, in task order.
pub fn plan_study(
    path: &Path,
    base: &[String],
    plan: &StudyPlan,
) -> Result<(Manifest<StudyLayout>, Vec<Scene>), SceneError> {
    let group = plan.placements.max(1);
    // The scene as given only names the study and marks the shipped setting; it is not run, so
    // a step its own spacing would refuse does not stop a study that varies both.
    let base_scene = match Scene::load(path, base) {
        Err(SceneError::StepTooLong { .. }) => {
            let unguarded: Vec<String> = base
                .iter()
                .cloned()
                .chain(["integration.step_guard=false".to_string()])
                .collect();
            Scene::load(path, &unguarded)?
        }
        loaded => loaded?,
    };
    if group > 1 && !matches!(base_scene.spec.cloth.shape, ClothShape::Circle { .. }) {
        return Err(SceneError::Invalid {
            path: base_scene.path.clone(),
            at: None,
            field: "cloth.shape".to_string(),
            value: format!("{:?}", base_scene.spec.cloth.shape),
            reason: "--placements applies to circular cloths: a rectangle's lattice fills its outline"
                .to_string(),
        });
    }
    let mut settings = Vec::new();
    let mut refused = Vec::new();
    let mut points = Vec::new();
    for setting in plan.settings() {
        let sets: Vec<String> = base
            .iter()
            .cloned()
            .chain(setting.iter().map(|(k, v)| format!("{k}={v}")))
            .collect();
        match Scene::load(path, &sets) {
            Ok(scene) => {
                points.push(scene);
                settings.push(setting);
            }
            Err(SceneError::StepTooLong {
                effect, max_step_s, ..
            }) => refused.push(RefusedPoint {
                setting,
                why: Refusal::StepTooLong {
                    effect: effect.to_string(),
                    max_step_s,
                },
            }),
            // A point only some combinations make invalid (a step too long for explicit damping
            // next to implicit points that take it) is listed, not fatal; if every point is
            // refused the study stops below with the reasons.
            Err(SceneError::Invalid {
                field, value, reason, ..
            }) => refused.push(RefusedPoint {
                setting,
                why: Refusal::Invalid {
                    field,
                    message: format!("{value}: {reason}"),
                },
            }),
            Err(e) => return Err(e),
        }
    }
    let reference_sets: Vec<String> = base.iter().chain(&plan.reference).cloned().collect();
    let reference_scene = Scene::load(path, &reference_sets)?;
    if settings.is_empty() {
        let refused: Vec<String> = refused
            .iter()
            .map(|r| format!("{:?} ({})", r.setting, r.why))
            .collect();
        return Err(SceneError::Invalid {
            path: base_scene.path.clone(),
            at: None,
            field: "integration.dt_s".to_string(),
            value: "every grid point".to_string(),
            reason: format!("every grid point is refused: {}", refused.join("; ")),
        });
    }
    // A grid point that is the reference (same resolved scene) is not run twice.
    let reference_group = match points.iter().position(|s| s.spec == reference_scene.spec) {
        Some(g) => g,
        None => {
            points.push(reference_scene);
            settings.len()
        }
    };
    let is_default = settings
        .iter()
        .map(|setting| {
            setting
                .iter()
                .all(|(k, v)| same_value(base_scene.field(k).as_ref(), v))
        })
        .collect();
    let mut scenes = Vec::with_capacity(points.len() * group);
    for point in &points {
        scenes.extend(placed_runs(point, group)?);
    }
    let layout = StudyLayout {
        scene: base_scene.spec.name.clone(),
        keys: plan.vary.iter().map(|v| v.key.clone()).collect(),
        reference_setting: plan.reference.clone(),
        placements: group,
        settings,
        is_default,
        reference_group,
        refused,
    };
    Ok((Manifest::new(path, scenes.len(), layout), scenes))
}

/// The study of the batch in `dir` from whatever tasks have finished: a grid point with a run
/// still missing is left out, and without the reference's runs no errors are given; the tasks
/// still missing are listed in [`Study::missing`].
pub fn collect_study(dir: &Path, manifest: &Manifest<StudyLayout>) -> Result<Study, BatchError> {
    let layout = &manifest.layout;
    let group = layout.placements.max(1);
    let (results, missing) = load_results(dir, manifest.tasks)?;
    let expected = layout.groups() * group;
    if manifest.tasks != expected {
        return Err(BatchError::malformed(
            dir.join(crate::batch::MANIFEST_FILE),
            format!(
                "{} tasks for {} groups of {group} runs",
                manifest.tasks,
                layout.groups()
            ),
        ));
    }
    // A group's results, if all of its runs have finished.
    let finished = |g: usize| -> Option<Vec<&TaskResult>> {
        results[g * group..(g + 1) * group]
            .iter()
            .map(Option::as_ref)
            .collect()
    };
    let reference_runs = finished(layout.reference_group);
    let (reference, reference_dc_std) = match &reference_runs {
        Some(runs) => {
            let (m, sd) = aggregate(&metrics_of(runs));
            (Some(m), sd)
        }
        None => (None, None),
    };
    // Against a failed (or missing) reference there is nothing to measure errors from.
    let comparable = reference.as_ref().filter(|r| r.failure.is_none());
    let surface = match (&reference_runs, comparable) {
        (Some(runs), Some(_)) => reference_surface(dir, layout.reference_group * group, runs[0])?,
        _ => None,
    };
    let mut rows = Vec::new();
    for (g, setting) in layout.settings.iter().enumerate() {
        let Some(runs) = finished(g) else { continue };
        let (m, dc_std) = aggregate(&metrics_of(&runs));
        let ok = m.failure.is_none();
        let error = |f: fn(&Metrics) -> Option<f64>| match (f(&m), comparable.and_then(f)) {
            (Some(a), Some(b)) if ok => Some((a - b).abs()),
            _ => None,
        };
        let shape_error_m = surface.as_ref().filter(|_| ok).map(|s| {
            runs.iter()
                .map(|r| r.positions_m.as_deref().map_or(f64::NAN, |p| s.rms_distance(p)))
                .sum::<f64>()
                / runs.len() as f64
        });
        rows.push(StudyRow {
            setting: setting.clone(),
            dc_error: error(|m| m.drape_coefficient),
            hang_error_m: error(|m| m.hang_corners_m),
            chord_error_deg: error(|m| m.cantilever_chord_deg),
            shape_error_m,
            metrics: m,
            dc_std,
            is_default: layout.is_default[g],
        });
    }
    Ok(Study {
        scene: layout.scene.clone(),
        keys: layout.keys.clone(),
        reference_setting: layout.reference_setting.clone(),
        reference,
        reference_dc_std,
        placements: group,
        rows,
        refused: layout.refused.clone(),
        missing,
    })
}

/// The metrics of a group's runs.
fn metrics_of<'a>(runs: &[&'a TaskResult]) -> Vec<&'a Metrics> {
    runs.iter().map(|r| &r.metrics).collect()
}

/// The draped surface of the reference's first run (task `task`), its woven grid rebuilt from
/// its task file.
fn reference_surface(
    dir: &Path,
    task: usize,
    run: &TaskResult,
) -> Result<Option<ReferenceSurface>, BatchError> {
    let Some(positions) = &run.positions_m else {
        return Ok(None);
    };
    let scene = Scene::from_text(&run.task_text, task_path(dir, task), &[])?;
    let (topology, _) = crate::scene::spawn::cloth_grid(&scene);
    Ok(ReferenceSurface::new(&topology, positions))
}
