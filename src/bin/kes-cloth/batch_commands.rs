//! `study`, `converge`, `task` and `collect`: batches of runs planned as task files, run here on
//! a thread pool or by a cluster's scheduler, and collected into their report.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use kes_cloth::batch::{self, BatchError, BatchLayout, Collected, Manifest, TaskStatus};
use kes_cloth::repeat::Repeats;
use kes_cloth::scene::Scene;
use kes_cloth::study::{ConvergencePlan, StudyPlan};

use crate::cli::BatchArgs;
use crate::fail;

impl BatchArgs {
    /// The batch folder: `--out`, or `out/<scene name>-<kind>`.
    fn dir(&self, scene: &str, kind: &str) -> PathBuf {
        self.out
            .clone()
            .unwrap_or_else(|| PathBuf::from("out").join(format!("{scene}-{kind}")))
    }

    /// Runs at a time: `--threads`, or every core.
    fn threads(&self) -> usize {
        self.threads
            .unwrap_or_else(|| std::thread::available_parallelism().map_or(1, |t| t.get()))
    }
}

/// Writes the plan of a batch of `kind` (its manifest, with the layout wrapped by `wrap`, and
/// its task files) into its folder; unless only planning, runs its tasks with a progress bar
/// and collects it with `finish`, then reports.
fn run_batch<L: Clone>(
    planned: (Manifest<L>, Vec<Scene>),
    scene_name: &str,
    kind: &'static str,
    wrap: fn(L) -> BatchLayout,
    at: &BatchArgs,
    finish: impl FnOnce(&Path, &Manifest<L>) -> Result<Collected, BatchError>,
) -> ExitCode {
    let (manifest, scenes) = planned;
    let dir = at.dir(scene_name, kind);
    if let Err(e) = batch::write_plan(&dir, &manifest.clone().map(wrap), &scenes, at.resume) {
        return fail(&e);
    }
    if at.plan {
        return planned_tasks(&dir, manifest.tasks);
    }
    let bar = batch_bar(kind, manifest.tasks);
    let result = batch::run_all(&dir, manifest.tasks, at.threads(), |done, total| {
        bar.set_length(total as u64);
        bar.set_position(done as u64);
    })
    .and_then(|()| finish(&dir, &manifest));
    bar.finish_and_clear();
    match result {
        Ok(collected) => report(&dir, &collected),
        Err(e) => fail(&e),
    }
}

/// `kes-cloth study`.
pub fn study(scene: &Path, plan: &StudyPlan, set: &[String], at: &BatchArgs) -> ExitCode {
    match kes_cloth::study::plan_study(scene, set, plan) {
        Ok(planned) => {
            let name = planned.0.layout.scene.clone();
            run_batch(planned, &name, "study", BatchLayout::Study, at, |dir, m| {
                kes_cloth::study::collect_study(dir, m).map(|s| Collected::Study(Box::new(s)))
            })
        }
        Err(e) => fail(&e),
    }
}

/// `kes-cloth converge`.
pub fn converge(scene: &Path, plan: &ConvergencePlan, set: &[String], at: &BatchArgs) -> ExitCode {
    if let Ok(Some(warning)) = kes_cloth::study::edge_rows_warning(scene, set, &plan.spacings) {
        eprintln!("warning: {warning}");
    }
    match kes_cloth::study::plan_convergence(scene, set, plan) {
        Ok(planned) => {
            let name = planned.0.layout.scene.clone();
            run_batch(
                planned,
                &name,
                "convergence",
                BatchLayout::Converge,
                at,
                |dir, m| kes_cloth::study::collect_convergence(dir, m).map(Collected::Converge),
            )
        }
        Err(e) => fail(&e),
    }
}

/// Tells how to run a planned batch of `tasks` tasks in `dir`.
fn planned_tasks(dir: &Path, tasks: usize) -> ExitCode {
    let d = dir.display();
    println!(
        "planned {tasks} tasks in {d}\n\
         run them, in any order, anywhere {d} is shared:\n  \
         here:        for k in $(seq 0 {last}); do kes-cloth task {d} $k; done\n  \
         Slurm:       KES_BATCH_DIR={d} sbatch --array=0-{last} deploy/slurm/task-array.sbatch\n  \
         Kubernetes:  completions: {tasks} in deploy/kubernetes/task-job.yaml (an Indexed Job)\n\
         then: kes-cloth collect {d}",
        last = tasks.saturating_sub(1)
    );
    ExitCode::SUCCESS
}

/// `kes-cloth task DIR [K]`: K from the argument, else from the scheduler's environment.
pub fn task(dir: &Path, index: Option<usize>, quiet: bool) -> ExitCode {
    let index = match index.map_or_else(scheduler_index, Ok) {
        Ok(k) => k,
        Err(e) => return fail(&e),
    };
    match batch::run_task(dir, index) {
        Ok(TaskStatus::AlreadyDone) => {
            if !quiet {
                println!(
                    "task {index}: already done ({})",
                    batch::result_path(dir, index).display()
                );
            }
            ExitCode::SUCCESS
        }
        Ok(TaskStatus::Ran(result)) => {
            if !quiet {
                let m = &result.metrics;
                println!(
                    "task {index}: {} steps in {:.1} s wall, {}{} -> {}",
                    m.steps,
                    m.wall_time_s,
                    if m.settled { "settled" } else { "not settled" },
                    m.failure
                        .as_ref()
                        .map_or(String::new(), |f| format!(", diverged at step {}", f.step)),
                    batch::result_path(dir, index).display()
                );
            }
            ExitCode::SUCCESS
        }
        Err(e) => fail(&e),
    }
}

/// The task index a scheduler gives: Slurm's `SLURM_ARRAY_TASK_ID`, or a Kubernetes Indexed
/// Job's `JOB_COMPLETION_INDEX`.
fn scheduler_index() -> Result<usize, String> {
    for var in ["SLURM_ARRAY_TASK_ID", "JOB_COMPLETION_INDEX"] {
        if let Ok(v) = std::env::var(var) {
            return v
                .trim()
                .parse()
                .map_err(|_| format!("{var}={v}: expected a task index (0, 1, ...)"));
        }
    }
    Err(
        "no task index: give K (kes-cloth task DIR K), or run under a Slurm job array \
         (SLURM_ARRAY_TASK_ID) or a Kubernetes Indexed Job (JOB_COMPLETION_INDEX)"
            .to_string(),
    )
}

/// `kes-cloth collect DIR`: the report from whatever has finished; exit code 1 while tasks are
/// missing (the partial report is still written).
pub fn collect(dir: &Path) -> ExitCode {
    match batch::collect(dir) {
        Ok(collected) => report(dir, &collected),
        Err(e) => fail(&e),
    }
}

/// Writes a collected batch's files into `dir` and prints its table; exit code 1 if tasks are
/// missing.
fn report(dir: &Path, collected: &Collected) -> ExitCode {
    let written = match collected {
        Collected::Study(s) => kes_cloth::study::write_study(s, dir)
            .map(|()| Some("study.md"))
            .map_err(|e| e.to_string()),
        Collected::Converge(c) => kes_cloth::study::write_convergence(c, dir)
            .map(|()| Some("convergence.md"))
            .map_err(|e| e.to_string()),
        Collected::Repeat(r) => repeat_report(dir, r).map(|()| None),
    };
    match written {
        Ok(Some(file)) => match std::fs::read_to_string(dir.join(file)) {
            Ok(table) => println!("{table}"),
            Err(e) => return fail(&format!("{}: {e}", dir.join(file).display())),
        },
        Ok(None) => {}
        Err(e) => return fail(&e),
    }
    println!("wrote {}", dir.display());
    let missing = collected.missing();
    if missing.is_empty() {
        ExitCode::SUCCESS
    } else {
        fail(&format!("{} tasks not finished: {missing:?}", missing.len()))
    }
}

/// `kes-cloth run --repeat N`: seeds 0..N−1 (or placements) as a batch in the run's folder.
pub fn repeat(scene: &Scene, n: usize, placements: bool, at: &BatchArgs, quiet: bool) -> ExitCode {
    let (manifest, scenes) = match kes_cloth::repeat::plan_repeats(scene, n, placements) {
        Ok(p) => p,
        Err(e) => return fail(&e),
    };
    let dir = at.dir(&manifest.layout.scene, "repeat");
    if let Err(e) = batch::write_plan(
        &dir,
        &manifest.clone().map(BatchLayout::Repeat),
        &scenes,
        at.resume,
    ) {
        return fail(&e);
    }
    if at.plan {
        return planned_tasks(&dir, manifest.tasks);
    }
    if !quiet {
        eprintln!(
            "running {n} seeds of {} on {} threads...",
            scene.spec.name,
            at.threads()
        );
    }
    if let Err(e) = batch::run_all(&dir, manifest.tasks, at.threads(), |_, _| {}) {
        return fail(&e);
    }
    let repeats = match kes_cloth::repeat::collect_repeats(&dir, &manifest) {
        Ok(r) => r,
        Err(e) => return fail(&e),
    };
    if let Err(e) = repeat_report(&dir, &repeats) {
        return fail(&e);
    }
    if !quiet {
        print_repeats(&repeats);
        println!("  wrote {}", dir.display());
    }
    match repeats.runs.iter().find_map(|(_, m)| m.failure.clone()) {
        Some(f) => fail(&kes_cloth::run::DivergenceError(f)),
        None => ExitCode::SUCCESS,
    }
}

/// Writes `repeat.json` and (if the scene asks for reports) `report.html` into `dir`.
fn repeat_report(dir: &Path, r: &Repeats) -> Result<(), String> {
    let path = dir.join("repeat.json");
    let text = serde_json::to_string_pretty(&r.summary).map_err(|e| e.to_string())?;
    std::fs::write(&path, text + "\n").map_err(|e| format!("{}: cannot write: {e}", path.display()))?;
    if r.scene.spec.output.report {
        kes_cloth::run::write_repeat_report(r, dir).map_err(|e| e.to_string())?;
    }
    Ok(())
}

/// One line per run and the summary.
fn print_repeats(r: &Repeats) {
    for (k, m) in &r.runs {
        let seed = r.seed(*k);
        let dc = m.drape_coefficient.map_or("-".into(), |v| format!("{v:.3}"));
        let nodes = m.nodes.map_or("-".into(), |v| v.to_string());
        let settled = if m.settled {
            format!("settled at {:.2} s", m.settle_time_s.unwrap_or(0.0))
        } else {
            "NOT settled".into()
        };
        let [ou, ov] = m.lattice_offset_m;
        let lattice = if r.placements {
            format!(", lattice shifted ({:.1}, {:.1}) mm", ou * 1e3, ov * 1e3)
        } else {
            String::new()
        };
        println!(
            "  run {k}, seed {seed}{lattice}: DC {dc}, {nodes} nodes, {settled}, {:.1} s wall",
            m.wall_time_s
        );
    }
    let s = &r.summary;
    println!(
        "{}: {} runs, {} settled; nodes {}; DC {}",
        r.scene.spec.name,
        s.runs,
        s.settled,
        s.node_counts_text(),
        s.dc_text()
    );
    if let Some(by_count) = s.dc_by_node_count_text() {
        println!("  DC by node count: {by_count}");
    }
}

/// A progress bar over `runs` runs of a batch (study, convergence).
fn batch_bar(label: &'static str, runs: usize) -> indicatif::ProgressBar {
    let bar = indicatif::ProgressBar::new(runs as u64).with_style(
        indicatif::ProgressStyle::with_template("{msg} [{bar:30}] {pos}/{len} runs, {elapsed} elapsed")
            .unwrap_or_else(|_| indicatif::ProgressStyle::default_bar()),
    );
    bar.set_message(label);
    bar
}
