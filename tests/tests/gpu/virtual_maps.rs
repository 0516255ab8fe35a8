//! Virtual shadow maps (`--shadow virtual`, `virtual_maps/`): the cache draws nothing for a
//! static scene and exactly the pages a moving box touches; the picture equals a full
//! re-render; a pool too small falls back to coarser levels and never leaves a hole; the hard
//! cases (sky only, a camera cut, far from the origin, the sun at the zenith and 1 degree up,
//! a 1 m scene) give the exact shadow.

use glam::Vec3;
use render_core::geom::Camera;
use render_core::scene::{Scene, Sun};
use render_core::shadow_view::VirtualSettings;
use render_core::technique::VirtualPages;
use shadowlab_tests::virtual_pages::{
    Frames, MARKED, Marking, RENDERED, SIZE, assert_drawn_again_exactly, box_scene_normal, camera,
    entries_with, scene, settings, touched_entries,
};
use shadowlab_tests::{against_truth, box_on_plane, translated};

#[test]
fn a_static_scene_draws_no_page_in_its_second_frame_and_its_picture_stays() {
    let scene = scene(Sun::default());
    let settings = settings(VirtualSettings::default());
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &settings);
    let second = frames.frame(&scene, &camera(), &settings);
    let p = first.pages;
    assert!(
        p.pages_marked > 0 && p.pages_rendered == p.pages_marked,
        "{p:?}"
    );
    assert_eq!(p.pages_refused, 0);
    assert_eq!(
        p.cache_hit_rate,
        Some(0.0),
        "a first frame finds nothing cached"
    );
    assert!(
        p.caster_pages > 0,
        "the box and the ground are drawn into pages: {p:?}"
    );
    let q = second.pages;
    assert_eq!(q.pages_rendered, 0, "{q:?}");
    assert_eq!(q.caster_pages, 0, "{q:?}");
    assert_eq!(q.cache_hit_rate, Some(1.0), "{q:?}");
    assert_eq!(
        (q.pages_marked, q.pages_resident),
        (p.pages_marked, p.pages_resident)
    );
    assert!(!q.all_invalidated);
    assert!(entries_with(&second.flags, RENDERED).is_empty());
    assert_eq!(
        entries_with(&first.flags, MARKED),
        entries_with(&second.flags, MARKED)
    );
    assert_eq!(first.capture.shadow, second.capture.shadow);
    // The box's shadow is in the picture.
    assert!(first.capture.shadow.contains(&0));
}

#[test]
fn with_the_cache_off_every_marked_page_is_drawn_each_frame() {
    let scene = scene(Sun::default());
    let settings = settings(VirtualSettings {
        cache: false,
        ..VirtualSettings::default()
    });
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &settings);
    let second = frames.frame(&scene, &camera(), &settings);
    assert!(second.pages.all_invalidated);
    assert_eq!(second.pages.pages_rendered, second.pages.pages_marked);
    assert_eq!(second.pages.cache_hit_rate, Some(0.0));
    assert_eq!(second.pages.pages_invalidated, first.pages.pages_resident);
    assert_eq!(first.capture.shadow, second.capture.shadow);
}

#[test]
fn moving_a_box_draws_again_exactly_the_pages_its_old_and_new_bounds_touch() {
    let mut scene = scene(Sun::default());
    let settings = settings(VirtualSettings::default());
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &settings);
    let [old, new] = frames.move_box(&mut scene);
    let second = frames.frame(&scene, &camera(), &settings);
    assert_eq!(second.pages.moved_boxes, 2);
    let (before, after) = (
        touched_entries(&second.views, old.min, old.max),
        touched_entries(&second.views, new.min, new.max),
    );
    // The box crossed page borders: its old and new pages differ, and both are drawn again.
    assert_ne!(before, after);
    let mut touched = [before, after].concat();
    touched.sort_unstable();
    touched.dedup();
    assert_drawn_again_exactly(&first, &second, &touched);
    // No stale shadow: the picture equals every page drawn again where it is.
    let redrawn = frames.redrawn(&scene, &camera(), &settings);
    assert_eq!(second.capture.shadow, redrawn.capture.shadow);
    assert_ne!(
        first.capture.shadow, second.capture.shadow,
        "the shadow moved"
    );
}

#[test]
fn a_pool_too_small_falls_back_to_coarser_levels_and_never_leaves_a_hole() {
    let scene = scene(Sun::default());
    let settings = settings(VirtualSettings {
        pages: 16,
        lod_bias: -3.0,
        ..VirtualSettings::default()
    });
    let frame = Frames::new(&scene).frame(&scene, &camera(), &settings);
    let p = frame.pages;
    assert!(p.pages_refused > 0, "{p:?}");
    assert!(p.pages_resident <= 16, "{p:?}");
    assert_eq!(p.pages_resident + p.pages_refused, p.pages_marked, "{p:?}");
    // Every receiver pixel is shaded from some level (the undersampling counts only those).
    let error = frame.report.error.expect("measured");
    let shaded = frame.report.undersampling.expect("measured").pixels;
    assert_eq!(shaded, error.visible_px);
    // The refused pixels read the coarsest level, which undersamples them.
    let under = frame.report.undersampling.expect("measured");
    assert!(under.p95_octaves > 0.0, "{under:?}");
}

#[test]
fn sky_only_marks_no_page() {
    let scene = scene(Sun::default());
    let up = Camera::look_at(
        Vec3::new(0.0, 30.0, 0.0),
        Vec3::new(0.0, 60.0, 1.0),
        60f32.to_radians(),
        0.1,
        500.0,
    );
    let frame = Frames::new(&scene).frame(&scene, &up, &settings(VirtualSettings::default()));
    let p = frame.pages;
    assert_eq!(
        (p.pages_marked, p.pages_rendered, p.caster_pages),
        (0, 0, 0),
        "{p:?}"
    );
    assert_eq!(p.cache_hit_rate, None, "no page marked, no rate");
    assert!(frame.capture.ids.iter().all(|&id| id == 0));
}

#[test]
fn a_camera_cut_leaves_no_stale_page() {
    let scene = scene(Sun::default());
    let settings = settings(VirtualSettings::default());
    // 300 m away, looking back: every level up to 6 (262 m squares) moves whole.
    let far = Camera::look_at(
        Vec3::new(300.0, 40.0, -17.0),
        Vec3::new(0.0, 1.0, 0.0),
        60f32.to_radians(),
        0.1,
        500.0,
    );
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera(), &settings);
    let cut = frames.frame(&scene, &far, &settings);
    assert!(
        cut.pages.pages_invalidated > 0,
        "fine levels' squares moved: {:?}",
        cut.pages
    );
    let redrawn = frames.redrawn(&scene, &far, &settings);
    assert_eq!(cut.capture.shadow, redrawn.capture.shadow);
    assert!(first.pages.pages_rendered > 0);
}

/// The exact shadow's error: wrong pixels off the exact picture's edges, at most `share`
/// of the visible ones.
fn near_exact(scene: &Scene, camera: &Camera, share: f64, v: VirtualSettings) -> VirtualPages {
    let (error, shadowed, _, report) = against_truth(scene, camera, &settings(v), SIZE);
    assert!(
        shadowed > 100,
        "the case has a shadow to get right: {shadowed}"
    );
    let off_edge = error.off_edge_px.expect("against the exact shadow");
    assert!(
        f64::from(off_edge) <= share * f64::from(error.visible_px),
        "{error:?}"
    );
    let p = report.virtual_pages.expect("pages");
    assert!(
        report
            .undersampling
            .is_some_and(|u| u.p95_octaves.is_finite())
    );
    p
}

#[test]
fn the_hard_cases_give_the_exact_shadow() {
    let far = Vec3::new(100_000.0, 0.0, 60_000.0);
    let at_far = |c: Camera| {
        Camera::look_at(
            c.eye + far,
            c.eye + far + c.forward,
            c.fov_y_rad,
            c.near_m,
            c.far_m,
        )
    };
    // Also with static casters apart and the receiver mask culling the movable box.
    let variants = [
        VirtualSettings::default(),
        VirtualSettings {
            separate_static: true,
            receiver_mask: true,
            ..VirtualSettings::default()
        },
    ];
    for v in variants {
        hard_cases(v, far, at_far);
    }
}

fn hard_cases(v: VirtualSettings, far: Vec3, at_far: impl Fn(Camera) -> Camera) {
    for (name, sun) in [
        ("default", Sun::default()),
        ("zenith", Sun::from_direction(Vec3::Y)),
        ("1 degree", Sun::from_azimuth_elevation_deg(35.0, 1.0)),
    ] {
        let p = near_exact(&scene(sun), &camera(), 0.002, v);
        assert!(p.pages_marked > 0, "{name}: {p:?}");
    }
    near_exact(
        &translated(&scene(Sun::default()), far),
        &at_far(camera()),
        0.002,
        v,
    );
    // A 1 m scene: a 10 cm box 5 cm above a 1 m ground, seen from 1 m.
    let small = box_on_plane(0.5, Vec3::new(0.1, 0.15, 0.075), 0.05, Sun::default());
    let close = Camera::look_at(
        Vec3::new(-0.45, 0.35, 0.55),
        Vec3::new(0.0, 0.025, 0.0),
        60f32.to_radians(),
        0.01,
        10.0,
    );
    near_exact(&small, &close, 0.002, v);
}

#[test]
fn page_marking_equals_the_cpu_reference() {
    let scene = scene(Sun::default());
    let settings = settings(VirtualSettings::default());
    let camera = camera();
    let frame = Frames::new(&scene).frame(&scene, &camera, &settings);
    let marking = Marking::new(&camera, &frame.views, settings.virtual_maps);
    let (mut certain, mut uncertain) = (Vec::new(), Vec::new());
    let (mut sure_texels, mut all_texels) = (Vec::new(), Vec::new());
    let mut unsure_texel_pixels = 0;
    let mut unsure_pixels = 0;
    let mut pixels = 0;
    for y in 0..SIZE.1 {
        for x in 0..SIZE.0 {
            let id = frame.capture.ids[(y * SIZE.0 + x) as usize];
            let Some(p) = shadowlab_tests::world_position(&frame.capture, &camera, x, y) else {
                continue;
            };
            pixels += 1;
            let marks = marking.marks(p, box_scene_normal(&scene, id, p));
            if marks.texels_certain {
                sure_texels.extend(marks.texels.iter().copied());
            } else {
                unsure_texel_pixels += 1;
            }
            all_texels.extend(marks.texels);
            if marks.certain {
                certain.extend(marks.entries);
            } else {
                unsure_pixels += 1;
                uncertain.extend(marks.entries);
            }
        }
    }
    certain.sort_unstable();
    certain.dedup();
    let gpu = entries_with(&frame.flags, MARKED);
    assert!(!certain.is_empty());
    let missing: Vec<_> = certain
        .iter()
        .filter(|e| gpu.binary_search(e).is_err())
        .collect();
    assert!(
        missing.is_empty(),
        "the GPU did not mark {missing:?} (of {})",
        certain.len()
    );
    // Pages only uncertain pixels mark: the GPU may or may not, but marks no others.
    let extra: Vec<_> = gpu
        .iter()
        .filter(|e| certain.binary_search(e).is_err())
        .filter(|e| !uncertain.contains(e))
        .collect();
    assert!(
        extra.is_empty(),
        "the GPU marked {extra:?} that no pixel reads"
    );
    assert!(
        unsure_pixels * 50 < pixels,
        "{unsure_pixels} of {pixels} pixels on a boundary"
    );
    assert_eq!(frame.pages.pages_marked as usize, gpu.len());
    // The texels pixels read: at least those the CPU is sure of, at most a row and a column
    // more for each pixel whose taps lie on a whole texel.
    for texels in [&mut sure_texels, &mut all_texels] {
        texels.sort_unstable();
        texels.dedup();
    }
    let sampled = frame.pages.texels_sampled.expect("the frame measured") as usize;
    let slack = unsure_texel_pixels * 2 * marking.kernel as usize;
    assert!(
        (sure_texels.len()..=all_texels.len() + slack).contains(&sampled),
        "{sampled} texels sampled, the CPU reads {} to {} + {slack}",
        sure_texels.len(),
        all_texels.len()
    );
    assert!(frame.pages.texels_rendered >= sampled as u64);
}
