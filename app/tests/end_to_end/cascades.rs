//! `--shadow cascades` from the command line: a shot's stats list each cascade, a bench sweep
//! prints a row per setup, and bad cascade flags get a message that names them.

use crate::common::{out_dir, run, shadowlab, text};

#[test]
fn a_cascaded_shot_reports_each_cascade_and_its_depths() {
    let png = out_dir("cascades").join("street.png");
    let output = run(shadowlab()
        .args([
            "shot",
            "builtin:city-small",
            "--size",
            "200x120",
            "--eye=-40,3.5,2",
            "--target=60,8,2",
            "--shadow",
            "cascades",
            "--cascades",
            "3",
            "--split",
            "geometric",
            "--split-first",
            "8",
            "--split-ratio",
            "4",
            "--method",
            "frag",
            "--out",
        ])
        .arg(&png));
    assert!(output.status.success(), "{}", text(&output));
    assert!(
        text(&output).contains("caster draws in 3 views"),
        "{}",
        text(&output)
    );
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(png.with_extension("json")).expect("stats"))
            .expect("JSON");
    assert_eq!(stats["technique"], "cascades");
    let views = stats["views"].as_array().expect("views");
    assert_eq!(views.len(), 3);
    // Engel's progression from 8 m by 4: the second cascade shades 8 to 32 m.
    let depths = &views[1]["shades_depth_m"];
    assert!(
        (depths[0].as_f64().expect("near") - 8.0).abs() < 1e-3,
        "{depths}"
    );
    assert!(
        (depths[1].as_f64().expect("far") - 32.0).abs() < 1e-3,
        "{depths}"
    );
    assert!(
        views[0]["shades_depth_m"][0].is_null(),
        "the first is open towards the eye"
    );
    let texel = |v: &serde_json::Value| v["texel_size_m"][0].as_f64().expect("texel");
    assert!(texel(&views[0]) < texel(&views[1]) && texel(&views[1]) < texel(&views[2]));
    assert_eq!(stats["error"]["missing_shadow_px"], 0);
    assert_eq!(stats["error"]["extra_shadow_px"], 0);
}

#[test]
fn bad_cascade_flags_name_the_flag() {
    for (flags, expected) in [
        (&["--cascades", "9"][..], "--cascades 9 is outside 1 to 8"),
        (&["--lambda", "2"], "--lambda 2 is outside 0 to 1"),
        (&["--splits", "5,3"], "--splits '5,3'"),
        (&["--split", "zhang"], "unknown split scheme 'zhang'"),
        (&["--cascade-fit", "round"], "unknown cascade fit 'round'"),
        (&["--shadow", "wavelets"], "unknown shadow setup 'wavelets'"),
        (
            &["--split-ratio", "0.5"],
            "--split-ratio must be at least 1",
        ),
        (
            &["--cascade-blend", "0.9"],
            "--cascade-blend 0.9 is outside 0 to 0.5",
        ),
        (
            &["--cascade-select", "nearest"],
            "unknown cascade selection 'nearest'",
        ),
        (&["--cascade-depths", "all"], "unknown cascade depths 'all'"),
        (&["--lispsm-n", "0"], "--lispsm-n 0 is outside 0.01 to 100"),
    ] {
        let output = run(shadowlab()
            .args(["shot", "builtin:boxes", "--size", "32x32", "--out"])
            .arg(out_dir("cascades").join("bad.png"))
            .args(flags));
        assert!(!output.status.success(), "{flags:?} should fail");
        assert!(
            text(&output).contains(expected),
            "{flags:?}: {}",
            text(&output)
        );
    }
}

#[test]
fn bench_sweeps_cascade_counts_after_the_single_and_the_lispsm_map() {
    let output = run(shadowlab().args([
        "bench",
        "builtin:boxes",
        "--size",
        "96x64",
        "--frames",
        "2",
        "--warmup",
        "1",
        "--methods",
        "frag",
        "--sweep",
        "cascades",
        "--cascade-counts",
        "2,4",
    ]));
    assert!(output.status.success(), "{}", text(&output));
    let out = String::from_utf8_lossy(&output.stdout);
    let rows: Vec<&str> = out
        .lines()
        .filter(|l| l.split_whitespace().any(|word| word == "frag") && !l.starts_with("setting"))
        .collect();
    assert_eq!(rows.len(), 4, "single, lispsm, 2 and 4 cascades:\n{out}");
    assert!(
        rows[0].starts_with("single") && rows[1].starts_with("lispsm"),
        "{out}"
    );
    // Every column has a number: timings, error against `none` and the exact shadow, and
    // undersampling from the measured frames.
    assert!(rows.iter().all(|r| !r.contains("n/a")), "{out}");
    assert!(
        rows[2].starts_with("2 cascades") && rows[3].starts_with("4 cascades"),
        "{out}"
    );
}
