use std::sync::atomic::{AtomicUsize, Ordering};

use glam::{Quat, Vec4};
use serde_json::{Value, json};

use super::*;
use crate::geom::Aabb;

const FLOAT: u32 = 5126;
const UNSIGNED_SHORT: u32 = 5123;
const UNSIGNED_INT: u32 = 5125;
const LINES: u32 = 1;
const TRIANGLE_STRIP: u32 = 5;

/// A glTF document under construction, with one binary buffer.
#[derive(Default)]
pub(super) struct TestGltf {
    bin: Vec<u8>,
    buffer_views: Vec<Value>,
    accessors: Vec<Value>,
    meshes: Vec<Value>,
    materials: Vec<Value>,
    nodes: Vec<Value>,
    scene_roots: Vec<usize>,
}

impl TestGltf {
    fn view(&mut self, bytes: &[u8]) -> usize {
        self.bin.resize(self.bin.len().next_multiple_of(4), 0);
        let offset = self.bin.len();
        self.bin.extend_from_slice(bytes);
        self.buffer_views
            .push(json!({"buffer": 0, "byteOffset": offset, "byteLength": bytes.len()}));
        self.buffer_views.len() - 1
    }

    fn accessor(&mut self, accessor: Value) -> usize {
        self.accessors.push(accessor);
        self.accessors.len() - 1
    }

    fn vec3s(&mut self, values: &[Vec3]) -> usize {
        let bytes: Vec<u8> = values
            .iter()
            .flat_map(Vec3::to_array)
            .flat_map(f32::to_le_bytes)
            .collect();
        let view = self.view(&bytes);
        self.accessor(json!({"bufferView": view, "componentType": FLOAT, "count": values.len(), "type": "VEC3"}))
    }

    /// Positions need min and max (glTF 2.0 requires them).
    fn positions(&mut self, points: &[Vec3]) -> usize {
        let accessor = self.vec3s(points);
        let bounds = Aabb::from_points(points.iter().copied().filter(|p| p.is_finite()));
        let (min, max) = if bounds.is_empty() {
            (Vec3::ZERO, Vec3::ZERO)
        } else {
            (bounds.min, bounds.max)
        };
        self.accessors[accessor]["min"] = json!(min.to_array());
        self.accessors[accessor]["max"] = json!(max.to_array());
        accessor
    }

    fn indices_u32(&mut self, indices: &[u32]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({"bufferView": view, "componentType": UNSIGNED_INT, "count": indices.len(), "type": "SCALAR"}))
    }

    fn indices_u16(&mut self, indices: &[u16]) -> usize {
        let bytes: Vec<u8> = indices.iter().flat_map(|i| i.to_le_bytes()).collect();
        let view = self.view(&bytes);
        self.accessor(json!({"bufferView": view, "componentType": UNSIGNED_SHORT, "count": indices.len(), "type": "SCALAR"}))
    }

    fn material(&mut self, base_color: [f32; 4]) -> usize {
        self.materials
            .push(json!({"pbrMetallicRoughness": {"baseColorFactor": base_color}}));
        self.materials.len() - 1
    }

    fn mesh(&mut self, name: &str, primitives: &[Value]) -> usize {
        self.meshes
            .push(json!({"name": name, "primitives": primitives}));
        self.meshes.len() - 1
    }

    /// A triangle mesh from positions and indices, with nothing else.
    pub(super) fn simple_mesh(&mut self, name: &str, positions: &[Vec3], indices: &[u32]) -> usize {
        let positions = self.positions(positions);
        let indices = self.indices_u32(indices);
        self.mesh(
            name,
            &[json!({"attributes": {"POSITION": positions}, "indices": indices})],
        )
    }

    pub(super) fn node(&mut self, node: Value) -> usize {
        self.nodes.push(node);
        self.nodes.len() - 1
    }

    pub(super) fn root(&mut self, node: Value) -> usize {
        let index = self.node(node);
        self.scene_roots.push(index);
        index
    }

    pub(super) fn json(&self, buffer_uri: Option<&str>) -> Value {
        let mut buffer = json!({"byteLength": self.bin.len()});
        if let Some(uri) = buffer_uri {
            buffer["uri"] = json!(uri);
        }
        json!({
            "asset": {"version": "2.0"},
            "scene": 0,
            "scenes": [{"nodes": self.scene_roots}],
            "nodes": self.nodes,
            "meshes": self.meshes,
            "materials": self.materials,
            "accessors": self.accessors,
            "bufferViews": self.buffer_views,
            "buffers": [buffer],
        })
    }

    /// Writes `<stem>.gltf` and `<stem>.bin` into `dir`; returns the `.gltf` path.
    pub(super) fn write_with_bin(&self, dir: &Path, stem: &str) -> PathBuf {
        let bin_name = format!("{stem}.bin");
        std::fs::write(dir.join(&bin_name), &self.bin).unwrap();
        let gltf_path = dir.join(format!("{stem}.gltf"));
        std::fs::write(&gltf_path, self.json(Some(&bin_name)).to_string()).unwrap();
        gltf_path
    }

    pub(super) fn embedded(&self) -> Vec<u8> {
        let uri = format!("data:application/octet-stream;base64,{}", base64(&self.bin));
        self.json(Some(&uri)).to_string().into_bytes()
    }

    /// Binary glTF: a 12-byte header, a JSON chunk padded with spaces, a BIN chunk padded
    /// with zeros.
    pub(super) fn glb(&self) -> Vec<u8> {
        let mut json_chunk = self.json(None).to_string().into_bytes();
        json_chunk.resize(json_chunk.len().next_multiple_of(4), b' ');
        let mut bin_chunk = self.bin.clone();
        bin_chunk.resize(bin_chunk.len().next_multiple_of(4), 0);
        let total_length = 12 + 8 + json_chunk.len() + 8 + bin_chunk.len();
        let mut glb = Vec::with_capacity(total_length);
        glb.extend_from_slice(b"glTF");
        glb.extend_from_slice(&2u32.to_le_bytes());
        glb.extend_from_slice(&(total_length as u32).to_le_bytes());
        glb.extend_from_slice(&(json_chunk.len() as u32).to_le_bytes());
        glb.extend_from_slice(b"JSON");
        glb.extend_from_slice(&json_chunk);
        glb.extend_from_slice(&(bin_chunk.len() as u32).to_le_bytes());
        glb.extend_from_slice(b"BIN\0");
        glb.extend_from_slice(&bin_chunk);
        glb
    }
}

fn base64(bytes: &[u8]) -> String {
    const ALPHABET: &[u8; 64] = b"ABCDEFGHIJKLMNOPQRSTUVWXYZabcdefghijklmnopqrstuvwxyz0123456789+/";
    let mut encoded = String::new();
    for chunk in bytes.chunks(3) {
        let byte = |i: usize| u32::from(chunk.get(i).copied().unwrap_or(0));
        let group = (byte(0) << 16) | (byte(1) << 8) | byte(2);
        for i in 0..4 {
            let sextet = (group >> (18 - 6 * i)) & 63;
            encoded.push(if i <= chunk.len() {
                char::from(ALPHABET[sextet as usize])
            } else {
                '='
            });
        }
    }
    encoded
}

/// A folder under the system temp folder, removed when dropped.
pub(super) struct TempDir(pub(super) PathBuf);

impl TempDir {
    pub(super) fn new(label: &str) -> Self {
        static COUNTER: AtomicUsize = AtomicUsize::new(0);
        let unique = COUNTER.fetch_add(1, Ordering::Relaxed);
        let path = std::env::temp_dir().join(format!(
            "shadowlab-gltf-{}-{unique}-{label}",
            std::process::id()
        ));
        std::fs::create_dir_all(&path).unwrap();
        Self(path)
    }
}

impl Drop for TempDir {
    fn drop(&mut self) {
        let _ = std::fs::remove_dir_all(&self.0);
    }
}

/// A unit quad in the XY plane, facing +Z.
fn quad() -> ([Vec3; 4], [u32; 6]) {
    (
        [Vec3::ZERO, Vec3::X, Vec3::new(1.0, 1.0, 0.0), Vec3::Y],
        [0, 1, 2, 0, 2, 3],
    )
}

/// `quads` x `quads` quads in the XZ plane, `size_m` wide, centred on the origin, facing +Y.
fn ground(quads: u32, size_m: f32) -> (Vec<Vec3>, Vec<u32>) {
    let step_m = size_m / quads as f32;
    let mut positions = Vec::new();
    for iz in 0..=quads {
        for ix in 0..=quads {
            let (x, z) = (
                ix as f32 * step_m - size_m / 2.0,
                iz as f32 * step_m - size_m / 2.0,
            );
            positions.push(Vec3::new(x, 0.0, z));
        }
    }
    let vertex = |ix: u32, iz: u32| iz * (quads + 1) + ix;
    let mut indices = Vec::new();
    for iz in 0..quads {
        for ix in 0..quads {
            let (v00, v10, v01, v11) = (
                vertex(ix, iz),
                vertex(ix + 1, iz),
                vertex(ix, iz + 1),
                vertex(ix + 1, iz + 1),
            );
            indices.extend([v00, v01, v10, v10, v01, v11]);
        }
    }
    (positions, indices)
}

pub(super) fn cube(size_m: f32) -> (Vec<Vec3>, Vec<u32>) {
    let corners = Aabb::new(Vec3::ZERO, Vec3::splat(size_m))
        .corners()
        .to_vec();
    let indices = vec![
        0, 2, 1, 1, 2, 3, 4, 5, 6, 5, 7, 6, 0, 1, 4, 1, 5, 4, 2, 6, 3, 3, 6, 7, 0, 4, 2, 2, 4, 6,
        1, 3, 5, 3, 7, 5,
    ];
    (corners, indices)
}

pub(super) fn no_chunking() -> ChunkSettings {
    ChunkSettings {
        max_extent_fraction: 0.0,
    }
}

fn import_glb(gltf: &TestGltf) -> Scene {
    import_gltf_slice(&gltf.glb(), "test.glb", &no_chunking()).unwrap()
}

/// The instance names (before chunking) and the warnings of a GLB named `test.glb`.
fn flatten_glb(gltf: &TestGltf) -> (Vec<String>, Vec<String>) {
    let gltf::Gltf { document, blob } = gltf::Gltf::from_slice(&gltf.glb()).unwrap();
    let path = Path::new("test.glb");
    let buffers = load_buffers(&document, blob, path, None).unwrap();
    let Ok(flat) = flatten_node_trees(&document, &buffers, path) else {
        panic!("a node was rejected");
    };
    let names = flat.instances.into_iter().map(|i| i.name).collect();
    (names, flat.warnings)
}

fn names(scene: &Scene) -> Vec<&str> {
    scene.instances.iter().map(|i| i.name.as_str()).collect()
}

fn instance<'s>(scene: &'s Scene, name: &str) -> &'s Instance {
    scene.instances.iter().find(|i| i.name == name).unwrap()
}

#[test]
fn hierarchy_flattens_into_world_transforms() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = quad();
    let mesh = gltf.simple_mesh("quad", &positions, &indices);
    let rotation = Quat::from_rotation_y(std::f32::consts::FRAC_PI_2);
    gltf.root(json!({"name": "parent", "translation": [1.0, 2.0, 3.0], "scale": [2.0, 2.0, 2.0], "children": [1]}));
    gltf.node(json!({"name": "child", "rotation": rotation.to_array(), "mesh": mesh}));
    gltf.root(json!({"mesh": mesh, "translation": [0.0, 0.0, -5.0]}));
    let scene = import_glb(&gltf);

    // The parent has no mesh and is no instance; the unnamed node is named by its index.
    assert_eq!(names(&scene), ["child", "node2"]);
    let expected = Mat4::from_translation(Vec3::new(1.0, 2.0, 3.0))
        * Mat4::from_scale(Vec3::splat(2.0))
        * Mat4::from_quat(rotation);
    let child = instance(&scene, "child");
    assert!(
        child.world_from_local.abs_diff_eq(expected, 1e-5),
        "{:?}",
        child.world_from_local
    );
    // The quad's corner (1, 0, 0) is rotated to (0, 0, -1), scaled by 2 and moved.
    let corner_in_world = child.world_from_local.transform_point3(Vec3::X);
    assert!(corner_in_world.abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5));
    // The quad spans y and z in world space: x = 1, y in [2, 4], z in [1, 3].
    assert!(
        child
            .aabb_in_world
            .min
            .abs_diff_eq(Vec3::new(1.0, 2.0, 1.0), 1e-5)
    );
    assert!(
        child
            .aabb_in_world
            .max
            .abs_diff_eq(Vec3::new(1.0, 4.0, 3.0), 1e-5)
    );
    let translation = instance(&scene, "node2").world_from_local.w_axis.truncate();
    assert!(translation.abs_diff_eq(Vec3::new(0.0, 0.0, -5.0), 1e-6));
    assert_eq!(scene.name, "test.glb");
}

#[test]
fn nodes_sharing_a_mesh_share_one_scene_mesh() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = cube(1.0);
    let mesh = gltf.simple_mesh("crate", &positions, &indices);
    gltf.root(json!({"name": "crate_a", "mesh": mesh}));
    gltf.root(json!({"name": "crate_b", "mesh": mesh, "translation": [4.0, 0.0, 0.0]}));
    let scene = import_glb(&gltf);
    assert_eq!(scene.meshes.len(), 1);
    assert_eq!(scene.meshes[0].name, "crate");
    assert_eq!(names(&scene), ["crate_a", "crate_b"]);
    assert!(scene.instances.iter().all(|i| i.mesh == 0));
    assert_eq!(scene.meshes[0].triangle_count(), 12);
    assert_eq!(scene.triangle_count(), 24);
}

#[test]
fn primitives_get_suffixes_and_lines_are_skipped() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = quad();
    let p = gltf.positions(&positions);
    let i32s = gltf.indices_u32(&indices);
    let i16s = gltf.indices_u16(&[0, 1, 2]);
    let lines = gltf.indices_u32(&[0, 1, 1, 2]);
    let mesh = gltf.mesh(
        "thing",
        &[
            json!({"attributes": {"POSITION": p}, "indices": i32s}),
            json!({"attributes": {"POSITION": p}, "indices": lines, "mode": LINES}),
            json!({"attributes": {"POSITION": p}, "indices": i16s}),
        ],
    );
    gltf.root(json!({"name": "thing_node", "mesh": mesh}));
    let scene = import_glb(&gltf);
    assert_eq!(names(&scene), ["thing_node", "thing_node/p2"]);
    let (_, warnings) = flatten_glb(&gltf);
    assert_eq!(
        warnings,
        ["test.glb: node 'thing_node', primitive 1 skipped: it draws Lines, not triangles"]
    );
    let mesh_names: Vec<&str> = scene.meshes.iter().map(|m| m.name.as_str()).collect();
    assert_eq!(mesh_names, ["thing", "thing/p2"]);
    assert_eq!(scene.mesh_of(&scene.instances[0]).triangle_count(), 2);
    assert_eq!(scene.mesh_of(&scene.instances[1]).triangle_count(), 1);
}

#[test]
fn normals_are_computed_when_missing_and_kept_when_present() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = quad();
    let bare = gltf.simple_mesh("bare", &positions, &indices);
    let p = gltf.positions(&positions);
    let i = gltf.indices_u32(&indices);
    // Deliberately not the geometric normal (+Z), and not unit length.
    let n = gltf.vec3s(&[Vec3::new(0.0, 3.0, 0.0); 4]);
    let with_normals = gltf.mesh(
        "with_normals",
        &[json!({"attributes": {"POSITION": p, "NORMAL": n}, "indices": i})],
    );
    gltf.root(json!({"name": "bare", "mesh": bare}));
    gltf.root(json!({"name": "with_normals", "mesh": with_normals}));
    let scene = import_glb(&gltf);

    let computed = &scene.mesh_of(instance(&scene, "bare")).normals;
    assert_eq!(computed.len(), 4);
    assert!(
        computed.iter().all(|n| n.abs_diff_eq(Vec3::Z, 1e-6)),
        "{computed:?}"
    );
    let from_file = &scene.mesh_of(instance(&scene, "with_normals")).normals;
    assert_eq!(from_file.len(), 4);
    assert!(
        from_file.iter().all(|n| n.abs_diff_eq(Vec3::Y, 1e-6)),
        "{from_file:?}"
    );
}

#[test]
fn unindexed_triangles_and_strips_become_triangle_lists() {
    let mut gltf = TestGltf::default();
    let (corners, indices) = quad();
    let unrolled: Vec<Vec3> = indices.iter().map(|&i| corners[i as usize]).collect();
    let p = gltf.positions(&unrolled);
    let soup = gltf.mesh("soup", &[json!({"attributes": {"POSITION": p}})]);
    // Strip order 0, 1, 3, 2 covers the quad with two triangles of the same winding.
    let strip_positions = [corners[0], corners[1], corners[3], corners[2]];
    let sp = gltf.positions(&strip_positions);
    let strip = gltf.mesh(
        "strip",
        &[json!({"attributes": {"POSITION": sp}, "mode": TRIANGLE_STRIP})],
    );
    gltf.root(json!({"name": "soup", "mesh": soup}));
    gltf.root(json!({"name": "strip", "mesh": strip}));
    let scene = import_glb(&gltf);

    let soup = scene.mesh_of(instance(&scene, "soup"));
    assert_eq!(soup.triangle_count(), 2);
    let strip = scene.mesh_of(instance(&scene, "strip"));
    assert_eq!(strip.triangle_count(), 2);
    for mesh in [soup, strip] {
        for triangle in mesh.indices.chunks_exact(3) {
            let [a, b, c] = [0, 1, 2].map(|k| mesh.positions[triangle[k] as usize]);
            let face_normal = (b - a).cross(c - a).normalize();
            assert!(
                face_normal.abs_diff_eq(Vec3::Z, 1e-6),
                "{} {triangle:?}",
                mesh.name
            );
        }
    }
}

#[test]
fn base_color_comes_from_the_material() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = quad();
    let p = gltf.positions(&positions);
    let i = gltf.indices_u32(&indices);
    let red = gltf.material([0.9, 0.1, 0.2, 0.5]);
    let painted = gltf.mesh(
        "painted",
        &[json!({"attributes": {"POSITION": p}, "indices": i, "material": red})],
    );
    let plain = gltf.mesh(
        "plain",
        &[json!({"attributes": {"POSITION": p}, "indices": i})],
    );
    gltf.root(json!({"name": "painted", "mesh": painted}));
    gltf.root(json!({"name": "plain", "mesh": plain}));
    let scene = import_glb(&gltf);
    let painted = Vec4::from(instance(&scene, "painted").base_color);
    assert!(
        painted.abs_diff_eq(Vec4::new(0.9, 0.1, 0.2, 0.5), 1e-6),
        "{painted}"
    );
    // glTF's default material is white.
    let plain = Vec4::from(instance(&scene, "plain").base_color);
    assert!(plain.abs_diff_eq(Vec4::ONE, 1e-6), "{plain}");
}

pub(super) fn two_boxes() -> TestGltf {
    let mut gltf = TestGltf::default();
    let (positions, indices) = cube(1.0);
    let mesh = gltf.simple_mesh("box", &positions, &indices);
    gltf.root(json!({"name": "left", "mesh": mesh, "translation": [-2.0, 0.0, 0.0]}));
    gltf.root(json!({"name": "right", "mesh": mesh, "translation": [2.0, 0.0, 0.0]}));
    gltf
}

#[test]
fn external_embedded_and_binary_files_load_alike() {
    let gltf = two_boxes();
    let dir = TempDir::new("formats");
    let external = gltf.write_with_bin(&dir.0, "boxes");
    let embedded = dir.0.join("embedded.gltf");
    std::fs::write(&embedded, gltf.embedded()).unwrap();
    let binary = dir.0.join("boxes.glb");
    std::fs::write(&binary, gltf.glb()).unwrap();

    for path in [&external, &embedded, &binary] {
        let scene = import_gltf(path, &ChunkSettings::default()).unwrap();
        assert_eq!(scene.name, path.display().to_string());
        assert_eq!(names(&scene), ["left", "right"], "{}", path.display());
        assert_eq!(scene.meshes.len(), 1);
        assert_eq!(scene.triangle_count(), 24);
        assert!(
            scene
                .bounds()
                .min
                .abs_diff_eq(Vec3::new(-2.0, 0.0, 0.0), 1e-6)
        );
        assert!(
            scene
                .bounds()
                .max
                .abs_diff_eq(Vec3::new(3.0, 1.0, 1.0), 1e-6)
        );
    }
    let in_memory = import_gltf_slice(&gltf.embedded(), "embedded", &no_chunking()).unwrap();
    assert_eq!(in_memory.triangle_count(), 24);
}

#[test]
fn a_missing_file_is_named_in_the_error() {
    let dir = TempDir::new("missing");
    let path = dir.0.join("nowhere_to_be_found.gltf");
    let error = import_gltf(&path, &ChunkSettings::default()).unwrap_err();
    assert!(matches!(error, ImportError::NotFound { .. }), "{error:?}");
    let message = error.to_string();
    assert!(
        message.contains("nowhere_to_be_found.gltf") && message.contains("not found"),
        "{message}"
    );
}

#[test]
fn a_corrupt_or_empty_file_is_named_in_the_error() {
    let dir = TempDir::new("corrupt");
    let mut state = 0x2545_f491_u32;
    let noise: Vec<u8> = (0..512)
        .map(|_| {
            state ^= state << 13;
            state ^= state >> 17;
            state ^= state << 5;
            state.to_le_bytes()[1]
        })
        .collect();
    let corrupt = dir.0.join("corrupt_scene.glb");
    std::fs::write(&corrupt, &noise).unwrap();
    let message = import_gltf(&corrupt, &ChunkSettings::default())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("corrupt_scene.glb") && message.contains("not a valid glTF"),
        "{message}"
    );

    let empty = dir.0.join("empty_scene.gltf");
    std::fs::write(&empty, b"").unwrap();
    let message = import_gltf(&empty, &ChunkSettings::default())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("empty_scene.gltf") && message.contains("empty"),
        "{message}"
    );
}

#[test]
fn a_missing_bin_is_named_in_the_error() {
    let dir = TempDir::new("missing-bin");
    let path = two_boxes().write_with_bin(&dir.0, "orphan");
    std::fs::remove_file(dir.0.join("orphan.bin")).unwrap();
    let error = import_gltf(&path, &ChunkSettings::default()).unwrap_err();
    assert!(
        matches!(error, ImportError::MissingBuffer { .. }),
        "{error:?}"
    );
    let message = error.to_string();
    assert!(
        message.contains("orphan.gltf") && message.contains("'orphan.bin'"),
        "{message}"
    );

    // In memory, an external buffer cannot be resolved at all.
    let json = two_boxes().json(Some("orphan.bin")).to_string();
    let message = import_gltf_slice(json.as_bytes(), "memory.gltf", &no_chunking())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("memory.gltf") && message.contains("orphan.bin"),
        "{message}"
    );
}

#[test]
fn a_file_without_triangles_is_an_error() {
    let mut gltf = TestGltf::default();
    let p = gltf.positions(&[Vec3::ZERO, Vec3::X]);
    let mesh = gltf.mesh(
        "wire",
        &[json!({"attributes": {"POSITION": p}, "mode": LINES})],
    );
    gltf.root(json!({"name": "wire", "mesh": mesh}));
    let error = import_gltf_slice(&gltf.glb(), "wires.glb", &no_chunking()).unwrap_err();
    assert_eq!(error.to_string(), "wires.glb contains no triangle meshes");
}

#[test]
fn broken_primitives_are_skipped_without_panicking() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = quad();
    let good = gltf.simple_mesh("good", &positions, &indices);
    let out_of_range = gltf.simple_mesh("out_of_range", &positions, &[0, 1, 99]);
    let p = gltf.positions(&positions);
    let overlong = gltf.indices_u32(&indices);
    gltf.accessors[overlong]["count"] = json!(1_000_000);
    let overlong = gltf.mesh(
        "overlong",
        &[json!({"attributes": {"POSITION": p}, "indices": overlong})],
    );
    let empty_positions = gltf.positions(&[]);
    let empty = gltf.mesh(
        "empty",
        &[json!({"attributes": {"POSITION": empty_positions}})],
    );
    let flat = gltf.positions(&positions);
    gltf.accessors[flat]["type"] = json!("VEC2");
    let wrong_type = gltf.mesh("wrong_type", &[json!({"attributes": {"POSITION": flat}})]);
    for (name, mesh) in [
        ("good", good),
        ("a", out_of_range),
        ("b", overlong),
        ("c", empty),
        ("d", wrong_type),
    ] {
        gltf.root(json!({"name": name, "mesh": mesh}));
    }
    let scene = import_glb(&gltf);
    assert_eq!(names(&scene), ["good"]);
    assert_eq!(scene.meshes.len(), 1);
    // Each broken primitive is skipped for its own reason, naming the node.
    let (_, warnings) = flatten_glb(&gltf);
    let expected = [
        ("node 'a'", "vertex index 99 is out of range (4 vertices)"),
        ("node 'b'", "runs past the end of buffer view"),
        ("node 'c'", "is empty"),
        ("node 'd'", "has type (F32, Vec2)"),
    ];
    assert_eq!(warnings.len(), expected.len(), "{warnings:#?}");
    for (warning, (node, reason)) in warnings.iter().zip(expected) {
        assert!(
            warning.contains(node) && warning.contains(reason),
            "{warning}"
        );
    }

    // A GLB header whose length is shorter than the header itself.
    let mut glb = gltf.glb();
    glb[8..12].copy_from_slice(&4u32.to_le_bytes());
    let message = import_gltf_slice(&glb, "short.glb", &no_chunking())
        .unwrap_err()
        .to_string();
    assert!(
        message.contains("short.glb") && message.contains("not a valid glTF"),
        "{message}"
    );
    // A truncated GLB.
    let glb = gltf.glb();
    let message = import_gltf_slice(&glb[..glb.len() / 2], "cut.glb", &no_chunking())
        .unwrap_err()
        .to_string();
    assert!(message.contains("cut.glb"), "{message}");
}

#[test]
fn triangles_with_non_finite_positions_are_dropped() {
    let mut gltf = TestGltf::default();
    let (mut positions, indices) = quad();
    positions[3] = Vec3::new(f32::NAN, 1.0, 0.0);
    let mesh = gltf.simple_mesh("torn", &positions, &indices);
    gltf.root(json!({"name": "torn", "mesh": mesh}));
    let scene = import_glb(&gltf);
    let torn = &scene.meshes[0];
    assert_eq!(torn.triangle_count(), 1);
    assert_eq!(torn.positions.len(), 3);
    assert!(torn.positions.iter().all(|p| p.is_finite()));
    assert!(scene.bounds().min.is_finite() && scene.bounds().max.is_finite());
    let (_, warnings) = flatten_glb(&gltf);
    assert_eq!(warnings.len(), 1);
    assert!(
        warnings[0].contains("1 of 2 triangles dropped"),
        "{}",
        warnings[0]
    );
}

#[test]
fn a_cycle_in_the_node_tree_terminates() {
    let mut gltf = TestGltf::default();
    let (positions, indices) = quad();
    let mesh = gltf.simple_mesh("quad", &positions, &indices);
    gltf.root(json!({"name": "a", "mesh": mesh, "children": [1]}));
    gltf.node(json!({"name": "b", "mesh": mesh, "children": [0]}));
    let scene = import_glb(&gltf);
    assert_eq!(names(&scene), ["a", "b"]);
    let (_, warnings) = flatten_glb(&gltf);
    assert_eq!(
        warnings,
        ["test.glb: node 0 appears twice in the node tree; imported once"]
    );
}

#[test]
fn a_large_ground_is_chunked_on_import() {
    let mut gltf = TestGltf::default();
    let (ground_positions, ground_indices) = ground(100, 200.0);
    let ground = gltf.simple_mesh("ground", &ground_positions, &ground_indices);
    let (box_positions, box_indices) = cube(2.0);
    let small_box = gltf.simple_mesh("box", &box_positions, &box_indices);
    gltf.root(json!({"name": "ground", "mesh": ground}));
    gltf.root(json!({"name": "box", "mesh": small_box, "translation": [5.0, 0.0, 5.0]}));
    let glb = gltf.glb();

    let chunked = import_gltf_slice(&glb, "yard.glb", &ChunkSettings::default()).unwrap();
    let whole = import_gltf_slice(&glb, "yard.glb", &no_chunking()).unwrap();
    assert_eq!(names(&whole), ["ground", "box"]);
    // 200 m scene, chunks of at most 50 m: 4 x 4 over the ground.
    let mut expected: Vec<String> = (0..16).map(|k| format!("ground#{k}")).collect();
    expected.push("box".into());
    assert_eq!(names(&chunked), expected);
    assert_eq!(chunked.triangle_count(), whole.triangle_count());
    assert_eq!(chunked.triangle_count(), 100 * 100 * 2 + 12);
    let chunk_union = chunked.instances[..16]
        .iter()
        .fold(Aabb::EMPTY, |acc, i| acc.union(i.aabb_in_world));
    let ground_box = whole.instances[0].aabb_in_world;
    assert!(
        chunk_union.min.abs_diff_eq(ground_box.min, 1e-4)
            && chunk_union.max.abs_diff_eq(ground_box.max, 1e-4)
    );
    assert!(
        chunked
            .instances
            .iter()
            .all(|i| (i.mesh as usize) < chunked.meshes.len())
    );
}

#[test]
fn percent_escapes_in_buffer_uris_are_decoded() {
    assert_eq!(
        percent_decode("my%20scene.bin").as_deref(),
        Some("my scene.bin")
    );
    assert_eq!(percent_decode("plain.bin").as_deref(), Some("plain.bin"));
    assert_eq!(percent_decode("bad%2"), None);
    assert_eq!(percent_decode("%FF.bin"), None);
}
