//! A flat, unstressed grid at its rest spacing feels no force from any generator.

use std::sync::Arc;

use glam::DVec3;
use kes_cloth::forces::{
    Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, KesTensile, SeedSeparation,
    Trellising,
};

mod common;

#[test]
fn flat_unstressed_grid_feels_zero_force() {
    for path in common::shipped_fabric_paths() {
        let fabric = kes_cloth::material::Fabric::load(&path).unwrap();
        // A circular cut exercises boundary springs too.
        let topo = Arc::new(ClothTopology::from_mask(21, 21, 0.005, |i, j| {
            let (x, y) = (i as f64 - 10.0, j as f64 - 10.0);
            x * x + y * y <= 100.0
        }));
        // Tilted plane, arbitrary origin: rest is rest in any pose.
        let warp = DVec3::new(1.0, 0.3, 0.0).normalize();
        let weft = warp.cross(DVec3::new(0.2, 1.0, 0.1)).normalize();
        let x = topo.rest_positions(DVec3::new(0.3, -1.0, 2.0), warp, weft);
        let mut geo = ClothGeometry::new(topo.clone());
        geo.update(&x);
        let gens: Vec<Box<dyn ForceGenerator>> = vec![
            Box::new(Bending::new(topo.clone(), &fabric)),
            Box::new(Trellising::new(topo.clone(), &fabric)),
            Box::new(SeedSeparation::new(topo.clone(), &fabric)),
            Box::new(KesTensile::new(topo.clone(), &fabric)),
        ];
        for g in gens {
            let mut buffer = ForceBuffer::new(&topo);
            g.add_forces(&geo, &vec![DVec3::ZERO; x.len()], &mut buffer);
            let f = buffer.resolve(&topo);
            let max = f.iter().map(|v| v.length()).fold(0.0, f64::max);
            // Round-off only: the weight of one particle is ~1e-5 N; 1e-12 N is nothing.
            assert!(
                max < 1e-12,
                "{}: {} gives {max:e} N on a flat grid",
                fabric.name,
                g.effect()
            );
            assert!(g.energy(&geo).abs() < 1e-15, "{}: energy at rest", g.effect());
        }
    }
}
