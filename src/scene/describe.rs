//! `kes-cloth check`: the resolved scene, in SI, as a person reads it.

use std::fmt::Write as _;

use super::{
    ClothShape, ColliderMotion, ColliderShape, EffectsSpec, IntegratorSpec, Scene, StretchModel,
    spawn::cloth_grid,
};
use crate::forces::{BUCKLING_MARGIN, LinkCompression};
use crate::implicit::{FrictionRelease, Preconditioner};
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
            "  {}: B {:.4e} N·m, 2HB {:.4e} N, bending length {:.2} mm, tensile EMT {:.2} %, LT {:.2}",
            if t == Thread::Warp { "warp" } else { "weft" },
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
        "cloth: {}, spacing {} m, {} nodes, {} links, node mass {:.3e} kg, node radius {} m, warp at {}°",
        shape_text(&s.cloth.shape),
        s.cloth.spacing_m,
        topology.particle_count,
        topology.links.len(),
        f.areal_density * s.cloth.spacing_m * s.cloth.spacing_m,
        scene.node_radius(),
        s.cloth.warp_angle_deg
    );
    let _ = writeln!(
        out,
        "world: gravity {} m/s², contact stiffness {} Hz against fixed bodies, {} Hz between moving ones{}",
        vector_text(s.world.gravity_m_per_s2),
        s.world.contact.fixed_hz,
        s.world.contact.moving_hz,
        if s.world.contact.link_support {
            "; links rest on the fixed bodies' edges (link support)"
        } else {
            ""
        }
    );
    for c in &s.world.colliders {
        let motion = match c.motion {
            ColliderMotion::Fixed => String::from("fixed"),
            ColliderMotion::Dynamic {
                mass_kg,
                velocity_m_per_s,
            } => format!(
                "dynamic, {mass_kg} kg thrown at {} m/s",
                vector_text(velocity_m_per_s)
            ),
        };
        let _ = writeln!(
            out,
            "  {}: {} at {} m, friction {}, {motion}",
            c.name,
            collider_text(&c.shape),
            vector_text(c.centre_m),
            c.friction
        );
    }
    let _ = writeln!(out, "effects: {}", effects_text(&s.effects));
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
    if let Some(rest) = s.rest_step_s() {
        let _ = writeln!(
            out,
            "  at rest (a quiet window confirmed, the creep watch) steps of {rest} s"
        );
    }
    let _ = writeln!(out, "  {}", integrator_text(scene, topology.particle_count));
    out
}

/// How our forces are integrated, and for an implicit solve its settings as this cloth gets them.
fn integrator_text(scene: &Scene, nodes: usize) -> String {
    let i = &scene.spec.integration;
    let scheme = match i.integrator {
        IntegratorSpec::Explicit => {
            return "integrator: explicit (our forces as one velocity kick a step)".into();
        }
        IntegratorSpec::Implicit => "backward Euler",
        IntegratorSpec::Bdf2 => "BDF2",
    };
    let solver = &i.implicit_solver;
    let rope = scene.spec.effects.stretch == StretchModel::Constraint;
    let friction = match solver.friction.unwrap_or(!rope) {
        true => format!(
            "on, a hold that gives way slides {}",
            match solver.friction_release {
                FrictionRelease::SameStep => "within its step (SameStep)",
                FrictionRelease::NextStep => "from the next step (NextStep)",
            }
        ),
        false => "left to Rapier's contact".into(),
    };
    format!(
        "integrator: implicit, {scheme}; conjugate gradients preconditioned by {}{}, stopping at a relative residual of {} or a velocity error of {} m/s, at most {} products a step; friction in the solve {friction}",
        solver.preconditioner.for_nodes(nodes).describe(),
        match solver.preconditioner {
            Preconditioner::Auto => format!(" (what Auto takes at {nodes} nodes)"),
            _ => String::new(),
        },
        solver.tolerance,
        solver.velocity_tolerance_m_per_s,
        solver.max_iterations,
    )
}

/// `(x, y, z)` with plain numbers.
fn vector_text(v: [f64; 3]) -> String {
    format!("({}, {}, {})", v[0], v[1], v[2])
}

/// The cloth's outline in words.
fn shape_text(shape: &ClothShape) -> String {
    match shape {
        ClothShape::Circle { diameter_m } => format!("circle {diameter_m} m across"),
        ClothShape::Square { side_m } => format!("square, side {side_m} m"),
        ClothShape::Rectangle { warp_m, weft_m } => {
            format!("rectangle {warp_m} m along the warp × {weft_m} m along the weft")
        }
    }
}

/// A collider's shape in words.
fn collider_text(shape: &ColliderShape) -> String {
    match shape {
        ColliderShape::Cylinder {
            radius_m,
            half_height_m,
        } => format!("cylinder, radius {radius_m} m, height {} m,", 2.0 * half_height_m),
        ColliderShape::Cuboid { half_extents_m: h } => {
            format!("box {} × {} × {} m", 2.0 * h[0], 2.0 * h[1], 2.0 * h[2])
        }
        ColliderShape::Ball { radius_m } => format!("ball, radius {radius_m} m,"),
    }
}

/// The effects that run, then those that do not.
fn effects_text(fx: &EffectsSpec) -> String {
    let stretch = match fx.stretch {
        StretchModel::Constraint => "stretch (Rapier rope joints, tension only, plus link compression)",
        StretchModel::Seed => "stretch (the seed's linear springs)",
        StretchModel::Kes => "stretch (the KES tensile law)",
    };
    let damping = fx
        .damping
        .as_ref()
        .map(|d| format!("damping {} /s", d.rate_per_s));
    let drag = fx.air_drag.as_ref().map(|_| "air drag".to_string());
    let flags = [
        (fx.gravity, "gravity".to_string()),
        (true, stretch.to_string()),
        (fx.bending, "bending".to_string()),
        (fx.trellising, "trellising".to_string()),
        (fx.contact, "contact".to_string()),
        (fx.friction, "friction".to_string()),
        (fx.self_collision, "self-collision".to_string()),
        (damping.is_some(), damping.unwrap_or_else(|| "damping".into())),
        (drag.is_some(), drag.unwrap_or_else(|| "air drag".into())),
        (fx.hysteresis, "hysteresis".to_string()),
    ];
    let on: Vec<&str> = flags.iter().filter(|f| f.0).map(|f| f.1.as_str()).collect();
    let off: Vec<&str> = flags.iter().filter(|f| !f.0).map(|f| f.1.as_str()).collect();
    format!(
        "{}; off: {}",
        on.join(", "),
        if off.is_empty() {
            "none".to_string()
        } else {
            off.join(", ")
        }
    )
}
