//! One backward-Euler velocity solve per step, on the matrix assembled for that step.

use std::sync::Arc;

use glam::{DMat3, DVec3};

use super::conjugate_gradient::{CgReport, conjugate_gradient};
use crate::forces::{
    ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, Perturbation, outer,
};

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
    /// h²·H + h·C of the current step, assembled once per solve.
    matrix: LinkMatrix,
    /// Inverse of each node's 3×3 diagonal block of the filtered system (block Jacobi).
    preconditioner: Vec<DMat3>,
    perturbation: Perturbation,
    product: ForceBuffer,
    /// For each node that a fixed surface pushed in Rapier's last step, that surface's unit
    /// normal (towards the node); zero for a free node. Set before each [`Self::solve`] (e.g. by
    /// [`crate::bodies::ClothBodies::read_supports`]).
    pub supports: Vec<DVec3>,
    /// For each node within [`crate::bodies::TOUCH_DISTANCE`] of a fixed surface, that
    /// surface's unit normal (zero otherwise). Set with [`Self::supports`].
    pub touching: Vec<DVec3>,
    /// Whether the last solve's surface pushed each supported node (Baraff & Witkin's release
    /// rule: a support is kept, while the node touches, until the surface would have to pull).
    pressed: Vec<bool>,
    /// b + h·M·g before the filter, for the surfaces' impulses A·Δv − b.
    unfiltered_rhs: Vec<DVec3>,
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
        copy_if_same_length(&mut self.dv, dv)
    }

    /// Which nodes the last solve's surface pushed (for checkpoints).
    pub fn pressed(&self) -> &[bool] {
        &self.pressed
    }

    /// Restores what [`Self::pressed`] returned; `false` (and nothing changed) if it does not fit
    /// this cloth.
    pub fn restore_pressed(&mut self, pressed: &[bool]) -> bool {
        copy_if_same_length(&mut self.pressed, pressed)
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
            matrix: LinkMatrix::new(&topology),
            preconditioner: vec![DMat3::ZERO; n],
            perturbation: Perturbation::new(&topology),
            supports: vec![DVec3::ZERO; n],
            touching: vec![DVec3::ZERO; n],
            pressed: vec![false; n],
            unfiltered_rhs: vec![DVec3::ZERO; n],
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
        // A node Rapier's contact did not push this step keeps its support while it still
        // touches the surface and the surface pushed it in the last solve: otherwise a node that
        // the filter keeps off the surface is released, pulled back onto it by the cloth, and
        // held again, every other step.
        for ((support, touch), pressed) in self.supports.iter_mut().zip(&self.touching).zip(&self.pressed) {
            if *support == DVec3::ZERO && *pressed {
                *support = *touch;
            }
        }
        let (topo, m) = (&*self.topology, self.node_mass);
        let (pert, product, matrix) = (&mut self.perturbation, &mut self.product, &mut self.matrix);
        // Assemble h²·H, and with it b = h·F − h²·H·v (h·M·g is added below); then add h·C.
        matrix.clear();
        for g in generators.iter().flatten() {
            g.add_stiffness_blocks(geometry, h * h, matrix);
        }
        pert.set(topo, velocities);
        let hv = matrix.product(topo, pert, product);
        for ((b, f), hv) in self.rhs.iter_mut().zip(&*forces).zip(hv) {
            *b = h * *f - *hv;
        }
        for g in generators.iter().flatten() {
            g.add_damping_blocks(h, matrix);
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
        for (u, b) in self.unfiltered_rhs.iter_mut().zip(&self.rhs) {
            *u = *b + h * weight;
        }
        for ((b, n), held) in self.rhs.iter_mut().zip(&self.supports).zip(&self.held) {
            *b = filter(*n, *held, *b + h * weight);
        }
        for ((dv, n), held) in self.dv.iter_mut().zip(&self.supports).zip(&self.held) {
            *dv = filter(*n, *held, *dv);
        }
        // Block Jacobi: each node's own 3×3 block of the filtered system P·A·P, inverted on the
        // plane the filter leaves free (the normal gets m, which the filter then removes again).
        self.preconditioner.fill(DMat3::from_diagonal(DVec3::splat(m)));
        matrix.add_particle_diagonal(topo, &mut self.preconditioner);
        for ((block, n), held) in self.preconditioner.iter_mut().zip(&self.supports).zip(&self.held) {
            *block = if *held {
                DMat3::ZERO
            } else if *n == DVec3::ZERO {
                block.inverse()
            } else {
                let plane = DMat3::IDENTITY - outer(*n, *n);
                let free = plane * *block * plane + m * outer(*n, *n);
                plane * free.inverse() * plane
            };
        }
        let preconditioner = &self.preconditioner;
        let (supports, held) = (&self.supports, &self.held);
        let matrix = &*matrix;
        let apply = |x: &[DVec3], out: &mut [DVec3]| {
            pert.set(topo, x);
            let ax = matrix.product(topo, pert, product);
            for ((((o, ax), x), n), held) in out.iter_mut().zip(ax).zip(x).zip(supports).zip(held) {
                *o = filter(*n, *held, m * *x + *ax);
            }
        };
        let precondition = |r: &[DVec3], z: &mut [DVec3]| {
            for ((z, r), block) in z.iter_mut().zip(r).zip(preconditioner) {
                *z = *block * *r;
            }
        };
        let [r, z, p, ap] = &mut self.scratch;
        let report = conjugate_gradient(
            apply,
            precondition,
            &self.rhs,
            &mut self.dv,
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
        // Each surface's impulse on its node, the normal part of A·Δv − b: a push keeps the
        // support for the next step, a pull releases it. (No product when nothing is supported.)
        if self.supports.iter().any(|n| *n != DVec3::ZERO) {
            pert.set(topo, &self.dv);
            let ax = matrix.product(topo, pert, product);
            for (i, pressed) in self.pressed.iter_mut().enumerate() {
                let n = self.supports[i];
                let impulse = m * self.dv[i] + ax[i] - self.unfiltered_rhs[i];
                *pressed = n != DVec3::ZERO && impulse.dot(n) >= 0.0;
            }
        } else {
            self.pressed.fill(false);
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

/// Copies `from` into `to` if they have the same length (a checkpoint of this cloth).
fn copy_if_same_length<T: Copy>(to: &mut [T], from: &[T]) -> bool {
    let fits = to.len() == from.len();
    if fits {
        to.copy_from_slice(from);
    }
    fits
}
