//! A scene file never reads outside its own folder, never allocates what it merely declares,
//! and a node that overflows is rejected by name. Each file is built in the test.

use std::path::Path;

use serde_json::json;

use super::tests::{TempDir, TestGltf, cube, no_chunking, two_boxes};
use super::*;

/// The `.gltf` of [`two_boxes`] written into `dir` with its buffer at `uri`.
fn gltf_with_uri(dir: &Path, stem: &str, uri: &str) -> PathBuf {
    let path = dir.join(format!("{stem}.gltf"));
    std::fs::write(&path, two_boxes().json(Some(uri)).to_string()).unwrap();
    path
}

fn load_error(path: &Path) -> String {
    match import_gltf(path, &no_chunking()) {
        Ok(scene) => panic!(
            "{} loaded ({} objects)",
            path.display(),
            scene.instances.len()
        ),
        Err(e @ ImportError::BadBuffer { .. }) => e.to_string(),
        Err(other) => panic!("{}: {other:?}", path.display()),
    }
}

#[test]
fn buffer_uris_resolve_inside_the_scenes_folder() {
    let root = TempDir::new("escape");
    let scene_dir = root.0.join("scene");
    std::fs::create_dir_all(scene_dir.join("sub")).unwrap();
    // A valid buffer outside the scene's folder: reading it would load the scene.
    two_boxes().write_with_bin(&root.0, "outside");
    let secret = root.0.join("outside.bin");
    let absolute = secret.display().to_string();
    let cases = [
        (
            "parent",
            "../outside.bin".to_owned(),
            "leads outside the scene's folder",
        ),
        ("deep", "sub/../../outside.bin".to_owned(), "leads outside"),
        ("escaped", "%2E%2E/outside.bin".to_owned(), "leads outside"),
        ("absolute", absolute.clone(), "is an absolute path"),
        ("file-uri", format!("file://{absolute}"), "has a scheme"),
        (
            "remote",
            "https://example.com/outside.bin".to_owned(),
            "has a scheme",
        ),
    ];
    for (stem, uri, why) in cases {
        let path = gltf_with_uri(&scene_dir, stem, &uri);
        let message = load_error(&path);
        assert!(
            message.contains(&format!("{stem}.gltf"))
                && message.contains(&uri)
                && message.contains(why),
            "{stem}: {message}"
        );
    }
    // A link inside the folder that leads out of it.
    #[cfg(unix)]
    {
        std::os::unix::fs::symlink(&secret, scene_dir.join("link.bin")).unwrap();
        let message = load_error(&gltf_with_uri(&scene_dir, "linked", "link.bin"));
        assert!(
            message.contains("linked.gltf") && message.contains("through a link"),
            "{message}"
        );
    }
    // Inside the folder, `..` that stays in it is fine.
    two_boxes().write_with_bin(&scene_dir.join("sub"), "inside");
    let path = gltf_with_uri(&scene_dir, "inside", "sub/../sub/inside.bin");
    let scene = import_gltf(&path, &no_chunking()).expect("a buffer inside the folder loads");
    assert_eq!(scene.instances.len(), 2);
}

#[test]
fn a_declared_size_is_checked_before_anything_is_allocated() {
    let dir = TempDir::new("huge");
    let boxes = two_boxes();
    let huge = 100_000_000_000u64;
    // An external file, a data URI and a GLB chunk, each claiming 100 GB.
    let path = boxes.write_with_bin(&dir.0, "huge");
    let mut document = boxes.json(Some("huge.bin"));
    document["buffers"][0]["byteLength"] = json!(huge);
    std::fs::write(&path, document.to_string()).unwrap();
    let message = load_error(&path);
    assert!(
        message.contains("huge.gltf") && message.contains(&format!("declares {huge} bytes")),
        "{message}"
    );

    let mut embedded: serde_json::Value = serde_json::from_slice(&boxes.embedded()).unwrap();
    embedded["buffers"][0]["byteLength"] = json!(huge);
    let error = import_gltf_slice(
        embedded.to_string().as_bytes(),
        "memory.gltf",
        &no_chunking(),
    )
    .unwrap_err()
    .to_string();
    assert!(
        error.contains("memory.gltf") && error.contains(&format!("should hold {huge}")),
        "{error}"
    );
}

#[test]
fn nodes_that_overflow_are_rejected_by_name() {
    let (positions, indices) = cube(1.0);
    let reject = |build: &dyn Fn(&mut TestGltf, usize)| {
        let mut gltf = TestGltf::default();
        let mesh = gltf.simple_mesh("box", &positions, &indices);
        gltf.root(json!({"name": "plain", "mesh": mesh}));
        build(&mut gltf, mesh);
        let bytes = gltf.glb();
        match import_gltf_slice(&bytes, "overflow.glb", &no_chunking()) {
            Err(e @ ImportError::BadNode { .. }) => e.to_string(),
            other => panic!("{other:?}"),
        }
    };
    // Scaled by 1e30: finite, but far beyond any scene.
    let message = reject(&|gltf, mesh| {
        gltf.root(json!({"name": "giant", "mesh": mesh, "scale": [1e30, 1e30, 1e30]}));
    });
    assert!(
        message.contains("overflow.glb") && message.contains("'giant'") && message.contains("1e30"),
        "{message}"
    );
    // A parent and a child at 1e30 each: the product is infinite.
    let message = reject(&|gltf, mesh| {
        let child = gltf.node(json!({"name": "child", "mesh": mesh, "scale": [1e30, 1e30, 1e30]}));
        gltf.root(json!({"name": "parent", "scale": [1e30, 1e30, 1e30], "children": [child]}));
    });
    assert!(
        message.contains("'child'") && message.contains("not finite"),
        "{message}"
    );
}
