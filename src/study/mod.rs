//! `kes-cloth study`: what accuracy costs in time, measured on a real scene.
//!
//! A study runs one scene across a grid of settings (`--vary KEY=V1,V2,...`, any scene field),
//! in parallel, and compares every run with a converged reference (`--reference KEY=V ...`, e.g.
//! the finest spacing and smallest step): the drape coefficient's error, the shape error (RMS
//! distance of the run's nodes from the reference's draped surface), the node count, strain,
//! whether it settled, and the wall time it took. [`write_study`] writes `study.csv`,
//! `study.md` and `work_precision.png` (error against wall time, log–log, one curve per varied
//! key, the scene's own setting marked).

mod shape_error;
mod study_plan;
mod study_report;
mod work_precision_plot;

use std::path::Path;

pub use shape_error::ReferenceSurface;
pub use study_plan::{StudyPlan, Vary};
pub use study_report::write_study;

use crate::output::Metrics;
use crate::repeat::simulate_all;
use crate::scene::{Scene, SceneError};

/// One run of a study.
#[derive(Clone, Debug)]
pub struct StudyRow {
    /// The varied keys' values of this run, in `--vary` order.
    pub setting: Vec<(String, String)>,
    /// Its metrics.
    pub metrics: Metrics,
    /// |DC − DC_reference| (dimensionless), for drapemeter scenes.
    pub dc_error: Option<f64>,
    /// |corner hang − reference corner hang| (m), for tablecloth scenes.
    pub hang_error_m: Option<f64>,
    /// RMS distance of this run's nodes from the reference's draped surface (m).
    pub shape_error_m: Option<f64>,
    /// Whether every varied key has the scene's own value (the shipped default).
    pub is_default: bool,
}

/// A finished study.
#[derive(Clone, Debug)]
pub struct Study {
    /// Scene name.
    pub scene: String,
    /// The varied keys, in `--vary` order.
    pub keys: Vec<String>,
    /// The reference's overrides (`KEY=VALUE`).
    pub reference_setting: Vec<String>,
    /// The reference's metrics.
    pub reference: Metrics,
    /// One row per grid point, in grid order (the last key varies fastest).
    pub rows: Vec<StudyRow>,
}

/// Runs the study of the scene at `path` (with `base` overrides on every run) on `threads`
/// threads; `on_done(finished, total)` reports progress.
pub fn run_study(
    path: &Path,
    base: &[String],
    plan: &StudyPlan,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<Study, SceneError> {
    let base_scene = Scene::load(path, base)?;
    let settings = plan.settings();
    let mut scenes = Vec::with_capacity(settings.len() + 1);
    for setting in &settings {
        let sets: Vec<String> = base
            .iter()
            .cloned()
            .chain(setting.iter().map(|(k, v)| format!("{k}={v}")))
            .collect();
        scenes.push(Scene::load(path, &sets)?);
    }
    let reference_sets: Vec<String> = base.iter().chain(&plan.reference).cloned().collect();
    let reference_scene = Scene::load(path, &reference_sets)?;
    // A grid point that is the reference (same resolved scene) is not run twice.
    let reused = scenes.iter().position(|s| s.spec == reference_scene.spec);
    if reused.is_none() {
        scenes.push(reference_scene);
    }
    let total = scenes.len();
    let finished = std::sync::atomic::AtomicUsize::new(0);
    let outcomes = simulate_all(&scenes, threads, |_, _| {
        let done = finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        on_done(done, total);
    });
    let reference_outcome = &outcomes[reused.unwrap_or(settings.len())];
    let surface = ReferenceSurface::new(&reference_outcome.topology, &reference_outcome.positions);
    let reference = reference_outcome.metrics.clone();
    let rows = settings
        .into_iter()
        .zip(&outcomes)
        .map(|(setting, outcome)| {
            let m = &outcome.metrics;
            let dc_error = match (m.drape_coefficient, reference.drape_coefficient) {
                (Some(a), Some(b)) if m.failure.is_none() => Some((a - b).abs()),
                _ => None,
            };
            let hang_error_m = match (m.hang_corners_m, reference.hang_corners_m) {
                (Some(a), Some(b)) if m.failure.is_none() => Some((a - b).abs()),
                _ => None,
            };
            let shape_error_m = (m.failure.is_none())
                .then(|| surface.as_ref().map(|s| s.rms_distance(&outcome.positions)))
                .flatten();
            let is_default = setting
                .iter()
                .all(|(k, v)| study_plan::same_value(base_scene.field(k).as_ref(), v));
            StudyRow {
                setting,
                metrics: m.clone(),
                dc_error,
                hang_error_m,
                shape_error_m,
                is_default,
            }
        })
        .collect();
    Ok(Study {
        scene: base_scene.spec.name.clone(),
        keys: plan.vary.iter().map(|v| v.key.clone()).collect(),
        reference_setting: plan.reference.clone(),
        reference,
        rows,
    })
}
