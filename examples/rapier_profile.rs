//! Where Rapier's step spends its time on the drape scene, and how each part grows with the node
//! count: the profile behind `docs/accuracy.md` §3's growth exponent.
//!
//! ```sh
//! cargo run --release --features rapier-profiler --example rapier_profile [-- 1000 4000 16000 64000]
//! ```
//!
//! The scene is `benches/drape_step.rs`'s: thick cotton on the drapemeter at about N nodes,
//! explicit at 0.125 ms·(σ/1 cm)², the sample starting 0.55σ above the disk. After 240 warm-up
//! steps, Rapier's own stage timers are summed over the next steps and printed per step.

use kes_cloth::scene::Scene;
use kes_cloth::schedule::{Physics, build_step_schedule};
use rapier3d::counters::Counters;

/// Sample diameter (m) of the drape scene.
const DIAMETER: f64 = 0.254;
/// Steps before timing (`KES_PROFILE_WARM_UP` overrides it, e.g. for a short run under
/// `valgrind --tool=callgrind`).
const WARM_UP: usize = 240;

/// Rapier's stages we report, in ms: (name, reader).
type Stage = (&'static str, fn(&Counters) -> f64);

const STAGES: [Stage; 9] = [
    ("whole step", |c| c.step_time_ms()),
    ("collision detection", |c| {
        c.stages.collision_detection_time.time_ms()
    }),
    ("  broad phase", |c| c.cd.broad_phase_time.time_ms()),
    ("  narrow phase", |c| c.cd.narrow_phase_time.time_ms()),
    ("island construction", |c| {
        c.stages.island_construction_time.time_ms()
    }),
    ("solver", |c| c.stages.solver_time.time_ms()),
    ("  constraint assembly", |c| {
        c.solver.velocity_assembly_time.time_ms()
    }),
    ("  velocity resolution", |c| {
        c.solver.velocity_resolution_time.time_ms()
    }),
    ("  velocity update", |c| c.solver.velocity_update_time.time_ms()),
];

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let sizes: Vec<usize> = std::env::args()
        .skip(1)
        .map(|a| a.parse())
        .collect::<Result<_, _>>()?;
    let sizes = if sizes.is_empty() {
        vec![1_000, 4_000, 16_000, 64_000]
    } else {
        sizes
    };
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/drape_cotton.ron");
    let mut columns = Vec::new();
    for &nodes in &sizes {
        // A circle of diameter D at spacing σ holds about (π/4)(D/σ)² nodes.
        let spacing = DIAMETER * (std::f64::consts::PI / (4.0 * nodes as f64)).sqrt();
        let dt = 1.25e-4 * (spacing / 0.01).powi(2);
        let sets = [
            format!("cloth.spacing_m={spacing}"),
            format!("cloth.perturbation_m={}", spacing / 20.0),
            format!("cloth.centre_m=[0.0,{},0.0]", 0.55 * spacing),
            format!("integration.dt_s={dt}"),
        ];
        let scene = Scene::load(path, &sets)?;
        let (mut world, cloth) = kes_cloth::scene::spawn::spawn(&scene);
        let count = world
            .get::<kes_cloth::schedule::ClothState>(cloth)
            .map_or(0, |s| s.positions.len());
        let mut schedule = build_step_schedule();
        let warm_up = std::env::var("KES_PROFILE_WARM_UP")
            .ok()
            .and_then(|v| v.parse().ok());
        for _ in 0..warm_up.unwrap_or(WARM_UP) {
            schedule.run(&mut world);
        }
        world
            .resource_mut::<Physics>()
            .0
            .physics_pipeline
            .counters
            .enable();
        // About 2 s of stepping per size (`KES_PROFILE_STEPS` overrides it).
        let steps = std::env::var("KES_PROFILE_STEPS")
            .ok()
            .and_then(|v| v.parse().ok())
            .unwrap_or((2e6 / count as f64).clamp(20.0, 2_000.0) as usize);
        let mut sums = [0.0; STAGES.len()];
        for _ in 0..steps {
            schedule.run(&mut world);
            let counters = &world.resource::<Physics>().0.physics_pipeline.counters;
            for (sum, (_, read)) in sums.iter_mut().zip(STAGES) {
                *sum += read(counters);
            }
        }
        let counters = &world.resource::<Physics>().0.physics_pipeline.counters;
        eprintln!(
            "{count} nodes: {steps} steps, {} contact pairs, {} constraints",
            counters.cd.ncontact_pairs, counters.solver.nconstraints
        );
        columns.push((count, sums.map(|s| s / steps as f64)));
    }
    print!("| Rapier stage (ms per step) |");
    for (count, _) in &columns {
        print!(" {count} nodes |");
    }
    println!(" growth, first to last size |");
    println!("|---|{}---|", "---|".repeat(columns.len()));
    for (k, (name, _)) in STAGES.iter().enumerate() {
        print!("| {name} |");
        for (_, ms) in &columns {
            print!(" {:.3} |", ms[k]);
        }
        let (first, last) = (columns[0], columns[columns.len() - 1]);
        let exponent = (last.1[k] / first.1[k]).ln() / (last.0 as f64 / first.0 as f64).ln();
        println!(" N^{exponent:.2} |");
    }
    Ok(())
}
