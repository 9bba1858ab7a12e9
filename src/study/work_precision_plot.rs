//! The work–precision diagram: error against wall time, log–log, one curve per varied key.

use std::path::Path;

use plotters::prelude::*;

use super::{Study, StudyMeasure, StudyRow};

/// Smallest error drawn (errors below it, e.g. a run identical to the reference, sit on it).
const ERROR_FLOOR: f64 = 1e-5;

/// Which error a panel plots.
type ErrorOf = fn(&StudyRow) -> Option<f64>;

type PlotError = Box<dyn std::error::Error + Send + Sync>;

/// Draws DC error and shape error against wall time into `path` (PNG).
pub(super) fn plot_work_precision(study: &Study, path: &Path) -> Result<(), std::io::Error> {
    draw(study, path).map_err(|e| std::io::Error::other(e.to_string()))
}

/// The whole decades around [lo, hi] (both > 0), so a log axis has labelled ends.
fn decades(lo: f64, hi: f64) -> std::ops::Range<f64> {
    let lo = 10f64.powf(lo.log10().floor());
    let hi = 10f64.powf(hi.log10().ceil()).max(lo * 10.0);
    lo..hi
}

/// Ticks at 1, 2 and 5 times each power of ten within `range` (both ends > 0): a log axis gets
/// labels even when its range spans a single decade.
fn log_ticks(range: &std::ops::Range<f64>) -> Vec<f64> {
    let (first, last) = (
        range.start.log10().floor() as i32,
        range.end.log10().ceil() as i32,
    );
    (first..=last)
        .flat_map(|e| [1.0, 2.0, 5.0].map(|k| k * 10f64.powi(e)))
        .filter(|v| *v >= range.start * (1.0 - 1e-9) && *v <= range.end * (1.0 + 1e-9))
        .collect()
}

/// A tick's label: the value to three significant digits, without trailing zeros or the
/// rounding noise of powers of ten (0.3, 20, 1e-5), so two ticks never read the same.
fn tick_label(v: &f64) -> String {
    let rounded: f64 = format!("{v:.2e}").parse().unwrap_or(*v);
    if rounded != 0.0 && !(1e-3..1e5).contains(&rounded.abs()) {
        format!("{rounded:e}")
    } else {
        format!("{rounded}")
    }
}

/// The varied key whose values a line runs through: the spacing when it is varied, else the
/// last varied key. Points that differ only in it (one integrator, one step, ...) are joined.
fn joined_key(study: &Study) -> usize {
    study
        .keys
        .iter()
        .position(|k| k == "cloth.spacing_m")
        .unwrap_or(study.keys.len().saturating_sub(1))
}

/// A key's last path segment, e.g. `dt_s` for `integration.dt_s`.
fn short_key(key: &str) -> &str {
    key.rsplit('.').next().unwrap_or(key)
}

/// The lines of the diagram: the runs that did not fail, grouped by the values of every varied
/// key but the joined one, each in the order of the joined key's values, with a label naming
/// those values.
fn lines(study: &Study) -> Vec<(String, Vec<&StudyRow>)> {
    let joined = joined_key(study);
    let mut groups: Vec<(String, Vec<&StudyRow>)> = Vec::new();
    for row in study.rows.iter().filter(|r| r.metrics.failure.is_none()) {
        let label: Vec<String> = row
            .setting
            .iter()
            .enumerate()
            .filter(|(j, _)| *j != joined)
            .map(|(_, (k, v))| format!("{}={v}", short_key(k)))
            .collect();
        let label = if label.is_empty() {
            format!("varying {}", study.keys.get(joined).map_or("", |k| short_key(k)))
        } else {
            label.join(", ")
        };
        match groups.iter_mut().find(|g| g.0 == label) {
            Some(group) => group.1.push(row),
            None => groups.push((label, vec![row])),
        }
    }
    // Along the joined key's values (numbers in order), so a line follows the refinement.
    let at = |r: &StudyRow| {
        r.setting
            .get(joined)
            .and_then(|s| s.1.parse::<f64>().ok())
            .unwrap_or(f64::NAN)
    };
    for group in &mut groups {
        group.1.sort_by(|a, b| at(a).total_cmp(&at(b)));
    }
    groups
}

/// Height (px) of one legend entry below a chart.
const LEGEND_ROW: u32 = 22;

fn draw(study: &Study, path: &Path) -> Result<(), PlotError> {
    crate::output::register_plot_font();
    let groups = lines(study);
    let joined = joined_key(study);
    // The legend goes below the charts, one row per line and one for the shipped scene, so it
    // covers no point.
    let legend_height = LEGEND_ROW * (groups.len() as u32 + 1) + 20;
    let root = BitMapBackend::new(path, (1400, 600 + legend_height)).into_drawing_area();
    root.fill(&WHITE)?;
    let (charts, legend) = root.split_vertically(600);
    let (left, right) = charts.split_horizontally(700);
    // Drapemeter scenes are judged by DC, tablecloth scenes by how low their corners hang,
    // clamped strips by their chord angle.
    let first: (&str, ErrorOf) = match study.measure() {
        StudyMeasure::DrapeCoefficient => ("drape coefficient error |DC − DC_ref|", |r| r.dc_error),
        StudyMeasure::CornerHang => ("corner hang error (mm)", |r| r.hang_error_m.map(|e| e * 1e3)),
        StudyMeasure::CantileverChord => ("chord angle error (degrees)", |r| r.chord_error_deg),
    };
    let panels: [(_, &str, ErrorOf); 2] = [
        (left, first.0, first.1),
        (right, "shape error, RMS (mm)", |r| {
            r.shape_error_m.map(|e| e * 1e3)
        }),
    ];
    let times: Vec<f64> = study.rows.iter().map(|r| r.metrics.wall_time_s).collect();
    let (t_min, t_max) = times
        .iter()
        .fold((f64::INFINITY, 0.0f64), |(a, b), &t| (a.min(t), b.max(t)));
    let x_range = decades(t_min.max(1e-3), t_max.max(1e-3));
    for (area, label, value) in panels {
        let errors: Vec<f64> = study.rows.iter().filter_map(value).collect();
        let e_max = errors.iter().fold(ERROR_FLOOR, |a, &e| a.max(e));
        let e_min = errors.iter().fold(e_max, |a, &e| a.min(e.max(ERROR_FLOOR)));
        let y_range = decades(e_min, e_max);
        let mut chart = ChartBuilder::on(&area)
            .caption(format!("{}: {label}", study.scene), ("sans-serif", 20))
            .margin(15)
            .x_label_area_size(45)
            .y_label_area_size(70)
            .build_cartesian_2d(
                x_range.clone().log_scale().with_key_points(log_ticks(&x_range)),
                y_range.clone().log_scale().with_key_points(log_ticks(&y_range)),
            )?;
        chart
            .configure_mesh()
            .x_label_formatter(&tick_label)
            .y_label_formatter(&tick_label)
            .x_desc("wall time (s)")
            .y_desc(label)
            .label_style(("sans-serif", 14))
            .draw()?;
        for (k, (_, rows)) in groups.iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let points: Vec<(f64, f64, &str)> = rows
                .iter()
                .filter_map(|r| {
                    value(r).map(|e| {
                        let at = r.setting.get(joined).map_or("", |s| s.1.as_str());
                        (r.metrics.wall_time_s, e.max(ERROR_FLOOR), at)
                    })
                })
                .collect();
            let xy: Vec<(f64, f64)> = points.iter().map(|p| (p.0, p.1)).collect();
            chart.draw_series(LineSeries::new(xy.clone(), colour.stroke_width(2)))?;
            chart.draw_series(xy.iter().map(|&p| Circle::new(p, 4, colour.filled())))?;
            // Each point names its value of the joined key, e.g. `0.0075`.
            chart.draw_series(points.iter().map(|&(x, y, at)| {
                EmptyElement::at((x, y))
                    + Text::new(
                        at.to_string(),
                        (7, -15),
                        ("sans-serif", 12).into_font().color(&colour),
                    )
            }))?;
        }
        let shipped: Vec<(f64, f64)> = study
            .rows
            .iter()
            .filter(|r| r.is_default)
            .filter_map(|r| value(r).map(|e| (r.metrics.wall_time_s, e.max(ERROR_FLOOR))))
            .collect();
        chart.draw_series(shipped.iter().map(|&p| Cross::new(p, 9, BLACK.stroke_width(3))))?;
    }
    let font = ("sans-serif", 15).into_font();
    let joined_name = study.keys.get(joined).map_or("", |k| short_key(k));
    legend.draw(&Text::new(
        format!("Lines join runs that differ only in {joined_name}; each point is labelled with its {joined_name}."),
        (20, 4),
        font.clone(),
    ))?;
    for (k, (label, _)) in groups.iter().enumerate() {
        let colour = Palette99::pick(k).to_rgba();
        let y = 4 + LEGEND_ROW as i32 * (k as i32 + 1);
        legend.draw(&PathElement::new(
            vec![(20, y + 8), (50, y + 8)],
            colour.stroke_width(2),
        ))?;
        legend.draw(&Circle::new((35, y + 8), 4, colour.filled()))?;
        legend.draw(&Text::new(label.clone(), (60, y), font.clone()))?;
    }
    let y = 4 + LEGEND_ROW as i32 * (groups.len() as i32 + 1);
    legend.draw(&Cross::new((35, y + 8), 6, BLACK.stroke_width(2)))?;
    legend.draw(&Text::new("the scene as shipped", (60, y), font))?;
    root.present()?;
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_decade_gets_labels_at_1_2_and_5() {
        let ticks = log_ticks(&(0.01..0.1));
        let labels: Vec<String> = ticks.iter().map(tick_label).collect();
        assert_eq!(labels, ["0.01", "0.02", "0.05", "0.1"]);
    }

    #[test]
    fn labels_of_round_values_read_cleanly() {
        let labels: Vec<String> = log_ticks(&(1e-5..100.0)).iter().map(tick_label).collect();
        assert_eq!(labels.first().map(String::as_str), Some("1e-5"));
        assert!(labels.contains(&"0.2".to_string()) && labels.contains(&"50".to_string()));
        let mut unique = labels.clone();
        unique.dedup();
        assert_eq!(unique, labels, "two ticks read the same");
    }
}
