//! Helpers shared by the integration tests: shipped fabrics, grids and a tiny seeded RNG.
#![allow(dead_code)]

use std::path::PathBuf;

use glam::DVec3;
use kes_cloth::forces::ClothTopology;
use kes_cloth::material::Fabric;

/// Path of a file in the crate.
pub fn crate_path(relative: &str) -> PathBuf {
    PathBuf::from(env!("CARGO_MANIFEST_DIR")).join(relative)
}

/// An empty folder of its own under the system's temporary folder, for a test named `tag`
/// (removed first if an earlier run left it).
pub fn fresh_dir(tag: &str) -> PathBuf {
    let dir = std::env::temp_dir().join(format!("kes-cloth-{tag}-{}", std::process::id()));
    std::fs::remove_dir_all(&dir).ok();
    std::fs::create_dir_all(&dir).expect("a temporary folder");
    dir
}

/// A shipped fabric by file stem, e.g. `"thick_cotton"`.
pub fn shipped_fabric(stem: &str) -> Fabric {
    Fabric::load(crate_path(&format!("assets/fabrics/{stem}.ron"))).expect("shipped fabric loads")
}

/// Every shipped fabric file.
pub fn shipped_fabric_paths() -> Vec<PathBuf> {
    let mut paths: Vec<PathBuf> = std::fs::read_dir(crate_path("assets/fabrics"))
        .expect("assets/fabrics exists")
        .map(|e| e.expect("readable entry").path())
        .filter(|p| p.extension().is_some_and(|e| e == "ron"))
        .collect();
    paths.sort();
    paths
}

/// xorshift64*: deterministic randomness without a dependency.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Self {
        Self(seed.wrapping_mul(0x9E37_79B9_7F4A_7C15) | 1)
    }
    /// Uniform in [0, 1).
    pub fn next_f64(&mut self) -> f64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        (self.0.wrapping_mul(0x2545_F491_4F6C_DD1D) >> 11) as f64 / (1u64 << 53) as f64
    }
    /// Uniform in [-1, 1).
    pub fn signed(&mut self) -> f64 {
        2.0 * self.next_f64() - 1.0
    }
    pub fn vec(&mut self, scale: f64) -> DVec3 {
        DVec3::new(self.signed(), self.signed(), self.signed()) * scale
    }
}

/// The `// expect: ...` lines of a bad input file: fragments its rejection message must hold.
pub fn expect_lines(path: &std::path::Path) -> Vec<String> {
    let text = std::fs::read_to_string(path).expect("bad input file is readable");
    text.lines()
        .filter_map(|l| l.strip_prefix("// expect: "))
        .map(String::from)
        .collect()
}

/// The message of a load that must fail without panicking.
pub fn rejection_message<T, E: std::fmt::Display>(
    path: &std::path::Path,
    load: impl FnOnce() -> Result<T, E> + std::panic::UnwindSafe,
) -> String {
    match std::panic::catch_unwind(load) {
        Ok(Err(e)) => e.to_string(),
        Ok(Ok(_)) => panic!("{} was accepted", path.display()),
        Err(_) => panic!("{} made the loader panic", path.display()),
    }
}

/// `--set` overrides that turn the shipped drapemeter scene of `fabric` (`"wool"` or
/// `"cotton"`) into the seed's explicit model, as tests of the explicit path need it: stretch
/// held by Rapier's rope joints with the link compression spring, every node a whole cell, and
/// the coarse lattice and step the explicit scenes use (thin wool 7.5 mm at 0.2 ms, thick cotton
/// 1 cm at 0.125 ms, both within the stability guard). Later overrides win.
pub fn explicit_drape(fabric: &str) -> Vec<String> {
    let (spacing, dt) = match fabric {
        "wool" => ("0.0075", "0.0002"),
        "cotton" => ("0.01", "0.000125"),
        other => panic!("no explicit drape for {other}"),
    };
    [
        "integration.integrator=Explicit".to_string(),
        "effects.stretch=Constraint".to_string(),
        "cloth.node_mass=Uniform".to_string(),
        format!("cloth.spacing_m={spacing}"),
        format!("integration.dt_s={dt}"),
    ]
    .to_vec()
}

/// An `nu × nv` rectangle whose springs are not all whole: the outline's bending widths shared
/// (half a spacing along the edges) and the first column held as by a clamp (the springs on
/// the clamp's edge half a spacing long), so that tests of forces and Hessians cover every patch.
pub fn patched_rectangle(nu: usize, nv: usize, sigma: f64) -> ClothTopology {
    let mut t = ClothTopology::rectangle(nu, nv, sigma);
    t.share_outline_widths();
    let held: Vec<usize> = (0..t.particle_count)
        .filter(|&k| t.grid_coords[k].0 == 0)
        .collect();
    t.hold_rigidly(&held);
    t
}

/// Named configurations of a rectangular grid of at least 5 × 2 nodes (spacing σ): random
/// (±σ/4), bent round a cylinder (θ ≈ 130°), folded back on itself at 0.5 and 0.2 rad (< π/4),
/// and sheared by 20°, 45° and 60°.
pub fn strained_configurations(topo: &ClothTopology) -> Vec<(String, Vec<DVec3>)> {
    let sigma = topo.spacing;
    let mut rng = Rng::new(7);
    let flat = topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z);
    let mut configs = Vec::new();
    for seed in 0..3 {
        let noisy: Vec<DVec3> = flat.iter().map(|p| *p + rng.vec(0.25 * sigma)).collect();
        configs.push((format!("random {seed}"), noisy));
    }
    // Wrapped round a cylinder of radius 1.2σ about the weft (z) axis: θ ≈ 130°.
    let r = 1.2 * sigma;
    let bent = flat
        .iter()
        .map(|p| {
            let a = p.x / r;
            DVec3::new(r * a.sin(), r * (1.0 - a.cos()), p.z) + rng.vec(0.02 * sigma)
        })
        .collect();
    configs.push(("bent".into(), bent));
    // Folded back on itself at i = 3 with an opening angle of 0.5 rad and 0.2 rad (< π/4).
    for fold in [0.5f64, 0.2] {
        let folded = topo
            .grid_coords
            .iter()
            .map(|&(i, j)| {
                let (i, z) = (i as f64, j as f64 * sigma);
                let p = if i <= 3.0 {
                    DVec3::new(i * sigma, 0.0, z)
                } else {
                    let s = (i - 3.0) * sigma;
                    DVec3::new(3.0 * sigma - s * fold.cos(), s * fold.sin(), z)
                };
                p + rng.vec(0.01 * sigma)
            })
            .collect();
        configs.push((format!("folded {fold} rad"), folded));
    }
    // Sheared: the weft leans towards the warp by φ.
    for phi_deg in [20.0f64, 45.0, 60.0] {
        let phi = phi_deg.to_radians();
        let weft = DVec3::new(phi.sin(), 0.0, phi.cos());
        let sheared = topo
            .rest_positions(DVec3::ZERO, DVec3::X, weft)
            .into_iter()
            .map(|p| p + rng.vec(0.02 * sigma))
            .collect();
        configs.push((format!("sheared {phi_deg}°"), sheared));
    }
    configs
}

/// A run's metrics as JSON without its wall-clock times (total and per effect): what two runs of
/// the same scene, seed and build must agree on bit for bit.
pub fn without_clock_times(m: &kes_cloth::output::Metrics) -> serde_json::Value {
    let mut v = serde_json::to_value(m).unwrap();
    let map = v.as_object_mut().unwrap();
    map.remove("wall_time_s");
    map.remove("solve_split");
    for cost in map["effects"].as_object_mut().unwrap().values_mut() {
        cost.as_object_mut().unwrap().remove("seconds");
    }
    v
}

/// A CSV table without its `column` (e.g. `wall_time_s`: what two runs of the same tasks need
/// not agree on).
pub fn csv_without_column(csv: &str, column: &str) -> String {
    let header: Vec<&str> = csv.lines().next().unwrap_or_default().split(',').collect();
    let at = header
        .iter()
        .position(|h| *h == column)
        .unwrap_or_else(|| panic!("no {column} column in {csv}"));
    csv.lines()
        .map(|l| {
            let mut cells: Vec<&str> = l.split(',').collect();
            cells.remove(at);
            cells.join(",")
        })
        .collect::<Vec<_>>()
        .join("\n")
}

/// A small study the batch tests run: the cantilever strip at 1 cm and 5 mm against a 2.5 mm
/// reference, three implicit tasks of 0.1–1 s (`kes-cloth` arguments, from the crate's folder).
pub const CANTILEVER_STUDY: [&str; 6] = [
    "study",
    "scenes/bending_length/cantilever_wool.ron",
    "--vary",
    "cloth.spacing_m=0.01,0.005",
    "--reference",
    "cloth.spacing_m=0.0025",
];

/// A bevy_ecs world holding `parts` (built into `physics`) as a host's cloth, and the crate's
/// schedule to step it (`embed::spawn_cloth`, `embed::install`); returns the world, the
/// schedule and the cloth's entity.
pub fn host_schedule(
    physics: rapier3d::prelude::PhysicsWorld,
    parts: kes_cloth::embed::ClothParts,
) -> (
    bevy_ecs::world::World,
    bevy_ecs::schedule::Schedule,
    bevy_ecs::entity::Entity,
) {
    let dt = physics.integration_parameters.dt as f64;
    let mut world = bevy_ecs::world::World::new();
    let entity = kes_cloth::embed::spawn_cloth(&mut world, parts);
    let settle = kes_cloth::scene::SettleSpec::default();
    kes_cloth::scene::spawn::insert_resources(&mut world, physics, dt, &settle);
    let mut schedule = bevy_ecs::schedule::Schedule::default();
    kes_cloth::embed::install(&mut schedule);
    (world, schedule, entity)
}

/// Whether two lists of positions are equal to the bit.
pub fn same_bits(a: &[DVec3], b: &[DVec3]) -> bool {
    let bits = |v: &DVec3| v.to_array().map(f64::to_bits);
    a.len() == b.len() && a.iter().map(bits).eq(b.iter().map(bits))
}

/// Asserts that the host's bevy_ecs `world` ended exactly where the plain loop did: no failure,
/// the cloth `entity`'s nodes equal to `cloth`'s to the bit, and each of `bodies` at the same
/// position in the schedule's physics as in `plain`.
pub fn assert_same_as_plain(
    world: &bevy_ecs::world::World,
    entity: bevy_ecs::entity::Entity,
    cloth: &kes_cloth::embed::KesCloth,
    plain: &rapier3d::prelude::PhysicsWorld,
    bodies: &[rapier3d::prelude::RigidBodyHandle],
) {
    use kes_cloth::schedule::{ClothState, Failure, Physics};
    assert_eq!(world.resource::<Failure>().0, None);
    let state = world.get::<ClothState>(entity).expect("the cloth");
    assert!(
        same_bits(&state.positions, cloth.positions()),
        "the cloth's nodes differ between the two ways in"
    );
    let stepped = &world.resource::<Physics>().0.bodies;
    for h in bodies {
        let (a, b) = (plain.bodies[*h].translation(), stepped[*h].translation());
        assert_eq!(
            a.to_array().map(f32::to_bits),
            b.to_array().map(f32::to_bits),
            "a body differs: {a:?} against {b:?}"
        );
    }
}
