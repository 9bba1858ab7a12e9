//! The laboratory's loops as pictures, in the instrument's units: M–K for both threads
//! (`kes_bending.png`) and F–φ (`kes_shear.png`).

use std::path::Path;

use plotters::prelude::*;

use super::{KesLabReport, KesLoop};
use crate::material::KesUnit;
use crate::output::OutputError;

type PlotError = Box<dyn std::error::Error + Send + Sync>;

/// Writes `kes_bending.png` and `kes_shear.png` into `dir`.
pub fn write_loop_plots(report: &KesLabReport, dir: &Path) -> Result<(), OutputError> {
    crate::output::register_plot_font();
    let bending = dir.join("kes_bending.png");
    let series = [("warp", &report.bending[0]), ("weft", &report.bending[1])];
    let title = format!("{}: KES-FB2 bending, M against K", report.fabric);
    let axes = (
        KesUnit::Curvature,
        KesUnit::MomentPerWidth,
        "K (cm⁻¹)",
        "M (gf·cm/cm)",
    );
    draw(&bending, &title, &series, axes).map_err(|e| OutputError::new(&bending, e))?;
    let shear = dir.join("kes_shear.png");
    let title = format!("{}: KES-FB1 shear, F against φ", report.fabric);
    let axes = (
        KesUnit::Degree,
        KesUnit::ForcePerLength,
        "φ (degrees)",
        "F (gf/cm)",
    );
    draw(&shear, &title, &[("shear", &report.shear)], axes).map_err(|e| OutputError::new(&shear, e))
}

fn draw(
    path: &Path,
    title: &str,
    series: &[(&str, &KesLoop)],
    (x_unit, y_unit, x_desc, y_desc): (KesUnit, KesUnit, &str, &str),
) -> Result<(), PlotError> {
    let points: Vec<Vec<(f64, f64)>> = series
        .iter()
        .map(|(_, lp)| {
            lp.legs
                .iter()
                .flatten()
                .map(|r| (x_unit.from_si(r.x), y_unit.from_si(r.y)))
                .collect()
        })
        .collect();
    let bound = |f: fn(&(f64, f64)) -> f64| {
        points
            .iter()
            .flatten()
            .map(f)
            .fold(0.0f64, |a, v| a.max(v.abs()))
            .max(1e-9)
            * 1.05
    };
    let (xm, ym) = (bound(|p| p.0), bound(|p| p.1));
    let root = BitMapBackend::new(path, (900, 650)).into_drawing_area();
    root.fill(&WHITE)?;
    let mut chart = ChartBuilder::on(&root)
        .caption(title, ("sans-serif", 20))
        .margin(15)
        .x_label_area_size(45)
        .y_label_area_size(70)
        .build_cartesian_2d(-xm..xm, -ym..ym)?;
    chart
        .configure_mesh()
        .x_desc(x_desc)
        .y_desc(y_desc)
        .label_style(("sans-serif", 14))
        .draw()?;
    for (k, ((name, _), pts)) in series.iter().zip(points).enumerate() {
        let colour = Palette99::pick(k).to_rgba();
        chart
            .draw_series(LineSeries::new(pts, colour.stroke_width(2)))?
            .label(*name)
            .legend(move |(x, y)| PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(2)));
    }
    chart
        .configure_series_labels()
        .position(SeriesLabelPosition::UpperLeft)
        .background_style(WHITE.mix(0.85))
        .border_style(BLACK)
        .label_font(("sans-serif", 14))
        .draw()?;
    root.present()?;
    Ok(())
}
