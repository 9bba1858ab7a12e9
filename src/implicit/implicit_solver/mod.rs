//! One linearly implicit velocity solve per step (backward Euler or BDF2), on the matrix
//! assembled for that step.

mod blocks;
mod coupling;
mod factors;
mod friction_release;
mod friction_start;
mod kick;
mod prescribed;
mod saved_state;
mod vectors;

use std::sync::Arc;

use glam::{DMat3, DVec3};

use super::carriers::Carriers;
use super::conjugate_gradient::{CgReport, Stop, conjugate_gradient};
use super::scheme::{Bdf2History, Scheme};
use super::solver_settings::{FrictionRelease, ImplicitSettings, ImplicitStats, LINK_TOLERANCE};
use super::supports::Supports;
use crate::forces::{
    ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, LinkMatrix, ParticleMatrix, Perturbation,
};
use coupling::Coupling;
use factors::{Factors, PassSystem};
use vectors::{filter, tangential, total_mass};

/// The implicit solve of one cloth: settings, node mass, warm start and scratch buffers.
#[derive(Clone, Debug)]
pub struct ImplicitSolver {
    topology: Arc<ClothTopology>,
    /// Solver settings.
    pub settings: ImplicitSettings,
    /// Mass of each node (kg), in particle order.
    masses: Vec<f64>,
    /// Last step's Δv (m/s): the warm start.
    dv: Vec<DVec3>,
    rhs: Vec<DVec3>,
    scratch: [Vec<DVec3>; 4],
    /// h²·H + h·C of the current step, assembled once per solve.
    matrix: LinkMatrix,
    /// The same matrix with h·C, in particle rows: what every product of the solve multiplies by.
    rows: ParticleMatrix,
    /// A product's result (scratch).
    ax: Vec<DVec3>,
    perturbation: Perturbation,
    product: ForceBuffer,
    /// The fixed surfaces under the nodes in Rapier's last step. Set before each
    /// [`Self::solve`] (e.g. by [`crate::bodies::ClothBodies::read_supports`]).
    pub supports: Supports,
    /// The host's dynamic bodies solved with the cloth ([`Carriers`]), and their velocity
    /// changes after a solve. Set before each [`Self::solve`] (e.g. by
    /// [`crate::bodies::ClothBodies::read_carriers`]); empty for a cloth alone.
    pub carriers: Carriers,
    /// Each node's velocity with its body's motion spread in (scratch of the coupled products).
    expanded: Vec<DVec3>,
    /// Whether the solve applies the supports' Coulomb friction (see [`Self::apply_friction`];
    /// default off).
    friction: bool,
    /// This step's nodes whose whole Δv is prescribed: pinned (held at zero) or stuck by
    /// static friction (stopped).
    fixed: Vec<bool>,
    /// Each node's 3×3 diagonal block of M + h·C + h²·H, before the filter.
    diagonal: Vec<DMat3>,
    /// This step's prescribed part of Δv (m/s), with friction in the solve: a stuck node's
    /// whole velocity stopped, a sliding one's motion along its support normal; zero elsewhere.
    prescribed: Vec<DVec3>,
    /// This step's kinetic friction of each node that slides, as a drag coefficient c (kg: the
    /// surface's tangential impulse is −c times the node's tangential velocity at the step's
    /// end; zero elsewhere).
    sliding_drag: Vec<f64>,
    /// Each sliding node's kinetic friction impulse μ·λ_n (N·s) from its last solve, zero for
    /// a node held or unsupported: a node that slid keeps sliding into the next step, with
    /// this impulse as its drag, until it has all but stopped.
    sliding_impulse: Vec<f64>,
    /// The system step h' (s) the sliding impulses were taken over (0 before any): a step of
    /// another length scales them to its own, as the friction force they stand for is the same.
    sliding_step_s: f64,
    /// Per node: a hold that left its friction cone in the last solve and, with
    /// [`FrictionRelease::NextStep`], slides from this step on.
    release_next: Vec<bool>,
    /// Whether the last solve's surface pushed each supported node (Baraff & Witkin's release
    /// rule: a support is kept, while the node touches, until the surface would have to pull).
    pressed: Vec<bool>,
    /// b + h·M·g before the filter, for the surfaces' impulses A·Δv − b.
    unfiltered_rhs: Vec<DVec3>,
    /// Nodes pinned to a body that is not dynamic (fixed or kinematic): their Δv is
    /// prescribed, as the pin will, by [`Self::pin_velocities`].
    held: Vec<bool>,
    /// For each node pinned to a moving (kinematic) body, the velocity (m/s) its pin will have
    /// over the coming step, which the solve gives the node; `None` elsewhere, where a held
    /// node's Δv is zero. Set before each [`Self::solve`] (e.g. by
    /// [`crate::bodies::ClothBodies::read_pin_velocities`]).
    pub pin_velocities: Vec<Option<DVec3>>,
    /// The preconditioner and its factors.
    factors: Factors,
    /// The nodes whose hold gave way in this step's last pass (their filter and diagonal block
    /// changed, the rest of the system did not).
    released: Vec<u32>,
    /// BDF2's history (`None` before its first step, or with backward Euler).
    bdf2: Option<Bdf2History>,
    /// The scheme's velocity of each node this step (m/s; with BDF2, Rapier's plus the lag).
    state_velocities: Vec<DVec3>,
    /// Totals so far.
    pub stats: ImplicitStats,
}

impl ImplicitSolver {
    /// A solver for a cloth of `topology` with nodes of `node_mass` (kg).
    pub fn new(topology: Arc<ClothTopology>, node_mass: f64, settings: ImplicitSettings) -> Self {
        let masses = vec![node_mass; topology.particle_count];
        Self::with_masses(topology, masses, settings)
    }

    /// A solver for a cloth of `topology` whose nodes have `masses` (kg, in particle order).
    pub fn with_masses(topology: Arc<ClothTopology>, masses: Vec<f64>, settings: ImplicitSettings) -> Self {
        let n = topology.particle_count;
        let matrix = LinkMatrix::new(&topology);
        Self {
            settings,
            masses,
            dv: vec![DVec3::ZERO; n],
            rhs: vec![DVec3::ZERO; n],
            scratch: std::array::from_fn(|_| vec![DVec3::ZERO; n]),
            rows: ParticleMatrix::new(&topology, &matrix),
            matrix,
            ax: vec![DVec3::ZERO; n],
            perturbation: Perturbation::new(&topology),
            supports: Supports::new(n),
            carriers: Carriers::new(n),
            expanded: vec![DVec3::ZERO; n],
            friction: false,
            fixed: vec![false; n],
            diagonal: vec![DMat3::ZERO; n],
            prescribed: vec![DVec3::ZERO; n],
            sliding_drag: vec![0.0; n],
            sliding_impulse: vec![0.0; n],
            sliding_step_s: 0.0,
            release_next: vec![false; n],
            pressed: vec![false; n],
            unfiltered_rhs: vec![DVec3::ZERO; n],
            held: vec![false; n],
            pin_velocities: vec![None; n],
            factors: Factors::new(settings.preconditioner.for_nodes(n), n),
            released: Vec::new(),
            bdf2: None,
            state_velocities: vec![DVec3::ZERO; n],
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

    /// Which nodes [`Self::hold`] holds in place, in particle order.
    pub fn held(&self) -> &[bool] {
        &self.held
    }

    /// Applies the supports' Coulomb friction inside the solve. Each supported node starts the
    /// step held (its tangential velocity stopped); a hold whose tangential impulse exceeds μ
    /// times its normal impulse is released, and the node slides against a kinetic friction
    /// drag, into the following steps until it has all but stopped. Without it the solve lets
    /// supported nodes slide freely in the surface's plane and leaves friction to Rapier's
    /// contact, which sees only the node's weight pressing on the
    /// surface, not the cloth's pull around a rim. Only consistent when every force on the
    /// cloth is in the solve: Rapier's rope joints are not, and with them the holds fail
    /// (`docs/model.md` §12).
    pub fn apply_friction(&mut self, on: bool) {
        self.friction = on;
    }

    /// Whether the supports' friction is in the solve ([`Self::apply_friction`]).
    pub fn has_friction(&self) -> bool {
        self.friction
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
        let factorisations_before = self.factors.factorisations();
        let assembly_start = std::time::Instant::now();
        // The step the system is assembled at, and the scheme's velocities: Rapier's, or with
        // BDF2 Rapier's plus each node's lag (scheme.rs).
        let rapier_velocities = velocities;
        let mut state = std::mem::take(&mut self.state_velocities);
        let n = self.masses.len();
        let bdf2 = match self.settings.scheme {
            Scheme::Bdf2 => {
                let history = self.bdf2.get_or_insert_with(|| Bdf2History::new(n));
                history.prepare(h);
                history.velocities(rapier_velocities, &self.held, &mut state);
                // Its first step is backward Euler's: started from a history of constant
                // velocity, BDF2 would miss a third of the first step's velocity change, an
                // error of first order in h that never decays.
                history.started.then_some(&*history)
            }
            Scheme::BackwardEuler => None,
        };
        let hs = bdf2.map_or(h, |history| history.system_step(h));
        let velocities: &[DVec3] = if bdf2.is_some() { &state } else { rapier_velocities };
        let supports = &mut self.supports;
        for ((support, touch), pressed) in supports
            .pushed
            .iter_mut()
            .zip(&supports.touching)
            .zip(&self.pressed)
        {
            if *support == DVec3::ZERO && *pressed {
                *support = *touch;
            }
        }
        let (topo, masses) = (&*self.topology, &self.masses);
        let (pert, product, matrix) = (&mut self.perturbation, &mut self.product, &mut self.matrix);
        // Assemble h²·H, and with it b = h·F − h²·H·v (h·M·g is added below); then add h·C.
        // (BDF2: h' for h, k·w for v, and its history and lag terms, scheme.rs.)
        matrix.clear();
        for g in generators.iter().flatten() {
            g.add_stiffness_blocks(geometry, hs * hs, matrix);
        }
        // Edges pressing on links between nodes: forces and stiffness, as any effect's.
        for link in &self.supports.links {
            link.add_forces(forces);
            link.add_stiffness_blocks(hs * hs, matrix);
        }
        match bdf2 {
            Some(history) => {
                let k = history.velocity_weight();
                for (a, w) in self.ax.iter_mut().zip(rapier_velocities) {
                    *a = k * *w;
                }
                pert.set(topo, &self.ax);
            }
            None => pert.set(topo, velocities),
        }
        let hv = matrix.product(topo, pert, product);
        // Gravity enters the solve too, and leaves the kick again because Rapier applies it.
        // Our stiff response then balances the cloth's weight where the cloth's constraints do:
        // solved without it, a cloth at rest ends where F = −(M + h²H)·g, as if it weighed
        // (M + h²H)/M times more in its stiff modes (docs/model.md §12).
        for (i, (((b, f), hv), m)) in self
            .unfiltered_rhs
            .iter_mut()
            .zip(&*forces)
            .zip(hv)
            .zip(masses)
            .enumerate()
        {
            *b = hs * *f - *hv + hs * (*m * gravity);
            if let Some(history) = bdf2 {
                *b += history.history(i, *m, velocities[i]);
            }
        }
        for g in generators.iter().flatten() {
            g.add_damping_blocks(hs, matrix);
        }
        // BDF2's lag: the forces were taken at Rapier's velocities, the scheme's differ by d.
        if let Some(history) = bdf2 {
            pert.set(topo, &history.lag);
            let lag = matrix.product(topo, pert, product);
            for (b, l) in self.unfiltered_rhs.iter_mut().zip(lag) {
                *b -= *l;
            }
        }
        for (d, m) in self.diagonal.iter_mut().zip(masses) {
            *d = DMat3::from_diagonal(DVec3::splat(*m));
        }
        matrix.add_particle_diagonal(topo, &mut self.diagonal);
        // The sliding nodes' friction impulses, taken over the last step's h', over this one's.
        if self.sliding_step_s > 0.0 && self.sliding_step_s != hs {
            let scale = hs / self.sliding_step_s;
            self.sliding_impulse.iter_mut().for_each(|i| *i *= scale);
        }
        self.sliding_step_s = hs;
        friction_start::start_holds(
            friction_start::Holds {
                fixed: &mut self.fixed,
                drag: &mut self.sliding_drag,
                impulse: &mut self.sliding_impulse,
                release_next: &mut self.release_next,
            },
            &self.held,
            &self.supports,
            self.friction,
            velocities,
        );
        let normals = &self.supports.pushed;
        self.rows.assemble(matrix);
        self.stats.assembly_s += assembly_start.elapsed().as_secs_f64();
        let (rows, ax) = (&self.rows, &mut self.ax);
        // The error δv = A⁻¹·r has |r|_P² ≈ rᵀ·A⁻¹·r = δvᵀ·A·δv ≥ Σ m·|δv|², so a residual below
        // √(Σm)·ε leaves a mass-weighted RMS velocity error below about ε.
        let stop = Stop {
            relative: if self.supports.links.is_empty() {
                self.settings.tolerance
            } else {
                self.settings.tolerance.min(LINK_TOLERANCE)
            },
            absolute: self.settings.velocity_tolerance * total_mass(masses).sqrt(),
            max_iterations: self.settings.max_iterations,
        };
        let mut report = CgReport::default();
        let next_step = self.settings.friction_release == FrictionRelease::NextStep;
        let passes = if next_step { 1 } else { FRICTION_PASSES };
        // A carrier's node at a pin of another body (held) is that pin's, not the carrier's.
        let (held, pinned) = (&self.held, &self.carriers.pinned);
        // The body's rows are backward Euler's over Rapier's step h, the nodes' over the
        // scheme's hs: scaled by hs/h to share the nodes' (BDF2: β, 2/3 at a constant step).
        let mut coupling = Coupling::new(&self.carriers, hs / h, |i| {
            !held[i] || pinned.get(i) == Some(&true)
        });
        let len = n + coupling.slots();
        for v in [&mut self.rhs, &mut self.dv]
            .into_iter()
            .chain(self.scratch.iter_mut())
        {
            v.resize(len, DVec3::ZERO);
        }
        let mut changes = Vec::new();
        self.released.clear();
        for pass in 0..passes {
            // Supported nodes: our Δv has no component along the support normal (Baraff &
            // Witkin's filtered CG), so the surface, not the rest of the cloth, carries what
            // presses on them. A fixed node keeps no component at all.
            let filter = |i: usize, v: DVec3| filter(normals[i], self.fixed[i], v);
            // Those parts of Δv that are prescribed, z (prescribed.rs): the solve finds the
            // rest, y = Δv − z, from P·A·y = P·(b − A·z).
            let prescription = prescribed::Prescription {
                held: &self.held,
                pin_velocities: &self.pin_velocities,
                friction: self.friction,
                normals,
                surface: &self.supports.velocity,
                fixed: &self.fixed,
            };
            let any_prescribed = prescription.write(velocities, &mut self.prescribed);
            // A sliding node's drag: −c·(v + Δv) along the surface, the −c·v part known.
            let drag = |i: usize, v: DVec3| self.sliding_drag[i] * tangential(normals[i], v);
            let surface = &self.supports.velocity;
            for (i, ((b, u), v)) in self
                .rhs
                .iter_mut()
                .zip(&self.unfiltered_rhs)
                .zip(velocities)
                .enumerate()
            {
                *b = *u - drag(i, *v - surface[i]);
            }
            if any_prescribed {
                rows.product(&self.prescribed, ax);
                for (((b, az), z), m) in self
                    .rhs
                    .iter_mut()
                    .zip(ax.iter())
                    .zip(&self.prescribed)
                    .zip(masses)
                {
                    *b -= *m * *z + *az;
                }
            }
            // The carriers' rows take what the filter leaves out of their nodes' rows.
            let (nodes_rhs, bodies_rhs) = self.rhs.split_at_mut(n);
            coupling.right_hand_side(nodes_rhs, hs, filter, bodies_rhs);
            for (i, b) in nodes_rhs.iter_mut().enumerate() {
                *b = filter(i, *b);
            }
            for (i, dv) in self.dv[..n].iter_mut().enumerate() {
                *dv = filter(i, *dv);
            }
            // The preconditioner of this pass (factors.rs).
            self.factors.project(normals, &self.fixed);
            let preconditioner_start = std::time::Instant::now();
            let active = self.factors.form(PassSystem {
                topology: topo,
                rows,
                masses,
                diagonal: &self.diagonal,
                drag: &self.sliding_drag,
                normals,
                fixed: &self.fixed,
                released: &self.released,
                pass,
            });
            coupling.factor(&self.diagonal, &self.factors.projection);
            self.stats.preconditioner_s += preconditioner_start.elapsed().as_secs_f64();
            let expanded = &mut self.expanded;
            let coupling = &coupling;
            let apply = |x: &[DVec3], out: &mut [DVec3]| {
                if coupling.slots() == 0 {
                    rows.product(x, out);
                    for (i, (o, x)) in out.iter_mut().zip(x).enumerate() {
                        *o = filter(i, masses[i] * *x + *o + drag(i, *x));
                    }
                    return;
                }
                let (x, x_bodies) = x.split_at(n);
                let (out, out_bodies) = out.split_at_mut(n);
                expanded.copy_from_slice(x);
                coupling.spread(x_bodies, filter, expanded);
                let x = &expanded[..];
                rows.product(x, out);
                for (i, (o, x)) in out.iter_mut().zip(x).enumerate() {
                    *o = masses[i] * *x + *o + drag(i, *x);
                }
                coupling.gather(out, x_bodies, filter, out_bodies);
                for (i, o) in out.iter_mut().enumerate() {
                    *o = filter(i, *o);
                }
            };
            let factors = &mut self.factors;
            let precondition = |r: &[DVec3], z: &mut [DVec3]| {
                let (r, r_bodies) = r.split_at(n);
                let (z, z_bodies) = z.split_at_mut(n);
                coupling.precondition(r_bodies, z_bodies);
                factors.apply(active, r, z, filter);
            };
            let [r, z, p, ap] = &mut self.scratch;
            let cg_start = std::time::Instant::now();
            let this_pass =
                conjugate_gradient(apply, precondition, &self.rhs, &mut self.dv, (r, z, p, ap), stop);
            self.stats.cg_s += cg_start.elapsed().as_secs_f64();
            self.factors.last_products = this_pass.iterations;
            let (dv, dv_bodies) = self.dv.split_at_mut(n);
            changes = coupling.finish(dv_bodies, filter, dv);
            report = CgReport {
                iterations: report.iterations + this_pass.iterations,
                ..this_pass
            };
            for (dv, z) in self.dv.iter_mut().zip(&self.prescribed) {
                *dv += *z;
            }
            // Each surface's impulse on its node, A·Δv − b: a push (normal part ≥ 0) keeps the
            // support for the next step, a pull releases it; a hold needs its tangential part
            // within μ times the normal one. (No product when nothing is supported.)
            if normals.iter().all(|n| *n == DVec3::ZERO) {
                self.pressed.fill(false);
                break;
            }
            rows.product(&self.dv[..n], ax);
            // The last pass only judges the supports: a release there could not be solved (with
            // NextStep, the one pass marks it for the next step).
            let released = friction_release::judge_holds(
                friction_release::Pass {
                    normals,
                    friction: &self.supports.friction,
                    held: &self.held,
                    masses,
                    dv: &self.dv,
                    product: ax,
                    rhs: &self.unfiltered_rhs,
                    velocities,
                },
                friction_start::Holds {
                    fixed: &mut self.fixed,
                    drag: &mut self.sliding_drag,
                    impulse: &mut self.sliding_impulse,
                    release_next: &mut self.release_next,
                },
                &mut self.pressed,
                &mut self.released,
                friction_release::Release {
                    next_step,
                    now: pass + 1 < passes,
                },
            );
            if !released {
                break;
            }
            self.stats.repeated += 1;
        }
        self.dv.truncate(n);
        // What the held carriers' constraints took, from the impulses A·Δv − b their surfaces
        // gave their nodes.
        let held = if coupling.any_held() {
            rows.product(&self.dv, ax);
            let (dv, rhs) = (&self.dv, &self.unfiltered_rhs);
            coupling.held_impulses(&changes, hs, |i| masses[i] * dv[i] + ax[i] - rhs[i])
        } else {
            Vec::new()
        };
        self.carriers.changes = changes;
        self.carriers.held_impulses = held;
        let kicks = kick::Kicks {
            normals,
            masses,
            held: &self.held,
            friction: self.friction,
            carriers: &self.carriers,
            bdf2,
        };
        kicks.forces(&self.dv, (h, gravity), forces);
        let stepped_bdf2 = bdf2.is_some();
        if let Some(history) = self
            .bdf2
            .as_mut()
            .filter(|_| self.settings.scheme == Scheme::Bdf2)
        {
            match stepped_bdf2 {
                true => history.advance(velocities, &self.dv),
                false => history.start(velocities),
            }
        }
        self.state_velocities = state;
        self.stats.solves += 1;
        // Counted as a difference, so that totals restored from a checkpoint carry on.
        let factorisations_after = self.factors.factorisations();
        self.stats.factorisations += factorisations_after - factorisations_before;
        self.stats.iterations += report.iterations as u64;
        if !report.converged {
            self.stats.unconverged += 1;
        }
        self.stats.last = report;
        report
    }
}

/// Solves with static-friction holds at most this many times a step: a hold outside its
/// friction cone is released and the solve repeated (warm-started from the last pass).
const FRICTION_PASSES: usize = 2;

/// Below this tangential speed (m/s), a sliding node's kinetic friction is a drag
/// proportional to its speed (a regularized Coulomb law), so that the solve stays linear.
const FRICTION_SPEED: f64 = 1e-4;
