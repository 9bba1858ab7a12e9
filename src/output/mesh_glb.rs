//! `final.glb`: the draped mesh as binary glTF 2.0 (positions in metres, +y up, per-vertex
//! normals, one double-sided cloth-coloured material), for 3D tools and the report's viewer.

use std::path::Path;

use glam::DVec3;
use serde_json::json;

use super::OutputError;
use crate::forces::ClothTopology;

/// glTF's component types and buffer targets.
const FLOAT: u32 = 5126;
const UNSIGNED_INT: u32 = 5125;
const ARRAY_BUFFER: u32 = 34962;
const ELEMENT_ARRAY_BUFFER: u32 = 34963;

/// Unit normal at every node (the cloth's surface normal, as contacts use it); straight up
/// where a node's triangles cancel.
fn vertex_normals(topology: &ClothTopology, positions: &[DVec3]) -> Vec<DVec3> {
    let mut normals = Vec::new();
    crate::bodies::sheet_normals(topology, positions, &mut normals);
    for n in &mut normals {
        if *n == DVec3::ZERO {
            *n = DVec3::Y;
        }
    }
    normals
}

/// The GLB bytes of the mesh named `name`.
pub fn glb_bytes(name: &str, topology: &ClothTopology, positions: &[DVec3]) -> Vec<u8> {
    let mut bin: Vec<u8> = Vec::new();
    for p in positions {
        for v in p.as_vec3().to_array() {
            bin.extend_from_slice(&v.to_le_bytes());
        }
    }
    let positions_len = bin.len();
    for n in vertex_normals(topology, positions) {
        for v in n.as_vec3().to_array() {
            bin.extend_from_slice(&v.to_le_bytes());
        }
    }
    let normals_len = bin.len() - positions_len;
    for t in &topology.triangles {
        for i in t {
            bin.extend_from_slice(&i.to_le_bytes());
        }
    }
    let indices_len = bin.len() - positions_len - normals_len;
    let (lo, hi) = positions.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(lo, hi), p| (lo.min(*p), hi.max(*p)),
    );
    let (lo, hi) = (lo.as_vec3().to_array(), hi.as_vec3().to_array());
    let document = json!({
        "asset": {"version": "2.0", "generator": "kes-cloth"},
        "scene": 0,
        "scenes": [{"nodes": [0]}],
        "nodes": [{"mesh": 0, "name": name}],
        "materials": [{
            "name": "cloth",
            "doubleSided": true,
            "pbrMetallicRoughness": {
                "baseColorFactor": [0.85, 0.78, 0.62, 1.0],
                "metallicFactor": 0.0,
                "roughnessFactor": 0.9
            }
        }],
        "meshes": [{"name": name, "primitives": [{
            "attributes": {"POSITION": 0, "NORMAL": 1},
            "indices": 2,
            "material": 0
        }]}],
        "buffers": [{"byteLength": bin.len()}],
        "bufferViews": [
            {"buffer": 0, "byteOffset": 0, "byteLength": positions_len, "target": ARRAY_BUFFER},
            {"buffer": 0, "byteOffset": positions_len, "byteLength": normals_len, "target": ARRAY_BUFFER},
            {"buffer": 0, "byteOffset": positions_len + normals_len, "byteLength": indices_len,
             "target": ELEMENT_ARRAY_BUFFER}
        ],
        "accessors": [
            {"bufferView": 0, "componentType": FLOAT, "count": positions.len(), "type": "VEC3",
             "min": lo, "max": hi},
            {"bufferView": 1, "componentType": FLOAT, "count": positions.len(), "type": "VEC3"},
            {"bufferView": 2, "componentType": UNSIGNED_INT, "count": 3 * topology.triangles.len(),
             "type": "SCALAR"}
        ]
    });
    let mut json_chunk = document.to_string().into_bytes();
    // Chunks are 4-byte aligned: JSON padded with spaces, binary with zeros.
    while json_chunk.len() % 4 != 0 {
        json_chunk.push(b' ');
    }
    while bin.len() % 4 != 0 {
        bin.push(0);
    }
    let total = 12 + 8 + json_chunk.len() + 8 + bin.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&(total as u32).to_le_bytes());
    glb.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json_chunk);
    glb.extend_from_slice(&(bin.len() as u32).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin);
    glb
}

/// Writes `dir/final.glb` and returns its bytes.
pub fn write_glb(
    dir: &Path,
    name: &str,
    topology: &ClothTopology,
    positions: &[DVec3],
) -> Result<Vec<u8>, OutputError> {
    let path = dir.join("final.glb");
    let bytes = glb_bytes(name, topology, positions);
    std::fs::write(&path, &bytes).map_err(|e| OutputError::new(&path, e))?;
    Ok(bytes)
}
