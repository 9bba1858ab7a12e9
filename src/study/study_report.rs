//! A study's files: `study.csv`, `study.md` and `work_precision.png`.

use std::fmt::Write as _;
use std::path::Path;

use super::work_precision_plot::plot_work_precision;
use super::{Study, StudyMeasure};
use crate::output::OutputError;

/// Writes the study's table (CSV and Markdown) and its work–precision diagram into `dir`.
pub fn write_study(study: &Study, dir: &Path) -> Result<(), OutputError> {
    std::fs::create_dir_all(dir).map_err(|e| OutputError::new(dir, e))?;
    let csv = dir.join("study.csv");
    std::fs::write(&csv, csv_text(study)).map_err(|e| OutputError::new(&csv, e))?;
    let md = dir.join("study.md");
    std::fs::write(&md, markdown(study)).map_err(|e| OutputError::new(&md, e))?;
    let png = dir.join("work_precision.png");
    plot_work_precision(study, &png).map_err(|e| OutputError::new(&png, e))?;
    crate::output::Report {
        title: format!("Study of {}", study.scene),
        pictures: vec![(
            "work_precision.png".into(),
            "error against wall time: what accuracy costs".into(),
        )],
        texts: vec![("Every run".into(), markdown(study))],
        ..crate::output::Report::default()
    }
    .write(dir)
}

/// `0.459 ± 0.020` over several placements, `0.459` for one run.
fn with_spread(dc: f64, sd: Option<f64>, placements: usize) -> String {
    match sd {
        Some(sd) if placements > 1 => format!("{dc:.3} ± {sd:.3}"),
        _ => format!("{dc:.3}"),
    }
}

fn opt(v: Option<f64>, digits: usize) -> String {
    v.map_or(String::new(), |v| format!("{v:.digits$}"))
}

fn csv_text(study: &Study) -> String {
    let mut s = study.keys.join(",");
    s += ",particles,spacing_m,dt_s,integrator,steps,wall_time_s,settled,settle_time_s,\
          drape_coefficient,nodes,dc_error,shape_error_m,max_strain,failed,default,\
          hang_corners_m,skirt_folds,hang_error_m,placements,dc_std,reference_failed,\
          reference_settled,cantilever_chord_deg,cantilever_exact_deg,chord_error_deg\n";
    for row in &study.rows {
        let m = &row.metrics;
        let values: Vec<&str> = row.setting.iter().map(|(_, v)| v.as_str()).collect();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:.3},{},{},{},{},{},{},{:.5},{},{},{},{},{},{},{},{},{},{},{},{}",
            values.join(","),
            m.particles,
            m.spacing_m,
            m.dt_s,
            m.integrator,
            m.steps,
            m.wall_time_s,
            m.settled,
            opt(m.settle_time_s, 4),
            opt(m.drape_coefficient, 4),
            m.nodes.map_or(String::new(), |n| n.to_string()),
            opt(row.dc_error, 4),
            opt(row.shape_error_m, 6),
            m.max_strain,
            m.failure.is_some(),
            row.is_default,
            opt(m.hang_corners_m, 5),
            m.skirt_folds.map_or(String::new(), |n| n.to_string()),
            opt(row.hang_error_m, 5),
            study.placements,
            opt(row.dc_std, 4),
            study
                .reference
                .as_ref()
                .map_or(String::new(), |r| r.failure.is_some().to_string()),
            study
                .reference
                .as_ref()
                .map_or(String::new(), |r| r.settled.to_string()),
            opt(m.cantilever_chord_deg, 3),
            opt(m.cantilever_exact_deg, 3),
            opt(row.chord_error_deg, 3),
        );
    }
    s
}

fn markdown(study: &Study) -> String {
    let mut s = format!("# Study of `{}`\n\n", study.scene);
    let reference_setting = if study.reference_setting.is_empty() {
        "the scene as shipped".to_string()
    } else {
        format!("`{}`", study.reference_setting.join(" "))
    };
    match &study.reference {
        Some(r) => reference_lines(&mut s, study, r, &reference_setting),
        None => {
            let _ = writeln!(
                s,
                "Reference ({reference_setting}): **not finished yet**: no errors are given.\n"
            );
        }
    }
    if !study.missing.is_empty() {
        let _ = writeln!(
            s,
            "**Tasks not finished**: {:?}. Grid points with a run missing are left out; run the \
             tasks (`kes-cloth task DIR K`) and collect again (`kes-cloth collect DIR`).\n",
            study.missing
        );
    }
    if study.placements > 1 {
        let _ = writeln!(
            s,
            "Every row and the reference are means over {} runs, each with its own placement of \
             the node lattice against the outline: DC mean ± sd, modal node count, mean wall \
             time per run, largest strain.\n",
            study.placements
        );
    }
    let measure = study.measure();
    s += if study.reference.as_ref().is_none_or(|r| r.failure.is_some()) {
        "★ marks the scene's own setting.\n\n".to_string()
    } else {
        match measure {
            StudyMeasure::DrapeCoefficient => "Errors are against the reference: DC error |DC − DC_ref|; ",
            StudyMeasure::CornerHang => {
                "Errors are against the reference: hang error |hang − hang_ref| of the four corners \
                 below the table top; "
            }
            StudyMeasure::CantileverChord => {
                "Errors are against the reference: chord error |chord − chord_ref|, the chord from \
                 the clamp's edge to the free end (the heavy elastica's exact angle beside it); "
            }
        }
        .to_string()
            + "shape error is the RMS distance of the run's nodes from the reference's draped surface. \
               ★ marks the scene's own setting.\n\n"
    }
    .as_str();
    let measures = match measure {
        StudyMeasure::DrapeCoefficient => "DC | folds | DC error",
        StudyMeasure::CornerHang => "corner hang (mm) | skirt folds | hang error (mm)",
        StudyMeasure::CantileverChord => "chord (°) | exact (°) | chord error (°)",
    };
    let _ = writeln!(
        s,
        "| {} | nodes | dt (ms) | wall (s) | settled (s) | {measures} | shape error (mm) | max strain |",
        study.keys.join(" | ")
    );
    let _ = writeln!(s, "|{}", "---|".repeat(study.keys.len() + 9));
    for row in &study.rows {
        let m = &row.metrics;
        let values: Vec<String> = row
            .setting
            .iter()
            .enumerate()
            .map(|(i, (_, v))| {
                if i == 0 && row.is_default {
                    format!("★ {v}")
                } else {
                    v.clone()
                }
            })
            .collect();
        let settled = match (m.failure.is_some(), m.settle_time_s) {
            (true, _) => "diverged".to_string(),
            (false, Some(t)) if m.settled => format!("{t:.2}"),
            _ => "no".to_string(),
        };
        let [value, count, error] = match measure {
            StudyMeasure::DrapeCoefficient => [
                m.drape_coefficient
                    .map_or(String::new(), |dc| with_spread(dc, row.dc_std, study.placements)),
                m.nodes.map_or("-".into(), |n| n.to_string()),
                opt(row.dc_error, 3),
            ],
            StudyMeasure::CornerHang => [
                opt(m.hang_corners_m.map(|h| h * 1e3), 1),
                m.skirt_folds.map_or("-".into(), |n| n.to_string()),
                opt(row.hang_error_m.map(|e| e * 1e3), 1),
            ],
            StudyMeasure::CantileverChord => [
                opt(m.cantilever_chord_deg, 2),
                opt(m.cantilever_exact_deg, 2),
                opt(row.chord_error_deg, 2),
            ],
        };
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {:.1} | {} | {value} | {count} | {error} | {} | {:.1} % |",
            values.join(" | "),
            m.particles,
            m.dt_s * 1e3,
            m.wall_time_s,
            settled,
            opt(row.shape_error_m.map(|e| e * 1e3), 2),
            m.max_strain * 100.0
        );
    }
    if !study.refused.is_empty() {
        s += "\nNot run:\n\n";
        for p in &study.refused {
            let setting: Vec<String> = p.setting.iter().map(|(k, v)| format!("{k}={v}")).collect();
            let _ = writeln!(s, "- {}: {}", setting.join(", "), p.why);
        }
    }
    s
}

/// The reference's line, and its failure or unsettled warning.
fn reference_lines(s: &mut String, study: &Study, r: &crate::output::Metrics, setting: &str) {
    let _ = writeln!(
        s,
        "Reference ({setting}): {} nodes at {} mm, dt {:.3} ms, {}; {}, {:.1} s wall.\n",
        r.particles,
        crate::output::number(r.spacing_m * 1e3),
        r.dt_s * 1e3,
        r.integrator,
        match (r.drape_coefficient, r.hang_corners_m, r.cantilever_chord_deg) {
            (_, _, Some(chord)) => format!(
                "chord {chord:.2}° (the heavy elastica's {})",
                r.cantilever_exact_deg.map_or("-".into(), |e| format!("{e:.2}°"))
            ),
            (Some(dc), _, _) => format!(
                "DC {}, {} nodes",
                with_spread(dc, study.reference_dc_std, study.placements),
                r.nodes.map_or("-".into(), |n| n.to_string())
            ),
            (None, Some(hang), _) => format!(
                "corners hang {:.1} mm, {} skirt folds",
                hang * 1e3,
                r.skirt_folds.map_or("-".into(), |n| n.to_string())
            ),
            _ => "no drape, tablecloth or cantilever measure".to_string(),
        },
        r.wall_time_s
    );
    if let Some(f) = &r.failure {
        let _ = writeln!(
            s,
            "**The reference failed** at step {} (t = {:.4} s, particle {}, effect `{}`: {}): no \
             errors are given. Choose a reference the stability guard and the solver can run.\n",
            f.step, f.time_s, f.particle, f.effect, f.message
        );
    } else if !r.settled {
        let _ = writeln!(
            s,
            "**The reference did not settle** within its {:.1} s: its measures are provisional, and \
             so is every error below. Give it more time (`integration.max_time_s`).\n",
            r.sim_time_s
        );
    }
}
