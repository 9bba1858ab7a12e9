//! A study as task files: each task runs exactly as its scene does, and plan → tasks (in any
//! order, one killed part-way and run again, one run twice) → collect gives the local study,
//! wall-clock times aside.

use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use kes_cloth::batch::BatchLayout;
use kes_cloth::batch::{TaskStatus, read_manifest, result_path, run_task, task_path};
use kes_cloth::run::{RunOptions, simulate};
use kes_cloth::scene::Scene;
use kes_cloth::study::{StudyPlan, Vary};

mod common;

/// Runs `kes-cloth ARGS DIR TAIL` from the crate's folder.
fn kes_cloth(args: &[&str], dir: &Path, tail: &[&str]) -> Output {
    kes_cloth_with(args, dir, tail, None)
}

/// As [`kes_cloth`], with one environment variable set.
fn kes_cloth_with(args: &[&str], dir: &Path, tail: &[&str], env: Option<(&str, &str)>) -> Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_kes-cloth"));
    command
        .args(args)
        .arg(dir)
        .args(tail)
        .current_dir(common::crate_path(""));
    if let Some((key, value)) = env {
        command.env(key, value);
    }
    command.output().expect("kes-cloth runs")
}

fn ok(out: &Output) -> String {
    let text = format!(
        "{}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    assert!(out.status.success(), "kes-cloth failed: {text}");
    text
}

/// A CSV without its wall-clock column: what two runs of the same tasks must agree on.
fn without_wall_time(csv: &str) -> String {
    common::csv_without_column(csv, "wall_time_s")
}

fn task_count(dir: &Path) -> usize {
    read_manifest::<BatchLayout>(dir).unwrap().tasks
}

/// A task file is self-contained (the fabric inline, every override applied) and runs bit for
/// bit as the scene it was planned from: the same metrics (clock times aside) and the same final
/// node positions, for a drape with seeds and lattice placements (task 1: seed 1, placement 1).
#[test]
fn a_task_runs_exactly_as_the_scene_it_was_planned_from() {
    let dir = common::fresh_dir("batch-task-file");
    let scene = common::crate_path("scenes/drape_wool.ron");
    let mut base = common::explicit_drape("wool");
    base.extend([
        "cloth.spacing_m=0.01".to_string(),
        "integration.dt_s=0.00025".to_string(),
        "integration.max_time_s=0.05".to_string(),
        // A start per seed, so the task carries both the seed and the placement.
        "cloth.roughness=PerNode".to_string(),
    ]);
    let plan = StudyPlan {
        vary: vec!["integration.dt_s=0.00025".parse::<Vary>().unwrap()],
        reference: vec!["integration.dt_s=0.000125".into()],
        placements: 2,
    };
    let (manifest, scenes) = kes_cloth::study::plan_study(&scene, &base, &plan).unwrap();
    assert_eq!(
        manifest.tasks, 4,
        "one grid point and the reference, two placements each"
    );
    kes_cloth::study::write_batch(&dir, &manifest.clone().map(BatchLayout::Study), &scenes, false).unwrap();
    let text = std::fs::read_to_string(task_path(&dir, 1)).unwrap();
    assert!(
        text.contains("fabric: Inline("),
        "the fabric is not inline:\n{text}"
    );
    let from_file = Scene::from_text(&text, task_path(&dir, 1), &[]).unwrap();
    assert_eq!(
        format!("{:?}", from_file.fabric),
        format!("{:?}", scenes[1].fabric)
    );
    assert_eq!(from_file.spec.seed, 1);
    assert_eq!(
        from_file.spec.cloth.lattice_offset_m,
        scenes[1].spec.cloth.lattice_offset_m
    );

    let TaskStatus::Ran(result) = run_task(&dir, 1).unwrap() else {
        panic!("task 1 had not run before");
    };
    let direct = simulate(&scenes[1], &RunOptions::default());
    assert_eq!(
        common::without_clock_times(&result.metrics),
        common::without_clock_times(&direct.metrics)
    );
    assert_eq!(result.positions_m.as_deref(), Some(direct.positions.as_slice()));
    // The result file reads back to the same numbers, bit for bit.
    let read = kes_cloth::batch::TaskResult::read_current(&dir, 1)
        .unwrap()
        .unwrap();
    assert_eq!(read.positions_m, result.positions_m);
    assert_eq!(
        common::without_clock_times(&read.metrics),
        common::without_clock_times(&result.metrics)
    );
    // An index outside the plan is an error that names the range.
    let err = run_task(&dir, 4).unwrap_err().to_string();
    assert!(
        err.contains("task 4 does not exist") && err.contains("0 to 3"),
        "{err}"
    );
}

/// The claim of the batch design: the tasks of a planned study, run in reverse order as separate
/// processes, one of them killed part-way (it leaves no result) and run again, one run twice
/// (the second does nothing), collect to the same table as the study run here in one command,
/// wall-clock times aside. While a task is missing, `collect` writes what it has, names the
/// missing tasks and exits non-zero.
#[test]
fn tasks_in_any_order_one_killed_and_rerun_collect_to_the_local_study() {
    let local = common::fresh_dir("batch-local");
    ok(&kes_cloth(
        &[&common::CANTILEVER_STUDY[..], &["--out"]].concat(),
        &local,
        &[],
    ));
    let planned = common::fresh_dir("batch-planned");
    let plan_text = ok(&kes_cloth(
        &[&common::CANTILEVER_STUDY[..], &["--plan", "--out"]].concat(),
        &planned,
        &[],
    ));
    assert!(plan_text.contains("planned 3 tasks"), "{plan_text}");
    assert!(!planned.join("study.csv").exists(), "--plan only plans");
    let n = task_count(&planned);

    // The reference (the last task, the longest) killed part-way leaves no result.
    let last = n - 1;
    let mut child = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .arg("task")
        .arg(&planned)
        .arg(last.to_string())
        .spawn()
        .unwrap();
    std::thread::sleep(std::time::Duration::from_millis(150));
    let finished_early = child.try_wait().unwrap().is_some();
    child.kill().ok();
    child.wait().unwrap();
    assert!(
        !finished_early,
        "the reference task finished within 150 ms: nothing was killed"
    );
    assert!(
        !result_path(&planned, last).exists(),
        "a killed task left a result"
    );

    // Task 0 alone, its index given as a Kubernetes Indexed Job gives it: collect writes a
    // partial study, names what is missing, exits non-zero.
    ok(&kes_cloth_with(
        &["task"],
        &planned,
        &[],
        Some(("JOB_COMPLETION_INDEX", "0")),
    ));
    assert!(result_path(&planned, 0).exists());
    let partial = kes_cloth(&["collect"], &planned, &[]);
    assert!(!partial.status.success(), "collect succeeded with tasks missing");
    let md = std::fs::read_to_string(planned.join("study.md")).unwrap();
    assert!(
        md.contains("Tasks not finished") && md.contains("not finished yet"),
        "{md}"
    );

    for k in (0..n).rev() {
        ok(&kes_cloth(&["task"], &planned, &[&k.to_string()]));
    }
    let first = std::fs::read(result_path(&planned, 0)).unwrap();
    let again = ok(&kes_cloth(&["task"], &planned, &["0"]));
    assert!(again.contains("already done"), "{again}");
    assert_eq!(
        std::fs::read(result_path(&planned, 0)).unwrap(),
        first,
        "a re-run changed a result"
    );

    ok(&kes_cloth(&["collect"], &planned, &[]));
    let csv = |dir: &PathBuf| without_wall_time(&std::fs::read_to_string(dir.join("study.csv")).unwrap());
    assert_eq!(csv(&planned), csv(&local));
    assert_eq!(csv(&local).lines().count(), 3, "a header and two rows");
}

/// Every batch kind goes through the same tasks: a convergence study and repeats over seeds and
/// placements, planned and run task by task, collect to what the one-command runs give (the
/// convergence table wall-clock times aside; the repeats' summary has none).
#[test]
fn planned_convergence_and_repeats_collect_to_the_local_runs() {
    let converge = [
        "converge",
        "scenes/bending_length/cantilever_wool.ron",
        "--spacings",
        "0.01,0.0075,0.005",
    ];
    let (local, planned) = (
        common::fresh_dir("converge-local"),
        common::fresh_dir("converge-planned"),
    );
    ok(&kes_cloth(&[&converge[..], &["--out"]].concat(), &local, &[]));
    ok(&kes_cloth(
        &[&converge[..], &["--plan", "--out"]].concat(),
        &planned,
        &[],
    ));
    for k in (0..task_count(&planned)).rev() {
        ok(&kes_cloth(&["task", "--quiet"], &planned, &[&k.to_string()]));
    }
    ok(&kes_cloth(&["collect"], &planned, &[]));
    let table =
        |dir: &PathBuf| without_wall_time(&std::fs::read_to_string(dir.join("convergence.csv")).unwrap());
    assert_eq!(table(&planned), table(&local));

    let mut repeat = vec![
        "run",
        "scenes/drape_wool.ron",
        "--repeat",
        "3",
        "--placements",
        "--quiet",
    ];
    let sets: Vec<String> = common::explicit_drape("wool")
        .into_iter()
        .chain([
            "cloth.spacing_m=0.01".into(),
            "integration.max_time_s=0.05".into(),
        ])
        .collect();
    for s in &sets {
        repeat.extend(["--set", s.as_str()]);
    }
    let (local, planned) = (
        common::fresh_dir("repeat-local"),
        common::fresh_dir("repeat-planned"),
    );
    ok(&kes_cloth(&[&repeat[..], &["--out"]].concat(), &local, &[]));
    ok(&kes_cloth(
        &[&repeat[..], &["--plan", "--out"]].concat(),
        &planned,
        &[],
    ));
    assert_eq!(task_count(&planned), 3);
    for k in [2, 0, 1] {
        ok(&kes_cloth(&["task"], &planned, &[&k.to_string()]));
        assert!(
            planned.join(format!("seed-{k}/metrics.json")).exists(),
            "run {k} wrote no outputs"
        );
    }
    ok(&kes_cloth(&["collect"], &planned, &[]));
    let summary = |dir: &PathBuf| std::fs::read_to_string(dir.join("repeat.json")).unwrap();
    assert_eq!(summary(&planned), summary(&local));
    assert!(planned.join("report.html").exists());
    // The shipped drape starts smooth, so its placements all keep the scene's seed 0, and the
    // report lists each run with that seed.
    let report = std::fs::read_to_string(planned.join("report.html")).unwrap();
    for k in 0..3 {
        assert!(
            report.contains(&format!("<tr><td>{k}</td><td>0</td>")),
            "run {k} not listed with seed 0:\n{report}"
        );
    }
}
