//! The command line: every subcommand, option and its help text (clap).

use std::path::PathBuf;

use clap::{Parser, Subcommand};

/// Simulate woven cloth from KES-F measurements (Horiba & Shimizu's particle model on Rapier).
///
/// A scene file (`scenes/*.ron`) names a fabric (`assets/fabrics/*.ron`, in KES units), the
/// cloth sample, the rigid world (drapemeter disk, table, floor) and the effects to simulate.
/// Everything inside is SI; only the fabric files speak KES units.
#[derive(Parser)]
#[command(
    name = "kes-cloth",
    version,
    about,
    long_about,
    after_help = "Start here:\n  kes-cloth run scenes/drape_wool.ron            thin wool on the seed's drapemeter\n  kes-cloth run scenes/drape_cotton.ron --repeat 5   five seeds, modal node count, DC mean ± sd\n  kes-cloth check scenes/tablecloth_cotton.ron   the scene and its fabric, resolved in SI\n  kes-cloth run scenes/cusick_wool.ron --checkpoint-every 1   then, after Ctrl-C: kes-cloth resume out/cusick_wool\n  kes-cloth fabric import my_kes_results.csv --out my_fabrics   fabric files from a KES table\n  kes-cloth drape my_fabrics/NAME.ron --tester cusick-30   a fabric file on a built-in tester\n  kes-cloth kes assets/fabrics/thick_cotton.ron  virtual KES bending and shear tests of a fabric\n  kes-cloth study scenes/drape_wool.ron --vary cloth.spacing_m=0.0075,0.005 --reference cloth.spacing_m=0.0025   accuracy vs time\n  kes-cloth converge scenes/drape_cotton.ron --spacings 0.01,0.0075,0.005   DC at zero spacing, with its uncertainty\n  kes-cloth study ... --plan --out /shared/s; sbatch --array=0-N ...; kes-cloth collect /shared/s   a study on a cluster (docs/batches.md)\nDocs: README.md, docs/model.md (the physics), docs/rapier.md, docs/validation.md, docs/batches.md."
)]
pub struct Cli {
    #[command(subcommand)]
    pub command: Command,
}

/// Where a batch (study, convergence study) runs and writes: shared by `study` and `converge`.
#[derive(clap::Args)]
pub struct BatchArgs {
    /// Output folder, the batch's folder [default: out/<scene name>-study, or -convergence].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Runs at a time [default: all cores].
    #[arg(long, value_name = "N")]
    pub threads: Option<usize>,
    /// Only plan: write the runs as numbered task files and a manifest into DIR, for
    /// `kes-cloth task DIR K` to run anywhere DIR is shared (a Slurm job array, a Kubernetes
    /// Indexed Job, a loop) and `kes-cloth collect DIR` to combine.
    #[arg(long)]
    pub plan: bool,
    /// Keep the results already in DIR of tasks that have not changed (a batch stopped
    /// part-way, or planned and partly run elsewhere) and run only the rest. Without it, DIR's
    /// old results are removed and every run starts afresh.
    #[arg(long)]
    pub resume: bool,
}

/// What a run writes and how it repeats: shared by `run` and `drape`.
#[derive(clap::Args)]
pub struct RunArgs {
    /// Output folder [default: out/<scene name>].
    #[arg(long, value_name = "DIR")]
    pub out: Option<PathBuf>,
    /// Override a scene field by its path, e.g. `integration.dt_s=0.0005`,
    /// `cloth.spacing_m=0.008`, `seed=7`, `effects.stretch=Kes`, `cloth.centre_m=(0, 0.02, 0)`,
    /// `world.colliders.0.friction=0` (a list element by its index), `cloth.pins_m=[(0, 0.5,
    /// 0), (0.1, 0.5, 0)]`, `"world.colliders.0.motion=Dynamic(mass_kg: 0.05,
    /// velocity_m_per_s: (0, -10, 0))"` (values are written as in the scene file; quote them
    /// for the shell). Repeatable.
    #[arg(long = "set", value_name = "KEY=VALUE")]
    pub set: Vec<String>,
    /// No progress bar and no summary.
    #[arg(long)]
    pub quiet: bool,
    /// Repeat the run with seeds 0..N-1 of the start roughness (on all cores), write
    /// each into DIR/seed-K/, and report the node counts the runs formed (most frequent first,
    /// each with its DC: a drape near a change of shape forms more than one) and DC's mean,
    /// sample standard deviation and the mean's standard error (DIR/repeat.json,
    /// DIR/report.html). The runs are a batch (DIR/tasks/, DIR/results/), as
    /// `study`'s are.
    #[arg(long, value_name = "N")]
    pub repeat: Option<usize>,
    /// With --repeat on a circular cloth: also shift the node lattice against the outline in
    /// each run (an even spread over ± half a spacing; run 0 keeps the scene's lattice), so the
    /// spread of DC and nodes includes where the grid falls against the disk's rim. With
    /// cloth.roughness=Smooth (one start for every lattice) the runs keep the scene's seed and
    /// the spread is the lattice's alone; with the default per-node roughness, another start on
    /// every lattice anyway, run k has seed k (docs/accuracy.md).
    #[arg(long, requires = "repeat")]
    pub placements: bool,
    /// Skip the companion run that estimates the numerical error of a single run's measured
    /// values (DC, corner hang, cantilever chord): by default the same scene is run again at
    /// 1.5 times the spacing (2 or 3 times where a clamp's or a table's edge lies on a row of nodes, so that it lies on one in both runs), which costs about half as much
    /// again, and each value is printed as value ± error. The companion takes the run's step,
    /// so the error is the lattice's at that step; the step's own share is measured with
    /// `kes-cloth study SCENE --vary integration.dt_s=...` (docs/accuracy.md, "The step").
    #[arg(long)]
    pub no_error_estimate: bool,
    /// With --repeat: only plan the runs as task files in DIR (`--out`), for `kes-cloth task`
    /// to run anywhere DIR is shared and `kes-cloth collect DIR` to summarise.
    #[arg(long, requires = "repeat")]
    pub plan: bool,
    /// With --repeat: keep the finished runs already in DIR (of unchanged tasks) and run only
    /// the rest.
    #[arg(long, requires = "repeat")]
    pub resume: bool,
}

#[derive(Subcommand)]
pub enum Command {
    /// Run a scene until the cloth settles (or the scene's time limit) and write its results.
    ///
    /// Writes into DIR (default `out/<scene name>/`): `metrics.json` (all SI, units in the
    /// keys), `final.obj` (the draped mesh, metres, +y up), `top.png` (a top view shaded by
    /// height with the disk or table outline), `side.png` (a side view), `final.glb` (the mesh as
    /// binary glTF) and `report.html` (the figures, both pictures, a 3D view and the fabric on one
    /// page, opened offline). Prints a short summary.
    ///
    /// Example: kes-cloth run scenes/drape_wool.ron --set integration.dt_s=0.0002 --set seed=3
    Run {
        /// The scene file (RON).
        scene: PathBuf,
        #[command(flatten)]
        args: RunArgs,
        /// Write `DIR/checkpoint.cbor` every SECONDS of simulated time (and on Ctrl-C), so that
        /// `kes-cloth resume DIR` can continue the run; the resumed run ends exactly where an
        /// uninterrupted one would.
        #[arg(long, value_name = "SECONDS")]
        checkpoint_every: Option<f64>,
    },
    /// Continue a run from the checkpoint in DIR (written by `run --checkpoint-every`, or on
    /// Ctrl-C) to its end, and write its results into DIR as `run` would.
    ///
    /// Example: kes-cloth run scenes/drape_cotton.ron --checkpoint-every 0.5   (Ctrl-C)
    ///          kes-cloth resume out/drape_cotton
    Resume {
        /// The run's output folder, holding `checkpoint.cbor`.
        dir: PathBuf,
        /// No progress bar and no summary.
        #[arg(long)]
        quiet: bool,
        /// Skip the companion run that estimates the numerical error (as `run
        /// --no-error-estimate`).
        #[arg(long)]
        no_error_estimate: bool,
    },
    /// Measure what accuracy costs in time: run a scene across a grid of settings (in parallel)
    /// and compare every run with a converged reference.
    ///
    /// Writes into DIR (default `out/<scene name>-study/`): `study.csv` and `study.md` (one row
    /// per setting: spacing, step, particles, steps, wall time, DC and nodes, DC error and shape
    /// error against the reference, strain, settled) and `work_precision.png` (error against
    /// wall time, log-log, one curve per varied key, the scene as shipped marked), and the batch
    /// itself: `tasks/K.ron` (each run as a self-contained scene), `results/K.json` and `runs/K/`
    /// (each run's own outputs). With `--plan` nothing runs: `kes-cloth task` runs the tasks,
    /// here or on a cluster, and `kes-cloth collect` writes the report (docs/batches.md).
    ///
    /// Grid points whose explicit step the stability guard refuses are listed in `study.md`, not
    /// run. With `--placements N` (circular cloths only) every point and the reference run N
    /// times, run k on the k-th lattice placement (and seed k, unless cloth.roughness=Smooth),
    /// and rows compare means.
    ///
    /// Example: kes-cloth study scenes/drape_wool.ron --placements 4
    ///   --vary cloth.spacing_m=0.0125,0.01,0.0075 --vary integration.dt_s=0.0002,0.0001
    ///   --reference cloth.spacing_m=0.005 --reference integration.dt_s=0.0000625
    Study {
        /// The scene file (RON).
        scene: PathBuf,
        /// A field to vary and its values, e.g. `integration.dt_s=0.0005,0.00025,0.000125`.
        /// Repeatable: the grid is the product of all of them.
        #[arg(long, value_name = "KEY=V1,V2,...", required = true)]
        vary: Vec<kes_cloth::study::Vary>,
        /// An override that makes the converged reference (finest spacing, smallest step).
        /// Repeatable. Without any, the scene as shipped is the reference.
        #[arg(long, value_name = "KEY=VALUE")]
        reference: Vec<String>,
        /// An override applied to every run, reference included. Repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        /// Run every grid point and the reference N times, run k on its own placement of the
        /// node lattice against a circular cloth's outline and with seed k unless
        /// cloth.roughness=Smooth (as `run --repeat N --placements`), and compare means: a single run at 1 cm scatters by ±0.02 in DC from
        /// where the grid falls alone (docs/accuracy.md §1a).
        #[arg(long, value_name = "N", default_value_t = 1)]
        placements: usize,
        #[command(flatten)]
        batch: BatchArgs,
    },
    /// How far a result is from the fabric's own answer: run a scene at three or more node
    /// spacings, fit the observed order of convergence, and extrapolate its drape coefficient
    /// (or tablecloth corner hang) to zero spacing with a numerical uncertainty.
    ///
    /// Each spacing σ runs at the step dt·(σ/σ₀)^q (σ₀, dt the scene's; q from --step-exponent,
    /// default 2 for explicit scenes, whose stability limits shrink as σ², 0 for implicit ones).
    /// Richardson extrapolation on the finest three spacings gives the value at σ → 0; its
    /// uncertainty is Roache's grid convergence index (safety factor 1.25 when the order lies in
    /// [0.5, 4], else 3 times the largest change between neighbouring spacings: those spacings
    /// are not yet in the asymptotic range). Writes `convergence.csv`, `convergence.md` and
    /// `convergence.png` (the quantity against σ, the fitted law, the band at σ → 0) into DIR
    /// (default `out/<scene name>-convergence/`).
    ///
    /// Example: kes-cloth converge scenes/drape_cotton.ron --spacings 0.01,0.0075,0.005
    ///   --placements 4
    Converge {
        /// The scene file (RON).
        scene: PathBuf,
        /// Node spacings (m), at least three, comma-separated.
        #[arg(long, value_name = "S1,S2,S3,...", value_delimiter = ',', required = true)]
        spacings: Vec<f64>,
        /// q in dt ∝ σ^q [default: 2 explicit, 0 implicit].
        #[arg(long, value_name = "Q")]
        step_exponent: Option<f64>,
        /// Runs per spacing, run k on the k-th lattice placement (circular cloths; seed k unless
        /// cloth.roughness=Smooth): where the lattice meets the rim scatters a single run's DC.
        #[arg(long, value_name = "N", default_value_t = 1)]
        placements: usize,
        /// An override applied to every run. Repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
        #[command(flatten)]
        batch: BatchArgs,
    },
    /// Run one task of a planned batch (`study --plan`, `converge --plan`) and write its result.
    ///
    /// Writes `DIR/results/K.json` (the run's metrics and final node positions, SI) through a
    /// temporary file and a rename, so a killed task leaves no partial result; a task whose
    /// result is already there does nothing. Without K, the index comes from the scheduler:
    /// Slurm's SLURM_ARRAY_TASK_ID or a Kubernetes Indexed Job's JOB_COMPLETION_INDEX.
    ///
    /// Example: kes-cloth study scenes/drape_wool.ron --vary cloth.spacing_m=0.01,0.0075
    ///   --reference cloth.spacing_m=0.005 --plan --out runs/wool
    ///          kes-cloth task runs/wool 0     (and 1, 2, in any order, on any machine)
    ///          kes-cloth collect runs/wool
    Task {
        /// The batch folder (holding `manifest.json` and `tasks/`).
        dir: PathBuf,
        /// The task's index, 0 to tasks − 1 [default: from the scheduler's environment].
        index: Option<usize>,
        /// Print nothing on success.
        #[arg(long)]
        quiet: bool,
    },
    /// Combine a batch's finished tasks into its report (`study.md`, `study.csv`, the plots;
    /// `convergence.md` ...), written into DIR.
    ///
    /// A study is collected from whatever has finished: grid points with a run missing are left
    /// out and listed, and the exit code is 1 until every task has finished. A convergence study
    /// needs every task.
    ///
    /// Example: kes-cloth collect runs/wool
    Collect {
        /// The batch folder.
        dir: PathBuf,
    },
    /// The virtual KES laboratory: simulate a KES-FB2 bending test and a KES-FB1 shear test on a
    /// strip of a fabric, with the same force generators as every scene, and read B, 2HB, G, 2HG
    /// and 2HG5 as the instruments would, beside the fabric file's values (KES units).
    ///
    /// Bending sweeps the curvature 0 → +2.5 → −2.5 → +2.5 cm⁻¹ (B: mean branch slope over
    /// 0.5–1.5 cm⁻¹; 2HB: loop width at ±1 cm⁻¹). Shear sweeps the angle 0 → +8° → −8° → +8°
    /// (G: mean branch slope over 0.5°–5°; 2HG, 2HG5: loop widths at ±0.5°, ±5°). Both read the
    /// closed loop after the first loading. Writes the
    /// loops into DIR (default `out/kes-<fabric file name>/`) as `kes_bending.png` and
    /// `kes_shear.png`.
    ///
    /// Example: kes-cloth kes assets/fabrics/thick_cotton.ron --spacing-m 0.005
    Kes {
        /// The fabric file (RON, KES units).
        fabric: PathBuf,
        /// Node spacing of the simulated strips (m), at most 7.4 mm.
        #[arg(long, value_name = "METRES", default_value_t = 0.005)]
        spacing_m: f64,
        /// Leave the hysteresis effect off: the elastic mean curves alone (no loop).
        #[arg(long)]
        no_hysteresis: bool,
        /// Print one JSON object (`{"B_warp": {"file": v, "recovered": v}, ...}`, KES units)
        /// instead of the table.
        #[arg(long)]
        json: bool,
        /// Output folder for the loop plots [default: out/kes-<fabric file name>].
        #[arg(long, value_name = "DIR")]
        out: Option<PathBuf>,
    },
    /// Drape a fabric file on a built-in tester, without writing a scene.
    ///
    /// The tester's specimen, disk or table, integration and settle criterion are the shipped
    /// scenes' (scenes/drape_*.ron, scenes/cusick_*.ron, scenes/tablecloth_*.ron); the lattice
    /// spacing is chosen from the fabric as the shipped scenes' is: on the drapemeters (BDF2 at
    /// 1/240 s) the coarsest of 2.5, 1.875, 1.25 mm within a sixth of the fabric's shorter
    /// bending length, where thin wool's and thick cotton's drapes move by less than 0.01 with
    /// the lattice's placement and, on the seed's drapemeter, lie within 0.01 of their limits
    /// (both 2.5 mm; thin wool on the Cusick tester drapes 0.015 higher at 1.875 mm, with a
    /// node more, so its figure there is uncertain by that much: docs/accuracy.md); the tablecloth
    /// keeps its 3.33 mm (a thirtieth of the table's half-width: the table's edge on a row of
    /// nodes). Writes what `run` writes, into DIR (default
    /// out/<tester>-<fabric file name>/).
    ///
    /// Example: kes-cloth drape assets/fabrics/thin_wool.ron --tester cusick-30 --repeat 3
    Drape {
        /// The fabric file (RON, KES units; `kes-cloth fabric import` writes them from a table).
        fabric: PathBuf,
        /// The tester.
        #[arg(long, value_enum, default_value = "seed")]
        tester: TesterArg,
        #[command(flatten)]
        args: RunArgs,
    },
    /// Fabric files: import them from a KES table (CSV), or check one.
    #[command(subcommand)]
    Fabric(FabricCommand),
    /// Validate a scene and print its resolved parameters in SI, without running it.
    Check {
        /// The scene file (RON).
        scene: PathBuf,
        /// Override a scene field by its path (as for `run`). Repeatable.
        #[arg(long = "set", value_name = "KEY=VALUE")]
        set: Vec<String>,
    },
}

/// What `kes-cloth fabric` does.
#[derive(Subcommand)]
pub enum FabricCommand {
    /// Write one fabric file (RON, KES units) per row of a CSV table of KES-F results.
    ///
    /// The header names the columns as KES reports do: name, source, W, T, B-1, B-2 (or B for
    /// both directions), 2HB-1, 2HB-2 (or 2HB), G, 2HG, 2HG5, LT-1, LT-2, WT-1, WT-2, RT-1, RT-2,
    /// EMT-1, EMT-2 (or LT, WT, RT, EMT); -1 is the warp, -2 the weft ("B warp", "B_weft" work
    /// too). Units are KES's own: W mg/cm², T mm, B gf·cm²/cm, 2HB gf·cm/cm, G gf/(cm·deg),
    /// 2HG and 2HG5 gf/cm, LT dimensionless, WT gf·cm/cm², RT and EMT %. A units row may follow
    /// the header (its name cell reads "units"); W may then be in g/m². Every row is validated
    /// as a fabric file is; an error names the row and column. `source` must say where the
    /// numbers come from.
    ///
    /// Example: kes-cloth fabric import assets/fabrics/example_kes_table.csv --out my_fabrics
    Import {
        /// The CSV table, one fabric per row.
        table: PathBuf,
        /// Folder for the fabric files, named after each fabric [default: fabrics].
        #[arg(long, value_name = "DIR", default_value = "fabrics")]
        out: PathBuf,
    },
    /// Print a fabric file's values in KES and SI units, with its bending lengths.
    ///
    /// Example: kes-cloth fabric check assets/fabrics/thin_wool.ron
    Check {
        /// The fabric file (RON, KES units).
        fabric: PathBuf,
    },
}

/// The built-in testers on the command line.
#[derive(Clone, Copy, clap::ValueEnum)]
pub enum TesterArg {
    /// The seed's drapemeter: a 25.4 cm (10 in) specimen on a 12.7 cm (5 in) disk.
    Seed,
    /// Cusick (BS 5058 / ISO 9073-9): a 24 cm specimen on the 18 cm disk.
    #[value(name = "cusick-24")]
    Cusick24,
    /// Cusick: a 30 cm specimen on the 18 cm disk (the standard's usual one).
    #[value(name = "cusick-30")]
    Cusick30,
    /// Cusick: a 36 cm specimen on the 18 cm disk (for limp fabrics).
    #[value(name = "cusick-36")]
    Cusick36,
    /// The seed's tablecloth: a 40 cm square on a 20 cm square table.
    Tablecloth,
}

impl From<TesterArg> for kes_cloth::scene::Tester {
    fn from(t: TesterArg) -> Self {
        use kes_cloth::scene::Tester;
        match t {
            TesterArg::Seed => Tester::Seed,
            TesterArg::Cusick24 => Tester::Cusick24,
            TesterArg::Cusick30 => Tester::Cusick30,
            TesterArg::Cusick36 => Tester::Cusick36,
            TesterArg::Tablecloth => Tester::Tablecloth,
        }
    }
}
