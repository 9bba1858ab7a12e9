//! `final.obj`: the draped cloth as a Wavefront OBJ triangle mesh (metres, +y up).

use std::fmt::Write as _;
use std::path::Path;

use glam::DVec3;

use super::OutputError;
use crate::forces::ClothTopology;

/// Writes the cloth's triangles at `positions` (m) to `dir/final.obj`.
pub fn write_obj(
    dir: &Path,
    name: &str,
    topology: &ClothTopology,
    positions: &[DVec3],
) -> Result<(), OutputError> {
    let path = dir.join("final.obj");
    let mut text = format!("# kes-cloth: {name}, units: metres, +y up\no cloth\n");
    for p in positions {
        let _ = writeln!(text, "v {:.6} {:.6} {:.6}", p.x, p.y, p.z);
    }
    for t in &topology.triangles {
        // OBJ indices are 1-based; reversed so normals point up for the flat cloth.
        let _ = writeln!(text, "f {} {} {}", t[0] + 1, t[2] + 1, t[1] + 1);
    }
    std::fs::write(&path, text).map_err(|e| OutputError::new(&path, e))
}
