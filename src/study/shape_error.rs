//! Shape error: how far a draped cloth's nodes lie from the reference's draped surface.

use glam::{DVec3, Vec3};
use parry3d::query::PointQuery;
use parry3d::shape::TriMesh;

use crate::forces::ClothTopology;

/// The reference run's draped surface, as a triangle mesh.
pub struct ReferenceSurface {
    mesh: TriMesh,
}

impl ReferenceSurface {
    /// The surface of the cloth `topology` at `positions` (m); `None` if it has no triangles
    /// or a non-finite position (a failed reference).
    pub fn new(topology: &ClothTopology, positions: &[DVec3]) -> Option<Self> {
        if topology.triangles.is_empty() || positions.iter().any(|p| !p.is_finite()) {
            return None;
        }
        let vertices: Vec<Vec3> = positions.iter().map(|p| p.as_vec3()).collect();
        TriMesh::new(vertices, topology.triangles.clone())
            .ok()
            .map(|mesh| Self { mesh })
    }

    /// Root-mean-square distance (m) of `points` from the surface (f32 geometry: ~10⁻⁸ m).
    pub fn rms_distance(&self, points: &[DVec3]) -> f64 {
        if points.is_empty() {
            return 0.0;
        }
        let sum: f64 = points
            .iter()
            .map(|p| {
                let q = self.mesh.project_local_point(p.as_vec3(), false).point;
                (q.as_dvec3() - *p).length_squared()
            })
            .sum();
        (sum / points.len() as f64).sqrt()
    }
}
