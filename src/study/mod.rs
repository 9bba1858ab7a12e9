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
mod study_batch;
mod study_plan;
mod study_report;
mod work_precision_plot;

use std::path::Path;

pub use convergence::{
    Convergence, ConvergenceLayout, ConvergencePlan, ConvergenceRow, collect_convergence, edge_rows_warning,
    finish_convergence, plan_convergence, run_convergence,
};
pub use convergence_report::{extrapolation_line, write_convergence};
pub use shape_error::ReferenceSurface;
pub use study_batch::{StudyLayout, collect_study, plan_study};
pub use study_plan::{StudyPlan, Vary};
pub use study_report::write_study;

use crate::batch::{self, BatchError, BatchLayout, Manifest};
use crate::output::Metrics;
use crate::repeat::{repeat_scenes, summarise_metrics};
use crate::scene::{Scene, SceneError};

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
    /// |chord − reference chord| (degrees), for cantilever scenes.
    pub chord_error_deg: Option<f64>,
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
    /// The reference's metrics (aggregated over placements as for a row); `None` while a run
    /// of it has not finished.
    pub reference: Option<Metrics>,
    /// Sample standard deviation of the reference's DC over its placements.
    pub reference_dc_std: Option<f64>,
    /// Runs per grid point and for the reference.
    pub placements: usize,
    /// One row per grid point, in grid order (the last key varies fastest).
    pub rows: Vec<StudyRow>,
    /// Grid points not run: the stability guard refused them (an explicit step too long for
    /// the spacing), or another rule did (e.g. explicit damping too strong for the step).
    pub refused: Vec<RefusedPoint>,
    /// Tasks of the batch not finished yet (their grid points are left out).
    pub missing: Vec<usize>,
}

impl Study {
    /// What the study's scene is judged by: the measure any run or the reference took.
    pub fn measure(&self) -> StudyMeasure {
        let all = || self.reference.iter().chain(self.rows.iter().map(|r| &r.metrics));
        if all().any(|m| m.drape_coefficient.is_some()) {
            StudyMeasure::DrapeCoefficient
        } else if all().any(|m| m.cantilever_chord_deg.is_some()) {
            StudyMeasure::CantileverChord
        } else {
            StudyMeasure::CornerHang
        }
    }
}

/// The value a study compares its runs by.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum StudyMeasure {
    /// A drapemeter's drape coefficient.
    DrapeCoefficient,
    /// A tablecloth's corner hang below the table top.
    CornerHang,
    /// A clamped strip's chord angle (the bending-length test).
    CantileverChord,
}

/// A grid point not run, and why.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct RefusedPoint {
    /// The varied keys' values, in `--vary` order.
    pub setting: Vec<(String, String)>,
    /// The rule that refused it.
    pub why: Refusal,
}

/// Why a grid point was not run.
#[derive(Clone, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Refusal {
    /// The stability guard: the explicit `effect` needs a step of at most `max_step_s` (s).
    StepTooLong {
        /// The effect with the tightest limit.
        effect: String,
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

/// Runs the study of the scene at `path` (with `base` overrides on every run) as a batch in
/// `dir` ([`crate::batch`]): [`plan_study`], [`write_batch`] (results already in `dir` removed),
/// then [`finish_study`].
pub fn run_study(
    path: &Path,
    base: &[String],
    plan: &StudyPlan,
    dir: &Path,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<Study, BatchError> {
    let (manifest, scenes) = plan_study(path, base, plan)?;
    write_batch(dir, &manifest.clone().map(BatchLayout::Study), &scenes, false)?;
    finish_study(dir, &manifest, threads, on_done)
}

/// Runs the unfinished tasks of the study planned in `dir` on `threads` threads
/// (`on_done(finished, total)` reports progress) and collects it; the first task that cannot
/// run is the error.
pub fn finish_study(
    dir: &Path,
    manifest: &Manifest<StudyLayout>,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<Study, BatchError> {
    if let Some((_, e)) = batch::run_tasks(dir, manifest.tasks, threads, on_done)
        .into_iter()
        .next()
    {
        return Err(e);
    }
    collect_study(dir, manifest)
}

/// Writes a planned batch (its manifest and task files) into `dir`; with `resume`, the results
/// of unchanged tasks already there are kept ([`batch::write_plan`]).
pub fn write_batch(
    dir: &Path,
    manifest: &Manifest<BatchLayout>,
    scenes: &[Scene],
    resume: bool,
) -> Result<(), BatchError> {
    batch::write_plan(dir, manifest, scenes, resume)
}

/// The runs of one grid point: the scene itself, or `n` > 1 runs on shifted lattice
/// placements ([`crate::repeat::repeat_scenes`]), each validated as a scene of its own (a rectangle refuses an offset).
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
pub(crate) fn aggregate(runs: &[&Metrics]) -> (Metrics, Option<f64>) {
    let summary = summarise_metrics(runs);
    let mut m = runs[0].clone();
    let n = runs.len() as f64;
    m.drape_coefficient = summary.dc_mean;
    m.nodes = summary.modal_nodes;
    m.wall_time_s = runs.iter().map(|o| o.wall_time_s).sum::<f64>() / n;
    m.max_strain = runs.iter().map(|o| o.max_strain).fold(0.0, f64::max);
    m.settled = runs.iter().all(|o| o.settled);
    // The slowest run's settle time, and none if any run did not settle.
    m.settle_time_s = runs
        .iter()
        .map(|o| o.settle_time_s.filter(|_| o.settled))
        .try_fold(0.0f64, |a, t| t.map(|t| a.max(t)));
    m.failure = runs.iter().find_map(|o| o.failure.clone());
    let hangs: Vec<f64> = runs.iter().filter_map(|o| o.hang_corners_m).collect();
    m.hang_corners_m = (hangs.len() == runs.len()).then(|| hangs.iter().sum::<f64>() / n);
    (m, summary.dc_std)
}
