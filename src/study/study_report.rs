//! A study's files: `study.csv`, `study.md` and `work_precision.png`.

use std::fmt::Write as _;
use std::path::Path;

use super::Study;
use super::work_precision_plot::plot_work_precision;
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
          reference_settled\n";
    for row in &study.rows {
        let m = &row.metrics;
        let values: Vec<&str> = row.setting.iter().map(|(_, v)| v.as_str()).collect();
        let _ = writeln!(
            s,
            "{},{},{},{},{},{},{:.3},{},{},{},{},{},{},{:.5},{},{},{},{},{},{},{},{},{}",
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
            "Every row and the reference are means over {} runs (seeds 0–{}, each with its own \
             placement of the node lattice against the outline): DC mean ± sd, modal node count, \
             mean wall time per run, largest strain.\n",
            study.placements,
            study.placements - 1
        );
    }
    let table = !study.is_drapemeter();
    s += if study.reference.as_ref().is_none_or(|r| r.failure.is_some()) {
        "★ marks the scene's own setting.\n\n"
    } else if table {
        "Errors are against the reference: hang error |hang − hang_ref| of the four corners below the \
         table top; shape error is the RMS distance of the run's nodes from the reference's draped \
         surface. ★ marks the scene's own setting.\n\n"
    } else {
        "Errors are against the reference: DC error |DC − DC_ref|; shape error is the RMS distance \
         of the run's nodes from the reference's draped surface. ★ marks the scene's own setting.\n\n"
    };
    let measures = if table {
        "corner hang (mm) | skirt folds | hang error (mm)"
    } else {
        "DC | folds | DC error"
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
        let _ = writeln!(
            s,
            "| {} | {} | {:.3} | {:.1} | {} | {} | {} | {} | {} | {:.1} % |",
            values.join(" | "),
            m.particles,
            m.dt_s * 1e3,
            m.wall_time_s,
            settled,
            if table {
                opt(m.hang_corners_m.map(|h| h * 1e3), 1)
            } else {
                m.drape_coefficient
                    .map_or(String::new(), |dc| with_spread(dc, row.dc_std, study.placements))
            },
            if table { m.skirt_folds } else { m.nodes }.map_or("-".into(), |n| n.to_string()),
            if table {
                opt(row.hang_error_m.map(|e| e * 1e3), 1)
            } else {
                opt(row.dc_error, 3)
            },
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
        "Reference ({setting}): {} nodes at {:.1} mm, dt {:.3} ms, {}; {}, {:.1} s wall.\n",
        r.particles,
        r.spacing_m * 1e3,
        r.dt_s * 1e3,
        r.integrator,
        match (r.drape_coefficient, r.hang_corners_m) {
            (Some(dc), _) => format!(
                "DC {}, {} nodes",
                with_spread(dc, study.reference_dc_std, study.placements),
                r.nodes.map_or("-".into(), |n| n.to_string())
            ),
            (None, Some(hang)) => format!(
                "corners hang {:.1} mm, {} skirt folds",
                hang * 1e3,
                r.skirt_folds.map_or("-".into(), |n| n.to_string())
            ),
            _ => "no drape or tablecloth measure".to_string(),
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
