//! Virtual shadow maps of a point light (`--shadow virtual --light point`): its cube's six
//! faces, each a chain of mips, through the same pages, pool, cull and cache as the sun's
//! clipmap. The exact shadow of a light inside the view; a static second frame draws nothing;
//! a moving box draws again exactly the pages its old and new bounds touch in every face; a
//! moving light draws every page; a pool too small falls back to coarser mips, no hole.

use glam::{DVec4, Vec3};
use render_core::frame::FrameSettings;
use render_core::geom::NEAR_M;
use render_core::scene::{PointShadow, Scene, Sun};
use render_core::shadow_view::{LEVEL_PAGES, PAGE_TEXELS, ShadowView, VirtualSettings};
use shadowlab_tests::virtual_pages::{
    FACE_LEVELS, Frames, MARKED, assert_drawn_again_exactly, chain_names, entries_with, scene,
    settings,
};
use shadowlab_tests::{
    LIGHT_BESIDE_THE_BOX, against_truth, gpu, ground_point, overlooking_the_box,
};

const SIZE: (u32, u32) = (256, 192);
fn point_settings(v: VirtualSettings, light: Vec3) -> FrameSettings {
    FrameSettings {
        point_light: Some(PointShadow::omni(light, 2.0e6)),
        ..settings(v)
    }
}

/// The entries of face levels `views` whose pages the world box `lo..hi` covers, widened by a
/// texel, as `box_pages` in `virtual_maps/tables.wgsl` finds them: none for a box wholly
/// behind a face's near plane, the whole square for one across it.
fn touched_face_entries(views: &[ShadowView], lo: Vec3, hi: Vec3) -> Vec<usize> {
    let mut out = Vec::new();
    for (level, view) in views.iter().enumerate() {
        let m = view.light.light_clip_from_world.as_dmat4();
        let size = f64::from(view.target.size);
        let (mut min, mut max) = ([f64::MAX; 2], [f64::MIN; 2]);
        let mut behind = 0;
        for i in 0..8 {
            let c = m * DVec4::new(
                f64::from(if i & 1 == 0 { lo.x } else { hi.x }),
                f64::from(if i & 2 == 0 { lo.y } else { hi.y }),
                f64::from(if i & 4 == 0 { lo.z } else { hi.z }),
                1.0,
            );
            if c.w < f64::from(NEAR_M) {
                behind += 1;
                continue;
            }
            let t = [
                (c.x / c.w * 0.5 + 0.5) * size,
                (0.5 - c.y / c.w * 0.5) * size,
            ];
            for k in 0..2 {
                min[k] = min[k].min(t[k] - 1.0);
                max[k] = max[k].max(t[k] + 1.0);
            }
        }
        if behind == 8 {
            continue;
        }
        if behind > 0 {
            (min, max) = ([-1.0; 2], [size + 1.0; 2]);
        }
        let side = (size as i64) / i64::from(PAGE_TEXELS);
        let page = |v: f64| (v / f64::from(PAGE_TEXELS)).floor() as i64;
        for y in page(min[1]).max(0)..=page(max[1]).min(side - 1) {
            for x in page(min[0]).max(0)..=page(max[0]).min(side - 1) {
                let per_level = i64::from(LEVEL_PAGES * LEVEL_PAGES) as usize;
                out.push(level * per_level + (y * i64::from(LEVEL_PAGES) + x) as usize);
            }
        }
    }
    out.sort_unstable();
    out.dedup();
    out
}

#[test]
fn a_point_light_in_the_view_casts_the_exact_shadow_through_its_cube_of_pages() {
    let scene = scene(Sun::default());
    let camera = overlooking_the_box();
    // The ground where the ray from the light through the box's centre lands; under the
    // light, and far out on its side.
    let centre = Vec3::new(0.0, 2.5, 0.0);
    let behind = LIGHT_BESIDE_THE_BOX
        + (centre - LIGHT_BESIDE_THE_BOX)
            * (LIGHT_BESIDE_THE_BOX.y / (LIGHT_BESIDE_THE_BOX.y - centre.y));
    let known = [
        ground_point(behind.x, behind.z),
        ground_point(LIGHT_BESIDE_THE_BOX.x, LIGHT_BESIDE_THE_BOX.z),
        ground_point(8.0, 6.0),
    ];
    for v in [
        VirtualSettings::default(),
        VirtualSettings {
            separate_static: true,
            receiver_mask: true,
            ..VirtualSettings::default()
        },
    ] {
        let settings = point_settings(v, LIGHT_BESIDE_THE_BOX);
        let (error, shadowed, renderer, report) = against_truth(&scene, &camera, &settings, SIZE);
        assert_eq!(report.shadow_failure, None);
        assert!(shadowed > 500, "{shadowed} exact shadowed points");
        let off_edge = error.off_edge_px.expect("against the exact shadow");
        assert!(off_edge * 500 <= error.visible_px, "{v:?}: {error:?}");
        let light = renderer.light_at(gpu(), &known).expect("read back");
        assert_eq!(
            light,
            [0.0, 1.0, 1.0],
            "behind the box, under the light, far out"
        );
        let views = renderer.last_views();
        assert_eq!(views.len(), 6 * FACE_LEVELS, "six faces");
        let minus_x = &views[FACE_LEVELS..2 * FACE_LEVELS];
        let names: Vec<_> = minus_x.iter().map(|v| v.name.clone()).collect();
        assert_eq!(names, chain_names("point -X"));
        let sizes = [0, 19, 20, 25].map(|i| minus_x[i].target.size);
        assert_eq!(
            sizes,
            [4096, 4096, 4096, 128],
            "tiles of 4096, then the mips"
        );
        let p = report.virtual_pages.expect("pages");
        assert_eq!(
            (p.levels, p.pages_refused),
            (6 * FACE_LEVELS as u32, 0),
            "{p:?}"
        );
        assert!(p.pages_marked > 0 && p.caster_pages > 0, "{p:?}");
        let under = report.undersampling.expect("measured");
        assert!(under.p95_octaves <= 0.5, "{under:?}");
    }
}

#[test]
fn six_mips_a_face_are_faces_of_4096_a_level_each_and_cast_the_same_exact_shadow() {
    let scene = scene(Sun::default());
    let v = VirtualSettings {
        levels: 6,
        ..VirtualSettings::default()
    };
    let settings = point_settings(v, LIGHT_BESIDE_THE_BOX);
    let (error, shadowed, renderer, report) =
        against_truth(&scene, &overlooking_the_box(), &settings, SIZE);
    assert!(shadowed > 500, "{shadowed} exact shadowed points");
    let off_edge = error.off_edge_px.expect("against the exact shadow");
    assert!(off_edge * 500 <= error.visible_px, "{error:?}");
    let views = renderer.last_views();
    assert_eq!(views.len(), 36, "six faces of six mips");
    assert_eq!(views[6].name, "point -X mip 0");
    assert_eq!((views[6].target.size, views[11].target.size), (4096, 128));
    assert_eq!(report.virtual_pages.expect("pages").levels, 36);
}

#[test]
fn a_light_touching_the_box_casts_its_exact_shadow_from_every_face_the_box_crosses() {
    // 2 cm beside the box's +X side (x 1), at half its height: the box's bounds cross the
    // near plane of every face but +X (behind which it lies), whose casters are then drawn
    // over the whole square.
    let light = Vec3::new(1.02, 2.5, 0.0);
    let scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let settings = point_settings(VirtualSettings::default(), light);
    let (error, shadowed, renderer, report) = against_truth(&scene, &camera, &settings, SIZE);
    assert!(
        shadowed > 5_000,
        "the box shades the ground on its far side: {shadowed}"
    );
    let off_edge = error.off_edge_px.expect("against the exact shadow");
    assert!(off_edge * 500 <= error.visible_px, "{error:?}");
    // Under the box dark; beside the light and out on its side lit.
    let lit = renderer
        .light_at(
            gpu(),
            &[
                ground_point(0.0, 0.0),
                ground_point(1.5, 0.0),
                ground_point(8.0, 3.0),
            ],
        )
        .expect("read back");
    assert_eq!(lit, [0.0, 1.0, 1.0]);
    let p = report.virtual_pages.expect("pages");
    assert_eq!(p.pages_refused, 0, "{p:?}");
}

#[test]
fn a_static_point_light_draws_no_page_in_the_second_frame_and_a_moved_one_every_page() {
    let scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let settings = point_settings(VirtualSettings::default(), LIGHT_BESIDE_THE_BOX);
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera, &settings);
    let second = frames.frame(&scene, &camera, &settings);
    assert_eq!(first.pages.pages_rendered, first.pages.pages_marked);
    // Pages in the faces below and beside the light, none in the one looking up.
    let faces_marked = |flags: &[u32]| {
        let marked = entries_with(flags, MARKED);
        (0..6)
            .map(|f| {
                marked
                    .iter()
                    .filter(|&&e| e / (FACE_LEVELS * 1024) == f)
                    .count()
            })
            .collect::<Vec<_>>()
    };
    let faces = faces_marked(&first.flags);
    assert_eq!(faces[2], 0, "+Y looks at the sky: {faces:?}");
    assert!(faces[3] > 0 && faces[1] > 0, "{faces:?}");
    assert_eq!(second.pages.pages_rendered, 0, "{:?}", second.pages);
    assert_eq!(second.pages.caster_pages, 0);
    assert_eq!(second.pages.cache_hit_rate, Some(1.0));
    assert_eq!(first.capture.shadow, second.capture.shadow);
    // The light moves 10 cm: every page is drawn again.
    let moved = point_settings(
        VirtualSettings::default(),
        LIGHT_BESIDE_THE_BOX + Vec3::X * 0.1,
    );
    let third = frames.frame(&scene, &camera, &moved);
    assert!(third.pages.all_invalidated);
    assert_eq!(third.pages.pages_rendered, third.pages.pages_marked);
    let redrawn = frames.redrawn(&scene, &camera, &moved);
    assert_eq!(third.capture.shadow, redrawn.capture.shadow);
}

#[test]
fn moving_a_box_draws_again_exactly_the_face_pages_its_old_and_new_bounds_touch() {
    let mut scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let settings = point_settings(VirtualSettings::default(), LIGHT_BESIDE_THE_BOX);
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera, &settings);
    let [old, new] = frames.move_box(&mut scene);
    let second = frames.frame(&scene, &camera, &settings);
    assert_eq!(second.pages.moved_boxes, 2);
    let mut touched = [
        touched_face_entries(&second.views, old.min, old.max),
        touched_face_entries(&second.views, new.min, new.max),
    ]
    .concat();
    touched.sort_unstable();
    touched.dedup();
    assert_drawn_again_exactly(&first, &second, &touched);
    let redrawn = frames.redrawn(&scene, &camera, &settings);
    assert_eq!(second.capture.shadow, redrawn.capture.shadow);
    assert_ne!(first.capture.shadow, second.capture.shadow);
}

#[test]
fn a_pool_too_small_for_a_point_light_falls_back_to_coarser_mips_and_leaves_no_hole() {
    let scene: Scene = scene(Sun::default());
    let settings = point_settings(
        VirtualSettings {
            pages: 32,
            lod_bias: -2.0,
            ..VirtualSettings::default()
        },
        LIGHT_BESIDE_THE_BOX,
    );
    let frame = Frames::new(&scene).frame(&scene, &overlooking_the_box(), &settings);
    let p = frame.pages;
    assert!(p.pages_refused > 0, "{p:?}");
    assert!(p.pages_resident <= 32, "{p:?}");
    let error = frame.report.error.expect("measured");
    let shaded = frame.report.undersampling.expect("measured").pixels;
    assert_eq!(shaded, error.visible_px, "every receiver pixel is shaded");
}

#[test]
fn a_close_view_reads_the_tiles_of_the_finest_mips_and_a_shadow_edge_on_a_tile_border_is_exact() {
    // Straight above the box's +X side: its shadow's edge on the ground runs under the light,
    // along the -Y face's middle, where the finest mips' tiles meet.
    let light = Vec3::new(1.0, 6.0, 0.0);
    let scene: Scene = scene(Sun::default());
    let camera = render_core::geom::Camera::look_at(
        Vec3::new(1.6, 0.8, 1.0),
        Vec3::new(1.0, 0.0, 0.3),
        12f32.to_radians(),
        0.05,
        100.0,
    );
    let settings = point_settings(VirtualSettings::default(), light);
    let (error, shadowed, renderer, report) = against_truth(&scene, &camera, &settings, SIZE);
    assert_eq!(report.shadow_failure, None);
    assert!(shadowed > 5_000, "{shadowed} shadowed points");
    assert!(
        error.visible_px - shadowed > 5_000,
        "{error:?}: lit points too"
    );
    let off_edge = error.off_edge_px.expect("against the exact shadow");
    assert!(off_edge * 500 <= error.visible_px, "{error:?}");
    let known = [ground_point(0.98, 0.3), ground_point(1.02, 0.3)];
    let reaching = renderer.light_at(gpu(), &known).expect("read back");
    assert_eq!(reaching, [0.0, 1.0], "2 cm either side of the edge");
    // The pixels read tiles of the -Y face's finest mips, more than one of them.
    let frame = Frames::new(&scene).frame(&scene, &camera, &settings);
    let mut tiles: Vec<usize> = entries_with(&frame.flags, MARKED)
        .iter()
        .map(|e| e / 1024)
        .filter(|level| level / FACE_LEVELS == 3 && level % FACE_LEVELS < 20)
        .collect();
    tiles.dedup();
    assert!(tiles.len() >= 2, "tile levels marked: {tiles:?}");
}
