//! Bad scene files opened in the running window, as "Open glTF…" opens them: each message
//! names the file and the problem, and the window keeps drawing the scene it had. Every file
//! is built here, from a packed copy of the built-in boxes.

use std::path::Path;

use crate::common::{has_display, out_dir, run, screenshot_stats, shadowlab, text};
use serde_json::{Value, json};

/// The boxes packed as `gltfpack` packs them: a `.gltf` whose first buffer is `bin_uri`.
fn write_gltf(dir: &Path, stem: &str, edit: impl FnOnce(&mut Value)) -> String {
    let boxes = render_core::scene::load_builtin("boxes", 0).expect("boxes");
    let (mut document, bin) = shadowlab_tests::packed_gltf(&boxes);
    std::fs::write(dir.join(format!("{stem}.bin")), &bin).expect("bin");
    document["buffers"][0]["uri"] = json!(format!("{stem}.bin"));
    edit(&mut document);
    let path = dir.join(format!("{stem}.gltf"));
    std::fs::write(&path, document.to_string()).expect("gltf");
    path.display().to_string()
}

/// The window on city-small opening `file` after its first frame, closing once that has
/// loaded or failed: its output and the stats of its last screenshot (into `shots`).
fn open_in_the_window(file: &str, shots: &Path) -> (std::process::Output, Value) {
    let output = run(shadowlab()
        .args([
            "builtin:city-small",
            "--then-open",
            file,
            "--exit-after-frames",
            "3",
            "--screenshot-dir",
        ])
        .arg(shots));
    assert!(output.status.success(), "{file}: {}", text(&output));
    let stats = screenshot_stats(shots);
    (output, stats)
}

#[test]
fn a_bad_file_opened_in_the_window_is_named_and_the_scene_stays() {
    if !has_display() {
        return;
    }
    let root = out_dir("window_loading");
    let dir = root.join("scene");
    std::fs::create_dir_all(&dir).expect("scene folder");
    // A valid buffer beside the scene's folder, which an escape would read.
    let outside = write_gltf(&root, "outside", |_| {});
    let outside_bin = Path::new(&outside).with_extension("bin");
    let absolute = outside_bin.display().to_string();
    let broken = dir.join("broken.glb");
    std::fs::write(&broken, b"glTF\x02\0\0\0 definitely not a GLB").expect("glb");

    let cases: Vec<(String, Vec<&str>)> = vec![
        (
            write_gltf(&dir, "escape", |d| {
                d["buffers"][0]["uri"] = json!("../outside.bin");
            }),
            vec![
                "escape.gltf",
                "../outside.bin",
                "leads outside the scene's folder",
            ],
        ),
        (
            write_gltf(&dir, "absolute", |d| {
                d["buffers"][0]["uri"] = json!(absolute);
            }),
            vec!["absolute.gltf", "is an absolute path"],
        ),
        (
            write_gltf(&dir, "huge", |d| {
                d["buffers"][0]["byteLength"] = json!(100_000_000_000_u64);
            }),
            vec!["huge.gltf", "declares 100000000000 bytes"],
        ),
        (
            write_gltf(&dir, "overflow", |d| {
                let s = 1e30;
                d["nodes"][0]["matrix"] = json!([s, 0, 0, 0, 0, s, 0, 0, 0, 0, s, 0, 0, 0, 0, 1]);
            }),
            vec!["overflow.gltf", "rejected"],
        ),
        (
            broken.display().to_string(),
            vec!["broken.glb", "not a valid glTF"],
        ),
    ];
    for (file, expected) in cases {
        let shots = root.join(format!(
            "shots-{}",
            Path::new(&file)
                .file_stem()
                .and_then(|s| s.to_str())
                .unwrap_or("x")
        ));
        let _ = std::fs::remove_dir_all(&shots);
        let (output, stats) = open_in_the_window(&file, &shots);
        let said = text(&output);
        assert!(output.status.success(), "{file}: {said}");
        assert!(
            said.contains("Could not open"),
            "{file}: no message\n{said}"
        );
        for part in &expected {
            assert!(
                said.contains(part),
                "{file}: the message lacks {part:?}\n{said}"
            );
        }
        assert!(said.contains("The current scene stays open"), "{said}");
        // The screenshot after the failed load is still of the city.
        assert_eq!(stats["scene"], "builtin:city-small", "{file}");
    }

    // And a good file does replace the scene.
    let good = write_gltf(&dir, "good", |_| {});
    let shots = root.join("shots-good");
    let _ = std::fs::remove_dir_all(&shots);
    let (output, stats) = open_in_the_window(&good, &shots);
    assert!(output.status.success(), "{}", text(&output));
    assert_eq!(stats["scene"], json!(good));
}
