//! Every force generator's force is minus the gradient of its energy.
//!
//! Central finite differences of the energy in f64 (step 1e-7·σ: truncation error ~(1e-7)²,
//! round-off ~1e-16·E/(1e-7·σ·F) ≈ 1e-9 relative) must match the analytic forces to a relative
//! 1e-5 of the largest force, on random, bent, folded (θ < π/4) and sheared (up to 60°)
//! configurations, for every shipped fabric and for sampled curves.

use std::sync::Arc;

use glam::DVec3;
use kes_cloth::forces::{
    Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, KesTensile, SeedSeparation,
    Trellising,
};
use kes_cloth::material::Fabric;

mod common;

const SIGMA: f64 = 0.005;
const NU: usize = 7;
const NV: usize = 5;

fn generators(topo: &Arc<ClothTopology>, fabric: &Fabric) -> Vec<Box<dyn ForceGenerator>> {
    vec![
        Box::new(Bending::new(topo.clone(), fabric)),
        Box::new(Trellising::new(topo.clone(), fabric)),
        Box::new(SeedSeparation::new(topo.clone(), fabric)),
        Box::new(KesTensile::new(topo.clone(), fabric)),
    ]
}

fn check_gradient(name: &str, generator: &dyn ForceGenerator, topo: &Arc<ClothTopology>, x: &[DVec3]) {
    let mut geo = ClothGeometry::new(topo.clone());
    geo.update(x);
    let mut buffer = ForceBuffer::new(topo);
    generator.add_forces(&geo, &vec![DVec3::ZERO; x.len()], &mut buffer);
    let forces = buffer.resolve(topo).to_vec();
    let scale = forces.iter().map(|f| f.abs().max_element()).fold(0.0, f64::max);
    assert!(scale > 0.0, "{name}: {} produced no force", generator.effect());
    let h = 1e-7 * SIGMA;
    let mut xp = x.to_vec();
    for p in 0..x.len() {
        for axis in 0..3 {
            let original = xp[p][axis];
            xp[p][axis] = original + h;
            geo.update(&xp);
            let e_plus = generator.energy(&geo);
            xp[p][axis] = original - h;
            geo.update(&xp);
            let e_minus = generator.energy(&geo);
            xp[p][axis] = original;
            let fd = -(e_plus - e_minus) / (2.0 * h);
            let analytic = forces[p][axis];
            assert!(
                (fd - analytic).abs() <= 1e-5 * scale,
                "{name}, {}: particle {p} axis {axis}: analytic {analytic:e}, finite difference {fd:e} (scale {scale:e})",
                generator.effect()
            );
        }
    }
}

fn check_fabric(fabric: &Fabric) {
    let topo = Arc::new(common::patched_rectangle(NU, NV, SIGMA));
    for (name, x) in common::strained_configurations(&topo) {
        for g in generators(&topo, fabric) {
            check_gradient(&format!("{} / {name}", fabric.name), g.as_ref(), &topo, &x);
        }
    }
}

#[test]
fn forces_are_minus_energy_gradient_for_every_shipped_fabric() {
    for path in common::shipped_fabric_paths() {
        check_fabric(&Fabric::load(&path).unwrap());
    }
}

#[test]
fn forces_are_minus_energy_gradient_with_sampled_curves() {
    check_fabric(&Fabric::load(common::crate_path("tests/fabrics/sampled_curves.ron")).unwrap());
}
