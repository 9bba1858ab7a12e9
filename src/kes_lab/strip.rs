//! A small strip of cloth driven through prescribed shapes, with the generalised force the
//! instrument must apply to hold each shape, found by virtual work.
//!
//! The strip carries the same force generators as a scene's cloth (bending, trellising and, when
//! asked, hysteresis). At each point x of a sweep the nodes are placed at `pose(x)`, the
//! hysteresis state is advanced to that shape (as one simulation step would), and the generalised
//! force is Q(x) = −Σᵢ Fᵢ·∂xᵢ/∂x: the work the instrument does per unit of x against the cloth's
//! internal forces Fᵢ. Dividing by the strip's energy weight (its area, and cos φ for shear) gives
//! the moment per width M(K) or the shear force per length F(φ) a KES instrument reads.

use std::sync::Arc;

use glam::DVec3;

use crate::forces::{
    Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, Hysteresis, Trellising,
};
use crate::material::Fabric;

/// Half-width of the central difference for ∂x/∂x_drive (drive units: m⁻¹ or rad).
const TANGENT_STEP: f64 = 1e-6;

/// A strip of cloth and its generators.
pub struct Strip {
    topology: Arc<ClothTopology>,
    generators: Vec<Box<dyn ForceGenerator>>,
    hysteresis: Option<Hysteresis>,
    geometry: ClothGeometry,
    forces: ForceBuffer,
}

/// One point of a sweep: the drive value x and the instrument's reading y (SI).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Reading {
    /// The drive (K in m⁻¹, or φ in rad).
    pub x: f64,
    /// The reading (M in N·m/m, or F in N/m).
    pub y: f64,
}

impl Strip {
    /// An `nu × nv` strip (nu crossings along the warp) of `fabric` at spacing σ (m).
    pub fn new(fabric: &Fabric, nu: usize, nv: usize, spacing: f64, hysteresis: bool) -> Self {
        let topology = Arc::new(ClothTopology::rectangle(nu, nv, spacing));
        let generators: Vec<Box<dyn ForceGenerator>> = vec![
            Box::new(Bending::new(topology.clone(), fabric)),
            Box::new(Trellising::new(topology.clone(), fabric)),
        ];
        Self {
            hysteresis: hysteresis.then(|| Hysteresis::new(topology.clone(), fabric, true, true)),
            geometry: ClothGeometry::new(topology.clone()),
            forces: ForceBuffer::new(&topology),
            generators,
            topology,
        }
    }

    /// The strip's grid.
    pub fn topology(&self) -> &ClothTopology {
        &self.topology
    }

    /// Energy the hysteresis elements have dissipated so far (J); 0 without hysteresis.
    pub fn dissipated(&self) -> f64 {
        self.hysteresis.as_ref().map_or(0.0, Hysteresis::dissipated)
    }

    /// Elastic and friction energy held in the strip at its current shape (J).
    pub fn stored_energy(&self) -> f64 {
        let elastic: f64 = self.generators.iter().map(|g| g.energy(&self.geometry)).sum();
        elastic + self.hysteresis.as_ref().map_or(0.0, |h| h.energy(&self.geometry))
    }

    /// Drives the strip through `path` (drive values in order) and returns, at each, the
    /// generalised force Q (J per drive unit) divided by `weight(x)`.
    pub fn sweep(
        &mut self,
        path: &[f64],
        pose: impl Fn(f64) -> Vec<DVec3>,
        weight: impl Fn(f64) -> f64,
    ) -> Vec<Reading> {
        let none = vec![DVec3::ZERO; self.topology.particle_count];
        path.iter()
            .map(|&x| {
                self.geometry.update(&pose(x));
                if let Some(h) = &mut self.hysteresis {
                    h.advance_state(&self.geometry);
                }
                self.forces.clear();
                for g in &self.generators {
                    g.add_forces(&self.geometry, &none, &mut self.forces);
                }
                if let Some(h) = &self.hysteresis {
                    h.add_forces(&self.geometry, &none, &mut self.forces);
                }
                let forces = self.forces.resolve(&self.topology);
                let (ahead, behind) = (pose(x + TANGENT_STEP), pose(x - TANGENT_STEP));
                let work: f64 = forces
                    .iter()
                    .zip(ahead.iter().zip(&behind))
                    .map(|(f, (a, b))| -f.dot((*a - *b) / (2.0 * TANGENT_STEP)))
                    .sum();
                Reading {
                    x,
                    y: work / weight(x),
                }
            })
            .collect()
    }
}

/// The sweep 0 → +max → −max → +max in steps of about `step`, as three monotone legs: a first
/// loading from rest, then one closed loop. The instruments sweep back to 0 only; the loop is
/// closed here so that both branches are read in steady state (a first loading from rest has no
/// friction history, and a real sample has one) and so that a loop area can be taken.
pub fn kes_cycle(max: f64, step: f64) -> [Vec<f64>; 3] {
    let n = (max / step).ceil() as usize;
    let leg = |from: f64, to: f64, count: usize| -> Vec<f64> {
        (0..=count)
            .map(|i| from + (to - from) * i as f64 / count as f64)
            .collect()
    };
    [leg(0.0, max, n), leg(max, -max, 2 * n), leg(-max, max, 2 * n)]
}
