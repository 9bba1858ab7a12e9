//! The work–precision diagram: error against wall time, log–log, one curve per varied key.

use std::path::Path;

use plotters::prelude::*;

use super::{Study, StudyRow};

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

/// The rows of the curve for key `k`: every other key at its default value when the default is
/// among its values (else its first value), sorted by wall time.
fn curve(study: &Study, k: usize) -> Vec<&StudyRow> {
    let anchors: Vec<String> = (0..study.keys.len())
        .map(|j| {
            study
                .rows
                .iter()
                .find(|r| r.is_default)
                .or(study.rows.first())
                .map_or(String::new(), |r| r.setting[j].1.clone())
        })
        .collect();
    let mut rows: Vec<&StudyRow> = study
        .rows
        .iter()
        .filter(|r| r.metrics.failure.is_none())
        .filter(|r| (0..study.keys.len()).all(|j| j == k || r.setting[j].1 == anchors[j]))
        .collect();
    rows.sort_by(|a, b| a.metrics.wall_time_s.total_cmp(&b.metrics.wall_time_s));
    rows
}

fn draw(study: &Study, path: &Path) -> Result<(), PlotError> {
    crate::output::register_plot_font();
    let root = BitMapBackend::new(path, (1400, 600)).into_drawing_area();
    root.fill(&WHITE)?;
    let (left, right) = root.split_horizontally(700);
    // Drapemeter scenes are judged by DC, tablecloth scenes by how low their corners hang.
    let first: (&str, ErrorOf) = if study.is_drapemeter() {
        ("drape coefficient error |DC − DC_ref|", |r| r.dc_error)
    } else {
        ("corner hang error (mm)", |r| r.hang_error_m.map(|e| e * 1e3))
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
        // Every grid point, so points off the curves (another key away from its default, e.g.
        // where the guard refused the default step at that spacing) are still seen.
        let grey = RGBColor(150, 150, 150);
        let all: Vec<(f64, f64)> = study
            .rows
            .iter()
            .filter(|r| r.metrics.failure.is_none())
            .filter_map(|r| value(r).map(|e| (r.metrics.wall_time_s, e.max(ERROR_FLOOR))))
            .collect();
        chart
            .draw_series(all.iter().map(|&p| Circle::new(p, 6, grey.stroke_width(1))))?
            .label("every grid point")
            .legend(move |(x, y)| Circle::new((x + 10, y), 5, grey.stroke_width(1)));
        for (k, key) in study.keys.iter().enumerate() {
            let colour = Palette99::pick(k).to_rgba();
            let points: Vec<(f64, f64)> = curve(study, k)
                .iter()
                .filter_map(|r| value(r).map(|e| (r.metrics.wall_time_s, e.max(ERROR_FLOOR))))
                .collect();
            chart
                .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))?
                .label(format!("varying {key}"))
                .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
            chart.draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))?;
        }
        let shipped: Vec<(f64, f64)> = study
            .rows
            .iter()
            .filter(|r| r.is_default)
            .filter_map(|r| value(r).map(|e| (r.metrics.wall_time_s, e.max(ERROR_FLOOR))))
            .collect();
        chart
            .draw_series(shipped.iter().map(|&p| Cross::new(p, 9, BLACK.stroke_width(3))))?
            .label("scene as shipped")
            .legend(|(x, y)| Cross::new((x + 10, y), 6, BLACK.stroke_width(2)));
        // Upper right: a slow run with a large error, the corner a work–precision diagram
        // leaves empty, so the legend hides no point there.
        chart
            .configure_series_labels()
            .position(SeriesLabelPosition::UpperRight)
            .background_style(WHITE.mix(0.85))
            .border_style(BLACK)
            .label_font(("sans-serif", 14))
            .draw()?;
    }
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
