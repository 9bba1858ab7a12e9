//! What a run leaves behind: `metrics.json`, `final.obj`, `top.png`, and the printed summary.

use std::path::Path;

use super::RunOutcome;
use super::declared_measures::declared_disk;
use crate::output::{OutputError, TopViewOutline, write_obj, write_top_view};
use crate::scene::{ColliderShape, Scene};

/// Writes `metrics.json` and, for a run that did not fail, `final.obj` and `top.png`.
pub fn write_outputs(scene: &Scene, outcome: &RunOutcome, dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::new(dir, e))?;
    outcome.metrics.write(dir)?;
    if outcome.metrics.failure.is_some() {
        return Ok(());
    }
    let out = &scene.spec.output;
    if out.mesh_obj {
        write_obj(dir, &scene.spec.name, &outcome.topology, &outcome.positions)?;
    }
    if out.top_png {
        // A thrown body that ended beyond the cloth (bounced off, fell away) is left out, so the
        // picture stays framed on the cloth.
        let cloth_extent = outcome
            .positions
            .iter()
            .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.z.abs()));
        let outlines: Vec<TopViewOutline> = scene
            .spec
            .world
            .colliders
            .iter()
            .zip(&outcome.collider_centres)
            .filter(|(c, at)| {
                c.motion == crate::scene::ColliderMotion::Fixed || at.x.abs().max(at.z.abs()) <= cloth_extent
            })
            .filter_map(|(c, at)| {
                let centre = [at.x, at.z];
                match c.shape {
                    ColliderShape::Cylinder { radius_m, .. } => Some(TopViewOutline::Circle {
                        centre,
                        radius: radius_m,
                    }),
                    ColliderShape::Cuboid {
                        half_extents_m: [x, _, z],
                    } if x < 1.0 && z < 1.0 => Some(TopViewOutline::Rectangle { centre, half: [x, z] }),
                    // A floor-sized box would only frame the picture.
                    ColliderShape::Cuboid { .. } => None,
                    ColliderShape::Ball { radius_m } => Some(TopViewOutline::Circle {
                        centre,
                        radius: radius_m,
                    }),
                }
            })
            .collect();
        let markers: Vec<[f64; 2]> = match (&outcome.drape, declared_disk(scene)) {
            (Some(d), Some((centre, _))) => d
                .node_angles
                .iter()
                .zip(&d.node_radii)
                .map(|(a, r)| [centre.x + r * a.cos(), centre.y + r * a.sin()])
                .collect(),
            _ => Vec::new(),
        };
        write_top_view(
            dir,
            out.image_size_px,
            &outcome.topology,
            &outcome.positions,
            &outlines,
            &markers,
        )?;
    }
    Ok(())
}

/// The short summary printed after a run.
pub fn summary(outcome: &RunOutcome) -> String {
    let m = &outcome.metrics;
    let mut s = format!(
        "{} ({}): {} nodes at {:.1} mm, dt {:.3} ms, {}\n",
        m.scene,
        m.fabric,
        m.particles,
        m.spacing_m * 1e3,
        m.dt_s * 1e3,
        match m.cg_iterations_mean {
            Some(it) => format!(
                "{} ({it:.0} CG products per step)",
                if m.integrator == "Bdf2" {
                    "implicit BDF2"
                } else {
                    "implicit"
                }
            ),
            None => "explicit".to_string(),
        }
    );
    match (m.settled, m.settle_time_s) {
        (true, Some(t)) => s += &format!("  settled at t = {t:.2} s"),
        _ => s += "  NOT settled: the numbers below are provisional",
    }
    s += &format!(
        " ({} steps, {:.2} s simulated, {:.1} s wall)\n",
        m.steps, m.sim_time_s, m.wall_time_s
    );
    s += &format!(
        "  lowest node {:.1} mm, max link strain {:.2} % (peak {:.2} %)\n  fastest node: moved {:.2} mm/s over the last step (Rapier's velocity {:.2} mm/s), {} over the settle window\n",
        m.min_height_m * 1e3,
        m.max_strain * 100.0,
        m.peak_strain * 100.0,
        m.max_step_speed_m_per_s * 1e3,
        m.max_speed_m_per_s * 1e3,
        m.window_speed_m_per_s
            .map_or("-".to_string(), |v| format!("{:.2} mm/s", v * 1e3))
    );
    s += &format!(
        "  deepest node inside a collider: {:.2} mm now, {:.2} mm at the worst step\n",
        m.max_penetration_m * 1e3,
        m.peak_penetration_m * 1e3
    );
    if let (Some(w), Some(node), Some(centroid)) = (m.creep_window_s, m.creep_max_node_m, m.creep_centroid_m)
    {
        s += &format!(
            "  creep over {w:.2} s after settling: nodes moved at most {:.3} mm, the centroid {:.3} mm\n",
            node * 1e3,
            centroid * 1e3
        );
    }
    if let (Some(dc), Some(n)) = (m.drape_coefficient, m.nodes) {
        let tag = if m.settled {
            ""
        } else {
            " (provisional: not settled)"
        };
        s += &format!("  drape coefficient {dc:.3}, {n} nodes{tag}\n");
    }
    if let (Some(chord), Some(exact)) = (m.cantilever_chord_deg, m.cantilever_exact_deg) {
        s += &format!(
            "  cantilever chord {chord:.2}° below the horizontal; the heavy elastica's {exact:.2}° ({:+.2}°)\n",
            chord - exact
        );
    }
    if let (Some(c), Some(side), Some(f)) = (m.hang_corners_m, m.hang_mid_sides_m, m.skirt_folds) {
        s += &format!(
            "  hang: corners {:.1} mm, mid-sides {:.1} mm; {f} skirt folds\n",
            c * 1e3,
            side * 1e3
        );
    }
    let ours: f64 = m
        .effects
        .iter()
        .filter(|(k, _)| *k != "rapier_step")
        .map(|(_, c)| c.seconds)
        .sum();
    let rapier = m.effects.get("rapier_step").map_or(0.0, |c| c.seconds);
    s += &format!("  time: our forces {ours:.2} s");
    if let Some(solve) = m.effects.get("implicit_solve").filter(|c| c.calls > 0) {
        s += &format!(" (of which the implicit solve {:.2} s)", solve.seconds);
    }
    s += &format!(", Rapier's step {rapier:.2} s");
    s
}
