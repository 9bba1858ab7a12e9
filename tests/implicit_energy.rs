//! Backward Euler on our forces alone (no Rapier): a sheared or bent sample of thick cotton with
//! the KES tensile law, released at 1/240 s and 1/60 s (17 and 67 times its explicit limit),
//! stays finite and loses energy at every step. The tolerance, 1e-9 of the starting energy,
//! only admits round-off once the sample has come to rest (energies then reach ~1e-16 J).

use std::sync::Arc;

use glam::DVec3;
use kes_cloth::forces::{
    Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, KesTensile, LinkDamping, Trellising,
};
use kes_cloth::implicit::{ImplicitSettings, ImplicitSolver};

mod common;

fn total_energy(gens: &[Option<&dyn ForceGenerator>], geo: &ClothGeometry, v: &[DVec3], m: f64) -> f64 {
    let kinetic: f64 = v.iter().map(|v| 0.5 * m * v.length_squared()).sum();
    kinetic + gens.iter().flatten().map(|g| g.energy(geo)).sum::<f64>()
}

#[test]
fn released_sheared_sample_loses_energy_at_large_steps() {
    let fabric = common::shipped_fabric("thick_cotton");
    let sigma = 0.01;
    let topo = Arc::new(ClothTopology::rectangle(15, 15, sigma));
    let configs = common::strained_configurations(&topo);
    let m = fabric.areal_density * sigma * sigma;
    let bending = Bending::new(topo.clone(), &fabric);
    let trellising = Trellising::new(topo.clone(), &fabric);
    let tensile = KesTensile::new(topo.clone(), &fabric);
    let damping = LinkDamping::new(topo.clone(), 150.0, m);
    let gens: [Option<&dyn ForceGenerator>; 4] =
        [Some(&bending), Some(&trellising), Some(&tensile), Some(&damping)];
    for (name, start) in configs
        .iter()
        .filter(|(n, _)| n.starts_with("sheared") || n == "bent")
    {
        for h in [1.0 / 240.0, 1.0 / 60.0] {
            let mut x = start.clone();
            let mut v = vec![DVec3::ZERO; x.len()];
            let mut geo = ClothGeometry::new(topo.clone());
            let mut buffer = ForceBuffer::new(&topo);
            let mut solver = ImplicitSolver::new(topo.clone(), m, ImplicitSettings::default());
            geo.update(&x);
            let mut energy = total_energy(&gens, &geo, &v, m);
            let initial = energy;
            for step in 0..200 {
                buffer.clear();
                for g in gens.iter().flatten() {
                    g.add_forces(&geo, &v, &mut buffer);
                }
                buffer.resolve(&topo);
                solver.solve(&gens, &geo, &v, &mut buffer.particle, (h, glam::DVec3::ZERO));
                for ((x, v), f) in x.iter_mut().zip(&mut v).zip(&buffer.particle) {
                    *v += *f * (h / m);
                    *x += *v * h;
                }
                geo.update(&x);
                let next = total_energy(&gens, &geo, &v, m);
                assert!(next.is_finite(), "{name}, h = {h}: non-finite at step {step}");
                assert!(
                    next <= energy + 1e-9 * initial,
                    "{name}, h = {h}: energy rose at step {step}: {energy:e} → {next:e}"
                );
                energy = next;
            }
        }
    }
}
