//! Writing a convergence study: `convergence.csv`, `convergence.md` and `convergence.png` (the
//! quantity against the spacing, the fitted power law and the extrapolated value's band).

use std::path::Path;

use plotters::prelude::*;

use super::convergence::{Convergence, ConvergenceRow};
use super::richardson::Extrapolation;
use crate::output::OutputError;

/// Writes the three files into `dir`.
pub fn write_convergence(c: &Convergence, dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::new(dir, e))?;
    let csv = dir.join("convergence.csv");
    std::fs::write(&csv, csv_text(c)).map_err(|e| OutputError::new(&csv, e))?;
    let md = dir.join("convergence.md");
    std::fs::write(&md, markdown(c)).map_err(|e| OutputError::new(&md, e))?;
    let png = dir.join("convergence.png");
    plot(c, &png).map_err(|e| OutputError::new(&png, std::io::Error::other(e.to_string())))
}

/// A row's value of the judged quantity.
type ValueOf = fn(&ConvergenceRow) -> Option<f64>;

/// The quantity the study is judged by: DC for a drape, corner hang (mm) for a tablecloth.
fn judged(c: &Convergence) -> Option<(&'static str, Extrapolation, ValueOf)> {
    if let Some(e) = c.drape_coefficient {
        return Some(("drape coefficient", e, |r| r.metrics.drape_coefficient));
    }
    if let Some(e) = c.cantilever_chord_deg {
        return Some(("cantilever chord (deg)", e, |r| r.metrics.cantilever_chord_deg));
    }
    c.hang_corners_m.map(|e| {
        let mm = Extrapolation {
            value: e.value * 1e3,
            uncertainty: e.uncertainty * 1e3,
            finest_error: e.finest_error * 1e3,
            noise: e.noise * 1e3,
            order: e.order,
        };
        (
            "corner hang (mm)",
            mm,
            (|r: &ConvergenceRow| r.metrics.hang_corners_m.map(|h| h * 1e3))
                as fn(&ConvergenceRow) -> Option<f64>,
        )
    })
}

/// One line: the extrapolated value with its uncertainty, its order and the finest run's error.
pub fn extrapolation_line(c: &Convergence) -> String {
    let Some((what, e, _)) = judged(c) else {
        return "nothing to extrapolate: a run failed, or the scene measures neither a drape nor a \
                tablecloth (`measure:`)"
            .to_string();
    };
    let order = match e.order {
        Some(p) => format!("observed order {p:.2}"),
        None => {
            "no order observed (the spacings are not in the asymptotic range: refine further)".to_string()
        }
    };
    let noise = if e.noise > 0.0 {
        format!("; ±{:.4} of the band is the scatter over placements", e.noise)
    } else {
        String::new()
    };
    format!(
        "{what} extrapolated to σ → 0: {:.4} ± {:.4} ({order}; the finest spacing is {:.4} from it{noise})",
        e.value, e.uncertainty, e.finest_error
    )
}

/// A row's node counts with their runs, most frequent first: "9 ×3, 8 ×1" (`sep` ", ",
/// `times` " ×"), or "9:3;8:1" for the CSV.
fn node_counts_cell(r: &ConvergenceRow, sep: &str, times: &str) -> String {
    r.node_counts
        .iter()
        .map(|g| format!("{}{times}{}", g.nodes, g.runs))
        .collect::<Vec<_>>()
        .join(sep)
}

fn csv_text(c: &Convergence) -> String {
    let mut s = String::from(
        "spacing_m,dt_s,particles,drape_coefficient,dc_std,nodes,hang_corners_m,skirt_folds,cantilever_chord_deg,cantilever_exact_deg,settled,wall_time_s,failed,node_counts\n",
    );
    let opt = |v: Option<f64>| v.map_or(String::new(), |v| format!("{v}"));
    for r in &c.rows {
        let m = &r.metrics;
        s += &format!(
            "{},{},{},{},{},{},{},{},{},{},{},{},{},{}\n",
            r.spacing_m,
            r.dt_s,
            m.particles,
            opt(m.drape_coefficient),
            opt(r.dc_std),
            m.nodes.map_or(String::new(), |n| n.to_string()),
            opt(m.hang_corners_m),
            m.skirt_folds.map_or(String::new(), |n| n.to_string()),
            opt(m.cantilever_chord_deg),
            opt(m.cantilever_exact_deg),
            m.settled,
            m.wall_time_s,
            m.failure.is_some(),
            node_counts_cell(r, ";", ":")
        );
    }
    s
}

fn markdown(c: &Convergence) -> String {
    let mut s = format!(
        "# Convergence of `{}` in the node spacing\n\n{} run(s) per spacing; step ∝ σ^{}.\n\n",
        c.scene, c.placements, c.step_exponent
    );
    s += "| spacing (mm) | step (ms) | particles | DC | nodes (× runs, where they differ) | corner hang (mm) | folds | cantilever chord (exact) | settled | wall (s) |\n";
    s += "|---|---|---|---|---|---|---|---|---|---|\n";
    for r in &c.rows {
        let m = &r.metrics;
        let dc = match (m.drape_coefficient, r.dc_std) {
            (Some(dc), Some(sd)) if c.placements > 1 => format!("{dc:.4} ± {sd:.4}"),
            (Some(dc), _) => format!("{dc:.4}"),
            _ => "–".to_string(),
        };
        s += &format!(
            "| {:.3} | {:.5} | {} | {dc} | {} | {} | {} | {} | {} | {:.1} |\n",
            r.spacing_m * 1e3,
            r.dt_s * 1e3,
            m.particles,
            if r.node_counts.len() > 1 {
                node_counts_cell(r, ", ", " ×")
            } else {
                m.nodes.map_or("–".to_string(), |n| n.to_string())
            },
            m.hang_corners_m
                .map_or("–".to_string(), |h| format!("{:.1}", h * 1e3)),
            m.skirt_folds.map_or("–".to_string(), |n| n.to_string()),
            match (m.cantilever_chord_deg, m.cantilever_exact_deg) {
                (Some(a), Some(e)) => format!("{a:.2}° ({e:.2}°)"),
                _ => "–".to_string(),
            },
            if m.failure.is_some() {
                "failed"
            } else if m.settled {
                "yes"
            } else {
                "no"
            },
            m.wall_time_s
        );
    }
    s += &format!("\n{}\n", extrapolation_line(c));
    if let Some((n, agree)) = c.nodes_settled() {
        s += &format!(
            "\nNodes at the finest spacing: {n}; {}.\n",
            if agree {
                "the next coarser spacing has the same"
            } else {
                "the next coarser spacing differs: the node count is not converged"
            }
        );
    }
    s += "\nMethod: Richardson extrapolation on the finest three spacings, uncertainty by the grid \
          convergence index (safety factor 1.25 with an observed order in [0.5, 4], else 3 times \
          the largest change between neighbouring spacings), and twice the propagated standard \
          error of the means over placements, in quadrature; `docs/accuracy.md`.\n";
    s
}

type PlotError = Box<dyn std::error::Error + Send + Sync>;

fn plot(c: &Convergence, path: &Path) -> Result<(), PlotError> {
    crate::output::register_plot_font();
    let root = BitMapBackend::new(path, (900, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let Some((what, e, value)) = judged(c) else {
        root.draw(&Text::new(
            "nothing to extrapolate (a run failed, or the scene declares no measure)",
            (40, 280),
            ("sans-serif", 20),
        ))?;
        return Ok(root.present()?);
    };
    let points: Vec<(f64, f64, f64)> = c
        .rows
        .iter()
        .filter_map(|r| {
            let sd = if what.starts_with("drape") {
                r.dc_std.unwrap_or(0.0)
            } else {
                0.0
            };
            value(r).map(|v| (r.spacing_m * 1e3, v, sd))
        })
        .collect();
    let x_max = points.iter().map(|p| p.0).fold(0.0, f64::max) * 1.1;
    let lo = points
        .iter()
        .map(|p| p.1 - p.2)
        .fold(e.value - e.uncertainty, f64::min);
    let hi = points
        .iter()
        .map(|p| p.1 + p.2)
        .fold(e.value + e.uncertainty, f64::max);
    let pad = 0.1 * (hi - lo).max(1e-3);
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("{}: {what} against the node spacing", c.scene),
            ("sans-serif", 22),
        )
        .margin(20)
        .x_label_area_size(50)
        .y_label_area_size(70)
        .build_cartesian_2d(0.0..x_max, (lo - pad)..(hi + pad))?;
    chart
        .configure_mesh()
        .x_desc("node spacing σ (mm)")
        .y_desc(what)
        .label_style(("sans-serif", 16))
        .draw()?;
    // The extrapolated value's band at σ = 0.
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [
                (0.0, e.value - e.uncertainty),
                (x_max * 0.03, e.value + e.uncertainty),
            ],
            RED.mix(0.3).filled(),
        )))?
        .label(format!("σ → 0: {:.4} ± {:.4}", e.value, e.uncertainty))
        .legend(|(x, y)| Rectangle::new([(x, y - 5), (x + 15, y + 5)], RED.mix(0.3).filled()));
    // The fitted power law through the finest three points.
    if let Some(p) = e.order {
        let finest = points.last().copied();
        if let Some((s3, f3, _)) = finest {
            let c_coef = (f3 - e.value) / s3.powf(p);
            let curve = (0..=100).map(|k| {
                let s = x_max * k as f64 / 100.0;
                (s, e.value + c_coef * s.powf(p))
            });
            chart
                .draw_series(LineSeries::new(curve, BLUE.mix(0.6)))?
                .label(format!("f₀ + C·σ^{p:.2}"))
                .legend(|(x, y)| PathElement::new([(x, y), (x + 15, y)], BLUE.mix(0.6)));
        }
    }
    // An analytic reference, where the scene has one (the cantilever's heavy elastica).
    if let Some(exact) = c.rows.iter().find_map(|r| r.metrics.cantilever_exact_deg) {
        chart
            .draw_series(LineSeries::new(
                [(0.0, exact), (x_max, exact)],
                GREEN.stroke_width(2),
            ))?
            .label(format!("exact (heavy elastica): {exact:.2}"))
            .legend(|(x, y)| PathElement::new([(x, y), (x + 15, y)], GREEN.stroke_width(2)));
    }
    chart
        .draw_series(
            points
                .iter()
                .map(|&(s, v, _)| Circle::new((s, v), 5, BLACK.filled())),
        )?
        .label("runs (mean over placements)")
        .legend(|(x, y)| Circle::new((x + 7, y), 5, BLACK.filled()));
    chart.draw_series(
        points
            .iter()
            .filter(|p| p.2 > 0.0)
            .map(|&(s, v, sd)| ErrorBar::new_vertical(s, v - sd, v, v + sd, BLACK, 8)),
    )?;
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::LowerRight)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 16))
        .draw()?;
    Ok(root.present()?)
}
