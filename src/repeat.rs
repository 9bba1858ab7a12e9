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
    /// The standard error of the mean DC, `dc_std`/√n over the n runs that measured one: how
    /// far another set of as many runs would put the mean, one standard deviation. None below
    /// two runs.
    pub dc_standard_error: Option<f64>,
    /// The node counts the runs formed, each with its runs and their DC, most frequent first
    /// (the smaller count on a tie). A drape near a change of shape forms more than one: thin
    /// wool forms 8 or 9 nodes by lattice placement and step (`docs/accuracy.md`), and its DC
    /// differs between them by more than within either.
    pub node_counts: Vec<NodeCountGroup>,
    /// Lattice offset of each run (m, along warp and weft).
    pub lattice_offsets_m: Vec<[f64; 2]>,
}

/// The runs of a repeat that formed one node count.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct NodeCountGroup {
    /// The node count (the drape's folds).
    pub nodes: u32,
    /// How many runs formed it.
    pub runs: usize,
    /// Mean DC of those runs (dimensionless), if they measured one.
    pub dc_mean: Option<f64>,
    /// Sample standard deviation of their DC (0 for a single run).
    pub dc_std: Option<f64>,
}

impl RepeatSummary {
    /// The node counts in words, most frequent first: "8 in all 4 runs", or "9 in 3 runs, 8 in 1".
    pub fn node_counts_text(&self) -> String {
        match self.node_counts.as_slice() {
            [] => "not measured".into(),
            [only] if only.runs == self.runs && self.runs > 1 => {
                format!("{} in all {} runs", only.nodes, only.runs)
            }
            groups => groups
                .iter()
                .enumerate()
                .map(|(i, g)| match (i, g.runs) {
                    (0, 1) => format!("{} in 1 run", g.nodes),
                    (0, r) => format!("{} in {r} runs", g.nodes),
                    (_, r) => format!("{} in {r}", g.nodes),
                })
                .collect::<Vec<_>>()
                .join(", "),
        }
    }

    /// DC's mean ± sample standard deviation over the runs, and the mean's standard error:
    /// "0.376 ± 0.006 (sd; the mean to ± 0.003)".
    pub fn dc_text(&self) -> String {
        match (self.dc_mean, self.dc_std, self.dc_standard_error) {
            (Some(m), Some(sd), Some(se)) => format!("{m:.3} ± {sd:.3} (sd; the mean to ± {se:.3})"),
            (Some(m), _, _) => format!("{m:.3} (one run)"),
            _ => "-".into(),
        }
    }

    /// DC for each node count, when the runs formed more than one: "9 nodes 0.378 ± 0.004,
    /// 8 nodes 0.369"; None for a single node count.
    pub fn dc_by_node_count_text(&self) -> Option<String> {
        (self.node_counts.len() > 1).then(|| {
            self.node_counts
                .iter()
                .map(|g| match (g.dc_mean, g.dc_std, g.runs) {
                    (Some(m), Some(sd), r) if r > 1 => format!("{} nodes {m:.3} ± {sd:.3}", g.nodes),
                    (Some(m), _, _) => format!("{} nodes {m:.3}", g.nodes),
                    _ => format!("{} nodes -", g.nodes),
                })
                .collect::<Vec<_>>()
                .join(", ")
        })
    }
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
    let pairs: Vec<(Option<u32>, Option<f64>)> = nodes.iter().copied().zip(dcs.iter().copied()).collect();
    let node_counts = node_count_groups(&pairs);
    let modal_nodes = node_counts.first().map(|g| g.nodes);
    let values: Vec<f64> = dcs.iter().flatten().copied().collect();
    let (dc_mean, dc_std) = mean_and_sd(&values);
    let dc_standard_error = dc_std
        .filter(|_| values.len() > 1)
        .map(|sd| sd / (values.len() as f64).sqrt());
    RepeatSummary {
        runs: runs.len(),
        settled: runs.iter().filter(|m| m.settled).count(),
        modal_nodes,
        nodes,
        drape_coefficients: dcs,
        dc_mean,
        dc_std,
        dc_standard_error,
        node_counts,
        lattice_offsets_m: runs.iter().map(|m| m.lattice_offset_m).collect(),
    }
}

/// The runs grouped by node count, from each run's (node count, DC): most frequent first, the
/// smaller count first on a tie; runs without a node count are left out.
pub fn node_count_groups(runs: &[(Option<u32>, Option<f64>)]) -> Vec<NodeCountGroup> {
    let mut by_count = std::collections::BTreeMap::<u32, Vec<Option<f64>>>::new();
    for (n, dc) in runs {
        if let Some(n) = n {
            by_count.entry(*n).or_default().push(*dc);
        }
    }
    let mut groups: Vec<NodeCountGroup> = by_count
        .into_iter()
        .map(|(n, group)| {
            let values: Vec<f64> = group.iter().flatten().copied().collect();
            let (dc_mean, dc_std) = mean_and_sd(&values);
            NodeCountGroup {
                nodes: n,
                runs: group.len(),
                dc_mean,
                dc_std,
            }
        })
        .collect();
    // The map gave ascending counts; a stable sort keeps the smaller first on a tie.
    groups.sort_by_key(|g| std::cmp::Reverse(g.runs));
    groups
}

/// The mean and sample standard deviation (0 for one value) of `values`; None if empty.
fn mean_and_sd(values: &[f64]) -> (Option<f64>, Option<f64>) {
    if values.is_empty() {
        return (None, None);
    }
    let n = values.len() as f64;
    let mean = values.iter().sum::<f64>() / n;
    let var = if values.len() > 1 {
        values.iter().map(|v| (v - mean).powi(2)).sum::<f64>() / (n - 1.0)
    } else {
        0.0
    };
    (Some(mean), Some(var.sqrt()))
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

#[cfg(test)]
mod tests {
    use super::*;

    fn summary(runs: &[(Option<u32>, Option<f64>)]) -> RepeatSummary {
        let values: Vec<f64> = runs.iter().filter_map(|r| r.1).collect();
        let (dc_mean, dc_std) = mean_and_sd(&values);
        let node_counts = node_count_groups(runs);
        RepeatSummary {
            runs: runs.len(),
            settled: runs.len(),
            modal_nodes: node_counts.first().map(|g| g.nodes),
            nodes: runs.iter().map(|r| r.0).collect(),
            drape_coefficients: runs.iter().map(|r| r.1).collect(),
            dc_mean,
            dc_std,
            dc_standard_error: dc_std
                .filter(|_| values.len() > 1)
                .map(|s| s / (values.len() as f64).sqrt()),
            node_counts,
            lattice_offsets_m: vec![[0.0; 2]; runs.len()],
        }
    }

    /// Thin wool at 1/960 s over four placements formed 9, 9, 9 and 8 nodes: the groups say so,
    /// most frequent first, each with its own DC (the 9-node runs' mean of three values, exact
    /// to rounding).
    #[test]
    fn a_drape_of_two_shapes_is_reported_by_node_count() {
        let s = summary(&[
            (Some(9), Some(0.380)),
            (Some(8), Some(0.368)),
            (Some(9), Some(0.376)),
            (Some(9), Some(0.378)),
        ]);
        assert_eq!(s.modal_nodes, Some(9));
        assert_eq!(
            s.node_counts
                .iter()
                .map(|g| (g.nodes, g.runs))
                .collect::<Vec<_>>(),
            [(9, 3), (8, 1)]
        );
        assert!(
            s.node_counts[0]
                .dc_mean
                .is_some_and(|m| (m - 0.378).abs() < 1e-12)
        );
        assert_eq!(s.node_counts[1].dc_std, Some(0.0));
        assert_eq!(s.node_counts_text(), "9 in 3 runs, 8 in 1");
        assert_eq!(
            s.dc_by_node_count_text().as_deref(),
            Some("9 nodes 0.378 ± 0.002, 8 nodes 0.368")
        );
        // sd of (0.380, 0.368, 0.376, 0.378) is 0.00525; over √4 runs the mean is known to 0.0026.
        assert_eq!(s.dc_text(), "0.376 ± 0.005 (sd; the mean to ± 0.003)");
    }

    /// An even split names the smaller count first (the modal count's tie rule), and one shape
    /// over all runs reads as such, with no breakdown.
    #[test]
    fn ties_name_the_smaller_count_and_one_shape_has_no_breakdown() {
        let tie = summary(&[(Some(9), Some(0.38)), (Some(8), Some(0.37))]);
        assert_eq!(tie.modal_nodes, Some(8));
        assert_eq!(tie.node_counts_text(), "8 in 1 run, 9 in 1");
        let one = summary(&[(Some(8), Some(0.365)), (Some(8), Some(0.367)), (None, None)]);
        assert_eq!(one.node_counts_text(), "8 in 2 runs");
        assert_eq!(one.dc_by_node_count_text(), None);
        let all = summary(&[(Some(4), Some(0.74)), (Some(4), Some(0.74))]);
        assert_eq!(all.node_counts_text(), "4 in all 2 runs");
        assert_eq!(summary(&[(Some(4), Some(0.74))]).dc_text(), "0.740 (one run)");
    }
}
