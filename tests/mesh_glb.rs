//! `final.glb` is valid binary glTF 2.0 holding the draped mesh: read back by the format's own
//! rules (header, 4-byte aligned JSON and BIN chunks, accessors into one buffer), it gives every
//! node's position to f32 precision, unit normals, and the lattice's triangles.

use glam::DVec3;
use kes_cloth::forces::ClothTopology;
use kes_cloth::output::glb_bytes;

fn u32_at(bytes: &[u8], at: usize) -> u32 {
    u32::from_le_bytes(bytes[at..at + 4].try_into().expect("four bytes"))
}

fn f32_at(bytes: &[u8], at: usize) -> f32 {
    f32::from_le_bytes(bytes[at..at + 4].try_into().expect("four bytes"))
}

#[test]
fn the_glb_reads_back_as_the_mesh() {
    let topology = ClothTopology::rectangle(4, 3, 0.01);
    // A bent sheet, so positions and normals are not trivial.
    let positions: Vec<DVec3> = topology
        .grid_coords
        .iter()
        .map(|&(i, j)| {
            let x = i as f64 * 0.01;
            DVec3::new(x, -2.0 * x * x, j as f64 * 0.01)
        })
        .collect();
    let glb = glb_bytes("bent", &topology, &positions);
    assert_eq!(&glb[0..4], b"glTF");
    assert_eq!(u32_at(&glb, 4), 2, "glTF version");
    assert_eq!(u32_at(&glb, 8) as usize, glb.len(), "total length");
    let json_len = u32_at(&glb, 12) as usize;
    assert_eq!(&glb[16..20], b"JSON");
    assert_eq!(json_len % 4, 0, "JSON chunk not aligned");
    let doc: serde_json::Value = serde_json::from_slice(&glb[20..20 + json_len]).expect("JSON chunk parses");
    let bin_at = 20 + json_len;
    let bin_len = u32_at(&glb, bin_at) as usize;
    assert_eq!(&glb[bin_at + 4..bin_at + 8], b"BIN\0");
    assert_eq!(bin_at + 8 + bin_len, glb.len());
    let bin = &glb[bin_at + 8..];
    assert_eq!(doc["asset"]["version"], "2.0");
    let primitive = &doc["meshes"][0]["primitives"][0];
    let view = |accessor: &serde_json::Value| {
        let v = &doc["bufferViews"][accessor["bufferView"].as_u64().expect("view") as usize];
        v["byteOffset"].as_u64().expect("offset") as usize
    };
    let pos = &doc["accessors"][primitive["attributes"]["POSITION"].as_u64().expect("POSITION") as usize];
    assert_eq!(pos["count"].as_u64(), Some(positions.len() as u64));
    let start = view(pos);
    for (k, p) in positions.iter().enumerate() {
        for (c, expected) in p.as_vec3().to_array().iter().enumerate() {
            assert_eq!(f32_at(bin, start + 12 * k + 4 * c), *expected, "node {k}");
        }
    }
    let normals = &doc["accessors"][primitive["attributes"]["NORMAL"].as_u64().expect("NORMAL") as usize];
    let start = view(normals);
    for k in 0..positions.len() {
        let n: Vec<f32> = (0..3).map(|c| f32_at(bin, start + 12 * k + 4 * c)).collect();
        let length = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        assert!((length - 1.0).abs() < 1e-5, "normal {k} has length {length}");
    }
    let indices = &doc["accessors"][primitive["indices"].as_u64().expect("indices") as usize];
    assert_eq!(
        indices["count"].as_u64(),
        Some(3 * topology.triangles.len() as u64)
    );
    let start = view(indices);
    for (t, tri) in topology.triangles.iter().enumerate() {
        for (c, i) in tri.iter().enumerate() {
            assert_eq!(u32_at(bin, start + 12 * t + 4 * c), *i, "triangle {t}");
        }
    }
}
