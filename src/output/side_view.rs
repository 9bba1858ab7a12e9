//! `side.png`: the draped cloth seen from the side (looking along −z, x to the right, y up),
//! nearer parts lighter, with the fixed colliders' silhouettes: how far the skirt falls and how
//! deep its folds are, which the top view cannot show.

use std::path::Path;

use glam::DVec3;
use plotters::prelude::*;

use super::OutputError;
use super::top_view::shaded_triangles;
use crate::forces::ClothTopology;

/// Renders `dir/side.png` (`size` pixels wide, as tall as the cloth at that scale, at least a
/// fifth of the width), framed on the cloth, with the grey
/// rectangles `silhouettes` ([x_min, y_min, x_max, y_max], m) behind it.
pub fn write_side_view(
    dir: &Path,
    size: u32,
    topology: &ClothTopology,
    positions: &[DVec3],
    silhouettes: &[[f64; 4]],
) -> Result<(), OutputError> {
    let path = dir.join("side.png");
    let err = |e: &dyn std::fmt::Display| OutputError::new(&path, e);
    let (x_lo, x_hi, y_lo, y_hi) = positions.iter().fold(
        (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY),
        |(a, b, c, d), p| (a.min(p.x), b.max(p.x), c.min(p.y), d.max(p.y)),
    );
    // The cloth's width fills the picture; its height sets the picture's, at the same scale
    // (at least a fifth of the width), with a margin above and below.
    let half_width = (x_hi - x_lo) / 2.0 * 1.08 + 1e-3;
    let x_mid = (x_lo + x_hi) / 2.0;
    let tall = ((y_hi - y_lo) * 1.3).max(0.4 * half_width);
    let top = y_hi + 0.15 * (tall - (y_hi - y_lo));
    let width = size;
    let height = ((size as f64) * tall / (2.0 * half_width)).round().max(1.0) as u32;
    let root = BitMapBackend::new(&path, (width, height)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .margin(4)
        .build_cartesian_2d(x_mid - half_width..x_mid + half_width, top - tall..top)
        .map_err(|e| err(&e))?;
    let grey = RGBColor(190, 190, 190);
    chart
        .draw_series(
            silhouettes
                .iter()
                .map(|s| Rectangle::new([(s[0], s[1]), (s[2], s[3])], grey.filled())),
        )
        .map_err(|e| err(&e))?;
    let polygons = shaded_triangles(topology, positions, |p| ((p.x, p.y), p.z));
    chart.draw_series(polygons).map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}
