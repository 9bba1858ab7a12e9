//! What a run leaves behind: `metrics.json`, `final.obj`, `top.png`, `side.png`, `report.html`,
//! and the printed summary.

use std::path::Path;

use super::declared_measures::declared_disk;
use super::{ErrorEstimate, Estimated, RunOutcome};
use crate::material::Fabric;
use crate::output::{
    OutputError, Report, ReportTable, TopViewOutline, fabric_sheet, write_glb, write_obj, write_repeat_plot,
    write_side_view, write_top_view,
};
use crate::scene::{ColliderShape, FabricSource, Scene};

/// Writes `metrics.json` and, for a run that did not fail, `final.obj`, `top.png`, `side.png`
/// and `report.html` (as the scene's `output` asks).
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
    if out.report {
        write_report(scene, outcome, dir)?;
    }
    Ok(())
}

/// Writes `side.png`, `final.glb` and `report.html` (with its `viewer/`) for a run that did not
/// fail.
fn write_report(scene: &Scene, outcome: &RunOutcome, dir: &Path) -> Result<(), OutputError> {
    let silhouettes: Vec<[f64; 4]> = scene
        .spec
        .world
        .colliders
        .iter()
        .zip(&outcome.collider_centres)
        .filter(|(c, _)| c.motion == crate::scene::ColliderMotion::Fixed)
        .filter_map(|(c, at)| match c.shape {
            ColliderShape::Cylinder {
                radius_m,
                half_height_m,
            } => Some([
                at.x - radius_m,
                at.y - half_height_m,
                at.x + radius_m,
                at.y + half_height_m,
            ]),
            ColliderShape::Cuboid {
                half_extents_m: [x, y, _],
            } => Some([at.x - x, at.y - y, at.x + x, at.y + y]),
            ColliderShape::Ball { .. } => None,
        })
        .collect();
    let out = &scene.spec.output;
    write_side_view(
        dir,
        out.image_size_px,
        &outcome.topology,
        &outcome.positions,
        &silhouettes,
    )?;
    let m = &outcome.metrics;
    let mut figures = vec![
        ("fabric".to_string(), m.fabric.clone()),
        (
            "settled".to_string(),
            match (m.settled, m.settle_time_s) {
                (true, Some(t)) => format!("yes, at {t:.2} s simulated"),
                _ => "no: the figures are provisional".to_string(),
            },
        ),
    ];
    if let (Some(dc), Some(nodes)) = (m.drape_coefficient, m.nodes) {
        let error = plus_minus(m.numerical_error.as_ref(), |e| e.drape_coefficient, 1.0, 3);
        figures.push((
            "drape coefficient DC".to_string(),
            format!(
                "{dc:.3}{error} (one run; ± from a run at a coarser spacing, see the summary; \
                 the spread over seeds and lattice placements is what `--repeat N --placements` \
                 measures, the extrapolated value what `kes-cloth converge` gives)"
            ),
        ));
        figures.push(("nodes (folds)".to_string(), nodes.to_string()));
    }
    figures.push((
        "lattice".to_string(),
        format!("{} nodes, {:.1} mm apart", m.particles, m.spacing_m * 1e3),
    ));
    figures.push(("step".to_string(), format!("{:.4} ms", m.dt_s * 1e3)));
    figures.push(("wall time".to_string(), format!("{:.1} s", m.wall_time_s)));
    let mut pictures = Vec::new();
    if out.top_png {
        pictures.push((
            "top.png".to_string(),
            "seen from above; red dots: the counted nodes".to_string(),
        ));
    }
    pictures.push((
        "side.png".to_string(),
        "seen from the side (along −z), nearer parts lighter".to_string(),
    ));
    let sheet = scene_fabric_sheet(scene);
    let glb = write_glb(dir, &scene.spec.name, &outcome.topology, &outcome.positions)?;
    Report {
        title: format!("{}: {}", scene.spec.name, m.fabric),
        figures,
        summary: summary(outcome),
        pictures,
        fabric_sheet: sheet,
        glb: Some(("final.glb".into(), glb)),
        ..Report::default()
    }
    .write(dir)
}

/// Fastest a node of a cloth at rest moves over a step (m/s), from its positions: settled
/// shipped drapes measure 0.01–0.3 mm/s, and `tests/shipped_scenes.rs` holds them below this.
/// A quiet window measures each node's travel over the window, so it can close on a node that
/// flickers in place at several mm/s; the summary warns when it did.
pub const AT_REST_STEP_SPEED_M_PER_S: f64 = 1e-3;

/// The short summary printed after a run.
pub fn summary(outcome: &RunOutcome) -> String {
    let m = &outcome.metrics;
    let mut s = format!(
        "{} ({}): {} nodes at {} mm, dt {:.3} ms, {}\n",
        m.scene,
        m.fabric,
        m.particles,
        crate::output::number(m.spacing_m * 1e3),
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
    if m.settle_restarts > 0 {
        s += &format!(
            " after {} quiet window(s) the confirmation watch undid",
            m.settle_restarts
        );
    }
    let rest = match m.rest_dt_s {
        Some(r) if m.rest_steps > 0 => format!(", {} of them at rest, of {:.4} s", m.rest_steps, r),
        _ => String::new(),
    };
    s += &format!(
        " ({} steps{rest}, {:.2} s simulated, {:.1} s wall)\n",
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
    if m.settled && m.max_step_speed_m_per_s > AT_REST_STEP_SPEED_M_PER_S {
        s += &format!(
            "  warning: called at rest while a node moved {:.2} mm/s over the last step, where a cloth \
             at rest keeps below {:.0} mm/s: it may still be flickering in place; a confirmation \
             watch (`integration.settle.confirm_s`, 2 s in the shipped scenes) waits that out \
             (docs/model.md §1, \"Rest\")\n",
            m.max_step_speed_m_per_s * 1e3,
            AT_REST_STEP_SPEED_M_PER_S * 1e3
        );
    }
    if m.strain_limited_steps > 0 {
        s += &format!(
            "  the strain limit shortened links after {} steps: the step is long for this lattice, \
             and a shorter one drapes without it (docs/model.md §12, \"The longest step\")\n",
            m.strain_limited_steps
        );
    }
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
    let estimate = m.numerical_error.as_ref();
    if let (Some(dc), Some(n)) = (m.drape_coefficient, m.nodes) {
        let tag = if m.settled {
            ""
        } else {
            " (provisional: not settled)"
        };
        let error = plus_minus(estimate, |e| e.drape_coefficient, 1.0, 3);
        let companion_nodes = estimate
            .and_then(|e| e.companion_nodes)
            .map_or(String::new(), |c| format!(" ({c} at the coarser spacing)"));
        s += &format!("  drape coefficient {dc:.3}{error}, {n} nodes{companion_nodes}{tag}\n");
    }
    if let (Some(chord), Some(exact)) = (m.cantilever_chord_deg, m.cantilever_exact_deg) {
        let error = plus_minus(estimate, |e| e.cantilever_chord_deg, 1.0, 2);
        s += &format!(
            "  cantilever chord {chord:.2}°{error} from the clamp's direction; the heavy elastica's {exact:.2}° ({:+.2}°)\n",
            chord - exact
        );
    }
    if let (Some(c), Some(side), Some(f)) = (m.hang_corners_m, m.hang_mid_sides_m, m.skirt_folds) {
        let error = plus_minus(estimate, |e| e.hang_corners_m, 1e3, 1);
        let companion_folds = estimate
            .and_then(|e| e.companion_skirt_folds)
            .map_or(String::new(), |c| format!(" ({c} at the coarser spacing)"));
        s += &format!(
            "  hang: corners {:.1}{error} mm, mid-sides {:.1} mm; {f} skirt folds{companion_folds}\n",
            c * 1e3,
            side * 1e3
        );
    }
    s += &estimate_line(estimate);
    let ours: f64 = m
        .effects
        .iter()
        .filter(|(k, _)| *k != "rapier_step")
        .map(|(_, c)| c.seconds)
        .sum();
    let rapier = m.effects.get("rapier_step").map_or(0.0, |c| c.seconds);
    s += &format!("  time: our forces {ours:.2} s");
    if let Some(solve) = m.effects.get("implicit_solve").filter(|c| c.calls > 0) {
        s += &format!(" (of which the implicit solve {:.2} s", solve.seconds);
        if let Some(split) = m.solve_split {
            s += &format!(
                ": assembly {:.2} s, preconditioner {:.2} s, CG {:.2} s",
                split.assembly_s, split.preconditioner_s, split.cg_s
            );
        }
        s += ")";
    }
    s += &format!(", Rapier's step {rapier:.2} s");
    s
}

/// " ± E" for a quantity with an estimated numerical error (scaled by `unit`, `digits` after the
/// point), " (numerical error not estimated)" otherwise.
fn plus_minus(
    estimate: Option<&ErrorEstimate>,
    pick: fn(&ErrorEstimate) -> Option<Estimated>,
    unit: f64,
    digits: usize,
) -> String {
    match estimate.and_then(pick) {
        Some(e) => format!(" ± {:.digits$}", e.error * unit),
        None => " (numerical error not estimated)".to_string(),
    }
}

/// How the numerical errors above were estimated (or why they were not).
fn estimate_line(estimate: Option<&ErrorEstimate>) -> String {
    match estimate {
        None => String::new(),
        Some(e) => match &e.companion_failure {
            Some(why) => format!("  numerical error not estimated: {why}\n"),
            None => format!(
                "  ± estimates the numerical error as {:.0}× |this run − the same scene at {:.2} mm \
                 ({}× the spacing{})|, an error of first order in the spacing at this step (the \
                 step's own share is not in it); `kes-cloth converge` measures the order and \
                 extrapolates\n",
                1.0 / (e.ratio.powf(e.assumed_order) - 1.0),
                e.companion_spacing_m * 1e3,
                e.ratio,
                if e.companion_settled {
                    ""
                } else {
                    ", which did not settle"
                },
            ),
        },
    }
}

/// The sheet of the scene's fabric in KES and SI units, if its KES values can be read.
fn scene_fabric_sheet(scene: &Scene) -> Option<String> {
    match &scene.spec.fabric {
        FabricSource::File(file) => {
            let base = scene.path.parent().unwrap_or(Path::new("."));
            Fabric::load_with_kes(base.join(file)).ok()
        }
        FabricSource::Inline(kes) => Fabric::from_kes(kes).ok().map(|f| ((**kes).clone(), f)),
    }
    .map(|(kes, fabric)| fabric_sheet(&kes, &fabric))
}

/// Writes `dir/report.html` for `--repeat`: the modal node count and DC's mean and spread, one
/// row per run (its seed and lattice shift), `repeat.png` (DC by run), run 0's pictures and 3D
/// view (from `seed-0/`), and the fabric.
pub fn write_repeat_report(repeats: &crate::repeat::Repeats, dir: &Path) -> Result<(), OutputError> {
    let (scene, runs, summary) = (&repeats.scene, &repeats.runs, &repeats.summary);
    let mut figures = vec![
        (
            "runs".to_string(),
            format!("{}, {} settled", summary.runs, summary.settled),
        ),
        (
            "drape coefficient DC: mean ± sample standard deviation".to_string(),
            summary.dc_text(),
        ),
        ("nodes (folds)".to_string(), summary.node_counts_text()),
    ];
    if let Some(by_count) = summary.dc_by_node_count_text() {
        figures.push(("DC by node count".to_string(), by_count));
    }
    let rows = runs
        .iter()
        .map(|(k, m)| {
            vec![
                k.to_string(),
                repeats.seed(*k).to_string(),
                format!(
                    "({:.1}, {:.1})",
                    m.lattice_offset_m[0] * 1e3,
                    m.lattice_offset_m[1] * 1e3
                ),
                m.drape_coefficient.map_or("-".into(), |v| format!("{v:.3}")),
                m.nodes.map_or("-".into(), |v| v.to_string()),
                match (m.settled, m.settle_time_s) {
                    (true, Some(t)) => format!("{t:.2}"),
                    _ => "not settled".into(),
                },
                format!("{:.1}", m.wall_time_s),
            ]
        })
        .collect();
    let first = dir.join("seed-0");
    let runs: Vec<(Option<f64>, Option<u32>)> =
        runs.iter().map(|(_, m)| (m.drape_coefficient, m.nodes)).collect();
    let mut pictures = Vec::new();
    if runs.iter().any(|r| r.0.is_some()) {
        write_repeat_plot(dir, &runs)?;
        pictures.push((
            "repeat.png".to_string(),
            "DC by run, node counts beside; the line is the mean, the band one standard deviation"
                .to_string(),
        ));
    }
    pictures.extend(
        ["top.png", "side.png"]
            .iter()
            .filter(|f| first.join(f).exists())
            .map(|f| (format!("seed-0/{f}"), format!("run 0: {f}"))),
    );
    Report {
        title: format!("{}: {} runs", scene.spec.name, summary.runs),
        figures,
        pictures,
        fabric_sheet: scene_fabric_sheet(scene),
        glb: std::fs::read(first.join("final.glb"))
            .ok()
            .map(|bytes| ("seed-0/final.glb".into(), bytes)),
        tables: vec![ReportTable {
            caption: "Each run".into(),
            header: [
                "run",
                "seed",
                "lattice shift (mm)",
                "DC",
                "nodes",
                "settled at (s)",
                "wall time (s)",
            ]
            .map(String::from)
            .to_vec(),
            rows,
        }],
        ..Report::default()
    }
    .write(dir)
}
