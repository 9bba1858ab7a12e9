//! A study through a real Slurm cluster: planned, run as an `sbatch` job array (one task per
//! element, `deploy/slurm/task-array.sbatch`), collected, and equal to the study run locally.
//!
//! Needs a running Slurm (the README's test command starts a single-node one with
//! `deploy/slurm/local-cluster up`).

use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

mod common;

fn kes_cloth(args: &[&str], out: &Path) {
    let o = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .args(args)
        .arg("--out")
        .arg(out)
        .current_dir(common::crate_path(""))
        .output()
        .unwrap();
    assert!(o.status.success(), "{}", String::from_utf8_lossy(&o.stderr));
}

/// The study's table without its wall-clock column.
fn table(dir: &Path) -> String {
    let csv = std::fs::read_to_string(dir.join("study.csv")).unwrap();
    common::csv_without_column(&csv, "wall_time_s")
}

#[test]
fn a_study_run_as_a_slurm_job_array_equals_the_local_study() {
    let ready = Command::new("sinfo").args(["-h", "-o", "%T"]).output();
    let state = ready
        .as_ref()
        .map(|o| String::from_utf8_lossy(&o.stdout).to_string());
    assert!(
        state
            .as_ref()
            .is_ok_and(|s| s.contains("idle") || s.contains("mix") || s.contains("alloc")),
        "no Slurm node ready ({state:?}): start one with `deploy/slurm/local-cluster up` (the \
         README's test command does)"
    );
    let local = common::fresh_dir("slurm-local");
    kes_cloth(&common::CANTILEVER_STUDY, &local);
    let planned = common::fresh_dir("slurm-planned");
    kes_cloth(&[&common::CANTILEVER_STUDY[..], &["--plan"]].concat(), &planned);
    let tasks = kes_cloth::batch::read_manifest::<kes_cloth::batch::BatchLayout>(&planned)
        .unwrap()
        .tasks;

    let mut sbatch = Command::new("sbatch")
        .arg("--wait")
        .arg(format!("--array=0-{}", tasks - 1))
        .arg("--time=00:10:00")
        .arg(format!("--output={}/slurm-%A_%a.out", planned.display()))
        .arg(common::crate_path("deploy/slurm/task-array.sbatch"))
        .env("KES_BATCH_DIR", &planned)
        .env("KES_CLOTH", env!("CARGO_BIN_EXE_kes-cloth"))
        .current_dir(&planned)
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .expect("sbatch runs");
    // The array's elements take seconds; ten minutes means the cluster is stuck.
    let deadline = Instant::now() + Duration::from_secs(600);
    let status = loop {
        if let Some(status) = sbatch.try_wait().unwrap() {
            break status;
        }
        if Instant::now() > deadline {
            sbatch.kill().ok();
            panic!("the job array did not finish within 10 minutes (squeue tells why)");
        }
        std::thread::sleep(Duration::from_millis(200));
    };
    let out = sbatch.wait_with_output().unwrap();
    assert!(
        status.success(),
        "sbatch --wait: {}{}",
        String::from_utf8_lossy(&out.stdout),
        String::from_utf8_lossy(&out.stderr)
    );
    // Each task ran as its own array element: one Slurm log per task, naming it.
    let logs: Vec<String> = std::fs::read_dir(&planned)
        .unwrap()
        .flatten()
        .filter(|e| e.file_name().to_string_lossy().starts_with("slurm-"))
        .map(|e| std::fs::read_to_string(e.path()).unwrap())
        .collect();
    assert_eq!(logs.len(), tasks, "{logs:?}");
    for k in 0..tasks {
        assert!(
            logs.iter().any(|l| l.starts_with(&format!("task {k}: "))),
            "{logs:?}"
        );
    }

    let collect = Command::new(env!("CARGO_BIN_EXE_kes-cloth"))
        .arg("collect")
        .arg(&planned)
        .output()
        .unwrap();
    assert!(
        collect.status.success(),
        "{}",
        String::from_utf8_lossy(&collect.stderr)
    );
    assert_eq!(table(&planned), table(&local));
}
