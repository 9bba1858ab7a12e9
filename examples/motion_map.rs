//! Where a drape is still moving: steps a drapemeter or Cusick scene and prints, every 0.25 s of
//! simulated time, the fastest node's speed over the last step (mm/s), where it lies (its
//! distance from the disk's axis and its height against the disk's top, mm), and how many nodes
//! move faster than 0.1 mm/s on the disk's top, at its rim (within three spacings of the rim's
//! corner) and in the skirt below.
//!
//! ```sh
//! cargo run --release --example motion_map -- scenes/cusick_wool.ron 16 \
//!     --set "cloth.lattice_offset_m=(-0.0006128058, -0.0010753993)"
//! ```
//!
//! Arguments: the scene file, the simulated time to step (s), and any number of `--set
//! path=value` overrides as `kes-cloth run` takes them. The scene runs without its settle
//! criterion's stop: every step to the time given.

use kes_cloth::run::declared_disk;
use kes_cloth::scene::Scene;
use kes_cloth::scene::spawn::spawn;
use kes_cloth::schedule::{ClothState, build_step_schedule};

/// Speed above which a node counts as moving (m/s).
const MOVING: f64 = 1e-4;
/// Interval between reports (s of simulated time).
const EVERY_S: f64 = 0.25;

fn main() {
    if let Err(e) = run() {
        eprintln!("motion_map: {e}");
        std::process::exit(2);
    }
}

fn run() -> Result<(), String> {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let usage = "usage: motion_map SCENE SECONDS [--set path=value]...";
    let (path, seconds) = match args.as_slice() {
        [path, seconds, ..] => (path, seconds),
        _ => return Err(usage.to_string()),
    };
    let seconds: f64 = seconds
        .parse()
        .map_err(|_| format!("SECONDS must be a number of seconds, not {seconds:?}; {usage}"))?;
    let mut sets = Vec::new();
    let mut rest = args[2..].iter();
    while let Some(flag) = rest.next() {
        match (flag.as_str(), rest.next()) {
            ("--set", Some(value)) => sets.push(value.clone()),
            _ => return Err(usage.to_string()),
        }
    }
    let scene = Scene::load(path, &sets).map_err(|e| e.to_string())?;
    let (centre, radius) = declared_disk(&scene)
        .ok_or_else(|| format!("{path}: not a drape scene (no `measure: Drape(disk: ..)`)"))?;
    let (dt, sigma) = (scene.spec.integration.dt_s, scene.spec.cloth.spacing_m);
    let (mut world, cloth) = spawn(&scene);
    let mut schedule = build_step_schedule();
    let every = ((EVERY_S / dt).round() as usize).max(1);
    for step in 1..=(seconds / dt).round() as usize {
        schedule.run(&mut world);
        if step % every != 0 {
            continue;
        }
        let state = world.get::<ClothState>(cloth).ok_or("the cloth left the world")?;
        let axis = |p: &glam::DVec3| (glam::DVec2::new(p.x, p.z) - centre).length();
        // The disk's top: the highest node over its inner half, where the cloth lies flat.
        let top = state
            .positions
            .iter()
            .filter(|p| axis(p) < 0.5 * radius)
            .map(|p| p.y)
            .fold(f64::NEG_INFINITY, f64::max);
        let (mut fastest, mut at) = (0.0, (0.0, 0.0));
        let mut moving = [0usize; 3];
        for (p, q) in state.positions.iter().zip(&state.previous_positions) {
            let speed = (*p - *q).length() / dt;
            let r = axis(p);
            if speed > fastest {
                (fastest, at) = (speed, (r, p.y - top));
            }
            if speed > MOVING {
                let region = if r < radius - 3.0 * sigma {
                    0
                } else if r < radius + 3.0 * sigma && p.y > top - 3.0 * sigma {
                    1
                } else {
                    2
                };
                moving[region] += 1;
            }
        }
        println!(
            "t {:6.2} s  fastest {:8.3} mm/s at r {:6.1} mm, {:6.1} mm below the top  \
             moving on the top {:5}, at the rim {:5}, in the skirt {:6}",
            step as f64 * dt,
            fastest * 1e3,
            at.0 * 1e3,
            -at.1 * 1e3,
            moving[0],
            moving[1],
            moving[2]
        );
    }
    Ok(())
}
