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
    /// For each node resting on a fixed surface, that surface's unit normal (towards the node);
    /// zero for a free node. Set before each [`Self::solve`] (e.g. by
    /// [`crate::bodies::ClothBodies::read_supports`]).
    pub supports: Vec<DVec3>,
    /// The right-hand side before the support filter.
    rhs_free: Vec<DVec3>,
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
            rhs_free: vec![DVec3::ZERO; n],
            product: ForceBuffer::new(&topology),
            stats: ImplicitStats::default(),
            topology,
        }
    }

    /// Replaces `forces` (N: every generator's force at the current state, summed per node) by
    /// M·Δv/h, the force that [`crate::bodies::ClothBodies::write_forces`] turns back into the
    /// kick Δv (m/s), our forces' backward-Euler velocity change over the step `h` (s).
    /// `generators` are the cloth's effects (`None` for an effect it does not carry, so callers
    /// need not allocate a list per step).
    pub fn solve(
        &mut self,
        generators: &[Option<&dyn ForceGenerator>],
        geometry: &ClothGeometry,
        velocities: &[DVec3],
        forces: &mut [DVec3],
        h: f64,
    ) -> CgReport {
        let (topo, m) = (&*self.topology, self.node_mass);
        let (pert, product) = (&mut self.perturbation, &mut self.product);
        // b = h·F − h²·H·v.
        pert.set(topo, velocities);
        product.clear();
        for g in generators.iter().flatten() {
            g.add_stiffness_product(geometry, pert, h * h, true, product);
        }
        let hv = product.resolve(topo);
        for ((b, f), hv) in self.rhs_free.iter_mut().zip(&*forces).zip(hv) {
            *b = h * *f - *hv;
        }
        // Supported nodes: our Δv has no component along the support normal (Baraff & Witkin's
        // filtered CG), so the surface, not the rest of the cloth, carries what presses on them.
        let filter = |n: DVec3, v: DVec3| v - n.dot(v) * n;
        // A support that would have to pull the node onto the surface (the force on it, b,
        // points away from the surface) is released for this step.
        for (n, free) in self.supports.iter_mut().zip(&self.rhs_free) {
            if n.dot(*free) > 0.0 {
                *n = DVec3::ZERO;
            }
        }
        for ((b, free), n) in self.rhs.iter_mut().zip(&self.rhs_free).zip(&self.supports) {
            *b = filter(*n, *free);
        }
        for (dv, n) in self.dv.iter_mut().zip(&self.supports) {
            *dv = filter(*n, *dv);
        }
        let supports = &self.supports;
        let apply = |x: &[DVec3], out: &mut [DVec3]| {
            apply_system(generators, geometry, (pert, product), (m, h), x, out);
            for (o, n) in out.iter_mut().zip(supports) {
                *o = filter(*n, *o);
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
        for (f, dv) in forces.iter_mut().zip(&self.dv) {
            *f = (m / h) * *dv;
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
