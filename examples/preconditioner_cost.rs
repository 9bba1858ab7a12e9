//! What each preconditioner of the implicit solve costs, against one product, at about 2k, 8k,
//! 32k and 100k nodes: the sparse Cholesky factor's symbolic analysis (once per cloth), numeric
//! factorisation and one application, the thread lines' factorisation and one application, the
//! two-level coarse correction's (4 times coarser) Galerkin product with its factorisation and
//! one application, and one product of the particle-row matrix (what every conjugate-gradient iteration multiplies
//! by).
//!
//! The matrix is a square sheet's, with every link, bending and trellis block filled (its
//! values do not change the costs, its pattern does). Run:
//!
//! ```text
//! cargo run --release --example preconditioner_cost [MAX_NODES]
//! ```

use std::time::Instant;

use glam::{DMat3, DVec3};
use kes_cloth::forces::{ClothTopology, LinkMatrix, ParticleMatrix};
use kes_cloth::implicit::{CoarseGrid, SparseCholesky, ThreadLines};

/// Mean wall time (ms) of `f` over `reps` calls.
fn time_ms(reps: usize, mut f: impl FnMut()) -> f64 {
    let start = Instant::now();
    for _ in 0..reps {
        f();
    }
    start.elapsed().as_secs_f64() * 1e3 / reps as f64
}

fn main() {
    let max_nodes: usize = std::env::args()
        .nth(1)
        .and_then(|a| a.parse().ok())
        .unwrap_or(110_000);
    println!(
        "| nodes | product | Cholesky: analysis | factor | apply | factor entries | thread lines: factor | apply | coarse (4×): nodes | form + factor | apply |"
    );
    println!("|---|---|---|---|---|---|---|---|---|---|---|");
    for side in [45usize, 90, 180, 320].into_iter().filter(|s| s * s <= max_nodes) {
        let topo = ClothTopology::rectangle(side, side, 0.0025);
        let mut links = LinkMatrix::new(&topo);
        for b in links.link.iter_mut() {
            *b = DMat3::from_diagonal(DVec3::new(3.0, 1.0, 0.5)) * 1e-3;
        }
        for slot in 0..links.slot_count() {
            links.add_element(
                slot,
                (DMat3::ZERO, DMat3::from_diagonal(DVec3::splat(1e-6)), DMat3::ZERO),
            );
        }
        let mut rows = ParticleMatrix::new(&topo, &links);
        rows.assemble(&links);
        let n = topo.particle_count;
        let masses = vec![1e-4; n];
        let projection = vec![DMat3::IDENTITY; n];
        let drag = vec![0.0; n];
        let diagonal: Vec<DMat3> = (0..n)
            .map(|i| rows.row(i).1[0] + DMat3::from_diagonal(DVec3::splat(masses[i])))
            .collect();
        let r = vec![DVec3::ONE; n];
        let mut z = vec![DVec3::ZERO; n];

        let product = time_ms(50, || rows.product(&r, &mut z));
        let mut cholesky = None;
        let analysis = time_ms(1, || cholesky = SparseCholesky::new(&rows));
        let mut cholesky = cholesky.expect("the sheet's pattern is analysed");
        let factor = time_ms(3, || assert!(cholesky.factor(&rows, &masses, &projection, &drag)));
        let apply = time_ms(10, || cholesky.solve(&r, &mut z));
        let mut lines = ThreadLines::new(&topo, &rows);
        let lines_factor = time_ms(10, || assert!(lines.factor(&rows, &diagonal, &projection)));
        let lines_apply = time_ms(50, || lines.solve(&r, &mut z));
        let mut coarse = CoarseGrid::new(&topo, &rows, 4).expect("the coarse pattern is analysed");
        let coarse_factor = time_ms(10, || assert!(coarse.factor(&rows, &diagonal, &projection)));
        let coarse_apply = time_ms(50, || coarse.add_correction(&r, &mut z));
        println!(
            "| {n} | {product:.3} ms | {analysis:.0} ms | {factor:.0} ms | {apply:.2} ms | {} | {lines_factor:.2} ms | {lines_apply:.3} ms | {} | {coarse_factor:.2} ms | {coarse_apply:.3} ms |",
            cholesky.factor_entries(),
            coarse.coarse_nodes()
        );
    }
}
