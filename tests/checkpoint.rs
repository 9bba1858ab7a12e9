//! A run stopped and resumed from its last checkpoint ends exactly where the uninterrupted run
//! ends; an interrupted run keeps its checkpoint and partial outputs.
//!
//! Claims:
//! 1. Interrupted at an arbitrary step (a timer sets the interrupt flag, as Ctrl-C does) and
//!    resumed, a run gives bit-identical metrics (wall times aside) and node positions to the
//!    same run left alone: explicit, and implicit with hysteresis (so the friction slips and the
//!    solver's warm start are part of the state), with the two-level preconditioner, and with
//!    BDF2 (whose history is part of the state); and stopped while it steps at rest
//!    (`integration.rest_dt_s`, whose step and counts are part of the state).
//! 2. `kes-cloth run --checkpoint-every` stopped by SIGINT exits with 130 and leaves
//!    `metrics.json` (marked interrupted), `final.obj`, `top.png` and `checkpoint.cbor`;
//!    `kes-cloth resume` finishes the run.
//! 3. Resuming without a readable checkpoint is an error naming the file, never a panic.

use std::path::Path;
use std::process::Command;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use kes_cloth::checkpoint::{CHECKPOINT_FILE, Snapshot};
use kes_cloth::run::{CheckpointPlan, RunOptions, resume, simulate};
use kes_cloth::scene::Scene;

mod common;

fn out_dir(name: &str) -> std::path::PathBuf {
    let dir = std::env::temp_dir().join(format!("kes-cloth-checkpoint-{name}"));
    let _ = std::fs::remove_dir_all(&dir);
    dir
}

#[test]
fn a_resumed_run_ends_exactly_where_the_uninterrupted_run_ends() {
    for (name, sets) in [
        ("explicit", vec!["integration.max_time_s=1.0", "seed=2"]),
        (
            "implicit_hysteresis",
            vec![
                "integration.max_time_s=1.5",
                "integration.integrator=Implicit",
                "integration.dt_s=0.002",
                "effects.hysteresis=true",
            ],
        ),
        (
            // The two-level preconditioner refactors at every pass: nothing of it carries
            // from step to step, so the resumed run's solves are the uninterrupted run's.
            "implicit_two_level",
            vec![
                "integration.max_time_s=0.6",
                "integration.integrator=Implicit",
                "integration.dt_s=0.0041666667",
                "effects.stretch=Kes",
                "integration.implicit_solver.preconditioner=TwoLevel(coarsening: 4)",
            ],
        ),
        (
            // BDF2 carries each node's lag and last velocity from step to step.
            "implicit_bdf2",
            vec![
                "integration.max_time_s=0.6",
                "integration.integrator=Bdf2",
                "integration.dt_s=0.0041666667",
                "effects.stretch=Kes",
            ],
        ),
        (
            // A hold that gave way in one solve slides from the next step: carried over.
            "implicit_release_next_step",
            vec![
                "integration.max_time_s=0.6",
                "integration.integrator=Bdf2",
                "integration.dt_s=0.0041666667",
                "effects.stretch=Kes",
                "integration.implicit_solver.friction_release=NextStep",
            ],
        ),
    ] {
        let mut all = common::explicit_drape("wool");
        all.extend(sets.into_iter().map(String::from));
        let scene = Scene::load(common::crate_path("scenes/drape_wool.ron"), &all).unwrap();
        let whole = simulate(&scene, &RunOptions::default());

        let dir = out_dir(name);
        let flag = Arc::new(AtomicBool::new(false));
        let timer = {
            let flag = flag.clone();
            std::thread::spawn(move || {
                std::thread::sleep(Duration::from_millis(250));
                flag.store(true, Ordering::Relaxed);
            })
        };
        let partial = simulate(&scene, &checkpointed(&dir, flag));
        timer.join().unwrap();
        assert!(
            partial.metrics.interrupted && partial.metrics.steps < whole.metrics.steps,
            "{name}: the run must have been stopped early to test anything (stopped at step {} of {})",
            partial.metrics.steps,
            whole.metrics.steps
        );
        assert!(
            partial.checkpoint_error.is_none(),
            "{:?}",
            partial.checkpoint_error
        );

        let (_, resumed) = resume(&dir, &RunOptions::default()).unwrap();
        assert!(!resumed.metrics.interrupted);
        assert_eq!(
            common::without_clock_times(&whole.metrics),
            common::without_clock_times(&resumed.metrics),
            "{name}: stopped at step {}",
            partial.metrics.steps
        );
        assert!(
            whole
                .positions
                .iter()
                .zip(&resumed.positions)
                .all(|(p, q)| p.to_array().map(f64::to_bits) == q.to_array().map(f64::to_bits)),
            "{name}: positions differ after resuming from step {}",
            partial.metrics.steps
        );
    }
}

/// Thick cotton at 1 cm as shipped (BDF2, the KES law, friction in the solve) steps at 1/30 s
/// through its 2 s confirmation once a settle window is quiet: stopped once a checkpoint 0.5 s
/// into that confirmation exists, and resumed, it ends bit for bit where the run left alone
/// ends.
#[test]
fn a_run_resumed_during_its_steps_at_rest_ends_where_the_uninterrupted_run_ends() {
    let sets = ["cloth.spacing_m=0.01", "integration.max_time_s=6"].map(String::from);
    let scene = Scene::load(common::crate_path("scenes/drape_cotton.ron"), &sets).unwrap();
    let whole = simulate(&scene, &RunOptions::default());
    assert!(
        whole.metrics.settled && whole.metrics.rest_steps > 0,
        "{:?}",
        whole.metrics
    );
    // The window opens at `settle_time_s` and is quiet 0.5 s later (`settle.hold_s`).
    let stop_after = whole.metrics.settle_time_s.unwrap() + 0.5 + 0.5;

    let dir = out_dir("rest_step");
    let flag = Arc::new(AtomicBool::new(false));
    let watcher = {
        let (flag, dir) = (flag.clone(), dir.clone());
        std::thread::spawn(move || {
            for _ in 0..12_000 {
                std::thread::sleep(Duration::from_millis(5));
                // A checkpoint being written does not read; the next one will.
                if Snapshot::read(&dir).is_ok_and(|s| s.time_s() >= stop_after) {
                    break;
                }
            }
            flag.store(true, Ordering::Relaxed);
        })
    };
    let partial = simulate(&scene, &checkpointed(&dir, flag));
    watcher.join().unwrap();
    let (stopped, all) = (partial.metrics.rest_steps, whole.metrics.rest_steps);
    assert!(
        partial.metrics.interrupted && stopped > 0 && stopped < all,
        "stopped after {stopped} of {all} steps at rest"
    );
    let (_, resumed) = resume(&dir, &RunOptions::default()).unwrap();
    assert_eq!(
        common::without_clock_times(&whole.metrics),
        common::without_clock_times(&resumed.metrics)
    );
    assert!(common::same_bits(&whole.positions, &resumed.positions));
}

/// Options for a run that writes a checkpoint into `dir` every 0.05 s of simulated time and
/// stops once `interrupt` is set.
fn checkpointed(dir: &Path, interrupt: Arc<AtomicBool>) -> RunOptions {
    RunOptions {
        checkpoint: Some(CheckpointPlan {
            dir: dir.to_path_buf(),
            every_s: 0.05,
        }),
        interrupt: Some(interrupt),
        ..RunOptions::default()
    }
}

fn kes_cloth() -> Command {
    Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
}

#[test]
fn ctrl_c_keeps_the_checkpoint_and_partial_outputs_and_resume_finishes() {
    let dir = out_dir("sigint");
    let scene = common::crate_path("scenes/drape_wool.ron");
    let mut child = kes_cloth()
        .args([
            "run",
            scene.to_str().unwrap(),
            "--quiet",
            "--checkpoint-every",
            "0.05",
        ])
        .args([
            "--set",
            "integration.max_time_s=20",
            // Interrupting and resuming, not the drape, is checked: 5 mm (the scene's 2.5 mm
            // costs five times as much).
            "--set",
            "cloth.spacing_m=0.005",
            "--out",
            dir.to_str().unwrap(),
        ])
        .spawn()
        .unwrap();
    // Wait for the first checkpoint, then interrupt as Ctrl-C would.
    let checkpoint = dir.join(CHECKPOINT_FILE);
    for _ in 0..600 {
        if checkpoint.exists() {
            break;
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    assert!(checkpoint.exists(), "no checkpoint within 30 s");
    let killed = Command::new("kill")
        .args(["-INT", &child.id().to_string()])
        .status()
        .unwrap();
    assert!(killed.success());
    let status = child.wait().unwrap();
    assert_eq!(status.code(), Some(130), "an interrupted run exits with 130");
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(metrics["interrupted"], true);
    for file in ["final.obj", "top.png", CHECKPOINT_FILE] {
        assert!(dir.join(file).exists(), "{file} kept");
    }

    let resumed = kes_cloth()
        .args(["resume", dir.to_str().unwrap(), "--quiet"])
        .status()
        .unwrap();
    assert!(resumed.success());
    let metrics: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.join("metrics.json")).unwrap()).unwrap();
    assert_eq!(metrics["interrupted"], false);
    assert_eq!(metrics["settled"], true, "the resumed drape settles");
}

#[test]
fn resuming_without_a_readable_checkpoint_is_an_error() {
    let dir = out_dir("bad");
    std::fs::create_dir_all(&dir).unwrap();
    let missing = kes_cloth()
        .args(["resume", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!missing.status.success());
    let text = String::from_utf8_lossy(&missing.stderr);
    assert!(
        text.starts_with("error:") && text.contains(CHECKPOINT_FILE),
        "{text}"
    );

    std::fs::write(Path::new(&dir).join(CHECKPOINT_FILE), b"not a checkpoint").unwrap();
    let corrupt = kes_cloth()
        .args(["resume", dir.to_str().unwrap()])
        .output()
        .unwrap();
    assert!(!corrupt.status.success());
    let text = String::from_utf8_lossy(&corrupt.stderr);
    assert!(text.contains("not a kes-cloth checkpoint"), "{text}");
}

/// A checkpoint keeps the fabric it ran with: if the fabric file changes before the resume, the
/// resume is refused (a silent switch of physics mid-run would give a result no run produced).
#[test]
fn a_changed_fabric_file_refuses_to_resume() {
    let dir = out_dir("changed-fabric");
    std::fs::create_dir_all(&dir).unwrap();
    let fabric = dir.join("fabric.ron");
    std::fs::copy(common::crate_path("assets/fabrics/thin_wool.ron"), &fabric).unwrap();
    let scene_text = std::fs::read_to_string(common::crate_path("scenes/drape_wool.ron"))
        .unwrap()
        .replace("../assets/fabrics/thin_wool.ron", "fabric.ron");
    let scene_path = dir.join("scene.ron");
    std::fs::write(&scene_path, scene_text).unwrap();
    let sets = ["integration.max_time_s=0.05".to_string()];
    let scene = Scene::load(&scene_path, &sets).unwrap();
    let options = RunOptions {
        checkpoint: Some(CheckpointPlan {
            dir: dir.clone(),
            every_s: 0.025,
        }),
        ..RunOptions::default()
    };
    simulate(&scene, &options);
    assert!(resume(&dir, &RunOptions::default()).is_ok(), "unchanged: resumes");

    let text = std::fs::read_to_string(&fabric).unwrap();
    std::fs::write(
        &fabric,
        text.replace("weight_mg_per_cm2: 12.5", "weight_mg_per_cm2: 13.5"),
    )
    .unwrap();
    assert_ne!(
        std::fs::read_to_string(&fabric).unwrap(),
        text,
        "the fabric was edited"
    );
    match resume(&dir, &RunOptions::default()) {
        Err(e) => assert!(e.to_string().contains("fabric"), "{e}"),
        Ok(_) => panic!("a resume with a changed fabric must be refused"),
    }
}
