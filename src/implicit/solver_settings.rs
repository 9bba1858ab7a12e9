//! What the implicit solve is told ([`ImplicitSettings`]) and what it reports over a run
//! ([`ImplicitStats`]).

use super::conjugate_gradient::CgReport;
use super::preconditioner::Preconditioner;
use super::scheme::Scheme;

/// The relative tolerance a solve uses at most while an edge presses on links
/// ([`super::LinkSupport`]): their stiff springs dominate |b|_P, and at 1e-3 the solve stopped
/// before the cloth's own motion was solved (thick cotton on the drapemeter at 3.75 mm with
/// block Jacobi: DC 0.702 with 4 nodes; at 1e-5, as with the two-level preconditioner or an
/// exact factor at 1e-3, 0.741 with 5; the products a step 37 and 40).
pub const LINK_TOLERANCE: f64 = 1e-5;

/// Conjugate-gradient settings of the implicit solve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImplicitSettings {
    /// Most operator products per step (default 200). A solve stopped early still returns a
    /// velocity change that reduces the residual; [`ImplicitStats`] counts how often it happens.
    pub max_iterations: usize,
    /// Relative residual |b − A·Δv|_P/|b|_P at which a solve stops (dimensionless; default
    /// 1e-3; the norm is the preconditioner's, [`CgReport::relative_residual`]). A step with
    /// an edge pressing on links ([`super::LinkSupport`]) uses at most [`LINK_TOLERANCE`].
    pub tolerance: f64,
    /// Mass-weighted RMS error of Δv (m/s) below which a solve stops whatever its relative
    /// residual (default 3e-6; 0 for none). Near rest b nearly vanishes, and the relative rule
    /// alone chases it: thick cotton at 5 mm and 1/240 s settled in 180 products a step, and
    /// in 105 with this floor, for the same DC to 1e-4 and a largest node speed at rest of
    /// 0.33 mm/s (0.16 mm/s without; 1.3 mm/s, above the settle limit, with a floor of 1e-5
    /// m/s; `docs/model.md` §12).
    pub velocity_tolerance: f64,
    /// Whether the solve applies the supports' Coulomb friction (see
    /// [`super::ImplicitSolver::apply_friction`]); `None` (default) for on when the cloth's
    /// stretch is in the solve and off with Rapier's rope joints.
    pub friction: Option<bool>,
    /// How each conjugate-gradient iteration is preconditioned (default
    /// [`Preconditioner::Auto`]).
    pub preconditioner: Preconditioner,
    /// How the solve steps in time (default [`Scheme::BackwardEuler`]).
    pub scheme: Scheme,
    /// When a static-friction hold whose impulse leaves its friction cone starts to slide
    /// (default [`FrictionRelease::SameStep`]).
    pub friction_release: FrictionRelease,
}

/// When a supported node held by static friction, whose solved impulse leaves the friction cone
/// (|λ_t| > μ·λ_n), starts to slide.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, serde::Serialize, serde::Deserialize)]
pub enum FrictionRelease {
    /// Released within the step, which is solved again with the node sliding (at most once).
    /// Thin wool on the drapemeter at 3.75 mm and 1/240 s repeats 82 % of its steps' solves;
    /// from the shipped smooth start it drapes to DC 0.386 ± 0.012 over four placements where
    /// 1/960 s gives 0.392 ± 0.012 (`docs/model.md` §12, "When a hold gives way").
    #[default]
    SameStep,
    /// Released from the next step on (it slides from then, against the kinetic friction of
    /// the impulse that broke the hold): one solve a step, the hold kept one step longer. The
    /// same wool drapes alike (0.382 ± 0.015), each step costs less, but rest comes no sooner:
    /// Cusick cotton's seed 0 rests at 9.2 s with it and 2.7 s with `SameStep`.
    NextStep,
}

impl Default for ImplicitSettings {
    fn default() -> Self {
        Self {
            max_iterations: 200,
            tolerance: 1e-3,
            velocity_tolerance: 3e-6,
            friction: None,
            preconditioner: Preconditioner::Auto,
            scheme: Scheme::BackwardEuler,
            friction_release: FrictionRelease::SameStep,
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
    /// Solves that stopped short of their tolerance (at `max_iterations`, or on a direction of
    /// non-positive curvature).
    pub unconverged: u64,
    /// Steps solved twice because a support's static friction gave way (a step's release).
    #[serde(default)]
    pub repeated: u64,
    /// Numeric Cholesky factorisations ([`Preconditioner::Cholesky`]; 0 with block Jacobi).
    #[serde(default)]
    pub factorisations: u64,
    /// The last solve.
    pub last: CgReport,
    /// Wall time over all solves (s) spent assembling the system: every generator's stiffness
    /// and damping blocks, the right-hand side and the particle rows.
    #[serde(default)]
    pub assembly_s: f64,
    /// Wall time over all solves (s) spent setting up the preconditioner (block inverses,
    /// thread-line and coarse factorisations, the sparse Cholesky factor).
    #[serde(default)]
    pub preconditioner_s: f64,
    /// Wall time over all solves (s) in the conjugate gradients themselves.
    #[serde(default)]
    pub cg_s: f64,
}
