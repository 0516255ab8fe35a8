//! The `shadowlab` binary as a user runs it: headless `shot` of the city, `bench`, `scenes`,
//! bad input with clear messages, and the real window under a display (Xvfb in CI).

use std::path::{Path, PathBuf};
use std::time::{Duration, Instant};

use crate::common::{
    has_display, out_dir, run, run_window, screenshot_stats, shadowlab, text, window_lock,
};

#[test]
fn shot_of_the_city_writes_a_picture_and_stats() {
    let dir = out_dir("shot_city");
    let png = dir.join("city.png");
    let output = run(shadowlab()
        .args([
            "shot",
            "builtin:city",
            "--size",
            "321x181",
            "--overlay",
            "light-view",
            "--out",
        ])
        .arg(&png));
    assert!(output.status.success(), "{}", text(&output));

    let image = image::open(&png).expect("the PNG opens").to_rgba8();
    assert_eq!(image.dimensions(), (321, 181));
    let distinct: std::collections::HashSet<[u8; 4]> = image.pixels().map(|p| p.0).collect();
    assert!(
        distinct.len() > 100,
        "the picture looks empty: {} colours",
        distinct.len()
    );

    let stats: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(png.with_extension("json")).expect("stats JSON written"),
    )
    .expect("valid JSON");
    assert_eq!(stats["scene"], "builtin:city");
    assert_eq!(stats["method"], "none");
    let objects = stats["objects"].as_u64().expect("objects");
    assert!((7_000..=15_000).contains(&objects), "{objects} objects");
    let counts = &stats["counts"];
    let total = counts["casters_total"].as_u64().expect("casters_total");
    let rendered = counts["casters_rendered"]
        .as_u64()
        .expect("casters_rendered");
    assert!(rendered > 0 && rendered <= total, "{rendered} of {total}");
    assert!(
        counts["receivers_visible"]
            .as_u64()
            .expect("receivers_visible")
            > 100
    );
    assert!(
        stats["timings_ms"]["frame_wall"]
            .as_f64()
            .expect("frame_wall")
            > 0.0
    );
    assert_eq!(stats["stages"][0]["remaining"].as_u64(), Some(total));
    assert_eq!(stats["technique"], "single");
    let views = stats["views"].as_array().expect("views");
    assert_eq!(views.len(), 1, "the single map is one view");
    assert_eq!(views[0]["name"], "sun");
    assert_eq!(views[0]["casters_rendered"].as_u64(), Some(rendered));
    assert_eq!(views[0]["stages"], stats["stages"]);
    assert_eq!(
        views[0]["casters_oracle"], counts["casters_oracle"],
        "one view's oracle is the frame's"
    );
    assert_eq!(views[0]["texel_size_m"], stats["light"]["texel_size_m"]);
    assert!(stats["shadow_failure"].is_null());
}

#[test]
fn shot_detail_reports_every_object() {
    let png = out_dir("detail").join("street.png");
    let args = [
        "shot",
        "builtin:city-small",
        "--method",
        "vfc",
        "--detail",
        "--size",
        "160x100",
        "--eye=-40,3.5,2",
        "--target=60,8,2",
        "--out",
    ];
    let output = run(shadowlab().args(args).arg(&png));
    assert!(output.status.success(), "{}", text(&output));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(png.with_extension("json")).expect("stats"))
            .expect("JSON");
    let detail = stats["objects_detail"].as_array().expect("objects_detail");
    assert_eq!(
        detail.len() as u64,
        stats["objects"].as_u64().expect("objects")
    );
    let count = |pred: &dyn Fn(&serde_json::Value) -> bool| {
        detail.iter().filter(|o| pred(o)).count() as u64
    };
    assert_eq!(
        count(&|o| o["shadow_map"] == "rendered"),
        stats["counts"]["casters_rendered"]
            .as_u64()
            .expect("rendered")
    );
    assert_eq!(
        count(&|o| o["visible"] == true),
        stats["counts"]["objects_visible"]
            .as_u64()
            .expect("visible")
    );
    assert_eq!(
        count(&|o| o["oracle"] == true),
        stats["counts"]["casters_oracle"].as_u64().expect("oracle")
    );
    assert!(
        count(&|o| o["shadow_map"] == "light frustum") > 0,
        "street level culls some casters by the light frustum"
    );
    assert!(
        detail
            .iter()
            .all(|o| o["oracle"] == false || o["shadow_map"] == "rendered"),
        "every oracle caster is rendered"
    );
    assert!(
        detail
            .iter()
            .any(|o| o["name"].as_str().is_some_and(|n| n.starts_with("ground_")))
    );
}

#[test]
fn bench_prints_a_table_and_writes_csv() {
    let dir = out_dir("bench");
    let csv = dir.join("bench.csv");
    let output = run(shadowlab()
        .args([
            "bench",
            "builtin:city-small",
            "--frames",
            "3",
            "--warmup",
            "1",
            "--size",
            "160x90",
            // Every method's row at a map of 512: the culling's compute passes, on one
            // lavapipe thread, grow with the map.
            "--shadow-res",
            "512",
            "--methods",
            "all",
            "--csv",
        ])
        .arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    let stdout = String::from_utf8_lossy(&output.stdout);
    assert!(
        stdout.contains("shadow pass ms") && stdout.lines().any(|l| l.starts_with("none")),
        "{stdout}"
    );
    let table = std::fs::read_to_string(&csv).expect("CSV written");
    let mut lines = table.lines();
    assert!(
        lines
            .next()
            .expect("header")
            .starts_with("setting,method,frames,frame_ms")
    );
    let rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    let methods: Vec<&str> = rows.iter().map(|r| r[1]).collect();
    let all: Vec<&str> = render_core::frame::Method::ALL
        .iter()
        .map(|m| m.name())
        .collect();
    assert_eq!(methods, all, "one row per method");
    for row in &rows {
        assert_eq!(row[2], "3");
        let drawn: f64 = row[6].parse().expect("casters drawn");
        let oracle: f64 = row[7].parse().expect("oracle casters");
        if row[1] == "incr" {
            // Nothing moves: the persistent map needs no caster once it is drawn.
            assert!(drawn == 0.0 && oracle > 0.0, "{row:?}");
        } else {
            assert!(drawn > 0.0 && oracle > 0.0 && oracle <= drawn, "{row:?}");
        }
        if row[1] != "dr-progressive" {
            assert_eq!(
                row[10], "0",
                "conservative methods have no error pixels: {row:?}"
            );
        }
    }
}

#[test]
fn bench_animates_the_cars_for_incremental_updates() {
    let dir = out_dir("bench_animate");
    let csv = dir.join("animate.csv");
    let output = run(shadowlab()
        .args([
            "bench",
            "builtin:city-small",
            "--frames",
            "3",
            "--warmup",
            "1",
            "--size",
            "160x90",
            "--methods",
            "none,incr",
            "--animate",
            "--speed",
            "15",
            "--csv",
        ])
        .arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    // Driving pace: half a metre a frame, two frames' worth of the street measured.
    assert!(
        text(&output).contains("camera at 15 m/s: 0.50 m a frame, 1 of the path's 360 m"),
        "{}",
        text(&output)
    );
    let table = std::fs::read_to_string(&csv).expect("CSV written");
    let rows: Vec<Vec<String>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').map(str::to_owned).collect())
        .collect();
    let drawn = |row: &[String]| -> f64 { row[6].parse().expect("casters drawn") };
    assert_eq!(rows.len(), 2, "{table}");
    // incr redraws what touches the moving cars, fewer than the whole map, without error.
    assert!(
        drawn(&rows[1]) > 0.0 && drawn(&rows[1]) < drawn(&rows[0]),
        "{table}"
    );
    assert_eq!(rows[1][10], "0", "{table}");
}

#[test]
fn no_adapter_says_how_to_get_one() {
    // No Metal adapter exists on Linux, so this asks for an adapter that is not there.
    if cfg!(target_os = "macos") {
        return;
    }
    let png = out_dir("no_adapter").join("x.png");
    let output = run(shadowlab()
        .env("WGPU_BACKEND", "metal")
        .args(["shot", "builtin:boxes", "--out"])
        .arg(&png));
    assert!(!output.status.success());
    let message = text(&output);
    assert!(
        message.contains("no GPU adapter") && message.contains("mesa-vulkan-drivers"),
        "{message}"
    );
    assert!(!png.exists());
}

#[test]
fn gltf_scene_and_path_from_assets_load_and_render() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let scene = root.join("assets/scenes/courtyard.gltf");
    let png = out_dir("courtyard").join("courtyard.png");
    let output = run(shadowlab()
        .arg("shot")
        .arg(&scene)
        .args([
            "--size",
            "200x120",
            "--eye=-40,30,-45",
            "--target=0,2,0",
            "--out",
        ])
        .arg(&png));
    assert!(output.status.success(), "{}", text(&output));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(png.with_extension("json")).expect("stats"))
            .expect("JSON");
    // 16 ground chunks, 8 pillars (one shared mesh), the roof ring and the tower.
    assert_eq!(stats["objects"], 26);
    assert!(
        stats["counts"]["receivers_visible"]
            .as_u64()
            .expect("count")
            > 10
    );
    let path = root.join("assets/paths/courtyard-walk.csv");
    let output = run(shadowlab()
        .arg("bench")
        .arg(&scene)
        .args([
            "--frames", "2", "--warmup", "0", "--size", "96x64", "--path",
        ])
        .arg(&path));
    assert!(output.status.success(), "{}", text(&output));
    assert!(text(&output).contains("path '"), "{}", text(&output));
}

/// The courtyard written in centimetres (a root node scaling it by 100, as a file exported in
/// cm would read): read as metres it gets a note naming `--units cm`; with `--units cm` it is
/// the courtyard again, with the same shadow texels.
#[test]
fn units_scale_a_file_and_a_size_that_looks_wrong_gets_a_note() {
    let root = Path::new(env!("CARGO_MANIFEST_DIR")).join("..");
    let source = root.join("assets/scenes/courtyard.gltf");
    let mut document: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(&source).expect("courtyard")).expect("JSON");
    let roots = document["scenes"][0]["nodes"].clone();
    let nodes = document["nodes"].as_array_mut().expect("nodes");
    nodes.push(
        serde_json::json!({"name": "centimetres", "scale": [100, 100, 100], "children": roots}),
    );
    let top = nodes.len() - 1;
    document["scenes"][0]["nodes"] = serde_json::json!([top]);
    let dir = out_dir("units");
    let file = dir.join("courtyard-cm.gltf");
    std::fs::write(&file, document.to_string()).expect("write");
    let shot = |scene: &Path, units: &str, stem: &str| {
        let png = dir.join(format!("{stem}.png"));
        let output = run(shadowlab()
            .arg("shot")
            .arg(scene)
            .args(["--size", "96x64", "--units", units, "--out"])
            .arg(&png));
        assert!(output.status.success(), "{}", text(&output));
        let stats: serde_json::Value = serde_json::from_str(
            &std::fs::read_to_string(png.with_extension("json")).expect("stats"),
        )
        .expect("JSON");
        (stats, text(&output))
    };
    let (as_metres, said) = shot(&file, "m", "as-metres");
    let note = as_metres["scene_notes"][0].as_str().expect("a note");
    assert!(note.contains("--units cm"), "{note}");
    assert!(
        said.contains("note: ") && said.contains("--units cm"),
        "{said}"
    );
    let (as_cm, _) = shot(&file, "cm", "as-cm");
    assert_eq!(as_cm["scene_notes"], serde_json::json!([]));
    let (original, _) = shot(&source, "m", "original");
    let texel =
        |stats: &serde_json::Value| stats["light"]["texel_size_m"][0].as_f64().expect("texel");
    let (cm, m) = (texel(&as_cm), texel(&original));
    assert!((cm / m - 1.0).abs() < 1e-3, "texels {cm} m and {m} m");
    assert!(
        texel(&as_metres) > 50.0 * m,
        "read as metres the texels are 100x larger"
    );
    // A bad unit names the flag and the choices.
    let output = run(shadowlab()
        .arg("shot")
        .arg(&file)
        .args(["--units", "feet", "--out"])
        .arg(dir.join("x.png")));
    assert!(!output.status.success());
    assert!(text(&output).contains("m, cm, mm, in"), "{}", text(&output));
}

#[test]
fn bench_sweeps_resolution_and_sun_elevation() {
    let dir = out_dir("bench_sweep");
    let csv = dir.join("res.csv");
    let args = [
        "bench",
        "builtin:city-small",
        "--frames",
        "2",
        "--warmup",
        "0",
        "--size",
        "96x64",
        "--methods",
        "none,vfc",
        "--sweep",
        "resolution",
        "--resolutions",
        "512,1024",
        "--csv",
    ];
    let output = run(shadowlab().args(args).arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    let table = std::fs::read_to_string(&csv).expect("CSV");
    let rows: Vec<Vec<&str>> = table
        .lines()
        .skip(1)
        .map(|l| l.split(',').collect())
        .collect();
    let settings: Vec<(&str, &str)> = rows.iter().map(|r| (r[0], r[1])).collect();
    assert_eq!(
        settings,
        [
            ("res 512", "none"),
            ("res 512", "vfc"),
            ("res 1024", "none"),
            ("res 1024", "vfc")
        ]
    );
    // Speed-up is against the first method when `ref` is not run: 1 for that method itself.
    assert!(
        rows.iter()
            .filter(|r| r[1] == "none")
            .all(|r| (r[12].parse::<f64>().expect("speed-up") - 1.0).abs() < 1e-9)
    );
    assert!(
        text(&output).contains("speed-up vs none"),
        "{}",
        text(&output)
    );

    let output = run(shadowlab().args([
        "bench",
        "builtin:boxes",
        "--frames",
        "1",
        "--warmup",
        "0",
        "--size",
        "64x48",
        "--sweep",
        "elevation",
        "--elevations",
        "10,80",
    ]));
    assert!(output.status.success(), "{}", text(&output));
    assert!(
        text(&output).contains("sun 10°") && text(&output).contains("sun 80°"),
        "{}",
        text(&output)
    );
    let bad = run(shadowlab().args([
        "bench",
        "builtin:boxes",
        "--sweep",
        "elevation",
        "--elevations",
        "0",
    ]));
    assert!(
        !bad.status.success() && text(&bad).contains("--elevations"),
        "{}",
        text(&bad)
    );
}

#[test]
fn time_poses_the_cars() {
    let dir = out_dir("time");
    let shot = |time: &str| {
        let png = dir.join(format!("t{time}.png"));
        let args = [
            "shot",
            "builtin:city-small",
            "--size",
            "160x100",
            "--eye=-40,3.5,2",
            "--target=60,2,2",
            "--time",
            time,
            "--out",
        ];
        let output = run(shadowlab().args(args).arg(&png));
        assert!(output.status.success(), "{}", text(&output));
        image::open(&png).expect("PNG").to_rgba8()
    };
    let (before, same, later) = (shot("0"), shot("0"), shot("5"));
    assert_eq!(before, same, "the same time gives the same picture");
    let changed = before
        .pixels()
        .zip(later.pixels())
        .filter(|(a, b)| a != b)
        .count();
    assert!(
        changed > 50,
        "cars did not move in 5 s: {changed} pixels changed"
    );
}

#[test]
fn scenes_lists_the_built_ins() {
    let output = run(shadowlab().arg("scenes"));
    assert!(output.status.success());
    let listing = text(&output);
    for name in ["builtin:city ", "builtin:city-small", "builtin:boxes"] {
        assert!(listing.contains(name), "{name} missing from:\n{listing}");
    }
}

#[test]
fn bad_input_gets_a_message_that_names_the_problem() {
    let dir = out_dir("bad_input");
    let broken = dir.join("broken.glb");
    std::fs::write(&broken, b"glTF\x02\x00\x00\x00this is not a binary glTF").expect("write");
    let png = dir.join("x.png");
    let cases: Vec<(Vec<String>, &str)> = vec![
        (
            vec![
                "shot".into(),
                broken.display().to_string(),
                "--out".into(),
                png.display().to_string(),
            ],
            "broken.glb",
        ),
        (
            vec![
                "shot".into(),
                "builtin:nope".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "builtin:city",
        ),
        (
            vec![
                "shot".into(),
                "scene.txt".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "scene.txt",
        ),
        (
            vec![
                "shot".into(),
                "builtin:boxes".into(),
                "--size".into(),
                "0x10".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "--size",
        ),
        (
            vec![
                "shot".into(),
                "builtin:boxes".into(),
                "--up".into(),
                "0,0,0".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "--up [0, 0, 0] is not a direction",
        ),
        (
            vec![
                "shot".into(),
                "builtin:boxes".into(),
                "--method".into(),
                "bogus".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "bogus",
        ),
        (
            vec![
                "shot".into(),
                "builtin:boxes".into(),
                "--shadow-res".into(),
                "100".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "--shadow-res",
        ),
        (
            vec![
                "shot".into(),
                "builtin:boxes".into(),
                "--eye".into(),
                "1,2".into(),
                "--out".into(),
                png.display().to_string(),
            ],
            "x,y,z",
        ),
        (
            vec![
                "bench".into(),
                "builtin:boxes".into(),
                "--path".into(),
                dir.join("missing.csv").display().to_string(),
            ],
            "missing.csv",
        ),
        (
            vec![
                "bench".into(),
                "builtin:boxes".into(),
                "--speed".into(),
                "0".into(),
            ],
            "'0' is not a speed",
        ),
        (
            vec![
                "bench".into(),
                "builtin:city-small".into(),
                "--speed".into(),
                "3000".into(),
                "--frames".into(),
                "10".into(),
                "--size".into(),
                "64x64".into(),
            ],
            "past the end of path 'city streets'",
        ),
        (
            vec![
                "bench".into(),
                "builtin:boxes".into(),
                "--sweep".into(),
                "clamp".into(),
                "--plot".into(),
                dir.join("clamp.png").display().to_string(),
            ],
            "--plot draws `--sweep maps` and `--sweep slices` only",
        ),
    ];
    for (args, expected) in cases {
        let output = run(shadowlab().args(&args));
        assert!(!output.status.success(), "{args:?} should fail");
        let message = text(&output);
        assert!(
            message.contains(expected),
            "{args:?}: message does not name '{expected}':\n{message}"
        );
        assert!(
            !message.contains("panicked"),
            "{args:?} panicked:\n{message}"
        );
    }
}

/// A city packed as `gltfpack` packs files (meshopt-compressed, quantized), written by the
/// test: `shot` renders it with every object, and the window opens it.
#[test]
fn a_meshopt_packed_file_renders_headless_and_in_the_window() {
    let dir = out_dir("packed");
    let city = render_core::scene::load_builtin("city-small", 0).expect("city-small");
    let glb = dir.join("city-packed.glb");
    std::fs::write(&glb, shadowlab_tests::packed_glb(&city)).expect("write the GLB");
    let png = dir.join("city-packed.png");
    let output = run(shadowlab()
        .arg("shot")
        .arg(&glb)
        .args(["--size", "160x96", "--chunk-fraction", "0", "--out"])
        .arg(&png));
    assert!(output.status.success(), "{}", text(&output));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(png.with_extension("json")).expect("stats"))
            .expect("JSON");
    assert_eq!(stats["objects"], city.instances.len());
    assert_eq!(stats["triangles"], city.triangle_count());
    if !has_display() {
        return;
    }
    let shots = dir.join("window");
    let _ = std::fs::remove_dir_all(&shots);
    let output = run_window(
        shadowlab()
            .arg(&glb)
            .args([
                "--chunk-fraction",
                "0",
                "--exit-after-frames",
                "3",
                "--screenshot-dir",
            ])
            .arg(&shots),
    );
    assert!(output.status.success(), "{}", text(&output));
    let stats = screenshot_stats(&shots);
    assert_eq!(stats["objects"], city.instances.len());
}

/// Opens the real window (winit + wgpu surface + egui), renders frames, saves a screenshot of
/// the whole window and closes. Needs a display: CI runs the tests under `xvfb-run`.
#[test]
fn window_opens_renders_and_saves_a_screenshot() {
    if !has_display() {
        return;
    }
    let dir = out_dir("window");
    for entry in std::fs::read_dir(&dir).expect("dir").flatten() {
        let _ = std::fs::remove_file(entry.path());
    }
    let _window = window_lock();
    let frames_csv = out_dir("window-frames").join("frames.csv");
    let mut child = shadowlab()
        .args([
            "builtin:city-small",
            "--play-path",
            "--exit-after-frames",
            "6",
            "--frame-log",
        ])
        .arg(&frames_csv)
        .arg("--screenshot-dir")
        .arg(&dir)
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("shadowlab starts");
    let deadline = Instant::now() + Duration::from_mins(4);
    while child.try_wait().expect("wait").is_none() {
        if Instant::now() > deadline {
            let _ = child.kill();
            panic!("the window did not close within 4 minutes");
        }
        std::thread::sleep(Duration::from_millis(200));
    }
    let output = child.wait_with_output().expect("output");
    assert!(output.status.success(), "{}", text(&output));
    // The screenshot went through the same path as F12: a PNG and its stats JSON.
    let files: Vec<PathBuf> = std::fs::read_dir(&dir)
        .expect("dir")
        .flatten()
        .map(|e| e.path())
        .collect();
    let png = files
        .iter()
        .find(|p| p.extension().is_some_and(|e| e == "png"))
        .unwrap_or_else(|| panic!("no PNG in {files:?}"));
    assert!(
        text(&output).contains(&png.display().to_string()),
        "the file name is reported: {}",
        text(&output)
    );
    let stats: serde_json::Value = serde_json::from_str(
        &std::fs::read_to_string(png.with_extension("json")).expect("stats JSON beside the PNG"),
    )
    .expect("JSON");
    assert_eq!(stats["scene"], "builtin:city-small");
    let image = image::open(png)
        .expect("window screenshot written")
        .to_rgba8();
    let (w, h) = image.dimensions();
    assert!(w >= 400 && h >= 300, "window screenshot is {w}x{h}");
    // The panel (left) and the 3D view (right) both drew something.
    let colours = |x0: u32, x1: u32| {
        let mut set = std::collections::HashSet::new();
        for y in (0..h).step_by(3) {
            for x in (x0..x1).step_by(3) {
                set.insert(image.get_pixel(x, y).0);
            }
        }
        set.len()
    };
    assert!(colours(0, w / 5) > 5, "the side panel looks empty");
    assert!(colours(w / 2, w) > 50, "the 3D view looks empty");

    // `--play-path`: the camera is on the scene's own path (a street), not framing the city.
    let city = render_core::scene::load_builtin("city-small", 0).expect("city-small");
    let path = render_core::scene::CameraPath::default_for(&city);
    let eye = &stats["view"]["eye"];
    let eye = glam::Vec3::new(
        eye[0].as_f64().expect("eye") as f32,
        eye[1].as_f64().expect("eye") as f32,
        eye[2].as_f64().expect("eye") as f32,
    );
    let off_path = (0..=200)
        .map(|k| path.sample(k as f32 / 200.0).eye.distance(eye))
        .fold(f32::MAX, f32::min);
    assert!(off_path < 2.0, "the eye {eye} is {off_path} m off the path");

    // `--frame-log`: a line per frame; none waited for the GPU but the screenshot's, whose
    // wait shows the count counts; the GPU's times came back all the same.
    let log = std::fs::read_to_string(&frames_csv).expect("frame log");
    let mut lines = log.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let column = |name: &str| header.iter().position(|h| *h == name).expect(name);
    let frames: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    assert_eq!(frames.len(), 6, "{log}");
    for frame in &frames {
        let screenshot = frame[column("screenshot")] == "1";
        let waits: u32 = frame[column("gpu_waits")].parse().expect("waits");
        assert_eq!(screenshot, waits > 0, "{log}");
        assert_eq!(frame[column("objects")], city.instances.len().to_string());
    }
    assert_eq!(frames[5][column("screenshot")], "1", "{log}");
    assert!(
        frames
            .iter()
            .any(|f| f[column("gpu_waits")] == "0" && !f[column("gpu_frame_ms")].is_empty()),
        "{log}"
    );
}

#[test]
fn shot_of_the_hall_lit_by_its_lights_names_its_path_and_has_exact_error_only_with_the_sun() {
    let dir = out_dir("shot_hall_lights");
    let png = dir.join("hall.png");
    let shot = |options: &[&str]| -> serde_json::Value {
        let head = [
            "shot",
            "builtin:hall",
            "--layered",
            "atlas",
            "--lights",
            "4",
        ];
        let output = run(shadowlab()
            .args(head)
            .args(options)
            .args(["--size", "161x91", "--out"])
            .arg(&png));
        assert!(output.status.success(), "{}", text(&output));
        serde_json::from_str(
            &std::fs::read_to_string(png.with_extension("json")).expect("stats JSON written"),
        )
        .expect("valid JSON")
    };
    let stats = shot(&["--shadow-res", "128"]);
    // Three spots and a point light: nine maps, one atlas pass.
    let layered = &stats["layered"];
    assert_eq!(layered["path"], "atlas");
    assert_eq!(layered["lights"], 4);
    assert_eq!(layered["maps"], 9);
    assert_eq!(layered["passes"], 1);
    // The exact shadow is the sun's: none is reported for many lights, and the notes say why.
    assert!(stats["exact_error"].is_null(), "{}", stats["exact_error"]);
    let notes = stats["notes"].to_string();
    assert!(notes.contains("no exact shadow"), "{notes}");
    // With the sun: two cascades before the nine maps, and the sun's error against the truth.
    let stats = shot(&["--sun-cascades", "--cascades", "2", "--shadow-res", "512"]);
    assert_eq!(stats["layered"]["maps"], 11);
    assert_eq!(stats["views"][0]["name"], "cascade 0");
    assert!(
        stats["exact_error"]["visible_px"].as_u64() > Some(0),
        "{}",
        stats["exact_error"]
    );
    assert!(!stats["notes"].to_string().contains("no exact shadow"));
}
