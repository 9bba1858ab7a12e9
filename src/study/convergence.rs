//! `kes-cloth converge`: a scene at several node spacings, the observed order of convergence
//! and the extrapolated drape coefficient (or tablecloth hang) with its numerical uncertainty
//! ([`super::richardson`]).
//!
//! Each spacing σ runs at the step dt·(σ/σ₀)^q, σ₀ and dt the scene's own, q the step exponent
//! (default 2 for explicit scenes, whose stability limits shrink as σ², and 0 for implicit ones,
//! whose step is chosen for contact, not for stability), so time and space refine together.

use std::path::Path;

use super::richardson::{Extrapolation, extrapolate_means};
use super::{aggregate, placed_runs};
use crate::output::Metrics;
use crate::repeat::simulate_all;
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

/// Runs the scene at `path` (with `base` overrides) at every spacing of `plan`, on `threads`
/// threads; `on_done(finished, total)` reports progress.
pub fn run_convergence(
    path: &Path,
    base: &[String],
    plan: &ConvergencePlan,
    threads: usize,
    on_done: impl Fn(usize, usize) + Sync,
) -> Result<Convergence, SceneError> {
    let scene = Scene::load(path, base)?;
    let invalid = |field: &str, value: String, reason: &str| SceneError::Invalid {
        path: scene.path.clone(),
        at: None,
        field: field.to_string(),
        value,
        reason: reason.to_string(),
    };
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
    let mut points = Vec::with_capacity(spacings.len());
    for &s in &spacings {
        let dt = dt0 * (s / sigma0).powf(exponent);
        let sets: Vec<String> = base
            .iter()
            .cloned()
            .chain([format!("cloth.spacing_m={s}"), format!("integration.dt_s={dt}")])
            .collect();
        points.push((s, dt, Scene::load(path, &sets)?));
    }
    let mut scenes = Vec::with_capacity(points.len() * group);
    for (_, _, point) in &points {
        scenes.extend(placed_runs(point, group)?);
    }
    let total = scenes.len();
    let finished = std::sync::atomic::AtomicUsize::new(0);
    on_done(0, total);
    let outcomes = simulate_all(&scenes, threads, |_, _| {
        let done = finished.fetch_add(1, std::sync::atomic::Ordering::Relaxed) + 1;
        on_done(done, total);
    });
    let rows: Vec<ConvergenceRow> = points
        .iter()
        .zip(outcomes.chunks(group))
        .map(|((s, dt, _), runs)| {
            let (metrics, dc_std) = aggregate(runs);
            ConvergenceRow {
                spacing_m: *s,
                dt_s: *dt,
                metrics,
                dc_std,
            }
        })
        .collect();
    let fit = |value: fn(&Metrics) -> Option<f64>, standard_error: &dyn Fn(&ConvergenceRow) -> f64| {
        let values: Option<Vec<f64>> = rows
            .iter()
            .map(|r| value(&r.metrics).filter(|_| r.metrics.failure.is_none()))
            .collect();
        let errors: Vec<f64> = rows.iter().map(standard_error).collect();
        extrapolate_means(&spacings, &values?, &errors)
    };
    // A DC mean's standard error over its placements; the corner hang is a single run's.
    let dc_error = |r: &ConvergenceRow| r.dc_std.unwrap_or(0.0) / (group as f64).sqrt();
    Ok(Convergence {
        scene: scene.spec.name.clone(),
        placements: group,
        step_exponent: exponent,
        drape_coefficient: fit(|m| m.drape_coefficient, &dc_error),
        hang_corners_m: fit(|m| m.hang_corners_m, &|_| 0.0),
        cantilever_chord_deg: fit(|m| m.cantilever_chord_deg, &|_| 0.0),
        rows,
    })
}
