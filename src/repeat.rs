//! Repeat runs, like a laboratory: the same scene with seeds 0..N−1 of the initial
//! perturbation, on all cores, summarised as the modal node count and the mean and spread of DC.
//! Optionally each run also shifts the node lattice against the cloth's outline, so the spread
//! includes where the grid happens to fall (`docs/accuracy.md`).

use std::sync::Mutex;
use std::sync::atomic::{AtomicUsize, Ordering};

use serde::Serialize;

use crate::run::{RunOptions, RunOutcome, simulate};
use crate::scene::Scene;

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

/// The scenes of `n` repeats of `scene`: run k has seed k and, if `placements`, the k-th lattice
/// offset of [`placement_offset`] (run 0 keeps the scene's own lattice).
pub fn repeat_scenes(scene: &Scene, n: usize, placements: bool) -> Vec<Scene> {
    (0..n)
        .map(|k| {
            let mut run = scene.clone();
            run.spec.seed = k as u64;
            if placements && k > 0 {
                run.spec.cloth.lattice_offset_m = placement_offset(k, run.spec.cloth.spacing_m);
            }
            run
        })
        .collect()
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
    let n = scenes.len();
    let next = AtomicUsize::new(0);
    let results: Mutex<Vec<Option<RunOutcome>>> = Mutex::new((0..n).map(|_| None).collect());
    std::thread::scope(|s| {
        for _ in 0..threads.clamp(1, n.max(1)) {
            s.spawn(|| {
                loop {
                    let i = next.fetch_add(1, Ordering::Relaxed);
                    if i >= n {
                        break;
                    }
                    let outcome = simulate(&scenes[i], &RunOptions::default());
                    on_done(i, &outcome);
                    if let Ok(mut r) = results.lock() {
                        r[i] = Some(outcome);
                    }
                }
            });
        }
    });
    results
        .into_inner()
        .map(|r| r.into_iter().flatten().collect())
        .unwrap_or_default()
}

/// Summarises repeat outcomes.
pub fn summarise(outcomes: &[RunOutcome]) -> RepeatSummary {
    let nodes: Vec<Option<u32>> = outcomes.iter().map(|o| o.metrics.nodes).collect();
    let dcs: Vec<Option<f64>> = outcomes.iter().map(|o| o.metrics.drape_coefficient).collect();
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
        runs: outcomes.len(),
        settled: outcomes.iter().filter(|o| o.metrics.settled).count(),
        modal_nodes,
        nodes,
        drape_coefficients: dcs,
        dc_mean,
        dc_std,
        lattice_offsets_m: outcomes.iter().map(|o| o.metrics.lattice_offset_m).collect(),
    }
}
