//! The implicit solve's matrix in particle space: Dᵀ·L·D plus the particle diagonal of a
//! [`LinkMatrix`], stored as 3×3 blocks row by row.
//!
//! [`LinkMatrix::product`] visits every link and coupling slot, scatters into links and then
//! into particles: three passes and two scatters a product. Here the same matrix is summed
//! once per solve into each particle's row of blocks (the particles it shares a link or an
//! element with, 12.6 on average on the woven grid), and each product is one pass. The
//! product is bound by reading the blocks, not by arithmetic, so only the upper triangle is
//! stored (the matrix is symmetric: its link blocks are, and each coupling enters with its
//! transpose) and each block serves its row and, transposed, its column.

use glam::{DMat3, DVec3};

use super::{ClothTopology, LinkMatrix};

/// A sparse symmetric matrix of 3×3 blocks with the coupling pattern of one cloth, stored as
/// its upper triangle (column ≥ row).
#[derive(Clone, Debug)]
pub struct ParticleMatrix {
    /// Row i's blocks are `block[row_start[i]..row_start[i + 1]]`.
    row_start: Vec<usize>,
    /// Column (particle) of each block.
    column: Vec<u32>,
    block: Vec<DMat3>,
    /// Where each link's blocks go: (p, p), (q, q) and the off-diagonal one, for link [p, q].
    link_blocks: Vec<[Place; 3]>,
    /// Where each coupling slot's blocks go, for its links a = [p_a, q_a], b = [p_b, q_b]:
    /// (p_a, p_b), (p_a, q_b), (q_a, p_b), (q_a, q_b).
    slot_blocks: Vec<[Place; 4]>,
    /// Index of each particle's diagonal block.
    diagonal: Vec<u32>,
}

/// Where the block of a pair (i, j) is stored: at (min, max), transposed if i > j.
#[derive(Clone, Copy, Debug)]
struct Place {
    index: u32,
    transposed: bool,
    diagonal: bool,
}

impl ParticleMatrix {
    /// A zero matrix with the pattern of `matrix` on `topology`.
    pub fn new(topology: &ClothTopology, matrix: &LinkMatrix) -> Self {
        let n = topology.particle_count;
        let mut columns: Vec<Vec<u32>> = (0..n as u32).map(|i| vec![i]).collect();
        let mut couple = |i: u32, j: u32| columns[i.min(j) as usize].push(i.max(j));
        for &[p, q] in &topology.links {
            couple(p, q);
        }
        for slot in 0..matrix.slot_count() {
            let [(a, _), (b, _)] = matrix.slot_links(slot);
            for i in topology.links[a] {
                for j in topology.links[b] {
                    couple(i, j);
                }
            }
        }
        let (row_start, column) = compress_rows(columns);
        let index = |i: u32, j: u32| -> Place {
            let (r, c) = (i.min(j) as usize, i.max(j));
            let row = &column[row_start[r]..row_start[r + 1]];
            // Every pair looked up here was entered above.
            Place {
                index: (row_start[r] + row.binary_search(&c).unwrap_or(0)) as u32,
                transposed: i > j,
                diagonal: i == j,
            }
        };
        let link_blocks = topology
            .links
            .iter()
            .map(|&[p, q]| [index(p, p), index(q, q), index(p, q)])
            .collect();
        let slot_blocks = (0..matrix.slot_count())
            .map(|slot| {
                let [(a, _), (b, _)] = matrix.slot_links(slot);
                let ([pa, qa], [pb, qb]) = (topology.links[a], topology.links[b]);
                [index(pa, pb), index(pa, qb), index(qa, pb), index(qa, qb)]
            })
            .collect();
        let diagonal = (0..n as u32).map(|i| index(i, i).index).collect();
        Self {
            block: vec![DMat3::ZERO; column.len()],
            row_start,
            column,
            link_blocks,
            slot_blocks,
            diagonal,
        }
    }

    /// Sums `matrix` (Dᵀ·L·D plus its particle diagonal) into the blocks, replacing what they
    /// held.
    pub fn assemble(&mut self, matrix: &LinkMatrix) {
        self.block.fill(DMat3::ZERO);
        let block = &mut self.block;
        // δd = δx_q − δx_p, and a link's force acts +1 on q, −1 on p: (p, p) and (q, q) get
        // the link's block, (p, q) and (q, p) its negative (one stored block: it is symmetric).
        for (l, [pp, qq, pq]) in self.link_blocks.iter().enumerate() {
            let k = matrix.link[l];
            block[pp.index as usize] += k;
            block[qq.index as usize] += k;
            block[pq.index as usize] -= k;
        }
        // Slot (a, b) with block C adds C·δd_b to link a's force and Cᵀ·δd_a to link b's: (i, j)
        // gets ±C for i on link a, j on link b, and (j, i) its transpose. A pair on the
        // diagonal (the particle both links share) gets both.
        for (slot, places) in self.slot_blocks.iter().enumerate() {
            let c = matrix.coupling_block(slot);
            // Signs of (p_a or q_a) × (p_b or q_b): (−)(−), (−)(+), (+)(−), (+)(+).
            for (place, sign) in places.iter().zip([1.0, -1.0, -1.0, 1.0]) {
                let b = &mut block[place.index as usize];
                if place.diagonal {
                    *b += sign * (c + c.transpose());
                } else if place.transposed {
                    *b += sign * c.transpose();
                } else {
                    *b += sign * c;
                }
            }
        }
        for (d, c) in self.diagonal.iter().zip(&matrix.particle) {
            block[*d as usize] += *c;
        }
    }

    /// Number of particles (block rows).
    pub fn particle_count(&self) -> usize {
        self.row_start.len() - 1
    }

    /// Row `i`'s stored blocks: their columns (ascending, the first one `i` itself) and the
    /// blocks A_ij.
    pub fn row(&self, i: usize) -> (&[u32], &[DMat3]) {
        let range = self.row_start[i]..self.row_start[i + 1];
        (&self.column[range.clone()], &self.block[range])
    }

    /// out = A·x.
    pub fn product(&self, x: &[DVec3], out: &mut [DVec3]) {
        out.fill(DVec3::ZERO);
        for (i, &xi) in x.iter().enumerate() {
            let (first, end) = (self.row_start[i], self.row_start[i + 1]);
            // The row's first block is its diagonal (columns ascend from i).
            let mut yi = out[i] + self.block[first] * xi;
            for (j, b) in self.column[first + 1..end]
                .iter()
                .zip(&self.block[first + 1..end])
            {
                let j = *j as usize;
                yi += *b * x[j];
                out[j] += DVec3::new(b.x_axis.dot(xi), b.y_axis.dot(xi), b.z_axis.dot(xi));
            }
            out[i] = yi;
        }
    }
}

/// Each row's columns sorted and deduplicated, concatenated: (row starts, columns), row i's
/// columns at `columns[starts[i]..starts[i + 1]]`.
pub(crate) fn compress_rows(rows: Vec<Vec<u32>>) -> (Vec<usize>, Vec<u32>) {
    let mut starts = Vec::with_capacity(rows.len() + 1);
    let mut columns = Vec::new();
    starts.push(0);
    for mut row in rows {
        row.sort_unstable();
        row.dedup();
        columns.extend(row);
        starts.push(columns.len());
    }
    (starts, columns)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::{ForceBuffer, Perturbation};

    #[test]
    fn products_match_the_link_space_matrix() {
        // Every link (symmetric, as every effect's are), coupling slot (not symmetric) and
        // particle term filled with a different block, so that a block summed into the wrong
        // place, with the wrong sign or untransposed shows: the two products agree to round-off
        // (1e-12 of their size).
        let topo = ClothTopology::rectangle(6, 5, 0.01);
        let mut links = LinkMatrix::new(&topo);
        let pseudo = |k: usize| {
            let f = |s: usize| ((k * 7919 + s * 104_729) % 1000) as f64 / 500.0 - 1.0;
            DMat3::from_cols_array(&std::array::from_fn(f))
        };
        for (l, b) in links.link.iter_mut().enumerate() {
            *b = pseudo(l) + pseudo(l).transpose();
        }
        for slot in 0..links.slot_count() {
            links.add_element(slot, (DMat3::ZERO, pseudo(10_000 + slot), DMat3::ZERO));
        }
        for (i, c) in links.particle.iter_mut().enumerate() {
            *c = pseudo(20_000 + i) + pseudo(20_000 + i).transpose();
        }
        let mut rows = ParticleMatrix::new(&topo, &links);
        rows.assemble(&links);
        let x: Vec<DVec3> = (0..topo.particle_count)
            .map(|i| DVec3::new(i as f64, (i * i % 7) as f64, -(i as f64).sqrt()))
            .collect();
        let mut pert = Perturbation::new(&topo);
        pert.set(&topo, &x);
        let mut buffer = ForceBuffer::new(&topo);
        let expected = links.product(&topo, &pert, &mut buffer).to_vec();
        let mut got = vec![DVec3::ZERO; x.len()];
        rows.product(&x, &mut got);
        let scale = expected.iter().map(|v| v.length()).fold(0.0, f64::max);
        for (i, (e, g)) in expected.iter().zip(&got).enumerate() {
            assert!(
                (*e - *g).length() <= 1e-12 * scale,
                "particle {i}: {g} against {e}"
            );
        }
    }
}
