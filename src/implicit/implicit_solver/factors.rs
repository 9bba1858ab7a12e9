//! The preconditioner of one cloth's solve: its factors, formed for each pass of a step
//! ([`Factors::form`]), and their application inside conjugate gradients ([`Factors::apply`]).

use glam::{DMat3, DVec3};

use super::blocks;
use crate::forces::{ClothTopology, ParticleMatrix};
use crate::implicit::coarse_grid::CoarseGrid;
use crate::implicit::preconditioner::{Active, KEEP_COARSE_FOR_RELEASED, Preconditioner};
use crate::implicit::sparse_cholesky::SparseCholesky;
use crate::implicit::thread_lines::ThreadLines;

/// The preconditioner's state, kept from pass to pass and step to step.
#[derive(Clone, Debug)]
pub(super) struct Factors {
    /// The preconditioner in use ([`crate::implicit::ImplicitSettings::preconditioner`] for
    /// this cloth's size).
    pub method: Preconditioner,
    /// The sparse Cholesky preconditioner, built at the first solve that asks for it (`None`
    /// before, with block Jacobi, or if faer could not analyse the system).
    cholesky: Option<SparseCholesky>,
    /// The thread-line preconditioner, built at the first solve that asks for it.
    lines: Option<ThreadLines>,
    /// The coarse-lattice correction, built at the first solve that asks for it (`None`
    /// before, or if faer could not analyse it).
    coarse: Option<CoarseGrid>,
    /// Inverse of each node's 3×3 diagonal block of the filtered system (block Jacobi; kg⁻¹).
    jacobi: Vec<DMat3>,
    /// Each node's filter this pass as a matrix (I, a support's plane, or 0).
    pub projection: Vec<DMat3>,
    /// Each node's diagonal block of the filtered system S (kg), for the thread lines.
    filtered_diagonal: Vec<DMat3>,
    /// Products the last solve pass needed (decides a sparse Cholesky refactorisation).
    pub last_products: usize,
}

/// What a pass's preconditioner is formed from.
pub(super) struct PassSystem<'a> {
    /// The cloth's lattice (for the thread lines and the coarse lattice).
    pub topology: &'a ClothTopology,
    /// h·C + h²·H of the step, in particle rows.
    pub rows: &'a ParticleMatrix,
    /// Node masses (kg).
    pub masses: &'a [f64],
    /// Each node's 3×3 diagonal block of M + h·C + h²·H, before the filter (kg).
    pub diagonal: &'a [DMat3],
    /// Each sliding node's kinetic friction drag (kg; zero elsewhere).
    pub drag: &'a [f64],
    /// Each supported node's surface normal (zero where none).
    pub normals: &'a [DVec3],
    /// The nodes whose whole Δv is prescribed this pass.
    pub fixed: &'a [bool],
    /// The nodes whose hold gave way in the step's last pass (empty at its first).
    pub released: &'a [u32],
    /// The pass of the step (0 first).
    pub pass: usize,
}

impl Factors {
    /// No factor yet, for a cloth of `n` nodes solved with `method`.
    pub fn new(method: Preconditioner, n: usize) -> Self {
        Self {
            method,
            cholesky: None,
            lines: None,
            coarse: None,
            jacobi: vec![DMat3::ZERO; n],
            projection: vec![DMat3::IDENTITY; n],
            filtered_diagonal: vec![DMat3::ZERO; n],
            last_products: usize::MAX,
        }
    }

    /// Numeric factorisations the factors have done (sparse Cholesky and coarse).
    pub fn factorisations(&self) -> u64 {
        self.cholesky.as_ref().map_or(0, |c| c.factorisations)
            + self.coarse.as_ref().map_or(0, |c| c.factorisations())
    }

    /// Each node's filter as a matrix, for this pass's supports and holds.
    pub fn project(&mut self, normals: &[DVec3], fixed: &[bool]) {
        blocks::projections(normals, fixed, &mut self.projection);
    }

    /// Forms the preconditioner of a pass (after [`Self::project`]) and says which one
    /// [`Self::apply`] uses: a sparse Cholesky factor of the filtered system, refactored when
    /// the last pass needed many products; the thread lines, with the coarse correction for
    /// the two-level preconditioner; or (by choice, or where neither can be built) block
    /// Jacobi, each node's own 3×3 block of the filtered system P·A·P, inverted on the plane
    /// the filter leaves free (the normal gets m, which the filter then removes again).
    pub fn form(&mut self, s: PassSystem<'_>) -> Active {
        let active = match self.method {
            Preconditioner::Cholesky { refactor_above } => {
                let due = self.last_products > refactor_above;
                let factor = &mut self.cholesky;
                if factor.is_none() {
                    *factor = SparseCholesky::new(s.rows);
                }
                let ready = match factor.as_mut() {
                    Some(factor) if due || !factor.is_factored() => {
                        factor.factor(s.rows, s.masses, &self.projection, s.drag)
                    }
                    Some(factor) => factor.is_factored(),
                    None => false,
                };
                if ready { Active::Cholesky } else { Active::Jacobi }
            }
            Preconditioner::ThreadLines | Preconditioner::TwoLevel { .. } => {
                // Both factors are formed afresh at each step's first pass. A repeated pass
                // (holds gave way) changes only the released nodes' filter and diagonal block:
                // it refactors only the thread chains through them, which equals a whole
                // refactorisation to the last bit, and keeps the first pass's coarse factor
                // unless more than KEEP_COARSE_FOR_RELEASED were released (then it forms
                // again only the coarse blocks they feed, also exact).
                let filtered = blocks::Filtered {
                    diagonal: s.diagonal,
                    projection: &self.projection,
                    drag: s.drag,
                    masses: s.masses,
                };
                filtered.diagonal_blocks(&mut self.filtered_diagonal);
                let (diagonal, projection) = (&self.filtered_diagonal, &self.projection);
                if let Preconditioner::TwoLevel { coarsening } = self.method {
                    if self.coarse.is_none() {
                        self.coarse = CoarseGrid::new(s.topology, s.rows, coarsening);
                    }
                    if let Some(coarse) = self.coarse.as_mut() {
                        if s.pass == 0 {
                            coarse.factor(s.rows, diagonal, projection);
                        } else if s.released.len() > KEEP_COARSE_FOR_RELEASED {
                            coarse.refactor_through(s.released, s.rows, diagonal, projection);
                        }
                    }
                }
                let lines = self
                    .lines
                    .get_or_insert_with(|| ThreadLines::new(s.topology, s.rows));
                let factored = if s.pass == 0 {
                    lines.factor(s.rows, diagonal, projection)
                } else {
                    lines.refactor_through(s.released, s.rows, diagonal, projection)
                };
                if factored { Active::Lines } else { Active::Jacobi }
            }
            Preconditioner::BlockJacobi | Preconditioner::Auto => Active::Jacobi,
        };
        if active == Active::Jacobi {
            let blocks = blocks::Filtered {
                diagonal: s.diagonal,
                projection: &self.projection,
                drag: s.drag,
                masses: s.masses,
            };
            blocks.jacobi_inverses(s.normals, s.fixed, &mut self.jacobi);
        }
        active
    }

    /// z = P·r for the cloth's nodes with the preconditioner [`Self::form`] chose (`active`),
    /// each node's z then filtered by `filter` (block Jacobi's blocks already are, so
    /// without a coarse correction its z is left as it is).
    pub fn apply(
        &mut self,
        active: Active,
        r: &[DVec3],
        z: &mut [DVec3],
        filter: impl Fn(usize, DVec3) -> DVec3,
    ) {
        let mut coarse = match self.method {
            Preconditioner::TwoLevel { .. } => self.coarse.as_mut().filter(|c| c.is_factored()),
            _ => None,
        };
        match (active, self.cholesky.as_mut(), self.lines.as_mut()) {
            (Active::Cholesky, Some(factor), _) => factor.solve(r, z),
            (Active::Lines, _, Some(lines)) => lines.solve(r, z),
            _ => {
                for ((z, r), block) in z.iter_mut().zip(r).zip(&self.jacobi) {
                    *z = *block * *r;
                }
                if coarse.is_none() {
                    return;
                }
            }
        }
        if let Some(coarse) = coarse.as_mut() {
            coarse.add_correction(r, z);
        }
        for (i, z) in z.iter_mut().enumerate() {
            *z = filter(i, *z);
        }
    }
}
