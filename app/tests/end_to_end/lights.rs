//! `--light` as a user gives it: the hall's first spot light casting the virtual maps' and the
//! volumes' shadows, named in the stats; a light the scene lacks, or a word that is no light,
//! gets a message that says what there is.

use crate::common::{out_dir, run, shadowlab, text};

fn stats_of(png: &std::path::Path) -> serde_json::Value {
    serde_json::from_str(
        &std::fs::read_to_string(png.with_extension("json")).expect("stats JSON written"),
    )
    .expect("valid JSON")
}

#[test]
fn a_spot_light_of_the_hall_casts_the_shadows_and_the_stats_name_it() {
    let dir = out_dir("shot_spot");
    let png = dir.join("hall.png");
    let shot = |shadow: &str, light: &str| {
        let output = run(shadowlab()
            .args(["shot", "builtin:hall", "--shadow", shadow, "--light", light])
            .args([
                "--eye=-1,8,9",
                "--target=-2,0,0",
                "--size",
                "161x91",
                "--out",
            ])
            .arg(&png));
        assert!(output.status.success(), "{}", text(&output));
        stats_of(&png)
    };
    let stats = shot("virtual", "spot");
    let light = &stats["view"]["shadow_light"];
    assert_eq!(light["kind"], "spot", "{light}");
    let outer = light["outer_cone_deg"].as_f64().expect("a cone");
    assert!((30.0..=40.0).contains(&outer), "the hall's spots: {light}");
    let views = stats["views"].as_array().expect("views");
    assert_eq!(
        views.len(),
        26,
        "one chain: 16 + 4 tiles of the finest mips, 6 mips"
    );
    assert_eq!(views[0]["name"], "spot mip 0 tile 0,0");
    let pages = &stats["virtual"];
    assert!(pages["pages_marked"].as_u64() > Some(0), "{pages}");
    assert_eq!(pages["pages_refused"], 0);
    let exact = &stats["exact_error"];
    assert!(exact["visible_px"].as_u64() > Some(0), "{exact}");
    assert!(
        stats["shadow_failure"].is_null(),
        "{}",
        stats["shadow_failure"]
    );
    // The same spot through shadow volumes: exact per pixel, the same light named.
    let stats = shot("volumes", "spot:0");
    assert_eq!(stats["view"]["shadow_light"], *light);
    assert_eq!(
        stats["exact_error"]["off_edge_px"], 0,
        "{}",
        stats["exact_error"]
    );
    // The sun is named as the sun.
    let stats = shot("virtual", "sun");
    assert_eq!(stats["view"]["shadow_light"]["kind"], "sun");
}

#[test]
fn a_light_the_scene_lacks_or_no_light_at_all_gets_a_message_that_says_what_there_is() {
    let dir = out_dir("shot_no_spot");
    let png = dir.join("x.png");
    let fails = |scene: &str, light: &str| {
        let output = run(shadowlab()
            .args(["shot", scene, "--shadow", "virtual", "--light", light])
            .args(["--size", "64x64", "--out"])
            .arg(&png));
        assert!(!output.status.success(), "{scene} --light {light} ran");
        text(&output)
    };
    let corridor = fails("builtin:corridor", "spot");
    assert!(corridor.contains("has 0 spot lights"), "{corridor}");
    let hall = fails("builtin:hall", "point:40");
    assert!(hall.contains("has 32 point and spot lights"), "{hall}");
    let word = fails("builtin:hall", "torch");
    assert!(
        word.contains("sun, point, point:N, spot or spot:N"),
        "{word}"
    );
}
