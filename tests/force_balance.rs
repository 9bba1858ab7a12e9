//! The forces of each spring sum to zero and exert no net moment (Newton's third law for a
//! spring that only depends on relative positions, and rotation invariance of its energy).

use std::sync::Arc;

use glam::DVec3;
use kes_cloth::forces::{
    Bending, ClothGeometry, ClothTopology, ForceBuffer, ForceGenerator, KesTensile, SeedSeparation,
    Trellising,
};

mod common;
use common::Rng;

const SIGMA: f64 = 0.005;

/// Largest |Σf| and |Σx×f| relative to the largest force (and force × σ): 1e-12 leaves
/// room for f64 round-off in sums of a handful of terms.
fn assert_balanced(name: &str, x: &[DVec3], f: &[DVec3]) {
    let scale = f.iter().map(|v| v.length()).fold(0.0, f64::max);
    assert!(scale > 0.0, "{name}: no force");
    let sum: DVec3 = f.iter().sum();
    let moment: DVec3 = x.iter().zip(f).map(|(p, v)| p.cross(*v)).sum();
    assert!(sum.length() <= 1e-12 * scale, "{name}: net force {sum:?}");
    assert!(
        moment.length() <= 1e-12 * scale * SIGMA * 10.0,
        "{name}: net moment {moment:?}"
    );
}

fn single_spring_forces(topo: Arc<ClothTopology>, generator: &dyn ForceGenerator, x: &[DVec3]) -> Vec<DVec3> {
    let mut geo = ClothGeometry::new(topo.clone());
    geo.update(x);
    let mut buffer = ForceBuffer::new(&topo);
    generator.add_forces(&geo, &vec![DVec3::ZERO; x.len()], &mut buffer);
    buffer.resolve(&topo).to_vec()
}

#[test]
fn each_spring_has_zero_net_force_and_moment() {
    let fabric = common::shipped_fabric("thick_cotton");
    let mut rng = Rng::new(3);
    // One bending spring (3 crossings on a warp), one link (2 crossings), one trellis corner
    // (an L of three crossings), each placed at random away from the origin.
    let bend = Arc::new(ClothTopology::rectangle(3, 1, SIGMA));
    let link = Arc::new(ClothTopology::rectangle(2, 1, SIGMA));
    let corner = Arc::new(ClothTopology::from_mask(2, 2, SIGMA, |i, j| !(i == 1 && j == 1)));
    assert_eq!(bend.bend_particles.len(), 1);
    assert_eq!(link.links.len(), 1);
    assert_eq!(corner.corner_particles.len(), 1);
    for trial in 0..50 {
        let offset = rng.vec(0.1);
        let place = |topo: &ClothTopology, rng: &mut Rng| -> Vec<DVec3> {
            topo.rest_positions(offset, DVec3::X, DVec3::Z)
                .into_iter()
                .map(|p| p + rng.vec(0.4 * SIGMA))
                .collect()
        };
        let x = place(&bend, &mut rng);
        assert_balanced(
            &format!("bending {trial}"),
            &x,
            &single_spring_forces(bend.clone(), &Bending::new(bend.clone(), &fabric), &x),
        );
        let x = place(&corner, &mut rng);
        assert_balanced(
            &format!("trellis {trial}"),
            &x,
            &single_spring_forces(corner.clone(), &Trellising::new(corner.clone(), &fabric), &x),
        );
        let x = place(&link, &mut rng);
        assert_balanced(
            &format!("seed {trial}"),
            &x,
            &single_spring_forces(link.clone(), &SeedSeparation::new(link.clone(), &fabric), &x),
        );
        assert_balanced(
            &format!("kes {trial}"),
            &x,
            &single_spring_forces(link.clone(), &KesTensile::new(link.clone(), &fabric), &x),
        );
    }
}

#[test]
fn topology_counts_match_a_woven_grid() {
    let t = ClothTopology::rectangle(4, 3, SIGMA);
    assert_eq!(t.particle_count, 12);
    assert_eq!(t.links.len(), 3 * 3 + 4 * 2);
    assert_eq!(t.warp_link_count, 9);
    assert_eq!(t.bend_particles.len(), 2 * 3 + 4);
    assert_eq!(t.warp_bend_count, 6);
    // Every cell has four corners.
    assert_eq!(t.corner_count(), 4 * 3 * 2);
    assert_eq!(t.full_crossings.len(), 2);
}
