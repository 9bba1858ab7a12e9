//! A fabric defined in code from KES values (no file), converted to SI, then draped on the
//! seed's drapemeter. Prints the SI values and the drape coefficient.

use glam::DVec3;
use kes_cloth::embed::{ClothBuilder, ClothOutline, prepare_world};
use kes_cloth::material::{
    Fabric, KesBending, KesCurves, KesFabric, KesShear, KesTensile, PerThread, Thread,
};
use kes_cloth::measure::{measure_drape, project};
use rapier3d::prelude::*;

fn main() -> Result<(), Box<dyn std::error::Error>> {
    let kes = KesFabric {
        name: "linen (example)".into(),
        source: "Invented for this example; within published ranges for linen".into(),
        weight_mg_per_cm2: 18.0,
        thickness_mm: 0.5,
        bending: PerThread {
            warp: KesBending {
                b: 0.25,
                two_hb: 0.20,
            },
            weft: KesBending {
                b: 0.20,
                two_hb: 0.15,
            },
        },
        shear: KesShear {
            g: 1.2,
            two_hg: 1.5,
            two_hg5: 3.0,
        },
        tensile: PerThread {
            warp: KesTensile {
                lt: 0.7,
                wt: 5.25,
                rt: 40.0,
                emt: 3.0,
            },
            weft: KesTensile {
                lt: 0.7,
                wt: 7.0,
                rt: 40.0,
                emt: 4.0,
            },
        },
        tensile_max_load_gf_per_cm: 500.0,
        curves: KesCurves::default(),
    };
    let fabric = Fabric::from_kes(&kes)?;
    println!(
        "{}: ρ_A {:.3} kg/m², B_warp {:.3e} N·m, G {:.2} N/m per rad, bending length {:.1} mm",
        fabric.name,
        fabric.areal_density,
        fabric.bending(Thread::Warp).rigidity,
        fabric.shear.rigidity,
        fabric.bending_length(Thread::Warp) * 1e3
    );

    // Rapier's default step, 1/60 s: beyond this fabric's explicit limit, so the builder
    // integrates it implicitly.
    let mut world = PhysicsWorld::default();
    prepare_world(&mut world.integration_parameters);
    // The seed's drapemeter: a 12.7 cm disk, its top at y = 0. The cloth rests on it with its
    // lower face, the disk's shape as it is.
    world.insert_collider(
        ColliderBuilder::cylinder(0.025, 0.0635)
            .translation(Vector::new(0.0, -0.025, 0.0))
            .build(),
        None,
    );
    let builder = ClothBuilder::new(fabric)
        .outline(ClothOutline::Circle(0.254))
        .spacing(0.01)
        .pose(DVec3::new(0.0, 0.005, 0.0), 0.0)
        .rest_on_lower_face(true);
    let (topology, flat) = builder.grid();
    let mut cloth = builder.build(&mut world)?;
    let seconds = 3.0;
    for _ in 0..(seconds / world.integration_parameters.dt).round() as usize {
        cloth.step(&mut world)?;
    }
    let m = measure_drape(
        &project(&topology.triangles, cloth.positions()),
        &project(&topology.triangles, &flat),
        glam::DVec2::ZERO,
        0.0635,
        topology.spacing / 50.0,
        2.0 * topology.spacing,
    );
    println!(
        "after {seconds} s on the drapemeter: DC {:.3}, {} nodes, lowest point {:.3} m, fastest node {:.1} mm/s",
        m.drape_coefficient,
        m.nodes,
        cloth.lowest_point(),
        cloth.motion().max_speed * 1e3
    );
    Ok(())
}
