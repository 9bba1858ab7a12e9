//! The implicit solve's matrix in particle space: Dᵀ·L·D plus the particle diagonal of a
//! [`LinkMatrix`], stored as 3×3 blocks row by row.
//!
//! [`LinkMatrix::product`] visits every link and coupling slot, scatters into links and then
//! into particles: three passes and two scatters a product. Here the same matrix is summed
//! once per solve into each particle's row of blocks (itself and the particles it shares a
//! link or an element with, 13 at most on the woven grid), and each product is one pass of
//! block multiplications that gathers from its neighbours.

use glam::{DMat3, DVec3};

use super::{ClothTopology, LinkMatrix};

/// A sparse symmetric matrix of 3×3 blocks with the coupling pattern of one cloth.
#[derive(Clone, Debug)]
pub struct ParticleMatrix {
    /// Row i's blocks are `block[row_start[i]..row_start[i + 1]]`.
    row_start: Vec<usize>,
    /// Column (particle) of each block.
    column: Vec<u32>,
    block: Vec<DMat3>,
    /// Where each link's four blocks go: (p, p), (q, q), (p, q), (q, p) for link [p, q].
    link_blocks: Vec<[u32; 4]>,
    /// Where each coupling slot's blocks go, for its links a = [p_a, q_a], b = [p_b, q_b]:
    /// (p_a, p_b), (p_a, q_b), (q_a, p_b), (q_a, q_b), then the same transposed.
    slot_blocks: Vec<[u32; 8]>,
    /// Index of each particle's diagonal block.
    diagonal: Vec<u32>,
}

impl ParticleMatrix {
    /// A zero matrix with the pattern of `matrix` on `topology`.
    pub fn new(topology: &ClothTopology, matrix: &LinkMatrix) -> Self {
        let n = topology.particle_count;
        let mut columns: Vec<Vec<u32>> = (0..n as u32).map(|i| vec![i]).collect();
        let mut couple = |i: u32, j: u32| {
            columns[i as usize].push(j);
            columns[j as usize].push(i);
        };
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
        let mut row_start = Vec::with_capacity(n + 1);
        let mut column = Vec::new();
        row_start.push(0);
        for mut row in columns {
            row.sort_unstable();
            row.dedup();
            column.extend(row);
            row_start.push(column.len());
        }
        let index = |i: u32, j: u32| -> u32 {
            let row = &column[row_start[i as usize]..row_start[i as usize + 1]];
            // Every pair looked up here was entered above.
            (row_start[i as usize] + row.binary_search(&j).unwrap_or(0)) as u32
        };
        let link_blocks = topology
            .links
            .iter()
            .map(|&[p, q]| [index(p, p), index(q, q), index(p, q), index(q, p)])
            .collect();
        let slot_blocks = (0..matrix.slot_count())
            .map(|slot| {
                let [(a, _), (b, _)] = matrix.slot_links(slot);
                let ([pa, qa], [pb, qb]) = (topology.links[a], topology.links[b]);
                [
                    index(pa, pb),
                    index(pa, qb),
                    index(qa, pb),
                    index(qa, qb),
                    index(pb, pa),
                    index(qb, pa),
                    index(pb, qa),
                    index(qb, qa),
                ]
            })
            .collect();
        let diagonal = (0..n as u32).map(|i| index(i, i)).collect();
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
        // δd = δx_q − δx_p, and a link's force acts +1 on q, −1 on p.
        for (l, idx) in self.link_blocks.iter().enumerate() {
            let k = matrix.link[l];
            block[idx[0] as usize] += k;
            block[idx[1] as usize] += k;
            block[idx[2] as usize] -= k;
            block[idx[3] as usize] -= k;
        }
        // Slot (a, b) with block C adds C·δd_b to link a's force and Cᵀ·δd_a to link b's.
        for (slot, idx) in self.slot_blocks.iter().enumerate() {
            let c = matrix.coupling_block(slot);
            let t = c.transpose();
            // Signs of (p_a or q_a) × (p_b or q_b): (−)(−), (−)(+), (+)(−), (+)(+).
            for (k, sign) in [1.0, -1.0, -1.0, 1.0].into_iter().enumerate() {
                block[idx[k] as usize] += sign * c;
                block[idx[k + 4] as usize] += sign * t;
            }
        }
        for (d, c) in self.diagonal.iter().zip(&matrix.particle) {
            block[*d as usize] += DMat3::from_diagonal(DVec3::splat(*c));
        }
    }

    /// out = A·x.
    pub fn product(&self, x: &[DVec3], out: &mut [DVec3]) {
        for (i, o) in out.iter_mut().enumerate() {
            let range = self.row_start[i]..self.row_start[i + 1];
            *o = self.column[range.clone()]
                .iter()
                .zip(&self.block[range])
                .map(|(j, b)| *b * x[*j as usize])
                .sum();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::forces::{ForceBuffer, Perturbation};

    #[test]
    fn products_match_the_link_space_matrix() {
        // Every link, coupling slot and particle term filled with a different non-symmetric
        // block, so that a block summed into the wrong place or with the wrong sign shows: the
        // two products agree to round-off (1e-12 of their size).
        let topo = ClothTopology::rectangle(6, 5, 0.01);
        let mut links = LinkMatrix::new(&topo);
        let pseudo = |k: usize| {
            let f = |s: usize| ((k * 7919 + s * 104_729) % 1000) as f64 / 500.0 - 1.0;
            DMat3::from_cols_array(&std::array::from_fn(f))
        };
        for (l, b) in links.link.iter_mut().enumerate() {
            *b = pseudo(l);
        }
        for slot in 0..links.slot_count() {
            links.add_element(slot, (DMat3::ZERO, pseudo(10_000 + slot), DMat3::ZERO));
        }
        for (i, c) in links.particle.iter_mut().enumerate() {
            *c = i as f64 * 0.1;
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
