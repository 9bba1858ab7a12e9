//! A sparse Cholesky factor of the filtered implicit system, used as the conjugate-gradient
//! preconditioner ([`super::Preconditioner::Cholesky`]).
//!
//! The lattice never changes, so neither does the pattern of M + h·C + h²·H: a fill-reducing
//! ordering (approximate minimum degree) and the symbolic factorisation are computed once, when
//! the solver is built, and each refactorisation is numeric only (`faer`'s supernodal LLᵀ).
//!
//! Supports, holds and pins change from step to step, and the filter P they define (each
//! node's projection: the identity, the plane of its support, or zero) would change the
//! pattern of P·A·P. The factor is therefore of
//!
//! S = P·A·P + (I − P)·M,
//!
//! which has A's pattern whatever P is: S maps the filter's range to itself and its null space
//! to itself (on the null space it is M), so S⁻¹·r for a filtered r is the solution of the
//! filtered system. A factor of an older S (other supports, other stiffness) is still
//! symmetric positive definite, so z = P·S_old⁻¹·P·r is a valid preconditioner, only a less
//! exact one: with [`super::Preconditioner::Cholesky`] the solve refactors once a solve has
//! needed more products than its `refactor_above`; the two-level preconditioner refactors its
//! coarse system at every pass.
//!
//! The factor is computed in double precision and applied in single precision: a solve reads
//! the whole factor twice and is bound by memory (the coarse factor is read at every product of
//! conjugate gradients). As a preconditioner its rounding (6·10⁻⁸ relative in each entry, up to
//! that times the system's condition number in a solve) does not change what conjugate gradients
//! converge to, only how fast (a fresh factor still converges in two products at 10⁻⁸,
//! `tests/implicit_preconditioners.rs`).

use std::sync::Arc;

use faer::dyn_stack::{MemBuffer, MemStack};
use faer::linalg::cholesky::llt::factor::LltRegularization;
use faer::sparse::linalg::cholesky::{
    CholeskySymbolicParams, SymbolicCholesky, SymmetricOrdering, factorize_symbolic_cholesky,
};
use faer::sparse::{SparseColMatRef, SymbolicSparseColMat};
use faer::{Conj, MatMut, Par, Side};
use glam::{DMat3, DVec3};

use crate::forces::ParticleMatrix;

/// A symmetric matrix of 3×3 blocks stored as its upper triangle, row by row: each row's
/// columns ascend and start with the row's own (its diagonal block).
pub trait UpperBlocks {
    /// Number of block rows.
    fn block_rows(&self) -> usize;
    /// Row `i`: its columns and blocks A_ij (j ≥ i).
    fn upper_row(&self, i: usize) -> (&[u32], &[DMat3]);
}

impl UpperBlocks for ParticleMatrix {
    fn block_rows(&self) -> usize {
        self.particle_count()
    }

    fn upper_row(&self, i: usize) -> (&[u32], &[DMat3]) {
        self.row(i)
    }
}

/// The symbolic analysis of one cloth's system and its latest numeric factor.
pub struct SparseCholesky {
    /// Lower triangle of the 3N × 3N system, column by column (scalar entries).
    pattern: SymbolicSparseColMat<usize>,
    /// S's entries in `pattern`'s order.
    values: Vec<f64>,
    /// The ordering and the factor's pattern, shared by clones.
    symbolic: Arc<SymbolicCholesky<usize>>,
    /// The numeric factor's entries, in double precision as faer computes them.
    factor: Vec<f64>,
    /// The same entries in single precision, which solves use; empty until a factorisation
    /// succeeds, and after one that fails.
    single: Vec<f32>,
    /// faer's workspace, sized for both the factorisation and a solve.
    workspace: MemBuffer,
    /// A right-hand side, as 3N scalars.
    rhs: Vec<f32>,
    /// Factorisations done.
    pub factorisations: u64,
}

impl std::fmt::Debug for SparseCholesky {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("SparseCholesky")
            .field("unknowns", &self.rhs.len())
            .field("factor_entries", &self.symbolic.len_val())
            .field("factorisations", &self.factorisations)
            .finish()
    }
}

impl Clone for SparseCholesky {
    fn clone(&self) -> Self {
        Self {
            pattern: self.pattern.clone(),
            values: self.values.clone(),
            symbolic: Arc::clone(&self.symbolic),
            factor: self.factor.clone(),
            single: self.single.clone(),
            workspace: MemBuffer::new(workspace_size(&self.symbolic)),
            rhs: self.rhs.clone(),
            factorisations: self.factorisations,
        }
    }
}

fn workspace_size(symbolic: &SymbolicCholesky<usize>) -> faer::dyn_stack::StackReq {
    symbolic
        .factorize_numeric_llt_scratch::<f64>(Par::Seq, Default::default())
        .or(symbolic.solve_in_place_scratch::<f32>(1, Par::Seq))
}

impl SparseCholesky {
    /// The symbolic analysis of a system with the block pattern of `rows` (which a factor
    /// built here must keep). `None` if faer cannot analyse it (out of memory).
    pub fn new(rows: &impl UpperBlocks) -> Option<Self> {
        let n = rows.block_rows();
        let mut col_ptr = Vec::with_capacity(3 * n + 1);
        let mut row_idx = Vec::new();
        col_ptr.push(0);
        for i in 0..n {
            let (columns, _) = rows.upper_row(i);
            for c in 0..3 {
                // The diagonal block's lower triangle, then every later particle's block.
                row_idx.extend((c..3).map(|r| 3 * i + r));
                for &j in &columns[1..] {
                    row_idx.extend((0..3).map(|r| 3 * j as usize + r));
                }
                col_ptr.push(row_idx.len());
            }
        }
        let pattern = SymbolicSparseColMat::new_checked(3 * n, 3 * n, col_ptr, None, row_idx);
        let symbolic = factorize_symbolic_cholesky(
            pattern.as_ref(),
            Side::Lower,
            SymmetricOrdering::Amd,
            CholeskySymbolicParams::default(),
        )
        .ok()?;
        let workspace = MemBuffer::try_new(workspace_size(&symbolic)).ok()?;
        Some(Self {
            values: vec![0.0; pattern.row_idx().len()],
            pattern,
            symbolic: Arc::new(symbolic),
            factor: Vec::new(),
            single: Vec::new(),
            workspace,
            rhs: vec![0.0; 3 * n],
            factorisations: 0,
        })
    }

    /// Entries of the factor (its memory is 12 bytes each: double and single precision).
    pub fn factor_entries(&self) -> usize {
        self.symbolic.len_val()
    }

    /// Whether a factor is ready for [`Self::solve`].
    pub fn is_factored(&self) -> bool {
        !self.single.is_empty()
    }

    /// Factors S = P·(M + `rows` + D)·P + (I − P)·M, P each node's `projection` (a symmetric
    /// projector: I, the plane of a support, or 0), M = `masses` (kg) and D = `drag`·P (kg,
    /// a sliding node's kinetic friction). Returns `false`, and keeps no factor, if S is not
    /// numerically positive definite.
    pub fn factor(
        &mut self,
        rows: &impl UpperBlocks,
        masses: &[f64],
        projection: &[DMat3],
        drag: &[f64],
    ) -> bool {
        let mut k = 0;
        for i in 0..masses.len() {
            let (columns, blocks) = rows.upper_row(i);
            let p = projection[i];
            let m = masses[i];
            let own = p * (DMat3::from_diagonal(DVec3::splat(m + drag[i])) + blocks[0]) * p
                + m * (DMat3::IDENTITY - p);
            for c in 0..3 {
                for r in c..3 {
                    self.values[k] = own.col(c)[r];
                    k += 1;
                }
                for (&j, b) in columns[1..].iter().zip(&blocks[1..]) {
                    // Block (i, j) is stored; column i of the lower triangle holds its transpose.
                    let s = (p * *b * projection[j as usize]).transpose();
                    for r in 0..3 {
                        self.values[k] = s.col(c)[r];
                        k += 1;
                    }
                }
            }
        }
        if self.factor.len() != self.symbolic.len_val() {
            self.factor = vec![0.0; self.symbolic.len_val()];
        }
        let matrix = SparseColMatRef::new(self.pattern.as_ref(), &self.values);
        let done = self
            .symbolic
            .factorize_numeric_llt(
                &mut self.factor,
                matrix,
                Side::Lower,
                LltRegularization::default(),
                Par::Seq,
                MemStack::new(&mut self.workspace),
                Default::default(),
            )
            .is_ok();
        self.single.clear();
        if done {
            self.factorisations += 1;
            self.single.extend(self.factor.iter().map(|&v| v as f32));
        }
        done
    }

    /// z = S⁻¹·r with the last factor (r and z in particle order). Call only when
    /// [`Self::is_factored`].
    pub fn solve(&mut self, r: &[DVec3], z: &mut [DVec3]) {
        for (chunk, v) in self.rhs.chunks_exact_mut(3).zip(r) {
            chunk.copy_from_slice(&v.as_vec3().to_array());
        }
        let n = self.rhs.len();
        let factor = faer::sparse::linalg::cholesky::LltRef::new(&self.symbolic, &self.single);
        factor.solve_in_place_with_conj(
            Conj::No,
            MatMut::from_column_major_slice_mut(&mut self.rhs, n, 1),
            Par::Seq,
            MemStack::new(&mut self.workspace),
        );
        for (v, chunk) in z.iter_mut().zip(self.rhs.chunks_exact(3)) {
            *v = glam::Vec3::from_slice(chunk).as_dvec3();
        }
    }
}
