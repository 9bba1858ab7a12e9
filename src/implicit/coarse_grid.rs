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

impl Scatter {
    /// What the filtered fine block `s` adds to the coarse block.
    #[inline(always)]
    fn contribution(&self, s: DMat3) -> DMat3 {
        let add = self.weight * s;
        match self.mode {
            0 => add,
            1 => add.transpose(),
            _ => add + add.transpose(),
        }
    }
}

/// Block (i, j) of the filtered system S = P·(M + A + D)·P + (I − P)·M: the filtered diagonal
/// block where j = i, P_i·A_ij·P_j elsewhere (A_ij itself between free nodes).
#[inline(always)]
fn filtered_block(i: usize, j: usize, block: &DMat3, diagonal: &[DMat3], projection: &[DMat3]) -> DMat3 {
    if j == i {
        diagonal[i]
    } else if projection[i] == DMat3::IDENTITY && projection[j] == DMat3::IDENTITY {
        *block
    } else {
        projection[i] * *block * projection[j]
    }
}

/// Lists of indices as one array and each list's start (with the end as a last entry).
fn flatten(lists: Vec<Vec<u32>>) -> (Vec<u32>, Vec<u32>) {
    let mut start = Vec::with_capacity(lists.len() + 1);
    start.push(0);
    let mut flat = Vec::new();
    for list in lists {
        flat.extend(list);
        start.push(flat.len() as u32);
    }
    (start, flat)
}

/// The coarse lattice of one cloth, its Galerkin matrix and factor.
#[derive(Clone, Debug)]
pub struct CoarseGrid {
    /// Each node's coarse parents, those of positive weight first (unused entries weigh 0).
    parents: Vec<[Parent; 4]>,
    /// How many of each node's parents weigh more than 0 (1, 2 or 4).
    parent_count: Vec<u8>,
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
    /// First fine block (in the particle matrix's order) of each fine row.
    block_start: Vec<u32>,
    /// For each fine node j, the fine blocks (i, j) stored in earlier rows i < j:
    /// `lower_block[lower_start[j]..lower_start[j + 1]]`.
    lower_start: Vec<u32>,
    lower_block: Vec<u32>,
    /// For each coarse block, the scatters that feed it, in the order [`Self::factor`] adds
    /// them: `contributors[contributor_start[c]..contributor_start[c + 1]]`.
    contributor_start: Vec<u32>,
    contributors: Vec<u32>,
    /// Each contributor's fine block (in the particle matrix's order).
    contributor_block: Vec<u32>,
    /// Each fine block's row.
    block_row: Vec<u32>,
    /// Scratch of [`Self::refactor_through`]: which coarse blocks it recomputes, as flags and
    /// as a list.
    marked: Vec<bool>,
    touched: Vec<u32>,
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
                let mut used = 0;
                for (a, b, w) in corners {
                    if w > 0.0 {
                        let k = &mut number[(a * nj + b) as usize];
                        if *k == u32::MAX {
                            *k = count;
                            count += 1;
                        }
                        out[used] = (*k, w);
                        used += 1;
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
        // Where each fine row's blocks start, the blocks below each node, and each coarse
        // block's scatters, for recomputing a few coarse blocks.
        let mut block_start = vec![0u32];
        let mut lower: Vec<Vec<u32>> = vec![Vec::new(); parents.len()];
        for i in 0..parents.len() {
            let (fine_columns, _) = rows.row(i);
            let first = block_start[i];
            for (d, &j) in fine_columns.iter().enumerate() {
                if j as usize != i {
                    lower[j as usize].push(first + d as u32);
                }
            }
            block_start.push(first + fine_columns.len() as u32);
        }
        let (lower_start, lower_block) = flatten(lower);
        let mut feeding: Vec<Vec<u32>> = vec![Vec::new(); matrix.column.len()];
        for (at, c) in scatter.iter().enumerate() {
            feeding[c.index as usize].push(at as u32);
        }
        let (contributor_start, contributors) = flatten(feeding);
        let contributor_block = contributors
            .iter()
            .map(|&at| scatter_start.partition_point(|&start| start <= at) as u32 - 1)
            .collect();
        let block_row = (0..block_start.len() - 1)
            .flat_map(|i| std::iter::repeat_n(i as u32, (block_start[i + 1] - block_start[i]) as usize))
            .collect();
        let marked = vec![false; matrix.column.len()];
        let parent_count = parents
            .iter()
            .map(|own| own.iter().filter(|(_, w)| *w > 0.0).count() as u8)
            .collect();
        Some(Self {
            parent_count,
            block_start,
            lower_start,
            lower_block,
            contributor_start,
            contributors,
            contributor_block,
            block_row,
            marked,
            touched: Vec::new(),
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
                let s = filtered_block(i, j as usize, block, diagonal, projection);
                let range = self.scatter_start[k] as usize..self.scatter_start[k + 1] as usize;
                for c in &self.scatter[range] {
                    self.matrix.block[c.index as usize] += c.contribution(s);
                }
                k += 1;
            }
        }
        self.factor_matrix()
    }

    /// Forms again only the coarse blocks fed by the fine nodes `changed`, whose filter or
    /// diagonal block changed while `rows` stayed as at the last [`Self::factor`] (a step's
    /// repeated pass, where a few holds gave way), and factors A_c. Each block recomputed sums
    /// its contributions in [`Self::factor`]'s order, so A_c and its factor equal a whole
    /// [`Self::factor`]'s to the last bit.
    pub fn refactor_through(
        &mut self,
        changed: &[u32],
        rows: &ParticleMatrix,
        diagonal: &[DMat3],
        projection: &[DMat3],
    ) -> bool {
        let mut blocks = std::mem::take(&mut self.touched);
        blocks.clear();
        for &node in changed {
            let node = node as usize;
            let own = self.block_start[node]..self.block_start[node + 1];
            let below =
                &self.lower_block[self.lower_start[node] as usize..self.lower_start[node + 1] as usize];
            for k in own.chain(below.iter().copied()) {
                let k = k as usize;
                for c in &self.scatter[self.scatter_start[k] as usize..self.scatter_start[k + 1] as usize] {
                    if !std::mem::replace(&mut self.marked[c.index as usize], true) {
                        blocks.push(c.index);
                    }
                }
            }
        }
        for &index in &blocks {
            let index = index as usize;
            self.marked[index] = false;
            let mut sum = DMat3::ZERO;
            let feeding = self.contributor_start[index] as usize..self.contributor_start[index + 1] as usize;
            for (&at, &k) in self.contributors[feeding.clone()]
                .iter()
                .zip(&self.contributor_block[feeding])
            {
                let i = self.block_row[k as usize] as usize;
                let (columns, fine) = rows.row(i);
                let d = (k - self.block_start[i]) as usize;
                let s = filtered_block(i, columns[d] as usize, &fine[d], diagonal, projection);
                sum += self.scatter[at as usize].contribution(s);
            }
            self.matrix.block[index] = sum;
        }
        self.touched = blocks;
        self.factor_matrix()
    }

    /// Factors the coarse matrix as it stands.
    fn factor_matrix(&mut self) -> bool {
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
        // Only the parents of positive weight: a zero weight's term is an exact no-op.
        let parents = self.parents.iter().zip(&self.parent_count);
        self.coarse.fill(DVec3::ZERO);
        for ((own, &count), r) in parents.clone().zip(r) {
            for &(a, w) in &own[..count as usize] {
                self.coarse[a as usize] += w * *r;
            }
        }
        self.cholesky.solve(&self.coarse, &mut self.solution);
        std::mem::swap(&mut self.coarse, &mut self.solution);
        for ((own, &count), z) in parents.zip(z) {
            for &(a, w) in &own[..count as usize] {
                *z += w * self.coarse[a as usize];
            }
        }
    }
}
