//! The window remembers its scene and settings between runs, in its config folder
//! (`SHADOWLAB_CONFIG_DIR` here): written when it closes, read when it opens.

use crate::common::{has_display, out_dir, run, screenshot_stats, shadowlab, text};

#[test]
fn the_window_reopens_with_the_last_scene_method_and_overlays() {
    if !has_display() {
        return;
    }
    let dir = out_dir("remembered");
    let _ = std::fs::remove_dir_all(&dir);
    let config = dir.join("config");
    let first = run(shadowlab().env("SHADOWLAB_CONFIG_DIR", &config).args([
        "builtin:city-small",
        "--method",
        "frag",
        "--overlay",
        "casters",
        "--shadow-res",
        "1024",
        "--exit-after-frames",
        "3",
    ]));
    assert!(first.status.success(), "{}", text(&first));
    let saved: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(config.join("settings.json")).expect("settings written on close"),
    )
    .expect("JSON");
    assert_eq!(saved["scene"], "builtin:city-small");
    assert_eq!(saved["frame"]["method"], "frag");
    assert_eq!(saved["frame"]["overlays"]["casters"], true);
    assert_eq!(saved["frame"]["shadow"]["resolution"], 1024);
    let eye = &saved["camera"]["eye"];
    assert!(eye[1].as_f64().is_some(), "the camera is saved: {saved}");

    // No scene and no flags: the same scene, method and overlay come back.
    let shots = dir.join("shots");
    let second = run(shadowlab()
        .env("SHADOWLAB_CONFIG_DIR", &config)
        .args(["--exit-after-frames", "3", "--screenshot-dir"])
        .arg(&shots));
    assert!(second.status.success(), "{}", text(&second));
    let stats = screenshot_stats(&shots);
    assert_eq!(stats["scene"], "builtin:city-small");
    assert_eq!(stats["method"], "frag");
    let again: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(config.join("settings.json")).expect("settings"),
    )
    .expect("JSON");
    assert_eq!(
        again["camera"], saved["camera"],
        "the camera came back and was kept"
    );
}
