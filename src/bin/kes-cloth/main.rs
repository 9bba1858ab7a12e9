//! `kes-cloth`: run and check cloth scenes built from Kawabata (KES-F) fabric measurements.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::Parser;
use std::sync::Arc;
use std::sync::atomic::{AtomicBool, Ordering};

use kes_cloth::run::{CheckpointPlan, RunOptions, RunOutcome, simulate, summary, write_outputs};
use kes_cloth::scene::Scene;

mod batch_commands;
mod cli;

use cli::{Cli, Command, FabricCommand, RunArgs};

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            args,
            checkpoint_every,
        } => {
            let scene = match Scene::load(&scene, &args.set) {
                Ok(s) => s,
                Err(e) => return fail(&e),
            };
            run_scene(&scene, args, checkpoint_every)
        }
        Command::Drape { fabric, tester, args } => {
            let tester = kes_cloth::scene::Tester::from(tester);
            let scene = match kes_cloth::scene::tester_scene(tester, &fabric, &args.set) {
                Ok(s) => s,
                Err(e) => return fail(&e),
            };
            if !args.quiet {
                eprintln!(
                    "{} on the {} tester: spacing {} m, step {} s ({:?})",
                    scene.fabric.name,
                    tester.name(),
                    scene.spec.cloth.spacing_m,
                    scene.spec.integration.dt_s,
                    scene.spec.integration.integrator
                );
            }
            run_scene(&scene, args, None)
        }
        Command::Resume {
            dir,
            quiet,
            no_error_estimate,
        } => {
            let options = RunOptions {
                progress: !quiet && std::io::stderr().is_terminal(),
                checkpoint: None,
                interrupt: Some(interrupt_flag()),
            };
            match kes_cloth::run::resume(&dir, &options) {
                Ok((scene, mut outcome)) => {
                    // As the uninterrupted run would have: the companion for the error estimate.
                    if !no_error_estimate {
                        kes_cloth::run::estimate_error(&scene, &mut outcome, &options);
                    }
                    finish_run(&scene, &outcome, &dir, quiet)
                }
                Err(e) => fail(&e),
            }
        }
        Command::Study {
            scene,
            vary,
            reference,
            set,
            placements,
            batch,
        } => {
            let plan = kes_cloth::study::StudyPlan {
                vary,
                reference,
                placements,
            };
            batch_commands::study(&scene, &plan, &set, &batch)
        }
        Command::Converge {
            scene,
            spacings,
            step_exponent,
            placements,
            set,
            batch,
        } => {
            let plan = kes_cloth::study::ConvergencePlan {
                spacings,
                step_exponent,
                placements,
            };
            batch_commands::converge(&scene, &plan, &set, &batch)
        }
        Command::Task { dir, index, quiet } => batch_commands::task(&dir, index, quiet),
        Command::Collect { dir } => batch_commands::collect(&dir),
        Command::Kes {
            fabric,
            spacing_m,
            no_hysteresis,
            json,
            out,
        } => run_kes_lab(&fabric, spacing_m, !no_hysteresis, json, out),
        Command::Fabric(FabricCommand::Import { table, out }) => import_fabrics(&table, &out),
        Command::Fabric(FabricCommand::Check { fabric }) => {
            match kes_cloth::material::Fabric::load_with_kes(&fabric) {
                Ok((kes, fabric)) => {
                    print!("{}", kes_cloth::output::fabric_sheet(&kes, &fabric));
                    ExitCode::SUCCESS
                }
                Err(e) => fail(&e),
            }
        }
        Command::Check { scene, set } => match Scene::load(&scene, &set) {
            Ok(s) => {
                println!("{}", kes_cloth::scene::describe(&s));
                ExitCode::SUCCESS
            }
            Err(e) => fail(&e),
        },
    }
}

/// A flag that Ctrl-C sets: the run stops after its current step, writes a checkpoint (when
/// checkpointing) and its partial outputs.
fn interrupt_flag() -> Arc<AtomicBool> {
    let flag = Arc::new(AtomicBool::new(false));
    let handler_flag = flag.clone();
    if let Err(e) = ctrlc::set_handler(move || handler_flag.store(true, Ordering::Relaxed)) {
        eprintln!("warning: Ctrl-C will not keep partial results: {e}");
    }
    flag
}

/// Writes a run's outputs and reports it; exit status 1 for a failed run, 130 for an
/// interrupted one.
fn finish_run(scene: &Scene, outcome: &RunOutcome, dir: &std::path::Path, quiet: bool) -> ExitCode {
    if let Err(e) = write_outputs(scene, outcome, dir) {
        return fail(&e);
    }
    if let Some(e) = &outcome.checkpoint_error {
        eprintln!("warning: a checkpoint could not be written: {e}");
    }
    if let Some(f) = &outcome.metrics.failure {
        return fail(&kes_cloth::run::DivergenceError(f.clone()));
    }
    if outcome.metrics.interrupted {
        let resume = if dir.join(kes_cloth::checkpoint::CHECKPOINT_FILE).exists() {
            format!("; continue with: kes-cloth resume {}", dir.display())
        } else {
            String::new()
        };
        eprintln!(
            "interrupted at t = {:.3} s: partial results in {}{resume}",
            outcome.metrics.sim_time_s,
            dir.display()
        );
        return ExitCode::from(130);
    }
    if !quiet {
        println!("{}", summary(outcome));
        println!("  wrote {}", dir.display());
    }
    ExitCode::SUCCESS
}

fn run_kes_lab(
    path: &std::path::Path,
    spacing: f64,
    hysteresis: bool,
    json: bool,
    out: Option<PathBuf>,
) -> ExitCode {
    let fabric = match kes_cloth::material::Fabric::load(path) {
        Ok(f) => f,
        Err(e) => return fail(&e),
    };
    // The strips must bend to 2.5 cm⁻¹ on the three-crossing circle: K ≤ 2cos(π/8)/σ.
    let coarsest = 2.0 * (std::f64::consts::PI / 8.0).cos() / kes_cloth::kes_lab::bending_test::MAX_CURVATURE;
    if !(spacing.is_finite() && (0.0005..=coarsest).contains(&spacing)) {
        return fail(&format!(
            "--spacing-m = {spacing}: must lie in [0.0005, {coarsest:.5}] m: a coarser strip cannot \
             bend to 2.5 cm⁻¹ on the circle of three crossings (docs/model.md §13)"
        ));
    }
    let report = kes_cloth::kes_lab::run_kes_lab(&fabric, spacing, hysteresis);
    let stem = path
        .file_stem()
        .map_or("fabric".into(), |s| s.to_string_lossy().into_owned());
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(format!("kes-{stem}")));
    if let Err(e) = std::fs::create_dir_all(&dir) {
        return fail(&format!("{}: cannot create: {e}", dir.display()));
    }
    if let Err(e) = kes_cloth::kes_lab::write_loop_plots(&report, &dir) {
        return fail(&e);
    }
    if json {
        println!("{}", report.json());
    } else {
        print!("{}", report.table());
        println!("wrote {}/kes_bending.png, kes_shear.png", dir.display());
    }
    ExitCode::SUCCESS
}

fn fail(e: &dyn std::fmt::Display) -> ExitCode {
    eprintln!("error: {e}");
    ExitCode::FAILURE
}

/// `kes-cloth fabric import`: validates every row first, then writes one file per fabric.
fn import_fabrics(table: &std::path::Path, out: &std::path::Path) -> ExitCode {
    use kes_cloth::material::{fabric_file_stem, fabric_file_text, read_kes_table};
    let fabrics = match read_kes_table(table) {
        Ok(f) => f,
        Err(e) => return fail(&e),
    };
    if fabrics.is_empty() {
        return fail(&format!("{}: the table has no fabric rows", table.display()));
    }
    if let Err(e) = std::fs::create_dir_all(out) {
        return fail(&format!("{}: cannot create the folder: {e}", out.display()));
    }
    let mut stems = std::collections::HashSet::new();
    for fabric in &fabrics {
        let mut stem = fabric_file_stem(&fabric.kes.name);
        if !stems.insert(stem.clone()) {
            stem = format!("{stem}_row{}", fabric.row);
            stems.insert(stem.clone());
        }
        let path = out.join(format!("{stem}.ron"));
        if let Err(e) = std::fs::write(&path, fabric_file_text(fabric, table)) {
            return fail(&format!("{}: cannot write: {e}", path.display()));
        }
        println!("{}  ({}, row {})", path.display(), fabric.kes.name, fabric.row);
    }
    println!(
        "{} fabric file(s) written; check one with: kes-cloth fabric check {}",
        fabrics.len(),
        out.join(format!("{}.ron", fabric_file_stem(&fabrics[0].kes.name)))
            .display()
    );
    ExitCode::SUCCESS
}

/// Runs `scene` once (or `--repeat` times) into `--out` (default `out/<scene name>`).
fn run_scene(scene: &Scene, args: RunArgs, checkpoint_every: Option<f64>) -> ExitCode {
    let RunArgs {
        out,
        quiet,
        repeat,
        placements,
        no_error_estimate,
        plan,
        resume,
        ..
    } = args;
    if (plan || resume) && repeat.is_none() {
        return fail(
            &"--plan and --resume apply to --repeat (a single run resumes from a checkpoint: --checkpoint-every)",
        );
    }
    let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&scene.spec.name));
    if let Some(n) = repeat {
        if checkpoint_every.is_some() {
            return fail(&"--checkpoint-every applies to a single run, not to --repeat");
        }
        let at = cli::BatchArgs {
            out: Some(dir),
            threads: None,
            plan,
            resume,
        };
        return batch_commands::repeat(scene, n, placements, &at, quiet);
    }
    // A checkpoint left in DIR by an earlier run is not this run's to resume.
    let stale = dir.join(kes_cloth::checkpoint::CHECKPOINT_FILE);
    if stale.exists()
        && let Err(e) = std::fs::remove_file(&stale)
    {
        return fail(&format!(
            "{}: cannot remove the earlier run's checkpoint: {e}",
            stale.display()
        ));
    }
    if let Some(every) = checkpoint_every
        && !(every.is_finite() && every > 0.0)
    {
        return fail(&format!(
            "--checkpoint-every = {every}: must be a positive number of simulated seconds"
        ));
    }
    let options = RunOptions {
        progress: !quiet && std::io::stderr().is_terminal(),
        checkpoint: checkpoint_every.map(|every_s| CheckpointPlan {
            dir: dir.clone(),
            every_s,
        }),
        interrupt: Some(interrupt_flag()),
    };
    let outcome = if no_error_estimate {
        simulate(scene, &options)
    } else {
        if options.progress && kes_cloth::run::measures_something(scene) {
            eprintln!(
                "estimating the numerical error alongside, on a second thread: the same scene at {}× the spacing",
                kes_cloth::run::companion_ratio(scene)
            );
        }
        kes_cloth::run::simulate_with_error_estimate(scene, &options)
    };
    finish_run(scene, &outcome, &dir, quiet)
}
