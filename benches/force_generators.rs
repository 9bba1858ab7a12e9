//! Cost of one evaluation of all KES force generators on a 100 × 100 grid (10 000 particles),
//! including the shared link-geometry pass. Criterion reports time per evaluation and, through
//! the element throughput, particles per second; ns per particle = 1e9 / (elements/s).
//! Target: ≤ 60 ns per particle on one core. The last entries time the implicit
//! solve's per-step assembly and one CG product: assembled in link space, summed into
//! particle rows (what the solve multiplies by), and matrix-free.

use std::hint::black_box;
use std::sync::Arc;

use criterion::{Criterion, Throughput, criterion_group, criterion_main};
use glam::DVec3;
use kes_cloth::forces::{
    Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, Hysteresis, KesTensile,
    LinkCompression, LinkDamping, LinkMatrix, ParticleMatrix, Perturbation, SeedSeparation, Trellising,
};
use kes_cloth::material::Fabric;

const N: usize = 100;
const SIGMA: f64 = 0.005;

fn draped_positions(topo: &ClothTopology) -> Vec<DVec3> {
    // A gently waved, slightly sheared and stretched sheet: every spring is loaded.
    topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::new(0.05, 0.0, 1.0).normalize())
        .into_iter()
        .map(|p| DVec3::new(p.x * 1.01, 0.01 * (p.x * 40.0).sin() * (p.z * 30.0).cos(), p.z))
        .collect()
}

fn bench(c: &mut Criterion) {
    let fabric = Fabric::load(concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/assets/fabrics/thick_cotton.ron"
    ))
    .expect("fabric");
    let topo = Arc::new(ClothTopology::rectangle(N, N, SIGMA));
    let x = draped_positions(&topo);
    let v = vec![DVec3::ZERO; x.len()];
    let mut geo = ClothGeometry::new(topo.clone());
    let mut f = ForceBuffer::new(&topo);
    let bending = Bending::new(topo.clone(), &fabric);
    let trellising = Trellising::new(topo.clone(), &fabric);
    let kes = KesTensile::new(topo.clone(), &fabric);
    let seed = SeedSeparation::new(topo.clone(), &fabric);
    // The shipped scenes' set: stretch by Rapier joints plus our compression spring, damping.
    let node_mass = fabric.areal_density * SIGMA * SIGMA;
    let compression = LinkCompression::new(topo.clone(), LinkCompression::default_modulus(&fabric, SIGMA));
    let damping = LinkDamping::new(topo.clone(), 150.0, node_mass);

    let mut group = c.benchmark_group("force_generators_100x100");
    group.throughput(Throughput::Elements((N * N) as u64));
    let sets: [(&str, Vec<&dyn ForceGenerator>); 8] = [
        ("geometry_only", vec![]),
        (
            "shipped_scene_set",
            vec![&bending, &trellising, &compression, &damping],
        ),
        ("bending_trellising", vec![&bending, &trellising]),
        ("all_kes_tensile", vec![&bending, &trellising, &kes]),
        ("all_seed_separation", vec![&bending, &trellising, &seed]),
        ("bending_only", vec![&bending]),
        ("trellising_only", vec![&trellising]),
        ("kes_tensile_only", vec![&kes]),
    ];
    for (name, gens) in sets {
        group.bench_function(name, |b| {
            b.iter(|| {
                geo.update(black_box(&x));
                f.clear();
                for g in &gens {
                    g.add_forces(&geo, &v, &mut f);
                }
                black_box(f.resolve(&topo));
            })
        });
    }
    // Hysteresis: the per-step state advance and the forces, on the loaded sheet after one
    // advance from the flat sheet (so the elements carry friction).
    let mut hysteresis = Hysteresis::new(topo.clone(), &fabric, true, true);
    geo.update(&topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z));
    hysteresis.advance_state(&geo);
    geo.update(&x);
    hysteresis.advance_state(&geo);
    group.bench_function("hysteresis_forces", |b| {
        b.iter(|| {
            f.clear();
            hysteresis.add_forces(black_box(&geo), &v, &mut f);
            black_box(f.resolve(&topo));
        })
    });
    group.bench_function("hysteresis_advance", |b| {
        b.iter(|| hysteresis.advance_state(black_box(&geo)))
    });
    // The implicit solve's two costs for the shipped scene set at 1/240 s: assembling h²H + hC
    // once per step, and one CG product with the assembled matrix (a solve takes 20-60).
    geo.update(&x);
    let h = 1.0 / 240.0;
    let shipped: [&dyn ForceGenerator; 4] = [&bending, &trellising, &compression, &damping];
    let mut matrix = LinkMatrix::new(&topo);
    let assemble = |matrix: &mut LinkMatrix| {
        matrix.clear();
        for g in shipped {
            g.add_stiffness_blocks(&geo, h * h, matrix);
            g.add_damping_blocks(h, matrix);
        }
    };
    group.bench_function("implicit_assembly_shipped_set", |b| {
        b.iter(|| assemble(black_box(&mut matrix)))
    });
    assemble(&mut matrix);
    let mut dx = Perturbation::new(&topo);
    dx.set(&topo, &x);
    group.bench_function("implicit_product_assembled", |b| {
        b.iter(|| {
            dx.set(&topo, black_box(&x));
            black_box(matrix.product(&topo, &dx, &mut f).len())
        })
    });
    let mut rows = ParticleMatrix::new(&topo, &matrix);
    group.bench_function("implicit_rows_assembly", |b| {
        b.iter(|| rows.assemble(black_box(&matrix)))
    });
    let mut out = vec![DVec3::ZERO; x.len()];
    group.bench_function("implicit_product_particle_rows", |b| {
        b.iter(|| rows.product(black_box(&x), &mut out))
    });
    group.bench_function("implicit_product_matrix_free", |b| {
        b.iter(|| {
            dx.set(&topo, black_box(&x));
            f.clear();
            for g in shipped {
                g.add_stiffness_product(&geo, &dx, h * h, true, &mut f);
                g.add_damping_product(&dx, h, &mut f);
            }
            black_box(f.resolve(&topo).len())
        })
    });
    group.finish();
}

criterion_group!(benches, bench);
criterion_main!(benches);
