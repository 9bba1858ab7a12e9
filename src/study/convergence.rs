//! `kes-cloth converge`: a scene at several node spacings, the observed order of convergence
//! and the extrapolated drape coefficient (or tablecloth hang) with its numerical uncertainty
//! ([`super::richardson`]).
//!
//! Each spacing σ runs at the step dt·(σ/σ₀)^q, σ₀ and dt the scene's own, q the step exponent
//! (default 2 for explicit scenes, whose stability limits shrink as σ², and 0 for implicit ones,
//! whose step is chosen for contact, not for stability), so time and space refine together.

use std::path::Path;

use serde::{Deserialize, Serialize};

use super::richardson::{Extrapolation, extrapolate_means};
use super::{aggregate, placed_runs};
use crate::batch::{self, BatchError, Manifest, load_results};
use crate::output::Metrics;
use crate::repeat::{NodeCountGroup, summarise_metrics};
use crate::scene::{ClothShape, IntegratorSpec, Scene, SceneError};

/// What a convergence study runs.
#[derive(Clone, Debug, PartialEq)]
pub struct ConvergencePlan {
    /// Node spacings (m), at least three.
    pub spacings: Vec<f64>,
    /// The step exponent q (dt ∝ σ^q); `None` for 2 (explicit) or 0 (implicit).
    pub step_exponent: Option<f64>,
    /// Runs per spacing (seeds and lattice placements, circular cloths only); 1 runs the scene
    /// as it is.
    pub placements: usize,
}

/// One spacing's runs.
#[derive(Clone, Debug)]
pub struct ConvergenceRow {
    /// Node spacing (m).
    pub spacing_m: f64,
    /// Step (s).
    pub dt_s: f64,
    /// Metrics over the placements (means; nodes modal), as a study row's.
    pub metrics: Metrics,
    /// Sample standard deviation of DC over the placements (0 for one run).
    pub dc_std: Option<f64>,
    /// The node counts the placements formed, most frequent first, each with its DC.
    pub node_counts: Vec<NodeCountGroup>,
}

/// A finished convergence study.
#[derive(Clone, Debug)]
pub struct Convergence {
    /// Scene name.
    pub scene: String,
    /// Runs per spacing.
    pub placements: usize,
    /// The step exponent used.
    pub step_exponent: f64,
    /// One row per spacing, coarsest first.
    pub rows: Vec<ConvergenceRow>,
    /// The drape coefficient extrapolated to σ → 0 (drape scenes whose every run succeeded).
    pub drape_coefficient: Option<Extrapolation>,
    /// The corner hang extrapolated to σ → 0 (m; tablecloth scenes).
    pub hang_corners_m: Option<Extrapolation>,
    /// The cantilever chord angle extrapolated to σ → 0 (degrees; cantilever scenes).
    pub cantilever_chord_deg: Option<Extrapolation>,
}

impl Convergence {
    /// The modal node count at the finest spacing, and whether the next coarser spacing has the
    /// same: the node count is converged only where neighbouring spacings agree.
    pub fn nodes_settled(&self) -> Option<(u32, bool)> {
        let n = self.rows.len();
        let finest = self.rows.last()?.metrics.nodes?;
        let agree = n >= 2 && self.rows[n - 2].metrics.nodes == Some(finest);
        Some((finest, agree))
    }
}

/// How a convergence study's tasks combine: spacing i's runs are tasks i·placements to
/// (i + 1)·placements − 1.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ConvergenceLayout {
    /// Scene name.
    pub scene: String,
    /// Runs per spacing.
    pub placements: usize,
    /// The step exponent q used.
    pub step_exponent: f64,
    /// Node spacings (m), coarsest first.
    pub spacings_m: Vec<f64>,
    /// Each spacing's step (s).
    pub steps_s: Vec<f64>,
}

/// Runs the scene at `path` (with `base` overrides) at every spacing of `plan` as a batch in
/// `dir` ([`crate::batch`]): [`plan_convergence`], [`super::write_batch`] (results already in
/// `dir` removed), then
/// [`finish_convergence`].
pub fn run_convergence(
    path: &Path,
    base: &[String],
    plan: &ConvergencePlan,
    dir: &Path,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<Convergence, BatchError> {
    let (manifest, scenes) = plan_convergence(path, base, plan)?;
    super::write_batch(
        dir,
        &manifest.clone().map(super::BatchLayout::Converge),
        &scenes,
        false,
    )?;
    finish_convergence(dir, &manifest, threads, on_done)
}

/// Runs the unfinished tasks of the convergence study planned in `dir` on `threads` threads
/// (`on_done(finished, total)` reports progress) and collects it.
pub fn finish_convergence(
    dir: &Path,
    manifest: &Manifest<ConvergenceLayout>,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<Convergence, BatchError> {
    if let Some((_, e)) = batch::run_tasks(dir, manifest.tasks, threads, on_done)
        .into_iter()
        .next()
    {
        return Err(e);
    }
    collect_convergence(dir, manifest)
}

/// Plans a convergence study of the scene at `path` (with `base` overrides): its manifest and
/// the scene of every task, in task order.
pub fn plan_convergence(
    path: &Path,
    base: &[String],
    plan: &ConvergencePlan,
) -> Result<(Manifest<ConvergenceLayout>, Vec<Scene>), SceneError> {
    let scene = Scene::load(path, base)?;
    let invalid =
        |field: &str, value: String, reason: &str| SceneError::invalid(&scene.path, field, value, reason);
    let mut spacings = plan.spacings.clone();
    spacings.sort_by(|a, b| b.total_cmp(a));
    spacings.dedup();
    if spacings.len() < 3 || spacings.iter().any(|s| s.is_nan() || *s <= 0.0) {
        return Err(invalid(
            "--spacings",
            format!("{:?}", plan.spacings),
            "needs at least three different positive spacings (m)",
        ));
    }
    let group = plan.placements.max(1);
    if group > 1 && !matches!(scene.spec.cloth.shape, ClothShape::Circle { .. }) {
        return Err(invalid(
            "--placements",
            group.to_string(),
            "applies to circular cloths: a rectangle's lattice fills its outline",
        ));
    }
    let exponent = plan
        .step_exponent
        .unwrap_or(match scene.spec.integration.integrator {
            IntegratorSpec::Explicit => 2.0,
            IntegratorSpec::Implicit | IntegratorSpec::Bdf2 => 0.0,
        });
    let (sigma0, dt0) = (scene.spec.cloth.spacing_m, scene.spec.integration.dt_s);
    let steps: Vec<f64> = spacings
        .iter()
        .map(|s| dt0 * (s / sigma0).powf(exponent))
        .collect();
    let mut scenes = Vec::with_capacity(spacings.len() * group);
    for (s, dt) in spacings.iter().zip(&steps) {
        let sets: Vec<String> = base
            .iter()
            .cloned()
            .chain([format!("cloth.spacing_m={s}"), format!("integration.dt_s={dt}")])
            .collect();
        scenes.extend(placed_runs(&Scene::load(path, &sets)?, group)?);
    }
    let layout = ConvergenceLayout {
        scene: scene.spec.name.clone(),
        placements: group,
        step_exponent: exponent,
        spacings_m: spacings,
        steps_s: steps,
    };
    Ok((Manifest::new(path, scenes.len(), layout), scenes))
}

/// A warning when the straight support edges of the scene at `path` (with `base` overrides; a
/// table's sides, a clamp's edge: [`Scene::support_edges_on_rows`]) lie on node rows at some of
/// `spacings` (m) and between rows at others. The cloth leaves such an edge at a row, so those
/// spacings differ by where the lattice meets the edge as well as by their size, and the
/// extrapolation mixes the two; `None` when every spacing meets the edges alike.
pub fn edge_rows_warning(
    path: &Path,
    base: &[String],
    spacings: &[f64],
) -> Result<Option<String>, SceneError> {
    let scene = Scene::load(path, base)?;
    let edges: Vec<Vec<bool>> = spacings.iter().map(|s| scene.support_edges_on_rows(*s)).collect();
    if edges.windows(2).all(|pair| pair[0] == pair[1]) {
        return Ok(None);
    }
    let list = |on: bool| {
        spacings
            .iter()
            .zip(&edges)
            .filter(|(_, e)| e.iter().any(|x| *x) == on)
            .map(|(s, _)| format!("{} mm", crate::output::number(s * 1e3)))
            .collect::<Vec<_>>()
            .join(", ")
    };
    Ok(Some(format!(
        "the support's straight edge (a table's side, a clamp's edge) lies on a row of nodes at {} and between rows at {}; \
         the cloth leaves such an edge at a row, so these spacings differ by where the lattice meets the edge as well as by \
         their size, and the extrapolation mixes the two. Spacings that halve (e.g. 0.01,0.005,0.0025 on the shipped \
         tablecloths) meet it alike.",
        list(true),
        list(false)
    )))
}

/// The convergence study of the batch in `dir`. Every task must have finished: an extrapolation
/// needs every spacing (the error names the tasks missing).
pub fn collect_convergence(
    dir: &Path,
    manifest: &Manifest<ConvergenceLayout>,
) -> Result<Convergence, BatchError> {
    let layout = &manifest.layout;
    let group = layout.placements.max(1);
    let (results, missing) = load_results(dir, manifest.tasks)?;
    if manifest.tasks != layout.spacings_m.len() * group {
        return Err(BatchError::malformed(
            dir.join(crate::batch::MANIFEST_FILE),
            format!(
                "{} tasks for {} spacings of {group} runs",
                manifest.tasks,
                layout.spacings_m.len()
            ),
        ));
    }
    if !missing.is_empty() {
        return Err(BatchError::Unfinished {
            dir: dir.to_path_buf(),
            missing,
        });
    }
    let metrics: Vec<&Metrics> = results.iter().flatten().map(|r| &r.metrics).collect();
    let rows: Vec<ConvergenceRow> = layout
        .spacings_m
        .iter()
        .zip(&layout.steps_s)
        .zip(metrics.chunks(group))
        .map(|((s, dt), runs)| {
            let (metrics, dc_std) = aggregate(runs);
            ConvergenceRow {
                spacing_m: *s,
                dt_s: *dt,
                metrics,
                dc_std,
                node_counts: summarise_metrics(runs).node_counts,
            }
        })
        .collect();
    let fit = |value: fn(&Metrics) -> Option<f64>, standard_error: &dyn Fn(&ConvergenceRow) -> f64| {
        let values: Option<Vec<f64>> = rows
            .iter()
            .map(|r| value(&r.metrics).filter(|_| r.metrics.failure.is_none()))
            .collect();
        let errors: Vec<f64> = rows.iter().map(standard_error).collect();
        extrapolate_means(&layout.spacings_m, &values?, &errors)
    };
    // A DC mean's standard error over its placements; the corner hang is a single run's.
    let dc_error = |r: &ConvergenceRow| r.dc_std.unwrap_or(0.0) / (group as f64).sqrt();
    Ok(Convergence {
        scene: layout.scene.clone(),
        placements: group,
        step_exponent: layout.step_exponent,
        drape_coefficient: fit(|m| m.drape_coefficient, &dc_error),
        hang_corners_m: fit(|m| m.hang_corners_m, &|_| 0.0),
        cantilever_chord_deg: fit(|m| m.cantilever_chord_deg, &|_| 0.0),
        rows,
    })
}
