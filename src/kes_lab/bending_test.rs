//! The virtual KES-FB2 pure-bending test: a strip bent to uniform curvature K, swept
//! 0 → +2.5 → −2.5 → +2.5 cm⁻¹ (see [`super::kes_cycle`]), reading the moment per unit width M(K).
//!
//! Every thread along the bent direction is laid on a regular polygon whose three-point curvature
//! is K (the curvature the bending springs see, `forces::bending`); threads across it stay
//! straight, so trellis corners stay at right angles and only bending (and its friction) does
//! work. M = Q/(n·σ²), with Q the generalised force and n·σ² the area the n bending springs of
//! that direction stand for.

use std::f64::consts::{FRAC_PI_4, PI};

use glam::DVec3;

use super::strip::{Reading, Strip, kes_cycle};
use crate::forces::bending::curvature_of_angle;
use crate::material::{Fabric, Thread};

/// Largest curvature of the sweep (m⁻¹): 2.5 cm⁻¹.
pub const MAX_CURVATURE: f64 = 250.0;

/// Curvature step of the sweep (m⁻¹): 0.01 cm⁻¹.
pub const CURVATURE_STEP: f64 = 1.0;

/// Crossings along the bent threads and across them.
const ALONG: usize = 6;
const ACROSS: usize = 2;

/// The angle θ (rad) between the two segments at a crossing for curvature `k` ≥ 0 (m⁻¹).
fn angle_of_curvature(k: f64, spacing: f64) -> f64 {
    let circle_limit = 2.0 / spacing * (FRAC_PI_4 / 2.0).cos();
    if k <= circle_limit {
        PI - 2.0 * (spacing * k / 2.0).min(1.0).asin()
    } else {
        // The fold extension is decreasing in θ on (0, π/4]: bisect.
        let (mut lo, mut hi) = (1e-6, FRAC_PI_4);
        for _ in 0..100 {
            let mid = 0.5 * (lo + hi);
            if curvature_of_angle(mid, spacing) > k {
                lo = mid;
            } else {
                hi = mid;
            }
        }
        0.5 * (lo + hi)
    }
}

/// A strip bent along `thread` to signed curvature `k` (m⁻¹); node order as the strip's grid.
fn bent_positions(thread: Thread, k: f64, spacing: f64) -> Vec<DVec3> {
    let turn = (PI - angle_of_curvature(k.abs(), spacing)).copysign(k);
    let mut thread_nodes = Vec::with_capacity(ALONG);
    let mut p = DVec3::ZERO;
    let mut heading = -turn * (ALONG as f64 - 2.0) / 2.0;
    for _ in 0..ALONG {
        thread_nodes.push(p);
        p += spacing * DVec3::new(heading.cos(), 0.0, heading.sin());
        heading += turn;
    }
    let (nu, nv) = grid(thread);
    let mut positions = Vec::with_capacity(nu * nv);
    for i in 0..nu {
        for j in 0..nv {
            let (along, across) = match thread {
                Thread::Warp => (i, j),
                Thread::Weft => (j, i),
            };
            positions.push(thread_nodes[along] + DVec3::Y * (across as f64 * spacing));
        }
    }
    positions
}

fn grid(thread: Thread) -> (usize, usize) {
    match thread {
        Thread::Warp => (ALONG, ACROSS),
        Thread::Weft => (ACROSS, ALONG),
    }
}

/// A strip for the bending test along `thread`.
pub fn bending_strip(fabric: &Fabric, thread: Thread, spacing: f64, hysteresis: bool) -> Strip {
    let (nu, nv) = grid(thread);
    Strip::new(fabric, nu, nv, spacing, hysteresis)
}

/// Sweeps `strip` (from [`bending_strip`]) along `path` (curvatures, m⁻¹) and reads M(K)
/// (N·m/m).
pub fn sweep_bending(strip: &mut Strip, thread: Thread, spacing: f64, path: &[f64]) -> Vec<Reading> {
    let topo = strip.topology();
    let springs = match thread {
        Thread::Warp => topo.warp_bend_count,
        Thread::Weft => topo.bend_links.len() - topo.warp_bend_count,
    };
    let area = springs as f64 * spacing * spacing;
    strip.sweep(path, |k| bent_positions(thread, k, spacing), |_| area)
}

/// The full KES-FB2 cycle along `thread`, as three legs (first loading, falling, rising).
pub fn bending_cycle(fabric: &Fabric, thread: Thread, spacing: f64, hysteresis: bool) -> [Vec<Reading>; 3] {
    let mut strip = bending_strip(fabric, thread, spacing, hysteresis);
    kes_cycle(MAX_CURVATURE, CURVATURE_STEP).map(|leg| sweep_bending(&mut strip, thread, spacing, &leg))
}
