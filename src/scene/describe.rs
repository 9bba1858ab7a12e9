//! `kes-cloth check`: the resolved scene, in SI, as a person reads it.

use std::fmt::Write as _;

use super::{ColliderMotion, Scene, StretchModel, spawn::cloth_grid};
use crate::forces::{BUCKLING_MARGIN, LinkCompression};
use crate::material::Thread;

/// A multi-line description of the validated scene and its fabric in SI units.
pub fn describe(scene: &Scene) -> String {
    let s = &scene.spec;
    let f = &scene.fabric;
    let (topology, _) = cloth_grid(scene);
    let mut out = String::new();
    let _ = writeln!(out, "scene `{}` ({})", s.name, scene.path.display());
    let _ = writeln!(out, "fabric: {}", f.name);
    let _ = writeln!(out, "  source: {}", f.source);
    let _ = writeln!(
        out,
        "  areal density {:.4} kg/m², thickness {:.2e} m",
        f.areal_density, f.thickness
    );
    for t in [Thread::Warp, Thread::Weft] {
        let b = f.bending(t);
        let _ = writeln!(
            out,
            "  {t:?}: B {:.4e} N·m, 2HB {:.4e} N, bending length {:.2} mm, tensile EMT {:.2} %, LT {:.2}",
            b.rigidity,
            b.hysteresis_width,
            f.bending_length(t) * 1e3,
            f.tensile(t).law.strain_at_max_load * 100.0,
            f.tensile(t).linearity
        );
    }
    let _ = writeln!(
        out,
        "  shear: G {:.4} N/m per rad, 2HG {:.4} N/m, 2HG5 {:.4} N/m",
        f.shear.rigidity, f.shear.hysteresis_width_small, f.shear.hysteresis_width_large
    );
    let _ = writeln!(
        out,
        "cloth: {:?}, spacing {} m, {} nodes, {} links, node mass {:.3e} kg, node radius {} m, warp at {}°",
        s.cloth.shape,
        s.cloth.spacing_m,
        topology.particle_count,
        topology.links.len(),
        f.areal_density * s.cloth.spacing_m * s.cloth.spacing_m,
        scene.node_radius(),
        s.cloth.warp_angle_deg
    );
    let _ = writeln!(
        out,
        "world: gravity {:?} m/s², contact stiffness {} Hz against fixed bodies, {} Hz between moving ones",
        s.world.gravity_m_per_s2, s.world.contact.fixed_hz, s.world.contact.moving_hz
    );
    for c in &s.world.colliders {
        let motion = match c.motion {
            ColliderMotion::Fixed => String::from("fixed"),
            ColliderMotion::Dynamic {
                mass_kg,
                velocity_m_per_s,
            } => format!("dynamic, {mass_kg} kg thrown at {velocity_m_per_s:?} m/s"),
        };
        let _ = writeln!(
            out,
            "  {}: {:?} at {:?} m, friction {}, {motion}",
            c.name, c.shape, c.centre_m, c.friction
        );
    }
    let _ = writeln!(out, "effects: {:?}", s.effects);
    let fx = &s.effects;
    if fx.stretch == StretchModel::Constraint {
        let modulus = match fx.compression_modulus_n_per_m {
            Some(e) => format!("{e} N/m (scene)"),
            None => format!(
                "{:.4e} N/m (default: {}·π²·B/σ²)",
                LinkCompression::default_modulus(f, s.cloth.spacing_m),
                BUCKLING_MARGIN
            ),
        };
        let _ = writeln!(out, "  link compression modulus {modulus}");
    }
    let limits = super::step_limits(s, f);
    let listed: Vec<String> = limits
        .iter()
        .map(|l| format!("{} {:.3e} s", l.effect, l.max_step))
        .collect();
    let _ = writeln!(out, "  largest explicit step per effect: {}", listed.join(", "));
    let i = &s.integration;
    let _ = writeln!(
        out,
        "integration: dt {} s, {} solver iterations × {} PGS, up to {} s; settled when no node travels faster than {} m/s on average over {} s",
        i.dt_s,
        i.solver_iterations,
        i.internal_pgs_iterations,
        i.max_time_s,
        i.settle.max_speed_m_per_s,
        i.settle.hold_s
    );
    out
}
