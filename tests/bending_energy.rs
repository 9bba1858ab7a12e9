//! For a linear M = B·K the bending energy is B·(1 + cos θ) for θ > π/4, whatever σ.

use std::sync::Arc;

use glam::DVec3;
use kes_cloth::forces::{Bending, ClothGeometry, ClothTopology, ForceGenerator};

mod common;

#[test]
fn linear_bending_energy_is_b_one_plus_cos_theta_for_any_spacing() {
    let fabric = common::shipped_fabric("thick_cotton");
    let b = fabric.bending[0].rigidity;
    for sigma in [0.002, 0.005, 0.0127] {
        // One warp bending spring: three crossings along the warp.
        let topo = Arc::new(ClothTopology::rectangle(3, 1, sigma));
        let bending = Bending::new(topo.clone(), &fabric);
        let mut geo = ClothGeometry::new(topo);
        for theta in [std::f64::consts::PI, 2.5, 2.0, 1.2, 0.8] {
            let a = DVec3::new(-sigma, 0.0, 0.0);
            let c = sigma * DVec3::new(-theta.cos(), theta.sin(), 0.0);
            geo.update(&[a, DVec3::ZERO, c]);
            let expected = b * (1.0 + theta.cos());
            let e = bending.energy(&geo);
            // 1e-12 relative: both sides are closed forms of the same quantity.
            assert!(
                (e - expected).abs() <= 1e-12 * b,
                "σ = {sigma}, θ = {theta}: {e} vs {expected}"
            );
        }
    }
}
