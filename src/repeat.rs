//! Repeat runs, like a laboratory: the same scene with seeds 0..N−1 of the start roughness, on
//! all cores, summarised as the modal node count and the mean and spread of DC. Optionally each
//! run also shifts the node lattice against the cloth's outline, so the spread includes where
//! the grid happens to fall; with a smooth start roughness the runs then keep the scene's seed,
//! and the spread is where the grid falls alone (`docs/accuracy.md`).

use serde::Serialize;

use std::path::Path;

use crate::batch::{BatchError, Manifest, load_results, parallel_map, task_path};
use crate::output::Metrics;
use crate::run::{RunOptions, RunOutcome, simulate};
use crate::scene::{ClothShape, Roughness, Scene, SceneError};

/// The distribution of a drape result over repeats.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RepeatSummary {
    /// Number of runs.
    pub runs: usize,
    /// How many of them settled.
    pub settled: usize,
    /// Most frequent node count (the smaller on a tie), if measured.
    pub modal_nodes: Option<u32>,
    /// Node count of each run, by seed.
    pub nodes: Vec<Option<u32>>,
    /// DC of each run, by seed.
    pub drape_coefficients: Vec<Option<f64>>,
    /// Mean DC over the runs that measured one.
    pub dc_mean: Option<f64>,
    /// Sample standard deviation of DC (0 for a single run).
    pub dc_std: Option<f64>,
    /// Lattice offset of each run (m, along warp and weft).
    pub lattice_offsets_m: Vec<[f64; 2]>,
}

/// The scenes of `n` repeats of `scene`: run k has seed k and, if `placements`, the k-th
/// lattice offset of [`placement_offset`] (run 0 keeps the scene's own lattice). Placements keep
/// the scene's seed when its start roughness is [`Roughness::Smooth`], one start for every
/// lattice, so that their spread is the lattice's alone; with [`Roughness::PerNode`], another
/// start on every lattice anyway, run k has seed k.
pub fn repeat_scenes(scene: &Scene, n: usize, placements: bool) -> Vec<Scene> {
    (0..n)
        .map(|k| {
            let mut run = scene.clone();
            run.spec.seed = repeat_seed(scene, k, placements);
            if placements && k > 0 {
                run.spec.cloth.lattice_offset_m = placement_offset(k, run.spec.cloth.spacing_m);
            }
            run
        })
        .collect()
}

/// The seed of run `k` of [`repeat_scenes`]: `k`, or the scene's own with placements over a
/// smooth start roughness.
pub fn repeat_seed(scene: &Scene, k: usize, placements: bool) -> u64 {
    if placements && scene.spec.cloth.roughness == Roughness::Smooth {
        scene.spec.seed
    } else {
        k as u64
    }
}

/// The k-th lattice offset (m) of a low-discrepancy (R2) sequence over the square of side
/// `spacing` (m) centred on zero; k = 0 gives (0, 0). Successive runs fill the square evenly,
/// so a few runs already sample near and far placements of the grid against the rim.
pub fn placement_offset(k: usize, spacing: f64) -> [f64; 2] {
    // The plastic number's powers (Roberts' R2 sequence).
    const G: f64 = 1.324_717_957_244_746;
    let coord = |a: f64| ((0.5 + k as f64 * a).fract() - 0.5) * spacing;
    [coord(1.0 / G), coord(1.0 / (G * G))]
}

/// Runs `scene` with seeds 0..n−1 on `threads` threads; outcomes are in seed order.
pub fn simulate_repeats(scene: &Scene, n: usize, threads: usize) -> Vec<RunOutcome> {
    simulate_all(&repeat_scenes(scene, n, false), threads, |_, _| {})
}

/// Runs every scene, `threads` at a time (each run on one thread); outcomes are in the order of
/// `scenes`. `on_done(i, outcome)` is called as each run finishes (e.g. for progress).
pub fn simulate_all(
    scenes: &[Scene],
    threads: usize,
    on_done: impl Fn(usize, &RunOutcome) + Sync,
) -> Vec<RunOutcome> {
    parallel_map(scenes.len(), threads, |i| {
        let outcome = simulate(&scenes[i], &RunOptions::default());
        on_done(i, &outcome);
        outcome
    })
}

/// Summarises repeat outcomes.
pub fn summarise(outcomes: &[RunOutcome]) -> RepeatSummary {
    let metrics: Vec<&Metrics> = outcomes.iter().map(|o| &o.metrics).collect();
    summarise_metrics(&metrics)
}

/// Summarises the metrics of repeat runs, in seed order.
pub fn summarise_metrics(runs: &[&Metrics]) -> RepeatSummary {
    let nodes: Vec<Option<u32>> = runs.iter().map(|m| m.nodes).collect();
    let dcs: Vec<Option<f64>> = runs.iter().map(|m| m.drape_coefficient).collect();
    let mut counts = std::collections::BTreeMap::new();
    for n in nodes.iter().flatten() {
        *counts.entry(*n).or_insert(0usize) += 1;
    }
    let modal_nodes = counts
        .iter()
        .max_by(|a, b| a.1.cmp(b.1).then(b.0.cmp(a.0)))
        .map(|(n, _)| *n);
    let values: Vec<f64> = dcs.iter().flatten().copied().collect();
    let (dc_mean, dc_std) = if values.is_empty() {
        (None, None)
    } else {
        let mean = values.iter().sum::<f64>() / values.len() as f64;
        let var = if values.len() > 1 {
            values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (values.len() - 1) as f64
        } else {
            0.0
        };
        (Some(mean), Some(var.sqrt()))
    };
    RepeatSummary {
        runs: runs.len(),
        settled: runs.iter().filter(|m| m.settled).count(),
        modal_nodes,
        nodes,
        drape_coefficients: dcs,
        dc_mean,
        dc_std,
        lattice_offsets_m: runs.iter().map(|m| m.lattice_offset_m).collect(),
    }
}

/// How a batch of repeats combines: task K is run K (seed K and/or the K-th placement).
#[derive(Clone, Debug, PartialEq, Serialize, serde::Deserialize)]
pub struct RepeatLayout {
    /// Scene name.
    pub scene: String,
    /// Whether each run also shifts the node lattice ([`placement_offset`]).
    pub placements: bool,
}

/// Repeats collected from a batch folder.
#[derive(Clone, Debug)]
pub struct Repeats {
    /// Run 0's scene, as its task file has it (for the report's name and fabric).
    pub scene: Scene,
    /// Each finished run's index and metrics, in run order ([`Repeats::seed`] gives its seed).
    pub runs: Vec<(usize, Metrics)>,
    /// Their summary.
    pub summary: RepeatSummary,
    /// Tasks (seeds) without a result yet.
    pub missing: Vec<usize>,
    /// Whether each run also shifts the node lattice.
    pub placements: bool,
}

impl Repeats {
    /// The seed of run `k` ([`repeat_seed`]).
    pub fn seed(&self, k: usize) -> u64 {
        repeat_seed(&self.scene, k, self.placements)
    }
}

/// Plans `n` repeats of `scene` (seeds 0..n−1, and lattice placements if `placements`) as a
/// batch whose run K writes into `DIR/seed-K/`; each run is validated as a scene of its own (a
/// shifted lattice must still meet the pins, and a rectangle refuses an offset).
pub fn plan_repeats(
    scene: &Scene,
    n: usize,
    placements: bool,
) -> Result<(Manifest<RepeatLayout>, Vec<Scene>), SceneError> {
    if n == 0 {
        return Err(SceneError::invalid(
            &scene.path,
            "--repeat",
            "0",
            "needs at least 1 run",
        ));
    }
    if placements && !matches!(scene.spec.cloth.shape, ClothShape::Circle { .. }) {
        return Err(SceneError::invalid(
            &scene.path,
            "--placements",
            "true",
            "applies to circular cloths: a rectangle's lattice fills its outline",
        ));
    }
    let scenes = repeat_scenes(scene, n, placements)
        .into_iter()
        .map(|run| Scene::from_spec(run.spec, run.path))
        .collect::<Result<Vec<_>, _>>()?;
    let layout = RepeatLayout {
        scene: scene.spec.name.clone(),
        placements,
    };
    let mut manifest = Manifest::new(&scene.path, n, layout);
    manifest.run_folder = "seed-".to_string();
    Ok((manifest, scenes))
}

/// The repeats of the batch in `dir`, from whatever runs have finished.
pub fn collect_repeats(dir: &Path, manifest: &Manifest<RepeatLayout>) -> Result<Repeats, BatchError> {
    let (results, missing) = load_results(dir, manifest.tasks)?;
    let task = task_path(dir, 0);
    let text = std::fs::read_to_string(&task).map_err(|e| BatchError::io(&task, e))?;
    let scene = Scene::from_text(&text, task, &[])?;
    let runs: Vec<(usize, Metrics)> = results
        .into_iter()
        .flatten()
        .map(|r| (r.task, r.metrics))
        .collect();
    let summary = summarise_metrics(&runs.iter().map(|(_, m)| m).collect::<Vec<_>>());
    Ok(Repeats {
        scene,
        runs,
        summary,
        missing,
        placements: manifest.layout.placements,
    })
}
