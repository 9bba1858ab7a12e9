//! A coarse-lattice correction for the implicit solve's preconditioner
//! ([`super::Preconditioner::TwoLevel`]).
//!
//! Out of the cloth's plane the system is stiff through bending along both thread directions
//! (a fourth-order operator: its conditioning grows as σ⁻⁴ at a fixed step), and a smooth
//! out-of-plane mode spans many nodes in both directions, which neither block Jacobi nor one
//! thread's band can invert: the products a solve needs grow with the lattice. The coarse
//! correction solves such modes on a lattice `c` times coarser: R interpolates bilinearly
//! from coarse nodes to the cloth's nodes (each node takes its value from the up to four
//! coarse nodes around it, 3 components each), the coarse system is the Galerkin product
//! A_c = Rᵀ·S·R of the filtered system S ([`super::sparse_cholesky`]), factored by sparse
//! Cholesky, and the preconditioner is
//!
//! z = B·r + P·R·A_c⁻¹·Rᵀ·r,
//!
//! B the thread lines ([`super::ThreadLines`]; block Jacobi where they fail). Both terms are
//! symmetric positive semi-definite and their sum is definite, so conjugate gradients apply.

use glam::{DMat3, DVec3};

use super::sparse_cholesky::{SparseCholesky, UpperBlocks};
use crate::forces::{ClothTopology, ParticleMatrix, compress_rows};

/// A coarse node's index and its interpolation weight (dimensionless).
type Parent = (u32, f64);

/// The coarse system's matrix, upper triangle of 3×3 blocks row by row.
#[derive(Clone, Debug)]
struct CoarseMatrix {
    row_start: Vec<usize>,
    column: Vec<u32>,
    block: Vec<DMat3>,
}

impl UpperBlocks for CoarseMatrix {
    fn block_rows(&self) -> usize {
        self.row_start.len() - 1
    }

    fn upper_row(&self, i: usize) -> (&[u32], &[DMat3]) {
        let range = self.row_start[i]..self.row_start[i + 1];
        (&self.column[range.clone()], &self.block[range])
    }
}

/// Where one fine block's weighted contribution goes in the coarse matrix.
#[derive(Clone, Copy, Debug)]
struct Scatter {
    /// Index of the coarse block.
    index: u32,
    /// 0: added as it is; 1: transposed; 2: plus its transpose (a coarse diagonal block fed
    /// by an off-diagonal fine block).
    mode: u8,
    /// Product of the two interpolation weights (dimensionless).
    weight: f64,
}

/// The coarse lattice of one cloth, its Galerkin matrix and factor.
#[derive(Clone, Debug)]
pub struct CoarseGrid {
    /// Each node's coarse parents (unused entries weigh 0).
    parents: Vec<[Parent; 4]>,
    /// For each stored fine block (in the particle matrix's order), its contributions:
    /// `scatter[scatter_start[k]..scatter_start[k + 1]]`.
    scatter: Vec<Scatter>,
    scatter_start: Vec<u32>,
    matrix: CoarseMatrix,
    cholesky: SparseCholesky,
    /// Zero masses, identity projections and zero drags of the coarse system (the Galerkin
    /// product already holds the filter).
    zeros: Vec<f64>,
    identities: Vec<DMat3>,
    /// Coarse right-hand side, then solution (swapped with `solution` by a solve).
    coarse: Vec<DVec3>,
    solution: Vec<DVec3>,
    /// Whether the last factorisation succeeded.
    factored: bool,
}

impl CoarseGrid {
    /// The lattice `coarsening` times coarser than `topology`'s (at least 2), with the
    /// pattern of `rows`. `None` if faer cannot analyse the coarse system.
    pub fn new(topology: &ClothTopology, rows: &ParticleMatrix, coarsening: usize) -> Option<Self> {
        let c = coarsening.max(2) as u32;
        let (mut max_i, mut max_j) = (0, 0);
        for &(i, j) in &topology.grid_coords {
            max_i = max_i.max(i);
            max_j = max_j.max(j);
        }
        let (ni, nj) = (max_i / c + 2, max_j / c + 2);
        let mut number = vec![u32::MAX; (ni * nj) as usize];
        let mut count = 0u32;
        let parents: Vec<[Parent; 4]> = topology
            .grid_coords
            .iter()
            .map(|&(i, j)| {
                let (ci, cj) = (i / c, j / c);
                let (fi, fj) = ((i % c) as f64 / c as f64, (j % c) as f64 / c as f64);
                let mut out = [(0, 0.0); 4];
                let corners = [
                    (ci, cj, (1.0 - fi) * (1.0 - fj)),
                    (ci + 1, cj, fi * (1.0 - fj)),
                    (ci, cj + 1, (1.0 - fi) * fj),
                    (ci + 1, cj + 1, fi * fj),
                ];
                for (slot, (a, b, w)) in out.iter_mut().zip(corners) {
                    if w > 0.0 {
                        let k = &mut number[(a * nj + b) as usize];
                        if *k == u32::MAX {
                            *k = count;
                            count += 1;
                        }
                        *slot = (*k, w);
                    }
                }
                out
            })
            .collect();
        // The coarse pattern: every pair of parents of a stored fine block.
        let nc = count as usize;
        let mut columns: Vec<Vec<u32>> = (0..count).map(|k| vec![k]).collect();
        for (i, own) in parents.iter().enumerate() {
            let (fine_columns, _) = rows.row(i);
            for &j in fine_columns {
                for &(a, wa) in own {
                    for &(b, wb) in &parents[j as usize] {
                        if wa > 0.0 && wb > 0.0 {
                            columns[a.min(b) as usize].push(a.max(b));
                        }
                    }
                }
            }
        }
        let (row_start, column) = compress_rows(columns);
        let matrix = CoarseMatrix {
            block: vec![DMat3::ZERO; column.len()],
            row_start,
            column,
        };
        // Every fine block's contributions, in the order `factor` visits the blocks.
        let (mut scatter, mut scatter_start) = (Vec::new(), vec![0u32]);
        let place = |i: u32, j: u32| -> u32 {
            let start = matrix.row_start[i as usize];
            let row = &matrix.column[start..matrix.row_start[i as usize + 1]];
            (start + row.binary_search(&j).unwrap_or(0)) as u32
        };
        for (i, own) in parents.iter().enumerate() {
            let (fine_columns, _) = rows.row(i);
            for &j in fine_columns {
                let j = j as usize;
                for &(a, wa) in own {
                    for &(b, wb) in &parents[j] {
                        if wa <= 0.0 || wb <= 0.0 || (j == i && a > b) {
                            // A diagonal fine block feeds each ordered pair of parents once.
                            continue;
                        }
                        let (index, mode) = match a.cmp(&b) {
                            _ if j == i => (place(a, b), 0),
                            std::cmp::Ordering::Less => (place(a, b), 0),
                            std::cmp::Ordering::Greater => (place(b, a), 1),
                            std::cmp::Ordering::Equal => (place(a, a), 2),
                        };
                        scatter.push(Scatter {
                            index,
                            mode,
                            weight: wa * wb,
                        });
                    }
                }
                scatter_start.push(scatter.len() as u32);
            }
        }
        let cholesky = SparseCholesky::new(&matrix)?;
        Some(Self {
            scatter,
            scatter_start,
            parents,
            matrix,
            cholesky,
            zeros: vec![0.0; nc],
            identities: vec![DMat3::IDENTITY; nc],
            coarse: vec![DVec3::ZERO; nc],
            solution: vec![DVec3::ZERO; nc],
            factored: false,
        })
    }

    /// Number of coarse nodes.
    pub fn coarse_nodes(&self) -> usize {
        self.coarse.len()
    }

    /// Forms A_c = Rᵀ·S·R for S = P·(M + `rows` + D)·P + (I − P)·M (`diagonal`: each node's
    /// diagonal block of S; `projection`: each node's P) and factors it. Returns whether the
    /// factor is ready.
    pub fn factor(&mut self, rows: &ParticleMatrix, diagonal: &[DMat3], projection: &[DMat3]) -> bool {
        self.matrix.block.fill(DMat3::ZERO);
        let mut k = 0;
        for i in 0..self.parents.len() {
            let (columns, blocks) = rows.row(i);
            for (&j, block) in columns.iter().zip(blocks) {
                let j = j as usize;
                // S_ii is the filtered diagonal; S_ij = P_i·A_ij·P_j (P = I on a free node).
                let s = if j == i {
                    diagonal[i]
                } else if projection[i] == DMat3::IDENTITY && projection[j] == DMat3::IDENTITY {
                    *block
                } else {
                    projection[i] * *block * projection[j]
                };
                let range = self.scatter_start[k] as usize..self.scatter_start[k + 1] as usize;
                for c in &self.scatter[range] {
                    let add = c.weight * s;
                    self.matrix.block[c.index as usize] += match c.mode {
                        0 => add,
                        1 => add.transpose(),
                        _ => add + add.transpose(),
                    };
                }
                k += 1;
            }
        }
        self.factored = self
            .cholesky
            .factor(&self.matrix, &self.zeros, &self.identities, &self.zeros);
        self.factored
    }

    /// Numeric factorisations of the coarse system so far.
    pub fn factorisations(&self) -> u64 {
        self.cholesky.factorisations
    }

    /// Whether the last factorisation succeeded.
    pub fn is_factored(&self) -> bool {
        self.factored
    }

    /// z += R·A_c⁻¹·Rᵀ·r (unfiltered: the caller filters z).
    pub fn add_correction(&mut self, r: &[DVec3], z: &mut [DVec3]) {
        self.coarse.fill(DVec3::ZERO);
        for (own, r) in self.parents.iter().zip(r) {
            for &(a, w) in own {
                self.coarse[a as usize] += w * *r;
            }
        }
        self.cholesky.solve(&self.coarse, &mut self.solution);
        std::mem::swap(&mut self.coarse, &mut self.solution);
        for (own, z) in self.parents.iter().zip(z) {
            for &(a, w) in own {
                *z += w * self.coarse[a as usize];
            }
        }
    }
}
