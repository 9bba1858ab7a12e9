//! Linearly implicit (backward Euler, or BDF2: [`Scheme`]) KES forces, after Baraff & Witkin
//! (1998).
//!
//! Rapier samples our forces once per step, so applied as they are they are explicit, and a
//! stiff fabric needs a step 10–20 times smaller than contact does (`docs/model.md` §7). With
//! [`Integrator::Implicit`], each step instead:
//!
//! 1. evaluates every force F at the current positions and velocities (as the explicit pass does);
//! 2. forms b = h·(F + M·g − h·H·v), H the clamped, positive semi-definite Hessian of our
//!    energies (assembled by [`crate::forces::ForceGenerator::add_stiffness_blocks`], the matrix
//!    that [`crate::forces::ForceGenerator::add_stiffness_product`] multiplies by) and g the nodes'
//!    gravity, so that the step's fixed point is the cloth's true equilibrium F + M·g = 0;
//! 3. assembles h²·H and h·C (C the damping matrix of the dissipative effects) block by block
//!    ([`crate::forces::LinkMatrix`], summed into particle rows for the products,
//!    [`crate::forces::ParticleMatrix`]) and solves (M + h·C + h²·H)·Δv = b by conjugate gradients,
//!    preconditioned by the inverse of each node's 3×3 diagonal block, or on a large cloth by
//!    the thread lines plus a coarse-lattice correction ([`Preconditioner`]), and warm-started
//!    from the previous step's Δv, with the normal
//!    component of Δv held at zero for nodes that a fixed surface pushed in Rapier's last step
//!    (Baraff & Witkin's filter, with Rapier's contact impulses as the active set), or that
//!    still touch the surface that pushed them in the last solve (their release rule: a support
//!    goes only when the surface would pull), and the whole Δv held at zero for nodes pinned to
//!    a body that cannot move;
//! 4. with friction in the solve ([`ImplicitSolver::apply_friction`], the default when no rope
//!    joints hold the stretch), first holds each supported node still (and stops its motion
//!    along the normal), then, for a hold whose tangential impulse exceeds μ times its normal
//!    impulse, releases it and solves again with a kinetic friction drag of μ times that normal
//!    impulse (Coulomb); a node that slid starts the next step sliding against its last
//!    friction impulse, and is held again once it has all but stopped (0.1 mm/s), so a
//!    step is solved twice only when a hold gives way;
//! 5. hands Rapier the force M·Δv/h − M·g, which reaches each node as the velocity kick
//!    Δv − h·g before Rapier's step (Rapier's gravity adds h·g back; joints and contacts follow).
//!
//! With [`Scheme::Bdf2`] steps 2–3 use h' = β·h (2h/3 at a constant step) and BDF2's history,
//! and step 5 hands Rapier BDF2's kick (`scheme.rs`).
//!
//! Only our forces, gravity and (optionally) the supports' friction are implicit; Rapier still
//! treats joints and contact its own way, except that a host's dynamic body touching the cloth
//! or pinning it is solved with it as a rigid body ([`Carriers`]).
//! The derivation, the clamp and the numerical damping it adds are in `docs/model.md` §12.

mod carriers;
mod coarse_grid;
mod conjugate_gradient;
mod implicit_solver;
mod link_supports;
mod preconditioner;
mod scheme;
mod solver_settings;
mod sparse_cholesky;
mod strain_limit;
mod supports;
mod thread_lines;

pub use carriers::{Carrier, Carriers, Twist};
pub use coarse_grid::CoarseGrid;
pub use conjugate_gradient::{CgReport, Stop, conjugate_gradient};
pub use implicit_solver::ImplicitSolver;
pub use link_supports::{LinkAnchors, LinkSupport};
pub use preconditioner::{KEEP_COARSE_FOR_RELEASED, Preconditioner, TWO_LEVEL_FROM_NODES};
pub use scheme::{Bdf2History, Scheme};
pub use solver_settings::{FrictionRelease, ImplicitSettings, ImplicitStats, LINK_TOLERANCE};
pub use sparse_cholesky::SparseCholesky;
pub use strain_limit::{STRAIN_LIMIT, limit_strain, over_limit};
pub use supports::Supports;
pub use thread_lines::ThreadLines;

/// How our forces are integrated over a step.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Integrator {
    /// Forces at the start of the step, as one velocity kick (symplectic Euler in Rapier): cheapest
    /// per step, but stable only for steps below the fabric's explicit limit.
    Explicit,
    /// Linearly implicit backward Euler (or BDF2, [`ImplicitSettings::scheme`]): stable at any
    /// step, with numerical damping that grows with h (far less of it with BDF2).
    Implicit(ImplicitSettings),
}
