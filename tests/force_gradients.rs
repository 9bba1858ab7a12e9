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
use common::Rng;

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

/// Named test configurations of an NU × NV grid (particle (i, j) at index i·NV + j).
fn configurations(topo: &ClothTopology) -> Vec<(String, Vec<DVec3>)> {
    let mut rng = Rng::new(7);
    let flat = topo.rest_positions(DVec3::ZERO, DVec3::X, DVec3::Z);
    let mut configs = Vec::new();
    for seed in 0..3 {
        let noisy: Vec<DVec3> = flat.iter().map(|p| *p + rng.vec(0.25 * SIGMA)).collect();
        configs.push((format!("random {seed}"), noisy));
    }
    // Wrapped round a cylinder of radius 1.2σ about the weft (z) axis: θ ≈ 130°.
    let r = 1.2 * SIGMA;
    let bent = flat
        .iter()
        .map(|p| {
            let a = p.x / r;
            DVec3::new(r * a.sin(), r * (1.0 - a.cos()), p.z) + rng.vec(0.02 * SIGMA)
        })
        .collect();
    configs.push(("bent".into(), bent));
    // Folded back on itself at i = 3 with an opening angle of 0.5 rad and 0.2 rad (< π/4).
    for fold in [0.5f64, 0.2] {
        let folded = topo
            .grid_coords
            .iter()
            .map(|&(i, j)| {
                let (i, z) = (i as f64, j as f64 * SIGMA);
                let p = if i <= 3.0 {
                    DVec3::new(i * SIGMA, 0.0, z)
                } else {
                    let s = (i - 3.0) * SIGMA;
                    DVec3::new(3.0 * SIGMA - s * fold.cos(), s * fold.sin(), z)
                };
                p + rng.vec(0.01 * SIGMA)
            })
            .collect();
        configs.push((format!("folded {fold} rad"), folded));
    }
    // Sheared: the weft leans towards the warp by φ.
    for phi_deg in [20.0f64, 45.0, 60.0] {
        let phi = phi_deg.to_radians();
        let weft = DVec3::new(phi.sin(), 0.0, phi.cos());
        let sheared = topo
            .rest_positions(DVec3::ZERO, DVec3::X, weft)
            .into_iter()
            .map(|p| p + rng.vec(0.02 * SIGMA))
            .collect();
        configs.push((format!("sheared {phi_deg}°"), sheared));
    }
    configs
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
    let topo = Arc::new(ClothTopology::rectangle(NU, NV, SIGMA));
    for (name, x) in configurations(&topo) {
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
