//! `kes-cloth study`: what accuracy costs in time, measured on a real scene.
//!
//! A study runs one scene across a grid of settings (`--vary KEY=V1,V2,...`, any scene field),
//! in parallel, and compares every run with a converged reference (`--reference KEY=V ...`, e.g.
//! the finest spacing and smallest step): the drape coefficient's error, the shape error (RMS
//! distance of the run's nodes from the reference's draped surface), the node count, strain,
//! whether it settled, and the wall time it took. [`write_study`] writes `study.csv`,
//! `study.md` and `work_precision.png` (error against wall time, log–log, one curve per varied
//! key, the scene's own setting marked).

mod convergence;
mod convergence_report;
pub mod heavy_elastica;
pub mod richardson;
mod shape_error;
mod study_plan;
mod study_report;
mod work_precision_plot;

use std::path::Path;

pub use convergence::{Convergence, ConvergencePlan, ConvergenceRow, run_convergence};
pub use convergence_report::{extrapolation_line, write_convergence};
pub use shape_error::ReferenceSurface;
pub use study_plan::{StudyPlan, Vary};
pub use study_report::write_study;

use crate::output::Metrics;
use crate::repeat::{repeat_scenes, simulate_all, summarise};
use crate::run::RunOutcome;
use crate::scene::{ClothShape, Scene, SceneError};

/// One grid point of a study.
#[derive(Clone, Debug)]
pub struct StudyRow {
    /// The varied keys' values of this run, in `--vary` order.
    pub setting: Vec<(String, String)>,
    /// Its metrics; over several placements, those of the first run with DC, corner hang and
    /// wall time replaced by their means, nodes by the modal count, strain by the largest,
    /// `settled` true only if every run settled (the settle time then the slowest run's), and
    /// `failure` the first run's that failed. Placements set each run's seed and lattice offset,
    /// so a `seed` or `cloth.lattice_offset_m` in the grid or in `--set` is overridden.
    pub metrics: Metrics,
    /// Sample standard deviation of DC over the placements (dimensionless; 0 for one run).
    pub dc_std: Option<f64>,
    /// |DC − DC_reference| (dimensionless), for drapemeter scenes (means over placements).
    pub dc_error: Option<f64>,
    /// |corner hang − reference corner hang| (m), for tablecloth scenes.
    pub hang_error_m: Option<f64>,
    /// RMS distance of this run's nodes from the reference's draped surface (m; over
    /// placements, the mean of each run's distance from the reference's first run).
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
    /// The reference's metrics (aggregated over placements as for a row).
    pub reference: Metrics,
    /// Sample standard deviation of the reference's DC over its placements.
    pub reference_dc_std: Option<f64>,
    /// Runs per grid point and for the reference.
    pub placements: usize,
    /// One row per grid point, in grid order (the last key varies fastest).
    pub rows: Vec<StudyRow>,
    /// Grid points not run: the stability guard refused them (an explicit step too long for
    /// the spacing), or another rule did (e.g. explicit damping too strong for the step).
    pub refused: Vec<RefusedPoint>,
}

impl Study {
    /// Whether the study's scene is judged by DC (a drapemeter) rather than by corner hang (a
    /// tablecloth): any run or the reference measured a drape coefficient.
    pub fn is_drapemeter(&self) -> bool {
        self.reference.drape_coefficient.is_some()
            || self.rows.iter().any(|r| r.metrics.drape_coefficient.is_some())
    }
}

/// A grid point not run, and why.
#[derive(Clone, Debug)]
pub struct RefusedPoint {
    /// The varied keys' values, in `--vary` order.
    pub setting: Vec<(String, String)>,
    /// The rule that refused it.
    pub why: Refusal,
}

/// Why a grid point was not run.
#[derive(Clone, Debug, PartialEq)]
pub enum Refusal {
    /// The stability guard: the explicit `effect` needs a step of at most `max_step_s` (s).
    StepTooLong {
        /// The effect with the tightest limit.
        effect: &'static str,
        /// Its largest stable step (s).
        max_step_s: f64,
    },
    /// Any other validation rule: the field and the message, as `kes-cloth check` gives them
    /// (e.g. explicit damping beyond 1/(4·dt) at a long step that only the implicit
    /// integrator can take).
    Invalid {
        /// The field at fault.
        field: String,
        /// Its value and the allowed range.
        message: String,
    },
}

impl std::fmt::Display for Refusal {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self {
            Self::StepTooLong { effect, max_step_s } => write!(
                f,
                "explicit {effect} needs dt ≤ {:.3} ms (refused by the stability guard, docs/model.md §10)",
                max_step_s * 1e3
            ),
            Self::Invalid { field, message } => write!(f, "{field}: {message}"),
        }
    }
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
                why: Refusal::StepTooLong { effect, max_step_s },
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
    // A grid point that is the reference (same resolved scene) is not run twice.
    let reused = points.iter().position(|s| s.spec == reference_scene.spec);
    if reused.is_none() {
        points.push(reference_scene);
    }
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
    let mut scenes = Vec::with_capacity(points.len() * group);
    for point in &points {
        scenes.extend(placed_runs(point, group)?);
    }
    let total = scenes.len();
    let finished = std::sync::atomic::AtomicUsize::new(0);
    on_done(0, total);
    let outcomes = simulate_all(&scenes, threads, |_, _| {
        let done = finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        on_done(done, total);
    });
    let groups: Vec<&[RunOutcome]> = outcomes.chunks(group).collect();
    let reference_runs = groups[reused.unwrap_or(settings.len())];
    let surface = ReferenceSurface::new(&reference_runs[0].topology, &reference_runs[0].positions);
    let (reference, reference_dc_std) = aggregate(reference_runs);
    // Against a failed reference there is nothing to measure errors from.
    let comparable = reference.failure.is_none();
    let rows = settings
        .into_iter()
        .zip(&groups)
        .map(|(setting, runs)| {
            let (m, dc_std) = aggregate(runs);
            let dc_error = match (m.drape_coefficient, reference.drape_coefficient) {
                (Some(a), Some(b)) if m.failure.is_none() && comparable => Some((a - b).abs()),
                _ => None,
            };
            let hang_error_m = match (m.hang_corners_m, reference.hang_corners_m) {
                (Some(a), Some(b)) if m.failure.is_none() && comparable => Some((a - b).abs()),
                _ => None,
            };
            let shape_error_m = match (&surface, m.failure.is_none() && comparable) {
                (Some(s), true) => {
                    Some(runs.iter().map(|o| s.rms_distance(&o.positions)).sum::<f64>() / runs.len() as f64)
                }
                _ => None,
            };
            let is_default = setting
                .iter()
                .all(|(k, v)| study_plan::same_value(base_scene.field(k).as_ref(), v));
            StudyRow {
                setting,
                metrics: m,
                dc_std,
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
        reference_dc_std,
        placements: group,
        rows,
        refused,
    })
}

/// The runs of one grid point: the scene itself, or `n` > 1 repeats with seeds 0..n−1 and
/// lattice placements, each validated as a scene of its own (a rectangle refuses an offset).
pub(crate) fn placed_runs(scene: &Scene, n: usize) -> Result<Vec<Scene>, SceneError> {
    if n <= 1 {
        return Ok(vec![scene.clone()]);
    }
    repeat_scenes(scene, n, true)
        .into_iter()
        .map(|run| Scene::from_spec(run.spec, run.path))
        .collect()
}

/// One grid point's metrics over its runs (see [`StudyRow::metrics`]) and its DC's spread.
pub(crate) fn aggregate(runs: &[RunOutcome]) -> (Metrics, Option<f64>) {
    let summary = summarise(runs);
    let mut m = runs[0].metrics.clone();
    let n = runs.len() as f64;
    m.drape_coefficient = summary.dc_mean;
    m.nodes = summary.modal_nodes;
    m.wall_time_s = runs.iter().map(|o| o.metrics.wall_time_s).sum::<f64>() / n;
    m.max_strain = runs.iter().map(|o| o.metrics.max_strain).fold(0.0, f64::max);
    m.settled = runs.iter().all(|o| o.metrics.settled);
    // The slowest run's settle time, and none if any run did not settle.
    m.settle_time_s = runs
        .iter()
        .map(|o| o.metrics.settle_time_s.filter(|_| o.metrics.settled))
        .try_fold(0.0f64, |a, t| t.map(|t| a.max(t)));
    m.failure = runs.iter().find_map(|o| o.metrics.failure.clone());
    let hangs: Vec<f64> = runs.iter().filter_map(|o| o.metrics.hang_corners_m).collect();
    m.hang_corners_m = (hangs.len() == runs.len()).then(|| hangs.iter().sum::<f64>() / n);
    (m, summary.dc_std)
}
