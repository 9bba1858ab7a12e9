//! `repeat.png`: each repeat's drape coefficient against its run, labelled with its node count,
//! over the mean and the band of one sample standard deviation.

use std::path::Path;

use plotters::prelude::*;

use super::OutputError;

/// Draws `dir/repeat.png` from each run's (DC, nodes), by run; runs without a DC are left out.
pub fn write_repeat_plot(dir: &Path, runs: &[(Option<f64>, Option<u32>)]) -> Result<(), OutputError> {
    let path = dir.join("repeat.png");
    let err = |e: &dyn std::fmt::Display| OutputError::new(&path, e);
    let points: Vec<(f64, f64, Option<u32>)> = runs
        .iter()
        .enumerate()
        .filter_map(|(run, (dc, nodes))| dc.map(|dc| (run as f64, dc, *nodes)))
        .collect();
    let n = points.len() as f64;
    let mean = points.iter().map(|p| p.1).sum::<f64>() / n.max(1.0);
    let sd = if points.len() > 1 {
        (points.iter().map(|p| (p.1 - mean).powi(2)).sum::<f64>() / (n - 1.0)).sqrt()
    } else {
        0.0
    };
    let (lo, hi) = points
        .iter()
        .fold((mean - sd, mean + sd), |(a, b), p| (a.min(p.1), b.max(p.1)));
    let pad = ((hi - lo) * 0.25).max(0.01);
    super::register_plot_font();
    let root = BitMapBackend::new(&path, (700, 400)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let last = runs.len().max(1) as f64 - 0.5;
    let mut chart = ChartBuilder::on(&root)
        .caption(
            format!("drape coefficient by run: {mean:.3} ± {sd:.3}"),
            ("sans-serif", 18),
        )
        .margin(12)
        .x_label_area_size(40)
        .y_label_area_size(60)
        .build_cartesian_2d(-0.5..last, lo - pad..hi + pad)
        .map_err(|e| err(&e))?;
    chart
        .configure_mesh()
        .x_desc("run")
        .y_desc("DC")
        .x_labels(runs.len().clamp(2, 12))
        .x_label_formatter(&|x| format!("{x:.0}"))
        .label_style(("sans-serif", 14))
        .draw()
        .map_err(|e| err(&e))?;
    let band = RGBColor(200, 215, 240);
    chart
        .draw_series(std::iter::once(Rectangle::new(
            [(-0.5, mean - sd), (last, mean + sd)],
            band.filled(),
        )))
        .map_err(|e| err(&e))?;
    chart
        .draw_series(LineSeries::new(
            [(-0.5, mean), (last, mean)],
            BLUE.stroke_width(2),
        ))
        .map_err(|e| err(&e))?;
    chart
        .draw_series(
            points
                .iter()
                .map(|&(x, y, _)| Circle::new((x, y), 5, BLACK.filled())),
        )
        .map_err(|e| err(&e))?;
    // Each point names its node count.
    chart
        .draw_series(points.iter().map(|&(x, y, nodes)| {
            EmptyElement::at((x, y))
                + Text::new(
                    nodes.map_or(String::new(), |k| format!("{k} nodes")),
                    (8, -16),
                    ("sans-serif", 13),
                )
        }))
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}
