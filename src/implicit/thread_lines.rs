//! The thread-line preconditioner ([`super::Preconditioner::ThreadLines`]): each warp and each
//! weft thread's own block-tridiagonal part of the filtered system, solved exactly.
//!
//! The implicit system is dominated by the threads' tensile stiffness, which couples each node
//! only to its two neighbours along each thread. Block Jacobi ignores that coupling, so the
//! products a solve needs grow with the number of nodes along a thread; solving each thread
//! as a chain (block Thomas algorithm, O(N)) removes it. With T_w and T_f the block-tridiagonal
//! parts of the filtered system S along the warp and the weft threads (each node's whole
//! diagonal block of S, and S's blocks between neighbours on the thread), the preconditioner is
//! z = ½·(T_w⁻¹ + T_f⁻¹)·r, symmetric positive definite when both parts are.
//!
//! The factors are computed in double precision and stored in single precision: a solve reads
//! every factor block (216 bytes a node, 432 in double precision), so the solve is bound
//! by memory, not arithmetic. The preconditioner's precision does not change what conjugate
//! gradients converge to (their residual is of the system itself, in double precision), only how
//! fast: each entry is stored to 6·10⁻⁸ relative, and a solve's error, up to that times the
//! band's condition number, makes the preconditioner a less exact inverse of the system (the
//! products a step at the shipped tolerance, 10⁻³, are unchanged, and
//! `tests/implicit_preconditioners.rs` solves to 10⁻¹⁰ with it).

use glam::{DMat3, DVec3, Mat3, Vec3};

use crate::forces::{ClothTopology, ParticleMatrix};

/// One thread's chain of nodes, in order along the thread.
#[derive(Clone, Copy, Debug)]
struct Chain {
    /// First entry of this chain in [`ThreadLines::nodes`].
    start: usize,
    /// Number of nodes.
    len: usize,
}

/// Where no block is stored (a chain's end).
const NONE: u32 = u32::MAX;

/// The chains of both thread directions and their banded factors.
#[derive(Clone, Debug)]
pub struct ThreadLines {
    /// Every chain's nodes, chain after chain: the warp chains, then the weft chains.
    nodes: Vec<u32>,
    chains: Vec<Chain>,
    /// For each entry, where the blocks between its node and the next and next-but-one nodes
    /// of its chain are stored in the particle matrix's row of the node ([`NONE`] past the end).
    ahead: Vec<[u32; 2]>,
    /// The inverse of each entry's pivot block D_k of the banded LDLᵀ factor (kg⁻¹).
    pivot_inverse: Vec<Mat3>,
    /// L_{k+1,k} and L_{k+2,k} of each entry k (dimensionless; zero past the chain's end).
    lower: Vec<[Mat3; 2]>,
    /// Intermediate values of a solve, per entry.
    work: Vec<Vec3>,
    /// The chain of each entry.
    entry_chain: Vec<u32>,
    /// Each node's entry in its warp chain and in its weft chain ([`NONE`] if in none).
    node_entries: Vec<[u32; 2]>,
    /// Whether every chain's last factorisation succeeded.
    factored: bool,
    /// Scratch of [`Self::refactor_through`]: the chains it refactors.
    touched: Vec<u32>,
}

impl ThreadLines {
    /// The warp and weft chains of `topology`, with the particle matrix `rows` (its pattern)
    /// for the blocks between chain neighbours.
    pub fn new(topology: &ClothTopology, rows: &ParticleMatrix) -> Self {
        let n = topology.particle_count;
        let mut nodes = Vec::with_capacity(2 * n);
        let mut chains = Vec::new();
        let (warp, weft) = topology.links.split_at(topology.warp_link_count);
        let mut warp_chains = 0;
        for (direction, links) in [warp, weft].into_iter().enumerate() {
            let mut next = vec![NONE; n];
            let mut has_previous = vec![false; n];
            for &[p, q] in links {
                next[p as usize] = q;
                has_previous[q as usize] = true;
            }
            for first in (0..n).filter(|&p| !has_previous[p]) {
                let start = nodes.len();
                let mut p = first as u32;
                while p != NONE {
                    nodes.push(p);
                    p = next[p as usize];
                }
                chains.push(Chain {
                    start,
                    len: nodes.len() - start,
                });
            }
            if direction == 0 {
                warp_chains = chains.len();
            }
        }
        // Links run towards higher particle indices, so the block (p, q) of a later node q is
        // stored in p's row.
        let mut ahead = vec![[NONE; 2]; nodes.len()];
        for chain in &chains {
            for k in chain.start..chain.start + chain.len {
                let (columns, _) = rows.row(nodes[k] as usize);
                for (d, slot) in ahead[k].iter_mut().enumerate() {
                    if k + d + 1 < chain.start + chain.len {
                        let q = nodes[k + d + 1];
                        *slot = columns.binary_search(&q).map_or(NONE, |at| at as u32);
                    }
                }
            }
        }
        let entries = nodes.len();
        let mut entry_chain = vec![0; entries];
        let mut node_entries = vec![[NONE; 2]; n];
        for (c, chain) in chains.iter().enumerate() {
            let direction = usize::from(c >= warp_chains);
            for k in chain.start..chain.start + chain.len {
                entry_chain[k] = c as u32;
                node_entries[nodes[k] as usize][direction] = k as u32;
            }
        }
        Self {
            nodes,
            chains,
            ahead,
            pivot_inverse: vec![Mat3::ZERO; entries],
            lower: vec![[Mat3::ZERO; 2]; entries],
            work: vec![Vec3::ZERO; entries],
            entry_chain,
            node_entries,
            factored: false,
            touched: Vec::new(),
        }
    }

    /// Factors each chain's band of S = P·(M + `rows` + D)·P + (I − P)·M (`projection` P per
    /// node; `diagonal` holds each node's diagonal block of S, kg). Returns `false` if a pivot
    /// is not positive definite (the caller then falls back to block Jacobi).
    pub fn factor(&mut self, rows: &ParticleMatrix, diagonal: &[DMat3], projection: &[DMat3]) -> bool {
        self.factored = (0..self.chains.len()).all(|c| self.factor_chain(c, rows, diagonal, projection));
        self.factored
    }

    /// Refactors only the chains through the nodes `changed`, after their filter or diagonal
    /// block changed while `rows` stayed as at the last [`Self::factor`] (a step's repeated
    /// pass, where a few holds gave way): every other chain's band is unchanged, so the result
    /// equals a whole [`Self::factor`] to the last bit. Factors every chain if the last factor
    /// failed.
    pub fn refactor_through(
        &mut self,
        changed: &[u32],
        rows: &ParticleMatrix,
        diagonal: &[DMat3],
        projection: &[DMat3],
    ) -> bool {
        if !self.factored {
            return self.factor(rows, diagonal, projection);
        }
        let mut chains = std::mem::take(&mut self.touched);
        chains.clear();
        chains.extend(
            changed
                .iter()
                .flat_map(|&p| self.node_entries[p as usize])
                .filter(|&k| k != NONE)
                .map(|k| self.entry_chain[k as usize]),
        );
        chains.sort_unstable();
        chains.dedup();
        self.factored = chains
            .iter()
            .all(|&c| self.factor_chain(c as usize, rows, diagonal, projection));
        self.touched = chains;
        self.factored
    }

    /// Factors chain `c`'s band ([`Self::factor`]); `false` if a pivot is not positive definite.
    fn factor_chain(
        &mut self,
        c: usize,
        rows: &ParticleMatrix,
        diagonal: &[DMat3],
        projection: &[DMat3],
    ) -> bool {
        // S_{k+d,k} = (P_k·A_{k,k+d}·P_{k+d})ᵀ for d = 1, 2 (zero where not stored).
        let below = |nodes: &[u32], ahead: &[[u32; 2]], k: usize, d: usize| -> DMat3 {
            let at = ahead[k][d - 1];
            if at == NONE {
                return DMat3::ZERO;
            }
            let i = nodes[k] as usize;
            let (columns, blocks) = rows.row(i);
            let j = columns[at as usize] as usize;
            let block = blocks[at as usize];
            if projection[i] == DMat3::IDENTITY && projection[j] == DMat3::IDENTITY {
                block.transpose()
            } else {
                (projection[i] * block * projection[j]).transpose()
            }
        };
        let Chain { start, len } = self.chains[c];
        // The last two entries' pivots and lower blocks in double precision, as the recurrence
        // needs them ([0]: entry k − 1, [1]: entry k − 2).
        let mut pivots = [DMat3::ZERO; 2];
        let mut lowers = [[DMat3::ZERO; 2]; 2];
        for k in start..start + len {
            let i = self.nodes[k] as usize;
            // D_k = S_kk − Σ_j L_kj·D_j·L_kjᵀ over the two entries before k.
            let mut pivot = diagonal[i];
            for d in 1..=2 {
                if k >= start + d {
                    let l = lowers[d - 1][d - 1];
                    pivot -= l * pivots[d - 1] * l.transpose();
                }
            }
            if !positive_definite(&pivot) {
                return false;
            }
            let inverse = pivot.inverse();
            // L_{k+1,k} = (S_{k+1,k} − L_{k+1,k−1}·D_{k−1}·L_{k,k−1}ᵀ)·D_k⁻¹; L_{k+2,k} = S_{k+2,k}·D_k⁻¹.
            let mut next = below(&self.nodes, &self.ahead, k, 1);
            if k > start {
                next -= lowers[0][1] * pivots[0] * lowers[0][0].transpose();
            }
            let next2 = below(&self.nodes, &self.ahead, k, 2);
            let lower = [next * inverse, next2 * inverse];
            self.pivot_inverse[k] = inverse.as_mat3();
            self.lower[k] = lower.map(|l| l.as_mat3());
            pivots = [pivot, pivots[0]];
            lowers = [lower, lowers[0]];
        }
        true
    }

    /// z = ½·(T_w⁻¹ + T_f⁻¹)·r with the last factors.
    pub fn solve(&mut self, r: &[DVec3], z: &mut [DVec3]) {
        z.fill(DVec3::ZERO);
        // Each chain's substitutions are a chain of dependent products; [`LANES`] neighbouring
        // chains (of similar lengths) advance together so that the processor overlaps them.
        // Each chain's arithmetic is the same as alone, and z sums each node's two terms (its
        // warp and weft chains', which meet in the one group that holds the last warp and first
        // weft chains) from zero, in either order with the same result.
        let chains = std::mem::take(&mut self.chains);
        let mut groups = chains.chunks_exact(LANES);
        for group in groups.by_ref() {
            let group: [Chain; LANES] = std::array::from_fn(|lane| group[lane]);
            self.solve_chains(group, r, z);
        }
        for &chain in groups.remainder() {
            self.solve_chains([chain], r, z);
        }
        self.chains = chains;
    }

    /// The substitutions of `L` distinct chains, advanced in step.
    fn solve_chains<const L: usize>(&mut self, chains: [Chain; L], r: &[DVec3], z: &mut [DVec3]) {
        let longest = chains.iter().map(|c| c.len).max().unwrap_or(0);
        // Forward: y_k = r_k − L_{k,k−1}·y_{k−1} − L_{k,k−2}·y_{k−2}.
        let (mut y1, mut y2) = ([Vec3::ZERO; L], [Vec3::ZERO; L]);
        for step in 0..longest {
            for (lane, chain) in chains.iter().enumerate() {
                if step >= chain.len {
                    continue;
                }
                let k = chain.start + step;
                let mut y = r[self.nodes[k] as usize].as_vec3();
                if step > 0 {
                    y -= self.lower[k - 1][0] * y1[lane];
                }
                if step > 1 {
                    y -= self.lower[k - 2][1] * y2[lane];
                }
                self.work[k] = y;
                (y2[lane], y1[lane]) = (y1[lane], y);
            }
        }
        // Back: x_k = D_k⁻¹·y_k − L_{k+1,k}ᵀ·x_{k+1} − L_{k+2,k}ᵀ·x_{k+2} (the two lower
        // blocks are zero past the chain's end).
        let (mut x1, mut x2) = ([Vec3::ZERO; L], [Vec3::ZERO; L]);
        for step in (0..longest).rev() {
            for (lane, chain) in chains.iter().enumerate() {
                if step >= chain.len {
                    continue;
                }
                let k = chain.start + step;
                let [l1, l2] = &self.lower[k];
                let x = self.pivot_inverse[k] * self.work[k]
                    - transposed_product(l1, x1[lane])
                    - transposed_product(l2, x2[lane]);
                z[self.nodes[k] as usize] += 0.5 * x.as_dvec3();
                (x2[lane], x1[lane]) = (x1[lane], x);
            }
        }
    }
}

/// Chains a solve advances together.
const LANES: usize = 4;

/// Lᵀ·x.
#[inline(always)]
fn transposed_product(l: &Mat3, x: Vec3) -> Vec3 {
    Vec3::new(l.x_axis.dot(x), l.y_axis.dot(x), l.z_axis.dot(x))
}

/// Whether a symmetric 3×3 block is positive definite (Sylvester's criterion; false for NaN).
fn positive_definite(a: &DMat3) -> bool {
    let minor = a.x_axis.x * a.y_axis.y - a.x_axis.y * a.y_axis.x;
    a.x_axis.x > 0.0 && minor > 0.0 && a.determinant() > 0.0
}
