//! A scene written as `gltfpack` packs files for the web and games: every mesh's positions
//! quantized to 16-bit integers (`KHR_mesh_quantization`, undone by its node's matrix), normals
//! in 8-bit octahedral form, and every stream compressed with meshoptimizer
//! (`EXT_meshopt_compression`) into a GLB whose fallback buffer has no bytes of its own.

use glam::{Mat4, Vec3};
use render_core::scene::{Mesh, Scene};
use serde_json::{Value, json};

/// One stream of the fallback buffer: its compressed bytes and how to decode them.
struct Stream {
    bytes: Vec<u8>,
    stride: usize,
    count: usize,
    mode: &'static str,
    filter: &'static str,
}

/// The packed file's JSON and binary chunk (to tamper with), see [`glb_bytes`].
pub fn packed_gltf(scene: &Scene) -> (Value, Vec<u8>) {
    let mut streams = Vec::new();
    let mut accessors = Vec::new();
    let mut meshes = Vec::new();
    // Each mesh's dequantization: local = min + q * step.
    let mut dequantize = Vec::new();
    for (m, mesh) in scene.meshes.iter().enumerate() {
        let (quantized, from_quantized) = quantize(mesh);
        dequantize.push(from_quantized);
        let normals: Vec<[f32; 4]> = mesh.normals.iter().map(|n| n.extend(0.0).into()).collect();
        let octahedral: Vec<[i8; 4]> = meshopt::encode_filter_oct(&normals, 8);
        let n = mesh.positions.len();
        let base = streams.len();
        streams.push(Stream {
            bytes: meshopt::encode_vertex_buffer(&quantized).expect("positions encode"),
            stride: 8,
            count: n,
            mode: "ATTRIBUTES",
            filter: "NONE",
        });
        streams.push(Stream {
            bytes: meshopt::encode_vertex_buffer(&octahedral).expect("normals encode"),
            stride: 4,
            count: n,
            mode: "ATTRIBUTES",
            filter: "OCTAHEDRAL",
        });
        streams.push(Stream {
            bytes: meshopt::encode_index_buffer(&mesh.indices, n).expect("indices encode"),
            stride: 4,
            count: mesh.indices.len(),
            mode: "TRIANGLES",
            filter: "NONE",
        });
        let (low, high) = quantized
            .iter()
            .fold(([u16::MAX; 3], [0; 3]), |(lo, hi), q| {
                (
                    [lo[0].min(q[0]), lo[1].min(q[1]), lo[2].min(q[2])],
                    [hi[0].max(q[0]), hi[1].max(q[1]), hi[2].max(q[2])],
                )
            });
        accessors.extend([
            json!({"bufferView": base, "componentType": 5123, "count": n, "type": "VEC3",
                   "min": low, "max": high}),
            json!({"bufferView": base + 1, "componentType": 5120, "normalized": true,
                   "count": n, "type": "VEC3"}),
            json!({"bufferView": base + 2, "componentType": 5125,
                   "count": mesh.indices.len(), "type": "SCALAR"}),
        ]);
        meshes.push(json!({"name": mesh.name, "primitives": [{
            "attributes": {"POSITION": 3 * m, "NORMAL": 3 * m + 1}, "indices": 3 * m + 2,
        }]}));
    }
    let nodes: Vec<Value> = scene
        .instances
        .iter()
        .map(|inst| {
            let matrix = inst.world_from_local * dequantize[inst.mesh as usize];
            json!({"name": inst.name, "mesh": inst.mesh, "matrix": matrix.to_cols_array()})
        })
        .collect();
    let (mut bin, mut views, mut fallback_length) = (Vec::new(), Vec::new(), 0);
    for s in &streams {
        let length = s.stride * s.count;
        let mut view = json!({
            "buffer": 1, "byteOffset": fallback_length, "byteLength": length,
            "extensions": {"EXT_meshopt_compression": {
                "buffer": 0, "byteOffset": bin.len(), "byteLength": s.bytes.len(),
                "byteStride": s.stride, "count": s.count, "mode": s.mode, "filter": s.filter,
            }},
        });
        if s.mode == "ATTRIBUTES" {
            view["byteStride"] = json!(s.stride);
        }
        views.push(view);
        bin.extend_from_slice(&s.bytes);
        bin.resize(bin.len().next_multiple_of(4), 0);
        fallback_length += length.next_multiple_of(4);
    }
    let extensions = ["EXT_meshopt_compression", "KHR_mesh_quantization"];
    let document = json!({
        "asset": {"version": "2.0", "generator": "shadowlab-tests packer"},
        "extensionsUsed": extensions,
        "extensionsRequired": extensions,
        "scene": 0,
        "scenes": [{"nodes": (0..nodes.len()).collect::<Vec<_>>()}],
        "nodes": nodes,
        "meshes": meshes,
        "accessors": accessors,
        "bufferViews": views,
        "buffers": [
            {"byteLength": bin.len()},
            {"byteLength": fallback_length,
             "extensions": {"EXT_meshopt_compression": {"fallback": true}}},
        ],
    });
    (document, bin)
}

/// The scene as a packed GLB (see the module).
pub fn packed_glb(scene: &Scene) -> Vec<u8> {
    let (document, bin) = packed_gltf(scene);
    glb_bytes(&document, &bin)
}

/// Positions as 16-bit steps over the mesh's box (padded to 8 bytes), and the matrix that
/// turns them back into the mesh's coordinates.
fn quantize(mesh: &Mesh) -> (Vec<[u16; 4]>, Mat4) {
    let min = mesh.aabb_in_local.min;
    let extent = (mesh.aabb_in_local.max - min).max_element().max(1e-6);
    let step = extent / 65535.0;
    let quantized = mesh
        .positions
        .iter()
        .map(|p| {
            let q = ((*p - min) / step)
                .round()
                .clamp(Vec3::ZERO, Vec3::splat(65535.0));
            // In 0..=65535 after the clamp.
            let [x, y, z] = q.to_array().map(|c| c as u16);
            [x, y, z, 0]
        })
        .collect();
    let from_quantized = Mat4::from_translation(min) * Mat4::from_scale(Vec3::splat(step));
    (quantized, from_quantized)
}

/// Binary glTF: a 12-byte header, a JSON chunk padded with spaces, a BIN chunk padded with
/// zeros.
pub fn glb_bytes(json: &Value, bin: &[u8]) -> Vec<u8> {
    let mut json_chunk = json.to_string().into_bytes();
    json_chunk.resize(json_chunk.len().next_multiple_of(4), b' ');
    let mut bin_chunk = bin.to_vec();
    bin_chunk.resize(bin_chunk.len().next_multiple_of(4), 0);
    let chunk_length = |chunk: &[u8]| u32::try_from(chunk.len()).expect("a GLB chunk under 4 GiB");
    let total = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
    let mut glb = Vec::with_capacity(total);
    glb.extend_from_slice(b"glTF");
    glb.extend_from_slice(&2u32.to_le_bytes());
    glb.extend_from_slice(&u32::try_from(total).expect("GLB under 4 GiB").to_le_bytes());
    glb.extend_from_slice(&chunk_length(&json_chunk).to_le_bytes());
    glb.extend_from_slice(b"JSON");
    glb.extend_from_slice(&json_chunk);
    glb.extend_from_slice(&chunk_length(&bin_chunk).to_le_bytes());
    glb.extend_from_slice(b"BIN\0");
    glb.extend_from_slice(&bin_chunk);
    glb
}
