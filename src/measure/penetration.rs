//! How deep node centres sit inside the true (unshrunk) colliders.
//!
//! Node centres should rest on collider surfaces (colliders are shrunk by the node radius; see
//! `bodies/world_colliders.rs`), so any depth here is a contact error.

use glam::DVec3;

use crate::bodies::WorldShape;

/// Depth (m) of point `p` inside `shape` centred at `centre`; 0 outside.
pub fn depth_inside(shape: &WorldShape, centre: DVec3, p: DVec3) -> f64 {
    let d = p - centre;
    let depth = match *shape {
        WorldShape::Cylinder { radius, half_height } => {
            let radial = radius - (d.x * d.x + d.z * d.z).sqrt();
            radial.min(half_height - d.y.abs())
        }
        WorldShape::Cuboid {
            half_extents: [x, y, z],
        } => (x - d.x.abs()).min(y - d.y.abs()).min(z - d.z.abs()),
        WorldShape::Ball { radius } => radius - d.length(),
    };
    depth.max(0.0)
}

/// The deepest node: (depth (m), node index); (0, 0) if none is inside.
pub fn max_penetration(colliders: &[(WorldShape, DVec3)], positions: &[DVec3]) -> (f64, usize) {
    let mut worst = (0.0, 0);
    for (i, p) in positions.iter().enumerate() {
        for (shape, centre) in colliders {
            let d = depth_inside(shape, *centre, *p);
            if d > worst.0 {
                worst = (d, i);
            }
        }
    }
    worst
}
