//! `top.png`: the draped cloth seen from above, shaded by height, with the collider outlines,
//! like the seed's Fig. 3.

use std::path::Path;

use glam::DVec3;
use plotters::prelude::*;

use super::OutputError;
use crate::forces::ClothTopology;

/// A collider outline to draw in the top view (true dimensions, m).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum TopViewOutline {
    /// A circle of `radius` around (x, z).
    Circle {
        /// Centre (x, z) (m).
        centre: [f64; 2],
        /// Radius (m).
        radius: f64,
    },
    /// An axis-aligned rectangle.
    Rectangle {
        /// Centre (x, z) (m).
        centre: [f64; 2],
        /// Half extents along x and z (m).
        half: [f64; 2],
    },
}

/// Renders `dir/top.png` (`size` × `size` pixels): x to the right, z down the image, with red
/// dots at `markers` (x, z) (m), e.g. the counted nodes.
pub fn write_top_view(
    dir: &Path,
    size: u32,
    topology: &ClothTopology,
    positions: &[DVec3],
    outlines: &[TopViewOutline],
    markers: &[[f64; 2]],
) -> Result<(), OutputError> {
    let path = dir.join("top.png");
    let err = |e: &dyn std::fmt::Display| OutputError::new(&path, e);
    // Square view around the cloth and the outlines.
    let mut extent = positions
        .iter()
        .fold(0.0f64, |m, p| m.max(p.x.abs()).max(p.z.abs()));
    for o in outlines {
        extent = extent.max(match *o {
            TopViewOutline::Circle { centre, radius } => centre[0].abs().max(centre[1].abs()) + radius,
            TopViewOutline::Rectangle { centre, half } => {
                (centre[0].abs() + half[0]).max(centre[1].abs() + half[1])
            }
        });
    }
    let extent = extent * 1.08 + 1e-3;
    let root = BitMapBackend::new(&path, (size, size)).into_drawing_area();
    root.fill(&WHITE).map_err(|e| err(&e))?;
    let mut chart = ChartBuilder::on(&root)
        .margin(4)
        .build_cartesian_2d(-extent..extent, extent..-extent)
        .map_err(|e| err(&e))?;

    // Seen from above: x right, z down the image, nearer (higher) triangles lighter and drawn
    // last, so the top surface stays visible.
    let polygons = shaded_triangles(topology, positions, |p| ((p.x, p.z), p.y));
    chart.draw_series(polygons).map_err(|e| err(&e))?;

    for o in outlines {
        let ring: Vec<(f64, f64)> = match *o {
            TopViewOutline::Circle { centre, radius } => (0..=180)
                .map(|k| {
                    let a = k as f64 * std::f64::consts::TAU / 180.0;
                    (centre[0] + radius * a.cos(), centre[1] + radius * a.sin())
                })
                .collect(),
            TopViewOutline::Rectangle { centre, half } => vec![
                (centre[0] - half[0], centre[1] - half[1]),
                (centre[0] + half[0], centre[1] - half[1]),
                (centre[0] + half[0], centre[1] + half[1]),
                (centre[0] - half[0], centre[1] + half[1]),
                (centre[0] - half[0], centre[1] - half[1]),
            ],
        };
        chart
            .draw_series(LineSeries::new(ring, BLACK.stroke_width(2)))
            .map_err(|e| err(&e))?;
    }
    let dot = (size / 80).max(3) as i32;
    chart
        .draw_series(
            markers
                .iter()
                .map(|m| Circle::new((m[0], m[1]), dot, RED.filled())),
        )
        .map_err(|e| err(&e))?;
    root.present().map_err(|e| err(&e))
}

/// The cloth's triangles as filled polygons for a view that maps a point to its image position
/// and its nearness to the viewer (m): in painter's order (farthest first), shaded from deep
/// blue (far) to light sand (near), so the drape's shape reads at a glance.
pub(super) fn shaded_triangles(
    topology: &ClothTopology,
    positions: &[DVec3],
    view: impl Fn(DVec3) -> ((f64, f64), f64),
) -> Vec<Polygon<(f64, f64)>> {
    let nearness: Vec<f64> = positions.iter().map(|p| view(*p).1).collect();
    let (lo, hi) = nearness
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &d| {
            (a.min(d), b.max(d))
        });
    let span = (hi - lo).max(1e-9);
    let mut tris: Vec<(f64, [u32; 3])> = topology
        .triangles
        .iter()
        .map(|t| (t.iter().map(|&i| nearness[i as usize]).sum::<f64>() / 3.0, *t))
        .collect();
    tris.sort_by(|a, b| a.0.total_cmp(&b.0));
    tris.iter()
        .map(|(d, t)| {
            let s = ((d - lo) / span).clamp(0.0, 1.0);
            let colour = RGBColor(
                (40.0 + 200.0 * s) as u8,
                (70.0 + 160.0 * s) as u8,
                (150.0 + 50.0 * s) as u8,
            );
            let pts: Vec<(f64, f64)> = t.iter().map(|&i| view(positions[i as usize]).0).collect();
            Polygon::new(pts, colour.filled())
        })
        .collect()
}
