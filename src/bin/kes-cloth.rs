//! `kes-cloth`: run and check cloth scenes built from Kawabata (KES-F) fabric measurements.

use std::io::IsTerminal;
use std::path::PathBuf;
use std::process::ExitCode;

use clap::{Parser, Subcommand};
use kes_cloth::run::{RunOptions, simulate, summary, write_outputs};
use kes_cloth::scene::Scene;

/// Simulate woven cloth from KES-F measurements (Horiba & Shimizu's particle model on Rapier).
///
/// A scene file (`scenes/*.ron`) names a fabric (`assets/fabrics/*.ron`, in KES units), the
/// cloth sample, the rigid world (drapemeter disk, table, floor) and the effects to simulate.
/// Everything inside is SI; only the fabric files speak KES units.
#[derive(Parser)]
#[command(name = "kes-cloth", version, about, long_about)]
struct Cli {
    #[command(subcommand)]
    command: Command,
}

#[derive(Subcommand)]
enum Command {
    /// Run a scene until the cloth settles (or the scene's time limit) and write its results.
    ///
    /// Writes into DIR (default `out/<scene name>/`): `metrics.json` (all SI, units in the
    /// keys), `final.obj` (the draped mesh, metres, +y up) and `top.png` (a top view shaded by
    /// height with the disk or table outline). Prints a short summary.
    ///
    /// Example: kes-cloth run scenes/drape_wool.ron --set integration.dt_s=0.0002 --set seed=3
    Run {
        /// The scene file (RON).
        scene: PathBuf,
        /// Output folder [default: out/<scene name>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
        /// Override a scene field by its path, e.g. `integration.dt_s=0.0005`,
        /// `cloth.spacing_m=0.008`, `seed=7`, `effects.stretch=Kes`. Repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// No progress bar and no summary.
        #[arg(long)]
        quiet: bool,
    },
    /// Validate a scene and print its resolved parameters in SI, without running it.
    Check {
        /// The scene file (RON).
        scene: PathBuf,
        /// Override a scene field by its path (as for `run`). Repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
}

fn main() -> ExitCode {
    let cli = Cli::parse();
    match cli.command {
        Command::Run {
            scene,
            out,
            set,
            quiet,
        } => {
            let scene = match Scene::load(&scene, &set) {
                Ok(s) => s,
                Err(e) => return fail(&e),
            };
            let dir = out.unwrap_or_else(|| PathBuf::from("out").join(&scene.spec.name));
            let options = RunOptions {
                progress: !quiet && std::io::stderr().is_terminal(),
            };
            let outcome = simulate(&scene, &options);
            if let Err(e) = write_outputs(&scene, &outcome, &dir) {
                return fail(&e);
            }
            if let Some(f) = &outcome.metrics.failure {
                return fail(&kes_cloth::run::DivergenceError(f.clone()));
            }
            if !quiet {
                println!("{}", summary(&outcome));
                println!("  wrote {}", dir.display());
            }
            ExitCode::SUCCESS
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

fn fail(e: &dyn std::fmt::Display) -> ExitCode {
    eprintln!("error: {e}");
    ExitCode::FAILURE
}
