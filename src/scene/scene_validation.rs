//! Physical and numerical range checks of a scene, each naming the field and the allowed range.

use crate::embed::{MAX_SMOOTH_AMPLITUDE_M, Roughness};

use super::scene_file::{
    ClothShape, ColliderMotion, ColliderShape, IntegrationSpec, IntegratorSpec, MeasureSpec, SCENE_VERSION,
    SceneFile, StretchModel,
};

/// A field outside its range: (field path, value, reason).
pub(crate) type Violation = (String, String, String);

fn violation(field: &str, value: impl std::fmt::Display, reason: impl Into<String>) -> Violation {
    (field.to_string(), value.to_string(), reason.into())
}

/// `low < value ≤ high` (NaN fails).
fn in_open_closed(field: &str, value: f64, low: f64, high: f64, unit: &str) -> Result<(), Violation> {
    if value > low && value <= high {
        Ok(())
    } else {
        Err(violation(
            field,
            value,
            format!("must lie in ({low}, {high}] {unit}")
                .trim_end()
                .to_string(),
        ))
    }
}

/// `low ≤ value ≤ high` (NaN fails).
fn in_closed(field: &str, value: f64, low: f64, high: f64, unit: &str) -> Result<(), Violation> {
    if value >= low && value <= high {
        Ok(())
    } else {
        Err(violation(
            field,
            value,
            format!("must lie in [{low}, {high}] {unit}")
                .trim_end()
                .to_string(),
        ))
    }
}

fn finite3(field: &str, v: [f64; 3]) -> Result<(), Violation> {
    if v.iter().all(|x| x.is_finite()) {
        Ok(())
    } else {
        Err(violation(
            field,
            format!("{v:?}"),
            "every component must be a finite number",
        ))
    }
}

fn whole(field: &str, value: usize, low: usize, high: usize) -> Result<(), Violation> {
    if (low..=high).contains(&value) {
        Ok(())
    } else {
        Err(violation(field, value, format!("must lie in [{low}, {high}]")))
    }
}

/// Largest cloth this build accepts (nodes); a guard against a spacing typo.
pub const MAX_NODES: usize = 1_000_000;

/// Checks every range of a parsed scene.
pub(crate) fn validate(s: &SceneFile) -> Result<(), Violation> {
    if s.version != SCENE_VERSION {
        return Err(violation(
            "version",
            s.version,
            format!("this build reads scene version {SCENE_VERSION}"),
        ));
    }
    let name_ok = !s.name.is_empty()
        && s.name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || "-_.".contains(c))
        && !s.name.starts_with('.');
    if !name_ok {
        return Err(violation(
            "name",
            format!("{:?}", s.name),
            "must be a non-empty file name of letters, digits, '-', '_' or '.'",
        ));
    }

    let c = &s.cloth;
    match c.shape {
        ClothShape::Circle { diameter_m } => {
            in_open_closed("cloth.shape.diameter_m", diameter_m, 0.0, 100.0, "m")?;
        }
        ClothShape::Square { side_m } => {
            in_open_closed("cloth.shape.side_m", side_m, 0.0, 100.0, "m")?;
        }
        ClothShape::Rectangle { warp_m, weft_m } => {
            in_open_closed("cloth.shape.warp_m", warp_m, 0.0, 100.0, "m")?;
            in_open_closed("cloth.shape.weft_m", weft_m, 0.0, 100.0, "m")?;
        }
    }
    let [warp, weft] = c.shape.extent_m();
    in_open_closed(
        "cloth.spacing_m",
        c.spacing_m,
        0.0,
        warp.min(weft) / 2.0,
        "m (at least three nodes across the cloth)",
    )?;
    let across = |l: f64| (l / c.spacing_m).floor() + 1.0;
    let nodes = across(warp) * across(weft);
    if nodes > MAX_NODES as f64 {
        return Err(violation(
            "cloth.spacing_m",
            c.spacing_m,
            format!("gives about {nodes:.0} nodes; at most {MAX_NODES} are allowed"),
        ));
    }
    finite3("cloth.centre_m", c.centre_m)?;
    in_closed("cloth.warp_angle_deg", c.warp_angle_deg, -360.0, 360.0, "deg")?;
    in_closed("cloth.initial_shear_deg", c.initial_shear_deg, -60.0, 60.0, "deg")?;
    match c.roughness {
        Roughness::PerNode => in_closed(
            "cloth.perturbation_m",
            c.perturbation_m,
            0.0,
            c.spacing_m / 4.0,
            "m (a quarter of the spacing, with cloth.roughness: PerNode)",
        )?,
        Roughness::Smooth => in_closed(
            "cloth.perturbation_m",
            c.perturbation_m,
            0.0,
            MAX_SMOOTH_AMPLITUDE_M,
            "m (with cloth.roughness: Smooth, whose steepest slope is then 1/2 or less)",
        )?,
    }
    for (k, &o) in c.lattice_offset_m.iter().enumerate() {
        in_closed(
            &format!("cloth.lattice_offset_m[{k}]"),
            o,
            -c.spacing_m / 2.0,
            c.spacing_m / 2.0,
            "m (within half a spacing)",
        )?;
    }
    if c.lattice_offset_m != [0.0; 2] && c.fold_gap_m.is_some() {
        return Err(violation(
            "cloth.lattice_offset_m",
            format!("{:?}", c.lattice_offset_m),
            "cannot be combined with `cloth.fold_gap_m`: the fold runs through a lattice line",
        ));
    }
    if c.lattice_offset_m != [0.0; 2] && !matches!(c.shape, ClothShape::Circle { .. }) {
        return Err(violation(
            "cloth.lattice_offset_m",
            format!("{:?}", c.lattice_offset_m),
            "applies to circular cloths only: a rectangle's lattice fills its outline",
        ));
    }
    in_closed(
        "cloth.clamp_m",
        c.clamp_m,
        0.0,
        warp / 2.0,
        "m (at most half the cloth's length along the warp)",
    )?;
    let radius = c.node_radius_m.unwrap_or(c.spacing_m / 2.0);
    if let Some(r) = c.node_radius_m {
        in_open_closed(
            "cloth.node_radius_m",
            r,
            0.0,
            c.spacing_m,
            "m (at most the spacing)",
        )?;
    }

    if let Some(gap) = c.fold_gap_m {
        in_closed(
            "cloth.fold_gap_m",
            gap,
            2.0 * radius,
            c.spacing_m / 2.0,
            "m (from two node radii, so the layers start apart, to half a spacing, so the links \
             round the fold start at most 12 % long)",
        )?;
        if !s.effects.self_collision {
            return Err(violation(
                "cloth.fold_gap_m",
                gap,
                "needs `effects.self_collision: true`: without it the folded layers pass through each other",
            ));
        }
    }

    finite3("world.gravity_m_per_s2", s.world.gravity_m_per_s2)?;
    in_open_closed("world.contact.fixed_hz", s.world.contact.fixed_hz, 0.0, 1e6, "Hz")?;
    in_open_closed(
        "world.contact.moving_hz",
        s.world.contact.moving_hz,
        0.0,
        1e6,
        "Hz",
    )?;
    if s.world.contact.link_support && s.integration.integrator == IntegratorSpec::Explicit {
        return Err(violation(
            "world.contact.link_support",
            true,
            "needs an implicit integrator (`integration.integrator: Implicit` or `Bdf2`): link support acts in the implicit solve",
        ));
    }
    for (i, col) in s.world.colliders.iter().enumerate() {
        let f = |name: &str| format!("world.colliders[{i}].{name}");
        finite3(&f("centre_m"), col.centre_m)?;
        in_closed(&f("friction"), col.friction, 0.0, 10.0, "")?;
        // Colliders are shrunk by the node radius so node centres rest on the true surface.
        let beyond_radius = |field: &str, value: f64| -> Result<(), Violation> {
            if value > radius && value <= 100.0 {
                Ok(())
            } else {
                Err(violation(
                    &f(field),
                    value,
                    format!(
                        "must exceed {radius} m (the node radius, by which the collider is shrunk) and be at most 100 m"
                    ),
                ))
            }
        };
        match col.shape {
            ColliderShape::Cylinder {
                radius_m,
                half_height_m,
            } => {
                beyond_radius("shape.radius_m", radius_m)?;
                beyond_radius("shape.half_height_m", half_height_m)?;
            }
            ColliderShape::Cuboid { half_extents_m } => {
                for h in half_extents_m {
                    beyond_radius("shape.half_extents_m", h)?;
                }
            }
            ColliderShape::Ball { radius_m } => beyond_radius("shape.radius_m", radius_m)?,
        }
        if let ColliderMotion::Dynamic {
            mass_kg,
            velocity_m_per_s,
        } = col.motion
        {
            if !matches!(col.shape, ColliderShape::Ball { .. }) {
                return Err(violation(
                    &f("motion"),
                    "Dynamic",
                    "only a `Ball` collider may move (the penetration check follows a ball's centre)",
                ));
            }
            in_open_closed(&f("motion.mass_kg"), mass_kg, 0.0, 1e4, "kg")?;
            finite3(&f("motion.velocity_m_per_s"), velocity_m_per_s)?;
        }
    }
    validate_measure(s)?;

    let i = &s.integration;
    in_open_closed("integration.dt_s", i.dt_s, 0.0, 0.1, "s")?;
    whole("integration.solver_iterations", i.solver_iterations, 1, 64)?;
    whole(
        "integration.internal_pgs_iterations",
        i.internal_pgs_iterations,
        1,
        64,
    )?;
    in_open_closed("integration.max_time_s", i.max_time_s, 0.0, 1e4, "s")?;
    in_open_closed(
        "integration.settle.max_speed_m_per_s",
        i.settle.max_speed_m_per_s,
        0.0,
        10.0,
        "m/s",
    )?;
    in_closed("integration.settle.hold_s", i.settle.hold_s, 0.0, 1e4, "s")?;
    in_closed(
        "integration.settle.min_time_s",
        i.settle.min_time_s,
        0.0,
        1e4,
        "s",
    )?;
    in_closed(
        "integration.settle.creep_check_s",
        i.settle.creep_check_s,
        0.0,
        1e4,
        "s",
    )?;
    in_closed("integration.settle.confirm_s", i.settle.confirm_s, 0.0, 1e4, "s")?;
    validate_rest_step(i)?;
    whole(
        "integration.implicit_solver.max_iterations",
        i.implicit_solver.max_iterations,
        1,
        100_000,
    )?;
    in_open_closed(
        "integration.implicit_solver.tolerance",
        i.implicit_solver.tolerance,
        0.0,
        1.0,
        "(relative residual)",
    )?;
    in_closed(
        "integration.implicit_solver.velocity_tolerance_m_per_s",
        i.implicit_solver.velocity_tolerance_m_per_s,
        0.0,
        1.0,
        "m/s",
    )?;
    if let crate::implicit::Preconditioner::TwoLevel { coarsening, .. } = i.implicit_solver.preconditioner {
        whole(
            "integration.implicit_solver.preconditioner.coarsening",
            coarsening,
            2,
            16,
        )?;
    }
    if let Some(modulus) = s.effects.compression_modulus_n_per_m {
        if s.effects.stretch != StretchModel::Constraint {
            return Err(violation(
                "effects.compression_modulus_n_per_m",
                modulus,
                "applies only with `stretch: Constraint` (the KES and seed laws resist compression themselves)",
            ));
        }
        in_open_closed("effects.compression_modulus_n_per_m", modulus, 0.0, 1e7, "N/m")?;
    }
    if let Some(d) = s.effects.damping {
        // Explicit at the step: an interior node has four links, stable while rate·dt < 1/4.
        // Implicitly, any rate is stable.
        let limit = match i.integrator {
            IntegratorSpec::Explicit => 0.25 / s.integration.dt_s,
            IntegratorSpec::Implicit | IntegratorSpec::Bdf2 => 1e6,
        };
        in_closed(
            "effects.damping.rate_per_s",
            d.rate_per_s,
            0.0,
            limit,
            match i.integrator {
                IntegratorSpec::Explicit => "1/s (explicit damping is stable below 1/(4·dt))",
                IntegratorSpec::Implicit | IntegratorSpec::Bdf2 => "1/s",
            },
        )?;
    }
    if let Some(a) = s.effects.air_drag {
        in_closed(
            "effects.air_drag.coefficient_n_s_per_m3",
            a.coefficient_n_s_per_m3,
            0.0,
            1e6,
            "N·s/m³",
        )?;
    }
    if s.effects.hysteresis && !s.effects.bending && !s.effects.trellising {
        return Err(violation(
            "effects.hysteresis",
            true,
            "needs `bending: true` or `trellising: true`: hysteresis is the friction of those effects",
        ));
    }

    whole("output.image_size_px", s.output.image_size_px as usize, 64, 8192)?;
    Ok(())
}

/// The measured collider exists, has the shape its measurement needs and stays put; a
/// tablecloth is rectangular.
fn validate_measure(s: &SceneFile) -> Result<(), Violation> {
    let (field, name, shape_ok, shape): (_, _, fn(&ColliderShape) -> bool, _) = match &s.measure {
        MeasureSpec::None => return Ok(()),
        MeasureSpec::Cantilever => {
            return if s.cloth.clamp_m > 0.0 && !matches!(s.cloth.shape, ClothShape::Circle { .. }) {
                Ok(())
            } else {
                Err(violation(
                    "measure",
                    "Cantilever",
                    "needs a `Rectangle` or `Square` strip with its root held (`cloth.clamp_m` > 0)",
                ))
            };
        }
        MeasureSpec::Drape { disk } => (
            "measure.disk",
            disk,
            |c| matches!(c, ColliderShape::Cylinder { .. }),
            "Cylinder",
        ),
        MeasureSpec::Tablecloth { table } => {
            if matches!(s.cloth.shape, ClothShape::Circle { .. }) {
                return Err(violation(
                    "measure",
                    "Tablecloth",
                    "needs a `Square` or `Rectangle` cloth: its corners and mid-sides are measured",
                ));
            }
            (
                "measure.table",
                table,
                |c| matches!(c, ColliderShape::Cuboid { .. }),
                "Cuboid",
            )
        }
    };
    let names: Vec<&str> = s.world.colliders.iter().map(|c| c.name.as_str()).collect();
    let Some(collider) = s.world.colliders.iter().find(|c| &c.name == name) else {
        return Err(violation(
            field,
            format!("{name:?}"),
            format!("must name one of the scene's colliders: {names:?}"),
        ));
    };
    if !shape_ok(&collider.shape) || collider.motion != ColliderMotion::Fixed {
        return Err(violation(
            field,
            format!("{name:?}"),
            format!("must name a fixed `{shape}` collider"),
        ));
    }
    Ok(())
}

/// `integration.rest_dt_s`: 0 (none) up to a fifth of the settle window, whose resolution a
/// longer step would coarsen.
fn validate_rest_step(i: &IntegrationSpec) -> Result<(), Violation> {
    let longest = i.settle.hold_s / 5.0;
    if i.rest_dt_s >= 0.0 && i.rest_dt_s <= longest {
        return Ok(());
    }
    Err(violation(
        "integration.rest_dt_s",
        i.rest_dt_s,
        format!(
            "must lie in [0, {longest}] s: at most a fifth of `settle.hold_s`, the settle \
             window's resolution (0: no step at rest)"
        ),
    ))
}
