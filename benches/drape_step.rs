//! One step of the drape scene (thick cotton on the seed's drapemeter, explicit, in contact with
//! the disk) at about 1k, 4k, 16k and 64k nodes, and the same sample as Rapier's
//! built-in soft-body cloth (its default warp/weft/shear edges and bend edges, none of our
//! forces) at the same node count, step and solver settings: the peer baseline.
//!
//! The implicit path (`drape_step_implicit`): thick cotton with the KES tensile law, backward
//! Euler at 1/240 s, cell-area masses and the default (`Auto`) preconditioner, at about 1k, 2k,
//! 4k, 8k, 16k, 32k and 64k nodes.
//!
//! Criterion times a whole step of each. After each size, the split of our step (our force
//! generators, the implicit solve if any, Rapier's step, and measurement = the rest) is printed
//! from the scene runner's own per-effect ledger, and for the implicit path the solve's own
//! split (assembly, preconditioner set-up, conjugate gradients, the rest) and its products a
//! step; at the end, the fitted exponent of the step's cost in N. The implicit path's split and
//! exponent come from the same 24 steps at every size (0.1–0.2 s of the drape), timed before
//! criterion's samples, which step the world on. `KES_BENCH_MAX_NODES`
//! (default 70000) skips larger sizes for a quick run; `KES_BENCH_PATH=explicit` or
//! `implicit` runs one path only (a criterion filter alone still runs every size's warm-up).

use std::hint::black_box;
use std::time::Instant;

use bevy_ecs::prelude::*;
use criterion::{BenchmarkId, Criterion, criterion_group, criterion_main};
use glam::Vec3;
use kes_cloth::bodies::{add_world_collider, configure_world};
use kes_cloth::scene::Scene;
use kes_cloth::scene::spawn::{spawn, world_shapes};
use kes_cloth::schedule::{EffectLedger, Implicit, build_step_schedule};
use rapier3d::prelude::*;

/// Sample diameter (m) of the drape scene.
const DIAMETER: f64 = 0.254;
/// Steps run before timing, so the cloth is in contact with the disk.
const SETTLE_STEPS: usize = 240;

/// The drape scene at about `nodes` nodes. The explicit step limits of bending and of the link
/// compression spring scale as σ² (the spring's is 0.139 ms at 1 cm for thick cotton), so the
/// step is 0.125 ms·(σ/1 cm)², inside the stability guard at every size; the sample starts 0.55σ above the
/// disk, within Rapier's 5 mm prediction distance, so its contacts are built and solved from the
/// first step (the 240 warm-up steps are too short for it to land at these steps).
fn scene(nodes: usize) -> Scene {
    // A circle of diameter D at spacing σ holds about (π/4)(D/σ)² nodes.
    let spacing = DIAMETER * (std::f64::consts::PI / (4.0 * nodes as f64)).sqrt();
    let dt = 1.25e-4 * (spacing / 0.01).powi(2);
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/drape_cotton.ron");
    let sets = [
        format!("cloth.spacing_m={spacing}"),
        format!("cloth.perturbation_m={}", spacing / 20.0),
        format!("cloth.centre_m=[0.0,{},0.0]", 0.55 * spacing),
        format!("integration.dt_s={dt}"),
    ];
    Scene::load(path, &sets).expect("drape scene loads")
}

/// Rapier's own cloth: an n × n square of the same node count, mass and spacing, on the same
/// colliders with the same integration settings.
fn builtin_cloth(scene: &Scene, nodes: usize) -> PhysicsWorld {
    let spec = &scene.spec;
    let i = &spec.integration;
    let mut world = PhysicsWorld::default();
    configure_world(
        &mut world,
        spec.world.gravity_m_per_s2,
        i.dt_s,
        (i.solver_iterations, i.internal_pgs_iterations),
        spec.world.contact.stiffness(),
    );
    for (col, (shape, _)) in spec.world.colliders.iter().zip(world_shapes(scene)) {
        add_world_collider(&mut world, shape, col.centre_m, col.friction, 0.0, None);
    }
    let n = (nodes as f64).sqrt().round() as usize;
    let sigma = spec.cloth.spacing_m as f32;
    let half = 0.5 * sigma * (n - 1) as f32;
    let mass = (scene.fabric.areal_density * spec.cloth.spacing_m.powi(2)) as f32;
    let builder = SoftBodyBuilder::cloth(
        Vec3::new(-half, spec.cloth.centre_m[1] as f32, -half),
        Vec3::new(sigma, 0.0, 0.0),
        Vec3::new(0.0, 0.0, sigma),
        n,
        n,
    )
    .particle_mass(mass)
    .particle_radius(0.5 * sigma)
    .can_sleep(false);
    world.insert_soft_body(builder);
    world
}

/// The implicit drape at about `nodes` nodes: the scene above with the KES tensile law,
/// backward Euler at 1/240 s and cell-area masses.
fn implicit_scene(nodes: usize) -> Scene {
    let spacing = DIAMETER * (std::f64::consts::PI / (4.0 * nodes as f64)).sqrt();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/scenes/drape_cotton.ron");
    let sets = [
        format!("cloth.spacing_m={spacing}"),
        format!("cloth.perturbation_m={}", spacing / 20.0),
        format!("cloth.centre_m=[0.0,{},0.0]", 0.55 * spacing),
        "integration.dt_s=0.004166666666666667".to_string(),
        "integration.integrator=Implicit".to_string(),
        "effects.stretch=Kes".to_string(),
        "cloth.node_mass=CellArea".to_string(),
    ];
    Scene::load(path, &sets).expect("implicit drape scene loads")
}

/// Steps run before timing the implicit path: 0.1 s at 1/240 s, the sample in contact with the
/// disk and its skirt falling.
const IMPLICIT_SETTLE_STEPS: usize = 24;

/// Steps timed for the implicit path's split and fitted exponent: the next 0.1 s, the same
/// span of the drape at every size.
const IMPLICIT_TIMED_STEPS: usize = 24;

/// Whether `path` (`explicit` or `implicit`) is to run: `KES_BENCH_PATH` names one, or is unset
/// for both.
fn runs(path: &str) -> bool {
    std::env::var("KES_BENCH_PATH").map_or(true, |p| p == path)
}

fn max_nodes() -> usize {
    std::env::var("KES_BENCH_MAX_NODES")
        .ok()
        .and_then(|v| v.parse().ok())
        .unwrap_or(70_000)
}

fn bench_implicit(c: &mut Criterion) {
    if !runs("implicit") {
        return;
    }
    let mut group = c.benchmark_group("drape_step_implicit");
    group.sample_size(10);
    let mut points = Vec::new();
    for nodes in [1_000usize, 2_000, 4_000, 8_000, 16_000, 32_000, 64_000]
        .into_iter()
        .filter(|n| *n <= max_nodes())
    {
        let scene = implicit_scene(nodes);
        let (mut world, cloth) = spawn(&scene);
        let mut schedule = build_step_schedule();
        for _ in 0..IMPLICIT_SETTLE_STEPS {
            schedule.run(&mut world);
        }
        let actual = scene_node_count(&mut world);
        // The same span of the drape at every size, timed outside criterion (whose samples
        // step the world on, so that which steps they time depends on the size's speed).
        *world.resource_mut::<EffectLedger>() = EffectLedger::with_all_effects();
        let before = world
            .get::<Implicit>(cloth)
            .map(|i| i.0.stats)
            .unwrap_or_default();
        let start = Instant::now();
        for _ in 0..IMPLICIT_TIMED_STEPS {
            schedule.run(&mut world);
        }
        let wall = start.elapsed().as_secs_f64();
        let after = world
            .get::<Implicit>(cloth)
            .map(|i| i.0.stats)
            .unwrap_or_default();
        let ledger = world.resource::<EffectLedger>().clone();
        print_split(actual, &ledger, wall, "");
        let steps = (after.solves - before.solves).max(1) as f64;
        let per = |a: f64, b: f64| (a - b) / steps * 1e3;
        let solve = ledger.get("implicit_solve").1 / steps * 1e3;
        let (assembly, preconditioner, cg) = (
            per(after.assembly_s, before.assembly_s),
            per(after.preconditioner_s, before.preconditioner_s),
            per(after.cg_s, before.cg_s),
        );
        eprintln!(
            "drape_step_implicit/kes/{actual}, steps {IMPLICIT_SETTLE_STEPS}–{}: solve {solve:.3} ms \
             a step = assembly {assembly:.3} + preconditioner {preconditioner:.3} + CG {cg:.3} \
             ({:.1} products) + rest {:.3} ms; step {:.3} ms",
            IMPLICIT_SETTLE_STEPS + IMPLICIT_TIMED_STEPS,
            (after.iterations - before.iterations) as f64 / steps,
            solve - assembly - preconditioner - cg,
            wall / steps * 1e3
        );
        points.push((actual as f64, wall / steps));
        group.bench_function(BenchmarkId::new("kes", actual), |b| {
            b.iter(|| schedule.run(black_box(&mut world)))
        });
    }
    group.finish();
    if points.len() >= 2 {
        // Least squares of ln(step time) against ln(N).
        let n = points.len() as f64;
        let (sx, sy) = points
            .iter()
            .fold((0.0, 0.0), |(sx, sy), (x, y)| (sx + x.ln(), sy + y.ln()));
        let (mx, my) = (sx / n, sy / n);
        let (sxy, sxx) = points.iter().fold((0.0, 0.0), |(sxy, sxx), (x, y)| {
            (sxy + (x.ln() - mx) * (y.ln() - my), sxx + (x.ln() - mx).powi(2))
        });
        eprintln!(
            "drape_step_implicit: step time ∝ N^{:.2} from {} to {} nodes",
            sxy / sxx,
            points[0].0,
            points[points.len() - 1].0
        );
    }
}

fn bench(c: &mut Criterion) {
    if !runs("explicit") {
        return;
    }
    let max_nodes = max_nodes();
    let mut group = c.benchmark_group("drape_step");
    group.sample_size(10);
    for nodes in [1_000usize, 4_000, 16_000, 64_000]
        .into_iter()
        .filter(|n| *n <= max_nodes)
    {
        let scene = scene(nodes);
        let (mut world, _) = spawn(&scene);
        let mut schedule = build_step_schedule();
        for _ in 0..SETTLE_STEPS {
            schedule.run(&mut world);
        }
        let actual = scene_node_count(&mut world);
        *world.resource_mut::<EffectLedger>() = EffectLedger::with_all_effects();
        let start = Instant::now();
        group.bench_function(BenchmarkId::new("kes", actual), |b| {
            b.iter(|| schedule.run(black_box(&mut world)))
        });
        print_split(
            actual,
            &world.resource::<EffectLedger>().clone(),
            start.elapsed().as_secs_f64(),
            " (incl. criterion overhead)",
        );

        let mut builtin = builtin_cloth(&scene, actual);
        for _ in 0..SETTLE_STEPS {
            builtin.step();
        }
        group.bench_function(BenchmarkId::new("rapier_builtin_cloth", actual), |b| {
            b.iter(|| black_box(&mut builtin).step())
        });
    }
    group.finish();
}

fn scene_node_count(world: &mut World) -> usize {
    let mut query = world.query::<&kes_cloth::schedule::ClothState>();
    query.iter(world).map(|s| s.positions.len()).sum()
}

/// Our step's split, from the scene runner's ledger over every timed step; `overhead` says
/// what else `wall` (s) holds.
fn print_split(nodes: usize, ledger: &EffectLedger, wall: f64, overhead: &str) {
    let (calls, rapier) = ledger.get("rapier_step");
    if calls == 0 {
        return;
    }
    let solve = ledger.get("implicit_solve").1;
    let forces: f64 = ledger
        .entries
        .iter()
        .filter(|(name, _, _)| *name != "rapier_step" && *name != "implicit_solve")
        .map(|(_, _, s)| s)
        .sum();
    let per = |s: f64| s / calls as f64 * 1e3;
    let step = wall / calls as f64 * 1e3;
    eprintln!(
        "drape_step/kes/{nodes}: {calls} steps, {step:.3} ms per step{overhead}: \
         our forces {:.3} ms ({:.1} %), implicit solve {:.3} ms, Rapier {:.3} ms ({:.1} %), \
         measurement and schedule {:.3} ms; per node-step {:.0} ns",
        per(forces),
        100.0 * forces / wall,
        per(solve),
        per(rapier),
        100.0 * rapier / wall,
        step - per(forces) - per(solve) - per(rapier),
        step * 1e6 / nodes as f64
    );
}

criterion_group!(benches, bench, bench_implicit);
criterion_main!(benches);
