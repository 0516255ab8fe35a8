//! `shadowlab report`: the folder a new user gets (pages, rows, plots that show something),
//! rows that are `bench`'s, and a wrong family named.

use crate::common::{has_display, out_dir, run, run_window, shadowlab, text};

/// The rows of a CSV `bench --csv` wrote, by column name.
fn csv_rows(csv: &str) -> Vec<std::collections::HashMap<String, String>> {
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    lines
        .map(|l| {
            header
                .iter()
                .zip(l.split(','))
                .map(|(h, v)| ((*h).to_owned(), v.to_owned()))
                .collect()
        })
        .collect()
}

/// The view of every run. Clamped volumes merge their intervals by a rule each process
/// measures on its adapter at start-up (Lloyd's V > R); fixed here, so the report's fill and
/// `bench`'s are the same numbers. Maps of 512: what is compared here (the report's numbers
/// against `bench`'s) holds at any size, and lavapipe runs the culling's compute passes,
/// whose work grows with the map, on one thread.
const VIEW: [&str; 10] = [
    "--frames",
    "2",
    "--warmup",
    "1",
    "--size",
    "160x90",
    "--volume-vertex-pixels",
    "100",
    "--shadow-res",
    "512",
];

#[test]
fn report_writes_pages_rows_and_plots_whose_numbers_are_benchs() {
    let dir = out_dir("report");
    let folder = dir.join("city-small");
    let _ = std::fs::remove_dir_all(&folder);
    let output = run(shadowlab()
        .args([
            "report",
            "builtin:city-small",
            "--families",
            "culling,volumes",
            "--sweeps",
            "slices",
            "--sweep-frames",
            "2",
        ])
        .args(VIEW)
        .arg("--out")
        .arg(&folder));
    assert!(output.status.success(), "{}", text(&output));
    let page = std::fs::read_to_string(folder.join("index.html")).expect("index.html");
    let markdown = std::fs::read_to_string(folder.join("report.md")).expect("report.md");
    assert!(
        page.contains("llvmpipe") || page.contains("Adapter: "),
        "the adapter at the top"
    );
    assert!(markdown.contains("Absolute times are this adapter's own"));
    // Every picture the page shows is beside it and has drawn something.
    let images: Vec<&str> = page
        .split("<img src=\"")
        .skip(1)
        .map(|rest| rest.split('"').next().expect("closing quote"))
        .collect();
    for name in [
        "culling-along-path.png",
        "culling-speed-error.png",
        "culling-speed-undersampling.png",
        "volumes-along-path.png",
        "volumes-speed-error.png",
        "culling-view-1.png",
        "volumes-view-1.png",
        "volumes-view-2.png",
        "sweep-slices-fill.png",
        "sweep-slices-stencil-gpu.png",
    ] {
        assert!(images.contains(&name), "{name} in {images:?}");
    }
    for name in &images {
        assert!(
            markdown.contains(&format!("]({name})")),
            "{name} in report.md"
        );
        let image = image::open(folder.join(name)).expect("a PNG").to_rgb8();
        let drawn = image.pixels().filter(|p| p.0 != [255, 255, 255]).count();
        assert!(
            drawn * 20 > image.pixels().len() / 10,
            "{name}: {drawn} pixels drawn, an empty plot"
        );
    }
    let rows = csv_rows(&std::fs::read_to_string(folder.join("rows.csv")).expect("rows.csv"));
    let culling: Vec<_> = rows
        .iter()
        .filter(|r| r["setting"].starts_with("culling: "))
        .collect();
    let volumes: Vec<_> = rows
        .iter()
        .filter(|r| r["setting"].starts_with("volumes: "))
        .collect();
    let slices: Vec<_> = rows
        .iter()
        .filter(|r| r["setting"].starts_with("slices sweep: "))
        .collect();
    // Standard volumes, then 1 to 32 slices against them.
    assert_eq!(slices.len(), 7);
    assert_eq!(slices[0]["setting"], "slices sweep: standard / clamp none");
    assert_eq!(
        slices[6]["setting"],
        "slices sweep: 32 slices / clamp conservative"
    );
    assert_eq!(culling.len(), render_core::frame::Method::ALL.len());
    assert_eq!(volumes[0]["setting"], "volumes: standard");
    assert_eq!(volumes.len(), 7);
    let json: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(folder.join("rows.json")).expect("json"))
            .expect("rows.json parses");
    assert_eq!(json.as_array().expect("rows").len(), rows.len());
    assert_eq!(
        json[0]["gpu_frame_ms_along_path"].as_array().map(Vec::len),
        Some(2)
    );
    // Standard volumes against the CC ones: the fill is counted, and clamping saves some.
    let fill = |r: &std::collections::HashMap<String, String>| -> f64 {
        r["fill_mfragments"].parse().expect("fill counted")
    };
    assert!(
        fill(volumes[0]) > fill(volumes[3]),
        "{:?} {:?}",
        volumes[0],
        volumes[3]
    );

    // Clamping saves fill against standard volumes, and more slices clamp tighter: less
    // fill than one slice (Lloyd's Figure 9).
    assert!(
        fill(slices[6]) < fill(slices[1]) && fill(slices[1]) < fill(slices[0]),
        "{:?} {:?} {:?}",
        slices[0],
        slices[1],
        slices[6]
    );
    // The sweep's rows are `bench --sweep slices`'s: the same fill, frame for frame.
    let csv = dir.join("bench-slices.csv");
    let output = run(shadowlab()
        .args(["bench", "builtin:city-small", "--methods", "vfc"])
        .args(["--sweep", "slices"])
        .args(VIEW)
        .arg("--csv")
        .arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    let bench = csv_rows(&std::fs::read_to_string(&csv).expect("bench CSV"));
    assert_eq!(bench.len(), slices.len());
    for (b, r) in bench.iter().zip(&slices) {
        let clamp = if b["setting"] == "standard" {
            "none"
        } else {
            "conservative"
        };
        assert_eq!(
            r["setting"],
            format!("slices sweep: {} / clamp {clamp}", b["setting"])
        );
        for column in ["fill_mfragments", "casters_drawn", "exact_error_px"] {
            assert_eq!(r[column], b[column], "{}: {column}", b["setting"]);
        }
    }

    // The same rows by `bench`: the counts are the same numbers (times differ run to run).
    let csv = dir.join("bench.csv");
    let output = run(shadowlab()
        .args(["bench", "builtin:city-small", "--methods", "vfc,frag"])
        .args(VIEW)
        .arg("--csv")
        .arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    let bench = csv_rows(&std::fs::read_to_string(&csv).expect("bench CSV"));
    for b in &bench {
        let r = culling
            .iter()
            .find(|r| r["method"] == b["method"])
            .expect("the method's report row");
        for column in [
            "casters_drawn",
            "casters_oracle",
            "shadow_triangles",
            "error_px_max",
            "exact_error_px",
            "undersampling_p95",
        ] {
            assert_eq!(r[column], b[column], "{}: {column}", b["method"]);
        }
    }
}

#[test]
fn a_wrong_family_is_named() {
    let output = run(shadowlab().args(["report", "builtin:boxes", "--families", "culling,cull"]));
    assert!(!output.status.success());
    assert!(text(&output).contains("'cull'"), "{}", text(&output));
    let output = run(shadowlab().args(["report", "builtin:boxes", "--families", "lights"]));
    assert!(!output.status.success());
    assert!(
        text(&output).contains("point or spot lights"),
        "{}",
        text(&output)
    );
}

#[test]
fn the_lights_family_runs_each_path_and_notes_the_adapters_fallbacks() {
    let folder = out_dir("report").join("hall");
    let _ = std::fs::remove_dir_all(&folder);
    let output = run(shadowlab()
        .args([
            "report",
            "builtin:hall",
            "--families",
            "lights",
            "--sweeps",
            "none",
            "--frames",
            "1",
        ])
        .args([
            "--warmup",
            "0",
            "--size",
            "96x64",
            "--shadow-res",
            "512",
            "--out",
        ])
        .arg(&folder));
    assert!(output.status.success(), "{}", text(&output));
    let rows = csv_rows(&std::fs::read_to_string(folder.join("rows.csv")).expect("rows.csv"));
    let settings: Vec<&str> = rows.iter().map(|r| r["setting"].as_str()).collect();
    assert_eq!(
        settings,
        ["lights: traditional", "lights: multiview", "lights: atlas"]
    );
    let markdown = std::fs::read_to_string(folder.join("report.md")).expect("report.md");
    // lavapipe's multiview draws only a pass's first view: the row says it ran a pass per map.
    if markdown.contains("llvmpipe") {
        assert!(
            markdown.contains("Note: lights / multiview:")
                && markdown.contains("'multiview' runs as 'traditional'"),
            "{markdown}"
        );
    }
    assert!(folder.join("lights-view-1.png").exists());
}

/// The window's compare table (`--compare`) and `bench` give the same numbers for the same
/// view and settings: the window's screenshot carries the table, and `bench` flies a path of
/// that one view at the window's view size.
#[test]
fn the_windows_compare_table_gives_benchs_numbers_for_the_same_view() {
    if !has_display() {
        return;
    }
    let dir = out_dir("compare-window");
    let _ = std::fs::remove_dir_all(&dir);
    std::fs::create_dir_all(&dir).expect("dir");
    let city = render_core::scene::load_builtin("city-small", 0).expect("city-small");
    let key = render_core::scene::CameraPath::default_for(&city).sample(0.3);
    let xyz = |v: glam::Vec3| format!("{},{},{}", v.x, v.y, v.z);
    // Maps of 512 in both: the same numbers at any size, and a quarter of the culling's work.
    let lens = [
        "--fov",
        "60",
        "--near",
        "0.1",
        "--far",
        "2000",
        "--shadow-res",
        "512",
    ];
    let output = run_window(
        shadowlab()
            .args(["builtin:city-small", "--fresh", "--compare"])
            .arg(format!("--eye={}", xyz(key.eye)))
            .arg(format!("--target={}", xyz(key.target)))
            .args(lens)
            .args(["--exit-after-frames", "2", "--screenshot-dir"])
            .arg(&dir),
    );
    assert!(output.status.success(), "{}", text(&output));
    let json = std::fs::read_dir(&dir)
        .expect("dir")
        .flatten()
        .map(|e| e.path())
        .find(|p| p.extension().is_some_and(|e| e == "json"))
        .expect("the screenshot's stats");
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(json).expect("stats")).expect("JSON");
    let table = stats["compare"].as_array().expect("the compare table");
    assert_eq!(
        table.len(),
        render_core::frame::Method::ALL.len(),
        "{stats}"
    );
    let size = format!("{}x{}", stats["size"][0], stats["size"][1]);

    let path = dir.join("one-view.csv");
    let line = format!("{},{}\n", xyz(key.eye), xyz(key.target));
    std::fs::write(&path, line.repeat(2)).expect("path");
    let csv = dir.join("bench.csv");
    let output = run(shadowlab()
        .args(["bench", "builtin:city-small", "--methods"])
        .arg("vfc,frag,dr-conservative,oracle")
        .args([
            "--frames",
            "1",
            "--warmup",
            "0",
            "--no-truth",
            "--size",
            &size,
        ])
        .args(lens)
        .arg("--path")
        .arg(&path)
        .arg("--csv")
        .arg(&csv));
    assert!(output.status.success(), "{}", text(&output));
    let bench = csv_rows(&std::fs::read_to_string(&csv).expect("bench CSV"));
    assert_eq!(bench.len(), 4);
    for b in &bench {
        let row = table
            .iter()
            .find(|r| r["method"] == b["method"].as_str())
            .expect("the method's row");
        assert_eq!(row["stale"], false);
        let number = |v: &str| v.parse::<f64>().expect("a number");
        for (ours, theirs) in [
            ("casters_drawn", "casters_drawn"),
            ("casters_oracle", "casters_oracle"),
            ("triangles", "shadow_triangles"),
            ("error_px", "error_px_max"),
        ] {
            assert_eq!(
                row[ours].as_f64(),
                Some(number(&b[theirs])),
                "{}: {ours} {row}",
                b["method"]
            );
        }
    }
}
