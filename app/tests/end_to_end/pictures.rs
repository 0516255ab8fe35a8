//! What a reader of a report sees in a picture `shot` writes: the legend of the overlays over
//! its bottom-left corner, in the colours the overlays use.

use crate::common::{out_dir, run, shadowlab, text};

/// A shot of the small city from its street, with `extra` flags.
fn shot(name: &str, extra: &[&str]) -> image::RgbaImage {
    let png = out_dir("pictures").join(name);
    let output = run(shadowlab()
        .args([
            "shot",
            "builtin:city-small",
            "--size",
            "360x240",
            "--method",
            "frag",
        ])
        .args(extra)
        .arg("--out")
        .arg(&png));
    assert!(output.status.success(), "{}", text(&output));
    image::open(&png).expect("the PNG opens").to_rgba8()
}

/// Pixels within 2 of `rgb` (linear, as the palette holds it) once sRGB-encoded, in the
/// picture's bottom half.
fn swatch_pixels(image: &image::RgbaImage, rgb: [f32; 3]) -> usize {
    let want: egui::Color32 = egui::Rgba::from_rgb(rgb[0], rgb[1], rgb[2]).into();
    let want = [want.r(), want.g(), want.b()];
    let (w, h) = image.dimensions();
    (h / 2..h)
        .flat_map(|y| (0..w).map(move |x| (x, y)))
        .filter(|&(x, y)| {
            let p = image.get_pixel(x, y).0;
            (0..3).all(|c| p[c].abs_diff(want[c]) <= 2)
        })
        .count()
}

#[test]
fn a_shot_with_overlays_carries_their_legend_and_no_legend_leaves_it_out() {
    use render_core::palette::{CULLED_MASK, MISSING_SHADOW, RENDERED};
    let overlays = ["--overlay", "casters", "--overlay", "error"];
    let with = shot("legend.png", &overlays);
    let without = shot("plain.png", &[&overlays[..], &["--no-legend"]].concat());
    assert_eq!(with.dimensions(), without.dimensions());

    // Each swatch is 11 px square with a 1 px border: at least its 9x9 inside.
    for swatch in [RENDERED, CULLED_MASK, MISSING_SHADOW] {
        let legend = swatch_pixels(&with, swatch.rgb);
        let plain = swatch_pixels(&without, swatch.rgb);
        assert!(
            legend >= plain + 81,
            "{}: {legend} pixels of its colour with the legend, {plain} without",
            swatch.name
        );
    }
    // The legend is along the bottom, from the left, and nowhere else.
    let h = with.height();
    for (x, y, a) in with.enumerate_pixels() {
        if a != without.get_pixel(x, y) {
            assert!(y > h / 3, "({x}, {y}) changed above the legend");
        }
    }
    assert!(
        with.get_pixel(12, h - 12) != without.get_pixel(12, h - 12),
        "no legend in the corner"
    );

    // No overlay, no legend.
    assert_eq!(
        shot("none.png", &[]),
        shot("none-flag.png", &["--no-legend"])
    );
}

#[test]
fn the_light_view_inset_shows_the_chosen_cascade_and_only_the_inset_changes() {
    let flags = |view: &'static str| {
        [
            "--shadow",
            "cascades",
            "--overlay",
            "light-view",
            "--no-legend",
            "--no-truth",
            "--inset-view",
            view,
            // Street level: every cascade holds visible receivers.
            "--eye=-40,3.5,2",
            "--target=60,8,2",
        ]
    };
    let first = shot("inset-0.png", &flags("0"));
    let last = shot("inset-3.png", &flags("3"));
    let (w, h) = first.dimensions();
    // The inset: a square of 0.4 of the shorter side (at most 256 px), 5 % of that in from
    // the top-left corner.
    let inset = (w.min(h) as f32 * 0.4).min(256.0);
    let side = (inset * 1.05).ceil() as u32 + 1;
    let (mut inside, mut outside) = (0, 0);
    for y in 0..h {
        for x in 0..w {
            if first.get_pixel(x, y) != last.get_pixel(x, y) {
                if x < side && y < side {
                    inside += 1;
                } else {
                    outside += 1;
                }
            }
        }
    }
    assert!(
        inside > 100,
        "the two cascades' maps differ: {inside} pixels"
    );
    assert_eq!(outside, 0, "the rest of the picture is the same frame");
}
