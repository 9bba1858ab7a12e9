//! Which preconditioner the implicit solve's conjugate gradients use (`docs/model.md` §12,
//! "Preconditioners"), and which one `Auto` stands for at a cloth's size.

/// The preconditioner of the implicit solve's conjugate gradients (`docs/model.md` §12,
/// "Preconditioners").
#[derive(Clone, Copy, Debug, PartialEq, serde::Serialize, serde::Deserialize)]
pub enum Preconditioner {
    /// Whichever is faster at the cloth's size: block Jacobi below [`TWO_LEVEL_FROM_NODES`]
    /// nodes, the two-level preconditioner (coarsening 4) from there on (the default).
    Auto,
    /// The inverse of each node's own 3×3 block: cheapest per product, but the products a
    /// solve needs grow with the lattice (about 33 a step at 1 cm, 120 at 2.5 mm for thick
    /// cotton at 1/240 s).
    BlockJacobi,
    /// A sparse Cholesky factor of the whole filtered system (fill-reducing ordering and
    /// symbolic analysis once per cloth, numeric factorisation when needed;
    /// [`super::SparseCholesky`]). A solve on a fresh factor converges in one or two products;
    /// the factor is kept while the system drifts, and refactored once a solve has needed
    /// more than `refactor_above` products (0: every solve). A kept factor is not saved in
    /// checkpoints: a resumed run refactors at its first solve, and so differs from an
    /// uninterrupted one within the solver's tolerance.
    Cholesky {
        /// Products of one solve above which the next solve refactors (dimensionless).
        refactor_above: usize,
    },
    /// Each warp and weft thread's block-tridiagonal part of the system solved exactly
    /// ([`super::ThreadLines`]): the threads' tensile stiffness, which dominates the system,
    /// is inverted along each thread at O(N) cost.
    ThreadLines,
    /// The thread lines plus a correction on a lattice `coarsening` times coarser
    /// ([`super::CoarseGrid`]), whose Galerkin system is factored by sparse Cholesky. Both are
    /// factored afresh at each step's first pass, so a step's result depends on that step's
    /// system alone (a resumed run ends where an uninterrupted one does). A repeated pass (holds
    /// gave way) refactors only the thread chains through the released nodes, and keeps the
    /// first pass's coarse factor when at most [`KEEP_COARSE_FOR_RELEASED`] were released
    /// (`docs/model.md` §12).
    TwoLevel {
        /// Coarse spacing over the cloth's spacing (dimensionless, 2 to 16; 4 recommended).
        coarsening: usize,
    },
}

/// Node count from which [`Preconditioner::Auto`] chooses the two-level preconditioner: at
/// 2,025 nodes both take the same time a step, at 8,093 the two-level one takes a third of
/// block Jacobi's wall time to a settled drape (thick cotton, `docs/model.md` §12).
pub const TWO_LEVEL_FROM_NODES: usize = 5_000;

/// Most released holds for which a step's repeated pass keeps the first pass's coarse factor,
/// built with those nodes held. The kept factor is still symmetric positive definite, so the
/// solve reaches the same tolerance. Kept for a few released nodes, the products barely change
/// (thin wool at 2.5 mm settling on the drapemeter: 8.19 a step against 8.12, where the coarse
/// factor's set-up costs the time of about 20); kept whatever the number released, the same
/// drape needed 9.7 a step and came to rest at 4.6 s instead of 1.3 s (`docs/model.md` §12).
pub const KEEP_COARSE_FOR_RELEASED: usize = 8;

impl Preconditioner {
    /// The preconditioner in words (for `kes-cloth check`).
    pub fn describe(self) -> String {
        match self {
            Self::Auto => {
                format!("Auto: block Jacobi below {TWO_LEVEL_FROM_NODES} nodes, two-level from there")
            }
            Self::BlockJacobi => "block Jacobi".into(),
            Self::Cholesky { refactor_above } => {
                format!("sparse Cholesky, refactored after a solve of more than {refactor_above} products")
            }
            Self::ThreadLines => "thread lines".into(),
            Self::TwoLevel { coarsening } => {
                format!("two-level (thread lines plus a lattice {coarsening} times coarser)")
            }
        }
    }

    /// The preconditioner this one stands for on a cloth of `nodes` nodes ([`Self::Auto`]
    /// resolved; any other is itself).
    pub fn for_nodes(self, nodes: usize) -> Self {
        match self {
            Self::Auto if nodes >= TWO_LEVEL_FROM_NODES => Self::TwoLevel { coarsening: 4 },
            Self::Auto => Self::BlockJacobi,
            other => other,
        }
    }
}

/// The preconditioner one pass of a solve applies: what [`Preconditioner`] chose, or block
/// Jacobi where its factor could not be formed.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Active {
    /// Each node's 3×3 diagonal block.
    Jacobi,
    /// The sparse Cholesky factor.
    Cholesky,
    /// The thread lines (with the coarse correction for the two-level preconditioner).
    Lines,
}
