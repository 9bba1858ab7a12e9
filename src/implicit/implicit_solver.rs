//! One backward-Euler velocity solve per step, matrix-free.

use std::sync::Arc;

use glam::DVec3;

use super::conjugate_gradient::{CgReport, conjugate_gradient};
use crate::forces::{ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, Perturbation};

/// Conjugate-gradient settings of the implicit solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImplicitSettings {
    /// Most operator products per step (default 200). A solve stopped early still returns a
    /// velocity change that reduces the residual; [`ImplicitStats`] counts how often it happens.
    pub max_iterations: usize,
    /// Relative residual |b − A·Δv|/|b| at which a solve stops (dimensionless; default 1e-3).
    pub tolerance: f64,
}

impl Default for ImplicitSettings {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            tolerance: 1e-3,
        }
    }
}

/// Totals over a run, for `metrics.json`.
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct ImplicitStats {
    /// Solves done (one per step).
    pub solves: u64,
    /// Operator products over all solves.
    pub iterations: u64,
    /// Solves that stopped at `max_iterations` above the tolerance.
    pub unconverged: u64,
    /// The last solve.
    pub last: CgReport,
}

/// The implicit solve of one cloth: settings, node mass, warm start and scratch buffers.
#[derive(Clone, Debug)]
pub struct ImplicitSolver {
    topology: Arc<ClothTopology>,
    /// Solver settings.
    pub settings: ImplicitSettings,
    /// Node mass (kg).
    node_mass: f64,
    /// Last step's Δv (m/s): the warm start.
    dv: Vec<DVec3>,
    rhs: Vec<DVec3>,
    scratch: [Vec<DVec3>; 4],
    inverse_diagonal: Vec<f64>,
    perturbation: Perturbation,
    product: ForceBuffer,
    /// For each node that a fixed surface pushed in Rapier's last step, that surface's unit
    /// normal (towards the node); zero for a free node. Set before each [`Self::solve`] (e.g. by
    /// [`crate::bodies::ClothBodies::read_supports`]).
    pub supports: Vec<DVec3>,
    /// Nodes pinned to a body that cannot move: their Δv is held at zero, as the pin will.
    held: Vec<bool>,
    /// Totals so far.
    pub stats: ImplicitStats,
}

impl ImplicitSolver {
    /// The last step's Δv (m/s), the next solve's warm start (for checkpoints).
    pub fn warm_start(&self) -> &[DVec3] {
        &self.dv
    }

    /// Restores a warm start saved by [`Self::warm_start`]; `false` (and nothing changed) if it
    /// does not fit this cloth.
    pub fn restore_warm_start(&mut self, dv: &[DVec3]) -> bool {
        if dv.len() != self.dv.len() {
            return false;
        }
        self.dv.copy_from_slice(dv);
        true
    }

    /// A solver for a cloth of `topology` with nodes of `node_mass` (kg).
    pub fn new(topology: Arc<ClothTopology>, node_mass: f64, settings: ImplicitSettings) -> Self {
        let n = topology.particle_count;
        Self {
            settings,
            node_mass,
            dv: vec![DVec3::ZERO; n],
            rhs: vec![DVec3::ZERO; n],
            scratch: std::array::from_fn(|_| vec![DVec3::ZERO; n]),
            inverse_diagonal: vec![1.0 / node_mass; n],
            perturbation: Perturbation::new(&topology),
            supports: vec![DVec3::ZERO; n],
            held: vec![false; n],
            product: ForceBuffer::new(&topology),
            stats: ImplicitStats::default(),
            topology,
        }
    }

    /// Holds `node` in place in every solve: for a node pinned to a fixed or kinematic body,
    /// whose joint will undo any velocity the solve gives it (ignored if out of range).
    pub fn hold(&mut self, node: usize) {
        if let Some(h) = self.held.get_mut(node) {
            *h = true;
        }
    }

    /// Replaces `forces` (N: every generator's force at the current state, summed per node) by
    /// M·Δv/h − M·g, the force that [`crate::bodies::ClothBodies::write_forces`] turns back into
    /// the kick Δv − h·g (m/s): Δv is the backward-Euler velocity change of our forces and
    /// gravity over the step `h` (s), and Rapier adds the h·g back. `gravity` (m/s²) is the
    /// nodes' gravity in Rapier ([`crate::bodies::ClothBodies::gravity`]). `generators` are the
    /// cloth's effects (`None` for an effect it does not carry, so callers need not allocate a
    /// list per step).
    pub fn solve(
        &mut self,
        generators: &[Option<&dyn ForceGenerator>],
        geometry: &ClothGeometry,
        velocities: &[DVec3],
        forces: &mut [DVec3],
        (h, gravity): (f64, DVec3),
    ) -> CgReport {
        let (topo, m) = (&*self.topology, self.node_mass);
        let (pert, product) = (&mut self.perturbation, &mut self.product);
        // b = h·F − h²·H·v (h·M·g is added below).
        pert.set(topo, velocities);
        product.clear();
        for g in generators.iter().flatten() {
            g.add_stiffness_product(geometry, pert, h * h, true, product);
        }
        let hv = product.resolve(topo);
        for ((b, f), hv) in self.rhs.iter_mut().zip(&*forces).zip(hv) {
            *b = h * *f - *hv;
        }
        // Supported nodes: our Δv has no component along the support normal (Baraff & Witkin's
        // filtered CG), so the surface, not the rest of the cloth, carries what presses on them.
        // A held (pinned) node keeps no component at all.
        let filter = |n: DVec3, held: bool, v: DVec3| {
            if held { DVec3::ZERO } else { v - n.dot(v) * n }
        };
        // Gravity enters the solve too, and leaves the kick again because Rapier applies it.
        // Our stiff response then balances the cloth's weight where the cloth's constraints do:
        // solved without it, a cloth at rest ends where F = −(M + h²H)·g, as if it weighed
        // (M + h²H)/M times more in its stiff modes (docs/model.md §12).
        let weight = m * gravity;
        for ((b, n), held) in self.rhs.iter_mut().zip(&self.supports).zip(&self.held) {
            *b = filter(*n, *held, *b + h * weight);
        }
        for ((dv, n), held) in self.dv.iter_mut().zip(&self.supports).zip(&self.held) {
            *dv = filter(*n, *held, *dv);
        }
        let (supports, held) = (&self.supports, &self.held);
        let apply = |x: &[DVec3], out: &mut [DVec3]| {
            apply_system(generators, geometry, (pert, product), (m, h), x, out);
            for ((o, n), held) in out.iter_mut().zip(supports).zip(held) {
                *o = filter(*n, *held, *o);
            }
        };
        let [r, z, p, ap] = &mut self.scratch;
        let report = conjugate_gradient(
            apply,
            &self.rhs,
            &mut self.dv,
            &self.inverse_diagonal,
            (r, z, p, ap),
            self.settings.tolerance,
            self.settings.max_iterations,
        );
        for (((f, dv), n), held) in forces
            .iter_mut()
            .zip(&self.dv)
            .zip(&self.supports)
            .zip(&self.held)
        {
            *f = (m / h) * *dv - filter(*n, *held, weight);
        }
        self.stats.solves += 1;
        self.stats.iterations += report.iterations as u64;
        if report.relative_residual > self.settings.tolerance {
            self.stats.unconverged += 1;
        }
        self.stats.last = report;
        report
    }
}

/// out = (M + h·C + h²·H)·x for nodes of mass `m` (kg) and step `h` (s).
fn apply_system(
    generators: &[Option<&dyn ForceGenerator>],
    geometry: &ClothGeometry,
    (pert, product): (&mut Perturbation, &mut ForceBuffer),
    (m, h): (f64, f64),
    x: &[DVec3],
    out: &mut [DVec3],
) {
    let topo = geometry.topology();
    pert.set(topo, x);
    product.clear();
    for g in generators.iter().flatten() {
        g.add_stiffness_product(geometry, pert, h * h, true, product);
        g.add_damping_product(pert, h, product);
    }
    for ((o, ax), x) in out.iter_mut().zip(product.resolve(topo)).zip(x) {
        *o = m * *x + *ax;
    }
}
