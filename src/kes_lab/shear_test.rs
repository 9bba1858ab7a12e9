//! The virtual KES-FB1 shear test: a square strip sheared as a trellis to angle φ, swept
//! 0 → +8° → −8° → +8° (see [`super::kes_cycle`]), reading the shear force per unit length F(φ).
//!
//! Warp threads stay along x and weft threads turn by φ, all links keeping their length σ, so
//! only trellising (and its friction) does work. KES holds the sample under 10 gf/cm of tension
//! across the shear; in this model thread tension does no work on a trellis of inextensible
//! threads, so it does not enter the reading. Every trellis corner stands for σ²/4 of cloth and
//! its energy grows as F·dγ with γ = sin φ, so F = Q/(n·σ²/4·cos φ) for n corners.

use glam::DVec3;

use super::strip::{Reading, Strip, kes_cycle};
use crate::material::Fabric;

/// Largest shear angle of the sweep (rad): 8°.
pub const MAX_SHEAR_DEG: f64 = 8.0;

/// Angle step of the sweep (degrees).
pub const SHEAR_STEP_DEG: f64 = 0.01;

/// Crossings per side of the sheared square.
const SIDE: usize = 4;

fn sheared_positions(phi: f64, spacing: f64) -> Vec<DVec3> {
    let weft = DVec3::new(phi.sin(), phi.cos(), 0.0);
    let mut positions = Vec::with_capacity(SIDE * SIDE);
    for i in 0..SIDE {
        for j in 0..SIDE {
            positions.push(spacing * (i as f64 * DVec3::X + j as f64 * weft));
        }
    }
    positions
}

/// A strip for the shear test.
pub fn shear_strip(fabric: &Fabric, spacing: f64, hysteresis: bool) -> Strip {
    Strip::new(fabric, SIDE, SIDE, spacing, hysteresis)
}

/// Sweeps `strip` (from [`shear_strip`]) along `path` (shear angles, rad) and reads F(φ) (N/m).
pub fn sweep_shear(strip: &mut Strip, spacing: f64, path: &[f64]) -> Vec<Reading> {
    let topo = strip.topology();
    let corners = 4 * topo.full_crossings.len() + topo.corner_links.len();
    let area = corners as f64 * spacing * spacing / 4.0;
    strip.sweep(
        path,
        |phi| sheared_positions(phi, spacing),
        |phi| area * phi.cos(),
    )
}

/// The full KES-FB1 shear cycle, as three legs (first loading, falling, rising).
pub fn shear_cycle(fabric: &Fabric, spacing: f64, hysteresis: bool) -> [Vec<Reading>; 3] {
    let mut strip = shear_strip(fabric, spacing, hysteresis);
    let (max, step) = (MAX_SHEAR_DEG.to_radians(), SHEAR_STEP_DEG.to_radians());
    kes_cycle(max, step).map(|leg| sweep_shear(&mut strip, spacing, &leg))
}
