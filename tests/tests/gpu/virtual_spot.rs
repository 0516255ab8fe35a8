//! A spot light (`--light spot`): the frame lit by its cone alone, the exact shadow counting
//! only what the cone reaches, and virtual shadow maps through one chain of mips along the
//! cone (`--shadow virtual`), with the same pages, pool, cull and cache as the sun's clipmap
//! and a point light's cube. The exact shadow inside the cone, from the virtual maps and from
//! shadow volumes; no page read outside the cone; a static spot's second frame draws
//! nothing, a turned one every page.

use glam::Vec3;
use render_core::frame::{FrameSettings, ShadowSetup};
use render_core::geom::Camera;
use render_core::scene::{PointShadow, Scene, SpotCone, Sun};
use render_core::shadow_view::VirtualSettings;
use render_core::truth::{PixelTruth, TruthCache};
use shadowlab_tests::virtual_pages::{FACE_LEVELS, Frames, chain_names, scene, settings};
use shadowlab_tests::{
    LIGHT_BESIDE_THE_BOX, against_truth, gpu, ground_point, overlooking_the_box, world_position,
};

const SIZE: (u32, u32) = (256, 192);
/// The box's centre (`virtual_pages::scene`: 2 x 3 x 1.5 m, 1 m off the ground).
const BOX_CENTRE: Vec3 = Vec3::new(0.0, 2.5, 0.0);
const OUTER_DEG: f32 = 38.0;
const INNER_DEG: f32 = 28.0;

/// A spot at [`LIGHT_BESIDE_THE_BOX`] aimed at the box's centre, turned by `turn_deg` about
/// the vertical.
fn spot(turn_deg: f32) -> PointShadow {
    let aim = (BOX_CENTRE - LIGHT_BESIDE_THE_BOX).normalize();
    PointShadow {
        cone: Some(SpotCone {
            direction: glam::Quat::from_rotation_y(turn_deg.to_radians()) * aim,
            inner_rad: INNER_DEG.to_radians(),
            outer_rad: OUTER_DEG.to_radians(),
        }),
        ..PointShadow::omni(LIGHT_BESIDE_THE_BOX, 2.0e6)
    }
}

fn spot_settings(setup: ShadowSetup, v: VirtualSettings, light: PointShadow) -> FrameSettings {
    FrameSettings {
        setup,
        point_light: Some(light),
        ..settings(v)
    }
}

/// The ground where the ray from the light through the box's centre (the narrow cone's axis)
/// lands: in the box's shadow.
fn behind_the_box() -> Vec3 {
    LIGHT_BESIDE_THE_BOX
        + (BOX_CENTRE - LIGHT_BESIDE_THE_BOX)
            * (LIGHT_BESIDE_THE_BOX.y / (LIGHT_BESIDE_THE_BOX.y - BOX_CENTRE.y))
}

/// Looking down at ground far on the light's +X, +Z side, which the cone (aimed at -X) does
/// not reach.
fn outside_the_cone() -> Camera {
    Camera::look_at(
        Vec3::new(12.0, 8.0, 14.0),
        Vec3::new(12.0, 0.0, 10.0),
        50f32.to_radians(),
        0.1,
        200.0,
    )
}

#[test]
fn a_spot_light_casts_the_exact_shadow_within_its_cone_and_counts_nothing_outside_it() {
    let scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let light = spot(0.0);
    let cone = light.cone.expect("a spot");
    // On the cone's axis past the box (shadowed), on the ground at 32 degrees from the axis
    // between the light and the box (lit), and under the light, 41 degrees out (outside).
    let behind = behind_the_box();
    let lit = Vec3::new(2.0, 0.0, LIGHT_BESIDE_THE_BOX.z);
    let under = Vec3::new(LIGHT_BESIDE_THE_BOX.x, 0.0, LIGHT_BESIDE_THE_BOX.z);
    assert!(cone.holds(behind - LIGHT_BESIDE_THE_BOX) && cone.holds(lit - LIGHT_BESIDE_THE_BOX));
    assert!(!cone.holds(under - LIGHT_BESIDE_THE_BOX));
    let known = [behind, lit, under].map(|p| ground_point(p.x, p.z));

    // The truth counts the points the cone reaches, every one of them, and no other.
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &camera, SIZE, light.shadow_light());
    let outside = exact
        .pixels
        .iter()
        .filter(|p| **p == PixelTruth::OutsideCone)
        .count();
    assert!(outside > 5_000, "the ground beyond the cone: {outside}");
    assert!(exact.points.len() > 5_000, "{}", exact.points.len());
    for p in &exact.points {
        let at = Vec3::from_slice(&p.position[..3]);
        assert!(
            cone.holds(at - LIGHT_BESIDE_THE_BOX),
            "{at} is outside the cone"
        );
    }

    for (setup, v) in [
        (ShadowSetup::Virtual, VirtualSettings::default()),
        (
            ShadowSetup::Virtual,
            VirtualSettings {
                separate_static: true,
                receiver_mask: true,
                ..VirtualSettings::default()
            },
        ),
        (ShadowSetup::Volumes, VirtualSettings::default()),
    ] {
        let settings = spot_settings(setup, v, light);
        let (error, shadowed, renderer, report) = against_truth(&scene, &camera, &settings, SIZE);
        assert_eq!(report.shadow_failure, None);
        assert!(shadowed > 500, "{shadowed} exact shadowed points");
        let off_edge = error.off_edge_px.expect("against the exact shadow");
        assert!(
            off_edge * 500 <= error.visible_px,
            "{setup:?} {v:?}: {error:?}"
        );
        let reaching = renderer.light_at(gpu(), &known).expect("read back");
        assert_eq!(
            reaching[..2],
            [0.0, 1.0],
            "{setup:?}: behind the box, lit beside it"
        );
        if setup != ShadowSetup::Virtual {
            continue;
        }
        // Outside the cone no page is read: the light there is not looked up.
        assert_eq!(reaching[2..], [1.0], "under the light, outside the cone");
        let views = renderer.last_views();
        let names: Vec<_> = views.iter().map(|v| v.name.clone()).collect();
        assert_eq!(names, chain_names("spot"));
        assert_eq!((views[0].target.size, views[25].target.size), (4096, 128));
        let p = report.virtual_pages.expect("pages");
        assert_eq!(
            (p.levels, p.pages_refused),
            (FACE_LEVELS as u32, 0),
            "{p:?}"
        );
        assert!(p.pages_marked > 0 && p.caster_pages > 0, "{p:?}");
        let under = report.undersampling.expect("measured");
        assert!(under.p95_octaves <= 0.5, "{under:?}");
    }
}

#[test]
fn ground_the_cone_does_not_reach_is_lit_by_the_sky_alone_and_reads_no_page() {
    let scene = scene(Sun::default());
    let camera = outside_the_cone();
    let light = spot(0.0);
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &camera, SIZE, light.shadow_light());
    assert_eq!(
        exact.points.len(),
        0,
        "the cone reaches none of this ground"
    );
    let virtual_maps = spot_settings(ShadowSetup::Virtual, VirtualSettings::default(), light);
    let spot_frame = Frames::new(&scene).frame(&scene, &camera, &virtual_maps);
    assert_eq!(spot_frame.pages.pages_marked, 0, "{:?}", spot_frame.pages);
    assert_eq!(spot_frame.pages.pages_rendered, 0);
    // The same light shining every way reads pages here and lights the ground more.
    let omni = FrameSettings {
        point_light: Some(PointShadow {
            cone: None,
            ..light
        }),
        ..virtual_maps
    };
    let omni_frame = Frames::new(&scene).frame(&scene, &camera, &omni);
    assert!(omni_frame.pages.pages_marked > 0, "{:?}", omni_frame.pages);
    let (spot_rgb, omni_rgb) = (&spot_frame.capture.color, &omni_frame.capture.color);
    let mut ground = 0;
    for (x, y, s) in spot_rgb.enumerate_pixels() {
        if world_position(&spot_frame.capture, &camera, x, y).is_none() {
            continue;
        }
        let o = omni_rgb.get_pixel(x, y);
        let (s, o) = (&s.0[..3], &o.0[..3]);
        assert!(
            s.iter().zip(o).all(|(s, o)| s < o),
            "({x}, {y}): {s:?} against {o:?}"
        );
        ground += 1;
    }
    assert!(ground > 10_000, "{ground} ground pixels");
}

#[test]
fn a_static_spot_draws_no_page_in_the_second_frame_and_a_turned_one_every_page() {
    let scene: Scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let settings = spot_settings(ShadowSetup::Virtual, VirtualSettings::default(), spot(0.0));
    let mut frames = Frames::new(&scene);
    let first = frames.frame(&scene, &camera, &settings);
    let second = frames.frame(&scene, &camera, &settings);
    assert!(first.pages.pages_rendered > 0);
    assert_eq!(first.pages.pages_rendered, first.pages.pages_marked);
    assert_eq!(second.pages.pages_rendered, 0, "{:?}", second.pages);
    assert_eq!(second.pages.cache_hit_rate, Some(1.0));
    assert_eq!(first.capture.shadow, second.capture.shadow);
    assert_eq!(first.capture.color, second.capture.color);
    // The spot turns 2 degrees about the vertical: every page is drawn again.
    let turned = spot_settings(ShadowSetup::Virtual, VirtualSettings::default(), spot(2.0));
    let third = frames.frame(&scene, &camera, &turned);
    assert!(third.pages.all_invalidated);
    assert_eq!(third.pages.pages_rendered, third.pages.pages_marked);
    let redrawn = frames.redrawn(&scene, &camera, &turned);
    assert_eq!(third.capture.shadow, redrawn.capture.shadow);
}

#[test]
fn a_pool_too_small_for_a_spot_falls_back_to_coarser_mips_and_leaves_no_hole() {
    let scene: Scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let shaded = |pages: u32| {
        let v = VirtualSettings {
            pages,
            lod_bias: -2.0,
            ..VirtualSettings::default()
        };
        let settings = spot_settings(ShadowSetup::Virtual, v, spot(0.0));
        let frame = Frames::new(&scene).frame(&scene, &camera, &settings);
        (
            frame.pages,
            frame.report.undersampling.expect("measured").pixels,
        )
    };
    let (enough, all) = shaded(VirtualSettings::default().pages);
    let (small, with_small) = shaded(16);
    assert_eq!(enough.pages_refused, 0, "{enough:?}");
    assert!(
        small.pages_refused > 0 && small.pages_resident <= 16,
        "{small:?}"
    );
    assert!(all > 5_000, "{all} pixels inside the cone");
    assert_eq!(with_small, all, "every pixel inside the cone is shaded");
}

#[test]
fn a_spot_wider_than_a_cube_face_casts_through_the_cube_and_still_reads_no_page_outside() {
    let scene: Scene = scene(Sun::default());
    let camera = overlooking_the_box();
    let mut light = spot(0.0);
    light.cone = light.cone.map(|c| SpotCone {
        inner_rad: 50f32.to_radians(),
        outer_rad: 60f32.to_radians(),
        ..c
    });
    let settings = spot_settings(ShadowSetup::Virtual, VirtualSettings::default(), light);
    let (error, shadowed, renderer, report) = against_truth(&scene, &camera, &settings, SIZE);
    assert!(shadowed > 500, "{shadowed} exact shadowed points");
    let off_edge = error.off_edge_px.expect("against the exact shadow");
    assert!(off_edge * 500 <= error.visible_px, "{error:?}");
    let views = renderer.last_views();
    assert_eq!(views.len(), 6 * FACE_LEVELS, "six faces");
    assert_eq!(views[0].name, "point +X mip 0 tile 0,0");
    let p = report.virtual_pages.expect("pages");
    assert_eq!(p.pages_refused, 0, "{p:?}");
    let behind = behind_the_box();
    let known =
        [behind, Vec3::new(2.0, 0.0, LIGHT_BESIDE_THE_BOX.z)].map(|p| ground_point(p.x, p.z));
    let reaching = renderer.light_at(gpu(), &known).expect("read back");
    assert_eq!(reaching, [0.0, 1.0], "behind the box, lit beside it");
    // The far ground the narrow cone left out is outside this one too, and reads no page.
    let far = Frames::new(&scene).frame(&scene, &outside_the_cone(), &settings);
    let mut truth = TruthCache::default();
    let exact = truth.exact(&scene, &outside_the_cone(), SIZE, light.shadow_light());
    assert_eq!(
        exact.points.len(),
        0,
        "the wide cone reaches none of that ground either"
    );
    assert_eq!(far.pages.pages_marked, 0, "{:?}", far.pages);
}
